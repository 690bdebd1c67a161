"""The cantilever check of the beam law (paper, Fig. 1): 2 m, d = 1 cm, E = 10 GPa, nu = 0.288,
a tip load; the deflection line of 5, 11 and 21 elements against Euler-Bernoulli beam theory.
Deck: inputs/cantilever.in."""

import math
import os
from dataclasses import dataclass

import numpy as np

from postprocess import dumps
from postprocess.output import write_text

from .. import INPUTS, engine
from ..generator import generate
from ..params import Key
from .base import CaseKind

PAPER = "the paper (README: the study WireNet reproduces)"
# the paper's beam (Fig. 1); steel's density: the check runs without gravity, the mass only sets
# the dynamics of the damped approach to rest
BEAM = dict(length=2.0, diameter=0.01, young=1e10, nu=0.288, density=7850.0)
LOAD = 0.01          # N: within 0.1 % of the large-deflection solution (reference README)
# the check's shear spring: Euler-Bernoulli (12 alpha E I / l0^3), whose chain reproduces the
# closed form for any number of elements (reference README); the check's own, not the rope's
SHEAR_MODEL = "eb"

KEYS = (
    Key("cantilever.elements", "list-int", [5, 11, 21], "", "beam discretisations compared with "
        "the closed form", PAPER + ", Fig. 1"),
)


@dataclass
class Deflection:
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


def cantilever(workdir, elements, load=LOAD, bending=1.0, shear=None, node_diameter=0.05,
               t_end=12.0, dt=None, np_=1):
    """Clamped chain with a tip load, damped to rest (viscous damping critical for the first
    bending mode: the rest state does not depend on it). Returns the deflection line."""
    L, d, rho = BEAM["length"], BEAM["diameter"], BEAM["density"]
    data = generate("beam", os.path.join(workdir, f"beam{elements}"), "--elements", elements,
                    "--length", L, "--diameter", d, "--node-diameter", node_diameter,
                    "--density", rho)
    ei = bending_stiffness(bending)
    shear = shear or SHEAR_MODEL
    line_mass = rho * math.pi * d * d / 4
    omega1 = 1.875104 ** 2 * math.sqrt(ei / (line_mass * L ** 4))
    # a third of the axial wave crossing time of an element keeps Verlet well inside stability
    dt = dt or 0.35 * (L / elements) / math.sqrt(BEAM["young"] / rho)
    steps = int(t_end * math.sqrt(1.0 / bending) / dt)
    variables = dict(data=data, types=data[:-len(".data")] + ".types.in", P=load, d=d, E=BEAM["young"], nu=BEAM["nu"], bending=bending,
                     shear=shear, dt=dt, steps=steps, gamma=2 * omega1 * line_mass * L / elements,
                     thermo_every=max(steps // 20, 1), out=f"final{elements}.dump")
    engine.run(INPUTS / "cantilever.in", workdir, variables, np=np_, total_steps=steps,
               label=f"{elements} elements", dt=dt)
    frame = next(dumps.iter_frames(os.path.join(workdir, f"final{elements}.dump")))
    order = np.argsort(frame.column("id"))
    x = np.linspace(0.0, L, elements + 1)  # undeformed positions, where beam theory is written
    w = -frame.column("z")[order]
    return Deflection(elements, load, x, w, load * x ** 2 * (3 * L - x) / (6 * ei))


class Cantilever(CaseKind):
    name = "cantilever"
    summary = "the cantilever check of the beam law (paper, Fig. 1)"
    deck = "cantilever.in"
    keys = KEYS
    takes = ("title", "cantilever.*")
    finished_file = "beam.csv"

    def record_kind(self):
        return "beam"

    def run(self, index, ctx):
        results = [cantilever(ctx.case_dir, n, np_=ctx.ranks)
                   for n in self.case["cantilever.elements"]]
        beam_rows = ["elements,load,tip_deflection,analytic_deflection,nrmse"]
        line_rows = ["x,deflection,elements,analytic_deflection"]
        for r in results:
            beam_rows.append(f"{r.elements},{r.load!r},{r.tip!r},{float(r.analytic[-1])!r},"
                             f"{r.nrmse!r}")
            line_rows += [f"{x!r},{w!r},{r.elements},{a!r}"
                          for x, w, a in zip(r.x, r.deflection, r.analytic)]
        write_text(os.path.join(ctx.case_dir, "beam.csv"), "\n".join(beam_rows) + "\n")
        write_text(os.path.join(ctx.case_dir, "deflection.csv"), "\n".join(line_rows) + "\n")
        return {"max_nrmse": max(r.nrmse for r in results), "shear": SHEAR_MODEL,
                "load": results[0].load}
