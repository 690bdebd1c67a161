"""Studies and their cases: what `./wirenet run [STUDY|CASE]` runs, one folder per case.

A case writes DIR/CASE/case.json (status, wall time, case facts) next to its CSVs; a case whose
case.json says "ok" and whose CSVs exist is skipped, so an interrupted study resumes.
"""

import json
import math
import os
import time
from dataclasses import dataclass

import numpy as np

from . import impact, liggghts, punch, report
from .output import write_text

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


def punch_runner(panel):
    def run_punch_case(case_dir, quick=False, np_=1):
        return punch.run_case(case_dir, panel, "spheroid", bending=0.05, quick=quick, np_=np_)
    return run_punch_case


def impact_runner(panel):
    def run_impact_case(case_dir, quick=False, np_=1):
        return impact.run_case(case_dir, panel, bending=0.05, quick=quick, np_=np_)
    return run_impact_case


CALIBRATION_FRACTIONS = (0.0, 0.01, 0.05, 0.25, 1.0)

CASES = {"beam": ("beam", run_beam_case)}
for f in CALIBRATION_FRACTIONS:
    CASES[f"calibration_{f:g}"] = ("calibration", calibration_runner(f))
for name, panel in (("punch_hex", "hex"), ("punch_compound", "compound")):
    CASES[name] = ("punch", punch_runner(panel))
for name, panel in (("impact_hex", "hex"), ("impact_square", "square"),
                    ("impact_compound", "compound")):
    CASES[name] = ("impact", impact_runner(panel))

STUDIES = {"compound": list(CASES),
           "calibration": [n for n in CASES if n.startswith("calibration_")],
           "punch": [n for n in CASES if CASES[n][0] in ("calibration", "punch")],
           "impact": [n for n in CASES if CASES[n][0] == "impact"]}
# ./wirenet run calibration: the five cone punches; ./wirenet run punch: those and the two
# semi-spheroid punches
CSV_OF_KIND = {"beam": "beam.csv", "calibration": "platter.csv", "punch": "platter.csv",
               "impact": "block.csv"}


def _complete(case_dir, kind):
    meta = os.path.join(case_dir, "case.json")
    if not (os.path.isfile(meta) and os.path.isfile(os.path.join(case_dir, CSV_OF_KIND[kind]))):
        return False
    with open(meta) as fh:
        return json.load(fh).get("status") == "ok"


def _write_meta(case_dir, meta):
    write_text(os.path.join(case_dir, "case.json"), json.dumps(meta, indent=2) + "\n")


def run(args):
    """The ``study`` subcommand behind ``./wirenet run``."""
    target = args.study
    if target in STUDIES:
        names = STUDIES[target]
    elif target in CASES:
        names = [target]
    else:
        known = ", ".join(list(STUDIES) + list(CASES))
        raise SystemExit(f"wirenet run: error: unknown study or case '{target}' (known: {known})")
    out = args.out or os.path.join("out", target)
    os.makedirs(out, exist_ok=True)
    for k, name in enumerate(names, 1):
        kind, runner = CASES[name]
        case_dir = os.path.join(out, name)
        os.makedirs(case_dir, exist_ok=True)
        prefix = f"[case {k}/{len(names)}] {name}"
        if _complete(case_dir, kind):
            print(f"{prefix}: complete, skipped (delete {case_dir} to run it again)", flush=True)
            continue
        print(f"{prefix}: running", flush=True)
        start = time.time()
        facts = runner(case_dir, quick=args.quick, np_=args.np)
        wall = time.time() - start
        _write_meta(case_dir, dict(status="ok", kind=kind, wall_time=wall, np=args.np,
                                   quick=args.quick, **facts))
        print(f"{prefix}: done in {wall:.1f} s", flush=True)
    summary = report.build(out, expected=names)
    for claim in summary["claims"]:
        print(f"claim {claim['id']}: {claim['verdict']}")
    print(f"report: {os.path.join(out, 'report.md')}")
