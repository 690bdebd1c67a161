"""Every key of a case file, declared once (runner/params.Key): the keys every kind shares are
here; each kind's own section is declared in its module (runner/kinds/), and a kind may state
its own default for a shared key (CaseKind.defaults). The loader (runner/casefile.py), the
templates of `./wirenet new` and the key tables of doc/case_files.md are all made from this
table; material and contact defaults come from their one source, inputs/include/materials.in
(runner/materials.py), each with the source written beside it there.
"""

import fnmatch

from . import kinds, supports
from .materials import MATERIALS, SOURCES
from .params import ByKey, Key

PAPER = "the paper (README: the study WireNet reproduces)"
GENERATOR = "doc/wirenet-gen.md"


def _material(name, unit, doc, low=0.0, low_open=True, high=None, type_="number", var=None):
    """A key whose default is the materials.in value of the same name (its source beside it)."""
    return Key(f"materials.{name}", type_, MATERIALS[name], unit, doc, SOURCES[name], low=low,
               low_open=low_open, high=high, var=var or name)


def _curve_pairs(text):
    values = [float(v) for v in text.split()]
    return [list(p) for p in zip(values[0::2], values[1::2])]


COMMON = [
    # --- the case ----------------------------------------------------------------------------
    Key("kind", "choice", None, "", "what the case does (required): " + "; ".join(
        f"{k.name}: {k.summary}" for k in kinds.ALL), "", choices=tuple(kinds.NAMES)),
    Key("title", "text", "", "", "one line shown in the report", ""),
    Key("gravity", "number", 9.81, "m/s2", "gravitational acceleration along -z on net and body "
        "(0: none)", "standard gravity (ISO 80000-3)", low=0.0, high=100.0, var="g"),
    # --- panel (wirenet-gen) -----------------------------------------------------------------
    Key("panel.net", "choice", "hex", "", "hex: double-twist hexagonal mesh; square: strand-rope "
        "square mesh; compound: hex over square (wirenet-gen; a fence: the net of every module)",
        PAPER, choices=("hex", "square", "compound")),
    Key("panel.width", "number", 3.0, "m", "panel size along x (edges at +-W/2)", PAPER,
        low=0.1, high=100.0, quick=1.2),
    Key("panel.height", "number", 3.0, "m", "panel size along y (edges at +-H/2)", PAPER,
        low=0.1, high=100.0, quick=1.2),
    Key("panel.placement", "choice", "twist", "", "hex lattice placement: a twist at the panel "
        "centre (twist), a single-wire bond at the centre (wire), started at the lower-left "
        "corner as YADE's hexaNet does (corner), or rows from the lower edge with twist columns "
        "mirror-symmetric about x = 0 (symmetric: hexaNet's isSymmetric=True net)", GENERATOR,
        choices=("twist", "wire", "corner", "symmetric")),
    Key("panel.selvedge", "choice", "loop", "", "edge wire of the hex mesh: a selvedge bond "
        "between consecutive edge nodes (loop), none, the lattice's own bonds along the edges "
        "kept (YADE's hexaNet has no selvedge), or sides: along the two x edges only, parallel "
        "to the twists (a strip cut from a roll, its y edges bare)", GENERATOR,
        choices=("loop", "none", "sides")),
    Key("panel.hex_node_radius", "number", 0.0, "m", "radius of a hex node sphere; 0: the "
        "generator's 5.4 mm (a diameter of 4 wire diameters)", GENERATOR, low=0.0, high=0.05),
    Key("panel.hex_node_mass", "number", 0.0039, "kg", "mass of a hex node", "Thoeni et al. "
        "(2013), the paper's node mass (" + GENERATOR + ")", low=1e-5, high=1.0),
    Key("panel.square_node_radius", "number", 0.0, "m", "radius of a square-mesh node sphere; "
        "0: the rope's radius", GENERATOR, low=0.0, high=0.1),
    Key("panel.rope_mass", "number", 0.4, "kg/m", "strand-rope mass per metre, lumped to the "
        "square mesh's nodes", GENERATOR, low=0.01, high=20.0),
    # the mesh product (wirenet-gen's options; materials.wire_d, selvedge_d and rope_d size the
    # generated net as they size its bonds)
    Key("panel.axis_distance", "number", 0.08, "m", "hex mesh: distance between neighbouring "
        "twist axes, the mesh size D of EN 10223-3 (the 80 of an 8x10 mesh)", "Thoeni et al. "
        "(2013), Pol et al. (2017): the 8x10 mesh (" + GENERATOR + ")", low=0.01, high=0.5),
    Key("panel.twist_length", "number", 0.04, "m", "hex mesh: length of a double twist (along "
        "y)", "Thoeni et al. (2013) (" + GENERATOR + ")", low=0.005, high=0.5),
    Key("panel.rise", "number", 0.04, "m", "hex mesh: y-distance a single-wire bond spans (row "
        "pitch = twist_length + rise; 0.03 makes the opening 100 mm vertex to vertex)",
        "Thoeni et al. (2013) (" + GENERATOR + ")", low=0.005, high=0.5),
    Key("panel.cell", "number", 0.3, "m", "square mesh: rope spacing (cell side)",
        PAPER + ", Table 1 (Bonati et al. 2004)", low=0.02, high=5.0),
    Key("panel.rope_elements", "integer", 3, "", "square mesh: beam elements per cell side",
        "numerical (" + GENERATOR + ")", low=1, high=50),
    # --- supports ----------------------------------------------------------------------------
    *[Key(f"supports.{edge}", "choice", "sliding", "", f"support of the {edge} edge "
          f"({where}): pinned (held in x, y, z), sliding (held across the edge line and in z, "
          "free along the edge), free", PAPER + ", section 3", choices=supports.KINDS)
      for edge, where in zip(supports.EDGES, ("x = -W/2", "x = +W/2", "y = -H/2", "y = +H/2"))],
    # --- pre-load ----------------------------------------------------------------------------
    Key("preload.mode", "choice", "settle", "", "sag: settle under gravity, then move the edges "
        "in the plane until the centre hangs preload.sag below its generated height (punch "
        "only); settle: settle under gravity (damped) only; none: start from the generated flat "
        "panel", PAPER + ", section 3 (punch: 1 cm pre-load)",
        choices=("sag", "settle", "none"), var="preload_mode"),
    # --- materials (materials.in) ------------------------------------------------------------
    _material("wire_d", "m", "diameter of the mesh wire (DT and SW bonds)", high=0.01),
    _material("selvedge_d", "m", "diameter of the selvedge wire", high=0.02),
    Key("materials.curve", "pairs", _curve_pairs(MATERIALS["curve"]), "-, Pa",
        "single-wire stress-strain table [[strain, stress], ...] (the (0, 0) point implied); the "
        "double twist is derived from it", SOURCES["curve"], var="curve"),
    _material("lambda_eps", "", "double-twist rule: strain factor (Bertrand et al. 2008)",
              high=1.0),
    _material("lambda_k", "", "double-twist rule: stiffness factor (Bertrand et al. 2008)",
              high=1.0),
    _material("wire_nu", "", "Poisson's ratio of the wire (double-twist rule)", low_open=False,
              high=0.5),
    _material("slack_u", "", "random initial slack of the wire bonds, lambda_u: a bond's slack "
              "is lambda_u l0 r, r triangular on [0, 1] (0: none, as the paper)", low_open=False,
              high=0.5),
    _material("slack_f", "", "slack: the first loading branch's force fraction lambda_f (1: a "
              "straight line to the law's first point)", high=1.0),
    Key("materials.slack_seed", "integer", int(MATERIALS["slack_seed"]), "", "slack: random "
        "seed (the draw depends on the seed and the two node ids only: the same net on any number "
        "of ranks); -1: every bond the largest slack", SOURCES["slack_seed"], low=-1,
        high=2 ** 31 - 1, var="slack_seed"),
    _material("rope_d", "m", "strand-rope diameter (beam bonds)", high=0.1),
    _material("rope_E", "Pa", "Young's modulus of the rope's equivalent cylinder", low=1e8,
              high=3e11),
    _material("rope_nu", "", "Poisson's ratio of the rope", low_open=False, high=0.5),
    Key("materials.bending", "bending", "calibrated", "", "bending fraction of the rope beams "
        "(fraction of E I): a number, or 'calibrated': the fraction the study's bending cases "
        f"fitted when they ran, else the paper's {MATERIALS['bending']:g}",
        PAPER + ", section 4", low=0.0, high=1.0),
    Key("materials.shear", "choice", MATERIALS["shear"], "", "rope beam shear model: eb "
        "(Euler-Bernoulli) or pb (parallel bond)", SOURCES["shear"], choices=("eb", "pb"),
        var="shear"),
    Key("materials.rope_strength", "bool", False, "", "ropes break (parallel-bond criterion "
        "with rope_sigma_t, rope_tau_c); false: unbreakable, as in the paper",
        "doc/bond_wirenet.md"),
    _material("rope_sigma_t", "Pa", "rope tensile strength (on the beam's gross area)",
              high=5e9),
    _material("rope_tau_c", "Pa", "rope shear strength", high=5e9),
    # --- contact -----------------------------------------------------------------------------
    Key("contact.kn", "number", MATERIALS["kn"], "N/m", "normal contact stiffness, net-body "
        "and node-node", SOURCES["kn"], low=1.0, high=1e12, var="kn"),
    Key("contact.ks", "number", MATERIALS["ks"], "N/m", "tangential contact stiffness",
        SOURCES["ks"], low=0.0, low_open=True, high=1e12, var="ks"),
    Key("contact.mu", "number", MATERIALS["mu"], "", "friction coefficient", SOURCES["mu"],
        low=0.0, high=2.0, var="mu"),
    Key("contact.zeta", "number", 0.0, "", "viscous normal contact damping, fraction of critical "
        "on the lightest node (punch: kills the ringing of a node riding on the platter)",
        "doc/punch.md", low=0.0, high=1.0),
    # --- damping -----------------------------------------------------------------------------
    Key("damping.local", "number", 0.0, "", "Cundall local damping factor on the net nodes "
        "(fence: on every atom during the impact)", "doc/impact.md, doc/punch.md, doc/fence.md",
        low=0.0, high=0.999, var="alpha"),
    Key("damping.bond", "number", 0.0, "", "viscous bond damping, fraction of each bond's "
        "critical damping (momentum-conserving)", "doc/impact.md, doc/fence.md", low=0.0,
        high=1.0, var="bond_zeta"),
    # --- outputs -----------------------------------------------------------------------------
    Key("output.row_travel", "number", 0.002, "m", "the load's travel between rows of the "
        "test's table (punch.csv, tensile.csv: force, reactions, energies)",
        "WireNet (runner/kinds/)", low=1e-7, high=1.0),
    Key("output.dump_rows", "integer", 10, "", "rows between dumps of the bond tensions (zone "
        "forces, Figure 4's frame)", "WireNet (runner/kinds/)", low=1, high=100000),
    Key("output.frames", "integer", 40, "", "ParaView frames over the load (CASE.pvd; each "
        "frame of a 3 m compound panel is about 0.5 MB)", "WireNet (inputs/include/frames.in)",
        low=1, high=400),
    Key("output.budget_tolerance", "number", 0.005, "", "largest departure of the energy budget "
        "(relative to the initial energy) and of the momentum balance (relative to the block's "
        "momentum) for a dynamic case to end ok; beyond it the case ends 'budget-open'",
        "issue #45 (0.5 %)", low=1e-6, high=0.5, quick=0.02),
    Key("output.zones.name", "text", "centre", "", "zone name (the first zone writes "
        "zone_forces.csv, the others zone_forces_NAME.csv)", "", per_item=True),
    Key("output.zones.centre", "vector2", [0.0, 0.0], "m", "zone centre, offset from the panel "
        "centre", PAPER, per_item=True),
    Key("output.zones.radius", "number", 1.0, "m", "zone radius (bond midpoints within it)",
        PAPER, low=0.0, low_open=True, high=100.0, per_item=True),
]

ENSEMBLES = "doc/ensembles.md"


def _ensemble(name, type_, default, unit, doc, source=ENSEMBLES, **kw):
    return Key(f"ensemble.{name}", type_, default, unit, doc, source, **kw)


# [ensemble]: what runner/ensemble.py makes of one case file: random members, a sweep or a
# one-at-a-time sensitivity study (each member a plain case of its own; doc/ensembles.md). A
# kind takes them with "ensemble.*" in its `takes`.
ENSEMBLE = [
    _ensemble("members", "integer", 1, "", "random members of the case (1: the case alone); "
              "with ensemble.sweep, members per swept value", low=1, high=10000),
    _ensemble("seed", "integer", 1, "", "seed of the draws: member k draws from the streams "
              "(seed, k, variable), so members added later leave the first ones as they were",
              low=0, high=2 ** 31 - 1),
    _ensemble("slack_seeds", "bool", False, "", "each member draws its own "
              "materials.slack_seed (the wires' random slack; needs materials.slack_u > 0)"),
    _ensemble("point_radius", "number", 0.0, "m", "impact point uniform over a disc of this "
              "radius around the case's (impact.point in the panel's plane; fence.impact_point "
              "in the net's plane); 0: the case's point", low=0.0, high=100.0),
    _ensemble("speed", "choice", "fixed", "", "block speed: fixed (the case's); normal (the "
              "case's speed times a factor of mean 1 and coefficient of variation "
              "ensemble.speed_cov, truncated at 3 standard deviations); uniform (on "
              "ensemble.speed_range); the direction stays the case's",
              choices=("fixed", "normal", "uniform")),
    _ensemble("speed_cov", "number", 0.05, "", "coefficient of variation of the block speed "
              "(ensemble.speed = normal)", low=0.0, high=0.3),
    _ensemble("speed_range", "vector2", [0.0, 0.0], "m/s", "[low, high] of the block speed "
              "(ensemble.speed = uniform)"),
    _ensemble("orientation", "choice", "fixed", "", "block orientation: fixed (the case's), or "
              "random: a uniformly random rotation of the case's orientation (impact.orientation, "
              "fence.block_orientation)", choices=("fixed", "random")),
    _ensemble("material_cov", "number", 0.0, "", "coefficient of variation of two factors "
              "(normal, mean 1, truncated at 3 standard deviations): one on the wires' stresses "
              "(materials.curve), one on the ropes' (materials.rope_E, rope_sigma_t, rope_tau_c "
              "and a fence's fence.support_curve); 0: none", low=0.0, high=0.3),
    _ensemble("friction_cov", "number", 0.0, "", "coefficient of variation of a factor on "
              "contact.mu (normal, mean 1, truncated at 3 standard deviations); 0: none",
              low=0.0, high=0.3),
    _ensemble("sweep", "text", "", "", "a sweep: the key whose values the members take, e.g. "
              "'fence.speed' (a key of [[impact]]: every entry); '': none"),
    _ensemble("values", "values", [], "", "the sweep's values, each checked as the swept key "
              "takes it, e.g. [20.0, 22.5, 25.0, 27.5, 30.0]"),
    _ensemble("sensitivity", "keys", [], "", "one-at-a-time sensitivity: keys (numbers, or "
              "[[strain, stress]] tables whose stresses are scaled), each times every factor of "
              "ensemble.factors alone, against the base case (member 0); 'unsourced': every "
              "number of the case without a read source (runner/schema.py unsourced)"),
    _ensemble("factors", "list-number", [0.8, 1.2], "", "the factors of the sensitivity study",
              "issue #45 (0.8x and 1.2x)", low=0.0, low_open=True, high=100.0),
]

KEYS = COMMON + [key for kind in kinds.ALL for key in kind.keys] + ENSEMBLE
BY_PATH = {k.path: k for k in KEYS}
if len(BY_PATH) != len(KEYS):
    raise RuntimeError("schema: a key is declared twice")
SECTIONS = sorted({".".join(k.path.split(".")[:n]) for k in KEYS
                   for n in range(1, k.path.count(".") + 1)})
# sections that are lists of tables ([[impact]], [[output.zones]]) or may be
LIST_SECTIONS = tuple(sorted({k.section for k in KEYS if k.per_item}))


def applies(key, kind):
    """Whether a case of this kind (a name) takes the key."""
    if key.path == "kind":
        return True
    return any(fnmatch.fnmatchcase(key.path, pattern) for pattern in kinds.BY_NAME[kind].takes)


def takers(key):
    """The kinds that take the key."""
    return [k.name for k in kinds.ALL if applies(key, k.name)]


# a source's first word says how far it goes (inputs/include/materials.in's header)
UNVERIFIED, NONE, NUMERICAL = "unverified:", "none:", "numerical:"
# numbers that act only when another key is set, their source mattering only then (a key
# itself: only when it is not 0)
ONLY_WITH = {"materials.rope_sigma_t": "materials.rope_strength",
             "materials.rope_tau_c": "materials.rope_strength",
             "drapery.plate_radius": "drapery.plate_radius"}


def source_of(key, kind):
    """The source of the key's default in a case of this kind: the kind's own where it states
    its own default (CaseKind.default_sources), else the key's."""
    return kinds.BY_NAME[kind].default_sources.get(key.path, key.source)


def unsourced(case):
    """The numbers of a case with no source read (an 'unverified:' or 'none:' source, or none
    at all), and the values they take in it: [{key, value, default, source}] (case.json's
    `unsourced`; the report lists them with their sensitivity, doc/fence.md "Sources").
    Numerical settings ('numerical:', results do not depend on them) are not listed."""
    out = []
    for key in KEYS:
        if key.per_item or not applies(key, case.kind) or key.path not in case.values:
            continue
        if key.path in ONLY_WITH and not case.values.get(ONLY_WITH[key.path]):
            continue
        source = source_of(key, case.kind) or ""
        if source.startswith(NUMERICAL) or not (
                source.startswith((UNVERIFIED, NONE)) or source.startswith("no source")):
            continue
        default = default_of(key, case.kind)
        out.append({"key": key.path, "value": case.values[key.path],
                    "default": default if isinstance(default, (int, float, str, list)) else None,
                    "source": source})
    return out


def default_of(key, kind, quick=False):
    """The key's default for a case of this kind (a value, ByKey or Derived), --quick's where it
    has one. A kind's own default stands in --quick too (a tensile strip is smaller than the
    quick panel), unless the kind states its own --quick default as well."""
    k = kinds.BY_NAME[kind]
    if quick and key.path in k.quick_defaults:
        return k.quick_defaults[key.path]
    if key.path in k.defaults:
        return k.defaults[key.path]
    if quick and key.quick is not None:
        return key.quick
    return key.default


def has_quick(key, kind):
    """Whether --quick changes the key's default for a case of this kind."""
    return key.path in kinds.BY_NAME[kind].quick_defaults or (
        key.quick is not None and key.path not in kinds.BY_NAME[kind].defaults)


def defaults_by_kind(key):
    """{kind: default} of the kinds that take the key (the key tables)."""
    return {k.name: default_of(key, k.name) for k in kinds.ALL if applies(key, k.name)}


__all__ = ["KEYS", "BY_PATH", "SECTIONS", "LIST_SECTIONS", "PAPER", "ByKey", "applies", "takers",
           "default_of", "has_quick", "defaults_by_kind", "source_of", "unsourced"]
