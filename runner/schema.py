"""Every key of a case file, declared once: type, default, unit, range, what it means and where
the default comes from. The loader (runner/casefile.py), the templates of `./wirenet new` and
doc/case_files.md are all made from this table; materials and contact defaults come from their
one source, inputs/include/materials.in.
"""

from dataclasses import dataclass

from postprocess.model import MATERIALS, PAPER_BENDING

from . import fence, impact, punch, supports

KINDS = ("punch", "impact", "cantilever", "fence")
NETS = ("hex", "square", "compound")
PAPER = "the paper (README: the study WireNet reproduces)"
MATERIALS_SOURCE = "inputs/include/materials.in (doc/bond_wirenet.md)"


# Keys that act only after a punch's pre-load, or on a rope that does not fail during it (the
# runner checks that none broke: runner/punch.check_preload_bonds): two punch cases that differ
# in nothing else share their pre-load (punch.preload_from).
PRELOAD_FREE = ("title", "materials.rope_strength", "materials.rope_sigma_t",
                "materials.rope_tau_c", "punch.travel", "punch.quasi_static_check",
                "punch.check_travel", "punch.speed_max", "punch.equilibrium_target",
                "punch.stop_drop", "punch.preload_from", "output.*")


@dataclass(frozen=True)
class Key:
    """One case-file key. ``kind`` limits it to one kind of case; ``default`` may be a dict per
    kind; None = derived (``derived`` says from what)."""
    path: str                   # dotted: section.name
    type: str                   # number, integer, bool, text, choice, vector2, vector3, quat,
    #                             pairs, list-int, file
    default: object
    unit: str
    doc: str
    source: str
    choices: tuple = ()
    low: float = None           # inclusive bounds for numbers
    high: float = None
    low_open: bool = False      # low excluded
    kind: str = None            # punch / impact / cantilever only
    derived: str = ""           # what a None default means
    quick: object = None        # the --quick value where it differs
    per_item: bool = False      # a key of each [[impact]] / [[output.zones]] entry

    @property
    def section(self):
        return self.path.rsplit(".", 1)[0] if "." in self.path else ""

    @property
    def name(self):
        return self.path.rsplit(".", 1)[-1]

    def default_for(self, kind, quick=False):
        if quick and self.quick is not None:
            return self.quick
        return self.default.get(kind) if isinstance(self.default, dict) else self.default


def _material(name, unit, doc, low=0.0, low_open=True, type_="number"):
    return Key(f"materials.{name}", type_, MATERIALS[name], unit, doc, MATERIALS_SOURCE,
               low=low, low_open=low_open)


KEYS = [
    # --- the case ----------------------------------------------------------------------------
    Key("kind", "choice", None, "", "what the case does: a quasi-static punch, a block impact, "
        "the cantilever check of the beam law, or a fence impact (EAD 340059; required)", "", choices=KINDS),
    Key("title", "text", "", "", "one line shown in the report", ""),
    Key("gravity", "number", 9.81, "m/s2", "gravitational acceleration along -z on net and block "
        "(0: none)", "standard gravity", low=0.0),
    # --- panel -------------------------------------------------------------------------------
    Key("panel.net", "choice", {"punch": "hex", "impact": "hex", "cantilever": "hex",
                                "fence": "compound"}, "", "hex: double-twist hexagonal mesh; "
        "square: strand-rope square mesh; compound: hex over square (wirenet-gen; a fence: the "
        "net of every module)", PAPER, choices=NETS),
    Key("panel.width", "number", 3.0, "m", "panel size along x (edges at +-W/2)", PAPER,
        low=0.0, low_open=True, quick=1.2),
    Key("panel.height", "number", 3.0, "m", "panel size along y (edges at +-H/2)", PAPER,
        low=0.0, low_open=True, quick=1.2),
    Key("panel.placement", "choice", "twist", "", "hex lattice placement: a twist at the panel "
        "centre (twist), a single-wire bond at the centre (wire), or started at the lower-left "
        "corner as YADE's hexaNet does (corner); doc/wirenet-gen.md",
        "doc/wirenet-gen.md", choices=("twist", "wire", "corner")),
    Key("panel.selvedge", "choice", "loop", "", "edge wire of the hex mesh: a selvedge bond "
        "(type 3) between consecutive edge nodes (loop), or none, the lattice's own bonds along "
        "the edges kept (YADE's hexaNet has no selvedge)", "doc/wirenet-gen.md",
        choices=("loop", "none")),
    Key("panel.hex_node_radius", "number", 0.0, "m", "radius of a hex node sphere; 0: the "
        "generator's 5.4 mm (a diameter of 4 wire diameters)", "doc/wirenet-gen.md", low=0.0),
    Key("panel.hex_node_mass", "number", 0.0039, "kg", "mass of a hex node", "doc/wirenet-gen.md "
        "(the paper's node mass)", low=0.0, low_open=True),
    Key("panel.square_node_radius", "number", 0.0, "m", "radius of a square-mesh node sphere; "
        "0: the rope's radius", "doc/wirenet-gen.md", low=0.0),
    Key("panel.rope_mass", "number", 0.4, "kg/m", "strand-rope mass per metre, lumped to the "
        "square mesh's nodes", "doc/wirenet-gen.md", low=0.0, low_open=True),
    # --- supports ----------------------------------------------------------------------------
    *[Key(f"supports.{edge}", "choice", "sliding", "", f"support of the {edge} edge "
          f"({where}): pinned (held in x, y, z), sliding (held across the edge line and in z, "
          "free along the edge), free", PAPER + ", section 3", choices=supports.KINDS)
      for edge, where in zip(supports.EDGES, ("x = -W/2", "x = +W/2", "y = -H/2", "y = +H/2"))],
    # --- pre-load ----------------------------------------------------------------------------
    Key("preload.mode", "choice", {"punch": "sag", "impact": "settle"}, "",
        "sag: settle under gravity, then move the edges in the plane until the centre hangs "
        "preload.sag below its generated height (punch only); settle: settle under gravity "
        "(damped) only; none: start from the generated flat panel",
        PAPER + ", section 3 (punch: 1 cm pre-load)", choices=("sag", "settle", "none")),
    Key("preload.sag", "number", 0.01, "m", "target sag of the panel centre for mode sag",
        PAPER, low=0.0, low_open=True, kind="punch"),
    Key("preload.settle_time", "number", 0.1, "s", "settling time under gravity before the "
        "block is released (impact)", "doc/impact.md", low=0.0, kind="impact", quick=0.01),
    # --- materials (materials.in) ------------------------------------------------------------
    _material("wire_d", "m", "diameter of the mesh wire (DT and SW bonds)"),
    _material("selvedge_d", "m", "diameter of the selvedge wire"),
    Key("materials.curve", "pairs", [list(p) for p in zip(
        *[iter(float(v) for v in MATERIALS["curve"].split())] * 2)], "-, Pa",
        "single-wire stress-strain table [[strain, stress], ...] (the (0, 0) point implied); "
        "the double twist is derived from it", "Thoeni et al. (2013); " + MATERIALS_SOURCE),
    _material("lambda_eps", "", "double-twist rule: strain factor (Bertrand et al. 2008)"),
    _material("lambda_k", "", "double-twist rule: stiffness factor (Bertrand et al. 2008)"),
    _material("wire_nu", "", "Poisson's ratio of the wire (double-twist rule)", low_open=False),
    _material("slack_u", "", "random initial slack of the wire bonds, lambda_u: a bond's slack "
              "is lambda_u l0 r, r triangular on [0, 1] (0: none, as the paper)", low_open=False),
    Key("materials.slack_f", "number", MATERIALS["slack_f"], "", "slack: the first loading "
        "branch's force fraction lambda_f (1: a straight line to the law's first point)",
        "Thoeni et al. (2013); doc/bond_wirenet.md", low=0.0, low_open=True, high=1.0),
    Key("materials.slack_seed", "integer", int(MATERIALS["slack_seed"]), "", "slack: random "
        "seed (the draw depends on the seed and the two node ids only: the same net on any number "
        "of ranks); -1: every bond the largest slack", MATERIALS_SOURCE, low=-1),
    _material("rope_d", "m", "strand-rope diameter (beam bonds)"),
    _material("rope_E", "Pa", "Young's modulus of the rope's equivalent cylinder"),
    _material("rope_nu", "", "Poisson's ratio of the rope", low_open=False),
    Key("materials.bending", "bending", "calibrated", "", "bending fraction of the rope beams "
        "(fraction of E I): a number, or 'calibrated': the fraction the study's calibration "
        f"cases found when they ran, else the paper's {PAPER_BENDING:g}",
        PAPER + ", section 4 (calibration)", low=0.0),
    Key("materials.shear", "choice", MATERIALS["shear"], "", "rope beam shear model: eb "
        "(Euler-Bernoulli) or pb (parallel bond)", MATERIALS_SOURCE, choices=("eb", "pb")),
    Key("materials.rope_strength", "bool", False, "", "ropes break (parallel-bond criterion "
        "with rope_sigma_t, rope_tau_c); false: unbreakable, as in the paper",
        "doc/bond_wirenet.md"),
    _material("rope_sigma_t", "Pa", "rope tensile strength (EN 12385-4 MBF of a 10 mm rope on "
              "the beam's area; approximate)"),
    _material("rope_tau_c", "Pa", "rope shear strength"),
    # --- contact -----------------------------------------------------------------------------
    Key("contact.kn", "number", {"punch": MATERIALS["kn"], "impact": MATERIALS["kn"],
                                 "cantilever": MATERIALS["kn"], "fence": fence.CONTACT["kn"]},
        "N/m", "normal contact stiffness, net-body and node-node (fence: a penalty 100x softer "
        "than the paper's, overlap under a wire's breaking force ~0.3 mm; doc/fence.md)",
        MATERIALS_SOURCE + "; fence: doc/fence.md", low=0.0, low_open=True),
    Key("contact.ks", "number", {"punch": MATERIALS["ks"], "impact": MATERIALS["ks"],
                                 "cantilever": MATERIALS["ks"], "fence": fence.CONTACT["ks"]},
        "N/m", "tangential contact stiffness", MATERIALS_SOURCE + "; fence: doc/fence.md",
        low=0.0, low_open=True),
    Key("contact.mu", "number", MATERIALS["mu"], "", "friction coefficient", MATERIALS_SOURCE,
        low=0.0),
    Key("contact.zeta", "number", {"punch": 0.3, "impact": 0.0, "fence": 0.0}, "", "viscous normal contact "
        "damping, fraction of critical on the lightest node (punch: kills the ringing of a node "
        "riding on the platter; impact: none, the paper's)", "doc/punch.md", low=0.0),
    # --- damping -----------------------------------------------------------------------------
    Key("damping.local", "number", {"punch": 0.7, "impact": 0.5, "fence": fence.ALPHA}, "",
        "Cundall local damping factor on the net nodes (fence: on every atom during the impact)",
        "punch: PFC's static default; impact: " + PAPER + "; fence: doc/fence.md", low=0.0,
        high=0.999),
    Key("damping.bond", "number", {"punch": 0.0, "impact": 0.0, "cantilever": 0.0,
                                   "fence": fence.BOND_ZETA}, "", "viscous bond damping, "
        "fraction of each bond's critical damping (momentum-conserving; doc/impact.md uses 0.05 "
        "with local 0)", "doc/impact.md, doc/fence.md", low=0.0, high=9.99),
    # --- punch -------------------------------------------------------------------------------
    Key("punch.platter", "choice", "spheroid", "", "platter shape: spheroid (the paper's "
        "semi-spheroid), cone (flat tip), sphere", PAPER, choices=("spheroid", "cone", "sphere"),
        kind="punch"),
    Key("punch.radius", "number", None, "m", "platter radius", PAPER, low=0.0, low_open=True,
        kind="punch", derived="spheroid 0.5, cone 0.34, sphere 0.5"),
    Key("punch.height", "number", None, "m", "platter height (spheroid: semi-axis along z; "
        "cone: apex to base; sphere: the radius)", PAPER, low=0.0, low_open=True, kind="punch",
        derived="spheroid 0.15, cone 0.78, sphere = radius"),
    Key("punch.tip_radius", "number", None, "m", "cone only: radius of the flat tip",
        "doc/punch.md", low=0.0, kind="punch", derived="0.02"),
    Key("punch.position", "vector2", [0.0, 0.0], "m", "platter axis, offset from the panel "
        "centre in x, y", PAPER, kind="punch"),
    Key("punch.speed", "number", 0.01, "m/s", "platter speed along -z", PAPER, low=0.0,
        low_open=True, kind="punch"),
    Key("punch.travel", "number", 0.5, "m", "platter travel after first touch", PAPER, low=0.0,
        low_open=True, kind="punch", derived="quick: hex/compound 0.03, square 0.1"),
    Key("punch.mass_scaling", "bool", True, "", "scale node masses to reach steps_per_metre "
        "at the stated speed (rate-independent laws: doc/punch.md); false: true masses, half "
        "the stable step", "doc/punch.md", kind="punch"),
    Key("punch.steps_per_metre", "number", None, "1/m", "time steps per metre of travel (with "
        "mass scaling)", "doc/punch.md (quasi-static evidence)", low=0.0, low_open=True,
        kind="punch", derived="hex/compound 4e6, square 3.125e5; quick 1e6"),
    Key("punch.quasi_static_check", "bool", True, "", "run the same case 4x slower beside it "
        "and compare the force curves (the quasi-static proof)", "doc/punch.md", kind="punch"),
    Key("punch.check_travel", "number", None, "", "fraction of the travel the slower twin runs",
        "doc/punch.md", low=0.0, low_open=True, high=1.0, kind="punch",
        derived="square 0.5, hex/compound 0.25"),
    Key("punch.speed_max", "number", None, "", "largest factor on punch.speed: past the twin's "
        "travel the speed follows the panel's equilibrium, rising while the edge reactions "
        "balance the platter force and weight within punch.equilibrium_target (1: constant "
        "speed; analytic body only)", "doc/punch.md (equilibrium-controlled loading)", low=1.0,
        high=100.0, kind="punch", derived="hex/compound 4, square 1; mesh body 1"),
    Key("punch.equilibrium_target", "number", 0.004, "", "the gap |R - W - F| / R (edge "
        "reactions R, weight W, platter force F) the speed control aims at",
        "doc/punch.md (equilibrium-controlled loading)", low=0.0, low_open=True, high=0.01,
        kind="punch"),
    Key("punch.stop_drop", "number", 0.0, "", "end the punch at the first row, after a bond "
        "has broken, whose platter force is below this fraction of the peak so far (the net "
        "has failed: a load test's post-peak drop); 0: run the whole travel",
        "doc/punch.md (breakable ropes)", low=0.0, high=0.999, kind="punch"),
    Key("punch.preload_from", "text", "", "", "another punch case of the same study whose "
        "pre-loaded panel this case starts from instead of pre-loading its own (the same panel, "
        "materials, pre-load and time step; only " + ", ".join(PRELOAD_FREE) + " may differ); "
        "run alone, the case pre-loads its own", "doc/punch.md (a shared pre-load)",
        kind="punch"),
    Key("punch.body", "choice", "analytic", "", "analytic: exact body (fix wirenet/body); mesh: "
        "the generator's STL (facet traps of doc/punch.md)", "doc/fix_wirenet_body.md",
        choices=("analytic", "mesh"), kind="punch"),
    # --- impact (a table, or [[impact]] entries: successive impacts on the same net) ----------
    Key("impact.block", "choice", "truncated-cube", "", "the block: the generator's truncated "
        "cube, or a closed STL surface (impact.stl, body mesh)", PAPER,
        choices=("truncated-cube", "stl"), kind="impact", per_item=True),
    Key("impact.stl", "file", "", "", "block STL file (relative to the case file), for block "
        "'stl'; mass properties of the uniform solid", "", kind="impact", per_item=True),
    Key("impact.side", "number", 0.45, "m", "truncated cube: side", PAPER, low=0.0,
        low_open=True, kind="impact", per_item=True),
    Key("impact.mass", "number", 44.5, "kg", "block mass", PAPER, low=0.0, low_open=True,
        kind="impact", per_item=True),
    Key("impact.velocity", "vector3", [0.0, 0.0, -10.0], "m/s", "block velocity at release "
        "(the panel lies in the x-y plane; -z is into it)", PAPER, kind="impact", per_item=True),
    Key("impact.point", "vector2", [0.0, 0.0], "m", "where the block starts above the panel: "
        "offset from the panel centre in x, y", PAPER, kind="impact", per_item=True),
    Key("impact.orientation", "quat", [1.0, 0.0, 0.0, 0.0], "", "block orientation, unit "
        "quaternion [w, x, y, z] (1, 0, 0, 0: faces normal to the axes)", "", kind="impact",
        per_item=True),
    Key("impact.duration", "number", 1.0, "s", "simulated time after release", PAPER, low=0.0,
        low_open=True, kind="impact", quick=0.06, per_item=True),
    Key("impact.dt_fraction", "number", impact.DT_SAFETY, "", "time step as a fraction of the "
        "stable step with the true masses (punch.stable_dt: the bonds and the contact on the "
        "lightest node, neighbours in antiphase)", "doc/impact.md (\"Time step\")",
        low=0.0, low_open=True, high=1.0, kind="impact", per_item=True),
    Key("impact.body", "choice", "analytic", "", "analytic: exact truncated cube (fix "
        "wirenet/body); mesh: the STL moved by fix wirenet/rigidmesh",
        "doc/fix_wirenet_body.md", choices=("analytic", "mesh"), kind="impact", per_item=True),
    # --- fence -------------------------------------------------------------------------------
    Key("fence.modules", "integer", 3, "", "functional modules (one net panel between two "
        "posts each)", "EAD 340059-00-0106 (three modules)", low=1, kind="fence"),
    Key("fence.spacing", "number", 10.0, "m", "post spacing", "EAD 340059-00-0106 (typical)",
        low=0.0, low_open=True, kind="fence", quick=4.0),
    Key("fence.height", "number", 5.0, "m", "post height (nominal height of the fence)",
        "issue #18", low=0.0, low_open=True, kind="fence", quick=2.0),
    Key("fence.post_tilt", "number", 10.0, "deg", "posts, net and support ropes lean downslope "
        "about the ground line (a vertical hinged post is an inverted pendulum)",
        "doc/wirenet-gen.md", low=0.0, high=40.0, kind="fence"),
    Key("fence.head_guides", "choice", "clamp", "", "top rope at the post heads: clamp (fixed "
        "to the head) or slide (through a guide; the posts sway)", "doc/wirenet-gen.md",
        choices=("clamp", "slide"), kind="fence"),
    Key("fence.block_mass", "number", fence.BLOCK["mass"], "kg", "block mass (1600 kg at 25 "
        "m/s: 500 kJ)", "EAD 340059-00-0106", low=0.0, low_open=True, kind="fence", quick=100.0),
    Key("fence.block_side", "number", fence.BLOCK["side"], "m", "side of the truncated cube "
        "(corner cut side/3; 0.865 m: 1600 kg at 2600 kg/m3)", "EAD 340059-00-0106", low=0.0,
        low_open=True, kind="fence", quick=0.35),
    Key("fence.speed", "number", fence.BLOCK["speed"], "m/s", "block speed against the fence "
        "normal, at the middle of the middle module", "EAD 340059-00-0106 (>= 25 m/s)",
        low=0.0, low_open=True, kind="fence", quick=5.0),
    Key("fence.duration", "number", 0.8, "s", "simulated time after release", "doc/fence.md",
        low=0.0, low_open=True, kind="fence", quick=0.15),
    Key("fence.settle_time", "number", 1.0, "s", "settling under gravity (damped) before the "
        "block is released", "doc/fence.md", low=0.0, low_open=True, kind="fence", quick=0.3),
    Key("fence.rest_time", "number", fence.REST_TIME, "s", "after each impact, the block and "
        "the fence come to rest with the settling's damping (the guideline measures the "
        "residual height then): at most this long, until their kinetic energy is below "
        f"{fence.REST_KE:g} of the block's or the middle module's support ropes have moved less "
        f"than {fence.REST_STILL * 1e3:g} mm in {fence.REST_WINDOW:g} s; 0: no rest, the residual "
        "height at the impact's end",
        "doc/fence.md", low=0.0, kind="fence", quick=0.1),
    Key("fence.impacts", "integer", 1, "", "1, or 2: the guideline's SEL test, a second block "
        "(the same one) on the unrepaired fence after the first block is taken away and the "
        "fence has come to rest", "EAD 340059-00-0106 (SEL)", low=1, high=2, kind="fence"),
    Key("fence.dt", "number", None, "s", "time step", "doc/fence.md", low=0.0, low_open=True,
        kind="fence", derived="half the smaller of the bond style's stable estimate and the "
        "block contact's limit"),
    Key("fence.row_time", "number", 2e-3, "s", "time between rows of fence.csv and the CSVs "
        "made from it", "WireNet (runner/fence.py)", low=0.0, low_open=True, kind="fence"),
    # --- cantilever --------------------------------------------------------------------------
    Key("cantilever.elements", "list-int", [5, 11, 21], "", "beam discretisations compared with "
        "the closed form", PAPER + ", Fig. 1", kind="cantilever"),
    # --- outputs -----------------------------------------------------------------------------
    Key("output.row_travel", "number", punch.ROW_TRAVEL, "m", "platter travel between rows "
        "of punch.csv (force, reactions, energies)", "WireNet (runner/punch.py)", low=0.0,
        low_open=True, kind="punch"),
    Key("output.row_time", "number", impact.OUTPUT_INTERVAL, "s", "time between rows of "
        "impact.csv, block.csv, energy.csv and momentum.csv", "WireNet (runner/impact.py)",
        low=0.0, low_open=True, kind="impact"),
    Key("output.dump_rows", "integer", {"punch": punch.DUMP_ROWS, "impact": impact.DUMP_ROWS},
        "", "rows between dumps of the bond tensions (zone forces, Figure 4's frame)",
        "WireNet (runner/punch.py, impact.py)", low=1),
    Key("output.frames", "integer", {"punch": punch.FRAMES, "impact": impact.FRAMES,
                                     "fence": impact.FRAMES}, "",
        "ParaView frames over the load (CASE.pvd)", "WireNet (inputs/include/frames.in)", low=1),
    Key("output.zones.name", "text", "centre", "", "zone name (the first zone writes "
        "zone_forces.csv, the others zone_forces_NAME.csv)", "", per_item=True),
    Key("output.zones.centre", "vector2", [0.0, 0.0], "m", "zone centre, offset from the panel "
        "centre", PAPER, per_item=True),
    Key("output.zones.radius", "number", 1.0, "m", "zone radius (bond midpoints within it)",
        PAPER, low=0.0, low_open=True, per_item=True),
]

BY_PATH = {k.path: k for k in KEYS}
# keys of a panel case that a fence has no use for: its modules' size is fence.spacing x
# fence.height, its supports are its anchors and posts, it always settles first (fence.settle_time),
# its outputs are per component
NOT_FOR_FENCE = ("panel.width", "panel.height", "supports.", "preload.", "output.zones",
                 "output.dump_rows")


def applies(key, kind):
    """Whether a case of this kind takes the key."""
    if key.kind not in (None, kind):
        return False
    return kind != "fence" or not any(key.path == k or key.path.startswith(k)
                                      for k in NOT_FOR_FENCE)
SECTIONS = sorted({".".join(k.path.split(".")[:n]) for k in KEYS
                   for n in range(1, k.path.count(".") + 1)})
# sections that are lists of tables ([[impact]], [[output.zones]]) or may be
LIST_SECTIONS = ("impact", "output.zones")
