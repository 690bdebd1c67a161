"""Block impact cases (paper, section 5): a rigid block (the truncated cube of fix wirenet/body,
or a closed STL moved by fix wirenet/rigidmesh) hits a hexagonal, square or compound panel.
Deck: inputs/impact.in. Beyond the paper, every case gets:

- the force on the edge supports (the posts) as a time series (edges.csv) and its peak;
- an energy budget whose terms are each measured by their own mechanism (energy.csv, case.json
  "energy"; the terms: BUDGET below);
- a momentum balance: the change of the momentum of block and net equals the impulse of the
  support reactions, of gravity (block and net) and of the damping forces (``momentum``);
- broken bonds: count and locations (ruptures.csv, case.json "ruptures").

Several [[impact]] entries are a sequence: units CASE (the first impact), CASE_impact2, ...,
each a case folder of its own starting from the net the previous one left (its run/net.restart).
"""

import math
import os
import time

import numpy as np

from postprocess.csvio import read_deck_table, write_csv
from postprocess.meta import PanelInfo

from .. import INPUTS, budget, dissipation, engine, netoutputs, supports, timestep
from ..budget import Term
from ..errors import RunError
from postprocess import record

from ..block import Block
from ..materials import bending_of, rope_strength, rope_strength_keyword
from ..panel import Panel, inside, write_supports, zones_of
from ..panel import check as panel_check
from ..params import Key
from .base import CaseKind

PAPER = "the paper (README: the study WireNet reproduces)"
GAP = 0.005            # clearance between the block and the highest node under it [m]
BOX_Z = 3.0            # the box reaches this far above and below the panel: a rebounding block stays in
TABLE = "impact.csv"   # the deck's table: names in its header (inputs/impact.in)


def _item(name, type_, default, unit, doc, source, **kw):
    return Key(f"impact.{name}", type_, default, unit, doc, source, per_item=True, **kw)


KEYS = (
    Key("preload.settle_time", "number", 0.1, "s", "settling time under gravity before the block "
        "is released (preload.mode 'settle')", "doc/impact.md", low=0.0, high=100.0, quick=0.01),
    _item("block", "choice", "truncated-cube", "", "the block: the generator's truncated cube, "
          "or a closed STL surface (impact.stl, body mesh)", PAPER,
          choices=("truncated-cube", "stl")),
    _item("stl", "file", "", "", "block STL file (relative to the case file), for block 'stl'; "
          "mass properties of the uniform solid", ""),
    _item("side", "number", 0.45, "m", "truncated cube: side", PAPER, low=0.01, high=20.0),
    _item("mass", "number", 44.5, "kg", "block mass", PAPER, low=1e-3, high=1e6, var="mass"),
    _item("velocity", "vector3", [0.0, 0.0, -10.0], "m/s", "block velocity at release (the panel "
          "lies in the x-y plane; -z is into it)", PAPER, var=("vx0", "vy0", "vz0")),
    _item("point", "vector2", [0.0, 0.0], "m", "where the block starts above the panel: offset "
          "from the panel centre in x, y", PAPER),
    _item("orientation", "quat", [1.0, 0.0, 0.0, 0.0], "", "block orientation, unit quaternion "
          "[w, x, y, z] (1, 0, 0, 0: faces normal to the axes)", ""),
    _item("duration", "number", 1.0, "s", "simulated time after release", PAPER, low=0.0,
          low_open=True, high=100.0, quick=0.06),
    _item("dt_fraction", "number", 0.5, "", "time step as a fraction of the stable step with the "
          "true masses (runner/timestep.py: the bonds and the contact on the lightest node)",
          "doc/impact.md (\"Time step\")", low=0.0, low_open=True, high=1.0),
    _item("body", "choice", "analytic", "", "analytic: exact truncated cube (fix wirenet/body); "
          "mesh: the STL moved by fix wirenet/rigidmesh", "doc/fix_wirenet_body.md",
          choices=("analytic", "mesh"), var="body_model"),
    Key("output.row_time", "number", 2e-4, "s", "time between rows of impact.csv, block.csv, "
        "energy.csv and momentum.csv", "WireNet (runner/kinds/impact.py)", low=1e-7, high=1.0),
    Key("output.force_window", "number", 5e-3, "s", "window of the block force's windowed peak "
        "(peak_block_force_windowed: the largest mean over this long; the first touch of the "
        "node spheres is a spike of a fraction of a millisecond above the contact's plateau)",
        "WireNet (runner/kinds/impact.py)", low=0.0, low_open=True, high=1.0),
)

# The energy budget of an impact: each term from its own mechanism (inputs/impact.in)
BUDGET = (
    Term("ke_block", ("ke_block",), "kinetic energy of the block (fix wirenet/body)", stored=True,
         dissipative=False),
    Term("ke_net", ("ke_net",), "kinetic energy of the net (compute ke, erotate/sphere)",
         stored=True, dissipative=False),
    Term("pe_block", ("pe_block",), "gravity potential energy of the block", dissipative=False),
    Term("pe_net", ("pe_net",), "gravity potential energy of the net (m g z_cm)",
         dissipative=False),
    Term("e_elastic", ("e_elastic",), "elastic energy of the bonds (bond style energy tally)",
         stored=True, dissipative=False),
    Term("w_plastic", ("w_plastic",), "plastic work of the wires (fix wirenet/bonds)",
         mechanism="plasticity"),
    *budget.RUPTURE_DAMPING_CONTACT_TERMS,
    Term("contact_layers", ("w_contact_pair",), "work of the node-node contacts between the "
         "layers of a compound panel (fix wirenet/contactwork pair): friction; their springs' "
         "energy is below 1e-5 J a contact", sign=-1,
         mechanism="friction: between the net's layers"),
)


class Setup:
    """Panel and block files plus every number the deck needs, from the checked case and its
    [[impact]] entry ``item``; ``restart``: the net an earlier impact of the sequence left."""

    def __init__(self, kind, workdir, item, bending, restart=None, save_net=False):
        c = kind.case
        self.kind, self.case, self.item, self.bending = kind, c, item, bending
        self.restart, self.save_net = restart, save_net
        if restart is not None and not os.path.isfile(restart):
            raise RunError(f"impact: {restart}: no net from the previous impact")
        self.velocity = tuple(item["velocity"])
        self.speed = float(np.linalg.norm(self.velocity))
        self.point = tuple(item["point"])
        self.body_model = item["body"]
        self.g = c["gravity"]
        self.panel = Panel(c, workdir, extra=("--zlo", -BOX_Z, "--zhi", BOX_Z))
        self.data_path, self.json_path, self.meta = (self.panel.data_path, self.panel.json_path,
                                                     self.panel.meta)
        self.layers = self.panel.layers
        self.block = Block(workdir, item["mass"], item["side"], item["orientation"],
                           item["stl"] or None)
        self.stl = self.block.path
        self.dt_fraction = item["dt_fraction"]
        self.dt = self.dt_fraction * timestep.of_panel(
            self.panel, dict(kind.key_variables(), bending=repr(bending)), workdir).loaded
        _, self.node_r = self.panel.centre_node()
        self.node_masses = self.panel.masses
        self.duration = item["duration"]
        self.relax_time = c["preload.settle_time"] if c["preload.mode"] == "settle" else 0.0
        self.steps = int(math.ceil(self.duration / self.dt))
        self.relax_steps = int(math.ceil(self.relax_time / self.dt))
        self.every = max(int(round(c["output.row_time"] / self.dt)), 1)
        self.dump_every = self.every * int(c["output.dump_rows"])
        # bonds.dump holds the bonds within zone_r of the panel centre's axis: every zone in it
        self.zone_r = max(math.hypot(*offset) + radius
                          for _, offset, radius in zones_of(c)) + 0.2
        self.supports = write_supports(c, workdir)

    def variables(self):
        centre = self.panel.centre
        v = dict(self.kind.key_variables(), **self.kind.item_variables(self.item, "impact"),
                 **self.block.inertia_variables(),
                 data=os.path.abspath(self.data_path), stl=os.path.abspath(self.stl),
                 types=os.path.abspath(self.panel.types_path), block_half=repr(self.block.half), gap=GAP,
                 foot_r=repr(0.9 * self.block.side if self.block.side else self.block.radius),
                 quat=" ".join(map(repr, self.block.quat)),
                 centre_x=repr(centre[0]), centre_y=repr(centre[1]),
                 impact_x=repr(centre[0] + self.point[0]), impact_y=repr(centre[1] + self.point[1]),
                 node_r=repr(self.node_r), layers=self.layers, bending=repr(self.bending),
                 alpha_relax=dissipation.SETTLE_ALPHA, dt=repr(self.dt), relax_steps=self.relax_steps,
                 steps=self.steps, every=self.every, dump_every=self.dump_every,
                 zone_r=repr(self.zone_r), out=".",
                 frame_every=max(int(math.ceil(self.steps / self.case["output.frames"])), 1))
        if self.restart:
            v.update(net_from="restart", restart=os.path.abspath(self.restart))
        if self.save_net:
            v["save_net"] = 1
        if self.block.side:
            v.update(block_side=repr(self.block.side), block_cut=repr(self.block.cut))
        v.update((k, os.path.abspath(path)) for k, path in self.supports.items())
        if self.case["materials.rope_strength"]:
            v["rope_strength"] = rope_strength_keyword(True, self.kind.material_values())
        return v


# ---------------------------------------------------------------------------------------------
# reading the run

def read_table(workdir):
    """impact.csv by its column names (the budget's and the block's)."""
    return read_deck_table(os.path.join(workdir, TABLE), sorted(
        {c for t in BUDGET for c in t.columns} | {
            "step", "time", "x", "y", "z", "vx", "vy", "vz", "force_mean", "rx_mean", "ry_mean",
            "rz_mean", "px_net", "py_net", "pz_net", "jx_damp", "jy_damp", "jz_damp",
            "contacts", "force"} | {f"r{c}_{p}_mean" for p in supports.PARTS for c in "xyz"}))


def windowed_peak(time_, force_mean, window):
    """The block force's largest mean over ``window`` seconds (the rows' window means averaged
    over the rows that span it), the middle of that window and the window as the rows make it:
    the contact's plateau, not the first touch's spike."""
    rows = max(int(round(window / (time_[1] - time_[0]))), 1) if len(time_) > 1 else 1
    rows = min(rows, len(force_mean))
    sums = np.cumsum(np.r_[0.0, force_mean])
    means = (sums[rows:] - sums[:-rows]) / rows
    k = int(np.argmax(means))
    return dict(peak_block_force_windowed=float(means[k]),
                time_of_peak_block_force_windowed=float(0.5 * (time_[k] + time_[k + rows - 1])),
                force_window=float(rows * (time_[1] - time_[0]) if len(time_) > 1 else window))


def block_verdict(table, broken):
    """What the net did with the block by the impact's end: 'passed through' (it never turned
    back, has left the net and bonds broke), 'rebounded' (it turned back and has left the net),
    'stopped' (it lies in the net)."""
    turned = np.any(table["vz"] > 0)
    free = table["contacts"][-1] == 0
    if free and not turned and broken:
        return "passed through"
    if free and turned:
        return "rebounded"
    return "stopped"


def momentum_balance(table, dt, mass, net_mass, g):
    """Change of the momentum of block + net against the impulses of the support reactions,
    gravity and the damping forces, per row; the error relative to the block's initial
    momentum. Reactions are window means over the rows' steps: impulse = mean x window."""
    t = table
    p_block = mass * np.column_stack([t["vx"], t["vy"], t["vz"]])
    p_net = np.column_stack([t["px_net"], t["py_net"], t["pz_net"]])
    dp = (p_block - p_block[0]) + (p_net - p_net[0])
    steps = t["step"] - t["step"][0]
    means = np.column_stack([t["rx_mean"], t["ry_mean"], t["rz_mean"]])
    j_react = budget.cumulative(means, np.r_[0.0, np.diff(steps)] * dt)
    j_grav = np.zeros_like(dp)
    j_grav[:, 2] = -(mass + net_mass) * g * steps * dt
    j_damp = np.column_stack([t["jx_damp"], t["jy_damp"], t["jz_damp"]])
    j_damp = j_damp - j_damp[0]
    gap = budget.momentum_gap(dp, j_react, j_grav, j_damp)
    p0 = float(np.linalg.norm(p_block[0]))
    return dict(dp=dp, dp_block=p_block - p_block[0], j_react=j_react, j_grav=j_grav,
                j_damp=j_damp, gap=gap, error=np.linalg.norm(gap, axis=1) / p0, p0=p0)


# ---------------------------------------------------------------------------------------------
# the kind

class Impact(CaseKind):
    name = "impact"
    summary = "a block impact on a panel (paper, section 5)"
    deck = "impact.in"
    keys = KEYS
    takes = ("title", "gravity", "panel.*", "supports.*", "preload.mode", "preload.settle_time",
             "materials.*", "contact.*", "damping.*", "impact.*", "output.row_time",
             "output.force_window",
             "output.dump_rows", "output.frames", "output.zones.*", "output.budget_tolerance",
             "ensemble.*")
    # the physical model (doc/impact.md, "Dissipation"): no damping of absolute velocity during
    # the impact; the bonds' structural damping, friction, plasticity and ruptures take the energy
    defaults = {"preload.mode": "settle", "damping.local": 0.0, "damping.bond": dissipation.STRUCTURAL_ZETA}
    default_sources = {"damping.bond": dissipation.STRUCTURAL_ZETA_SOURCE}
    finished_file = "block.csv"
    WEIGHT = {"compound": 15, "hex": 8, "square": 2}

    @classmethod
    def check(cls, case, fail):
        super().check(case, fail)
        panel_check(case, fail)
        if case["preload.mode"] == "sag":
            fail("preload.mode", "'sag' is a punch pre-load; an impact case takes 'settle' or "
                                 "'none'")
        for k, item in enumerate(case.impacts, 1):
            label = f"impact[{k}]" if len(case.impacts) > 1 else "impact"
            if item["block"] == "stl":
                if not item["stl"]:
                    fail(f"{label}.stl", "block 'stl' needs the STL file")
                stl = os.path.join(os.path.dirname(case.path), item["stl"])
                if not os.path.isfile(stl):
                    fail(f"{label}.stl", f"no such file: {stl}")
                if item["body"] != "mesh":
                    fail(f"{label}.body", "a block STL is moved as a mesh: body = 'mesh'")
                item["stl"] = os.path.abspath(stl)
            elif item["stl"]:
                fail(f"{label}.stl", "only for block = 'stl'")
            if k > 1 and item["body"] != "analytic":
                fail(f"{label}.body", "successive impacts need the analytic block")
            if not item["velocity"][2] < 0:
                fail(f"{label}.velocity", f"{item['velocity']}: the block starts above the panel "
                                          "and must move down into it (a negative z component)")
            inside(case, item["point"], 0.0, fail, f"{label}.point")

    def units(self):
        n = len(self.case.impacts)
        return [(self.case.name if k == 0 else f"{self.case.name}_impact{k + 1}", k)
                for k in range(n)]

    def weight(self):
        return self.WEIGHT.get(self.case["panel.net"], 1)

    def verdict(self, facts):
        if not facts["peak_block_force"] > 0:
            return (record.NO_CONTACT, "the block never touched the net: check impact.point, "
                                       "impact.velocity and impact.duration")
        return self.budget_verdict(facts)

    def run(self, index, ctx):
        c = self.case
        item = c.impacts[index]
        bending, source = bending_of(c, ctx.study_dir)
        units = self.units()
        previous = os.path.join(ctx.study_dir, units[index - 1][0], "run", "net.restart") \
            if index else None
        setup = Setup(self, os.path.join(ctx.case_dir, "setup"), item, bending, previous,
                      save_net=index + 1 < len(units))
        workdir = os.path.join(ctx.case_dir, "run")
        start = time.time()
        wall = engine.run(INPUTS / "impact.in", workdir, setup.variables(), np=ctx.ranks,
                          total_steps=setup.steps, label=f"impact {c['panel.net']}", dt=setup.dt,
                          phase_marker="impact: block released",
                          before=("settling", setup.relax_steps, False))
        table = read_table(workdir)
        facts = self.write_outputs(setup, ctx.case_dir, workdir, table)
        facts.update(panel=c["panel.net"], bending=bending, bending_source=source,
                     block=dict(mass=setup.block.mass, side=setup.block.side, speed=setup.speed,
                                velocity=list(setup.velocity), point=list(setup.point),
                                quat=list(setup.block.quat),
                                inertia=setup.block.inertia.tolist()),
                     gravity=setup.g, body_model=setup.body_model, damping=c["damping.local"],
                     bond_damping=c["damping.bond"],
                     dissipation=dissipation.model(c),
                     rope_strength=list(rope_strength(self.material_values()))
                     if c["materials.rope_strength"] else None,
                     dt=setup.dt, dt_fraction=setup.dt_fraction, steps=setup.steps,
                     duration=setup.duration, relax_time=setup.relax_time,
                     relax_steps=setup.relax_steps, nodes=int(len(setup.node_masses)),
                     net_mass=float(np.sum(setup.node_masses)), run_wall_time=wall,
                     post_wall_time=time.time() - start - wall,
                     sequence=dict(index=index + 1, of=len(units),
                                   previous=units[index - 1][0] if index else None))
        return facts

    def write_outputs(self, setup, case_dir, workdir, t):
        """block.csv, edges.csv, energy.csv, momentum.csv, ruptures.csv, zone_forces.csv and the
        ParaView series; returns the facts for case.json."""
        time_ = t["time"] - t["time"][0]
        write_csv(os.path.join(case_dir, "block.csv"), ("time", "x", "y", "z", "vx", "vy", "vz",
                                                        "force"),
                  zip(time_, t["x"], t["y"], t["z"], t["vx"], t["vy"], t["vz"], t["force_mean"]))
        edge = np.sqrt(t["rx_mean"] ** 2 + t["ry_mean"] ** 2 + t["rz_mean"] ** 2)
        # each edge's and the corners' reaction: the loads a designer sizes the supports for
        # (the total above cancels the pulls of opposite edges)
        part = {p: np.column_stack([t[f"r{c}_{p}_mean"] for c in "xyz"]) for p in supports.PARTS}
        part_force = {p: np.linalg.norm(r, axis=1) for p, r in part.items()}
        columns = ["time", "rx", "ry", "rz", "force"]
        values = [time_, t["rx_mean"], t["ry_mean"], t["rz_mean"], edge]
        for p in supports.PARTS:
            columns += [f"{p}_rx", f"{p}_ry", f"{p}_rz", f"{p}_force"]
            values += [part[p][:, 0], part[p][:, 1], part[p][:, 2], part_force[p]]
        write_csv(os.path.join(case_dir, "edges.csv"), columns, zip(*values))
        terms, total, e0, error = budget.energy_budget(t, BUDGET)
        names = tuple(term.name for term in BUDGET)
        write_csv(os.path.join(case_dir, "energy.csv"), ("time",) + names + ("total", "closure_error"),
                  zip(time_, *(terms[k] for k in names), total, error))
        net_mass = float(np.sum(setup.node_masses))
        mom = momentum_balance(t, setup.dt, setup.block.mass, net_mass, setup.g)
        write_csv(os.path.join(case_dir, "momentum.csv"),
                  ("time", "dpz_block", "dpz_total", "jz_reactions", "jz_gravity", "jz_damping",
                   "error"),
                  zip(time_, mom["dp_block"][:, 2], mom["dp"][:, 2], mom["j_react"][:, 2],
                      mom["j_grav"][:, 2], mom["j_damp"][:, 2], mom["error"]))
        panel = PanelInfo(setup.json_path)
        ruptures = netoutputs.ruptures(os.path.join(workdir, "ruptures.dump"), setup.dt,
                                       panel.families)
        netoutputs.write_ruptures(os.path.join(case_dir, "ruptures.csv"), ruptures)
        t0 = t["step"][0] * setup.dt
        netoutputs.write_zones(case_dir, workdir, setup.json_path, zones_of(self.case), setup.dt,
                               lambda times: np.interp(times - t0, time_, t["z"][0] - t["z"]))
        netoutputs.write_series(case_dir, workdir, setup.data_path, setup.stl, setup.dt)

        k_edge = int(np.argmax(edge))
        k_force = int(np.argmax(t["force_mean"]))
        k_low = int(np.argmin(t["z"]))
        rebound = np.nonzero((t["vz"] > 0) & (np.arange(len(t["vz"])) > k_low))[0]
        closure = dict(closure_error=float(np.max(np.abs(error))), initial_energy=e0,
                       final={k: float(terms[k][-1]) for k in names},
                       at_lowest_point={k: float(terms[k][k_low]) for k in names},
                       mechanisms=budget.mechanisms(terms, BUDGET),
                       local_damping_fraction=float(terms["damping"][-1]) / e0)
        closure["final_error"] = float(error[-1])
        momentum = dict(error=float(np.max(mom["error"])), initial_block_momentum=mom["p0"],
                        final_error=float(mom["error"][-1]),
                        final={"dpz_block": float(mom["dp_block"][-1, 2]),
                               "dpz_total": float(mom["dp"][-1, 2]),
                               "jz_reactions": float(mom["j_react"][-1, 2]),
                               "jz_gravity": float(mom["j_grav"][-1, 2]),
                               "jz_damping": float(mom["j_damp"][-1, 2])})
        return dict(
            energy=closure, momentum=momentum,
            edge_force_peak=float(edge[k_edge]), time_of_edge_force_peak=float(time_[k_edge]),
            edge_force_peak_z=float(np.max(np.abs(t["rz_mean"]))),
            support_peaks={p: dict(force=float(f.max()), time=float(time_[int(np.argmax(f))]),
                                   force_z=float(np.max(np.abs(part[p][:, 2]))))
                           for p, f in part_force.items()},
            side_force_peak=max(float(part_force[p].max()) for p in supports.EDGES),
            peak_block_force=float(t["force_mean"][k_force]),
            time_of_peak_block_force=float(time_[k_force]),
            peak_block_force_raw=float(np.max(t["force"])),
            **windowed_peak(time_, t["force_mean"], self.case["output.force_window"]),
            max_displacement=float(t["z"][0] - t["z"][k_low]),
            time_of_max_displacement=float(time_[k_low]),
            rebound_time=float(time_[rebound[0]]) if rebound.size else None,
            final_block_velocity=[float(t["vx"][-1]), float(t["vy"][-1]), float(t["vz"][-1])],
            block_verdict=block_verdict(t, len(ruptures)),
            broken_bonds=len(ruptures),
            ruptures=ruptures[:200], ruptures_listed=min(len(ruptures), 200),
            first_rupture=netoutputs.rupture_facts(ruptures[0]) if ruptures else None,
            families=sorted(set(panel.families.values())))
