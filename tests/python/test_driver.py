"""The ./wirenet driver as a user types it: the README's commands from the repository root with
the default output folder, a relative --out from another folder, exit codes of bad commands,
interrupts (no orphaned LIGGGHTS, the case redone), a second run into a busy folder, quick vs
full results, and file modes under umask 022."""

import fcntl
import json
import os
import pathlib
import shutil
import signal
import stat
import subprocess
import time

import pytest

import lmp

DRIVER = lmp.ROOT / "wirenet"


def driver(*args, cwd=lmp.ROOT, timeout=600, umask=None, setup=False, env_extra=None):
    """Run ./wirenet; the set-up step (apt check, incremental build: about 7 s) only where the
    test is about the command exactly as typed."""
    env = dict(os.environ, WIRENET_BUILD=str(lmp.BUILD))
    env.pop("WIRENET_NP", None)      # the defaults under test are the machine's, not the caller's
    if not setup:
        env["WIRENET_SETUP"] = "skip"
    env.update(env_extra or {})

    def preexec():
        if umask is not None:
            os.umask(umask)
    return subprocess.run([str(DRIVER), *args], cwd=cwd, env=env, capture_output=True, text=True,
                          timeout=timeout, preexec_fn=preexec)


def untracked():
    """Files git sees as new or changed (empty when the tree is not a git checkout)."""
    if not (lmp.ROOT / ".git").exists():
        return set()
    p = subprocess.run(["git", "status", "--porcelain", "--untracked-files=all"], cwd=lmp.ROOT,
                       capture_output=True, text=True)
    return set(p.stdout.splitlines()) if p.returncode == 0 else set()


@pytest.fixture
def default_out():
    """out/beam of the repository, moved aside while the test runs (a user's results stay)."""
    out = lmp.ROOT / "out" / "beam"
    saved = lmp.ROOT / "out" / ".beam.saved-by-test"
    if out.exists():
        shutil.rmtree(saved, ignore_errors=True)
        out.rename(saved)
    yield out
    shutil.rmtree(out, ignore_errors=True)
    if saved.exists():
        saved.rename(out)


def test_readme_command_from_the_repository_root(default_out):
    """`./wirenet run beam --quick` exactly as typed: default output folder out/beam, a report,
    and nothing new in the source tree outside out/ (no stray log.liggghts)."""
    before = untracked()
    p = driver("run", "beam", "--quick", setup=True)
    assert p.returncode == 0, p.stdout[-2000:] + p.stderr[-2000:]
    assert (default_out / "report.md").is_file()
    meta = json.loads((default_out / "beam" / "case.json").read_text())
    assert meta["status"] == "ok" and meta["mode"] == "quick"
    assert meta["np"] == len(os.sched_getaffinity(0))     # --np defaults to the cores (nproc)
    stray = {line for line in untracked() - before if not line[3:].startswith("out/")}
    assert not stray, f"the run left files in the source tree: {stray}"


def test_relative_out_from_another_folder(tmp_path):
    p = driver("run", "beam", "--quick", "--out", "rel/study", cwd=tmp_path)
    assert p.returncode == 0, p.stderr[-2000:]
    assert (tmp_path / "rel" / "study" / "report.md").is_file()
    assert (tmp_path / "rel" / "study" / "beam" / "beam.csv").is_file()


@pytest.mark.parametrize("args, phrase", [
    (("run", "beam", "--np", "0"), "--np: expected an integer > 0, got '0'"),
    (("run", "beam", "--np", "-1"), "--np: expected an integer > 0, got '-1'"),
    (("run", "no_such_case"), "unknown study or case 'no_such_case'"),
    (("frobnicate",), "unknown command 'frobnicate'"),
])
def test_bad_commands_exit_2_with_one_line(tmp_path, args, phrase):
    if args[0] == "run":
        args += ("--out", str(tmp_path / "o"))
    p = driver(*args, cwd=tmp_path)
    assert p.returncode == 2, (p.returncode, p.stderr)
    errors = [l for l in p.stderr.splitlines() if "error" in l]
    assert len(errors) == 1 and phrase in errors[0], p.stderr
    assert not errors[0].endswith(" 2"), p.stderr   # the exit code is not part of the message
    assert "Traceback" not in p.stderr
    assert not (tmp_path / "o").exists() or not any((tmp_path / "o").iterdir())


@pytest.mark.parametrize("variable, value, expected", [
    ("WIRENET_SETUP", "skp", "skip or unset"),
    ("WIRENET_JOBS", "abc", "an integer > 0"),
    ("WIRENET_JOBS", "0", "an integer > 0"),
    ("WIRENET_SUBNORMALS", "kep", "keep or flush"),
])
@pytest.mark.parametrize("command", ["run", "setup"])   # quick even if the check were missing
def test_bad_environment_exits_2_with_one_line(tmp_path, variable, value, expected, command):
    """A mistyped variable of the driver is refused before anything runs or is written, not
    silently read as its default (WIRENET_SETUP=skp did a full set-up; WIRENET_SUBNORMALS=kep
    flushed)."""
    args = ("run", "beam", "--quick", "--out", str(tmp_path / "o")) if command == "run" else (command,)
    p = driver(*args, cwd=tmp_path, env_extra={variable: value})
    assert p.returncode == 2, (p.returncode, p.stderr[-2000:])
    assert p.stderr.splitlines() == [f"wirenet: error: {variable} must be {expected} (got '{value}')"]
    assert p.stdout == "" and not (tmp_path / "o").exists()


@pytest.mark.parametrize("value", ["abc", "0", "2.5", "-3"])
def test_bad_wirenet_np_exits_2_with_one_line(tmp_path, value):
    p = driver("run", "beam", "--quick", "--out", str(tmp_path / "o"), cwd=tmp_path,
               env_extra={"WIRENET_NP": value})
    assert p.returncode == 2, (p.returncode, p.stderr)
    errors = [l for l in p.stderr.splitlines() if "error" in l]
    assert errors == [f"wirenet run: error: WIRENET_NP must be an integer from 1 to 4096 "
                      f"(got '{value}')"], p.stderr
    assert not (tmp_path / "o").exists()


def test_wirenet_np_sets_the_default_and_np_wins(tmp_path):
    p = driver("run", "beam", "--quick", "--out", str(tmp_path / "a"), env_extra={"WIRENET_NP": "2"})
    assert p.returncode == 0, p.stderr[-2000:]
    assert json.loads((tmp_path / "a" / "beam" / "case.json").read_text())["np"] == 2
    p = driver("run", "beam", "--quick", "--np", "1", "--out", str(tmp_path / "b"),
               env_extra={"WIRENET_NP": "2"})
    assert p.returncode == 0, p.stderr[-2000:]
    assert json.loads((tmp_path / "b" / "beam" / "case.json").read_text())["np"] == 1


def test_busy_output_folder_is_refused(tmp_path):
    """A second run into a folder that a run holds stops at once with one line."""
    out = tmp_path / "busy"
    out.mkdir()
    with open(out / ".wirenet.lock", "a+") as held:
        fcntl.flock(held, fcntl.LOCK_EX | fcntl.LOCK_NB)
        held.write("pid 12345\n")
        held.flush()
        p = driver("run", "beam", "--quick", "--out", str(out))
    assert p.returncode == 2, p.stderr
    assert "is in use by another run (pid 12345)" in p.stderr
    assert not (out / "beam").exists()


def test_quick_result_never_stands_for_a_full_case(tmp_path):
    out = tmp_path / "s"
    assert driver("run", "beam", "--quick", "--out", str(out)).returncode == 0
    p = driver("run", "beam", "--quick", "--out", str(out))
    assert "complete, skipped" in p.stdout
    p = driver("run", "beam", "--out", str(out))
    assert p.returncode == 0, p.stderr[-2000:]
    assert "complete, skipped" not in p.stdout and "running (full" in p.stdout
    meta = json.loads((out / "beam" / "case.json").read_text())
    assert meta["quick"] is False and meta["mode"] == "full"
    summary = json.loads((out / "summary.json").read_text())
    assert summary["cases"]["beam"]["mode"] == "full"
    assert "| beam | beam | full |" in (out / "report.md").read_text()


def test_outputs_honour_the_umask(tmp_path):
    out = tmp_path / "modes"
    p = driver("run", "beam", "--quick", "--out", str(out), umask=0o022)
    assert p.returncode == 0, p.stderr[-2000:]
    wrong = []
    for path in [out, *out.rglob("*")]:
        mode = stat.S_IMODE(path.stat().st_mode)
        want = 0o755 if path.is_dir() else 0o644
        if mode != want and not (path.is_file() and mode == 0o755):
            wrong.append(f"{path.relative_to(out)}: {oct(mode)}")
    assert not wrong, wrong


def _liggghts_in(folder):
    """(PID, program) of the processes whose working folder lies in ``folder``."""
    pids = []
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            cwd = os.readlink(f"/proc/{pid}/cwd")
        except OSError:
            continue
        if cwd.startswith(str(folder)):
            try:
                with open(f"/proc/{pid}/cmdline", "rb") as fh:
                    name = fh.read().split(b"\0")[0].decode(errors="replace")
            except OSError:
                name = "?"
            pids.append((int(pid), name))
    return pids


def _assert_redone(out, case):
    """The next run into ``out`` runs the unfinished case again, to its end."""
    p = driver("run", "impact_compound", "--quick", "--out", str(out))
    assert p.returncode == 0, p.stderr[-2000:]
    assert "complete, skipped" not in p.stdout
    assert json.loads((case / "case.json").read_text())["status"] == "ok"


def _start_quick_impact(cwd, out):
    """./wirenet run impact_compound --quick into ``out``, returned once its LIGGGHTS runs:
    (the driver's process, the case folder)."""
    env = dict(os.environ, WIRENET_BUILD=str(lmp.BUILD), WIRENET_SETUP="skip")
    proc = subprocess.Popen([str(DRIVER), "run", "impact_compound", "--quick", "--out", str(out)],
                            cwd=cwd, env=env, stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    case = out / "impact_compound"
    deadline = time.time() + 300
    while time.time() < deadline and not _liggghts_in(case):
        if proc.poll() is not None:
            _stop(proc)
            raise AssertionError(proc.communicate())
        time.sleep(0.2)
    if not _liggghts_in(case):
        _stop(proc)
        raise AssertionError("LIGGGHTS never started")
    return proc, case


@pytest.mark.parametrize("sig, code", [(signal.SIGTERM, 143), (signal.SIGINT, 130)])
def test_interrupt_stops_liggghts_and_the_case_is_redone(tmp_path, sig, code):
    out = tmp_path / "int"
    proc, case = _start_quick_impact(tmp_path, out)
    try:
        time.sleep(1.0)
        proc.send_signal(sig)
        stdout, stderr = proc.communicate(timeout=60)
        assert proc.returncode == code, (proc.returncode, stderr)
        lines = [l for l in stderr.splitlines() if l.strip()]
        assert lines and "interrupted" in lines[-1], stderr
        assert "Traceback" not in stderr
        # LIGGGHTS is gone when the study exits; a singleton's OpenMPI daemon (orted, in a session
        # of its own) follows once it sees its LIGGGHTS die: allow it a few seconds
        deadline = time.time() + 10
        while _liggghts_in(case) and time.time() < deadline:
            time.sleep(0.2)
        assert not _liggghts_in(case), "LIGGGHTS processes outlived the interrupted study"
        meta = json.loads((case / "case.json").read_text())
        assert meta["status"] == "interrupted"
        if sig == signal.SIGTERM:   # the next run redoes the case (once is enough)
            _assert_redone(out, case)
    finally:
        _stop(proc)


def test_a_killed_runner_takes_its_liggghts_with_it_and_the_case_resumes(tmp_path):
    """Issue #43: SIGKILL cannot be trapped, so the runner cannot stop LIGGGHTS itself: its ranks
    must stop when it dies (the parent-death signal of runner/engine.py), and the next run into
    the same folder (the lock died with the runner) redoes the case."""
    out = tmp_path / "killed"
    proc, case = _start_quick_impact(tmp_path, out)
    try:
        runners = [pid for pid, cmd in _processes_naming(str(out)) if "-m runner" in cmd]
        assert len(runners) == 1, _processes_naming(str(out))
        os.kill(runners[0], signal.SIGKILL)
        proc.communicate(timeout=60)
        deadline = time.time() + 15
        while _liggghts_in(case) and time.time() < deadline:
            time.sleep(0.2)
        assert not _liggghts_in(case), "LIGGGHTS processes outlived the killed runner"
        _assert_redone(out, case)
    finally:
        _stop(proc)


def _stop(proc):
    """A driver a failed test left running: SIGTERM, which its trap passes on to its child."""
    if proc.poll() is None:
        proc.send_signal(signal.SIGTERM)
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            proc.kill()


def _processes_naming(text):
    found = []
    for pid in filter(str.isdigit, os.listdir("/proc")):
        try:
            with open(f"/proc/{pid}/cmdline", "rb") as fh:
                cmd = fh.read().replace(b"\0", b" ").decode(errors="replace")
        except OSError:
            continue
        if text in cmd and int(pid) != os.getpid():
            found.append((int(pid), cmd[:120]))
    return found


def test_interrupt_during_setup_stops_the_build(tmp_path):
    """SIGTERM while the set-up configures a new build folder: the driver exits 143 at once
    with one line, and no cmake, make or tar of that folder lives on."""
    # the build keeps the tarball it fetched; an offline build names its local copy instead
    tarball = pathlib.Path(os.environ.get("WIRENET_LIGGGHTS_TARBALL") or
                           lmp.BUILD / "downloads" / "liggghts_3.8.0+repack1.orig.tar.xz")
    assert tarball.is_file(), f"no LIGGGHTS tarball at {tarball}"
    build = tmp_path / "fresh-build"
    env = dict(os.environ, WIRENET_BUILD=str(build), WIRENET_LIGGGHTS_TARBALL=str(tarball))
    env.pop("WIRENET_SETUP", None)     # this test is of the set-up itself (a suite run with skip)
    proc = subprocess.Popen([str(DRIVER), "setup"], cwd=tmp_path, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    try:
        deadline = time.time() + 60
        while time.time() < deadline and not _processes_naming(str(build)):
            assert proc.poll() is None, proc.communicate()
            time.sleep(0.1)
        assert _processes_naming(str(build)), "the set-up never started configuring"
        time.sleep(1.0)
        start = time.time()
        proc.send_signal(signal.SIGTERM)
        _, stderr = proc.communicate(timeout=30)
        assert proc.returncode == 143, (proc.returncode, stderr)
        assert time.time() - start < 10, "the signal waited for the build step"
        assert stderr.strip().splitlines()[-1] == "wirenet: interrupted (SIGTERM)"
        deadline = time.time() + 10
        while _processes_naming(str(build)) and time.time() < deadline:
            time.sleep(0.2)
        assert not _processes_naming(str(build)), _processes_naming(str(build))
    finally:
        _stop(proc)


def _two_impacts(tmp_path, second="impact_hex"):
    """A study file of two impact cases (names of inputs/cases)."""
    study = tmp_path / "two.toml"
    study.write_text(f'cases = ["impact_compound", "{second}"]\n')
    return study


def test_cases_of_a_study_run_side_by_side(tmp_path):
    """On two cores two impacts run at once, one rank each: the second starts before the first
    ends, and each case.json says 1 rank; alone, a case takes both."""
    out = tmp_path / "side"
    p = driver("run", str(_two_impacts(tmp_path)), "--quick", "--np", "2", "--out", str(out))
    assert p.returncode == 0, p.stderr[-2000:]
    lines = p.stdout.splitlines()
    started = next(k for k, l in enumerate(lines) if l.startswith("[case 2/2] impact_hex: running"))
    first_done = next(k for k, l in enumerate(lines) if l.startswith("[case 1/2] impact_compound: done"))
    assert started < first_done, p.stdout
    metas = [json.loads((out / name / "case.json").read_text())
             for name in ("impact_compound", "impact_hex")]
    assert all(m["np"] == 1 for m in metas)
    # the report's elapsed time is the span of the overlapping cases, less than their sum
    span = max(m["finished"] for m in metas) - min(m["started"] for m in metas)
    assert span < sum(m["wall_time"] for m in metas)
    assert f"From the first start to the last end: {span:.0f} s" in (out / "report.md").read_text()
    p = driver("run", "impact_square", "--quick", "--np", "2", "--out", str(out))
    assert p.returncode == 0 and "(quick, 2 ranks)" in p.stdout, p.stdout


def test_interrupt_stops_every_case_running_side_by_side(tmp_path):
    out = tmp_path / "int2"
    env = dict(os.environ, WIRENET_BUILD=str(lmp.BUILD), WIRENET_SETUP="skip")
    proc = subprocess.Popen([str(DRIVER), "run", str(_two_impacts(tmp_path)), "--quick", "--np",
                             "2", "--out", str(out)], cwd=tmp_path, env=env,
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    cases = [out / "impact_compound", out / "impact_hex"]
    try:
        deadline = time.time() + 300
        while time.time() < deadline and not all(_liggghts_in(c) for c in cases):
            assert proc.poll() is None, proc.communicate()
            time.sleep(0.1)
        assert all(_liggghts_in(c) for c in cases), "the two cases never ran at once"
        proc.send_signal(signal.SIGTERM)
        stdout, stderr = proc.communicate(timeout=60)
        assert proc.returncode == 143, (proc.returncode, stderr)
        assert "Traceback" not in stderr
        deadline = time.time() + 10
        while any(_liggghts_in(c) for c in cases) and time.time() < deadline:
            time.sleep(0.2)
        assert not any(_liggghts_in(c) for c in cases), "LIGGGHTS outlived the study"
        for c in cases:
            assert json.loads((c / "case.json").read_text())["status"] == "interrupted", c.name
    finally:
        _stop(proc)


def test_a_failed_case_stops_the_one_beside_it(tmp_path):
    """A case that fails (here: its LIGGGHTS binary is not there) stops the study with one line;
    the case running beside it is stopped and marked interrupted, never left 'running'."""
    out = tmp_path / "fail"
    study = _two_impacts(tmp_path)
    build = tmp_path / "build"
    (build / "bin").mkdir(parents=True)
    os.symlink(lmp.BUILD / "bin" / "wirenet-gen", build / "bin" / "wirenet-gen")
    # the first case's LIGGGHTS runs (a real one); the second's is a script that fails at once
    real = lmp.BUILD / "bin" / "liggghts"
    flag = tmp_path / "first-started"
    (build / "bin" / "liggghts").write_text(
        "#!/bin/sh\n"
        f'case "$PWD" in */impact_hex/*) while [ ! -e {flag} ]; do sleep 0.1; done; '
        'echo "ERROR: made to fail by the test" >&2; exit 1;; esac\n'
        f"touch {flag}\nexec {real} \"$@\"\n")
    (build / "bin" / "liggghts").chmod(0o755)
    p = driver("run", str(study), "--quick", "--np", "2", "--out", str(out),
               env_extra={"WIRENET_BUILD": str(build)})
    assert p.returncode != 0
    assert "made to fail by the test" in p.stderr and "Traceback" not in p.stderr
    assert json.loads((out / "impact_hex" / "case.json").read_text())["status"] == "failed"
    assert json.loads((out / "impact_compound" / "case.json").read_text())["status"] == "interrupted"


def test_mpi_runs_get_the_shared_memory_tuning_unless_the_user_set_it(monkeypatch):
    """The runs' OpenMPI environment sends a net's ghost messages eagerly through the shared
    buffers (docs/PERFORMANCE.md: 2 ranks 1.5x instead of 1.1x), and a user's own value wins."""
    from runner import engine
    monkeypatch.delenv("OMPI_MCA_btl_vader_eager_limit", raising=False)
    monkeypatch.setenv("OMPI_MCA_btl_vader_single_copy_mechanism", "cma")
    env = engine.mpi_env()
    assert env["OMPI_MCA_btl_vader_eager_limit"] == "65536"
    assert env["OMPI_MCA_btl_vader_single_copy_mechanism"] == "cma"
    assert env["OMPI_ALLOW_RUN_AS_ROOT"] == "1"
