"""The engine: LIGGGHTS launched from Python, on one rank or under mpirun, in its own process
group, with progress lines, interrupts and the CPU time it used; the cores a case lends back to
the study's scheduler while part of it has ended. What is launched (the deck and its variables)
is the kinds' business (runner/kinds/); how it is launched is this module's."""

import contextlib
import os
import re
import shlex
import signal
import subprocess
import sys
import threading
import time
from pathlib import Path

from . import INPUTS, ROOT
from .errors import RunError


def build_dir():
    return Path(os.environ.get("WIRENET_BUILD", ROOT / "build"))


def binary(name):
    path = build_dir() / "bin" / name
    if not path.is_file():
        raise RunError(f"{path}: not built (run ./wirenet setup)")
    return path


# OpenMPI's shared-memory transport (vader, OpenMPI 4) sends messages above its 4 kB eager
# limit in a rendezvous and copies them with a system call into the other process (CMA,
# process_vm_readv). A net's ghost exchange sends messages of a few to some tens of kB at every
# step: eagerly, through the shared buffers, the 2-rank step of the 3 m compound punch and
# impact is 1.5 times the 1-rank speed instead of 1.1 (docs/PERFORMANCE.md). Other transports
# and OpenMPI versions ignore these names; a user's own settings win.
MPI_TUNING = {"OMPI_MCA_btl_vader_single_copy_mechanism": "none",
              "OMPI_MCA_btl_vader_eager_limit": "65536"}


def mpi_env():
    # OpenMPI refuses to run as root without these; oversubscription keeps small machines usable.
    env = dict(MPI_TUNING, **os.environ)
    env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
               OMPI_MCA_rmaps_base_oversubscribe="1")
    return env



# LIGGGHTS processes (or their mpirun) that are running now, each the leader of its own process
# group, so that an interrupted study can stop them with all their ranks (stop_all).
_LIVE = set()
_LIVE_LOCK = threading.Lock()
_STOPPED = threading.Event()   # set by stop_all: no new run starts (cases run in threads)


def stop_all(grace=5.0):
    """Stop every running LIGGGHTS process group (see stop); runs asked for afterwards fail at
    once, until allow_new_runs()."""
    _STOPPED.set()
    with _LIVE_LOCK:
        procs = list(_LIVE)
    stop(procs, grace)


def allow_new_runs():
    _STOPPED.clear()


class _PerCase:
    """A number per case label, kept for the study's thread by the case threads."""

    def __init__(self):
        self.values = {}

    def add(self, label, amount):
        with _LIVE_LOCK:
            self.values[label] = self.values.get(label, 0) + amount

    def get(self, label):
        with _LIVE_LOCK:
            return self.values.get(label, 0)

    def forget(self, label):
        with _LIVE_LOCK:
            self.values.pop(label, None)


# Cores a case gives back before it ends (a punch whose run or twin has finished while the other
# goes on): the study's scheduler may start another case on them.
_RELEASED = _PerCase()
# CPU seconds (user + system) of the LIGGGHTS processes that have ended, with their ranks under
# mpirun (it waits for them): a study on C cores takes at least their sum / C, and the elapsed
# time against that sum shows how well the cases filled the cores.
_CPU = _PerCase()


def release_cores(label, cores):
    _RELEASED.add(label, cores)


def released_cores(label):
    return _RELEASED.get(label)


def forget_released(label):
    _RELEASED.forget(label)


def cpu_seconds(label):
    return float(_CPU.get(label))


def forget_cpu(label):
    _CPU.forget(label)


# The case a thread works for: progress lines name it when cases run side by side.
_CONTEXT = threading.local()


@contextlib.contextmanager
def labelled(name):
    """``with labelled(NAME):`` prefixes this thread's progress lines with NAME."""
    previous, _CONTEXT.label = current_label(), name
    try:
        yield
    finally:
        _CONTEXT.label = previous


def current_label():
    return getattr(_CONTEXT, "label", None)


def stop(procs, grace=5.0):
    """SIGTERM to each process group, SIGKILL to those still alive after ``grace`` seconds."""
    for proc in procs:
        _signal_group(proc, signal.SIGTERM)
    deadline = time.time() + grace
    for proc in procs:
        try:
            proc.wait(timeout=max(deadline - time.time(), 0.1))
        except subprocess.TimeoutExpired:
            _signal_group(proc, signal.SIGKILL)
            proc.wait()


def _signal_group(proc, sig):
    try:
        os.killpg(proc.pid, sig)
    except ProcessLookupError:
        pass


_PR_SET_PDEATHSIG = 1    # linux/prctl.h


def _die_with_parent():
    """In the child before exec: SIGTERM when the runner dies, however it dies (SIGKILL
    included), so that LIGGGHTS (or mpirun, which then stops its ranks) never computes on
    outside the folder lock. Linux only; elsewhere a no-op."""
    try:
        import ctypes
        libc = ctypes.CDLL(None, use_errno=True)
        libc.prctl(_PR_SET_PDEATHSIG, signal.SIGTERM, 0, 0, 0)
    except (OSError, AttributeError):
        pass


_NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


def run(deck, workdir, variables=None, np=1, total_steps=None, label="", dt=None,
        phase_marker=None, then=None, marker_seen=None):
    """Run the deck file in workdir with -var NAME VALUE pairs; show progress (step, simulated
    time, ETA) on long runs; raise with LIGGGHTS' ERROR line on failure. With phase_marker, the
    steps before the log line holding it are a preparation phase of unknown length (reported
    without ETA); total_steps and the ETA count from that line on; marker_seen (a
    threading.Event) is set once the progress scan has seen that line. then = (name, steps): a
    phase that may follow the counted steps for at most that many steps (a rest that ends when
    the motion has died down), reported as such; (name, steps, marker): the phase may start
    earlier, at the log line holding that marker (an impact that ends before its longest
    duration), and the counted steps are then given as at most."""
    workdir = Path(workdir).resolve()
    workdir.mkdir(parents=True, exist_ok=True)
    deck = Path(deck).resolve()
    # never "-screen none": LIGGGHTS 3.8's STL reader (input_mesh_tri.cpp) prints to the
    # screen without checking it, so any deck with a mesh would crash
    cmd = [str(binary("liggghts")), "-in", str(deck), "-log", "log.lammps", "-echo", "none",
           "-screen", "screen.txt"]
    # the decks include their shared parts from ${inc} (inputs/include)
    variables = {"inc": str(INPUTS / "include"), **(variables or {})}
    for name, value in variables.items():
        cmd += ["-var", name, str(value)]
    if np > 1:
        cmd = ["mpirun", "-np", str(np)] + cmd
    # the exact command, so that a run can be repeated by hand (from its folder)
    (workdir / "command.txt").write_text(" ".join(shlex.quote(c) for c in cmd) + "\n")
    start = time.time()
    if current_label():
        label = f"{current_label()}: {label}"
    # own process group: a signal to the study reaches LIGGGHTS only through stop_all, which
    # also reaches every rank under mpirun; the check and the start are one step under the lock
    with _LIVE_LOCK:
        if _STOPPED.is_set():
            raise RunError(f"LIGGGHTS not started in {workdir}: the study is stopping")
        proc = subprocess.Popen(cmd, cwd=workdir, env=mpi_env(), stdout=subprocess.PIPE,
                                stderr=subprocess.STDOUT, text=True, start_new_session=True,
                                preexec_fn=_die_with_parent)
        _LIVE.add(proc)
    try:
        output = _follow(proc, workdir, total_steps, label, dt, phase_marker, then, marker_seen)
    except BaseException:      # an interrupt (or any error) while it runs: it must not outlive us
        stop([proc])
        raise
    finally:
        with _LIVE_LOCK:
            _LIVE.discard(proc)
    log = (workdir / "log.lammps").read_text(errors="replace") if (workdir / "log.lammps").exists() else ""
    errors = [l for l in (log + output).splitlines() if "ERROR" in l]
    if proc.returncode or errors:
        msg = errors[0] if errors else (output.strip().splitlines() or ["no output"])[-1]
        raise RunError(f"LIGGGHTS failed in {workdir}: {msg}")
    # LIGGGHTS ends a run early, writes a restart and exits 0 on SIGTERM from outside: a deck
    # that prints END_MARKER as its last line must have reached it
    if END_MARKER in deck.read_text(errors="replace") and END_MARKER not in log:
        raise RunError(f"LIGGGHTS stopped before the end of {deck.name} in {workdir} "
                               f"(killed from outside?): the case is not complete")
    return time.time() - start


END_MARKER = "wirenet: end of deck"


def log_line(workdir, marker):
    """The first line of a run's log.lammps that starts with ``marker`` (an event the deck
    printed), or None."""
    path = Path(workdir) / "log.lammps"
    try:
        with open(path, errors="replace") as fh:
            return next((line for line in fh if line.startswith(marker)), None)
    except OSError as exc:
        raise RunError(f"{path}: {exc.strerror or exc}") from None


def _follow(proc, workdir, total_steps, label, dt, phase_marker, then=None, marker_seen=None):
    """Wait for the process, printing progress lines; return its output. The output goes to a
    pipe read only at the end, so LIGGGHTS must keep it short (-screen screen.txt)."""
    last = time.time()
    progress = Progress(workdir / "log.lammps", total_steps, label, dt, phase_marker, then,
                        marker_seen) if total_steps else None
    case = current_label()
    while _reap(proc, case) is None:
        time.sleep(0.5)
        if progress and time.time() - last > 5:
            last = time.time()
            progress.report()
    return proc.stdout.read()


def _reap(proc, case):
    """proc's exit code once it has ended (reaped here with wait4, which also gives its CPU
    time and its waited-for children's, counted for the case), else None."""
    if proc.returncode is not None:
        return proc.returncode
    try:
        pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
    except ChildProcessError:     # reaped elsewhere (stop(): an interrupted study)
        return proc.poll()
    if pid == 0:
        return None
    proc.returncode = os.waitstatus_to_exitcode(status)
    if case is not None:
        _CPU.add(case, usage.ru_utime + usage.ru_stime)
    return proc.returncode


class Progress:
    """Progress lines of a running deck from the thermo rows of its log: one line whenever the
    step has moved, with the ETA of the counted phase (after phase_marker, if given); steps
    beyond it belong to the phase `then` = (name, at most so many steps), if given."""

    def __init__(self, log, total, label, dt, phase_marker=None, then=None, marker_seen=None):
        self.log, self.total, self.label, self.dt = log, total, label, dt
        self.marker, self.then, self.marker_seen = phase_marker, then, marker_seen
        self.phase_start = None if phase_marker else time.time()
        self.first_step = None if phase_marker else 0   # counted step seen at phase_start
        self.last_step = None
        self.early = None     # the step at which the `then` phase started before total

    @staticmethod
    def _last_step(lines):
        step = None
        for line in lines:
            words = line.split()
            # thermo rows: all numbers, the first an integer step
            if words and words[0].isdigit() and all(_NUMBER.match(w) for w in words):
                step = int(words[0])
        return step

    def _scan(self):
        """(latest thermo step, whether the marker has been seen) of the log; sets self.early
        to the step at which the `then` phase started early (its marker's line), if it did."""
        text = self.log.read_text(errors="replace")
        marked = self.marker is None or self.marker in text
        if self.marker is not None and marked:
            text = text[text.index(self.marker):]
        early = self.then[2] if self.then and len(self.then) > 2 else None
        if early and self.early is None and early in text:
            before = text[:text.index(early)].splitlines()
            self.early = self._last_step(before) or 0
        return self._last_step(text.splitlines()[-50:]), marked

    def report(self):
        try:
            step, marked = self._scan()
        except OSError:
            return
        if marked and self.phase_start is None:
            self.phase_start, self.first_step = time.time(), step or 0
            if self.marker_seen is not None:
                self.marker_seen.set()
        if step is None or (step, marked) == self.last_step:
            return
        self.last_step = (step, marked)
        if not marked:
            print(f"    {self.label}: preparing (step {step})", file=sys.stderr, flush=True)
            return
        sim = f", t = {step * self.dt:.4g} s" if self.dt else ""
        if self.then and (step > self.total or self.early is not None):
            name, steps = self.then[:2]
            start = self.total if self.early is None else self.early
            print(f"    {self.label}: {name}: step {max(step - start, 0)}/{steps} at most{sim}",
                  file=sys.stderr, flush=True)
            return
        elapsed, done = time.time() - self.phase_start, step - self.first_step
        frac = min(step / self.total, 1.0)
        eta = f"{elapsed * max(self.total - step, 0) / done:.0f} s" \
            if done > 0 and elapsed > 0 else "n/a"
        most = " at most" if self.then and len(self.then) > 2 else ""
        print(f"    {self.label}: step {step}/{self.total}{most} ({100 * frac:.0f} %{sim}), "
              f"ETA {eta}{most}", file=sys.stderr, flush=True)
