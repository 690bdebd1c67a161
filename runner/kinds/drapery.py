"""Drapery cases (issue #42; doc/drapery.md): a mesh panel hung on a slope from a row of top
anchors, lying on the ground below them and bolted on a grid, hit by a rigid block that slides
and tumbles down the slope from above the top anchors into the gap between the mesh and the
slope. Deck: inputs/drapery.in.

The panel is generated flat (wirenet-gen, the [panel] keys) and turned onto the slope here, so
gravity stays vertical and every output is in the world frame: the slope is the plane through
the origin with the outward unit normal n = (0, -sin b, cos b), its up-slope direction
u = (0, cos b, sin b); the top anchor line runs along x at up-slope distance 0, drapery.top_height
off the slope. The mesh is laid from there straight down to the slope at HANG_ANGLE and then on
it, bolted to the slope at the grid anchors; it settles under its weight (damped, outside the
budget) before the block is released.

Outputs: the block's path, the anchors' loads (each anchor's, the top row's and the grid's sums),
the bulge (how far the mesh rose off the slope since it settled), the energy budget (each term
by its own mechanism: BUDGET), ruptures and the ParaView series.
"""

import dataclasses
import math
import os
import shutil
import time

import numpy as np

from postprocess import record, vtu
from postprocess.csvio import read_csv, read_deck_table, write_csv
from postprocess.errors import PostprocessError
from postprocess.meta import PanelInfo

from .. import INPUTS, budget, dissipation, engine, netoutputs, timestep
from ..block import Block, floor_damping
from ..budget import Term
from ..errors import RunError
from ..materials import MATERIALS, SOURCES, bending_of
from ..panel import Panel
from ..params import Derived, Key
from .base import CaseKind

TABLE = "drapery.csv"    # the deck's table: names in its header (inputs/drapery.in)
HANG_ANGLE = 30.0        # deg: the laid mesh's line from the top anchors to the slope (settling
                         # finds the hanging shape; a numerical start, not a property)
MARGIN = 4.0             # m: the box beyond the laid mesh (the block lifts it, the foot slides)
GAP = 0.005              # m: the block's clearance above the slope at release
ROCK_DENSITY = 2700.0    # kg/m3: granite and limestone 2600-2750 (rockfall practice; the
                         # density gives the block's size only)
DEBRIS_TYPE = 9          # the debris spheres' atom type, with the 14-type contact tables
DEBRIS_TYPES = 14        # (include/contacts.in: the same contact values for every type pair)
DEBRIS_MOLECULE = 3      # the first sphere's molecule ID, one each: the deck excludes contacts
                         # within a molecule (the nets' are 1 and 2)
TERRAIN_TOLERANCE = 1e-6  # m: a terrain vertex this far above the slope plane still lies on it
SETTLE_CHECK = 0.01      # s: how often the settling asks whether the mesh is still
SETTLE_SOFTEN = 16.0     # the slope's contact with the nodes this many times softer while the
                         # mesh settles (kn, ks; fix_modify soften): the step is then the bonds',
                         # 2.2x the contact's on the example; the still mesh moves by its weight
                         # / kn (nm). Not with a terrain (fix wall/gran keeps its stiffness)
SETTLE_WEIGHT_STEP = 4.0  # drapery.settle_weight's stages: the weight falls 4x from one to the
                          # next (64: 64, 16, 4, 1 g), so each gives back a quarter of the wires'
                          # stretch (measured: docs/PERFORMANCE.md, "2026-12-07: drapery")
SETTLE_PLASTIC_WORK = 1e-6  # J: a settling whose wires did more plastic work than this (round-off
                            # 1e-17 J on the examples) yielded: not-settled
SETTLED_FRACTION = 0.1   # the mesh's own rise before the load touches it, at most this of the
                         # peak bulge: else the bulge and the anchors' loads are the settling's
CONTACT_FRACTION = 1e-6  # the load touched the mesh: a peak force above this times its weight
DEBRIS_GAP = 0.01        # the heap's spheres a hundredth of a diameter apart at release
EXAMPLE = "WireNet's drapery example (issue #42: a 10 m x 10 m mesh on a 60 degree slope)"


def _drapery(name, type_, default, unit, doc, source, **kw):
    return Key(f"drapery.{name}", type_, default, unit, doc, source, **kw)


def _ground(name, doc, **kw):
    """The block's ground: default and source from inputs/include/materials.in (as the fence's)."""
    return _drapery(name, "number", float(MATERIALS[name]), kw.pop("unit", ""), doc,
                    SOURCES[name], **kw)


KEYS = (
    _drapery("slope", "number", 60.0, "deg", "slope angle from the horizontal (the mesh lies on "
             "it; gravity stays vertical)", EXAMPLE, low=0.0, low_open=True, high=89.0),
    _drapery("top_height", "number", 1.0, "m", "height of the top anchor line above the slope "
             "(the gap the block enters under the mesh)", EXAMPLE + ": a design choice",
             low=0.05, high=10.0, quick=0.9),
    _drapery("anchor_spacing", "number", 3.0, "m", "spacing of the grid anchors below the top "
             "row (across and down the slope, the centre line between two columns; the node "
             "nearest each grid point is bolted to the slope from the start; none where the "
             "laid mesh hangs above the slope); 0: the top row only", EXAMPLE + " (a 3 m grid)",
             low=0.0, high=100.0, quick=1.0),
    _drapery("plate_radius", "number", 0.0, "m", "secured drapery: the radius of each grid "
             "bolt's plate; every node of the laid mesh within it of the bolt's node is held "
             "with it (the plate pressing the mesh onto the slope), and the bolt's load is their "
             "sum; 0: the bolt holds its one node", "unverified: spike plates of secured drapery "
             "systems are 0.2-0.35 m across (manufacturers' data sheets, e.g. a 330 x 200 mm "
             "plate; not read)", low=0.0, high=5.0),
    _drapery("block_mass", "number", 500.0, "kg", "block mass (a truncated cube)", EXAMPLE,
             low=1.0, high=1e6),
    _drapery("block_side", "number", Derived(
        lambda v: (v["drapery.block_mass"] / ROCK_DENSITY) ** (1.0 / 3.0),
        f"the cube of the block's mass at {ROCK_DENSITY:g} kg/m3"), "m",
        "the truncated cube's side", "rock density 2600-2750 kg/m3 (granite, limestone)",
        low=0.01, high=20.0),
    _drapery("release_distance", "number", 5.0, "m", "where the block starts: up-slope "
             "distance from the top anchor line, on the slope", EXAMPLE + " (5 m upslope)",
             low=0.0, high=1000.0, quick=0.5),
    _drapery("release_speed", "number", 0.0, "m/s", "the block's speed down the slope at "
             "release", EXAMPLE + " (released at rest)", low=0.0, high=100.0, quick=6.0),
    _drapery("load", "choice", "block", "", "what comes down the slope: block (one rigid "
             "block, drapery.block_*) or debris (a heap of rock spheres, drapery.debris_*); "
             "either released drapery.release_distance upslope at drapery.release_speed",
             EXAMPLE + " (a block)", choices=("block", "debris")),
    _drapery("debris_mass", "number", 500.0, "kg", "debris: the heap's mass (spheres of "
             f"drapery.debris_diameter at {ROCK_DENSITY:g} kg/m3, as many as it takes)",
             "the example's block mass, as debris", low=1.0, high=1e6, quick=150.0),
    _drapery("debris_diameter", "number", 0.2, "m", "debris: the spheres' diameter (larger "
             "than the mesh's longest node spacing: the wires between nodes are not contact "
             "surfaces, only the node spheres are)", "a design choice: cobbles (ISO 14688-1: "
             "cobbles 63-200 mm, boulders above)", low=0.01, high=5.0, quick=0.15),
    _drapery("debris_width", "number", 2.0, "m", "debris: the heap's width across the slope, "
             "centred on drapery.point_x (the heap is as many rows up the slope as layers "
             "deep)", "a design choice", low=0.01, high=100.0, quick=0.6),
    _drapery("terrain", "file", "", "", "the ground as a surface: an ASCII STL file (relative to "
             "the case file) in the drapery's world frame (m; the slope plane through the "
             "origin, x across, up the slope towards +y and +z), nowhere above the slope plane "
             "(the mesh is laid on the plane and settles onto the terrain); the nodes and the "
             "debris touch it with the node contact law; needs drapery.load debris (the block "
             "touches the analytic slope only); empty: the slope plane", "a design choice"),
    _drapery("point_x", "number", 0.0, "m", "the block's path across the slope: offset from "
             "the panel's centre line", EXAMPLE),
    _drapery("settle_time", "number", 5.0, "s", "settling of the laid mesh under its weight "
             "before the load is released, at most (viscous damping, outside the budget; it ends "
             "earlier once the mesh is still: drapery.settle_speed)", "doc/drapery.md",
             low=0.0, high=100.0, quick=2.0),
    _drapery("settle_speed", "number", 1e-3, "m/s", "the settling ends when the mesh's rms "
             f"speed falls below this (checked every {SETTLE_CHECK:g} s; under the settling's "
             f"viscous damping of {dissipation.SETTLE_VISCOUS:g} 1/s a speed v is an unbalanced "
             f"acceleration of {dissipation.SETTLE_VISCOUS:g} v)",
             "numerical: a stillness tolerance (the case's not-settled check judges it)",
             low=0.0, low_open=True, high=100.0),
    _drapery("settle_weight", "number", 64.0, "", "the mesh settles first under this many "
             "times its weight (damping and speed limit sqrt of it times theirs), then under its "
             "own to drapery.settle_speed: the same shape of wires that barely stretch, sooner "
             "with its wires as many times as strong (no wire may yield or break meanwhile: "
             "settling.heavier_plastic_work)",
             "numerical (doc/drapery.md, \"A heavier mesh first\")", low=1.0, high=1000.0),
    _drapery("duration", "number", 3.0, "s", "simulated time after the release", EXAMPLE,
             low=0.0, low_open=True, high=100.0, quick=0.15),
    _drapery("dt_fraction", "number", 0.5, "", "time step as a fraction of the stable step of "
             "the bonds and of the contact on the lightest node (runner/timestep.py)",
             "doc/impact.md (\"Time step\")", low=0.0, low_open=True, high=1.0),
    _ground("ground_kn", "normal stiffness of the block's contact with the slope (tangential: "
            "a tenth of it)", unit="N/m", low=1.0, high=1e12),
    _ground("ground_mu", "friction of the block on the slope", low=0.0, high=2.0),
    _ground("ground_restitution", "normal coefficient of restitution of the block on the slope",
            low=0.01, high=1.0),
)

# The energy budget: each term from its own mechanism (inputs/drapery.in)
BUDGET = (
    Term("ke_block", ("ke_block",), "kinetic energy of the block", stored=True,
         dissipative=False),
    Term("ke_net", ("ke_net",), "kinetic energy of the mesh", stored=True, dissipative=False),
    Term("pe_block", ("pe_block",), "gravity potential energy of the block", dissipative=False),
    Term("pe_net", ("pe_net",), "gravity potential energy of the mesh", dissipative=False),
    Term("e_elastic", ("e_elastic",), "elastic energy of the bonds", stored=True,
         dissipative=False),
    Term("w_plastic", ("w_plastic",), "plastic work of the wires", mechanism="plasticity"),
    *budget.RUPTURE_DAMPING_CONTACT_TERMS,
    Term("contact_layers", ("w_contact_pair",), "work of the node-node contacts of a compound "
         "mesh's layers", sign=-1, mechanism="friction: between the net's layers"),
) + budget.GROUND_TERMS


# drapery.load debris: the same columns, the load's terms are the heap's, its contacts with the
# mesh and with itself pair contacts (include/debris.in)
DEBRIS_MEANINGS = {
    "ke_block": dict(meaning="kinetic energy of the debris"),
    "pe_block": dict(meaning="gravity potential energy of the debris"),
    "contact_layers": dict(meaning="work of the pair contacts: the debris on the mesh and on "
                           "itself (and a compound mesh's layers)",
                           mechanism="friction: debris on mesh and on itself"),
    "friction_ground": dict(meaning="dissipated by the slope's contacts with the nodes and the "
                            "debris: friction and normal damping",
                            mechanism="friction: net and debris on the slope"),
}


def budget_of(case):
    """The case's budget: BUDGET, its load's terms named for the debris with drapery.load
    debris."""
    if case["drapery.load"] != "debris":
        return BUDGET
    return tuple(dataclasses.replace(t, **DEBRIS_MEANINGS.get(t.name, {})) for t in BUDGET)


class Slope:
    """The slope's frame: up-slope u, outward normal n (world frame, gravity -z)."""

    def __init__(self, angle_deg):
        b = math.radians(angle_deg)
        self.u = np.array([0.0, math.cos(b), math.sin(b)])
        self.n = np.array([0.0, -math.sin(b), math.cos(b)])

    def point(self, across, up, off):
        """World position of (across x, up-slope distance, height off the slope)."""
        return np.outer(across, [1.0, 0.0, 0.0]) + np.outer(up, self.u) + np.outer(off, self.n)

    def coordinates(self, p):
        """(across, up-slope, off the slope) of world positions p (rows)."""
        p = np.atleast_2d(p)
        return p[:, 0], p @ self.u, p @ self.n


def laid_positions(x, y, z, radius, slope, top_height):
    """The flat panel's nodes laid on the slope, and which of them lie on it: the top row
    (largest y) on the anchor line top_height off the slope, the mesh from there straight down
    at HANG_ANGLE to the slope and then on it (lengths along the mesh kept, up to the one kink),
    each layer at its own height above the slope's contact."""
    s = y.max() - y                                   # distance from the top row along the mesh
    delta = math.radians(HANG_ANGLE)
    hang = top_height / math.sin(delta)               # the hanging length
    on_slope = s > hang
    up = -np.where(on_slope, hang * math.cos(delta) + (s - hang), s * math.cos(delta))
    off = np.where(on_slope, 0.0, top_height - s * math.sin(delta))
    off = off + radius.max() + (z - z.min())
    return slope.point(x, up, off), on_slope


def plates(ids, laid, free, bolts, radius):
    """{bolt id: [node ids its plate holds]}: the bolt's node and the nodes of the laid mesh
    (``free``: on the slope, not the top row) within ``radius`` of it."""
    row = {int(atom): k for k, atom in enumerate(ids)}
    out = {}
    for bolt in bolts:
        near = np.linalg.norm(laid - laid[row[bolt]], axis=1) <= radius
        out[bolt] = sorted({bolt} | {int(a) for a in ids[near & free]})
    return out


def debris_heap(case, slope, lift):
    """(centres of the debris spheres (world), the mass of one): drapery.debris_mass in spheres
    of drapery.debris_diameter packed cubically on the slope (DEBRIS_GAP apart), a heap
    drapery.debris_width across centred on drapery.point_x, its lowest row's spheres touching
    the line drapery.release_distance upslope, its first layer ``lift`` off the slope; as many
    rows up the slope as layers deep (the last layer partly filled)."""
    d = case["drapery.debris_diameter"]
    one = ROCK_DENSITY * math.pi / 6.0 * d ** 3
    n = max(int(math.ceil(case["drapery.debris_mass"] / one - 1e-9)), 1)
    pitch = d * (1.0 + DEBRIS_GAP)
    n_across = max(int(case["drapery.debris_width"] / pitch), 1)
    n_rows = max(int(math.ceil(math.sqrt(n / n_across))), 1)
    k = np.arange(n)
    across = case["drapery.point_x"] + (k % n_across - (n_across - 1) / 2.0) * pitch
    up = case["drapery.release_distance"] + 0.5 * d + (k // n_across % n_rows) * pitch
    off = lift + 0.5 * d + (k // (n_across * n_rows)) * pitch
    return slope.point(across, up, off), one


def tilt_data(src, dst, positions, box, extra=(), types=None):
    """A copy of data file src with the atoms at ``positions`` (rows in the Atoms section's
    order), the box ((xlo, xhi), (ylo, yhi), (zlo, zhi)), the Atoms lines ``extra`` (type x y z
    diameter density molecule, without the ID) added after them with the next IDs, and
    ``types`` atom types (None: as src)."""
    with open(src, encoding="utf-8") as handle:
        lines = handle.read().split("\n")
    labels = ("xlo xhi", "ylo yhi", "zlo zhi")
    out, atom, last_id = [], 0, 0
    section = None
    for line in lines:
        words = line.split()
        for axis, label in enumerate(labels):
            if line.rstrip().endswith(label):
                line = f"{box[axis][0]!r} {box[axis][1]!r} {label}"
        if words[1:] == ["atoms"]:
            line = f"{int(words[0]) + len(extra)} atoms"
        elif words[1:] == ["atom", "types"] and types is not None:
            line = f"{types} atom types"
        elif words and words[0].isalpha() and len(words) <= 2 and not line.endswith(labels):
            section = words[0]
        elif section == "Atoms" and len(words) >= 5:
            if atom < len(positions):
                p = positions[atom]
                words[2:5] = (repr(float(p[0])), repr(float(p[1])), repr(float(p[2])))
                line = " ".join(words)
            last_id = max(last_id, int(words[0]))
            atom += 1
            out.append(line)
            if atom == len(positions):
                out.extend(f"{last_id + k + 1} {row}" for k, row in enumerate(extra))
            continue
        out.append(line)
    if atom != len(positions):
        raise RunError(f"drapery: {src}: {atom} atoms in its Atoms section, {len(positions)} "
                       "expected")
    with open(dst, "w", encoding="utf-8") as handle:
        handle.write("\n".join(out))


def grid_points(width, length, spacing):
    """(across, distance down the mesh from the top row) of the grid anchors: rows every
    ``spacing`` below the top row, columns ``spacing`` apart with the centre line between two
    (a block aimed at the centre runs between the bolts, not onto one), each at least half a
    spacing from the mesh's side and foot edges."""
    if spacing <= 0:
        return []
    half = 0.5 * spacing
    n_across = int(math.floor(width / 2 / spacing + 1e-9))
    across = [s * (j + 0.5) * spacing for j in range(n_across) for s in (-1, 1)]
    down = [k * spacing for k in range(1, int(math.floor((length - half) / spacing + 1e-9)) + 1)]
    return [(a, d) for d in down for a in across]


def write_group(path, groups):
    """A deck include defining each group of {name: atom IDs} (a group command adds to a
    group: 200 IDs a line; an empty group as all minus all)."""
    lines = []
    for name, ids in groups.items():
        if not len(ids):
            lines.append(f"group {name} subtract all all")
        for k in range(0, len(ids), 200):
            lines.append(f"group {name} id " + " ".join(str(int(i)) for i in ids[k:k + 200]))
    with open(path, "w", encoding="utf-8") as handle:
        handle.write("\n".join(lines) + "\n")


class Setup:
    """The laid mesh, its anchors, the block and every number the deck needs."""

    def __init__(self, kind, workdir, bending):
        c = kind.case
        self.kind, self.case, self.bending = kind, c, bending
        self.g = c["gravity"]
        self.slope = Slope(c["drapery.slope"])
        self.panel = Panel(c, workdir)
        data = self.panel.data
        x, y, z = data.atom("x"), data.atom("y"), data.atom("z")
        radius = data.atom("diameter") / 2
        self.node_r = float(radius.max())
        self.top_height = c["drapery.top_height"]
        laid, on_slope = laid_positions(x, y, z, radius, self.slope, self.top_height)
        self.foot = float(self.slope.coordinates(laid)[1].min())   # the mesh's lower edge
        self.width = float(x.max() - x.min())
        self.length = float(y.max() - y.min())      # along the mesh, from the top row down
        ids = data.atom_ids
        top = y >= y.max() - 1e-3
        self.top_ids = ids[top]
        # bolts in the slope: the grid points where the laid mesh lies on it (the hanging part
        # near the top row has none)
        self.grid, self.grid_skipped = [], 0
        for across, down in grid_points(self.width, self.length, c["drapery.anchor_spacing"]):
            d = np.hypot(x - (0.5 * (x.max() + x.min()) + across), (y.max() - y) - down)
            d[top] = np.inf
            k = int(np.argmin(d))
            if on_slope[k]:
                self.grid.append(int(ids[k]))
            else:
                self.grid_skipped += 1
        self.grid = sorted(set(self.grid))
        # secured drapery: each bolt's plate holds the laid nodes within its radius
        self.plates = plates(ids, laid, on_slope & ~top, self.grid, c["drapery.plate_radius"])
        # the block: a face on the slope, up-slope of the anchor line, moving down it
        b = math.radians(c["drapery.slope"])
        quat = (math.cos(b / 2), math.sin(b / 2), 0.0, 0.0)
        self.block = Block(workdir, c["drapery.block_mass"], c["drapery.block_side"], quat)
        lift = self.block.extent(-self.slope.n) + GAP
        self.release = self.slope.point([c["drapery.point_x"]],
                                        [c["drapery.release_distance"]], [lift])[0]
        self.velocity = -c["drapery.release_speed"] * self.slope.u
        self.debris, self.debris_one, extra = self.heap(data, x, y)
        # the box: the laid mesh and the load's start, MARGIN beyond; with debris, also as far
        # down the slope as a sphere sliding without friction gets in drapery.duration (atoms
        # must stay in the box; the block is no atom)
        pts = np.vstack([laid, self.release, self.debris.reshape(-1, 3)])
        if len(self.debris):
            t = c["drapery.duration"]
            run_out = c["drapery.release_speed"] * t + 0.5 * self.g * math.sin(b) * t * t
            top = self.slope.coordinates(self.debris)[2].max() + c["drapery.debris_diameter"]
            pts = np.vstack([pts, self.slope.point([c["drapery.point_x"]] * 2,
                                                   [c["drapery.release_distance"] - run_out] * 2,
                                                   [0.0, top])])
        if c["drapery.terrain"]:        # LIGGGHTS keeps a fixed mesh's triangles in the box
            pts = np.vstack([pts, vtu.read_stl(c["drapery.terrain"])[0]])
        box = [(float(pts[:, a].min() - MARGIN), float(pts[:, a].max() + MARGIN)) for a in range(3)]
        self.data_path = os.path.join(workdir, "drapery.data")
        tilt_data(self.panel.data_path, self.data_path, laid, box, extra,
                  DEBRIS_TYPES if len(self.debris) else None)
        self.anchors_path = os.path.join(workdir, "anchors.in")
        write_group(self.anchors_path, {"top_anchors": self.top_ids, "grid_anchors": sorted(
            m for members in self.plates.values() for m in members)})
        variables = dict(kind.key_variables(), bending=repr(bending))
        self.dt = c["drapery.dt_fraction"] * timestep.of_panel(self.panel, variables,
                                                               workdir).loaded
        # the settling's step, with the slope's contact as soft as it is meanwhile
        self.soften = 1.0 if c["drapery.terrain"] else SETTLE_SOFTEN
        soft = dict(variables, kn=repr(c["contact.kn"] / self.soften),
                    ks=repr(c["contact.ks"] / self.soften))
        self.dt_settle = c["drapery.dt_fraction"] * timestep.of_panel(
            self.panel, soft, workdir, name="timestep_settling").loaded
        self.node_masses = self.panel.masses
        self.duration = c["drapery.duration"]
        self.steps = int(math.ceil(self.duration / self.dt))
        self.relax_steps = int(math.ceil(c["drapery.settle_time"] / self.dt_settle))
        self.settle_chunk = min(max(int(math.ceil(SETTLE_CHECK / self.dt_settle)), 1),
                                max(self.relax_steps, 1))
        self.settle_chunks = int(math.ceil(self.relax_steps / self.settle_chunk))
        self.every = max(int(round(c["output.row_time"] / self.dt)), 1)
        self.dump_every = self.every * int(c["output.dump_rows"])

    def heap(self, data, x, y):
        """drapery.load debris: (the spheres' centres, the mass of one, their Atoms lines);
        no spheres for a block. Refuses spheres that pass between the mesh's nodes."""
        c = self.case
        if c["drapery.load"] != "debris":
            return np.zeros((0, 3)), 0.0, []
        d = c["drapery.debris_diameter"]
        row = {int(atom): k for k, atom in enumerate(data.atom_ids)}
        a = [row[int(i)] for i in data.bond("atom1")]
        b = [row[int(i)] for i in data.bond("atom2")]
        spacing = float(np.max(np.hypot(x[a] - x[b], y[a] - y[b])))
        if not d > spacing:
            raise RunError(f"drapery.debris_diameter: {d:g} m is not larger than the mesh's "
                           f"longest node spacing ({spacing:g} m): the spheres would pass "
                           "between the nodes (the wires are not contact surfaces)")
        centres, one = debris_heap(c, self.slope, GAP)
        lines = [f"{DEBRIS_TYPE} {p[0]!r} {p[1]!r} {p[2]!r} {d!r} {ROCK_DENSITY!r} "
                 f"{DEBRIS_MOLECULE + k}" for k, p in enumerate(centres.tolist())]
        return centres, one, lines

    def variables(self):
        c = self.case
        kn = c["drapery.ground_kn"]
        gamma = floor_damping(c["drapery.ground_restitution"], kn, self.block.mass)
        n = self.slope.n
        v = dict(self.kind.key_variables(), **self.block.inertia_variables(),
                 data=os.path.abspath(self.data_path),
                 types=os.path.abspath(self.panel.types_path),
                 anchors=os.path.abspath(self.anchors_path), grid=1 if self.grid else 0,
                 ny=repr(float(n[1])), nz=repr(float(n[2])), node_r=repr(self.node_r),
                 layers=self.panel.layers, bending=repr(self.bending), mass=repr(self.block.mass),
                 block_side=repr(self.block.side), block_cut=repr(self.block.cut),
                 quat=" ".join(map(repr, self.block.quat)),
                 impact_x=repr(float(self.release[0])), impact_y=repr(float(self.release[1])),
                 zb=repr(float(self.release[2])),
                 vx0=repr(float(self.velocity[0])), vy0=repr(float(self.velocity[1])),
                 vz0=repr(float(self.velocity[2])),
                 block_floor=f"floor 0 0 0 0 {n[1]!r} {n[2]!r} kn {kn!r} kt {kn / 10!r} "
                             f"mu {c['drapery.ground_mu']!r} gamma_n {gamma!r}",
                 settle_viscous=repr(dissipation.SETTLE_VISCOUS),
                 settle_speed=repr(c["drapery.settle_speed"]), settle_chunk=self.settle_chunk,
                 settle_chunks=self.settle_chunks, dt_settle=repr(self.dt_settle),
                 settle_weight=repr(c["drapery.settle_weight"]),
                 settle_stages=settle_stages(c["drapery.settle_weight"]),
                 settle_soften=repr(self.soften), dt=repr(self.dt), steps=self.steps,
                 every=self.every,
                 dump_every=self.dump_every, out=".",
                 frame_every=max(int(math.ceil(self.steps / c["output.frames"])), 1))
        if c["drapery.terrain"]:
            v.update(ground="terrain", terrain_file=c["drapery.terrain"])
        if len(self.debris):
            v.update(debris=1, debris_type=DEBRIS_TYPE, atom_types=DEBRIS_TYPES,
                     pair_contacts=1, load="debris", frames_body="none")
        return v


def settle_stages(weight):
    """How many heavier stages the settling has before the one under the mesh's own weight:
    the weight falls SETTLE_WEIGHT_STEP times (at most) from one stage to the next."""
    if weight <= 1.0:
        return 0
    return max(int(math.ceil(math.log(weight) / math.log(SETTLE_WEIGHT_STEP) - 1e-9)), 1)


def read_settling(workdir, case):
    """settling.csv (the deck's): when the settling ended, the mesh's rms speed then, and
    whether that was below drapery.settle_speed (else the settling ran its whole time)."""
    row = read_csv(os.path.join(workdir, "settling.csv"), required=(
        "step", "time", "rms_speed", "still", "first_stage_time", "plastic_work", "broken",
        "heavier_plastic_work", "heavier_broken"))
    first = float(row["first_stage_time"][-1])
    return {"time": float(row["time"][-1]), "steps": int(row["step"][-1]),
            "rms_speed": float(row["rms_speed"][-1]), "still": bool(row["still"][-1]),
            "speed_limit": case["drapery.settle_speed"],
            "viscous": dissipation.SETTLE_VISCOUS, "weight": case["drapery.settle_weight"],
            "first_stage_time": first if first >= 0 else None,
            "plastic_work": float(row["plastic_work"][-1]), "broken": int(row["broken"][-1]),
            # by the end of the last heavier stage (0 at settle_weight 1): the settling's own
            "heavier_plastic_work": float(row["heavier_plastic_work"][-1]),
            "heavier_broken": int(row["heavier_broken"][-1])}


def read_table(workdir):
    """drapery.csv by its column names."""
    return read_deck_table(os.path.join(workdir, TABLE), sorted(
        {col for t in BUDGET for col in t.columns} | {
            "step", "time", "x", "y", "z", "vx", "vy", "vz", "force", "force_mean", "contacts",
            "top_x", "top_y", "top_z", "grid_x", "grid_y", "grid_z", "lift", "gap",
            "j_load_x", "j_load_y", "j_load_z"}))


def load_force(time_, table):
    """The mean force of the net on the load over each row's window (N): the change of the
    contacts' impulse on it (j_load_*) over the row's time; 0 on the first row."""
    j = np.column_stack([table["j_load_x"], table["j_load_y"], table["j_load_z"]])
    force = np.zeros(len(time_))
    force[1:] = np.linalg.norm(np.diff(j, axis=0), axis=1) / np.maximum(np.diff(time_), 1e-300)
    return force


def debris_end(path, slope, foot):
    """Where the debris ended: (facts, verdict) from the last frame of its dump (id x y z vx vy
    vz): the fractions of the spheres below the mesh's foot, more than 2 m off the slope,
    still faster than 0.1 m/s, and the rest (held under or on the mesh)."""
    frame = netoutputs.last_frame(path)
    p = np.column_stack([frame.column(c) for c in ("x", "y", "z")])
    speed = np.linalg.norm(np.column_stack([frame.column(c) for c in ("vx", "vy", "vz")]),
                           axis=1)
    across, up, off = slope.coordinates(p)
    past = up < foot
    left = ~past & (off > 2.0)
    moving = ~past & ~left & (speed > 0.1)
    held = ~past & ~left & ~moving
    share = {name: float(np.mean(mask)) for name, mask in (
        ("past_foot", past), ("left_slope", left), ("moving", moving), ("held", held))}
    verdict = "debris: " + ", ".join(f"{100 * share[k]:.0f} % {text}" for k, text in (
        ("past_foot", "reached the foot"), ("held", "stopped under the mesh"),
        ("moving", "moving"), ("left_slope", "left the slope")) if share[k] > 0)
    return dict(spheres=int(len(p)), fractions=share, largest_off=float(off.max()),
                lowest_up=float(up.min()), mesh_foot=foot), verdict


def anchor_peaks(path, positions, slope, plates=None):
    """{anchor id: peak window-mean force [N], its time step, where it is (across, up-slope,
    off the slope), the nodes it holds} of a fix wirenet/hold ... each table (top_anchors.txt,
    grid_anchors.txt); ``plates`` {anchor id: [node ids]}: an anchor's force is the vector sum
    of its plate's nodes' (each node its own anchor without)."""
    steps, ids, forces = netoutputs.read_support_rows(path)
    column = {int(atom): k for k, atom in enumerate(ids)}
    plates = plates or {atom: [atom] for atom in column}
    out = {}
    for atom, members in plates.items():
        magnitude = np.linalg.norm(forces[:, [column[m] for m in members], :].sum(axis=1), axis=1)
        j = int(np.argmax(magnitude))
        across, up, off = slope.coordinates(positions[int(atom)])
        out[int(atom)] = dict(force=float(magnitude[j]), step=int(steps[j]),
                              across=float(across[0]), up=float(up[0]), off=float(off[0]),
                              nodes=len(members))
    return out


def block_end(slope, table, foot):
    """Where the block ended and what that means: (facts, verdict). 'reached the foot': beyond
    the mesh's lower edge (up-slope coordinate ``foot``); 'left the slope': more than 2 m off it; 'moving': still faster than
    0.1 m/s at the run's end (a longer drapery.duration tells); 'stopped under the mesh'
    otherwise."""
    p = np.column_stack([table["x"], table["y"], table["z"]])
    across, up, off = slope.coordinates(p)
    speed = math.sqrt(table["vx"][-1] ** 2 + table["vy"][-1] ** 2 + table["vz"][-1] ** 2)
    if up[-1] < foot:
        verdict = "reached the foot"
    elif off.max() > 2.0:
        verdict = "left the slope"
    elif speed > 0.1:
        verdict = "moving"
    else:
        verdict = "stopped under the mesh"
    return dict(across=float(across[-1]), up=float(up[-1]), off=float(off[-1]),
                travel=float(up[0] - up[-1]), largest_off=float(off.max()),
                final_speed=speed, mesh_foot=foot), verdict


class Drapery(CaseKind):
    name = "drapery"
    summary = "a mesh hung on a slope, bolted, hit by a block from upslope (doc/drapery.md)"
    deck = "drapery.in"
    keys = KEYS
    takes = ("title", "gravity", "panel.*", "materials.*", "contact.*", "damping.*", "drapery.*",
             "output.row_time", "output.dump_rows", "output.frames", "output.budget_tolerance")
    not_taken = "a drapery is held by its top anchors and grid (drapery.*), not by supports"
    defaults = {"panel.width": 10.0, "panel.height": 10.0, "panel.net": "hex",
                "damping.local": 0.0, "damping.bond": dissipation.STRUCTURAL_ZETA}
    default_sources = {"panel.width": EXAMPLE, "panel.height": EXAMPLE, "panel.net": EXAMPLE,
                       "damping.bond": dissipation.STRUCTURAL_ZETA_SOURCE}
    # --quick: a 2.4 m x 3 m strip with anchors every metre, the block released 0.5 m upslope at
    # 6 m/s (drapery.release_speed), so that it reaches the mesh within the quick 0.15 s
    quick_defaults = {"panel.width": 2.4, "panel.height": 3.0}
    finished_file = "block.csv"

    @classmethod
    def check(cls, case, fail):
        super().check(case, fail)
        if abs(case["drapery.point_x"]) >= case["panel.width"] / 2:
            fail("drapery.point_x", f"{case['drapery.point_x']:g} m is beyond the mesh's side "
                                    f"edges (panel.width {case['panel.width']:g} m)")
        side = case["drapery.block_side"]
        if case["drapery.load"] == "block" and \
                side * math.sqrt(3) >= case["drapery.top_height"] + case["panel.height"]:
            fail("drapery.block_side", f"{side:g} m: the block is larger than the mesh and its "
                                       "gap")
        if not case["gravity"] > 0:
            fail("gravity", "a drapery hangs and its block falls under gravity: gravity > 0")
        if case["drapery.terrain"]:
            cls.check_terrain(case, fail)
        plate, spacing = case["drapery.plate_radius"], case["drapery.anchor_spacing"]
        if plate > 0 and not 2 * plate < spacing:
            fail("drapery.plate_radius", f"{plate:g} m: plates need a grid whose bolts they do not "
                                         f"overlap (drapery.anchor_spacing {spacing:g} m > 2 x "
                                         "plate_radius)")

    @staticmethod
    def check_terrain(case, fail):
        """drapery.terrain: an ASCII STL of triangles with every vertex on or below the slope
        plane (so none of it can cut the mesh laid on the plane), with the debris load; the path
        made absolute."""
        key = "drapery.terrain"
        if case["drapery.load"] != "debris":
            fail(key, "the block touches the analytic slope only: a terrain needs "
                      "drapery.load = 'debris'")
        path = os.path.join(os.path.dirname(case.path or "."), case[key])
        if not os.path.isfile(path):
            fail(key, f"no such file: {path}")
        try:
            points, triangles = vtu.read_stl(path)
        except PostprocessError as exc:
            fail(key, str(exc))
        if not len(triangles):
            fail(key, f"{path}: no triangles (an ASCII STL: facet, outer loop, vertex x y z)")
        off = Slope(case["drapery.slope"]).coordinates(points)[2]
        if off.max() > TERRAIN_TOLERANCE:
            k = int(np.argmax(off))
            fail(key, f"{path}: vertex {tuple(float(v) for v in points[k])} is {off[k]:.4g} m "
                      "above the slope plane (the terrain must lie on or below it)")
        case.values[key] = os.path.abspath(path)

    def weight(self):
        return 20

    def verdict(self, facts):
        # heavier stages that damaged the mesh first: nothing after them is the case's (in the
        # last stage, under its own weight, a yield is the mesh's and the budget's to judge)
        settle = facts.get("settling") or {}
        work, broken = settle.get("heavier_plastic_work", 0.0), settle.get("heavier_broken", 0)
        if broken or work > SETTLE_PLASTIC_WORK:
            return (record.NOT_SETTLED, f"wires yielded or broke while the mesh settled under "
                    f"up to {settle['weight']:g} times its weight (plastic work {work:.3g} J, "
                    f"{broken} broken): the settled mesh is not its own; lower "
                    f"drapery.settle_weight")
        load = facts.get("debris") or facts.get("block") or {}
        # round-off of the contacts' impulse on a load that never touched is far below this
        touched = facts["peak_block_force"] > CONTACT_FRACTION * load.get("mass", 0.0) * \
            facts.get("gravity", 0.0)
        if not touched:
            what = "debris" if facts.get("debris") else "block"
            return (record.NO_CONTACT, f"the {what} never touched the mesh: check "
                                       "drapery.release_distance, drapery.point_x and "
                                       "drapery.duration")
        before = facts.get("before_contact") or {}
        if before.get("bulge", 0.0) > SETTLED_FRACTION * facts["bulge_peak"]:
            speed = (f" (the settling ended after {settle['time']:.3g} s with the mesh at "
                     f"{settle['rms_speed']:.2g} m/s rms)" if settle else "")
            return (record.NOT_SETTLED, f"the mesh was still moving when the load was released"
                    f"{speed}: it rose {before['bulge']:.3g} m off the slope before the load "
                    f"touched it, {before['bulge'] / facts['bulge_peak']:.0%} of the peak bulge "
                    f"({facts['bulge_peak']:.3g} m); lengthen drapery.settle_time")
        return self.budget_verdict(facts)

    def run(self, index, ctx):
        c = self.case
        bending, source = bending_of(c, ctx.study_dir)
        setup = Setup(self, os.path.join(ctx.case_dir, "setup"), bending)
        workdir = os.path.join(ctx.case_dir, "run")
        start = time.time()
        wall = engine.run(INPUTS / "drapery.in", workdir, setup.variables(), np=ctx.ranks,
                          total_steps=setup.steps, label=f"drapery {c['panel.net']}",
                          dt=setup.dt, phase_marker="drapery: block released",
                          before=("settling", setup.settle_chunk * setup.settle_chunks, True))
        table = read_table(workdir)
        facts = self.write_outputs(setup, ctx.case_dir, workdir, table)
        facts.update(panel=c["panel.net"], bending=bending, bending_source=source,
                     slope=c["drapery.slope"], top_height=setup.top_height,
                     block=None if len(setup.debris) else dict(
                         mass=setup.block.mass, side=setup.block.side,
                         release=setup.release.tolist(), velocity=setup.velocity.tolist(),
                         quat=list(setup.block.quat)),
                     gravity=setup.g, damping=c["damping.local"],
                     bond_damping=c["damping.bond"], dissipation=dissipation.model(c),
                     dt=setup.dt, steps=setup.steps, duration=setup.duration,
                     relax_steps=setup.relax_steps,
                     settling=dict(read_settling(workdir, c), dt=setup.dt_settle,
                                   contact_softened=setup.soften),
                     nodes=int(len(setup.node_masses)),
                     grid_anchors=len(setup.grid), grid_points_hanging=setup.grid_skipped,
                     plate_radius=c["drapery.plate_radius"],
                     plate_nodes=[len(m) for m in setup.plates.values()],
                     load=c["drapery.load"], debris=dict(
                         spheres=int(len(setup.debris)), diameter=c["drapery.debris_diameter"],
                         mass=float(len(setup.debris) * setup.debris_one),
                         width=c["drapery.debris_width"],
                         velocity=setup.velocity.tolist()) if len(setup.debris) else None,
                     net_mass=float(np.sum(setup.node_masses)), run_wall_time=wall,
                     post_wall_time=time.time() - start - wall)
        return facts

    def write_outputs(self, setup, case_dir, workdir, t):
        """block.csv, anchors.csv, energy.csv, ruptures.csv and the ParaView series; returns
        the facts for case.json."""
        time_ = t["time"] - t["time"][0]
        debris = len(setup.debris) > 0
        if debris:      # the deck's force columns are the block's: the heap's from its impulse
            t["force_mean"] = t["force"] = load_force(time_, t)
        write_csv(os.path.join(case_dir, "block.csv"), ("time", "x", "y", "z", "vx", "vy", "vz",
                                                        "force"),
                  zip(time_, t["x"], t["y"], t["z"], t["vx"], t["vy"], t["vz"], t["force_mean"]))
        top = np.linalg.norm(np.column_stack([t["top_x"], t["top_y"], t["top_z"]]), axis=1)
        grid = np.linalg.norm(np.column_stack([t["grid_x"], t["grid_y"], t["grid_z"]]), axis=1)
        write_csv(os.path.join(case_dir, "anchors.csv"),
                  ("time", "top_x", "top_y", "top_z", "top_force", "grid_x", "grid_y", "grid_z",
                   "grid_force", "bulge", "gap"),
                  zip(time_, t["top_x"], t["top_y"], t["top_z"], top, t["grid_x"], t["grid_y"],
                      t["grid_z"], grid, t["lift"], t["gap"]))
        terms_of = budget_of(self.case)
        # relative to the largest energy of a term: a load released at rest brings next to none
        terms, total, e0, error = budget.energy_budget(t, terms_of, relative_to_largest=True)
        names = tuple(term.name for term in terms_of)
        write_csv(os.path.join(case_dir, "energy.csv"), ("time",) + names +
                  ("total", "closure_error"), zip(time_, *(terms[k] for k in names), total, error))
        panel = PanelInfo(setup.panel.json_path)
        ruptures = netoutputs.ruptures(os.path.join(workdir, "ruptures.dump"), setup.dt,
                                       panel.families)
        netoutputs.write_ruptures(os.path.join(case_dir, "ruptures.csv"), ruptures)
        netoutputs.write_series(case_dir, workdir, setup.data_path, setup.block.path, setup.dt)
        if self.case["drapery.terrain"]:        # for ParaView, beside the series
            shutil.copyfile(self.case["drapery.terrain"], os.path.join(case_dir, "terrain.stl"))
        # the anchors where they were bolted: the settled mesh (the frame at the release)
        ids, settled = netoutputs.last_nodes(os.path.join(workdir, "frames", "nodes.dump"), 0)
        positions = dict(zip(ids.tolist(), settled))
        anchors = {"top": anchor_peaks(os.path.join(workdir, "top_anchors.txt"), positions,
                                       setup.slope)}
        if setup.grid:
            anchors["grid"] = anchor_peaks(os.path.join(workdir, "grid_anchors.txt"), positions,
                                           setup.slope, setup.plates)
        end, verdict = block_end(setup.slope, t, setup.foot)
        if debris:      # the heap's centroid travelled (block_end); where its spheres ended
            heap, verdict = debris_end(os.path.join(workdir, "debris_end.dump"), setup.slope,
                                       setup.foot)
            end = dict(end, **heap)
        k_lift = int(np.argmax(t["lift"]))
        k_force = int(np.argmax(t["force_mean"]))
        # the mesh's own motion from the release to the load's first touch (the settling's test)
        load_mass = len(setup.debris) * setup.debris_one if debris else setup.block.mass
        touching = np.nonzero(t["force_mean"] > CONTACT_FRACTION * load_mass * setup.g)[0]
        k_touch = int(touching[0]) if len(touching) else len(time_) - 1
        before_contact = dict(time=float(time_[k_touch]) if len(touching) else None,
                              bulge=float(t["lift"][:k_touch + 1].max()),
                              mesh_kinetic_energy=float(t["ke_net"][:k_touch + 1].max()),
                              top_row_force=[float(top[0]), float(top[:k_touch + 1].max())])
        closure = dict(closure_error=float(np.max(np.abs(error))), initial_energy=e0,
                       reference_energy=budget.reference_energy(terms, terms_of, e0),
                       final={k: float(terms[k][-1]) for k in names},
                       final_error=float(error[-1]),
                       mechanisms=budget.mechanisms(terms, terms_of),
                       local_damping_fraction=float(terms["damping"][-1]) / e0)

        def peak(group):
            if not anchors.get(group):
                return None
            atom = max(anchors[group], key=lambda a: anchors[group][a]["force"])
            return dict(anchors[group][atom], id=atom)
        return dict(
            energy=closure, momentum=None,
            anchors={g: {str(a): v for a, v in group.items()} for g, group in anchors.items()},
            top_anchor_peak=peak("top"), grid_anchor_peak=peak("grid"),
            top_row_force_peak=float(top.max()), grid_force_peak=float(grid.max()),
            bulge_peak=float(t["lift"][k_lift]), time_of_bulge_peak=float(time_[k_lift]),
            before_contact=before_contact,
            gap_peak=float(t["gap"].max()),
            peak_block_force=float(t["force_mean"][k_force]),
            time_of_peak_block_force=float(time_[k_force]),
            peak_block_force_raw=float(np.max(t["force"])),
            block_end=end, block_verdict=verdict, broken_bonds=len(ruptures),
            ruptures=ruptures[:200], ruptures_listed=min(len(ruptures), 200),
            first_rupture=netoutputs.rupture_facts(ruptures[0]) if ruptures else None,
            families=sorted(set(panel.families.values())))
