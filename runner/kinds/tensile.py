"""Tensile test cases: a strip of net clamped along two opposite edges (EN 10223-3's test of
double-twist meshes; YADE's examples/WireMatPM/wiretensiltest.py), or a single wire or strand
rope (a chain of bonds), pulled until it fails. Deck: inputs/tensile.in; doc/tensile.md.

Outputs the curve F(u) (tensile.csv), and the figures of a manufacturer's data sheet: the
strength per metre of width (peak force / strip width), the elongation at the peak and at
failure (displacement / clamp distance), the first rupture and where it happened. The run's
quasi-static evidence is the punch's (runner/quasistatic.py): a twin four times slower, the
kinetic energy against the work, and the clamps' equilibrium (the fixed clamp's reaction
against the force on the moving one).
"""

import math
import os
import threading

import numpy as np

from postprocess import record
from postprocess.csvio import read_csv, write_csv
from postprocess.meta import read_json

from .. import INPUTS, engine, netoutputs, quasistatic, timestep
from ..errors import RunError
from ..generator import generate
from ..materials import bending_of, rope_strength_keyword
from ..panel import Panel
from ..params import ByKey, Key
from .base import CaseKind

YADE = "YADE's examples/WireMatPM/wiretensiltest.py (Debian package yade)"
DT_SAFETY = 0.5        # half the stable step
RAMP_STEPS = 200       # the clamp's speed grows from 0 over so many steps (no shock)
FAILED = "tensile: failed:"   # the deck's line when the force has dropped after a rupture
TABLE = "tensile.csv"


def _tensile(name, type_, default, unit, doc, source, **kw):
    return Key(f"tensile.{name}", type_, default, unit, doc, source, **kw)


KEYS = (
    _tensile("specimen", "choice", "net", "", "net: a strip of the net of [panel] (panel.width "
             "wide across the pull, panel.height long along it for tensile.direction along); "
             "wire: a single mesh wire (materials.wire_d); rope: a strand rope (materials.rope_d, "
             "the beam law)", "EN 10223-3 (the mesh), its wire and rope tests",
             choices=("net", "wire", "rope")),
    _tensile("direction", "choice", "along", "", "net: the pull along the twists (y, the "
             "standard's longitudinal strength) or across them (x, transverse)", "EN 10223-3",
             choices=("along", "across")),
    _tensile("chain_length", "number", 0.5, "m", "wire or rope: the clamp distance",
             "WireNet", low=0.01, high=10.0),
    _tensile("chain_elements", "integer", 5, "", "wire or rope: bonds in series", "WireNet",
             low=1, high=1000),
    _tensile("speed", "number", 0.05, "m/s", "the moving clamp's speed", YADE + " (0.1 1/s on "
             "0.52 m: 0.052 m/s); the slower twin checks that the result does not depend on it",
             low=1e-6, high=10.0, var="speed"),
    _tensile("travel", "number", ByKey("tensile.specimen", {"net": 0.2, "wire": 0.2,
                                                            "rope": 0.05}),
             "m", "the moving clamp's largest travel (the run ends earlier once the specimen "
             "has failed: tensile.stop_drop)", "WireNet", low=1e-4, high=10.0, var="travel",
             quick=ByKey("tensile.specimen", {"net": 0.06, "wire": 0.2, "rope": 0.05})),
    _tensile("stop_drop", "number", 0.5, "", "failure: the first row after a rupture whose "
             "force is below this fraction of the peak so far ends the test (0: the whole "
             "travel)", "EN 10223-3 (the test ends at the failure)", low=0.0, high=0.999,
             var="stop_drop"),
    _tensile("quasi_static_check", "bool", True, "", "run the same test 4x slower beside it "
             "and compare the force curves (the quasi-static proof; doc/punch.md); false: no "
             "twin, the evidence recorded but not deciding the status",
             "doc/punch.md"),
    _tensile("report_at", "list-number", [0.01, 0.02, 0.04], "m", "displacements at which "
             "case.json gives the force (YADE's comparison points)", YADE),
)


class Setup:
    """The specimen and every number the deck needs, from the checked case."""

    def __init__(self, kind, workdir, bending):
        c = kind.case
        self.kind, self.case, self.workdir, self.bending = kind, c, workdir, bending
        os.makedirs(workdir, exist_ok=True)
        self.specimen = c["tensile.specimen"]
        if self.specimen == "net":
            self.panel = Panel(c, workdir)
            self.data_path, self.types_path = self.panel.data_path, self.panel.types_path
            self.json_path, self.layers = self.panel.json_path, self.panel.layers
            along = c["tensile.direction"] == "along"
            self.axis = "y" if along else "x"
            self.length = c["panel.height"] if along else c["panel.width"]
            self.width = c["panel.width"] if along else c["panel.height"]
        else:
            self.panel, self.layers, self.axis = None, 1, "x"
            self.length, self.width = c["tensile.chain_length"], None
            d = c["materials.wire_d"] if self.specimen == "wire" else c["materials.rope_d"]
            prefix = os.path.join(workdir, "chain")
            # the wire's or rope's own mass lumped to the nodes (steel 7850 kg/m3)
            self.data_path = generate("beam", prefix, "--elements", c["tensile.chain_elements"],
                                      "--length", self.length, "--diameter", d,
                                      "--node-diameter", 4 * d, "--density", 7850.0)
            self.types_path, self.json_path = prefix + ".types.in", prefix + ".json"
        self.speed, self.travel = c["tensile.speed"], c["tensile.travel"]
        self.dt = DT_SAFETY * self._stable_step()
        self.every = max(int(round(c["output.row_travel"] / (self.speed * self.dt))), 1)
        if self.every >= 200:       # 20 kinetic-energy samples a row, as the punch
            self.every = 20 * int(round(self.every / 20))

    def _stable_step(self):
        """The stable step of the specimen alone (the free step: no loading body; a compound
        net's layers press each other)."""
        if self.panel is not None:
            return timestep.of_panel(self.panel, self.base_variables(), self.workdir).free
        probe = os.path.join(self.workdir, "timestep")
        engine.run(INPUTS / "tensile.in", probe, dict(self.base_variables(1.0), probe=1),
                   label="stable step")
        return timestep.read(probe).free

    def base_variables(self, speed_factor=1.0):
        c = self.case
        v = dict(self.kind.key_variables(), data=os.path.abspath(self.data_path),
                 types=os.path.abspath(self.types_path), layers=self.layers,
                 bending=repr(self.bending), axis=self.axis,
                 specimen="net" if self.specimen == "net" else "chain",
                 chain_law="wire" if self.specimen == "wire" else "beam",
                 chain_d=repr(c["materials.wire_d"]), mass_scale="1.0",
                 ghost=repr(3.0 * read_json(self.json_path)["max_bond_length"]))
        if c["materials.rope_strength"]:
            v["rope_strength"] = rope_strength_keyword(True, self.kind.material_values())
        return v

    def variables(self, speed_factor=1.0, travel=None, stop_broken=0):
        c = self.case
        travel = travel or self.travel
        speed = self.speed / speed_factor
        every = self.every * int(speed_factor)
        steps = int(math.ceil(travel / (speed * self.dt)))
        return dict(self.base_variables(), speed=repr(speed), travel=repr(travel),
                    dt=repr(self.dt), nramp=RAMP_STEPS, every=every,
                    ke_every=every // 20 if every % 20 == 0 else 1,
                    dump_every=every * c["output.dump_rows"],
                    frame_every=max(int(math.ceil(steps / c["output.frames"])), 1),
                    stop_broken=stop_broken, out=".", probe=0), steps


def read_table(workdir):
    return read_csv(os.path.join(workdir, TABLE), required=(
        "time", "displacement", "force", "reaction", "weight", "ke", "broken", "step"))


def failure(table, drop):
    """(displacement, force) where the specimen failed: the first row after a rupture whose
    force is below ``drop`` x the peak so far; None if it held."""
    f, broken = table["force"], table["broken"]
    peak = np.maximum.accumulate(f)
    hit = np.nonzero((broken > 0) & (f < drop * peak))[0]
    return (float(table["displacement"][hit[0]]), float(f[hit[0]])) if hit.size else None


def force_at(table, u):
    """The force at the clamp's travel u (linear between rows), None beyond the run."""
    d = np.r_[0.0, table["displacement"]]
    if u > d[-1]:
        return None
    return float(np.interp(u, d, np.r_[0.0, table["force"]]))


class Tensile(CaseKind):
    name = "tensile"
    summary = "a tensile test of a net strip, a wire or a rope (EN 10223-3)"
    deck = "tensile.in"
    keys = KEYS
    takes = ("title", "gravity", "panel.net", "panel.width", "panel.height", "panel.placement",
             "panel.selvedge", "panel.hex_node_radius", "panel.hex_node_mass",
             "panel.square_node_radius", "panel.rope_mass", "panel.axis_distance",
             "panel.twist_length", "panel.rise", "panel.cell", "panel.rope_elements",
             "materials.*", "contact.kn",
             "contact.ks", "contact.mu", "damping.*", "tensile.*", "output.row_travel",
             "output.dump_rows", "output.frames")
    # no gravity (a test rig's strip lies in its frame); the local damping of YADE's example
    defaults = {"gravity": 0.0, "damping.local": 0.5, "panel.width": 1.0, "panel.height": 0.5,
                "output.row_travel": 2e-4, "output.dump_rows": 25, "output.frames": 20}
    not_taken = ("not used by a tensile case (its clamps hold the two edges across the pull; "
                 "it starts from the generated strip)")
    finished_file = "tensile.csv"

    @property
    def width(self):
        return 2 if self.case["tensile.quasi_static_check"] else 1

    def weight(self):
        return 4

    def verdict(self, facts):
        if not facts["peak_force"] > 0:
            return (record.NO_CONTACT, "the specimen carried no force: check the clamps "
                                       "(tensile.direction) and tensile.travel")
        evidence = facts["quasi_static"]
        if not self.case.quick and self.case["tensile.quasi_static_check"] and \
                evidence.get("passed") is False:          # false: recorded, not judged
            return (record.NOT_QUASI_STATIC, "the quasi-static evidence failed: lower "
                                             "tensile.speed")
        return None

    def run(self, index, ctx):
        c = self.case
        bending, _ = bending_of(c, ctx.study_dir)
        setup = Setup(self, os.path.join(ctx.case_dir, "setup"), bending)
        results = self._runs(setup, ctx)
        fast = read_table(results["run"])
        slow = read_table(results["slow"]) if "slow" in results else None
        return self.outputs(setup, ctx.case_dir, results["run"], fast, slow)

    def _runs(self, setup, ctx):
        """The run and, with the quasi-static check, its 4x slower twin side by side (the twin
        stops at the first rupture: the comparison ends there)."""
        runs = [("run", 1.0, 0)]
        if self.case["tensile.quasi_static_check"]:
            runs.append(("slow", float(quasistatic.SLOW_FACTOR), 1))
        ranks = max(ctx.ranks // len(runs), 1)
        results, errors = {}, []

        def one(name, factor, stop_broken):
            workdir = os.path.join(ctx.case_dir, name)
            variables, steps = setup.variables(factor, stop_broken=stop_broken)
            try:
                with engine.labelled(ctx.label):
                    engine.run(INPUTS / "tensile.in", workdir, variables, np=ranks,
                               total_steps=steps, label=name, dt=setup.dt,
                               phase_marker="tensile: pulling")
                results[name] = workdir
            except Exception as exc:      # re-raised below, in the case's thread
                errors.append(exc)
        threads = [threading.Thread(target=one, args=r) for r in runs]
        for t in threads:
            t.start()
        for t in threads:
            t.join()
        if errors:
            raise errors[0]
        return results

    def outputs(self, setup, case_dir, workdir, fast, slow):
        c = self.case
        write_csv(os.path.join(case_dir, "tensile.csv"),
                  ("time", "displacement", "force", "reaction", "broken"),
                  zip(fast["time"], fast["displacement"], fast["force"], fast["reaction"],
                      fast["broken"]))
        families = {}
        if setup.specimen == "net":
            from postprocess.meta import PanelInfo
            families = PanelInfo(setup.json_path).families
        rows = netoutputs.ruptures(os.path.join(workdir, "ruptures.dump"), setup.dt, families)
        netoutputs.write_ruptures(os.path.join(case_dir, "ruptures.csv"), rows)
        if not len(fast["force"]):
            raise RunError(f"{workdir}/tensile.csv: no rows")
        k = int(np.argmax(fast["force"]))
        peak, u_peak = float(fast["force"][k]), float(fast["displacement"][k])
        failed = failure(fast, c["tensile.stop_drop"] or 0.5)
        netoutputs.write_series(case_dir, workdir, setup.data_path, None, setup.dt)
        first = None
        if rows:
            r = rows[0]
            u = float(np.interp(r["time"], fast["time"], fast["displacement"]))
            first = dict(displacement=u, step=r["step"], position=[r["x"], r["y"], r["z"]],
                         bond=dict(atom1=r["atom1"], atom2=r["atom2"], type=r["type"],
                                   family=r["family"]))
        return dict(
            specimen=setup.specimen, direction=c["tensile.direction"] if setup.panel else "x",
            panel=c["panel.net"] if setup.panel else None,
            clamp_distance=setup.length, width=setup.width, speed=setup.speed,
            dt=setup.dt, peak_force=peak, displacement_at_peak=u_peak,
            strength_per_metre=peak / setup.width if setup.width else None,
            elongation_at_peak=u_peak / setup.length,
            failure=None if failed is None else dict(displacement=failed[0], force=failed[1],
                                                     elongation=failed[0] / setup.length),
            first_rupture=first, broken_bonds=len(rows),
            forces_at={repr(u): force_at(fast, u) for u in c["tensile.report_at"]},
            quasi_static=quasistatic.quasi_static_evidence(fast, slow))
