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
    if not os.access(path, os.X_OK):
        raise RunError(f"{path}: not executable (being rebuilt? run ./wirenet setup)")
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
        phase_marker=None, then=None, marker_seen=None, before=None):
    """Run the deck file in workdir with -var NAME VALUE pairs; show progress (step, simulated
    time, ETA) on long runs; raise with LIGGGHTS' ERROR line on failure. With phase_marker, the
    steps before the log line holding it are a preparation phase of unknown length (reported
    without ETA); total_steps and the ETA count from that line on; marker_seen (a
    threading.Event) is set once the progress scan has seen that line. then = (name, steps): a
    phase that may follow the counted steps for at most that many steps (a rest that ends when
    the motion has died down), reported as such; (name, steps, marker): the phase may start
    earlier, at the log line holding that marker (an impact that ends before its longest
    duration), and the counted steps are then given as at most. before = (name, steps): the
    preparation phase by name, at most so many steps (a settling that ends once still);
    (name, steps, False): exactly so many. A case of a study in partition mode
    (use_partitions) runs as one partition of a shared mpirun instead (Partitions)."""
    workdir = Path(workdir).resolve()
    workdir.mkdir(parents=True, exist_ok=True)
    deck = Path(deck).resolve()
    # the decks include their shared parts from ${inc} (inputs/include)
    variables = {"inc": str(INPUTS / "include"), **(variables or {})}
    cmd = _command(deck, variables)
    if np > 1:
        cmd = ["mpirun", "-np", str(np)] + cmd
    # the exact command, so that a run can be repeated by hand (from its folder)
    (workdir / "command.txt").write_text(" ".join(shlex.quote(c) for c in cmd) + "\n")
    if current_label():
        label = f"{current_label()}: {label}"
    follow = dict(total=total_steps, label=label, dt=dt, phase_marker=phase_marker, then=then,
                  marker_seen=marker_seen, before=before)
    pool = _PARTITIONS.get("pool")
    if pool is not None and pool.takes(current_label()):
        return pool.submit(_Request(deck, workdir, variables, current_label(), follow))
    start = time.time()
    # own process group: a signal to the study reaches LIGGGHTS only through stop_all, which
    # also reaches every rank under mpirun; the check and the start are one step under the lock
    proc = _start(cmd, workdir)
    try:
        progress = [Progress(workdir / "log.lammps", **follow)] if total_steps else []
        output = _follow(proc, progress, [current_label()] if current_label() else [])
    finally:
        with _LIVE_LOCK:
            _LIVE.discard(proc)
    _check(deck, workdir, proc.returncode, output)
    return time.time() - start


def _command(deck, variables):
    """LIGGGHTS' command line of a deck with its -var values (without mpirun)."""
    # never "-screen none": LIGGGHTS 3.8's STL reader (input_mesh_tri.cpp) prints to the
    # screen without checking it, so any deck with a mesh would crash
    cmd = [str(binary("liggghts")), "-in", str(deck), "-log", "log.lammps", "-echo", "none",
           "-screen", "screen.txt"]
    for name, value in variables.items():
        cmd += ["-var", name, str(value)]
    return cmd


def _start(cmd, workdir):
    """Popen of a LIGGGHTS command (or its mpirun) in its own process group, registered in
    _LIVE; refused once the study is stopping."""
    with _LIVE_LOCK:
        if _STOPPED.is_set():
            raise RunError(f"LIGGGHTS not started in {workdir}: the study is stopping")
        try:
            proc = subprocess.Popen(cmd, cwd=workdir, env=mpi_env(), stdout=subprocess.PIPE,
                                    stderr=subprocess.STDOUT, text=True, start_new_session=True,
                                    preexec_fn=_die_with_parent)
        except OSError as exc:      # the binary replaced under us (a rebuild), mpirun missing
            raise RunError(f"cannot start {cmd[0]} in {workdir}: "
                           f"{exc.strerror or exc}") from None
        _LIVE.add(proc)
    return proc


def _check(deck, workdir, returncode, output, other=""):
    """RunError with LIGGGHTS' ERROR line (of its log, else of its output) unless the run ended
    well; ``other``: why the process ended when this run's own log says nothing (a partition
    job that another partition stopped)."""
    log_path = workdir / "log.lammps"
    log = log_path.read_text(errors="replace") if log_path.exists() else ""
    own = [l for l in log.splitlines() if "ERROR" in l]
    errors = own or ([] if other else [l for l in output.splitlines() if "ERROR" in l])
    if returncode or errors:
        msg = errors[0] if errors else other or \
            (output.strip().splitlines() or ["no output"])[-1]
        raise RunError(f"LIGGGHTS failed in {workdir}: {msg}")
    # LIGGGHTS ends a run early, writes a restart and exits 0 on SIGTERM from outside: a deck
    # that prints END_MARKER as its last line must have reached it
    if END_MARKER in deck.read_text(errors="replace") and END_MARKER not in log:
        raise RunError(f"LIGGGHTS stopped before the end of {deck.name} in {workdir} "
                       f"(killed from outside?): the case is not complete")


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


def _follow(proc, progress, cases):
    """Wait for the process, printing the progress lines of each Progress every 5 s; return its
    output, read only at the end (LIGGGHTS must keep it short: -screen FILE). An interrupt (or
    any error) while it runs stops it: it must not outlive us."""
    last = time.time()
    try:
        while _reap(proc, cases) is None:
            time.sleep(0.5)
            if progress and time.time() - last > 5:
                last = time.time()
                for p in progress:
                    p.report()
    except BaseException:
        stop([proc])
        raise
    return proc.stdout.read()


def _reap(proc, cases):
    """proc's exit code once it has ended (reaped here with wait4, which also gives its CPU
    time and its waited-for children's, counted for the cases in equal shares), else None."""
    if proc.returncode is not None:
        return proc.returncode
    try:
        pid, status, usage = os.wait4(proc.pid, os.WNOHANG)
    except ChildProcessError:     # reaped elsewhere (stop(): an interrupted study)
        return proc.poll()
    if pid == 0:
        return None
    proc.returncode = os.waitstatus_to_exitcode(status)
    for case in cases:
        _CPU.add(case, (usage.ru_utime + usage.ru_stime) / len(cases))
    return proc.returncode


class Progress:
    """Progress lines of a running deck from the thermo rows of its log: one line whenever the
    step has moved, with the ETA of the counted phase (after phase_marker, if given); steps
    beyond it belong to the phase `then` = (name, at most so many steps), if given; the steps
    before the marker to the phase `before` = (name, at most so many steps), if given."""

    def __init__(self, log, total, label, dt, phase_marker=None, then=None, marker_seen=None,
                 before=None):
        self.log, self.total, self.label, self.dt = log, total, label, dt
        self.before = before
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
            most = " at most" if self.before and (len(self.before) < 3 or self.before[2]) else ""
            what = f"{self.before[0]}: step {step}/{self.before[1]}{most}" if self.before \
                else f"preparing (step {step})"
            print(f"    {self.label}: {what}", file=sys.stderr, flush=True)
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


# ---------------------------------------------------------------------------------------------
# LIGGGHTS' multi-partition mode

_PARTITIONS = {}      # "pool": the Partitions of a study in partition mode (use_partitions)


def use_partitions(pool):
    """Route the runs of the cases that join ``pool`` through it (None: back to one process
    per run)."""
    if pool is None:
        _PARTITIONS.pop("pool", None)
    else:
        _PARTITIONS["pool"] = pool


class _Request:
    """One run waiting for its partition: the deck, its folder and variables, the case it is
    for, its progress settings; then how it ended."""

    def __init__(self, deck, workdir, variables, case, follow):
        self.deck, self.workdir, self.variables, self.case = deck, workdir, variables, case
        self.follow = follow
        self.done = False
        self.error = None
        self.wall = 0.0


def wrapper_text(request):
    """The partition's own deck: into the run's folder, its log there, its variables as the
    command line would give them (index variables: the deck's own `index` defaults yield to
    them), then the deck."""
    def quoted(name, value):
        text = str(value)
        if '"' in text:
            raise RunError(f"{request.workdir}: {name}: a value with a double quote cannot be "
                           "handed to a partition")
        return f'"{text}"'
    lines = ["# one partition of a LIGGGHTS multi-partition job (runner/engine.py Partitions):",
             "# this run's folder, log and variables, then its deck; the same run alone:",
             "# command.txt", f"shell cd {quoted('folder', request.workdir)}",
             f"log {quoted('folder', request.workdir / 'log.lammps')}"]
    lines += [f"variable {name} index {quoted('-var ' + name, value)}"
              for name, value in request.variables.items()]
    lines.append(f"include {quoted('deck', request.deck)}")
    return "\n".join(lines) + "\n"


class Partitions:
    """The runs of the cases side by side in a study, gathered into LIGGGHTS' multi-partition
    mode: one `mpirun -np P*K liggghts -partition PxK` of P partitions of K ranks, each running
    one case's deck in its own folder (the top deck's `world` variable names each partition's
    wrapper, wrapper_text). A batch starts once every case that has joined waits for a run (at
    most ``slots`` cases join: the scheduler's capacity); runs of different decks (a stable-step
    probe beside an impact) share a batch. One partition's ERROR stops the whole job
    (LIGGGHTS: MPI_Abort): its case fails with its own ERROR line, the others with that one.
    ``folder``: where each batch keeps its top deck, command and universe log."""

    def __init__(self, slots, ranks, folder):
        self.slots, self.ranks, self.folder = slots, ranks, Path(folder)
        self.cond = threading.Condition()
        self.joined, self.waiting = set(), []
        self.batches = 0
        self.closed = False
        self.thread = threading.Thread(target=self._loop, daemon=True)
        self.thread.start()

    def takes(self, case):
        with self.cond:
            return case is not None and case in self.joined

    def join(self, case):
        with self.cond:
            self.joined.add(case)
            self.cond.notify_all()

    def leave(self, case):
        with self.cond:
            self.joined.discard(case)
            self.cond.notify_all()

    def close(self):
        with self.cond:
            self.closed = True
            self.cond.notify_all()
        self.thread.join()

    def submit(self, request):
        """Wait until the request's batch has run; its wall time, or its RunError."""
        with self.cond:
            self.waiting.append(request)
            self.cond.notify_all()
            while not request.done:
                self.cond.wait()
        if request.error is not None:
            raise request.error
        return request.wall

    def _ready(self):
        cases = {r.case for r in self.waiting}
        return bool(self.waiting) and (len(self.waiting) >= self.slots or self.joined <= cases)

    def _loop(self):
        while True:
            with self.cond:
                while not self.closed and not self._ready():
                    self.cond.wait()
                if self.closed:
                    for request in self.waiting:
                        request.error, request.done = RunError("the study stopped"), True
                    self.cond.notify_all()
                    return
                batch, self.waiting = self.waiting[:self.slots], self.waiting[self.slots:]
            try:
                self._run(batch)
            except BaseException as exc:    # noqa: B902 (handed to the cases' threads)
                for request in batch:
                    request.error = request.error or (
                        exc if isinstance(exc, RunError) else RunError(str(exc)))
            with self.cond:
                for request in batch:
                    request.done = True
                self.cond.notify_all()

    def _run(self, batch):
        """One mpirun of the batch's runs; each request's error (or none) set after it."""
        self.batches += 1
        folder = self.folder / f"batch_{self.batches:04d}"
        folder.mkdir(parents=True, exist_ok=True)
        wrappers = []
        for request in batch:
            path = request.workdir / "partition.in"
            path.write_text(wrapper_text(request))
            wrappers.append(f'"{path}"')
        (folder / "top.in").write_text(
            "# LIGGGHTS multi-partition job (runner/engine.py Partitions): partition N runs the\n"
            "# N-th wrapper, which goes into its run's folder and includes its deck\n"
            f"variable member world {' '.join(wrappers)}\ninclude ${{member}}\n")
        p, k = len(batch), self.ranks
        cmd = ["mpirun", "-np", str(p * k), str(binary("liggghts")), "-partition", f"{p}x{k}",
               "-in", "top.in", "-log", "log.lammps", "-plog", "log.partition",
               "-pscreen", "screen.partition", "-echo", "none"]
        (folder / "command.txt").write_text(" ".join(shlex.quote(c) for c in cmd) + "\n" +
                                            "".join(f"# partition {j}: {r.workdir}\n"
                                                    for j, r in enumerate(batch)))
        start = time.time()
        proc = _start(cmd, folder)
        try:
            progress = [Progress(r.workdir / "log.lammps", **r.follow) for r in batch
                        if r.follow["total"]]
            output = _follow(proc, progress, [r.case for r in batch])
        finally:
            with _LIVE_LOCK:
                _LIVE.discard(proc)
        failed = _first_error(batch)
        for request in batch:
            request.wall = time.time() - start
            why = f"the partition job ended (exit {proc.returncode}): {failed}" if failed else ""
            try:
                _check(request.deck, request.workdir, proc.returncode, output, why)
            except RunError as exc:
                request.error = exc


def _first_error(batch):
    """'FOLDER: ERROR line' of the first partition whose log holds an ERROR line, or ''."""
    for request in batch:
        log = request.workdir / "log.lammps"
        text = log.read_text(errors="replace") if log.exists() else ""
        line = next((l for l in text.splitlines() if "ERROR" in l), None)
        if line:
            return f"{request.workdir}: {line}"
    return ""
