"""Quasi-static punch cases (paper, sections 3-4): the cone punch on the strand-rope square mesh
for the bending-stiffness calibration and the semi-spheroid punch on the hexagonal and the
compound panel. Deck: inputs/punch.in.

Loading rate and mass scaling
-----------------------------
Every law of the model is rate-independent (elastic-plastic wires, elastic beams, linear
contacts without viscous damping, Coulomb friction, Cundall local damping), so only inertia
separates a run from the static answer. Scaling every node mass by S and dividing gravity by S
leaves the weight unchanged and stretches every period by sqrt(S); the stable time step grows by
sqrt(S) as well. A run at speed v with masses S m is therefore the same computation, step by
step, as a run at v sqrt(S) with the true masses: the number of steps per metre of travel is
what buys quasi-statics. The platter moves at the paper's 1 cm/s (so `time` in platter.csv is
the test's time) and S is chosen to give the number of steps per metre that the evidence below
requires; `equivalent_speed` in case.json is v sqrt(S), the speed with the true masses. Past
the twin's travel the speed follows the equilibrium (SPEED_MAX, EQ_TARGET below), so from there
`time` is no longer travel / speed; every travel is read off punch.csv (travel_at).

Evidence, computed for every case and written to case.json:
- the same case is run four times slower (speed / 4, same masses and step): the largest
  difference of the two force-displacement curves, relative to the peak force, up to the first
  rupture (`curve_difference`);
- the kinetic energy of the net stays below a fraction of the work done by the platter
  (`kinetic_energy_fraction`, the largest ratio KE / W over the output steps once W > 1 % of
  its final value, up to the first rupture);
- equilibrium: at every output step the platter force plus the panel's weight equals the sum of
  the z reactions of the edge supports (`equilibrium_error`: the largest gap relative to the
  peak reaction; `equilibrium_error_of_current`: relative to the reaction of the same step, on
  the steps where the force is at least 10 % of its peak; `equilibrium_holds_from`: the travel
  from which the gap stays within 1 % of the same step's reaction at every row up to the first
  rupture. Early in the travel the platter carries less than the panel's weight, and the gap left
  by any finite speed, small against the peak, is large against that force: in the full hex case
  13 N at 1 cm, against 129 N; the 4x slower twin's gap is 5-10 times smaller).
"""

import math
import os
import re
import shutil
import threading
import time

import numpy as np

from postprocess import bodyframes, liggghts, model, vtu, zone
from postprocess.csvio import read_csv, write_csv
from postprocess.datafile import read_data
from postprocess.errors import PostprocessError
from postprocess.meta import PanelInfo, read_json
from postprocess.model import PAPER_BENDING, rope_strength_keyword

# Materials and contacts (the SW curve among them, tests/reference/wire_law_traces/README.md):
# their one source is inputs/include/materials.in, read by postprocess/model.

# The cone's apex is a flat disc of 2 cm radius: on a sharp apex the rope crossing at the panel
# centre rests on a point and, once the ropes pull hard enough, slips off sideways at a moment
# set by round-off, so two runs at different rates part ways there (doc/punch.md).
PLATTERS = {"cone": dict(radius=0.34, height=0.78, tip_radius=0.02),
            "spheroid": dict(radius=0.5, height=0.15),
            "sphere": dict(radius=0.5, height=0.5)}
ALPHA = 0.7          # local damping for the quasi-static runs (PFC's default for static runs)
CONTACT_ZETA = 0.3   # viscous normal contact damping, fraction of critical on the lightest node
PAPER_SPEED = 0.01   # m/s
SLOW_FACTOR = 4
# Steps per metre of platter travel (full, quick). The light hexagonal mesh (3.9 g nodes)
# needs 4e6: at 1e6 the inertia of the spreading deformation, amplified by local damping
# (1 / (1 - alpha)), kept the platter force 10-30 % above the edge reactions on the 1.2 m
# panel; at 4e6 they agree within 1 % (doc/punch.md). The strand-rope square mesh passes with a
# margin of 30 or more at 3.125e5 (the calibrations' curve difference 0.03 %; doc/punch.md).
# Quick runs are a first look: they report the evidence but are not expected to pass it.
STEPS_PER_M = {"square": (3.125e5, 1e6), "hex": (4e6, 1e6), "compound": (4e6, 1e6)}
QUICK_TRAVEL = {"square": 0.1, "hex": 0.03, "compound": 0.03}
# Travel of the four-times-slower twin, as a fraction of the production travel. The light
# panels compare the first quarter (the twin then costs as many steps as the production run),
# the square mesh the first half (twice as many): inertia matters most early, where the forces
# are smallest (the largest difference of the calibrations lies at 3-5 cm of their 50 cm); the
# equilibrium and kinetic-energy checks cover every output step of the whole travel.
SLOW_TRAVEL = {"square": 0.5, "hex": 1.0 / SLOW_FACTOR, "compound": 1.0 / SLOW_FACTOR}
TOLERANCE = 0.01     # 1 %: curve agreement, kinetic energy fraction, equilibrium
# Equilibrium-controlled loading (inputs/punch.in, label speed_rule): past the twin's travel
# the platter's speed follows the panel's equilibrium, scaled every 5 rows so that the largest
# gap |R - W - F| / R of those rows approaches EQ_TARGET, up to SPEED_MAX times the base speed.
# Early on, where the force is small, the gap is above the target and the speed stays; it rises
# once the net carries the load (hex: from 0.18 m, compound 0.16 m). The twin runs at constant
# speed: the curve comparison covers the base-speed part, the equilibrium and kinetic-energy
# checks every row (doc/punch.md). The square mesh's calibrations are cheap: constant speed.
SPEED_MAX = {"square": 1.0, "hex": 4.0, "compound": 4.0}
EQ_TARGET = 0.004
# The loading body: "analytic" (fix wirenet/body, exact shape, no facets: the default) or "mesh"
# (the generator's STL with fix mesh/surface/stress + wall/gran + move/mesh, for shapes with no
# analytic form; the facet traps of doc/punch.md apply to it). inputs/include/platter_*.in.
BODY_MODELS = ("analytic", "mesh")
# The runners' default per platter: the analytic body (its curve agrees with a 192-segment STL
# within 1 % of the peak force: tests/python/test_punch_body.py; doc/punch.md). "mesh" runs the
# STL (the facet traps of doc/punch.md apply there).
DEFAULT_BODY = {"spheroid": "analytic", "cone": "analytic"}
STL_RESOLUTION = 48  # segments around the axis of the platter STL (mesh path and frames)
FRAMES = 20          # ParaView frames over the travel (inputs/include/frames.in)
ROW_TRAVEL = 0.002   # m of platter travel between rows of punch.csv
RAMP = 0.002         # m of travel over which the platter's speed grows from 0 (deck variable ramp)
DUMP_ROWS = 5        # rows between bond dumps (zone forces, first rupture's picture)


def platter_stl_kind(platter):
    """wirenet-gen shape of a platter's STL (a sphere is drawn as its lower half-spheroid)."""
    return "cone" if platter == "cone" else "spheroid"


def model_variables(materials):
    """-var values of materials.in overrides (a curve given as pairs becomes its flat list)."""
    out = {}
    for name, value in (materials or {}).items():
        if isinstance(value, (list, tuple)):
            value = " ".join(repr(float(x)) for pair in value for x in pair)
        out[name] = value if isinstance(value, str) else repr(value)
    return out


def crop_stl(path, depth):
    """Keep the facets of a platter STL (apex at z = -h, base at z = 0) that reach within
    ``depth`` of the apex: a fine mesh then costs only where the net can touch it (the side-by-side
    comparison of a fine STL with the analytic body, tests/python/test_punch_body.py)."""
    points, triangles = vtu.read_stl(path)
    zmin = float(points[:, 2].min())
    keep = points[triangles][:, :, 2].min(axis=1) < zmin + depth
    bodyframes.write_stl(path, points, triangles[keep], name="platter")
    return int(keep.sum())


def check_body_model(body_model):
    if body_model not in BODY_MODELS:
        raise PostprocessError(f"unknown body model '{body_model}' (analytic or mesh)")
    return body_model


QUICK_SIZE = 1.2   # m: the quick panels (square: 4 x 4 cells of 0.3 m, a rope crossing at the centre)


def panel_options(kind, quick, width=None, height=None, extra=()):
    """wirenet-gen options of the panel; quick without a stated size = a small panel that still
    holds the load (a case file that states its size keeps it)."""
    size = []
    if quick:
        width, height = (v or QUICK_SIZE for v in (width, height))
    if width:
        size += ["--width", width]
    if height:
        size += ["--height", height]
    return [kind, *size, *extra]


# ---------------------------------------------------------------------------------------------
# set-up

def node_masses(data):
    d = data.atoms[:, 5]
    return data.atoms[:, 6] * math.pi * d ** 3 / 6.0


def stable_dt(data, bending, layers, platter=True, materials=None):
    """Stable step with the true masses: bonds (as bond_style wirenet estimates it: two-node
    frequencies doubled for neighbours in antiphase) plus the stiffest contact on the lightest
    node, combined as omega^2 = omega_bond^2 + omega_contact^2. ``materials``: overrides of
    materials.in (model.resolve). The one time-step estimator of the punch and impact cases."""
    mat = model.resolve(materials)
    ids = data.atoms[:, 0].astype(int)
    index = {i: k for k, i in enumerate(ids)}
    mass = node_masses(data)
    radius = data.atoms[:, 5] / 2
    pos = data.atoms[:, 2:5]
    w2 = 0.0
    eps1, sig1 = model.sw_curve(mat)[0]
    rope_r = mat["rope_d"] / 2
    area = math.pi * rope_r ** 2
    inertia = math.pi * rope_r ** 4 / 4
    shear_mod = mat["rope_E"] / (2 * (1 + mat["rope_nu"]))
    for _, btype, a1, a2 in data.bonds.astype(int):
        i, j = index[a1], index[a2]
        l0 = float(np.linalg.norm(pos[i] - pos[j]))
        inv_m = 1 / mass[i] + 1 / mass[j]
        if btype in (1, 2, 3):
            d = mat["selvedge_d"] if btype == 3 else mat["wire_d"]
            k = sig1 * math.pi * d * d / 4 / (eps1 * l0)
            w2 = max(w2, 2 * (2 * k if btype == 1 else k) * inv_m)
        else:
            kax = mat["rope_E"] * area / l0
            kb = bending * mat["rope_E"] * inertia / l0
            kt = bending * shear_mod * 2 * inertia / l0
            kr = 6 * kb + 2 * kt
            inv_i = 1 / (0.4 * mass[i] * radius[i] ** 2) + 1 / (0.4 * mass[j] * radius[j] ** 2)
            w2 = max(w2, 2 * max(kax, 12 * kb / l0 ** 2) * inv_m, 2 * kr * inv_i)
    m_min = float(mass.min())
    if platter or layers > 1:
        w2 += (2.0 if layers > 1 else 1.0) * (mat["kn"] + 2.5 * mat["ks"]) / m_min
    return 2.0 / math.sqrt(w2)


def centre_node(data, meta, offset=(0.0, 0.0)):
    """The node nearest to the panel centre (+ offset in x, y) on the loaded (topmost) layer."""
    z = data.atoms[:, 4]
    top = z >= z.max() - 1e-9
    centre = np.asarray(meta["centre"], float)[:2] + np.asarray(offset, float)
    d = np.hypot(data.atoms[:, 2] - centre[0], data.atoms[:, 3] - centre[1])
    d[~top] = np.inf
    k = int(np.argmin(d))
    return int(data.atoms[k, 0]), float(data.atoms[k, 5] / 2)


class Setup:
    """Everything a punch run needs; .variables(speed, out) gives the deck's -var values.

    The keyword options are those of a punch case file (runner/schema.py documents each with its
    default and source); their defaults are the paper's."""

    def __init__(self, workdir, panel, platter, bending=PAPER_BENDING, quick=False, steps_per_m=None,
                 travel=None, stop_broken=0, body_model=None, resolution=STL_RESOLUTION,
                 stl_depth=None, rope_strength=False, width=None, height=None, gen_options=(),
                 supports=None, preload_mode=2, preload=0.01, gravity=9.81, speed=PAPER_SPEED,
                 mass_scaling=True, shape=None, position=(0.0, 0.0), alpha=ALPHA,
                 contact_zeta=CONTACT_ZETA, slow_travel=None, quasi_static=True, materials=None,
                 bond_zeta=0.0, row_travel=ROW_TRAVEL, dump_rows=DUMP_ROWS, frames=FRAMES,
                 speed_max=None, eq_target=EQ_TARGET, stop_drop=0.0):
        self.body_model = check_body_model(body_model or DEFAULT_BODY.get(platter, "analytic"))
        os.makedirs(workdir, exist_ok=True)
        self.panel, self.platter, self.bending, self.quick = panel, platter, bending, quick
        self.rope_strength = rope_strength   # breakable ropes (materials.in rope_sigma_t/tau_c)
        self.shape = dict(shape or PLATTERS[platter])
        self.speed, self.gravity, self.alpha = float(speed), float(gravity), float(alpha)
        self.preload_mode, self.preload = int(preload_mode), float(preload)
        self.supports, self.materials, self.bond_zeta = supports, dict(materials or {}), bond_zeta
        self.position = tuple(float(v) for v in position)
        self.quasi_static = quasi_static
        self.row_travel, self.dump_rows, self.frames = float(row_travel), int(dump_rows), int(frames)
        prefix = os.path.join(workdir, "panel")
        options = panel_options(panel, quick, width, height, gen_options)
        self.data_path = liggghts.generate(options[0], prefix, *options[1:])
        self.json_path = prefix + ".json"
        # the STL: the body itself on the mesh path, only the frames' drawing with the analytic one
        self.resolution = int(resolution)
        self.stl = os.path.join(workdir, f"{platter}.stl")
        tip = ["--tip-radius", self.shape["tip_radius"]] if "tip_radius" in self.shape else []
        liggghts.generate(f"shape {platter_stl_kind(platter)}", self.stl,
                          "--radius", self.shape["radius"], "--height", self.shape["height"],
                          "--resolution", self.resolution, *tip)
        if stl_depth:
            crop_stl(self.stl, stl_depth)
        self.meta = read_json(self.json_path)
        data = read_data(self.data_path)
        self.layers = 2 if self.meta.get("kind") == "compound" else 1
        self.centre_id, self.centre_r = centre_node(data, self.meta, self.position)
        self.platter_xy = np.asarray(self.meta["centre"], float)[:2] + np.asarray(self.position)
        self.dt_true = stable_dt(data, bending, self.layers, materials=self.materials)
        dt_pre_true = stable_dt(data, bending, self.layers, platter=False, materials=self.materials)
        self.dt_safety = 0.5
        self.travel = travel or (QUICK_TRAVEL[panel] if quick else 0.5)
        self.slow_travel = SLOW_TRAVEL[panel] if slow_travel is None else slow_travel
        # (the mesh platter's speed cannot change: constant speed unless asked for, then an error)
        default_max = SPEED_MAX[panel] if self.body_model == "analytic" else 1.0
        self.speed_max = float(default_max if speed_max is None else speed_max)
        self.eq_target = float(eq_target)
        if self.speed_max > 1.0 and self.body_model != "analytic":
            raise PostprocessError("punch.speed_max > 1 needs the analytic body (punch.body = "
                                   "\"analytic\"): the mesh platter's speed cannot change")
        # the speed may change past the twin's travel (the curve comparison's part)
        self.speed_from = self.travel * self.slow_travel
        if mass_scaling:
            # steps per metre of travel: sets the equivalent speed (see the module docstring)
            self.steps_per_m = steps_per_m or STEPS_PER_M[panel][1 if quick else 0]
            dt_needed = 1.0 / (self.speed * self.steps_per_m)
            self.mass_scale = (dt_needed / (self.dt_safety * self.dt_true)) ** 2
            self.dt = dt_needed
        else:                 # true masses at the stated speed (a dynamic punch, as YADE's)
            self.mass_scale = 1.0
            self.dt = self.dt_safety * self.dt_true
            self.steps_per_m = 1.0 / (self.speed * self.dt)
        self.dt_preload = max(self.dt, self.dt_safety * dt_pre_true * math.sqrt(self.mass_scale))
        self.stop_broken = stop_broken
        if not 0.0 <= stop_drop < 1.0:
            raise PostprocessError(f"punch: stop_drop must be in [0, 1) (got {stop_drop})")
        self.stop_drop = float(stop_drop)   # end at this fraction of the peak after a rupture
        # viscous normal contact damping (mass-specific, 1/s): contact_zeta of critical for the
        # lightest (scaled) node on the platter; it damps the ringing of a node riding on the
        # platter, which local damping leaves alone (doc/punch.md), and vanishes at rest
        m_min = float(node_masses(data).min()) * self.mass_scale
        self.gamma_n = 2 * contact_zeta * math.sqrt(model.resolve(self.materials)["kn"] / m_min)
        period = self.slow_period()
        self.relax_steps = max(int(math.ceil(2.5 * period / self.dt_preload)), 10)

    def slow_period(self):
        """Fundamental period of the pre-loaded panel (a membrane whose tension carries its
        weight with a sag of 1 cm: N = p L^2 / (8 s)), with the scaled masses; 0 without
        gravity (no pre-load to relax)."""
        if not self.gravity > 0:
            return 0.0
        width = self.meta["panel"]["width"]
        areal = self.meta["areal_mass"] * self.mass_scale
        pressure = self.meta["areal_mass"] * self.gravity
        tension = pressure * width ** 2 / (8 * max(self.preload, 0.01))
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
            return f"cone {s['radius']!r} {s['height']!r} {s.get('tip_radius', 0.0)!r}", "0 0 -1"
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
        speed = self.speed / speed_factor
        if every is None:
            every = max(int(round(self.row_travel / (speed * self.dt))), 1)
            if every >= 200:     # a multiple of 20: the kinetic energy is sampled 20 times a row,
                every = 20 * int(round(every / 20))     # not at every step (a pass per sample)
        ke_every = every // 20 if every % 20 == 0 else 1    # 20 kinetic-energy samples a row
        shape, axis = self.body_shape()
        v = dict(model_variables(self.materials),
                 data=os.path.abspath(self.data_path), stl=os.path.abspath(self.stl),
                 platter_h=self.shape["height"], centre_id=self.centre_id, centre_r=self.centre_r,
                 layers=self.layers, bending=self.bending, alpha=self.alpha,
                 mass_scale=repr(self.mass_scale), g=repr(self.gravity),
                 dt=repr(self.dt), dt_preload=repr(self.dt_preload), relax_steps=self.relax_steps,
                 speed=repr(speed), ramp=repr(RAMP), preload_mode=self.preload_mode,
                 preload=repr(self.preload),
                 travel=travel or self.travel, every=every, ke_every=ke_every,
                 dump_every=every * self.dump_rows, out=".",
                 stop_broken=self.stop_broken if stop_broken is None else stop_broken,
                 gamma_n=repr(self.gamma_n), body_model=self.body_model,
                 platter_shape=shape, platter_axis=axis,
                 platter_x=repr(float(self.platter_xy[0])), platter_y=repr(float(self.platter_xy[1])),
                 speed_max=repr(self.speed_max if controlled else 1.0),
                 speed_from=repr(self.speed_from), eq_target=repr(self.eq_target),
                 stop_drop=repr(self.stop_drop),
                 frame_every=max(int(math.ceil(self.expected_steps(
                     travel or self.travel, speed_factor, controlled) / self.frames)), 1))
        if self.supports:     # {deck variable: include file} of runner/cases.write_supports
            v.update((k, os.path.abspath(path)) for k, path in self.supports.items())
        if self.bond_zeta:
            v["bond_zeta"] = repr(self.bond_zeta)
        if self.rope_strength:
            v["rope_strength"] = rope_strength_keyword(True, self.materials)
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


# ---------------------------------------------------------------------------------------------
# runs

PRELOAD_MARKER = "pre-load: centre sag"   # the deck's line after the pre-load (and its restart)

# Cases of a study whose pre-load another case starts from (punch.preload_from; runner/study.py
# fills it): case folder name -> Event set once its run/preload.restart is written.
SHARED_PRELOADS = {}


def run_pair(setup, case_dir, np_=1, preload_from=None):
    """The case at the chosen rate (case_dir/run) and, when the quasi-static check is on, four
    times slower (case_dir/slow), side by side (two processes sharing the np_ ranks, at least one
    each). The twin does not repeat the pre-load: the run writes run/preload.restart once its
    pre-load is done and the twin starts from it (the same panel to the last bit of the
    restart file). While the run pre-loads alone, the twin's ranks are given back to the study
    (runner/study.py). ``preload_from``: another case's preload.restart that both start from
    (no pre-load of their own). Returns their folders and wall times."""
    results, errors, done, done_lock = {}, [], [], threading.Lock()
    case_label = liggghts.current_label()   # this thread's; the run and the twin get it too
    shared = SHARED_PRELOADS.get(case_label)    # another case starts from this one's pre-load
    # set when the run's progress scan saw PRELOAD_MARKER (the study waits on a shared one)
    preloaded = shared if shared is not None else threading.Event()
    restart = preload_from or os.path.join(case_dir, "run", "preload.restart")

    def release(cores):
        if case_label is not None:
            liggghts.release_cores(case_label, cores)

    def one(name, factor):
        with liggghts.labelled(case_label):
            if name == "slow" and not preload_from and not wait_for_preload():
                return       # the run failed before its pre-load ended: its error is raised
            run_one(name, factor)
        # the first of the two to finish gives its ranks back to the study
        with done_lock:
            done.append(name)
            if len(done) < len(threads):
                release(ranks)

    def wait_for_preload():
        """True once the run has written its restart (its progress scan saw the line after
        it, or the run ended well), False if the run failed first."""
        while not preloaded.wait(0.5) and threads[0].is_alive():
            pass
        if preloaded.is_set() or "run" in results:
            release(-ranks)
            return True
        return False

    def run_one(name, factor):
        workdir = os.path.join(case_dir, name)
        # the comparison ends at the first rupture: the slow run stops there; it keeps its
        # constant speed (the speed control is the run's)
        slow = factor > 1
        travel = setup.travel * (setup.slow_travel if slow and not setup.quick else 1.0)
        variables, every = setup.variables(factor, stop_broken=1 if slow else None, travel=travel,
                                           controlled=not slow)
        if preload_from or (slow and len(threads) > 1):
            variables.update(preloaded=1, restart=restart)
        elif len(threads) > 1 or shared is not None:
            variables.update(save_preload=1)
        steps = setup.expected_steps(travel, factor, controlled=not slow)
        try:
            # the pre-load's length is not known in advance (it relaxes until the sag settles);
            # the deck restarts the step count at 0 after the line PRELOAD_MARKER
            wall = liggghts.run(liggghts.INPUTS / "punch.in", workdir, variables, np=ranks,
                                total_steps=steps, label=f"{name}", dt=setup.dt,
                                phase_marker=PRELOAD_MARKER,
                                marker_seen=None if slow else preloaded)
            results[name] = (workdir, wall, factor)
        except Exception as exc:      # re-raised below, in the caller's thread
            errors.append(exc)

    threads = [threading.Thread(target=one, args=("run", 1.0))]
    if setup.quasi_static:
        threads.append(threading.Thread(target=one, args=("slow", float(SLOW_FACTOR))))
    ranks = max(np_ // len(threads), 1)
    if len(threads) > 1 and not preload_from:
        release(ranks)        # the twin waits for the run's pre-load
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    if errors:
        raise errors[0]
    if preload_from:
        check_preload_bonds(preload_from, results["run"][0])
        # the pre-load's record is the source's (the deck wrote a placeholder row)
        for workdir, _, _ in results.values():
            shutil.copyfile(os.path.join(os.path.dirname(preload_from), "preload.csv"),
                            os.path.join(workdir, "preload.csv"))
    elif shared is None and os.path.isfile(restart):
        os.remove(restart)    # the pair's own hand-over, no output (a shared one: the study's)
    return results


def restart_case(restart):
    """The case folder name of a case's run/preload.restart."""
    return os.path.basename(os.path.dirname(os.path.dirname(restart)))


def broken_after_preload(workdir):
    """Broken bonds on the deck's line after the pre-load (PRELOAD_MARKER) of a run's log."""
    with open(os.path.join(workdir, "log.lammps"), errors="replace") as fh:
        for line in fh:
            if line.startswith(PRELOAD_MARKER) and line.rstrip().endswith("broken bonds)"):
                return int(float(line.rsplit("(", 1)[1].split()[0]))
    raise PostprocessError(f"{workdir}/log.lammps: no line '{PRELOAD_MARKER} ...'")


DROP_MARKER = "punch: ended by the drop:"   # the deck's line when punch.stop_drop ends a run
DROP_LINE = re.compile(r"force (\S+) N below \S+ of the peak (\S+) N at (\S+) m")


def drop_end(workdir):
    """Where punch.stop_drop ended the run (the deck's DROP_MARKER line): {displacement, force,
    peak_force}, or None if the run went on to the end of its travel."""
    path = os.path.join(workdir, "log.lammps")
    with open(path, errors="replace") as fh:
        for line in fh:
            if line.startswith(DROP_MARKER):
                found = DROP_LINE.search(line)
                try:
                    force, peak, travel = map(float, found.groups() if found else ("",) * 3)
                except ValueError:
                    raise PostprocessError(f"{path}: unreadable line '{line.strip()}'") from None
                return dict(displacement=travel, force=force, peak_force=peak)
    return None


def ending(rope_strength, rope_end, drop):
    """case.json's ended_by: a rope's failure first (the breakable-rope cases' event), then the
    force's drop (punch.stop_drop), else the travel's end."""
    if rope_end:
        return "rope failure"
    if drop:
        return "force drop"
    return "end of travel" if rope_strength else "end of travel (ropes unbreakable)"


def check_preload_bonds(restart, workdir):
    """A run from another case's pre-load (punch.preload_from) must find its panel as that
    case left it: a bond of this case's materials that breaks at once (a breakable rope past
    its strength) would have broken in its own pre-load, which is then not the other's."""
    had, has = broken_after_preload(os.path.dirname(restart)), broken_after_preload(workdir)
    if has != had:
        raise PostprocessError(f"punch.preload_from: {has - had} bonds break at once on the "
                               f"pre-loaded panel of {restart_case(restart)}: with these "
                               "materials the pre-load differs; remove punch.preload_from")


def largest_speed_factor(table, speed):
    """The platter's largest speed between two rows of punch.csv, as a factor on the base
    speed (1 at constant speed; up to speed_max under the speed control)."""
    d, t = np.asarray(table["displacement"], float), np.asarray(table["time"], float)
    if len(d) < 2:
        return 1.0
    ok = np.diff(t) > 0
    return float(np.max(np.diff(d)[ok] / np.diff(t)[ok]) / speed) if ok.any() else 1.0


def read_punch(workdir):
    table = read_csv(os.path.join(workdir, "punch.csv"),
                     required=("time", "displacement", "force", "reaction", "weight", "ke",
                               "broken", "step"))
    return table


def read_ruptures(path):
    """Rows (step, atom1, atom2, type, x, y, z, elongation) of the rupture dump, by step."""
    if not os.path.isfile(path):
        return np.zeros((0, 8))
    with open(path) as fh:
        lines = fh.read().splitlines()
    rows = []
    body = False
    for line in lines:
        if line.startswith("ITEM: ENTRIES"):
            body = True
            continue
        if line.startswith("ITEM:"):
            body = False
            continue
        if body and line.strip():
            rows.append([float(v) for v in line.split()[:8]])
    rows = np.array(rows, float).reshape(-1, 8)
    return rows[np.argsort(rows[:, 0], kind="stable")]


def work_done(disp, force):
    """Cumulative work of the platter (trapezoid rule, from 0 at zero travel)."""
    d = np.r_[0.0, disp]
    f = np.r_[0.0, force]
    return np.cumsum(np.r_[0.0, 0.5 * (f[1:] + f[:-1]) * np.diff(d)])[1:]


def rupture_limit(table):
    """Index limit (exclusive) of the rows before the first rupture."""
    broken = np.asarray(table["broken"])
    hit = np.nonzero(broken > 0)[0]
    return int(hit[0]) if hit.size else len(broken)


def snap_events(table, upto=None):
    """Displacement intervals of snap-through events before ``upto`` rows: rows where the
    platter force drops by more than 1 % of its peak from one output row to the next, or the
    kinetic energy jumps above ten times its median. At such a limit point the static path
    itself jumps (a node slips over the platter or off the cone tip); the run crosses it
    dynamically at any speed. Each event covers two output rows either side."""
    n = len(table["force"]) if upto is None else upto
    f, ke, d = table["force"][:n], table["ke"][:n], table["displacement"][:n]
    if n < 3:
        return []
    peak = float(np.max(np.abs(f)))
    drop = np.r_[False, np.diff(f) < -0.01 * peak]
    spike = ke > 10 * max(float(np.median(ke)), 1e-300)
    rows = np.nonzero(drop | spike)[0]
    intervals = []
    for k in rows:
        lo, hi = d[max(k - 2, 0)], d[min(k + 2, n - 1)]
        if intervals and lo <= intervals[-1][1]:
            intervals[-1][1] = max(intervals[-1][1], hi)
        else:
            intervals.append([float(lo), float(hi)])
    return intervals


def _outside(d, intervals):
    keep = np.ones(len(d), bool)
    for lo, hi in intervals:
        keep &= ~((d >= lo) & (d <= hi))
    return keep


def curve_difference(fast, slow):
    """Largest |F_fast - F_slow| on the slow run's displacements up to the first rupture of
    either run, relative to the slow run's peak force there, away from the snap events of
    either run (``max``) and everywhere (``max_all``); and the RMS difference."""
    nf, ns = rupture_limit(fast), rupture_limit(slow)
    d_end = min(fast["displacement"][nf - 1], slow["displacement"][ns - 1])
    keep = slow["displacement"][:ns] <= d_end + 1e-12
    d = slow["displacement"][:ns][keep]
    fs = slow["force"][:ns][keep]
    ff = np.interp(d, fast["displacement"][:nf], fast["force"][:nf])
    peak = float(np.max(np.abs(fs)))
    events = snap_events(fast, nf) + snap_events(slow, ns)
    calm = _outside(d, events)
    if not peak > 0:
        return dict(max=float("nan"), max_all=float("nan"), rms=float("nan"), up_to=float(d_end),
                    snap_events=events)
    gap = np.abs(ff - fs) / peak
    return dict(max=float(np.max(gap[calm])), max_all=float(np.max(gap)),
                rms=float(np.sqrt(np.mean(gap ** 2))), up_to=float(d_end),
                snap_events=sorted(events), calm_fraction=float(np.mean(calm)))


def kinetic_fraction(table, calm=True):
    """Largest KE / W over the output rows before the first rupture where W > 1 % of its
    final value; with calm, away from the snap events."""
    n = rupture_limit(table)
    w = work_done(table["displacement"][:n], table["force"][:n])
    if not n or not w[-1] > 0:
        return float("nan")
    use = w > 0.01 * w[-1]
    if calm:
        use &= _outside(table["displacement"][:n], snap_events(table, n))
    return float(np.max(table["ke"][:n][use] / w[use]))


def equilibrium_error(table, upto=None, relative_to_current=False, calm=True):
    """Largest |F + W - R| over the output rows (platter force F, panel weight W, sum of the
    edge z reactions R), relative to the peak reaction (default) or, with
    relative_to_current, to the current reaction on the rows where F >= 10 % of its peak;
    with calm, away from the snap events."""
    n = len(table["force"]) if upto is None else upto
    if not n:
        return float("nan")
    r = table["reaction"][:n]
    gap = np.abs(r - table["weight"][:n] - table["force"][:n])
    if not np.max(np.abs(r)) > 1e-9 * np.max(np.abs(table["force"][:n])):
        return float("nan")    # the supports carry nothing yet (a fast, dynamic punch)
    use = np.ones(n, bool)
    if calm:
        use &= _outside(table["displacement"][:n], snap_events(table, n))
    if not relative_to_current:
        return float(np.max(gap[use]) / np.max(np.abs(r)))
    use &= table["force"][:n] >= 0.1 * np.max(table["force"][:n])
    return float(np.max(gap[use] / np.abs(r[use])))


def equilibrium_holds_from(table, upto=None, tolerance=None):
    """Smallest platter travel from which the gap |F + W - R| stays within tolerance of the
    current reaction R at every output row up to `upto` (None: never within it)."""
    tolerance = TOLERANCE if tolerance is None else tolerance
    n = len(table["force"]) if upto is None else upto
    if not n:
        return None
    r = table["reaction"][:n]
    bad = np.abs(r - table["weight"][:n] - table["force"][:n]) > tolerance * np.abs(r)
    if not bad.any():
        return 0.0
    last = int(np.nonzero(bad)[0][-1])
    return None if last + 1 >= n else float(table["displacement"][last + 1])


def first_rupture(setup, workdir, table, families):
    rows = read_ruptures(os.path.join(workdir, "ruptures.dump"))
    if not len(rows):
        return None
    step, a1, a2, btype = rows[0][:4]
    d = float(travel_at(table, step * setup.dt))
    force = float(np.interp(d, np.r_[0.0, table["displacement"]], np.r_[0.0, table["force"]]))
    return dict(displacement=d, force=force, step=int(step),
                bond=dict(atom1=int(a1), atom2=int(a2), type=int(btype),
                          family=families.get(int(btype), f"type{int(btype)}")),
                position=[float(v) for v in rows[0][4:7]])


def rope_failure(setup, workdir, table, families):
    """How the punch ended for breakable ropes: the travel at the first rope rupture, or None
    (the travel ended first, or the ropes are unbreakable)."""
    if not setup.rope_strength:
        return None
    rope = {t for t, name in families.items() if name == "rope"}
    for row in read_ruptures(os.path.join(workdir, "ruptures.dump")):
        if int(row[3]) in rope:
            return dict(displacement=float(travel_at(table, row[0] * setup.dt)),
                        step=int(row[0]))
    return None


ZONES = (("centre", (0.0, 0.0), 1.0),)   # the paper's 1 m circle at the panel centre


def write_zones(case_dir, workdir, json_path, zones, dt, displacement):
    """zone_forces.csv for the first zone and zone_forces_NAME.csv for every other one: zones
    are (name, (x, y) offset from the panel centre, radius). ``displacement(times)`` gives the
    load's travel at the dump times. Returns the panel's families."""
    panel = PanelInfo(json_path)
    for k, (name, offset, radius) in enumerate(zones):
        centre = panel.centre + np.r_[np.asarray(offset, float), 0.0]
        info = PanelInfo(json_path, centre=centre)
        times, names, totals, maxima, counts = zone.compute(
            [os.path.join(workdir, "bonds.dump")], info, radius, dt)
        file = "zone_forces.csv" if k == 0 else f"zone_forces_{name}.csv"
        write_csv(os.path.join(case_dir, file), zone.HEADER,
                  zone.rows(times, displacement(times), names, totals, maxima, counts))
    return panel.families


def write_outputs(setup, case_dir, workdir, table, zones=ZONES):
    """platter.csv and the zone forces of the run in workdir, into case_dir."""
    write_csv(os.path.join(case_dir, "platter.csv"), ("time", "displacement", "force"),
              [(0.0, 0.0, 0.0)] + [(float(t), float(d), float(f)) for t, d, f in
                                   zip(table["time"], table["displacement"], table["force"])])
    families = write_zones(case_dir, workdir, setup.json_path, zones, setup.dt,
                           lambda times: travel_at(table, times))
    # the ParaView series CASE/CASE.pvd (net) and CASE/CASE_body.pvd (platter); the analytic
    # body's frames are the generator's STL moved to its poses
    bodyframes.write_body_frames(workdir, setup.stl)
    vtu.write_case_series(case_dir, workdir, setup.data_path, setup.dt)
    return families


def preload_facts(workdir):
    rows = read_csv(os.path.join(workdir, "preload.csv"), required=("edge_offset", "sag"))
    facts = dict(iterations=int(len(rows["sag"]) - 1), edge_offset=float(rows["edge_offset"][-1]),
                 centre_sag=float(rows["sag"][-1]), gravity_sag=float(rows["sag"][0]))
    if "relax_steps" in rows:
        facts["steps"] = int(np.sum(rows["relax_steps"]))
    return facts


def quasi_static_evidence(fast, slow):
    """The quasi-static evidence of a run (module docstring); the comparison with the slower
    twin is null when the twin was not run."""
    n = rupture_limit(fast)
    ke, eq = kinetic_fraction(fast), equilibrium_error(fast, n)
    evidence = dict(
        slow_factor=None, curve_difference=None, curve_difference_with_snaps=None,
        curve_difference_rms=None, compared_up_to=None, snap_events=snap_events(fast, n),
        kinetic_energy_fraction=ke, kinetic_energy_fraction_slow=None,
        kinetic_energy_fraction_with_snaps=kinetic_fraction(fast, calm=False),
        equilibrium_error=eq, equilibrium_error_slow=None,
        equilibrium_error_with_snaps=equilibrium_error(fast, n, calm=False),
        equilibrium_error_after_rupture=equilibrium_error(fast, calm=False),
        equilibrium_error_of_current=equilibrium_error(fast, n, relative_to_current=True),
        equilibrium_holds_from=equilibrium_holds_from(fast, n), equilibrium_holds_from_slow=None,
        passed=bool(ke <= TOLERANCE and eq <= TOLERANCE))
    if slow is None:
        return evidence
    diff = curve_difference(fast, slow)
    evidence.update(
        slow_factor=SLOW_FACTOR, curve_difference=diff["max"],
        curve_difference_with_snaps=diff["max_all"], curve_difference_rms=diff["rms"],
        compared_up_to=diff["up_to"], snap_events=diff["snap_events"],
        kinetic_energy_fraction_slow=kinetic_fraction(slow),
        equilibrium_error_slow=equilibrium_error(slow, rupture_limit(slow)),
        equilibrium_holds_from_slow=equilibrium_holds_from(slow, rupture_limit(slow)),
        passed=bool(diff["max"] <= TOLERANCE and evidence["passed"]))
    return evidence


def run_case(case_dir, panel, platter, bending=PAPER_BENDING, quick=False, np_=1, zones=ZONES,
             preload_from=None, **setup_options):
    """One punch case with its quasi-static evidence; returns the facts for case.json.
    ``preload_from``: the preload.restart of another case to start from (run_pair)."""
    setup = Setup(os.path.join(case_dir, "setup"), panel, platter, bending, quick,
                  **setup_options)
    start = time.time()
    runs = run_pair(setup, case_dir, np_, preload_from)
    run_dir, wall_fast, _ = runs["run"]
    slow_dir, wall_slow, _ = runs.get("slow", (None, None, None))
    fast = read_punch(run_dir)
    slow = read_punch(slow_dir) if slow_dir else None
    families = write_outputs(setup, case_dir, run_dir, fast, zones)
    rupture = first_rupture(setup, run_dir, fast, families)
    rope_end = rope_failure(setup, run_dir, fast, families)
    drop = drop_end(run_dir)
    facts = dict(
        panel=panel, platter=platter, bending=bending, platter_shape=setup.shape,
        body_model=setup.body_model, position=list(setup.position),
        speed=setup.speed, mass_scale=setup.mass_scale, equivalent_speed=setup.equivalent_speed,
        dt=setup.dt, dt_preload=setup.dt_preload, relax_steps=setup.relax_steps,
        steps_per_metre=setup.steps_per_m, damping=setup.alpha, gravity=setup.gravity,
        speed_control=dict(speed_max=setup.speed_max, equilibrium_target=setup.eq_target,
                           from_travel=setup.speed_from,
                           largest_factor=largest_speed_factor(fast, setup.speed)),
        travel=setup.travel, reached=float(fast["displacement"][-1]),
        peak_force=float(np.max(fast["force"])), preload=preload_facts(run_dir),
        preload_from=restart_case(preload_from) if preload_from else None,
        first_rupture=rupture,
        rope_strength=list(model.rope_strength(setup.materials)) if setup.rope_strength else None,
        first_rope_rupture=rope_end,
        ended_by=ending(setup.rope_strength, rope_end, drop),
        stop_drop=setup.stop_drop, ended_at_drop=drop,
        quasi_static=quasi_static_evidence(fast, slow),
        run_wall_time=wall_fast, slow_wall_time=wall_slow, pair_wall_time=time.time() - start)
    return facts
