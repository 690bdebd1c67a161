"""Quasi-static punch cases (paper, sections 3-4): a platter pushed into a pre-loaded panel; the
paper's cone punch on the strand-rope square mesh and its semi-spheroid punch on the hexagonal
and the compound panel. Deck: inputs/punch.in.

Loading rate and mass scaling
-----------------------------
Every law of the model is rate-independent (elastic-plastic wires, elastic beams, linear
contacts, Coulomb friction, Cundall local damping), so only inertia separates a run from the
static answer. Scaling every node mass by S and dividing gravity by S leaves the weight unchanged
and stretches every period by sqrt(S); the stable time step grows by sqrt(S) as well. A run at
speed v with masses S m is therefore the same computation, step by step, as a run at v sqrt(S)
with the true masses: the number of steps per metre of travel is what buys quasi-statics. The
platter moves at the paper's 1 cm/s (so `time` in platter.csv is the test's time) and S is
chosen to give punch.steps_per_metre; `equivalent_speed` in case.json is v sqrt(S). Past the
twin's travel the speed follows the equilibrium (punch.speed_max), so from there `time` is no
longer travel / speed; every travel is read off punch.csv (travel_at).

The evidence (runner/quasistatic.py) compares the run with a twin four times slower, run side by
side on the same cores, which starts from the run's pre-load.
"""

import math
import os
import re
import shutil
import threading
import time

import numpy as np

from postprocess import bodyframes, vtu
from postprocess.csvio import read_csv, write_csv

from postprocess import record

from .. import INPUTS, engine, netoutputs, quasistatic, timestep
from ..errors import RunError
from ..generator import generate
from ..materials import bending_of, rope_strength, rope_strength_keyword
from ..panel import Panel, inside, write_supports, zones_of
from ..panel import check as panel_check
from ..params import ByKey, Derived, Key
from .base import CaseKind

PAPER = "the paper (README: the study WireNet reproduces)"
# The cone's apex is a flat disc of 2 cm radius: on a sharp apex the rope crossing at the panel
# centre rests on a point and, once the ropes pull hard enough, slips off sideways at a moment
# set by round-off, so two runs at different rates part ways there (doc/punch.md).
PLATTERS = ("spheroid", "cone", "sphere")
STL_RESOLUTION = 48  # segments around the axis of the platter STL (mesh path and frames)
RAMP = 0.002         # m of travel over which the platter's speed grows from 0 (deck: ramp)
DT_SAFETY = 0.5      # the step with the true masses: half the stable one
# Cases of a study whose names say they are the bending-fraction cases of the paper's section 4
BENDING_CASE_PREFIX = "calibration"

PRELOAD_MARKER = "pre-load: centre sag"   # the deck's line after the pre-load (and its restart)
DROP_MARKER = "punch: ended by the drop:"  # the deck's line when punch.stop_drop ends a run
DROP_LINE = re.compile(r"force (\S+) N below \S+ of the peak (\S+) N at (\S+) m")
TABLE = "punch.csv"   # the deck's table: names in its header (inputs/punch.in)


def _punch(name, type_, default, unit, doc, source, **kw):
    return Key(f"punch.{name}", type_, default, unit, doc, source, **kw)


def _sphere_height(values):
    return values["punch.radius"] if values["punch.platter"] == "sphere" else \
        {"spheroid": 0.15, "cone": 0.78}[values["punch.platter"]]


def _speed_max(values):
    if values["punch.body"] == "mesh":
        return 1.0
    return 1.0 if values["panel.net"] == "square" else 4.0


# Keys that act only after a punch's pre-load, or on a rope that does not fail during it (the
# runner checks that none broke): two punch cases that differ in nothing else share their
# pre-load (punch.preload_from).
PRELOAD_FREE = ("title", "materials.rope_strength", "materials.rope_sigma_t",
                "materials.rope_tau_c", "punch.travel", "punch.quasi_static_check",
                "punch.check_travel", "punch.speed_max", "punch.equilibrium_target",
                "punch.stop_drop", "punch.preload_from", "output.*")

KEYS = (
    Key("preload.sag", "number", 0.01, "m", "target sag of the panel centre for preload.mode "
        "'sag'", PAPER, low=0.0, low_open=True, high=1.0, var="preload"),
    _punch("platter", "choice", "spheroid", "", "platter shape: spheroid (the paper's "
           "semi-spheroid), cone (flat tip), sphere", PAPER, choices=PLATTERS),
    _punch("radius", "number", ByKey("punch.platter", {"spheroid": 0.5, "cone": 0.34,
                                                       "sphere": 0.5}),
           "m", "platter radius", PAPER + " (cone: Bonati et al. 2004)", low=0.01, high=10.0),
    _punch("height", "number", Derived(_sphere_height, "spheroid 0.15, cone 0.78, sphere: "
                                       "punch.radius"), "m",
           "platter height (spheroid: semi-axis along z; cone: apex to base; sphere: the radius)",
           PAPER, low=0.001, high=10.0),
    _punch("tip_radius", "number", ByKey("punch.platter", {"spheroid": 0.0, "cone": 0.02,
                                                           "sphere": 0.0}),
           "m", "cone only: radius of the flat tip", "doc/punch.md", low=0.0, high=1.0),
    _punch("position", "vector2", [0.0, 0.0], "m", "platter axis, offset from the panel centre "
           "in x, y", PAPER),
    _punch("speed", "number", 0.01, "m/s", "platter speed along -z", PAPER, low=1e-6, high=100.0,
           var="speed"),
    _punch("travel", "number", 0.5, "m", "platter travel after first touch", PAPER, low=0.0,
           low_open=True, high=10.0,
           quick=ByKey("panel.net", {"hex": 0.03, "square": 0.1, "compound": 0.03})),
    _punch("mass_scaling", "bool", True, "", "scale node masses to reach steps_per_metre at "
           "the stated speed (rate-independent laws: doc/punch.md); false: true masses, half "
           "the stable step", "doc/punch.md"),
    _punch("steps_per_metre", "number", ByKey("panel.net", {"hex": 4e6, "square": 3.125e5,
                                                            "compound": 4e6}),
           "1/m", "time steps per metre of travel (with mass scaling)",
           "doc/punch.md (quasi-static evidence)", low=1e3, high=1e10, quick=1e6),
    _punch("quasi_static_check", "bool", True, "", "run the same case 4x slower beside it and "
           "compare the force curves (the quasi-static proof); false: no twin, and the "
           "evidence (kinetic energy, equilibrium) is recorded but does not decide the status "
           "(a dynamic test as another code runs it)", "doc/punch.md"),
    _punch("check_travel", "number", ByKey("panel.net", {"hex": 0.25, "square": 0.5,
                                                         "compound": 0.25}),
           "", "fraction of the travel the slower twin runs (--quick: the whole travel)",
           "doc/punch.md", low=0.0, low_open=True, high=1.0),
    _punch("speed_max", "number", Derived(_speed_max, "hex/compound 4, square 1; punch.body "
                                          "mesh: 1"), "",
           "largest factor on punch.speed: past the twin's travel the speed follows the panel's "
           "equilibrium, rising while the edge reactions balance the platter force and weight "
           "within punch.equilibrium_target (1: constant speed; analytic body only)",
           "doc/punch.md (equilibrium-controlled loading)", low=1.0, high=100.0),
    _punch("equilibrium_target", "number", 0.004, "", "the gap |R - W - F| / R (edge reactions "
           "R, weight W, platter force F) the speed control aims at",
           "doc/punch.md (equilibrium-controlled loading)", low=0.0, low_open=True, high=0.01,
           var="eq_target"),
    _punch("stop_drop", "number", 0.0, "", "end the punch at the first row, after a bond has "
           "broken, whose platter force is below this fraction of the peak so far (the net has "
           "failed: a load test's post-peak drop); 0: run the whole travel",
           "doc/punch.md (breakable ropes)", low=0.0, high=0.999, var="stop_drop"),
    _punch("preload_from", "text", "", "", "another punch case of the same study whose "
           "pre-loaded panel this case starts from instead of pre-loading its own (the same "
           "panel, materials, pre-load and time step; only " + ", ".join(PRELOAD_FREE) +
           " may differ); run alone, the case pre-loads its own",
           "doc/punch.md (a shared pre-load)"),
    _punch("body", "choice", "analytic", "", "analytic: exact body (fix wirenet/body); mesh: "
           "the generator's STL (facet traps of doc/punch.md)", "doc/fix_wirenet_body.md",
           choices=("analytic", "mesh"), var="body_model"),
)


def platter_stl_kind(platter):
    """wirenet-gen shape of a platter's STL (a sphere is drawn as its lower half-spheroid)."""
    return "cone" if platter == "cone" else "spheroid"


def crop_stl(path, depth):
    """Keep the facets of a platter STL (apex at z = -h, base at z = 0) that reach within
    ``depth`` of the apex: a fine mesh then costs only where the net can touch it."""
    points, triangles = vtu.read_stl(path)
    zmin = float(points[:, 2].min())
    keep = points[triangles][:, :, 2].min(axis=1) < zmin + depth
    bodyframes.write_stl(path, points, triangles[keep], name="platter")
    return int(keep.sum())


class Setup:
    """Everything a punch run needs, from the checked case: the panel, the platter's STL, the
    time step and mass scaling; variables() gives the deck's -var values of one run."""

    def __init__(self, kind, workdir, bending, stl_depth=None, resolution=STL_RESOLUTION):
        c = kind.case
        self.kind, self.case, self.bending = kind, c, bending
        self.platter = c["punch.platter"]
        self.shape = {"radius": c["punch.radius"], "height": c["punch.height"]}
        if self.platter == "cone":
            self.shape["tip_radius"] = c["punch.tip_radius"]
        self.speed, self.travel = c["punch.speed"], c["punch.travel"]
        self.speed_max, self.eq_target = c["punch.speed_max"], c["punch.equilibrium_target"]
        self.stop_drop, self.quasi_static = c["punch.stop_drop"], c["punch.quasi_static_check"]
        self.check_travel, self.position = c["punch.check_travel"], tuple(c["punch.position"])
        self.body_model, self.gravity = c["punch.body"], c["gravity"]
        self.rope_strength = c["materials.rope_strength"]
        self.stop_broken = 0
        self.panel = Panel(c, workdir)
        self.data_path, self.json_path, self.meta = (self.panel.data_path, self.panel.json_path,
                                                     self.panel.meta)
        self.layers = self.panel.layers
        # the STL: the body itself on the mesh path, only the frames' drawing with the analytic one
        self.stl = os.path.join(workdir, f"{self.platter}.stl")
        tip = ["--tip-radius", self.shape["tip_radius"]] if self.platter == "cone" else []
        generate(f"shape {platter_stl_kind(self.platter)}", self.stl, "--radius",
                 self.shape["radius"], "--height", self.shape["height"], "--resolution",
                 resolution, *tip)
        if stl_depth:
            crop_stl(self.stl, stl_depth)
        self.centre_id, self.centre_r = self.panel.centre_node(self.position)
        self.platter_xy = self.panel.centre[:2] + np.asarray(self.position)
        # the stable steps with the true masses: under the platter, and alone for the pre-load
        stable = timestep.of_panel(self.panel, dict(kind.key_variables(), bending=repr(bending)),
                                   workdir)
        self.dt_true, dt_pre_true = stable.loaded, stable.free
        # the speed may change past the twin's travel (the curve comparison's part)
        self.speed_from = self.travel * self.check_travel
        if c["punch.mass_scaling"]:
            # steps per metre of travel: sets the equivalent speed (module docstring)
            self.steps_per_m = c["punch.steps_per_metre"]
            dt_needed = 1.0 / (self.speed * self.steps_per_m)
            self.mass_scale = (dt_needed / (DT_SAFETY * self.dt_true)) ** 2
            self.dt = dt_needed
        else:                 # true masses at the stated speed (a dynamic punch, as YADE's)
            self.mass_scale = 1.0
            self.dt = DT_SAFETY * self.dt_true
            self.steps_per_m = 1.0 / (self.speed * self.dt)
        self.dt_preload = max(self.dt, DT_SAFETY * dt_pre_true * math.sqrt(self.mass_scale))
        # viscous normal contact damping (mass-specific, 1/s): contact.zeta of critical for the
        # lightest (scaled) node on the platter; it damps the ringing of a node riding on the
        # platter, which local damping leaves alone (doc/punch.md), and vanishes at rest
        m_min = float(self.panel.masses.min()) * self.mass_scale
        self.gamma_n = 2 * c["contact.zeta"] * math.sqrt(c["contact.kn"] / m_min)
        self.relax_steps = max(int(math.ceil(2.5 * self.slow_period() / self.dt_preload)), 10)
        self.supports = write_supports(c, workdir)

    def slow_period(self):
        """Fundamental period of the pre-loaded panel (a membrane whose tension carries its
        weight with a sag of 1 cm: N = p L^2 / (8 s)), with the scaled masses; 0 without
        gravity (no pre-load to relax)."""
        if not self.gravity > 0:
            return 0.0
        width = self.meta["panel"]["width"]
        areal = self.meta["areal_mass"] * self.mass_scale
        pressure = self.meta["areal_mass"] * self.gravity
        tension = pressure * width ** 2 / (8 * max(self.case["preload.sag"], 0.01))
        c = math.sqrt(tension / areal)
        return 2 * width / (c * math.sqrt(2))

    @property
    def equivalent_speed(self):
        return self.speed * math.sqrt(self.mass_scale)

    def body_shape(self):
        """fix wirenet/body shape arguments and local +z axis of the platter (the same solid as
        the generator's STL: base disc at the reference point, dome or tip towards -z)."""
        s = self.shape
        if self.platter == "cone":
            return f"cone {s['radius']!r} {s['height']!r} {s['tip_radius']!r}", "0 0 -1"
        return f"spheroid {s['radius']!r} {s['radius']!r} {s['height']!r}", "0 0 1"

    def expected_steps(self, travel, speed_factor=1.0, controlled=True):
        """Steps of the punch over ``travel`` (after the pre-load): exact at constant speed; with
        the speed control an estimate (the part past speed_from at the mean of 1 and
        speed_max), for the progress line and the frame interval."""
        base = 1.0 / (self.speed / speed_factor * self.dt)
        if not controlled or self.speed_max <= 1.0 or travel <= self.speed_from:
            return int(math.ceil(travel * base))
        rest = (travel - self.speed_from) / (0.5 * (1.0 + self.speed_max))
        return int(math.ceil((self.speed_from + rest) * base))

    def variables(self, speed_factor=1.0, every=None, stop_broken=None, travel=None,
                  controlled=True):
        """-var values of one run; ``controlled``: the speed control of inputs/punch.in is on
        (the run; the twin keeps its constant speed)."""
        c = self.case
        speed = self.speed / speed_factor
        if every is None:
            every = max(int(round(c["output.row_travel"] / (speed * self.dt))), 1)
            if every >= 200:     # a multiple of 20: the kinetic energy is sampled 20 times a row,
                every = 20 * int(round(every / 20))     # not at every step (a pass per sample)
        ke_every = every // 20 if every % 20 == 0 else 1    # 20 kinetic-energy samples a row
        shape, axis = self.body_shape()
        travel = travel or self.travel
        v = dict(self.kind.key_variables(),
                 data=os.path.abspath(self.data_path), stl=os.path.abspath(self.stl),
                 types=os.path.abspath(self.panel.types_path), platter_h=repr(self.shape["height"]), centre_id=self.centre_id,
                 centre_r=repr(self.centre_r), layers=self.layers, bending=repr(self.bending),
                 mass_scale=repr(self.mass_scale), dt=repr(self.dt),
                 dt_preload=repr(self.dt_preload), relax_steps=self.relax_steps,
                 speed=repr(speed), ramp=repr(RAMP), travel=repr(travel), every=every,
                 ke_every=ke_every, dump_every=every * c["output.dump_rows"], out=".",
                 stop_broken=self.stop_broken if stop_broken is None else stop_broken,
                 gamma_n=repr(self.gamma_n), platter_shape=shape, platter_axis=axis,
                 platter_x=repr(float(self.platter_xy[0])),
                 platter_y=repr(float(self.platter_xy[1])),
                 speed_max=repr(self.speed_max if controlled else 1.0),
                 speed_from=repr(self.speed_from),
                 frame_every=max(int(math.ceil(self.expected_steps(
                     travel, speed_factor, controlled) / c["output.frames"])), 1))
        v.update((k, os.path.abspath(path)) for k, path in self.supports.items())
        if self.rope_strength:
            v["rope_strength"] = rope_strength_keyword(True, self.kind.material_values())
        return v, every


def travel_at(table, times):
    """Platter travel at the given times from a run's punch.csv: its rows pair the window means
    of time and travel, which lie on the travel-time curve wherever the speed is constant over
    the window (and within a fraction of a row's travel in a speed ramp). Linear between rows,
    from (0, 0), and extrapolated past the last row (a dump at the last step)."""
    t = np.r_[0.0, np.asarray(table["time"], float)]
    d = np.r_[0.0, np.asarray(table["displacement"], float)]
    at = np.atleast_1d(np.asarray(times, float))
    out = np.interp(at, t, d)
    if len(t) >= 2 and t[-1] > t[-2]:
        late = at > t[-1]
        out[late] = d[-1] + (at[late] - t[-1]) * (d[-1] - d[-2]) / (t[-1] - t[-2])
    return out if np.ndim(times) else float(out[0])


def read_table(workdir):
    return read_csv(os.path.join(workdir, TABLE),
                    required=("time", "displacement", "force", "reaction", "weight", "ke",
                              "broken", "step"))


def restart_case(restart):
    """The case folder name of a case's run/preload.restart."""
    return os.path.basename(os.path.dirname(os.path.dirname(restart)))


def broken_after_preload(workdir):
    """Broken bonds on the deck's line after the pre-load (PRELOAD_MARKER) of a run's log."""
    line = engine.log_line(workdir, PRELOAD_MARKER)
    if line is None or not line.rstrip().endswith("broken bonds)"):
        raise RunError(f"{workdir}/log.lammps: no line '{PRELOAD_MARKER} ...'")
    return int(float(line.rsplit("(", 1)[1].split()[0]))


def check_preload_bonds(restart, workdir):
    """A run from another case's pre-load (punch.preload_from) must find its panel as that
    case left it: a bond of this case's materials that breaks at once (a breakable rope past
    its strength) would have broken in its own pre-load, which is then not the other's."""
    had, has = broken_after_preload(os.path.dirname(restart)), broken_after_preload(workdir)
    if has != had:
        raise RunError(f"punch.preload_from: {has - had} bonds break at once on the pre-loaded "
                       f"panel of {restart_case(restart)}: with these materials the pre-load "
                       "differs; remove punch.preload_from")


def drop_end(workdir):
    """Where punch.stop_drop ended the run (the deck's DROP_MARKER line): {displacement, force,
    peak_force}, or None if the run went on to the end of its travel."""
    line = engine.log_line(workdir, DROP_MARKER)
    if line is None:
        return None
    found = DROP_LINE.search(line)
    try:
        force, peak, travel = map(float, found.groups() if found else ("",) * 3)
    except ValueError:
        raise RunError(f"{workdir}/log.lammps: unreadable line '{line.strip()}'") from None
    return dict(displacement=travel, force=force, peak_force=peak)


def ending(rope_strength_on, rope_end, drop):
    """case.json's ended_by: a rope's failure first (the breakable-rope cases' event), then the
    force's drop (punch.stop_drop), else the travel's end."""
    if rope_end:
        return "rope failure"
    if drop:
        return "force drop"
    return "end of travel" if rope_strength_on else "end of travel (ropes unbreakable)"


def largest_speed_factor(table, speed):
    """The platter's largest speed between two rows of punch.csv, as a factor on the base
    speed (1 at constant speed; up to speed_max under the speed control)."""
    d, t = np.asarray(table["displacement"], float), np.asarray(table["time"], float)
    if len(d) < 2:
        return 1.0
    ok = np.diff(t) > 0
    return float(np.max(np.diff(d)[ok] / np.diff(t)[ok]) / speed) if ok.any() else 1.0


def preload_facts(workdir):
    rows = read_csv(os.path.join(workdir, "preload.csv"), required=("edge_offset", "sag"))
    facts = dict(iterations=int(len(rows["sag"]) - 1), edge_offset=float(rows["edge_offset"][-1]),
                 centre_sag=float(rows["sag"][-1]), gravity_sag=float(rows["sag"][0]))
    if "relax_steps" in rows:
        facts["steps"] = int(np.sum(rows["relax_steps"]))
    return facts


class Pair:
    """The case at the chosen rate (case_dir/run) and, with the quasi-static check, four times
    slower (case_dir/slow), side by side: two processes sharing the ranks, at least one each
    (an odd rank count gives the run the extra one: it is the longer of the two).
    The twin does not repeat the pre-load: the run writes run/preload.restart once its pre-load
    is done and the twin starts from it (the same panel to the last bit). While the run
    pre-loads alone, the twin's ranks are lent back to the study. ``ctx.start_from``: another
    case's preload.restart that both start from; ``ctx.share_event``: set once this case's own
    pre-load is written for another case to start from."""

    def __init__(self, setup, ctx):
        self.setup, self.ctx = setup, ctx
        self.results, self.errors, self.done = {}, [], []
        self.lock = threading.Lock()
        self.preloaded = ctx.share_event or threading.Event()
        self.restart = ctx.start_from or os.path.join(ctx.case_dir, "run", "preload.restart")
        names = ["run"] + (["slow"] if setup.quasi_static else [])
        self.threads = {n: threading.Thread(target=self._one, args=(n,)) for n in names}
        twin = max(ctx.ranks // 2, 1) if len(names) > 1 else 0
        self.ranks = {"run": max(ctx.ranks - twin, 1)}
        if twin:
            self.ranks["slow"] = twin

    def run(self):
        if len(self.threads) > 1 and not self.ctx.start_from:
            self.ctx.lend(self.ranks["slow"])  # the twin waits for the run's pre-load
        for t in self.threads.values():
            t.start()
        for t in self.threads.values():
            t.join()
        if self.errors:
            raise self.errors[0]
        if self.ctx.start_from:
            check_preload_bonds(self.ctx.start_from, self.results["run"][0])
            # the pre-load's record is the source's (the deck wrote a placeholder row)
            for workdir, _ in self.results.values():
                shutil.copyfile(os.path.join(os.path.dirname(self.ctx.start_from), "preload.csv"),
                                os.path.join(workdir, "preload.csv"))
        elif self.ctx.share_event is None and os.path.isfile(self.restart):
            os.remove(self.restart)   # the pair's own hand-over, no output (a shared one: the study's)
        return self.results

    def _one(self, name):
        with engine.labelled(self.ctx.label):
            if name == "slow" and not self.ctx.start_from and not self._wait_for_preload():
                return       # the run failed before its pre-load ended: its error is raised
            self._run_one(name)
        with self.lock:       # the first of the two to finish lends its ranks to the study
            self.done.append(name)
            if len(self.done) < len(self.threads):
                self.ctx.lend(self.ranks[name])

    def _wait_for_preload(self):
        """True once the run has written its restart (its progress scan saw the line after
        it, or the run ended well), False if the run failed first."""
        run = self.threads["run"]
        while not self.preloaded.wait(0.5) and run.is_alive():
            pass
        if self.preloaded.is_set() or "run" in self.results:
            self.ctx.lend(-self.ranks["slow"])
            return True
        return False

    def _run_one(self, name):
        s = self.setup
        workdir = os.path.join(self.ctx.case_dir, name)
        # the comparison ends at the first rupture: the slow run stops there; it keeps its
        # constant speed (the speed control is the run's)
        slow = name == "slow"
        factor = float(quasistatic.SLOW_FACTOR) if slow else 1.0
        # (a quick run is short: its twin compares the whole travel)
        travel = s.travel * (s.check_travel if slow and not self.setup.case.quick else 1.0)
        variables, _ = s.variables(factor, stop_broken=1 if slow else None, travel=travel,
                                   controlled=not slow)
        if self.ctx.start_from or (slow and len(self.threads) > 1):
            variables.update(preloaded=1, restart=self.restart)
        elif len(self.threads) > 1 or self.ctx.share_event is not None:
            variables.update(save_preload=1)
        steps = s.expected_steps(travel, factor, controlled=not slow)
        try:
            # the pre-load's length is not known in advance (it relaxes until the sag settles);
            # the deck restarts the step count at 0 after the line PRELOAD_MARKER
            wall = engine.run(INPUTS / "punch.in", workdir, variables, np=self.ranks[name],
                              total_steps=steps, label=name, dt=s.dt,
                              phase_marker=PRELOAD_MARKER,
                              marker_seen=None if slow else self.preloaded)
            self.results[name] = (workdir, wall)
        except Exception as exc:      # re-raised by run(), in the case's thread
            self.errors.append(exc)


class Punch(CaseKind):
    name = "punch"
    summary = "a quasi-static punch test (paper, sections 3-4)"
    deck = "punch.in"
    keys = KEYS
    takes = ("title", "gravity", "panel.*", "supports.*", "preload.*", "materials.*",
             "contact.*", "damping.*", "punch.*", "output.row_travel", "output.dump_rows",
             "output.frames", "output.zones.*")
    defaults = {"preload.mode": "sag", "damping.local": 0.7, "contact.zeta": 0.3,
                "output.dump_rows": 5, "output.frames": 20}
    finished_file = "platter.csv"

    # relative cost by net (the default study's measured wall times, docs/PERFORMANCE.md)
    WEIGHT = {"compound": 30, "hex": 20, "square": 3}

    @classmethod
    def check(cls, case, fail):
        super().check(case, fail)
        panel_check(case, fail)
        v = case.values
        if v["punch.radius"] >= 0.5 * min(v["panel.width"], v["panel.height"]):
            fail("punch.radius", f"{v['punch.radius']:g} m: the platter is wider than the panel "
                                 f"({v['panel.width']:g} m x {v['panel.height']:g} m)")
        inside(case, v["punch.position"], v["punch.radius"], fail, "punch.position")
        if v["punch.platter"] != "cone" and "punch.tip_radius" in case.stated:
            fail("punch.tip_radius", "only for punch.platter = 'cone'")
        if v["punch.body"] == "mesh" and v["punch.speed_max"] > 1:
            fail("punch.speed_max", "> 1 needs punch.body = 'analytic' (the mesh platter moves "
                                    "at a constant speed)")

    def verdict(self, facts):
        if not facts["peak_force"] > 0:
            return (record.NO_CONTACT, "the platter never touched the net (its tip in a mesh "
                                       "opening?): move punch.position onto a node or widen the "
                                       "platter's tip")
        evidence = facts["quasi_static"]
        # punch.quasi_static_check false: a dynamic test as another code runs it (YADE's
        # punch example); its evidence is recorded, not judged
        if not self.case.quick and self.case["punch.quasi_static_check"] and \
                evidence.get("passed") is False:
            return (record.NOT_QUASI_STATIC,
                    "the quasi-static evidence failed (curve against the slower twin "
                    f"{evidence.get('curve_difference')}, kinetic energy / work "
                    f"{evidence.get('kinetic_energy_fraction')}, equilibrium "
                    f"{evidence.get('equilibrium_error')}; 1 % each): raise "
                    "punch.steps_per_metre or lower punch.speed_max")
        return None

    @property
    def width(self):
        return 2 if self.case["punch.quasi_static_check"] else 1

    def weight(self):
        return self.WEIGHT.get(self.case["panel.net"], 1)

    def record_kind(self):
        """The cone punches of the bending-fraction study are recorded as 'calibration'."""
        return "calibration" if self.case.name.startswith(BENDING_CASE_PREFIX) else self.name

    def run(self, index, ctx):
        c = self.case
        bending, source = bending_of(c, ctx.study_dir)
        setup = Setup(self, os.path.join(ctx.case_dir, "setup"), bending)
        start = time.time()
        results = Pair(setup, ctx).run()
        run_dir, wall_fast = results["run"]
        slow_dir, wall_slow = results.get("slow", (None, None))
        fast = read_table(run_dir)
        slow = read_table(slow_dir) if slow_dir else None
        families = self.write_outputs(setup, ctx.case_dir, run_dir, fast)
        rows = netoutputs.ruptures(os.path.join(run_dir, "ruptures.dump"), setup.dt, families)
        rupture = self.first_rupture(rows, fast)
        rope_end = next(({"displacement": float(travel_at(fast, r["time"])), "step": r["step"]}
                         for r in rows if r["family"] == "rope"), None) \
            if setup.rope_strength else None
        drop = drop_end(run_dir)
        return dict(
            panel=c["panel.net"], platter=setup.platter, bending=bending,
            bending_source=source, platter_shape=setup.shape, body_model=setup.body_model,
            position=list(setup.position), speed=setup.speed, mass_scale=setup.mass_scale,
            equivalent_speed=setup.equivalent_speed, dt=setup.dt, dt_preload=setup.dt_preload,
            relax_steps=setup.relax_steps, steps_per_metre=setup.steps_per_m,
            damping=c["damping.local"], gravity=setup.gravity,
            speed_control=dict(speed_max=setup.speed_max, equilibrium_target=setup.eq_target,
                               from_travel=setup.speed_from,
                               largest_factor=largest_speed_factor(fast, setup.speed)),
            travel=setup.travel, reached=float(fast["displacement"][-1]),
            peak_force=float(np.max(fast["force"])), preload=preload_facts(run_dir),
            preload_from=restart_case(ctx.start_from) if ctx.start_from else None,
            first_rupture=rupture,
            rope_strength=list(rope_strength(self.material_values()))
            if setup.rope_strength else None,
            first_rope_rupture=rope_end,
            ended_by=ending(setup.rope_strength, rope_end, drop),
            stop_drop=setup.stop_drop, ended_at_drop=drop,
            quasi_static=quasistatic.quasi_static_evidence(fast, slow),
            run_wall_time=wall_fast, slow_wall_time=wall_slow,
            pair_wall_time=time.time() - start)

    @staticmethod
    def first_rupture(rows, table):
        """The first broken bond with the platter's travel and force when it broke."""
        if not rows:
            return None
        r = rows[0]
        d = float(travel_at(table, r["time"]))
        force = float(np.interp(d, np.r_[0.0, table["displacement"]], np.r_[0.0, table["force"]]))
        return dict(displacement=d, force=force, step=r["step"],
                    bond=dict(atom1=r["atom1"], atom2=r["atom2"], type=r["type"],
                              family=r["family"]),
                    position=[r["x"], r["y"], r["z"]])

    def write_outputs(self, setup, case_dir, workdir, table):
        """platter.csv, the zone forces and the ParaView series of the run in workdir, into
        case_dir; returns the panel's families."""
        write_csv(os.path.join(case_dir, "platter.csv"), ("time", "displacement", "force"),
                  [(0.0, 0.0, 0.0)] + [(float(t), float(d), float(f)) for t, d, f in
                                       zip(table["time"], table["displacement"], table["force"])])
        families = netoutputs.write_zones(case_dir, workdir, setup.json_path, zones_of(self.case),
                                          setup.dt, lambda times: travel_at(table, times))
        netoutputs.write_series(case_dir, workdir, setup.data_path, setup.stl, setup.dt)
        return families
