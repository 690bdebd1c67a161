"""Running the project's binaries (LIGGGHTS, wirenet-gen) from Python, with progress output."""

import os
import re
import subprocess
import sys
import time
from pathlib import Path

from .errors import PostprocessError

ROOT = Path(__file__).resolve().parents[1]
INPUTS = ROOT / "inputs"


def build_dir():
    return Path(os.environ.get("WIRENET_BUILD", ROOT / "build"))


def binary(name):
    path = build_dir() / "bin" / name
    if not path.is_file():
        raise PostprocessError(f"{path}: not built (run ./wirenet setup)")
    return path


def mpi_env():
    # OpenMPI refuses to run as root without these; oversubscription keeps small machines usable.
    return dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1",
                OMPI_MCA_rmaps_base_oversubscribe="1")


def generate(kind, out_prefix, *options):
    """Run wirenet-gen KIND OPTIONS --out PREFIX; return PREFIX.data."""
    cmd = [str(binary("wirenet-gen")), *kind.split(), *map(str, options), "--out", str(out_prefix)]
    p = subprocess.run(cmd, capture_output=True, text=True)
    if p.returncode:
        raise PostprocessError(f"wirenet-gen failed: {p.stderr.strip()}")
    return f"{out_prefix}.data"


_NUMBER = re.compile(r"^[-+]?(\d+\.?\d*|\.\d+)([eE][-+]?\d+)?$")


def run(deck, workdir, variables=None, np=1, total_steps=None, label="", dt=None):
    """Run the deck file in workdir with -var NAME VALUE pairs; show progress (step, simulated
    time, ETA) on long runs; raise with LIGGGHTS' ERROR line on failure."""
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    # never "-screen none": LIGGGHTS 3.8's STL reader (input_mesh_tri.cpp) prints to the
    # screen without checking it, so any deck with a mesh would crash
    cmd = [str(binary("liggghts")), "-in", str(deck), "-log", "log.lammps", "-echo", "none",
           "-screen", "screen.txt"]
    for name, value in (variables or {}).items():
        cmd += ["-var", name, str(value)]
    if np > 1:
        cmd = ["mpirun", "-np", str(np)] + cmd
    start = time.time()
    proc = subprocess.Popen(cmd, cwd=workdir, env=mpi_env(), stdout=subprocess.PIPE,
                            stderr=subprocess.STDOUT, text=True)
    last = start
    while proc.poll() is None:
        time.sleep(0.5)
        if total_steps and time.time() - last > 5:
            last = time.time()
            _progress(workdir / "log.lammps", total_steps, start, label, dt)
    output = proc.stdout.read()
    log = (workdir / "log.lammps").read_text(errors="replace") if (workdir / "log.lammps").exists() else ""
    errors = [l for l in (log + output).splitlines() if "ERROR" in l]
    if proc.returncode or errors:
        msg = errors[0] if errors else (output.strip().splitlines() or ["no output"])[-1]
        raise PostprocessError(f"LIGGGHTS failed in {workdir}: {msg}")
    return time.time() - start


def _progress(log, total, start, label, dt):
    step = None
    try:
        for line in log.read_text(errors="replace").splitlines()[-50:]:
            words = line.split()
            # thermo rows: all numbers, the first an integer step
            if words and words[0].isdigit() and all(_NUMBER.match(w) for w in words):
                step = int(words[0])
    except OSError:
        return
    if not step:
        return
    elapsed = time.time() - start
    frac = min(step / total, 1.0)
    eta = elapsed * (1 - frac) / frac if frac > 0 else float("nan")
    sim = f", t = {step * dt:.4g} s" if dt else ""
    print(f"    {label}: step {step}/{total} ({100 * frac:.0f} %{sim}), ETA {eta:.0f} s",
          file=sys.stderr, flush=True)
