"""Studies and their cases: what `./wirenet run [STUDY|CASE|FILE.toml]` runs, one folder per case.

A case is a case file (TOML; doc/case_files.md): the paper's are inputs/cases/NAME.toml, a
study is a list of them (inputs/studies/NAME.toml: ``cases = [...]``). A case writes
DIR/CASE/case.json (status, wall time, case facts) next to its CSVs; a case whose case.json says
"ok", in the same mode (--quick or not) and from the same case-file values, and whose CSVs
exist, is skipped, so an interrupted study resumes.
"""

import fcntl
import os
import signal
import sys
import time
import tomllib

from postprocess import record, report

from . import INPUTS, casefile, engine, ensemble, kinds
from .errors import CaseFileError, StudyError
from .kinds.punch import PRELOAD_FREE
from .scheduler import Interrupted, run_cases

CASE_DIR = INPUTS / "cases"
STUDY_DIR = INPUTS / "studies"
DEFAULT_STUDY = "compound"


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
    except OSError as exc:
        raise StudyError(f"{path}: {exc.strerror or exc}") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise StudyError(f"{path}: not valid TOML: {exc}") from None
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
        except (OSError, tomllib.TOMLDecodeError, UnicodeDecodeError):
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
        except CaseFileError as exc:
            raise StudyError(str(exc)) from None
    for case in loaded:
        if case.kept_long:
            kept = ", ".join(f"{k} = {v!r}" for k, v in case.kept_long)
            print(f"{case.name}: --quick keeps what the case file states: {kept} (remove the "
                  "keys for the quick values)", flush=True)
    names = [u for c in loaded for u, _ in kinds.of(c).units()]
    dup = sorted({n for n in names if names.count(n) > 1})
    if dup:
        raise StudyError(f"two cases of the study share the name {dup[0]} (case folders must "
                         "differ): rename one case file")
    check_preload_sources(loaded)
    return loaded


def expand_ensembles(loaded, out):
    """The cases to run: each case file as it is, or, when its [ensemble] section asks for
    members, its members (runner/ensemble.py; their case files will be OUT/NAME/member_KKK/
    case.toml); and the ensembles. Every member is checked before anything runs."""
    cases, ensembles = [], []
    for case in loaded:
        try:
            if not ensemble.active(case):
                ensemble.check_inactive(case)
                cases.append(case)
                continue
            found = ensemble.expand(case, out)
        except CaseFileError as exc:
            raise StudyError(str(exc)) from None
        ensembles.append(found)
        cases += found.cases
    return cases, ensembles


# what partition mode runs: a kind whose case runs one LIGGGHTS process at a time
PARTITION_KINDS = ("impact", "fence")


def check_partitions(cases, np_, partitions):
    """--partitions M: M cases at a time as the partitions of one LIGGGHTS job of --np / M
    ranks each (engine.Partitions); one line for what cannot be."""
    if partitions is None:
        return
    if np_ % partitions:
        raise StudyError(f"--partitions {partitions}: --np {np_} is not a multiple of it (each "
                         "partition runs on --np / --partitions ranks)")
    for case in cases:
        if case.kind not in PARTITION_KINDS:
            raise StudyError(f"--partitions: {case.name} is a {case.kind} case; partition mode "
                             f"runs {' and '.join(PARTITION_KINDS)} cases (a punch runs its "
                             "slower twin beside it)")


def _preload_free(path):
    return any(path == p or (p.endswith("*") and path.startswith(p[:-1]))
               for p in PRELOAD_FREE)


def check_preload_sources(loaded):
    """punch.preload_from: the named case, when it is in the study, must be a punch that runs
    its own pre-load and differs from this one only in keys that act after it
    (PRELOAD_FREE). A source outside the study is no error: the case then pre-loads its
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


def output_folder(given):
    """The absolute output folder, created (with its parents) and writable; one line naming it
    otherwise."""
    out = os.path.abspath(given)
    if os.path.exists(out) and not os.path.isdir(out):
        raise StudyError(f"--out {given}: {out} is a file, not a folder")
    try:
        os.makedirs(out, exist_ok=True)
    except OSError as exc:
        raise StudyError(f"--out {given}: cannot create {out}: {exc.strerror or exc}") from None
    if not os.access(out, os.W_OK | os.X_OK):
        raise StudyError(f"--out {given}: {out} is not writable")
    return out


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


class Result:
    """What a study left: its folder, summary (summary.json's content), the cases it ran and
    those of them that are not sound (record.UNSOUND: name -> the case's summary entry)."""

    def __init__(self, out, summary, names):
        self.out, self.summary, self.names = out, summary, names
        self.unsound = {n: s for n, s in report.all_cases(summary).items()
                        if n in names and s["status"] in record.UNSOUND}


def execute(target=None, out=None, quick=False, overrides=(), np_=None, partitions=None,
            prepare=None):
    """Run a study, a case or a case file (target; the default study if None) into ``out``
    (default out/NAME) and write its report; return its Result. Raises StudyError (bad input,
    before anything runs), CaseFileError, RunError (a case failed) or Interrupted. Paths are made
    absolute at once: LIGGGHTS runs inside each case folder, where a relative path would point
    elsewhere. ``prepare()``, when given, returns (out, files) instead of the target (the data
    sheet writes its case files into the output folder: runner/datasheet.py)."""
    np_ = default_ranks() if np_ is None else np_
    _check_np(np_)
    if prepare is None:
        name, files = resolve_target(target or DEFAULT_STUDY)
        given = out or os.path.join("out", name)
        loaded, ensembles = expand_ensembles(load_cases(files, quick, overrides or ()),
                                             os.path.abspath(given))
        out = output_folder(given)
    else:
        out, files = prepare()
        loaded, ensembles = expand_ensembles(load_cases(files, quick, ()), out)
    check_partitions(loaded, np_, partitions)
    with FolderLock(out):
        for found in ensembles:
            ensemble.write_manifest(out, found)
        names = run_cases(loaded, out, quick, np_, partitions)
        summary = report.build(out, expected=names)
    return Result(out, summary, names)


def run(args, prepare=None, after=None):
    """``./wirenet run``: execute() with the command line's arguments, its claims and report
    printed; exit code 3 when a case is not sound, 2 on bad input, 128 + N on signal N.
    ``after(out, summary)`` runs once the report is written."""
    previous = {s: signal.signal(s, _raise_interrupt) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        start = time.time()
        result = execute(args.target, args.out, args.quick, args.set or (), args.np,
                         getattr(args, "partitions", None), prepare)
        for claim in result.summary["claims"]:
            print(f"claim {claim['id']}: {claim['verdict']}")
        print(f"report: {os.path.join(result.out, 'report.md')} "
              f"(wall time {time.time() - start:.0f} s)")
        if after is not None:
            after(result.out, result.summary)
        if result.unsound:
            for n, s in result.unsound.items():
                print(f"wirenet run: {n}: {s['status']}: {s['verdict']}", file=sys.stderr)
            sys.exit(3)
    except Interrupted as exc:
        engine.stop_all()
        print(f"wirenet run: interrupted ({exc.name}); the unfinished case is redone on the next "
              "run", file=sys.stderr, flush=True)
        sys.exit(128 + exc.signum)
    except StudyError as exc:
        print(f"wirenet run: error: {exc}", file=sys.stderr, flush=True)
        sys.exit(2)
    finally:
        for sig, handler in previous.items():
            signal.signal(sig, handler)
