"""Studies and their cases: what `./wirenet run [STUDY|CASE|FILE.toml]` runs, one folder per case.

A case is a case file (TOML; doc/case_files.md): the paper's are inputs/cases/NAME.toml, a
study is a list of them (inputs/studies/NAME.toml: ``cases = [...]``). A case writes
DIR/CASE/case.json (status, wall time, case facts) next to its CSVs; a case whose case.json says
"ok", in the same mode (--quick or not) and from the same case-file values, and whose CSVs
exist, is skipped, so an interrupted study resumes.
"""

import fcntl
import hashlib
import json
import os
import shutil
import signal
import sys
import threading
import time
import tomllib

from postprocess import liggghts, report
from postprocess.output import write_json

from . import casefile, cases, punch, schema

INPUTS = liggghts.INPUTS
CASE_DIR = INPUTS / "cases"
STUDY_DIR = INPUTS / "studies"
DEFAULT_STUDY = "compound"
CSV_OF_KIND = {"beam": "beam.csv", "calibration": "platter.csv", "punch": "platter.csv",
               "impact": "block.csv"}


def case_fingerprint(case):
    """sha256 of a case's checked values: a changed case file (or --set) runs the case again."""
    text = json.dumps(dict(values=case.values, impacts=case.impacts, zones=case.zones),
                      sort_keys=True, default=str)
    return hashlib.sha256(text.encode()).hexdigest()[:16]


def _read_meta(case_dir):
    """case.json of a case folder as a dict, or None when absent or unreadable."""
    try:
        with open(os.path.join(case_dir, "case.json"), encoding="utf-8") as fh:
            meta = json.load(fh)
    except (OSError, ValueError):
        return None
    return meta if isinstance(meta, dict) else None


def _complete(case_dir, kind, quick, fingerprint):
    """Finished in the requested mode from the same case values: status ok, the kind's CSV
    present, the same --quick setting (a quick result never stands for a full case, nor the
    other way round) and the same case fingerprint."""
    meta = _read_meta(case_dir)
    return (meta is not None and meta.get("status") == "ok" and
            bool(meta.get("quick")) == bool(quick) and
            meta.get("case_fingerprint") == fingerprint and
            os.path.isfile(os.path.join(case_dir, CSV_OF_KIND[kind])))


def _write_meta(case_dir, meta):
    write_json(os.path.join(case_dir, "case.json"), meta)


def _fresh_case_dir(case_dir):
    """Empty the folder of a case that is to be (re)run. Only a folder WireNet wrote (it holds a
    case.json) or an empty one is touched; anything else is the user's and stops the run."""
    if os.path.isdir(case_dir) and os.listdir(case_dir):
        if not os.path.isfile(os.path.join(case_dir, "case.json")):
            raise StudyError(f"{case_dir} exists and is not a WireNet case folder (no case.json); "
                             "move it away or choose another --out")
        shutil.rmtree(case_dir)
    os.makedirs(case_dir, exist_ok=True)


class StudyError(Exception):
    """A one-line user error of ``./wirenet run`` (exit code 2)."""


class Interrupted(BaseException):
    """SIGINT or SIGTERM during a study; BaseException so that no ``except Exception`` of a
    runner swallows it."""

    def __init__(self, signum):
        super().__init__(signum)
        self.signum = signum
        self.name = signal.Signals(signum).name


def _raise_interrupt(signum, frame):
    raise Interrupted(signum)


class FolderLock:
    """An exclusive lock on an output folder (flock on DIR/.wirenet.lock, released by the kernel
    when the process ends, however it ends), so two runs never write the same cases."""

    def __init__(self, folder):
        self.path = os.path.join(folder, ".wirenet.lock")
        self.handle = None

    def __enter__(self):
        self.handle = open(self.path, "a+", encoding="utf-8")
        try:
            fcntl.flock(self.handle, fcntl.LOCK_EX | fcntl.LOCK_NB)
        except BlockingIOError:
            self.handle.seek(0)
            holder = self.handle.read().strip() or "another process"
            self.handle.close()
            raise StudyError(f"{os.path.dirname(self.path)} is in use by another run "
                             f"({holder}); wait for it or choose another --out") from None
        self.handle.seek(0)
        self.handle.truncate()
        self.handle.write(f"pid {os.getpid()}\n")
        self.handle.flush()
        return self

    def __exit__(self, *exc):
        self.handle.close()
        return False


def _names(folder):
    return sorted(p.stem for p in folder.glob("*.toml"))


def _study_files(path):
    """The case files a study file lists (names of inputs/cases/ or paths relative to it)."""
    try:
        with open(path, "rb") as handle:
            listed = tomllib.load(handle).get("cases")
    except (OSError, tomllib.TOMLDecodeError) as exc:
        raise StudyError(f"{path}: {exc}") from None
    if not isinstance(listed, list) or not listed or not all(isinstance(c, str) for c in listed):
        raise StudyError(f"{path}: cases: must be a list of case names or files")
    return [_case_path(c, os.path.dirname(path)) for c in listed]


def _case_path(entry, base):
    if entry.endswith(".toml"):
        return os.path.normpath(os.path.join(base, entry))
    path = CASE_DIR / f"{entry}.toml"
    if not path.is_file():
        raise StudyError(f"unknown case '{entry}' (inputs/cases/ has: {', '.join(_names(CASE_DIR))})")
    return str(path)


def resolve_target(target):
    """(name, [case file, ...]) of a study name, a case name, a case file or a study file."""
    if target.endswith(".toml"):
        path = os.path.abspath(target)
        if not os.path.isfile(path):
            raise StudyError(f"{target}: no such file")
        try:
            with open(path, "rb") as handle:
                is_study = "cases" in tomllib.load(handle)
        except (OSError, tomllib.TOMLDecodeError):
            is_study = False      # the case-file reader names the error
        stem = os.path.splitext(os.path.basename(path))[0]
        return stem, (_study_files(path) if is_study else [path])
    if (STUDY_DIR / f"{target}.toml").is_file():
        return target, _study_files(str(STUDY_DIR / f"{target}.toml"))
    if (CASE_DIR / f"{target}.toml").is_file():
        return target, [str(CASE_DIR / f"{target}.toml")]
    known = ", ".join(_names(STUDY_DIR) + _names(CASE_DIR))
    raise StudyError(f"unknown study or case '{target}' (known: {known}; or a FILE.toml)")


def load_cases(files, quick, overrides):
    """Every case file read and checked before anything runs (a mistake in the tenth file stops
    the study before the first case)."""
    loaded = []
    for path in files:
        try:
            loaded.append(casefile.read(path, overrides, quick))
        except casefile.CaseFileError as exc:
            raise StudyError(str(exc)) from None
    names = [u for c in loaded for u, _ in cases.runner_of(c).units()]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise StudyError(f"two cases of the study share the name {dup[0]} (case folders must "
                         "differ): rename one case file")
    check_preload_sources(loaded)
    return loaded


def _preload_free(path):
    return any(path == p or (p.endswith("*") and path.startswith(p[:-1]))
               for p in schema.PRELOAD_FREE)


def check_preload_sources(loaded):
    """punch.preload_from: the named case, when it is in the study, must be a punch that runs
    its own pre-load and differs from this one only in keys that act after it
    (schema.PRELOAD_FREE). A source outside the study is no error: the case then pre-loads its
    own panel (a case run alone)."""
    by_name = {c.name: c for c in loaded}
    for case in loaded:
        source = case.values.get("punch.preload_from") if case.kind == "punch" else ""
        if not source:
            continue
        if source not in by_name:       # said, not refused: a typo would go unnoticed
            print(f"{case.name}: punch.preload_from: {source} is not in this run; the case "
                  "pre-loads its own panel", flush=True)
            continue
        where = f"{case.path}: punch.preload_from"
        other = by_name[source]
        if other is case:
            raise StudyError(f"{where}: names the case itself")
        if other.kind != "punch":
            raise StudyError(f"{where}: {source} is not a punch (kind = {other.kind!r})")
        if other.values.get("punch.preload_from") in by_name:
            raise StudyError(f"{where}: {source} starts from the pre-load of "
                             f"{other.values['punch.preload_from']}; name that case instead")
        for key in sorted(set(case.values) | set(other.values)):
            if not _preload_free(key) and case.values.get(key) != other.values.get(key):
                raise StudyError(f"{where}: {source} has {key} = "
                                 f"{other.values.get(key)!r}, this case {case.values.get(key)!r} "
                                 "(a shared pre-load needs the same panel, materials, pre-load "
                                 "and time step)")


MAX_RANKS = 4096


def _check_np(np_):
    if not 1 <= np_ <= MAX_RANKS:
        raise StudyError(f"--np must be an integer from 1 to {MAX_RANKS} (got {np_})")


def default_ranks():
    """The default of --np: WIRENET_NP when set, else the cores this process may run on (what
    `nproc` prints)."""
    text = os.environ.get("WIRENET_NP", "").strip()
    if not text:
        return max(len(os.sched_getaffinity(0)), 1)
    try:
        value = int(text)
    except ValueError:
        value = 0
    if not 1 <= value <= MAX_RANKS:
        raise StudyError(f"WIRENET_NP must be an integer from 1 to {MAX_RANKS} (got '{text}')")
    return value


class Job:
    """One case folder of a study: what it runs, on how many ranks, and how it ended."""

    def __init__(self, case, runner, name, index, number, total):
        self.case, self.runner, self.name, self.index = case, runner, name, index
        self.prefix = f"[case {number}/{total}] {name}"
        self.kind = cases.record_kind(case)
        self.fingerprint = case_fingerprint(case)
        # an impact of a sequence starts from the net the previous one left
        self.after = runner.units()[index - 1][0] if index > 0 else None
        self.ranks = self.cost = 1
        # the job of this study whose pre-load this punch starts from (punch.preload_from)
        self.preload_source = None
        self.thread = self.error = self.facts = None
        self.start = self.wall = 0.0

    def meta(self, quick, **extra):
        mode = "quick" if quick else "full"
        return dict(kind=self.kind, quick=quick, mode=mode, np=self.ranks,
                    case_file=self.case.path, case_fingerprint=self.fingerprint,
                    title=self.case["title"], **extra)

    def work(self, out):
        """The case, in its own thread: errors are kept for the study's thread."""
        try:
            with liggghts.labelled(self.name):
                self.facts = self.runner.run(self.index, os.path.join(out, self.name), out,
                                             self.ranks)
        except BaseException as exc:   # noqa: B902 (handed on to the study's thread)
            self.error = exc
        self.wall = time.time() - self.start


def _plan(jobs, np_):
    """Ranks of each case. Alone, or on one core, a case takes all --np ranks (a punch splits
    them between its run and its twin). Several cases on several cores run side by side, each
    on as few ranks as it can use well: one, two for a punch with its twin (one each; the
    first of the two to end gives its core back); a net of a few thousand nodes gains less from
    a second rank than a second case does (docs/PERFORMANCE.md). Returns the number of cores
    shared out."""
    if np_ == 1 or len(jobs) == 1:
        for job in jobs:
            job.ranks, job.cost = np_, 1
        return 1
    for job in jobs:
        job.ranks = job.cost = min(job.runner.width(), np_)
    return np_


# Relative cost of a case by kind and net, from the measured wall times of the default study
# (docs/PERFORMANCE.md): the longest cases start first, so that the short ones fill the cores
# at the end instead of one long case running alone.
WEIGHT = {("punch", "compound"): 30, ("punch", "hex"): 20, ("impact", "compound"): 15,
          ("impact", "hex"): 8, ("punch", "square"): 3, ("impact", "square"): 2}


def _weight(job):
    return WEIGHT.get((job.case.kind, job.case["panel.net"]), 1)


def run_cases(loaded, out, quick, np_):
    """Run the cases not yet complete in this mode, side by side where cores allow (_plan),
    the longest first (WEIGHT); the folder lock is held by the caller. A case starts whenever a
    core is free, counting the cores a running case gave back (a punch whose run or twin has
    finished); a punch pair may then share a core with another case for a while (single-rank
    processes: the kernel shares the core, no rank spins). A failed case stops the others
    (marked 'interrupted', redone on the next run) and the study."""
    units = [(case, runner, name, index) for case in loaded
             for runner in [cases.runner_of(case)] for name, index in runner.units()]
    jobs = []
    for k, (case, runner, name, index) in enumerate(units, 1):
        job = Job(case, runner, name, index, k, len(units))
        if _complete(os.path.join(out, name), job.kind, quick, job.fingerprint):
            print(f"{job.prefix}: complete, skipped (delete {os.path.join(out, name)} to run it "
                  "again)", flush=True)
        else:
            jobs.append(job)
    capacity = _plan(jobs, np_)
    shared = _share_preloads(jobs)
    liggghts.allow_new_runs()
    pending, running = sorted(jobs, key=lambda j: -_weight(j)), []
    try:
        while pending or running:
            used = sum(max(j.cost - liggghts.released_cores(j.name), 0) for j in running)
            for job in list(pending):
                if used >= capacity:
                    break
                if job.after is not None and job.after in {j.name for j in pending + running}:
                    continue
                if _waits_for_preload(job, pending + running):
                    continue
                if job.preload_source is not None:
                    job.runner.preload_restart = _shared_restart(job, out)
                _launch(job, out, quick)
                pending.remove(job)
                running.append(job)
                used += job.cost
            if not running:   # cannot happen: a case waits only for one that runs or waits
                raise StudyError("internal error: no case can start")
            running[0].thread.join(0.2)
            for job in [j for j in running if not j.thread.is_alive()]:
                running.remove(job)
                liggghts.forget_released(job.name)
                cpu = liggghts.cpu_seconds(job.name)
                liggghts.forget_cpu(job.name)
                if job.error is not None:
                    pending.clear()
                    _stop_jobs(running, out, quick)
                    _write_meta(os.path.join(out, job.name), job.meta(
                        quick, status="failed", error=str(job.error)))
                    raise job.error
                # start and end (Unix time): cases side by side overlap, so the study's
                # elapsed time is the span of these, not the sum of the wall times
                _write_meta(os.path.join(out, job.name), job.meta(
                    quick, status="ok", wall_time=job.wall, cpu_time=cpu, started=job.start,
                    finished=job.start + job.wall, **job.facts))
                print(f"{job.prefix}: done in {job.wall:.1f} s", flush=True)
    except Interrupted:
        _stop_jobs(running, out, quick)
        raise
    finally:
        for name in shared:       # the hand-over of a shared pre-load is no output
            punch.SHARED_PRELOADS.pop(name, None)
            restart = os.path.join(out, name, "run", "preload.restart")
            if os.path.isfile(restart):
                os.remove(restart)
    return [name for _, _, name, _ in units]


def _share_preloads(jobs):
    """Link each punch whose punch.preload_from names a case that runs in this study to that
    job, which then keeps its run/preload.restart and announces it (punch.SHARED_PRELOADS).
    A source already complete from an earlier run left no restart: the case pre-loads its own.
    Returns the names of the sources."""
    by_name = {j.name: j for j in jobs}
    for job in jobs:
        if job.case.kind == "punch":
            job.preload_source = by_name.get(job.case.values.get("punch.preload_from"))
    shared = {j.preload_source.name for j in jobs if j.preload_source is not None}
    for name in shared:
        punch.SHARED_PRELOADS[name] = threading.Event()
    return shared


def _waits_for_preload(job, waiting):
    """A case that starts from another's pre-load waits (holding no core) while that case is
    pending or running and has not written it yet."""
    source = job.preload_source
    return (source is not None and source in waiting and
            not punch.SHARED_PRELOADS[source.name].is_set())


def _shared_restart(job, out):
    """The source's preload.restart once the case may start; None if the source ended without
    one (the case pre-loads its own). A short source may end before its progress scan saw the
    line after its pre-load: its restart is kept all the same."""
    restart = os.path.join(out, job.preload_source.name, "run", "preload.restart")
    return restart if os.path.isfile(restart) else None


def _launch(job, out, quick):
    case_dir = os.path.join(out, job.name)
    _fresh_case_dir(case_dir)
    # 'running' until the case returns: an interrupted or failed case is never 'ok'
    _write_meta(case_dir, job.meta(quick, status="running"))
    side = f", {job.ranks} rank{'s' if job.ranks > 1 else ''}"
    print(f"{job.prefix}: running ({'quick' if quick else 'full'}{side}) from "
          f"{os.path.relpath(job.case.path)}", flush=True)
    job.start = time.time()
    job.thread = threading.Thread(target=job.work, args=(out,), daemon=True)
    job.thread.start()


def _stop_jobs(running, out, quick):
    """Stop the LIGGGHTS runs of the running cases and mark them interrupted."""
    liggghts.stop_all()
    for job in running:
        job.thread.join()
        _write_meta(os.path.join(out, job.name), job.meta(quick, status="interrupted"))


def run(args):
    """``./wirenet run``. Paths are made absolute at once: LIGGGHTS runs inside each case
    folder, where a relative path would point elsewhere."""
    previous = {s: signal.signal(s, _raise_interrupt) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        np_ = default_ranks() if args.np is None else args.np
        _check_np(np_)
        name, files = resolve_target(args.target or DEFAULT_STUDY)
        loaded = load_cases(files, args.quick, args.set or ())
        out = os.path.abspath(args.out or os.path.join("out", name))
        os.makedirs(out, exist_ok=True)
        start = time.time()
        with FolderLock(out):
            names = run_cases(loaded, out, args.quick, np_)
            summary = report.build(out, expected=names)
        for claim in summary["claims"]:
            print(f"claim {claim['id']}: {claim['verdict']}")
        print(f"report: {os.path.join(out, 'report.md')} (wall time {time.time() - start:.0f} s)")
    except Interrupted as exc:
        liggghts.stop_all()
        print(f"wirenet run: interrupted ({exc.name}); the unfinished case is redone on the next "
              "run", file=sys.stderr, flush=True)
        sys.exit(128 + exc.signum)
    except StudyError as exc:
        print(f"wirenet run: error: {exc}", file=sys.stderr, flush=True)
        sys.exit(2)
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
