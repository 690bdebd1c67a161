"""Studies and their cases: what `./wirenet run [STUDY|CASE]` runs, one folder per case.

A case writes DIR/CASE/case.json (status, wall time, case facts) next to its CSVs; a case whose
case.json says "ok" and whose CSVs exist is skipped, so an interrupted study resumes.
"""

import fcntl
import json
import math
import os
import shutil
import signal
import sys
import time
from dataclasses import dataclass

import numpy as np

from . import impact, liggghts, punch, report
from .model import PAPER_BENDING
from .output import write_json, write_text

# ---------------------------------------------------------------------------------------------
# Cantilever check (paper, Fig. 1): 2 m, d = 1 cm, E = 10 GPa, nu = 0.288, tip load.

BEAM = dict(length=2.0, diameter=0.01, young=1e10, nu=0.288, density=7850.0)


@dataclass
class Cantilever:
    elements: int
    load: float
    x: np.ndarray            # node positions along the beam [m]
    deflection: np.ndarray   # downward deflection [m]
    analytic: np.ndarray     # P x^2 (3L - x) / (6 f EI)

    @property
    def tip(self):
        return float(self.deflection[-1])

    @property
    def nrmse(self):
        span = self.analytic.max() - self.analytic.min()
        return float(np.sqrt(np.mean((self.deflection - self.analytic) ** 2)) / span)


def bending_stiffness(bending=1.0):
    return bending * BEAM["young"] * math.pi * BEAM["diameter"] ** 4 / 64


def cantilever(workdir, elements, load=0.01, bending=1.0, shear="eb", node_diameter=0.05,
               t_end=12.0, dt=None, np_=1):
    """Clamped chain with a tip load, damped to rest (viscous damping critical for the first
    bending mode: the rest state does not depend on it). Returns the deflection line."""
    L, d, rho = BEAM["length"], BEAM["diameter"], BEAM["density"]
    data = liggghts.generate("beam", os.path.join(workdir, f"beam{elements}"), "--elements", elements,
                             "--length", L, "--diameter", d, "--node-diameter", node_diameter,
                             "--density", rho)
    ei = bending_stiffness(bending)
    line_mass = rho * math.pi * d * d / 4
    omega1 = 1.875104 ** 2 * math.sqrt(ei / (line_mass * L ** 4))
    # a third of the axial wave crossing time of an element keeps Verlet well inside stability
    dt = dt or 0.35 * (L / elements) / math.sqrt(BEAM["young"] / rho)
    steps = int(t_end * math.sqrt(1.0 / bending) / dt)
    variables = dict(data=data, P=load, d=d, E=BEAM["young"], nu=BEAM["nu"], bending=bending,
                     shear=shear, dt=dt, steps=steps, gamma=2 * omega1 * line_mass * L / elements,
                     thermo_every=max(steps // 20, 1), out=f"final{elements}.dump")
    liggghts.run(liggghts.INPUTS / "cantilever.in", workdir, variables, np=np_, total_steps=steps,
                 label=f"{elements} elements", dt=dt)
    rows = np.loadtxt(os.path.join(workdir, f"final{elements}.dump"), skiprows=9, ndmin=2)
    rows = rows[np.argsort(rows[:, 0])]
    x = np.linspace(0.0, L, elements + 1)  # undeformed positions, where beam theory is written
    w = -rows[:, 3]
    return Cantilever(elements, load, x, w, load * x ** 2 * (3 * L - x) / (6 * ei))


def run_beam_case(case_dir, quick=False, np_=1):
    results = [cantilever(case_dir, n, np_=np_) for n in (5, 11, 21)]
    beam_rows = ["elements,load,tip_deflection,analytic_deflection,nrmse"]
    line_rows = ["x,deflection,elements,analytic_deflection"]
    for r in results:
        beam_rows.append(f"{r.elements},{r.load!r},{r.tip!r},{float(r.analytic[-1])!r},{r.nrmse!r}")
        line_rows += [f"{x!r},{w!r},{r.elements},{a!r}" for x, w, a in zip(r.x, r.deflection, r.analytic)]
    write_text(os.path.join(case_dir, "beam.csv"), "\n".join(beam_rows) + "\n")
    write_text(os.path.join(case_dir, "deflection.csv"), "\n".join(line_rows) + "\n")
    return {"max_nrmse": max(r.nrmse for r in results), "shear": "eb", "load": results[0].load}


# ---------------------------------------------------------------------------------------------

# Quasi-static punch cases (postprocess/punch.py, inputs/punch.in): cone on the square mesh for
# the bending calibration, semi-spheroid on the hexagonal and the compound panel.

def calibration_runner(fraction):
    def run_calibration_case(case_dir, quick=False, np_=1):
        return punch.run_case(case_dir, "square", "cone", bending=fraction, quick=quick, np_=np_)
    return run_calibration_case


def punch_runner(panel, rope_strength=False):
    def run_punch_case(case_dir, quick=False, np_=1):
        return punch.run_case(case_dir, panel, "spheroid", bending=PAPER_BENDING, quick=quick,
                              np_=np_, rope_strength=rope_strength)
    return run_punch_case


def impact_runner(panel, dissipation="local"):
    """An impact case under local damping (the paper's) or under bond damping instead."""
    model = dict(alpha=0.0, bond_zeta=impact.BOND_ZETA) if dissipation == "bond" else {}

    def run_impact_case(case_dir, quick=False, np_=1):
        return impact.run_case(case_dir, panel, bending=PAPER_BENDING, quick=quick, np_=np_,
                               **model)
    return run_impact_case


CALIBRATION_FRACTIONS = (0.0, 0.01, 0.05, 0.25, 1.0)

CASES = {"beam": ("beam", run_beam_case)}
for f in CALIBRATION_FRACTIONS:
    CASES[f"calibration_{f:g}"] = ("calibration", calibration_runner(f))
for name, panel in (("punch_hex", "hex"), ("punch_compound", "compound")):
    CASES[name] = ("punch", punch_runner(panel))
# beyond the paper: the compound punch with breakable ropes, to their failure or the travel's end
CASES["punch_compound_rope"] = ("punch", punch_runner("compound", rope_strength=True))
for name, panel in (("impact_hex", "hex"), ("impact_square", "square"),
                    ("impact_compound", "compound")):
    CASES[name] = ("impact", impact_runner(panel))
for name, panel in (("impact_hex", "hex"), ("impact_square", "square"),
                    ("impact_compound", "compound")):
    CASES[name + report.BOND_SUFFIX] = ("impact", impact_runner(panel, "bond"))

STUDIES = {"compound": list(CASES),
           "calibration": [n for n in CASES if n.startswith("calibration_")],
           "punch": [n for n in CASES if CASES[n][0] in ("calibration", "punch")],
           "impact": [n for n in CASES if CASES[n][0] == "impact"]}
# ./wirenet run calibration: the five cone punches; ./wirenet run punch: those and the two
# semi-spheroid punches
CSV_OF_KIND = {"beam": "beam.csv", "calibration": "platter.csv", "punch": "platter.csv",
               "impact": "block.csv"}


def _read_meta(case_dir):
    """case.json of a case folder as a dict, or None when absent or unreadable."""
    try:
        with open(os.path.join(case_dir, "case.json"), encoding="utf-8") as fh:
            meta = json.load(fh)
    except (OSError, ValueError):
        return None
    return meta if isinstance(meta, dict) else None


def _complete(case_dir, kind, quick):
    """Finished in the requested mode: status ok, the kind's CSV present, and the same --quick
    setting (a quick result never stands for a full case, nor the other way round)."""
    meta = _read_meta(case_dir)
    return (meta is not None and meta.get("status") == "ok" and
            bool(meta.get("quick")) == bool(quick) and
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


def _targets(target):
    if target in STUDIES:
        return STUDIES[target]
    if target in CASES:
        return [target]
    known = ", ".join(list(STUDIES) + list(CASES))
    raise StudyError(f"unknown study or case '{target}' (known: {known})")


MAX_RANKS = 4096


def _check_np(np_):
    if not 1 <= np_ <= MAX_RANKS:
        raise StudyError(f"--np must be an integer from 1 to {MAX_RANKS} (got {np_})")


def run_cases(names, out, quick, np_):
    """Run the cases not yet complete in this mode; the folder lock is held by the caller."""
    for k, name in enumerate(names, 1):
        kind, runner = CASES[name]
        case_dir = os.path.join(out, name)
        prefix = f"[case {k}/{len(names)}] {name}"
        if _complete(case_dir, kind, quick):
            print(f"{prefix}: complete, skipped (delete {case_dir} to run it again)", flush=True)
            continue
        _fresh_case_dir(case_dir)
        mode = "quick" if quick else "full"
        # 'running' until the runner returns: an interrupted or failed case is never 'ok'
        _write_meta(case_dir, dict(status="running", kind=kind, quick=quick, mode=mode, np=np_))
        print(f"{prefix}: running ({mode})", flush=True)
        start = time.time()
        try:
            facts = runner(case_dir, quick=quick, np_=np_)
        except Interrupted:
            _write_meta(case_dir, dict(status="interrupted", kind=kind, quick=quick, mode=mode,
                                       np=np_))
            raise
        except Exception as exc:
            _write_meta(case_dir, dict(status="failed", kind=kind, quick=quick, mode=mode, np=np_,
                                       error=str(exc)))
            raise
        wall = time.time() - start
        _write_meta(case_dir, dict(status="ok", kind=kind, wall_time=wall, np=np_, quick=quick,
                                   mode=mode, **facts))
        print(f"{prefix}: done in {wall:.1f} s", flush=True)


def run(args):
    """The ``study`` subcommand behind ``./wirenet run``. Paths are made absolute at once:
    LIGGGHTS runs inside each case folder, where a relative path would point elsewhere."""
    previous = {s: signal.signal(s, _raise_interrupt) for s in (signal.SIGINT, signal.SIGTERM)}
    try:
        _check_np(args.np)
        names = _targets(args.study)
        out = os.path.abspath(args.out or os.path.join("out", args.study))
        os.makedirs(out, exist_ok=True)
        start = time.time()
        with FolderLock(out):
            run_cases(names, out, args.quick, args.np)
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
