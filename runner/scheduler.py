"""The cases of a study side by side on the machine's cores: which start when, on how many
ranks, and what each case folder's record says when it ends.

A case folder is a Job. Jobs start whenever a core is free, the longest first
(CaseKind.weight), counting the cores a running case lent back (a punch whose run or twin has
finished); a punch pair may then share a core with another case for a while (single-rank
processes: the kernel shares the core, no rank spins). An impact of a sequence waits for the
one before it; a punch that starts from another's pre-load (punch.preload_from) waits, holding
no core, until that pre-load is written. A failed case stops the others (marked 'interrupted',
redone on the next run) and the study.

Members of an ensemble (runner/ensemble.py) are cases like any other, one rank each (a member
gives the same result wherever it runs: alone with --np 1, or side by side); each writes its
case file, case.toml, into its folder when it starts. In partition mode (--partitions M) up to M
cases run at once as the partitions of one LIGGGHTS multi-partition job of K = N / M ranks each
(engine.Partitions).
"""

import hashlib
import json
import os
import shutil
import threading
import time

from postprocess import record
from postprocess.errors import PostprocessError
from postprocess.output import write_json
from postprocess.record import CaseRecord

from . import engine, ensemble, kinds, schema
from .errors import StudyError
from .kinds.base import RunContext


class Interrupted(BaseException):
    """SIGINT or SIGTERM during a study; BaseException so that no ``except Exception`` of a
    kind swallows it."""

    def __init__(self, signum):
        import signal
        super().__init__(signum)
        self.signum = signum
        self.name = signal.Signals(signum).name


def case_fingerprint(case):
    """sha256 of a case's checked values: a changed case file (or --set) runs the case again.
    The [ensemble] keys are no input of a run (an ensemble's members are cases of their own)."""
    values = {k: v for k, v in case.values.items() if not k.startswith("ensemble.")}
    text = json.dumps(dict(values=values, impacts=case.impacts, zones=case.zones),
                      sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def read_record(case_dir):
    """The CaseRecord of a case folder, or None when absent or unreadable."""
    try:
        with open(os.path.join(case_dir, "case.json"), encoding="utf-8") as fh:
            meta = json.load(fh)
        return CaseRecord.from_json(meta) if isinstance(meta, dict) else None
    except (OSError, ValueError, TypeError):
        return None


def write_record(case_dir, rec):
    write_json(os.path.join(case_dir, "case.json"), rec.to_json())


def complete(case_dir, finished_file, quick, fingerprint):
    """Finished in the requested mode from the same case values: status ok, the kind's file
    that shows a finished unit present, the same --quick setting (a quick result never stands
    for a full case, nor the other way round) and the same case fingerprint."""
    rec = read_record(case_dir)
    return (rec is not None and rec.status == record.OK and bool(rec.quick) == bool(quick) and
            rec.case_fingerprint == fingerprint and
            os.path.isfile(os.path.join(case_dir, finished_file)))


def fresh_case_dir(case_dir):
    """Empty the folder of a case that is to be (re)run. Only a folder WireNet wrote (it holds a
    case.json) or an empty one is touched; anything else is the user's and stops the run."""
    if os.path.isdir(case_dir) and os.listdir(case_dir):
        if not os.path.isfile(os.path.join(case_dir, "case.json")):
            raise StudyError(f"{case_dir} exists and is not a WireNet case folder (no case.json); "
                             "move it away or choose another --out")
        shutil.rmtree(case_dir)
    os.makedirs(case_dir, exist_ok=True)


class Job:
    """One case folder of a study: what it runs, on how many ranks, and how it ended."""

    def __init__(self, case, kind, name, index, number, total):
        self.case, self.kind, self.name, self.index = case, kind, name, index
        self.prefix = f"[case {number}/{total}] {name}"
        self.fingerprint = case_fingerprint(case)
        # an impact of a sequence starts from the net the previous one left
        self.after = kind.units()[index - 1][0] if index > 0 else None
        self.ranks = self.cost = 1
        # the job whose pre-load this punch starts from (punch.preload_from), and the event a
        # job sets once its own pre-load is written for another
        self.source = None
        self.share_event = None
        self.thread = self.error = self.facts = None
        self.start = self.wall = 0.0
        self.partitions = None    # the engine.Partitions its runs go through, if any

    def record(self, quick, status, **fields):
        return CaseRecord(kind=self.kind.record_kind(), status=status, quick=bool(quick),
                          np=self.ranks, case_file=self.case.path,
                          case_fingerprint=self.fingerprint, title=self.case["title"], **fields)

    def work(self, out):
        """The case, in its own thread: errors are kept for the study's thread."""
        start_from = None
        if self.source is not None:
            restart = os.path.join(out, self.source.name, "run", "preload.restart")
            # a short source may end before its progress scan saw its pre-load's line: its
            # restart is kept all the same; without one the case pre-loads its own
            start_from = restart if os.path.isfile(restart) else None
        ctx = RunContext(case_dir=os.path.join(out, self.name), study_dir=out, ranks=self.ranks,
                         label=self.name, start_from=start_from, share_event=self.share_event)
        try:
            with engine.labelled(self.name):
                self.facts = self.kind.run(self.index, ctx)
        except BaseException as exc:   # noqa: B902 (handed on to the study's thread)
            self.error = exc
        finally:
            if self.partitions is not None:
                self.partitions.leave(self.name)
        self.wall = time.time() - self.start

    def waits(self, waiting):
        """Whether the job must wait: for the impact before it in a sequence, or for the
        pre-load of the case it starts from, while those are pending or running."""
        names = {j.name for j in waiting}
        if self.after is not None and self.after in names:
            return True
        return (self.source is not None and self.source in waiting and
                not self.source.share_event.is_set())


def plan(jobs, np_, partitions=None):
    """Ranks of each case. Alone, or on one core, a case takes all --np ranks (a punch splits
    them between its run and its twin). Several cases on several cores run side by side, each
    on as few ranks as it can use well: one, two for a punch with its twin (one each; the
    first of the two to end gives its core back); a net of a few thousand nodes gains less from
    a second rank than a second case does (docs/PERFORMANCE.md). A member of an ensemble runs
    on one rank wherever it runs (its result then does not depend on the others). With
    ``partitions`` M, each case is one partition of np_ / M ranks, M at a time. Returns the
    number of cores (partitions) shared out."""
    if partitions:
        for job in jobs:
            job.ranks, job.cost = np_ // partitions, 1
        return partitions
    if np_ == 1 or len(jobs) == 1:
        for job in jobs:
            job.ranks, job.cost = (1 if job.case.member_of else np_), 1
        return 1
    for job in jobs:
        job.ranks = job.cost = 1 if job.case.member_of else min(job.kind.width, np_)
    return np_


def share_preloads(jobs):
    """Link each punch whose punch.preload_from names a case that runs in this study to that
    job, which then keeps its run/preload.restart and sets its share_event once it is written.
    A source already complete from an earlier run left no restart: the case pre-loads its own.
    Returns the sources."""
    by_name = {j.name: j for j in jobs}
    for job in jobs:
        job.source = by_name.get(job.case.values.get("punch.preload_from") or "")
    sources = {j.source for j in jobs if j.source is not None}
    for job in sources:
        job.share_event = threading.Event()
    return sources


def run_cases(loaded, out, quick, np_, partitions=None):
    """Run the cases not yet complete in this mode, side by side where cores allow (plan), the
    longest first; with ``partitions`` M, M at a time as the partitions of one LIGGGHTS job of
    np_ / M ranks each (engine.Partitions; its batches in OUT/.partitions). The folder lock is
    held by the caller. Returns the case folder names."""
    units = [(case, kind, name, index) for case in loaded
             for kind in [kinds.of(case)] for name, index in kind.units()]
    jobs = []
    for k, (case, kind, name, index) in enumerate(units, 1):
        job = Job(case, kind, name, index, k, len(units))
        if complete(os.path.join(out, name), kind.finished_file, quick, job.fingerprint):
            print(f"{job.prefix}: complete, skipped (delete {os.path.join(out, name)} to run it "
                  "again)", flush=True)
        else:
            jobs.append(job)
    capacity = plan(jobs, np_, partitions)
    sources = share_preloads(jobs)
    engine.allow_new_runs()
    pool = None
    if partitions and jobs:
        pool = engine.Partitions(partitions, np_ // partitions, os.path.join(out, ".partitions"))
        engine.use_partitions(pool)
        for job in jobs:
            job.partitions = pool
    pending, running = sorted(jobs, key=lambda j: -j.kind.weight()), []
    try:
        while pending or running:
            used = sum(max(j.cost - engine.released_cores(j.name), 0) for j in running)
            for job in list(pending):
                if used >= capacity:
                    break
                if job.waits(pending + running):
                    continue
                _launch(job, out, quick)
                pending.remove(job)
                running.append(job)
                used += job.cost
            if not running:   # cannot happen: a case waits only for one that runs or waits
                raise StudyError("internal error: no case can start")
            running[0].thread.join(0.2)
            for job in [j for j in running if not j.thread.is_alive()]:
                running.remove(job)
                _finish(job, out, quick, running, pending)
    except Interrupted:
        stop_jobs(running, out, quick)
        raise
    finally:
        if pool is not None:
            engine.use_partitions(None)
            pool.close()
        for job in sources:       # the hand-over of a shared pre-load is no output
            restart = os.path.join(out, job.name, "run", "preload.restart")
            if os.path.isfile(restart):
                os.remove(restart)
    return [name for _, _, name, _ in units]


def _with_sources(job):
    """The facts, and the numbers of the case that no source read backs (the report's list)."""
    missing = schema.unsourced(job.case)
    return dict(job.facts, unsourced=missing) if missing else job.facts


def _finish(job, out, quick, running, pending):
    """Record how a job ended; a failure stops the others and the study."""
    engine.forget_released(job.name)
    cpu = engine.cpu_seconds(job.name)
    engine.forget_cpu(job.name)
    case_dir = os.path.join(out, job.name)
    if job.error is not None:
        pending.clear()
        stop_jobs(running, out, quick)
        try:
            write_record(case_dir, job.record(quick, record.FAILED, error=str(job.error)))
        except (OSError, PostprocessError):
            pass    # a full disk or a folder gone: the error below says why; 'running' reruns it
        raise job.error
    # did it do what the case says? (a run can end well and mean nothing)
    status, verdict = job.kind.verdict(job.facts) or (record.OK, None)
    # start and end (Unix time): cases side by side overlap, so the study's elapsed time is
    # the span of these, not the sum of the wall times
    write_record(case_dir, job.record(quick, status, wall_time=job.wall, cpu_time=cpu,
                                      started=job.start, finished=job.start + job.wall,
                                      verdict=verdict, facts=_with_sources(job)))
    if status == record.OK:
        print(f"{job.prefix}: done in {job.wall:.1f} s", flush=True)
    else:
        print(f"{job.prefix}: {status} after {job.wall:.1f} s: {verdict}", flush=True)


def _launch(job, out, quick):
    case_dir = os.path.join(out, job.name)
    fresh_case_dir(case_dir)
    if job.case.member_of:
        ensemble.write_member_file(job.case, case_dir)
    # 'running' until the case returns: an interrupted or failed case is never 'ok'
    write_record(case_dir, job.record(quick, record.RUNNING))
    side = f", {job.ranks} rank{'s' if job.ranks > 1 else ''}"
    print(f"{job.prefix}: running ({'quick' if quick else 'full'}{side}) from "
          f"{os.path.relpath(job.case.path)}", flush=True)
    job.start = time.time()
    if job.partitions is not None:
        job.partitions.join(job.name)
    job.thread = threading.Thread(target=job.work, args=(out,), daemon=True)
    job.thread.start()


def stop_jobs(running, out, quick):
    """Stop the LIGGGHTS runs of the running cases and mark them interrupted."""
    engine.stop_all()
    for job in running:
        job.thread.join()
        write_record(os.path.join(out, job.name), job.record(quick, record.INTERRUPTED))
