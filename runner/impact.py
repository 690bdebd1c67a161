"""Block impact cases (paper, section 5): a rigid truncated cube (0.45 m, 44.5 kg, 10 m/s along
-z, undamped; the generator's STL moved by fix wirenet/rigidmesh, or the exact body of fix
wirenet/body: ``body_model``, doc/impact.md) hits the centre of a hexagonal, square or compound panel.
Deck: inputs/impact.in. Beyond the paper, every case gets:

- the force on the edge supports (the posts) as a time series (edges.csv) and its peak;
- an energy budget whose terms are each measured by their own mechanism (energy.csv,
  case.json "energy"): block and net kinetic energy, gravity potential energy of both (from the
  positions), elastic energy of the bonds (bond style energy tally), plastic work of the wires
  (from each wire's largest elongation, fix wirenet/bonds), energy released by broken bonds (fix wirenet/bonds),
  work of the local damping (fix wirenet/damping), energy dissipated by bond damping
  (bond_coeff ... damping ZETA, f_wirenet_bonds[4]), work of the contact forces on the nodes
  (fix wirenet/contactwork around fix wall/gran) and on the block (fix wirenet/rigidmesh), work
  of the node-node contacts between compound layers (fix wirenet/contactwork pair).
  Their sum must stay at its initial value; ``closure_error`` is the largest departure
  relative to the initial energy;
- a momentum balance: the change of the momentum of block and net equals the impulse of the
  support reactions, of gravity (block and net) and of the damping forces (``momentum``);
- broken bonds: count and locations (ruptures.csv, case.json "ruptures").
"""

import math
import os
import time

import numpy as np

from postprocess import bodyframes, liggghts, model, solid, vtu
from postprocess.csvio import read_csv, read_deck_table, write_csv
from postprocess.datafile import read_data
from postprocess.errors import PostprocessError
from postprocess.meta import PanelInfo, read_json
from postprocess.model import PAPER_BENDING, rope_strength_keyword

from . import punch

BLOCK = dict(side=0.45, mass=44.5, speed=10.0)
ALPHA = 0.5            # local damping on the net nodes (paper, dynamic runs)
# The second dissipation model: no local damping, viscous bond damping of 5 % of each bond's
# critical damping instead. No measurement fixes this ratio for these nets: 5 % is a round value
# of the order of the few percent usual for steel structures with friction in their joints
# (the double twists); doc/impact.md says so, and the report shows both models side by side.
BOND_ZETA = 0.05
ALPHA_RELAX = 0.7      # while the net settles under its weight before the impact
GAP = 0.005            # clearance between the block and the highest node under it [m]
G = 9.81
DT_SAFETY = 0.5        # as the punch cases: half the stable step with the true masses
OUTPUT_INTERVAL = 2e-4   # s between rows of impact.csv / block.csv
DUMP_ROWS = 10           # rows between bond dumps (zone forces)
# The block's default model: "analytic" (fix wirenet/body truncated-cube, free, no facets) or
# "mesh" (the generator's STL moved by fix wirenet/rigidmesh); doc/impact.md.
DEFAULT_BODY = "analytic"
FRAMES = 40              # ParaView frames over the impact (inputs/include/frames.in)


def _panel_options(kind, quick, width=None, height=None, extra=()):
    """wirenet-gen options; the box is raised so that a rebounding block stays inside it."""
    if kind not in ("hex", "square", "compound"):
        raise PostprocessError(f"impact: unknown panel '{kind}' (hex, square or compound)")
    return [*punch.panel_options(kind, quick, width, height, extra), "--zlo", -3.0, "--zhi", 3.0]


class Block:
    """The block: the generator's truncated cube (analytic or mesh) or a closed STL of the user
    (mesh), with its mass properties, oriented by the unit quaternion ``quat``. Writes the
    oriented, centred STL the frames draw (and the mesh path moves) into ``workdir``."""

    def __init__(self, workdir, mass, side, quat=(1.0, 0.0, 0.0, 0.0), stl=None):
        self.mass, self.quat = float(mass), tuple(float(v) for v in quat)
        self.path = os.path.join(workdir, "block.stl")
        rotation = solid.quaternion_matrix(self.quat)
        if stl is None:
            liggghts.generate("shape truncated-cube", self.path, "--side", side, "--mass", mass)
            meta = read_json(os.path.join(workdir, "block.json"))
            self.side = float(meta["parameters"]["side"])
            self.cut = float(meta["parameters"]["corner_cut"])
            inertia, centroid = np.asarray(meta["inertia"], float), np.zeros(3)
            points, triangles = vtu.read_stl(self.path)
        else:
            self.side = self.cut = None
            points, triangles = vtu.read_stl(stl)
            _, centroid, inertia = solid.mass_properties(points, triangles, self.mass)
        points = (points - centroid) @ rotation.T
        bodyframes.write_stl(self.path, points, triangles, name="block")
        self.inertia = rotation @ inertia @ rotation.T     # space axes as placed
        self.half = float(-points[:, 2].min())             # centroid to the lowest point
        self.radius = float(np.linalg.norm(points[:, :2], axis=1).max())


class Setup:
    """Panel and block files plus every number the deck needs. The keyword options are those of
    an impact case file (runner/schema.py documents each with its default and source); their
    defaults are the paper's."""

    def __init__(self, workdir, panel, bending=PAPER_BENDING, quick=False, duration=None, relax=None,
                 mass=BLOCK["mass"], side=BLOCK["side"], speed=BLOCK["speed"], alpha=ALPHA,
                 procs=None, body_model=DEFAULT_BODY, bond_zeta=0.0, rope_strength=False,
                 width=None, height=None, gen_options=(), supports=None, gravity=G,
                 velocity=None, point=(0.0, 0.0), quat=(1.0, 0.0, 0.0, 0.0), stl=None,
                 materials=None, restart=None, save_net=False, row_time=OUTPUT_INTERVAL,
                 dump_rows=DUMP_ROWS, frames=FRAMES, zones=punch.ZONES, dt_fraction=DT_SAFETY):
        velocity = (0.0, 0.0, -speed) if velocity is None else tuple(float(v) for v in velocity)
        if not (mass > 0 and side > 0 and np.linalg.norm(velocity) > 0):
            raise PostprocessError(f"impact: mass, side and speed must be > 0 (got {mass}, "
                                   f"{side}, {np.linalg.norm(velocity)})")
        if not 0 <= alpha < 1:
            raise PostprocessError(f"impact: damping alpha must be in [0, 1) (got {alpha})")
        # the block: an exact truncated cube of fix wirenet/body ("analytic") or an STL moved by
        # fix wirenet/rigidmesh ("mesh"); the STL is written in both cases (the frames draw it)
        self.body_model = punch.check_body_model(body_model)
        if stl is not None and self.body_model != "mesh":
            raise PostprocessError("impact: a block STL needs body_model mesh")
        if not 0 <= bond_zeta < 10:
            raise PostprocessError(f"impact: bond damping zeta must be in [0, 10) (got {bond_zeta})")
        self.bond_zeta = bond_zeta
        self.rope_strength = rope_strength   # breakable ropes (materials.in rope_sigma_t/tau_c)
        self.materials, self.supports, self.g = dict(materials or {}), supports, float(gravity)
        # successive impacts: start from the net an earlier impact left (its restart file) and
        # leave the net for the next one
        self.restart, self.save_net = restart, save_net
        if restart is not None and not os.path.isfile(restart):
            raise PostprocessError(f"impact: {restart}: no net from the previous impact")
        os.makedirs(workdir, exist_ok=True)
        self.panel, self.bending, self.quick = panel, bending, quick
        self.mass, self.side, self.alpha = mass, side, alpha
        self.velocity, self.speed = velocity, float(np.linalg.norm(velocity))
        self.point = tuple(float(v) for v in point)
        self.procs = procs      # MPI processor grid "PX PY PZ" (None: LIGGGHTS chooses)
        options = _panel_options(panel, quick, width, height, gen_options)
        prefix = os.path.join(workdir, "panel")
        self.data_path = liggghts.generate(options[0], prefix, *options[1:])
        self.json_path = prefix + ".json"
        self.block = Block(workdir, mass, side, quat, stl)
        self.stl = self.block.path
        self.meta = read_json(self.json_path)
        data = read_data(self.data_path)
        self.layers = 2 if self.meta.get("kind") == "compound" else 1
        # the stable step of the punch cases (bonds + the 1e9 N/m contact on the lightest node)
        # times dt_fraction (0.5: doc/impact.md "Time step")
        if not 0 < dt_fraction <= 1:
            raise PostprocessError(f"impact: dt_fraction must be in (0, 1] (got {dt_fraction})")
        self.dt_fraction = float(dt_fraction)
        self.dt = dt_fraction * punch.stable_dt(data, bending, self.layers, platter=True,
                                              materials=self.materials)
        _, self.node_r = punch.centre_node(data, self.meta)
        self.node_masses = punch.node_masses(data)
        self.duration = duration or (0.06 if quick else 1.0)
        self.relax_time = relax if relax is not None else (0.01 if quick else 0.1)
        self.steps = int(math.ceil(self.duration / self.dt))
        self.relax_steps = int(math.ceil(self.relax_time / self.dt))
        self.every = max(int(round(row_time / self.dt)), 1)
        self.dump_every = self.every * int(dump_rows)
        self.frames = int(frames)
        # bonds.dump holds the bonds within zone_r of the panel centre's axis: every zone in it
        self.zone_r = max(math.hypot(*offset) + radius for _, offset, radius in zones) + 0.2

    def variables(self):
        inertia = self.block.inertia
        centre = self.meta.get("centre", [0.0, 0.0, 0.0])
        v = dict(punch.model_variables(self.materials),
                 data=os.path.abspath(self.data_path), stl=os.path.abspath(self.stl),
                 mass=repr(self.mass), ixx=repr(inertia[0, 0]), iyy=repr(inertia[1, 1]),
                 izz=repr(inertia[2, 2]), ixy=repr(inertia[0, 1]), ixz=repr(inertia[0, 2]),
                 iyz=repr(inertia[1, 2]), block_half=repr(self.block.half), gap=GAP,
                 foot_r=repr(0.9 * self.side if self.block.side else self.block.radius),
                 vx0=repr(self.velocity[0]), vy0=repr(self.velocity[1]),
                 vz0=repr(self.velocity[2]), quat=" ".join(map(repr, self.block.quat)),
                 centre_x=repr(centre[0]), centre_y=repr(centre[1]),
                 impact_x=repr(centre[0] + self.point[0]), impact_y=repr(centre[1] + self.point[1]),
                 node_r=repr(self.node_r), layers=self.layers, bending=self.bending,
                 alpha=self.alpha, alpha_relax=ALPHA_RELAX, g=repr(self.g),
                 dt=repr(self.dt), relax_steps=self.relax_steps, steps=self.steps,
                 every=self.every, dump_every=self.dump_every,
                 zone_r=repr(self.zone_r), out=".",
                 frame_every=max(int(math.ceil(self.steps / self.frames)), 1),
                 body_model=self.body_model)
        if self.restart:
            v.update(net_from="restart", restart=os.path.abspath(self.restart))
        if self.save_net:
            v["save_net"] = 1
        if self.block.side:
            v.update(block_side=repr(self.block.side), block_cut=repr(self.block.cut))
        if self.supports:     # {deck variable: include file} of runner/cases.write_supports
            v.update((k, os.path.abspath(path)) for k, path in self.supports.items())
        if self.procs:
            v["procs"] = self.procs
        if self.bond_zeta:
            v["bond_zeta"] = repr(self.bond_zeta)
        if self.rope_strength:
            v["rope_strength"] = rope_strength_keyword(True, self.materials)
        return v


# ---------------------------------------------------------------------------------------------
# reading the run

COLUMNS = ("step", "time", "x", "y", "z", "vx", "vy", "vz", "force", "fx", "fy", "fz",
           "ke_block", "pe_block", "w_contact_block", "ke_net", "pe_net", "e_elastic",
           "w_plastic", "e_released", "broken", "w_damping", "w_contact_net", "w_contact_pair", "px_net",
           "py_net", "pz_net", "jx_damp", "jy_damp", "jz_damp", "jx_contact", "jy_contact",
           "jz_contact", "rx", "ry", "rz", "rx_mean", "ry_mean", "rz_mean", "force_mean")


def read_impact(workdir):
    """impact.csv without the comment line that fix print adds when it appends."""
    table = read_deck_table(os.path.join(workdir, "impact.csv"), COLUMNS)
    table["w_bond_damping"] = _bond_damping_work(workdir, table["step"])
    return table


def _bond_damping_work(workdir, steps):
    """Energy dissipated by bond damping since the impact began, at the rows' steps, from
    bond_damping.csv (inputs/include/bond_damping_work.in): 0 at step 0, which fix print may
    not write; a row the file lacks is an error."""
    path = os.path.join(workdir, "bond_damping.csv")
    rows = read_csv(path, required=("step", "w_bond_damping"))
    by_step = {0: 0.0}
    by_step.update(zip(rows["step"].astype(int).tolist(), rows["w_bond_damping"].tolist()))
    missing = [int(s) for s in steps if int(s) not in by_step]
    if missing:
        raise PostprocessError(f"{path}: no row for step {missing[0]} of impact.csv")
    return np.array([by_step[int(s)] for s in steps])


ENERGY_TERMS = ("ke_block", "ke_net", "pe_block", "pe_net", "e_elastic", "w_plastic",
                "e_released", "damping", "bond_damping", "contact", "contact_layers")


def energy_budget(table):
    """Per row: every term of the budget measured from the first row (potential energies as
    changes, dissipations as positive amounts), their sum and the closure error relative to
    the initial energy E0 = kinetic energy of block and net + elastic energy of the bonds."""
    t = table
    terms = {
        "ke_block": t["ke_block"],
        "ke_net": t["ke_net"],
        "pe_block": t["pe_block"] - t["pe_block"][0],
        "pe_net": t["pe_net"] - t["pe_net"][0],
        "e_elastic": t["e_elastic"],
        "w_plastic": t["w_plastic"] - t["w_plastic"][0],
        "e_released": t["e_released"] - t["e_released"][0],
        # work done by the damping / the contacts on block and nodes: their negatives are the
        # energy they took out (contact: friction, plus the small spring energy of open contacts)
        "damping": -(t["w_damping"] - t["w_damping"][0]),
        # viscous bond damping (bond_coeff ... damping ZETA): energy it dissipated
        "bond_damping": t["w_bond_damping"] - t["w_bond_damping"][0],
        "contact": -((t["w_contact_block"] - t["w_contact_block"][0]) +
                     (t["w_contact_net"] - t["w_contact_net"][0])),
        # node-node contacts between the layers of a compound panel (friction)
        "contact_layers": -(t["w_contact_pair"] - t["w_contact_pair"][0]),
    }
    total = sum(terms[k] for k in ENERGY_TERMS)
    e0 = float(total[0])
    error = (total - e0) / e0
    return terms, total, e0, error


def momentum_balance(table, dt, every, mass, net_mass, g=G):
    """Change of the momentum of block + net against the impulses of the support reactions,
    gravity and the damping forces, per row; the error relative to the block's initial
    momentum. Reactions are window means over ``every`` steps: impulse = mean x every x dt."""
    t = table
    p_block = mass * np.column_stack([t["vx"], t["vy"], t["vz"]])
    p_net = np.column_stack([t["px_net"], t["py_net"], t["pz_net"]])
    dp = (p_block - p_block[0]) + (p_net - p_net[0])
    steps = t["step"] - t["step"][0]
    means = np.column_stack([t["rx_mean"], t["ry_mean"], t["rz_mean"]])
    window = np.r_[0.0, np.diff(steps)] * dt
    j_react = np.cumsum(means * window[:, None], axis=0)
    j_grav = np.zeros_like(dp)
    j_grav[:, 2] = -(mass + net_mass) * g * steps * dt
    j_damp = np.column_stack([t["jx_damp"], t["jy_damp"], t["jz_damp"]])
    j_damp = j_damp - j_damp[0]
    gap = dp - (j_react + j_grav + j_damp)
    p0 = float(np.linalg.norm(p_block[0]))
    return dict(dp=dp, dp_block=p_block - p_block[0], j_react=j_react, j_grav=j_grav,
                j_damp=j_damp, gap=gap, error=np.linalg.norm(gap, axis=1) / p0, p0=p0)


def read_ruptures(path, dt, families):
    rows = punch.read_ruptures(path)
    out = []
    for step, a1, a2, btype, x, y, z, elong in rows:
        out.append(dict(time=float(step) * dt, step=int(step), atom1=int(a1), atom2=int(a2),
                        type=int(btype), family=families.get(int(btype), f"type{int(btype)}"),
                        x=float(x), y=float(y), z=float(z), elongation=float(elong)))
    return out


# ---------------------------------------------------------------------------------------------
# outputs

def write_outputs(setup, case_dir, workdir, table, zones=punch.ZONES):
    """block.csv, edges.csv, energy.csv, momentum.csv, ruptures.csv, zone_forces.csv; returns
    the facts for case.json."""
    t = table
    time_ = t["time"] - t["time"][0]
    write_csv(os.path.join(case_dir, "block.csv"), ("time", "x", "y", "z", "vx", "vy", "vz",
                                                    "force"),
              zip(time_, t["x"], t["y"], t["z"], t["vx"], t["vy"], t["vz"], t["force_mean"]))
    edge = np.sqrt(t["rx_mean"] ** 2 + t["ry_mean"] ** 2 + t["rz_mean"] ** 2)
    write_csv(os.path.join(case_dir, "edges.csv"), ("time", "rx", "ry", "rz", "force"),
              zip(time_, t["rx_mean"], t["ry_mean"], t["rz_mean"], edge))
    terms, total, e0, error = energy_budget(t)
    write_csv(os.path.join(case_dir, "energy.csv"),
              ("time",) + ENERGY_TERMS + ("total", "closure_error"),
              zip(time_, *(terms[k] for k in ENERGY_TERMS), total, error))
    net_mass = float(np.sum(setup.node_masses))
    mom = momentum_balance(t, setup.dt, setup.every, setup.mass, net_mass, setup.g)
    write_csv(os.path.join(case_dir, "momentum.csv"),
              ("time", "dpz_block", "dpz_total", "jz_reactions", "jz_gravity", "jz_damping",
               "error"),
              zip(time_, mom["dp_block"][:, 2], mom["dp"][:, 2], mom["j_react"][:, 2],
                  mom["j_grav"][:, 2], mom["j_damp"][:, 2], mom["error"]))
    panel = PanelInfo(setup.json_path)
    ruptures = read_ruptures(os.path.join(workdir, "ruptures.dump"), setup.dt, panel.families)
    write_csv(os.path.join(case_dir, "ruptures.csv"),
              ("time", "atom1", "atom2", "type", "family", "x", "y", "z", "elongation"),
              [(r["time"], r["atom1"], r["atom2"], r["type"], r["family"], r["x"], r["y"],
                r["z"], r["elongation"]) for r in ruptures])
    t0 = t["step"][0] * setup.dt
    punch.write_zones(case_dir, workdir, setup.json_path, zones, setup.dt,
                      lambda times: np.interp(times - t0, time_, t["z"][0] - t["z"]))

    # the ParaView series CASE/CASE.pvd (net) and CASE/CASE_body.pvd (block); the analytic
    # block's frames are the generator's STL moved to its poses
    bodyframes.write_body_frames(workdir, setup.stl)
    vtu.write_case_series(case_dir, workdir, setup.data_path, setup.dt)

    k_edge = int(np.argmax(edge))
    k_force = int(np.argmax(t["force_mean"]))
    k_low = int(np.argmin(t["z"]))
    rebound = np.nonzero((t["vz"] > 0) & (np.arange(len(t["vz"])) > k_low))[0]
    closure = dict(closure_error=float(np.max(np.abs(error))), initial_energy=e0,
                   final={k: float(terms[k][-1]) for k in ENERGY_TERMS},
                   at_lowest_point={k: float(terms[k][k_low]) for k in ENERGY_TERMS})
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
        peak_block_force=float(t["force_mean"][k_force]),
        time_of_peak_block_force=float(time_[k_force]),
        max_displacement=float(t["z"][0] - t["z"][k_low]), time_of_max_displacement=float(time_[k_low]),
        rebound_time=float(time_[rebound[0]]) if rebound.size else None,
        final_block_velocity=[float(t["vx"][-1]), float(t["vy"][-1]), float(t["vz"][-1])],
        broken_bonds=len(ruptures),
        ruptures=ruptures[:200], ruptures_listed=min(len(ruptures), 200),
        first_rupture=rupture_facts(ruptures[0]) if ruptures else None,
        families=sorted(set(panel.families.values())))


def rupture_facts(r):
    """A rupture as case.json's first_rupture object (the same keys as the punch cases', with
    time instead of the platter's displacement and force)."""
    return dict(time=r["time"], step=r["step"], position=[r["x"], r["y"], r["z"]],
                bond=dict(atom1=r["atom1"], atom2=r["atom2"], type=r["type"], family=r["family"]))


def run_case(case_dir, panel, bending=PAPER_BENDING, quick=False, np_=1, zones=punch.ZONES,
             **setup_options):
    """One impact case; returns the facts for case.json."""
    setup = Setup(os.path.join(case_dir, "setup"), panel, bending, quick, zones=zones,
                  **setup_options)
    workdir = os.path.join(case_dir, "run")
    start = time.time()
    wall = liggghts.run(liggghts.INPUTS / "impact.in", workdir, setup.variables(), np=np_,
                        total_steps=setup.steps, label=f"impact {panel}", dt=setup.dt,
                        phase_marker="impact: block released")
    table = read_impact(workdir)
    facts = write_outputs(setup, case_dir, workdir, table, zones)
    facts.update(panel=panel, bending=bending,
                 block=dict(mass=setup.mass, side=setup.block.side, speed=setup.speed,
                            velocity=list(setup.velocity), point=list(setup.point),
                            quat=list(setup.block.quat), inertia=setup.block.inertia.tolist()),
                 gravity=setup.g,
                 body_model=setup.body_model, damping=setup.alpha, bond_damping=setup.bond_zeta,
                 dissipation="bond" if setup.bond_zeta else "local",
                 rope_strength=list(model.rope_strength(setup.materials)) if setup.rope_strength else None,
                 dt=setup.dt, dt_fraction=setup.dt_fraction, steps=setup.steps,
                 duration=setup.duration, relax_time=setup.relax_time,
                 relax_steps=setup.relax_steps, nodes=int(len(setup.node_masses)),
                 net_mass=float(np.sum(setup.node_masses)), run_wall_time=wall,
                 post_wall_time=time.time() - start - wall)
    return facts
