"""Fence impact cases in the form of EAD 340059-00-0106 (doc/fence.md): a `wirenet-gen fence`
(net modules between hinged posts, support and upslope ropes with brakes, the net on shackles)
settles under its weight, then the guideline's block (the truncated cube, density about
2600 kg/m3) hits the middle of the middle module against the fence normal.
Deck: inputs/fence.in (include/fence_impact.in). Results, each from its own mechanism:

- braking distance (the block's largest travel along the normal after its first touch) and the
  residual height of the middle module at rest (the least vertical distance between the top
  and bottom support ropes there), against the nominal height;
- the window-mean reaction of every anchor and post base as a time series and its peak;
- the peak tension of every rope family, the elongation of every brake;
- the energy budget (BUDGET) and its closure; the bonds' share split by component (net, ropes,
  brakes, posts: elastic, plastic, released, bond damping);
- the momentum balance (supports, ground, gravity, damping impulses);
- ruptures by family.
"""

import functools
import hashlib
import json
import math
import os
import re
import shutil
import time

import numpy as np

from postprocess import dumps, output
from postprocess.csvio import read_csv, read_deck_table, write_csv
from postprocess.datafile import read_data
from postprocess.errors import PostprocessError
from postprocess.meta import read_json

from .. import INPUTS, budget, dissipation, engine, netoutputs, timestep
from ..budget import Term
from ..errors import RunError
from postprocess import record

from ..block import Block, compose, first_touch, floor_damping
from ..generator import generate
from ..materials import MATERIALS, SOURCES, bending_of, rope_strength_keyword
from ..panel import changed_options, generator_options, node_masses
from ..params import Key
from .base import CaseKind

EAD = "EAD 340059-00-0106"
# After an impact the block and the fence come to rest with local damping (SETTLE_ALPHA), with a
# viscous part (-C m v on every node): local damping acts on the unbalanced force only and cannot
# stop parts that move steadily under balanced forces (upslope ropes creeping while their brakes
# slide at the plateau kept 110 J in the compound fence for the whole 1 s). 10 1/s damps the
# fence's slow sway (periods about 1 s) at about 0.8 of critical
REST_VISCOUS = 10.0
REST_KE = 1e-5           # the rest ends below this fraction of the block's energy (5 J at 500 kJ)
# The settling before the impact ends once the fence is still: its kinetic energy below SETTLE_KE
# (1 J: a 5 t fence moving at 2 cm/s), the residual height's probe still (REST_STILL over
# REST_WINDOW) and its weight carried by the supports and the ground within SETTLE_CARRY, or at
# fence.settle_time (then the case is not-settled). The weight test is the one that says the
# state is static: a damping that acts as a force to ground (local damping, against sign v) can
# hold a fence that creeps down its ropes still by the first two (doc/fence.md, "Settling")
SETTLE_KE = 1.0          # J
SETTLE_CARRY = 0.01      # 1 % of the weight: the sum of the reactions, read as window means
SETTLE_STILL = "fence settle: still"   # the deck's line when the settling ended on its tests
SETTLE_NOT_STILL = "fence settle: not still:"   # ... and when it did not: the last window's tests
# The settling runs in pieces of SETTLE_PIECE, each a LIGGGHTS `run` followed by the deck's
# stillness test: about 80 ms of set-up per piece on the default fence (40 s in pieces of one
# output row, 2 ms), 8 s in pieces of 10 ms
SETTLE_PIECE = 0.01      # s
# neighbour bins: 0.1 m (each build checks the layer exclusion of every candidate in the 27 bins
# around a node before its distance: 12.5 % faster than 0.2 m on the default fence,
# docs/PERFORMANCE.md 2026-12-07), coarser where the fence's box would need more than
# MAX_BINS of them (a bin head per bin on every rank, cleared at every build)
BIN_SIZE = 0.1           # m
MAX_BINS = 2.0e7
# ... or once the middle module's support ropes are still: the deck's probe of the residual
# height has stayed within REST_STILL over REST_WINDOW (the height is read to the centimetre)
REST_STILL = 1e-3        # m
REST_WINDOW = 0.1        # s
GAP = 0.005              # block to the foremost net node at release [m]
TABLE = "fence.csv"      # the deck's table: names in its header (include/fence_impact.in)
IMPACT_ENDED = "impact: ended"   # the deck's line when the impact ends before fence.duration
SETTLED = "fence settled:"       # the deck's line at the settling's end: reactions and weight


def _fence(name, type_, default, unit, doc, source, **kw):
    return Key(f"fence.{name}", type_, default, unit, doc, source, **kw)


def _part(name, type_, unit, doc, **kw):
    """A fence part's number: its default and source from inputs/include/materials.in."""
    default = MATERIALS[name]
    if type_ == "pairs":
        values = [float(v) for v in default.split()]
        default = [list(p) for p in zip(values[0::2], values[1::2])]
    kw.setdefault("var", name)
    return _fence(name, type_, default, unit, doc, SOURCES[name], **kw)


# case key -> wirenet-gen fence option (passed when the value differs from the key's default:
# runner/panel.py changed_options)
FENCE_OPTIONS = (("fence.support_rope_d", "--support-rope-diameter"),
                 ("fence.upslope_rope_d", "--upslope-rope-diameter"),
                 ("fence.anchor_distance", "--anchor-distance"),
                 ("fence.bottom_anchor_distance", "--bottom-anchor-distance"),
                 ("fence.upslope_distance", "--upslope-distance"),
                 ("fence.upslope_sag", "--upslope-sag"),
                 ("fence.brakes", "--brakes"), ("fence.upslope_brakes", "--upslope-brakes"),
                 ("fence.post_area", "--post-area"), ("fence.post_iy", "--post-iy"),
                 ("fence.post_iz", "--post-iz"), ("fence.post_j", "--post-j"),
                 ("fence.post_width", "--post-node-diameter"))


KEYS = (
    _fence("modules", "integer", 3, "", "functional modules (one net panel between two posts "
           "each)", EAD + " (three modules)", low=1, high=20),
    _fence("spacing", "number", 10.0, "m", "post spacing", EAD + " (typical)", low=1.0,
           high=30.0, quick=4.0),
    _fence("height", "number", 5.0, "m", "post height (nominal height of the fence)",
           "issue #18", low=0.5, high=15.0, quick=2.0),
    _fence("post_tilt", "number", 10.0, "deg", "posts, net and support ropes lean downslope "
           "about the ground line (a vertical hinged post is an inverted pendulum)",
           "doc/wirenet-gen.md", low=0.0, high=40.0),
    _fence("head_guides", "choice", "clamp", "", "top rope at the post heads: clamp (fixed to "
           "the head) or slide (through a guide; the posts sway)", "doc/wirenet-gen.md",
           choices=("clamp", "slide")),
    _fence("block_mass", "number", 1600.0, "kg", "block mass (1600 kg at 25 m/s: 500 kJ)", EAD,
           low=1.0, high=1e5, quick=100.0, var="mass"),
    _fence("block_side", "number", 0.865, "m", "side of the truncated cube (corner cut side/3; "
           "0.865 m: 1600 kg at 2600 kg/m3)", EAD, low=0.05, high=5.0, quick=0.35, var="block_side"),
    _fence("speed", "number", 25.0, "m/s", "block speed against the fence normal, at the middle "
           "of the middle module", EAD + " (>= 25 m/s)", low=0.1, high=100.0, quick=5.0,
           var="speed"),
    _fence("impact_point", "vector2", [0.0, 0.0], "m", "aim point: offset from the middle of the "
           "middle module along the fence (x) and up the net's plane", EAD + " (the middle of "
           "the middle module)"),
    _fence("block_orientation", "quat", [1.0, 0.0, 0.0, 0.0], "", "the block's turn in its own "
           "frame from face-on (a face towards the fence), unit quaternion [w, x, y, z]",
           "doc/fence.md (face-on)"),
    _fence("duration", "number", 0.8, "s", "longest simulated time after release (the impact "
           "ends earlier: fence.impact_end)", "doc/fence.md", low=0.0, low_open=True, high=20.0,
           quick=0.15),
    _fence("impact_end", "number", 0.1, "s", "the impact ends this long after the block's largest "
           "travel along the normal, once the block no longer moves into the fence (the peak "
           "forces are past; the rest brings block and fence to rest: fence.rest_time), or this "
           "long after the block last touched the fence (it went through, over or under it, or "
           "bounced off); 0: the whole fence.duration", "doc/fence.md (\"The impact's end\")", low=0.0, high=20.0,
           var="impact_end"),
    _fence("settle_time", "number", 3.0, "s", "settling under gravity before the block is "
           "released, at most: it ends once the fence is still (kinetic energy below "
           f"{SETTLE_KE:g} J, the residual height's probe and the post heads' mean y each within "
           f"{REST_STILL * 1e3:g} mm over {REST_WINDOW:g} s, the supports and the ground carrying its weight to "
           f"{SETTLE_CARRY:.0%}); a fence not still by then is not-settled. The full square "
           "fence is still after 1.7 s, the default compound one after 2.1 s, the quick compound "
           "one after 1.2 s", "doc/fence.md (\"Settling\")",
           low=0.0, low_open=True, high=20.0, quick=2.5),
    _fence("rest_time", "number", 1.0, "s", "after each impact, the block and the fence come "
           "to rest with local damping 0.7 and a viscous part (the guideline measures the "
           f"residual height then): at most this long, until their kinetic energy is below {REST_KE:g} of the "
           f"block's or the middle module's support ropes have moved less than "
           f"{REST_STILL * 1e3:g} mm in {REST_WINDOW:g} s; 0: no rest, the residual height at "
           "the impact's end", "doc/fence.md", low=0.0, high=20.0, quick=0.1),
    _fence("impacts", "integer", 1, "", "1, or 2: the guideline's SEL test, a second block (the "
           "same one) on the unrepaired fence after the first block is taken away and the fence "
           "has come to rest", EAD + " (SEL)", low=1, high=2, var="impacts"),
    _fence("settle_mass_factor", "integer", 4, "", "while the fence settles, the hex mesh's "
           "light nodes carry this many times their mass (their weight unchanged): a static state "
           "does not depend on the masses, and the step they set grows by its square root; a "
           "power of two (the masses come back exactly); 1: none. Best: the largest power of two "
           "at which they no longer set the step, (step of the others / step of the light "
           "nodes)^2 = (2.55e-5 / 1.15e-5)^2 = 4.9 on the default compound fence; beyond it the "
           "extra mass only slows the net's slow motions (16: the compound fence not still "
           "within 6 s; 4: still after 2.1 s)", "doc/fence.md (\"Settling\")",
           low=1, high=1024),
    _fence("settle_kinetic", "bool", True, "", "while the fence settles, kinetic damping: every "
           "velocity is set to zero at each peak of the fence's kinetic energy (fix "
           "wirenet/kinetic; dynamic relaxation, Barnes 1999). It applies no force, so the state "
           "it stops in is the structure's own: the supports carry the whole weight",
           "doc/fix_wirenet_kinetic.md; doc/fence.md (\"Settling\")", var="settle_kinetic"),
    _fence("settle_local", "number", 0.0, "", "local (Cundall) damping while the fence settles, "
           "with or instead of the kinetic damping; 0: none. Against sign(v) it acts as a dry "
           "friction to ground: 0.7 (PFC's static default) holds the default compound fence "
           "creeping down its ropes with 13 % of its weight on the damping (measured, doc/fence.md "
           "\"Settling\"), and the weight test then fails", "doc/fence.md (\"Settling\")",
           low=0.0, high=0.99, var="settle_alpha"),
    _fence("settle_viscous", "number", 0.0, "1/s", "viscous damping while the fence settles, "
           "-C m v on every node, with the kinetic damping: it damps the slow swings between the "
           "kinetic damping's stops and holds no static load (C m v vanishes as the fence comes "
           "to rest, unlike local damping)", "doc/fence.md (\"Settling\")", low=0.0, high=1000.0,
           var="settle_viscous"),
    _fence("dt_fraction", "number", 0.5, "", "time step as a fraction of the stable step of the "
           "bonds and the block's contact on the lightest node (compute wirenet/timestep), while "
           "settling and during the impact. 0.8 runs 1.4x faster and is stable (the estimate is "
           "15 % below the assembled net's highest frequency), but moves the default compound "
           "fence's post-base peak at the support ropes' rupture by 20 % (0.7 % between two runs "
           "at 0.5 that settled differently; 0.3 gives -6 %: that peak is not converged)",
           "docs/PERFORMANCE.md (2026-11-28, the fence's time step)", low=0.0, low_open=True, high=1.0),
    _fence("settle_dt_fraction", "number", 0.0, "", "the settling's time step as a fraction of "
           "its stable step (the bonds and contacts with the light nodes settle_mass_factor times "
           "heavier); 0: fence.dt_fraction. No block touches the settling, which ends on its "
           "stillness tests: 0.8 settles the quick fences 1.5-2.2x sooner (impact outputs within "
           "1.4 %), the default compound fence 1.15x (its failing post-base peak, an event, 13 % "
           "lower)", "docs/PERFORMANCE.md (2026-11-29, fifth: the settling's step)",
           low=0.0, high=1.0),
    _fence("dt", "number", 0.0, "s", "time step; 0: fence.dt_fraction of the stable step of the "
           "bonds and the block's contact on the lightest node (compute wirenet/timestep)", "doc/fence.md",
           low=0.0, high=1e-3),
    _fence("row_time", "number", 2e-3, "s", "time between rows of fence.csv and the CSVs made "
           "from it", "WireNet (runner/kinds/fence.py)", low=1e-6, high=1.0),
    # the fence's parts (inputs/include/materials.in: the values and their sources)
    _part("support_curve", "pairs", "-, Pa", "stress-strain table of the support and upslope "
          "ropes on the gross area pi d^2/4: [[strain, stress], ...], rupture at the last point"),
    _part("brake_force", "number", "N", "brake activation (plateau) force", low=1.0, high=1e7),
    _part("brake_stroke", "number", "m", "brake stroke (it ruptures beyond)", low=0.0,
          low_open=True, high=20.0),
    _part("brake_k", "number", "N/m", "brake stiffness before it slides", low=1.0, high=1e12),
    _part("shackle_kn", "number", "N/m", "shackle holding stiffness (fix wirenet/shackle)",
          low=1.0, high=1e12),
    _part("shackle_kt", "number", "N/m", "shackle stick stiffness along the rope", low=1.0,
          high=1e12),
    _part("shackle_mu", "number", "", "friction of a shackle sliding on its rope", low=0.0,
          high=2.0),
    _part("post_E", "number", "Pa", "Young's modulus of the post steel", low=1e8, high=1e12),
    # the fence's make-up (wirenet-gen fence's options, passed when they differ from these
    # defaults, which are the generator's: doc/wirenet-gen.md, "fence"; generators/src/Fence.h)
    _fence("support_rope_d", "number", 0.022, "m", "diameter of the top and bottom support "
           "ropes", "unverified: 22 mm ropes of 500 kJ kits (manufacturers' kit sheets, not "
           "read)", low=0.004, high=0.1),
    _fence("upslope_rope_d", "number", 0.022, "m", "diameter of the upslope ropes (quick: "
           "12 mm, scaled with its 2 m posts: a hinged post stands only while its lean outweighs "
           "the pull of its upslope rope's sag, which grows with the rope's weight, and 22 mm "
           "ropes pull the quick fence's posts over)", "unverified: as fence.support_rope_d; "
           "quick: doc/fence.md (\"Why a hinged post stands\")", low=0.004, high=0.1, quick=0.012),
    _fence("anchor_distance", "number", 5.0, "m", "the top rope's lateral anchors beyond the "
           "end posts, on the ground", "none: a design choice of this test fence", low=0.5,
           high=50.0),
    _fence("bottom_anchor_distance", "number", 2.5, "m", "the bottom rope's lateral anchors "
           "beyond the end posts", "none: a design choice of this test fence", low=0.5,
           high=50.0),
    _fence("upslope_distance", "number", 10.0, "m", "upslope anchors behind the posts (quick: "
           "4 m, twice its post height as 10 m is twice the full fence's)", "none: a design "
           "choice of this test fence; quick: doc/fence.md (\"Why a hinged post stands\")",
           low=1.0, high=50.0, quick=4.0),
    _fence("upslope_sag", "number", 0.1, "", "installed sag of the upslope ropes at mid-chord, "
           "a fraction of the chord (0: built straight). A hinged post stands while the lean of "
           "its vertical loads outweighs its upslope rope's pull, w L^2 / (8 f) for a sag f: a "
           "rope built straight pulls the head upslope until it has come close enough to give "
           "the rope its sag, and the posts of both 22 mm fences then lean over upslope",
           "none: a design choice; doc/fence.md (\"Why a hinged post stands\")", low=0.0,
           high=0.5),
    _fence("brakes", "integer", 1, "", "brakes in each support rope next to each lateral "
           "anchor (0: none)", "none: a design choice of this test fence", low=0, high=10),
    _fence("upslope_brakes", "integer", 1, "", "brakes in each upslope rope next to its anchor "
           "(0: none)", "none: a design choice of this test fence", low=0, high=10),
    _fence("post_area", "number", 0.005383, "m2", "post section area", "EN 10365:2017 (HEA "
           "200)", low=1e-5, high=0.1),
    _fence("post_iy", "number", 3.692e-05, "m4", "post second moment about the strong axis "
           "(along the fence)", "EN 10365:2017 (HEA 200)", low=1e-9, high=0.01),
    _fence("post_iz", "number", 1.336e-05, "m4", "post second moment about the weak axis "
           "(upslope)", "EN 10365:2017 (HEA 200)", low=1e-9, high=0.01),
    _fence("post_j", "number", 2.098e-07, "m4", "post torsion constant", "EN 10365:2017 (HEA "
           "200)", low=1e-10, high=0.01),
    _fence("post_width", "number", 0.2, "m", "post width, the contact sphere of the post's "
           "nodes (the flange width)", "EN 10365:2017 (HEA 200: b = 200 mm)", low=0.02,
           high=2.0),
    # the block on the ground (not the settling's: var None, passed by Setup.variables)
    _part("ground_kn", "number", "N/m", "normal stiffness of the block's contact with the "
          "ground (tangential: a tenth of it)", low=1.0, high=1e12, var=None),
    _part("ground_mu", "number", "", "friction of the block on the ground", low=0.0, high=2.0,
          var=None),
    _part("ground_restitution", "number", "", "normal coefficient of restitution of the block "
          "on the ground (a viscous normal damping of the floor contact gives it)", low=0.0,
          low_open=True, high=1.0, var=None),
)

# The energy budget of a fence impact: each term from its own mechanism (include/fence_impact.in)
BUDGET = (
    Term("ke_block", ("ke_block",), "kinetic energy of the block", stored=True, dissipative=False),
    Term("ke_net", ("ke_net",), "kinetic energy of the fence", stored=True, dissipative=False),
    Term("pe_block", ("pe_block",), "gravity potential energy of the block", dissipative=False),
    Term("pe_net", ("pe_net",), "gravity potential energy of the fence", dissipative=False),
    Term("e_elastic", ("e_elastic",), "elastic energy of the bonds (wires, brakes, ropes, posts)",
         stored=True, dissipative=False),
    Term("e_shackle", ("e_shackle",), "spring energy of the shackles", stored=True,
         dissipative=False),
    Term("w_plastic", ("w_plastic",), "plastic work of wires, ropes and brakes (fix "
         "wirenet/bonds; split by component in components.csv)", mechanism="plasticity"),
    *budget.RUPTURE_DAMPING_CONTACT_TERMS,
    Term("contact_layers", ("w_contact_pair",), "work of the node-node contacts (friction; "
         "their springs' energy is below 1e-3 J a contact)", sign=-1,
         mechanism="friction: between the net's layers"),
    Term("friction", ("w_friction",), "shackle friction (fix wirenet/shackle)",
         mechanism="friction: shackles on ropes"),
    Term("shackle_damping", ("w_shackle_damping",), "shackle damping",
         mechanism="friction: shackles on ropes"),
) + budget.GROUND_TERMS
# the fence's parts by family (wirenet-gen fence, doc/file_formats.md) and its components for the
# energy per component (every other bond type is the net's)
PART_FAMILIES = ("support_rope", "brake", "upslope", "upslope_brake", "post")
COMPONENT_FAMILIES = {"ropes": ("support_rope", "upslope"), "brakes": ("brake", "upslope_brake"),
                      "posts": ("post",)}
# the columns of bond_types.txt (fix ave/time mode vector of fix wirenet/bonds' array): per bond
# type, its bonds' elastic energy, energy released at ruptures, plastic work, bond damping (J)
BOND_TALLIES = ("elastic", "released", "plastic", "bond_damping")


def part_types(meta):
    """{family: bond types} of the fence's parts, from the generator's JSON."""
    types = {f: [] for f in PART_FAMILIES}
    for t, name in meta["bond_types"].items():
        if name in types:
            types[name].append(int(t))
    return {f: tuple(sorted(v)) for f, v in types.items()}


def component_types(meta, ntypes):
    """{component: bond types} of a fence with ntypes bond types."""
    parts_of = part_types(meta)
    parts = {c: tuple(t for f in families for t in parts_of[f])
             for c, families in COMPONENT_FAMILIES.items()}
    taken = {t for types in parts.values() for t in types}
    return {"net": tuple(t for t in range(1, ntypes + 1) if t not in taken), **parts}


SETTLED_DIR = ".settled"    # DIR/.settled/KEY/settled.restart: settled fences of the study
# deck variables the settling never reads (the block, the impact's end and damping): fences that
# differ only in them share one settled state (an ensemble of block speeds, masses or sizes)
IMPACT_ONLY = ("mass", "block_side", "speed", "impact_end", "impacts", "alpha")


def keep_settled(restart, cached, settled):
    """Keep a run's settled fence for the study's other cases, and its settled facts (or None)
    beside it in settled.json, the facts first: each is written whole, then renamed, so a case
    that finds the restart file finds its facts too."""
    if not os.path.isfile(restart):
        return
    os.makedirs(os.path.dirname(cached), exist_ok=True)
    if settled is not None:
        output.write_json(settled_facts_path(cached), settled)
    with output.atomic_path(cached) as tmp:
        shutil.copyfile(restart, tmp)


def shared_settled_dir():
    """Where still settled fences are kept for every study of this user (WIRENET_CACHE, default
    $XDG_CACHE_HOME/wirenet or ~/.cache/wirenet; 'off': nowhere), or None."""
    root = os.environ.get("WIRENET_CACHE", "")
    if root == "off":
        return None
    if not root:
        root = os.path.join(os.environ.get("XDG_CACHE_HOME") or
                            os.path.join(os.path.expanduser("~"), ".cache"), "wirenet")
    return os.path.join(os.path.abspath(root), "settled")


def settled_path(study_dir, setup, still, shared=False):
    """Where a settled fence is kept: a still one under the key without the settling's cap, any
    other under the key with it; in the study's folder, or (``shared``) in the user's store."""
    root = shared_settled_dir() if shared else os.path.join(study_dir, SETTLED_DIR)
    return os.path.join(root, setup.settled_key(capped=not still), "settled.restart")


# The user's store keeps the settled fences used last within this size (about 50 default
# compound fences of 40 MB; a rebuilt binary or an edited deck makes new keys, so old entries
# are never asked for again): a settled state is a cache, settled again when missing.
STORE_LIMIT = 2 * 1024 ** 3     # bytes


def find_settled(study_dir, setup):
    """The kept settled fence a case can start from, or None: the study's own (a still one
    first), then a still one of the user's store (the same key: the same files, decks, binary
    and settling variables, whichever study settled it), marked as used now."""
    places = [(False, True), (False, False)] + ([(True, True)] if shared_settled_dir() else [])
    for shared, still in places:
        path = settled_path(study_dir, setup, still, shared)
        if os.path.isfile(path):
            if shared:
                _mark_used(os.path.dirname(path))
            return path
    return None


def _mark_used(entry):
    try:
        os.utime(entry)
    except OSError:
        pass


def prune_store(root, limit=None):
    """Remove the store's least recently used settled fences (by their folder's time, set when
    kept or used) beyond ``limit`` bytes, the latest always kept; returns how many went. It never
    fails: what it cannot read or remove (another case keeping or pruning meanwhile) stays."""
    limit = STORE_LIMIT if limit is None else limit
    entries = []
    try:
        for entry in os.scandir(root):
            try:
                if entry.is_dir(follow_symlinks=False):
                    size = sum(f.stat().st_size for f in os.scandir(entry.path) if f.is_file())
                    entries.append((entry.stat().st_mtime, size, entry.path))
            except OSError:
                continue
    except OSError:
        return 0
    entries.sort(reverse=True)
    total, removed = 0, 0
    for k, (_, size, path) in enumerate(entries):
        total += size
        if k > 0 and total > limit:
            shutil.rmtree(path, ignore_errors=True)
            removed += 1
    return removed


def share_settled(cached, setup, settled):
    """Copy a still settled fence of the study to the user's store (a cache: a failure to write
    it is said and passed over)."""
    if not shared_settled_dir() or not (settled and settled.get("still")):
        return
    target = settled_path(None, setup, True, shared=True)
    if os.path.isfile(target):
        return
    try:
        keep_settled(cached, target, settled)
    except (OSError, PostprocessError) as exc:   # (the atomic writes raise the latter)
        reason = exc.strerror if isinstance(exc, OSError) and exc.strerror else exc
        print(f"wirenet: note: the settled fence not kept in the store ({reason}); set "
              "WIRENET_CACHE to another folder or 'off'")
        return
    removed = prune_store(shared_settled_dir())
    if removed:
        print(f"wirenet: note: {removed} settled fence(s) used least recently removed from the "
              f"store {shared_settled_dir()} (it keeps {STORE_LIMIT / 1024 ** 3:g} GB)")


def settled_facts_path(cached):
    return os.path.join(os.path.dirname(cached), "settled.json")


_NUMBER = r"(\S+)"
SETTLED_LINE = re.compile(
    rf"^{SETTLED} reactions {_NUMBER} {_NUMBER} {_NUMBER} N and the ground {_NUMBER} N against "
    rf"the weight {_NUMBER} N, kinetic energy {_NUMBER} J")


def read_settled(line):
    """The deck's line at the settling's end (SETTLED, inputs/fence.in): the supports' and the
    ground's vertical reactions against the weight. What they do not carry is held by the
    settling's damping or still accelerating, not carried by the structure: the settled state
    is that far from an equilibrium (doc/fence.md, "Settling")."""
    found = SETTLED_LINE.match(line)
    try:
        rx, ry, rz, ground, weight, ke = (float(v) for v in found.groups())
    except (AttributeError, ValueError):
        raise RunError(f"the deck's settling line is not what the runner reads: {line.strip()}")
    return {"reactions": [rx, ry, rz], "ground": ground, "weight": weight, "kinetic_energy": ke,
            "weight_carried": (rz + ground) / weight if weight > 0 else None}


NOT_STILL_LINE = re.compile(
    rf"^{SETTLE_NOT_STILL} kinetic energy {_NUMBER} J \(limit {_NUMBER}\), the probe moved "
    rf"{_NUMBER} m and the post heads {_NUMBER} m \(limit {_NUMBER}\), the weight carried to "
    rf"{_NUMBER} \(limit {_NUMBER}\) over the last {_NUMBER} steps of {_NUMBER} s")


def read_not_still(line):
    """The deck's line when the settling ran out of time (SETTLE_NOT_STILL, inputs/fence.in):
    the stillness tests of the last window it judged, each beside its limit."""
    found = NOT_STILL_LINE.match(line)
    try:
        ke, ke_max, probe, heads, moved_max, carry, carry_max, steps, dt = \
            (float(v) for v in found.groups())
    except (AttributeError, ValueError):
        raise RunError(f"the deck's settling line is not what the runner reads: {line.strip()}")
    return {"window": steps * dt, "kinetic_energy": [ke, ke_max], "probe_moved": [probe, moved_max],
            "heads_moved": [heads, moved_max], "weight_missed": [carry, carry_max]}


def failed_stillness(window):
    """What kept the fence from being still, in words: the tests of read_not_still's window that
    failed (a limit of 0 is a test switched off)."""
    words = {"kinetic_energy": "its kinetic energy was {:.3g} J (limit {:g} J)",
             "probe_moved": "the residual height's probe moved {:.3g} m (limit {:g} m)",
             "heads_moved": "the post heads' mean y moved {:.3g} m (limit {:g} m)",
             "weight_missed": "the supports and the ground missed {:.2%} of its weight (limit {:.0%})"}
    failed = [text.format(*window[key]) for key, text in words.items()
              if window[key][1] > 0 and not window[key][0] < window[key][1]]
    return "; ".join(failed) or "no test failed in the last window (it was too short)"


def middle_module(meta):
    """Where the residual height is measured: the middle module's x range (between its posts)
    and the height that splits the top from the bottom support rope as generated."""
    fence_ = meta["fence"]
    mid = fence_["post_x"][fence_["modules"] // 2:fence_["modules"] // 2 + 2]
    return min(mid), max(mid), 0.5 * float(fence_["height"])


def rest_probe(meta, dt, every, window="rest_window"):
    """The deck's variables of the stillness probe (inputs/fence.in): the middle module, the
    window in steps of dt (whole rows of `every`), named ``window``."""
    x0, x1, zsplit = middle_module(meta)
    return {"rest_still": repr(REST_STILL), "rest_x0": repr(x0), "rest_x1": repr(x1),
            "rest_zsplit": repr(zsplit),
            window: int(math.ceil(REST_WINDOW / dt / every)) * every}


def block_turn(tilt_deg):
    """Unit quaternion turning the block's z axis onto the fence normal (0, cos t, sin t): a
    face towards the fence."""
    turn = math.radians(tilt_deg) - math.pi / 2
    return (math.cos(turn / 2), math.sin(turn / 2), 0.0, 0.0)


def aim_point(meta, offset):
    """The block's aim: the generator's impact target (the middle of the middle module) moved
    by offset = [along x, up the net's plane (the direction x cross n)]."""
    n = np.asarray(meta["normal"], float)
    up = np.cross([1.0, 0.0, 0.0], n)
    target = np.asarray(meta["impact_target"], float)
    return tuple(float(v) for v in target + offset[0] * np.array([1.0, 0.0, 0.0]) +
                 offset[1] * up / np.linalg.norm(up))


def bin_size(positions):
    """The neighbour bins' size [m] for atoms at ``positions``: BIN_SIZE, or the size at which
    their bounding box (1 m more each way: the block, the swinging ropes) holds MAX_BINS."""
    extent = np.ptp(np.asarray(positions, float), axis=0) + 2.0
    return max(BIN_SIZE, float(np.prod(extent) / MAX_BINS) ** (1.0 / 3.0))


class Setup:
    """Everything a fence run needs, from the checked case; variables() gives the deck's -var
    values."""

    def __init__(self, kind, workdir, bending, np_=1):
        c = kind.case
        self.kind, self.case, self.workdir, self.bending = kind, c, workdir, bending
        os.makedirs(workdir, exist_ok=True)
        self.g = c["gravity"]
        self.mass, self.side, self.speed = c["fence.block_mass"], c["fence.block_side"], \
            c["fence.speed"]
        self.impacts = c["fence.impacts"]
        net = c["panel.net"]
        prefix = os.path.join(workdir, "fence")
        self.data_path = generate(
            "fence", prefix, "--modules", c["fence.modules"], "--spacing", c["fence.spacing"],
            "--height", c["fence.height"], "--net", net, "--post-tilt", c["fence.post_tilt"],
            "--head-guides", c["fence.head_guides"], *generator_options(c, "compound"),
            *changed_options(c, FENCE_OPTIONS))
        self.json_path, self.shackles = prefix + ".json", prefix + ".shackles"
        self.types_path = prefix + ".types.in"
        self.meta = read_json(self.json_path)
        self.layers = 2 if net == "compound" else 1
        # the impacts' block, turned as released (the frames draw its STL from that pose): face-on,
        # then turned in its own frame by fence.block_orientation
        self.block = Block(workdir, self.mass, self.side,
                           compose(block_turn(self.meta["fence"]["post_tilt_deg"]),
                                   c["fence.block_orientation"]))
        self.block_path, self.quat = self.block.path, self.block.quat
        self.aim = aim_point(self.meta, c["fence.impact_point"])
        # centroid to the foremost point along -n: side/2 face-on (exactly), else the vertices'
        face_on = list(c["fence.block_orientation"]) == [1.0, 0.0, 0.0, 0.0]
        self.block_half = self.side / 2 if face_on else \
            self.block.extent(-np.asarray(self.meta["normal"], float))
        data = read_data(self.data_path)
        self.binsize = bin_size(data.positions)
        masses = node_masses(data)
        self.fence_mass = float(np.sum(masses))
        # the block's contact on the net's nodes (the hex and square meshes' atom types)
        net_types = [int(t) for t, role in self.meta["atom_types"].items()
                     if role.startswith(("hex_", "square_"))]
        net = np.isin(data.atom("type").astype(int), net_types)
        self.node_r = float(np.max(data.atom("diameter")[net]) / 2)
        # the stable step of bonds and the block's contact on the lightest node (both layers of
        # a compound net), from the bond style's estimate (runner/timestep.py)
        self.settle_mass = c["fence.settle_mass_factor"]
        if self.settle_mass & (self.settle_mass - 1):
            raise RunError(f"fence.settle_mass_factor: must be a power of two (the masses come "
                           f"back exactly), got {self.settle_mass}")
        stable, settling = self._stable_step(np_)
        self.dt_bonds, self.dt_contact, self.dt_stable = stable.bonds, stable.contact, stable.loaded
        self.dt_fraction = c["fence.dt_fraction"]
        self.dt_settle_stable = settling.loaded
        self.dt_settle = (c["fence.settle_dt_fraction"] or self.dt_fraction) * settling.loaded
        self.dt = c["fence.dt"] or self.dt_fraction * self.dt_stable
        if self.dt > self.dt_stable:
            raise RunError(f"fence.dt = {self.dt:g} s exceeds the stable step "
                           f"{self.dt_stable:g} s (bonds {self.dt_bonds:g} s, contact "
                           f"{self.dt_contact:g} s)")
        self.duration, self.settle_time = c["fence.duration"], c["fence.settle_time"]
        self.steps = int(math.ceil(self.duration / self.dt))
        self.every = max(int(round(c["fence.row_time"] / self.dt)), 1)
        self.settle_every = max(int(round(SETTLE_PIECE / self.dt_settle)), 1)
        self.relax_steps = int(math.ceil(self.settle_time / self.dt_settle / self.settle_every)) \
            * self.settle_every
        self.rest_time = c["fence.rest_time"]
        self.rest_steps = int(math.ceil(self.rest_time / self.dt / self.every)) * self.every
        self.frame_every = max(int(math.ceil(self.steps / int(c["output.frames"]))), 1)

    @property
    def energy(self):
        return 0.5 * self.mass * self.speed ** 2

    @property
    def ground_z(self):
        """The ground plane: the bottom rope's nodes (z = 0, wirenet-gen fence) lie on it."""
        return -0.5 * self.meta["ropes"]["support"]["diameter"]

    def _base_variables(self):
        section = self.meta["posts"]["section"]
        ropes = self.meta["ropes"]
        v = dict(self.kind.key_variables(), data=os.path.abspath(self.data_path),
                 types=os.path.abspath(self.types_path), shackles=os.path.abspath(self.shackles),
                 support_d=repr(ropes["support"]["diameter"]),
                 ground_z=repr(self.ground_z),
                 upslope_d=repr(ropes["upslope"]["diameter"]), post_A=repr(section["A"]),
                 post_Iy=repr(section["Iy"]), post_Iz=repr(section["Iz"]),
                 post_J=repr(section["J"]), ghost=repr(2.5 * self.meta["max_bond_length"]),
                 layers=self.layers, bending=repr(self.bending), binsize=repr(self.binsize),
                 out=".")
        if self.case["materials.rope_strength"]:
            v["rope_strength"] = rope_strength_keyword(True, self.kind.material_values())
        return v

    def _stable_step(self, np_):
        """The stable steps of the fence as built and while it settles (fence.in with probe 1:
        its bonds and the contact, include/timestep.in; then with the light nodes' masses
        scaled)."""
        probe = os.path.join(self.workdir, "probe")
        engine.run(INPUTS / "fence.in", probe,
                   dict(self._base_variables(), probe=1, settle_mass=self.settle_mass), np=np_,
                   label="fence: stable step")
        return timestep.read(probe), timestep.read(probe, " settling")

    def settle_variables(self):
        """The deck variables the settling depends on besides the fence's files: with them and
        the files, the settled state's key (settled_key)."""
        return dict(self._base_variables(), dt_settle=repr(self.dt_settle),
                    relax_steps=self.relax_steps, settle_every=self.settle_every,
                    settle_mass=self.settle_mass, settle_ke=repr(SETTLE_KE),
                    settle_carry=repr(SETTLE_CARRY),
                    **rest_probe(self.meta, self.dt_settle, self.settle_every, "settle_window"))

    @functools.cached_property
    def _files_digest(self):
        """The settled key's hash of the files (read once per case: the binary is 40 MB and a
        case asks for its key up to five times)."""
        h = hashlib.sha256()
        # the generated files name their own folder: the key must not
        prefix = os.path.abspath(os.path.join(self.workdir, "fence")).encode()
        files = [self.data_path, self.shackles, self.types_path, INPUTS / "fence.in",
                 *sorted((INPUTS / "include").glob("*.in")), engine.binary("liggghts")]
        for path in files:
            with open(path, "rb") as fh:
                h.update(fh.read().replace(prefix, b"PREFIX"))
        return h

    def settled_key(self, capped=False):
        """sha256 of everything the settled fence depends on: the generated files, the deck and
        its includes, the settling's variables and the LIGGGHTS binary. A fence that became
        still is the same whatever fence.settle_time allowed it (the deck stops at stillness):
        its key leaves the cap (relax_steps) out; one that did not is kept under ``capped``."""
        h = self._files_digest.copy()
        variables = {k: v for k, v in self.settle_variables().items()
                     if k not in ("data", "types", "shackles", "out", "inc") + IMPACT_ONLY
                     and (capped or k != "relax_steps")}
        h.update(json.dumps(variables, sort_keys=True).encode())
        return h.hexdigest()[:20]

    def variables(self):
        tx, ty, tz = self.aim
        nx, ny, nz = self.meta["normal"]
        # alpha_relax: the rest's local damping (include/fence_rest.in), not the settling's
        v = dict(self.settle_variables(), **self.block.inertia_variables(), dt=repr(self.dt),
                 alpha_relax=dissipation.SETTLE_ALPHA,
                 steps=self.steps, every=self.every,
                 dump_every=self.every, frame_every=self.frame_every,
                 target_x=repr(tx), target_y=repr(ty), target_z=repr(tz), normal_x=repr(nx),
                 normal_y=repr(ny), normal_z=repr(nz), block_cut=repr(self.block.cut),
                 quat=" ".join(map(repr, self.quat)),
                 block_half=repr(self.block_half), gap=GAP, foot_r=repr(max(1.0, self.side)),
                 node_r=repr(self.node_r), rest_steps=self.rest_steps,
                 rest_chunk=self.every, rest_ke=repr(REST_KE * self.energy),
                 rest_viscous=repr(REST_VISCOUS),
                 **rest_probe(self.meta, self.dt, self.every), **self.ground_variables())
        return v

    def ground_variables(self):
        """The block lands on the ground (fix wirenet/body's floor keywords: block_floor of
        include/block_analytic.in); tangential stiffness a tenth of the normal one, as the
        paper's contact."""
        c = self.kind.case
        kn = c["fence.ground_kn"]
        gamma = floor_damping(c["fence.ground_restitution"], kn, self.mass)
        return {"block_floor": f"floor 0 0 {self.ground_z!r} 0 0 1 kn {kn!r} kt {kn / 10!r} "
                               f"mu {c['fence.ground_mu']!r} gamma_n {gamma!r}"}


# ---------------------------------------------------------------------------------------------
# reading the run

def read_table(workdir):
    """fence.csv by its column names (the budget's, the block's, the momentum's)."""
    names = {c for t in BUDGET for c in t.columns} | {
        "step", "time", "x", "y", "z", "vx", "vy", "vz", "force", "px_net", "py_net", "pz_net",
        "jx_damp", "jy_damp", "jz_damp", "anchors_x", "anchors_y", "anchors_z", "bases_x",
        "bases_y", "bases_z", "ground_x", "ground_y", "ground_z", "jx_floor", "jy_floor", "jz_floor"}
    return read_deck_table(os.path.join(workdir, TABLE), sorted(names))


def read_bond_types(workdir):
    """bond_types.txt: (steps, {tally: [row, type - 1]}) of BOND_TALLIES."""
    steps, rows = netoutputs.read_vector_rows(os.path.join(workdir, "bond_types.txt"), len(BOND_TALLIES))
    return steps, rows


def component_energies(tallies, components):
    """{component: {tally: series}} for components {name: bond types}: elastic energy as it is,
    the dissipations (released, plastic, bond damping) from the first row on."""
    out = {}
    for name, types in components.items():
        cols = tallies[:, [t - 1 for t in types], :].sum(axis=1)
        out[name] = {k: cols[:, j] - (cols[0, j] if k != "elastic" else 0.0)
                     for j, k in enumerate(BOND_TALLIES)}
    return out


def fence_mechanisms(terms, components):
    """The energy dissipated by each mechanism over the impact (J): the budget's, with the
    plastic work split into the brakes' sliding and the yielding of wires and ropes."""
    out = budget.mechanisms(terms, BUDGET)
    brakes = float(components["brakes"]["plastic"][-1])
    out["brakes"] = brakes
    out["plasticity"] = out.get("plasticity", 0.0) - brakes
    return out


def momentum_balance(t, block_mass, fence_mass, g):
    """Change of the momentum of block and fence against the impulses of the support reactions
    and of the ground (window means x window length), of gravity and of the damping; the gap
    relative to the block's initial momentum, per row and component."""
    p_block = block_mass * np.column_stack([t["vx"], t["vy"], t["vz"]])
    p_net = np.column_stack([t["px_net"], t["py_net"], t["pz_net"]])
    dp = (p_block - p_block[0]) + (p_net - p_net[0])
    reactions = np.column_stack([t["anchors_x"] + t["bases_x"], t["anchors_y"] + t["bases_y"],
                                 t["anchors_z"] + t["bases_z"]])
    window = np.r_[0.0, np.diff(t["time"])]
    j_react = budget.cumulative(reactions, window)
    j_grav = np.zeros_like(dp)
    j_grav[:, 2] = -(block_mass + fence_mass) * g * (t["time"] - t["time"][0])
    j_damp = np.column_stack([t["jx_damp"], t["jy_damp"], t["jz_damp"]])
    # the ground pushes the nodes with minus the nodes' force on it
    j_ground = -budget.cumulative(np.column_stack([t["ground_x"], t["ground_y"], t["ground_z"]]),
                                  window)
    # the block's floor: its impulse on the block since the block was placed (exact sums)
    j_floor = np.column_stack([t["jx_floor"], t["jy_floor"], t["jz_floor"]])
    gap = budget.momentum_gap(dp, j_react, j_grav, j_ground, j_damp - j_damp[0],
                              j_floor - j_floor[0])
    return gap / float(np.linalg.norm(p_block[0]))


def read_parts(path):
    """parts.dump (dump local of compute wirenet/local over ropes, brakes and posts): per frame
    (step, {column: values}) by the compute's column names."""
    frames = []
    for f in dumps.iter_frames(path):
        mapping = dumps.bond_column_map(f)
        frames.append((f.step, {name: f.data[:, k] for name, k in mapping.items()}))
    if not frames:
        raise PostprocessError(f"{path}: no frames")
    return frames


def residual_height(setup, nodes_frame, data):
    """Least vertical distance between the top and the bottom support rope over the middle
    module (its posts' x range), in the frame (ids, positions); the ropes' nodes are those of
    the generator's role 'rope', top or bottom by their height in the data file."""
    x0, x1, zsplit = middle_module(setup.meta)
    rope_type = rope_node_type(setup.meta)
    rope = data.atom("type") == rope_type
    rope_ids = data.atom_ids[rope]
    top_ids = set(rope_ids[data.atom("z")[rope] > zsplit].tolist())
    ids, pos = nodes_frame
    ropes = np.isin(ids, rope_ids)
    inside = ropes & (pos[:, 0] >= x0) & (pos[:, 0] <= x1)
    top = inside & np.isin(ids, list(top_ids))
    bottom = inside & ~np.isin(ids, list(top_ids))
    if not top.any() or not bottom.any():
        raise RunError("fence: no support rope nodes in the middle module")
    order = np.argsort(pos[bottom, 0])
    zb = np.interp(pos[top, 0], pos[bottom, 0][order], pos[bottom, 2][order])
    return float(np.min(pos[top, 2] - zb))


def rope_node_type(meta):
    """The atom type of the support ropes' nodes (the generator's JSON atom_types)."""
    for t, role in meta["atom_types"].items():
        if role == "support_rope":
            return int(t)
    raise RunError("fence: the generator's JSON names no atom type 'support_rope'")


def read_rest(workdir):
    """The rest after an impact (include/fence_rest.in), or None without one: the state at rest
    (rest.dump: ids, positions) and rest.csv by its column names (time, ke, gap)."""
    dump = os.path.join(workdir, "rest.dump")
    if not os.path.exists(dump):
        return None
    rows = read_csv(os.path.join(workdir, "rest.csv"), required=("time", "ke", "gap"))
    if not len(rows["time"]):
        raise PostprocessError(f"{workdir}/rest.csv: no rows")
    carry = read_csv(os.path.join(workdir, "rest_carry.csv"),
                     required=("rz", "ground", "fence_weight", "block_weight"))
    if not len(carry["rz"]):
        raise PostprocessError(f"{workdir}/rest_carry.csv: no rows")
    weight = float(carry["fence_weight"][-1]) + float(carry["block_weight"][-1])
    return dict(nodes=netoutputs.last_nodes(dump), time=float(rows["time"][-1]), ke=float(rows["ke"][-1]),
                times=rows["time"], gaps=rows["gap"],
                carried=(float(carry["rz"][-1]) + float(carry["ground"][-1])) / weight,
                block_in_fence=bool(carry["block_weight"][-1] > 0))


def rest_facts(rest, impact_end, setup):
    """case.json's rest: how long it took after the impact's last row, the kinetic energy at
    its end against the limit, how far the probe of the residual height moved over its last
    REST_WINDOW (still: less than REST_STILL, as the deck ends the rest on), and the share of
    the weight (the fence's, and the block's if it touches the fence: block_in_fence) the
    supports and the ground carried at its end: the rest's damping holds the rest."""
    last = rest["times"] >= rest["times"][-1] - REST_WINDOW * (1 - 1e-9)
    moved = float(np.ptp(rest["gaps"][last]))
    full = rest["times"][-1] - impact_end >= REST_WINDOW * (1 - 1e-3)
    return dict(time=rest["time"] - impact_end, kinetic_energy=rest["ke"],
                limit=REST_KE * setup.energy, reached=bool(rest["ke"] < REST_KE * setup.energy),
                probe_moved=moved, still=bool(full and moved < REST_STILL),
                weight_carried=rest["carried"], block_in_fence=rest["block_in_fence"])


# ---------------------------------------------------------------------------------------------
# the kind

class Fence(CaseKind):
    name = "fence"
    summary = "a block impact on a whole fence (" + EAD + ")"
    deck = "fence.in"
    keys = KEYS
    takes = ("title", "gravity", "panel.net", "panel.placement", "panel.selvedge",
             "panel.hex_node_radius", "panel.hex_node_mass", "panel.square_node_radius",
             "panel.rope_mass", "panel.axis_distance", "panel.twist_length", "panel.rise",
             "panel.cell", "panel.rope_elements", "materials.*", "contact.kn", "contact.ks",
             "contact.mu", "damping.*", "fence.*", "output.frames", "output.budget_tolerance", "ensemble.*")
    # a penalty 100x softer than the paper's 1e9 N/m, so that the block's contact does not set
    # the step on 4 g hex nodes: a wire's breaking force (~3 kN) overlaps it by ~0.3 mm against
    # node radii of 5 mm (doc/fence.md); the physical model of the impacts (doc/impact.md)
    defaults = {"panel.net": "compound", "contact.kn": 1e7, "contact.ks": 1e6,
                "damping.local": 0.0, "damping.bond": dissipation.STRUCTURAL_ZETA}
    default_sources = {"contact.kn": "none: a penalty stiffness, the paper's 1e9 N/m / 100 (the "
                                      "time step on 4 g nodes; doc/fence.md)",
                       "contact.ks": "none: a penalty stiffness, contact.kn / 10 as the paper's",
                       "damping.bond": dissipation.STRUCTURAL_ZETA_SOURCE}
    not_taken = ("not used by a fence case (module size: fence.spacing and fence.height; "
                 "supports: its anchors and posts; it settles for fence.settle_time)")
    finished_file = "block.csv"
    width = 2

    @classmethod
    def check(cls, case, fail):
        super().check(case, fail)
        along, up = case["fence.impact_point"]
        for value, half, where in ((along, case["fence.spacing"] / 2, "along the fence"),
                                   (up, case["fence.height"] / 2, "up the net")):
            if abs(value) >= half:
                fail("fence.impact_point", f"{case['fence.impact_point']}: {abs(value):g} m "
                                           f"{where} leaves the middle module ({half:g} m each "
                                           "side: fence.spacing / 2, fence.height / 2)")
        rows = 2 * case["fence.row_time"]
        if case["fence.duration"] < rows:
            fail("fence.duration", f"{case['fence.duration']:g} s: shorter than two rows of "
                                   f"fence.csv ({rows:g} s: 2 x fence.row_time)")
        if not case["fence.settle_kinetic"] and case["fence.settle_local"] == 0:
            fail("fence.settle_local", "0 with fence.settle_kinetic false: nothing would bring "
                                       "the settling fence to rest")

    def verdict(self, facts):
        touched = facts.get("braking_distance")
        if not touched:
            return (record.NO_CONTACT, "the block never touched the fence: check fence.speed "
                                       "and fence.duration")
        settled = facts.get("settled") or {}
        if settled.get("still") is False:
            window = settled.get("last_window")
            why = (f"in its last {window['window']:.3g} s: {failed_stillness(window)}" if window
                   else f"its supports and the ground carried {settled['weight_carried']:.1%} of "
                        f"its weight (kinetic energy {settled['kinetic_energy']:.3g} J)")
            return (record.NOT_SETTLED,
                    f"the fence was not still when the block was released: after "
                    f"fence.settle_time ({facts['settle_time']:g} s), {why}; lengthen "
                    "fence.settle_time, or see doc/fence.md (\"Limits\") if it does not stand at all")
        return self.budget_verdict(facts) or self.ended_verdict(facts)

    @staticmethod
    def ended_verdict(facts):
        """NOT_ENDED when the block was still going into the fence as the impact ended and
        the rest after it did not end still either: it never turned and did not leave the fence
        (the rest was not skipped); its braking distance and residual height are not yet the
        test's. Without a rest (fence.rest_time 0) the case asks for the impact alone."""
        rest = facts.get("rest")
        if facts.get("block_stopped") is not False or rest is None or rest.get("still"):
            return None
        return (record.NOT_ENDED,
                f"the block was still moving into the fence when the run ended (at "
                f"{facts['final_block_speed']:.3g} m/s after fence.duration "
                f"{facts['duration']:g} s, and not still after the rest): its braking distance "
                "and residual height are not the test's yet; lengthen fence.duration")

    def run(self, index, ctx):
        c = self.case
        bending, source = bending_of(c, ctx.study_dir)
        setup = Setup(self, os.path.join(ctx.case_dir, "setup"), bending, np_=ctx.ranks)
        workdir = os.path.join(ctx.case_dir, "run")
        start = time.time()
        # a fence settled before with everything the same is taken as it was left
        cached = find_settled(ctx.study_dir, setup)
        variables = setup.variables()
        if cached:
            variables.update(from_settled=1, settled=cached)
        wall = engine.run(INPUTS / "fence.in", workdir, variables, np=ctx.ranks,
                          total_steps=setup.steps, label="fence", dt=setup.dt,
                          phase_marker="impact: block released",
                          then=("rest", setup.rest_steps, IMPACT_ENDED) if setup.rest_steps else None,
                          before=None if variables.get("from_settled") else ("settling", setup.relax_steps))
        if variables.get("from_settled"):
            # (a settled state kept before its facts were: none to show)
            path = settled_facts_path(cached)
            settled = read_json(path) if os.path.isfile(path) else None
        else:
            line = engine.log_line(workdir, SETTLED)
            settled = read_settled(line) if line else None
            if settled is not None:
                settled["still"] = engine.log_line(workdir, SETTLE_STILL) is not None
                late = engine.log_line(workdir, SETTLE_NOT_STILL)
                if late:
                    settled["last_window"] = read_not_still(late)
            kept = settled_path(ctx.study_dir, setup, bool(settled and settled["still"]))
            if not os.path.isfile(kept):   # (a member beside this one may have kept it first)
                keep_settled(os.path.join(workdir, "settled.restart"), kept, settled)
            share_settled(kept, setup, settled)
        facts = self.write_outputs(setup, ctx.case_dir, workdir, read_table(workdir))
        facts["settled_from"] = cached if variables.get("from_settled") else None
        facts["settled"] = settled
        ended = engine.log_line(workdir, IMPACT_ENDED)
        # the impact's simulated time: ended early (the deck's line) or the whole duration
        facts["impact_time"] = float(ended.split()[2]) if ended else c["fence.duration"]
        if setup.impacts == 2:
            second = os.path.join(workdir, "impact_2")
            second_dir = os.path.join(ctx.case_dir, "impact_2")
            os.makedirs(second_dir, exist_ok=True)
            facts["second_impact"] = self.write_outputs(setup, second_dir, second,
                                                        read_table(second))
        facts.update(fence=setup.meta["fence"], fence_mass=setup.fence_mass,
                     atoms=int(setup.meta["counts"]["atoms"]), bending_source=source,
                     block=dict(mass=setup.mass, side=setup.side, speed=setup.speed,
                                quat=list(setup.quat), energy=setup.energy,
                                point=list(c["fence.impact_point"]), aim=list(setup.aim)),
                     gravity=setup.g, damping=c["damping.local"], bond_damping=c["damping.bond"],
                     dissipation=dissipation.model(c),
                     dt=setup.dt, dt_fraction=setup.dt_fraction, dt_stable_bonds=setup.dt_bonds,
                     dt_stable_contact=setup.dt_contact, steps=setup.steps,
                     dt_settle=setup.dt_settle, dt_settle_stable=setup.dt_settle_stable,
                     duration=setup.duration, settle_time=setup.settle_time,
                     rest_time=setup.rest_time, impacts=setup.impacts,
                     relax_steps=setup.relax_steps, run_wall_time=wall,
                     post_wall_time=time.time() - start - wall)
        return facts

    def write_outputs(self, setup, case_dir, workdir, t):
        """block.csv, energy.csv, components.csv, supports.csv, ropes.csv, brakes.csv,
        ruptures.csv and the ParaView series; returns the facts for case.json."""
        time_ = t["time"] - t["time"][0]
        n = np.asarray(setup.meta["normal"], float)
        pos = np.column_stack([t["x"], t["y"], t["z"]])
        travel = (pos[0] - pos) @ n
        write_csv(os.path.join(case_dir, "block.csv"),
                  ("time", "x", "y", "z", "vx", "vy", "vz", "travel", "force"),
                  zip(time_, t["x"], t["y"], t["z"], t["vx"], t["vy"], t["vz"], travel,
                      t["force"]))
        terms, total, e0, error = budget.energy_budget(t, BUDGET)
        names = tuple(term.name for term in BUDGET)
        write_csv(os.path.join(case_dir, "energy.csv"), ("time",) + names + ("total", "closure_error"),
                  zip(time_, *(terms[k] for k in names), total, error))
        gap = momentum_balance(t, setup.mass, setup.fence_mass, setup.g)
        type_steps, tallies = read_bond_types(workdir)
        components = component_energies(tallies, component_types(setup.meta, tallies.shape[1]))
        write_csv(os.path.join(case_dir, "components.csv"),
                  ("time",) + tuple(f"{c}_{k}" for c in components for k in BOND_TALLIES),
                  zip((type_steps - type_steps[0]) * setup.dt,
                      *(components[c][k] for c in components for k in BOND_TALLIES)))

        names_of = {a["id"]: a["name"] for a in setup.meta["anchors"]}
        names_of.update({b: f"post_base_{k}" for k, b in enumerate(setup.meta["post_bases"])})
        supports, peaks = [], {}
        for file in ("anchors.txt", "bases.txt"):
            steps, ids, forces = netoutputs.read_support_rows(os.path.join(workdir, file))
            magnitude = np.linalg.norm(forces, axis=2)
            for k, atom in enumerate(ids):
                j = int(np.argmax(magnitude[:, k]))
                peaks[names_of[int(atom)]] = dict(atom=int(atom), peak=float(magnitude[j, k]),
                                                  time=float((steps[j] - steps[0]) * setup.dt),
                                                  at_peak=forces[j, k].tolist())
            supports.append((steps, ids, magnitude))
        steps = supports[0][0]
        write_csv(os.path.join(case_dir, "supports.csv"),
                  ("time",) + tuple(names_of[int(a)] for _, ids, _ in supports for a in ids),
                  zip((steps - steps[0]) * setup.dt, *(m[:, k] for _, ids, m in supports
                                                        for k in range(len(ids)))))

        frames = read_parts(os.path.join(workdir, "parts.dump"))
        family_types = part_types(setup.meta)
        peaks_of = {}
        for family, types in family_types.items():
            peaks_of[family] = [float(np.max(np.abs(cols["tension"][np.isin(cols["type"], types)]),
                                             initial=0.0)) for _, cols in frames]
        part_times = [(s - frames[0][0]) * setup.dt for s, _ in frames]
        write_csv(os.path.join(case_dir, "ropes.csv"), ("time",) + tuple(peaks_of),
                  zip(part_times, *peaks_of.values()))
        brake_types = family_types["brake"] + family_types["upslope_brake"]
        elongation = []
        for _, cols in frames:
            b = np.isin(cols["type"], brake_types)
            elongation.append(dict(zip((f"{int(a)}-{int(c)}" for a, c in
                                        zip(cols["atom1"][b], cols["atom2"][b])),
                                       cols["length"][b] - cols["length0"][b])))
        brake_keys = list(elongation[0])
        write_csv(os.path.join(case_dir, "brakes.csv"), ("time",) + tuple(brake_keys),
                  zip(part_times, *([e.get(k, math.nan) for e in elongation]
                                    for k in brake_keys)))

        # the net's families from the JSON, the fence parts' as the deck names them (the JSON
        # calls a support rope "rope", as the square mesh's strand rope)
        family_of = {int(k): v for k, v in setup.meta["bond_families"].items()}
        family_of.update({t: family for family, types in family_types.items() for t in types})
        ruptures = netoutputs.ruptures(os.path.join(workdir, "ruptures.dump"), setup.dt,
                                       family_of)
        netoutputs.write_ruptures(os.path.join(case_dir, "ruptures.csv"), ruptures)
        by_family = {}
        for r in ruptures:
            by_family[r["family"]] = by_family.get(r["family"], 0) + 1

        data = read_data(setup.data_path)
        end_of_impact = residual_height(
            setup, netoutputs.last_nodes(os.path.join(workdir, "frames", "nodes.dump"),
                              int(t["step"][-1])), data)
        rest = read_rest(workdir)
        height = residual_height(setup, rest["nodes"], data) if rest else end_of_impact
        netoutputs.write_series(case_dir, workdir, setup.data_path, setup.block_path, setup.dt)
        _, touch_travel = first_touch(time_, travel, np.column_stack([t["vx"], t["vy"], t["vz"]]),
                                      np.array([0.0, 0.0, -setup.g]))
        speed = np.sqrt(t["vx"] ** 2 + t["vy"] ** 2 + t["vz"] ** 2)
        # stopped: the block's velocity along the normal turned (it no longer moves into the
        # fence) at some row; a block that flies over or through the fence never turns
        along = np.column_stack([t["vx"], t["vy"], t["vz"]]) @ n
        return dict(
            block_stopped=bool(np.any(along >= 0.0)),
            braking_distance=float(np.max(travel) - touch_travel),
            time_of_braking_distance=float(time_[int(np.argmax(travel))]),
            residual_height=height, nominal_height=float(setup.meta["fence"]["height"]),
            residual_height_ratio=height / float(setup.meta["fence"]["height"]),
            residual_height_at="rest" if rest else "end of impact",
            # the deck skips the rest of a block that left the fence moving on (a failed test)
            rest_skipped=os.path.isfile(os.path.join(workdir, "rest.skipped")),
            residual_height_end_of_impact=end_of_impact,
            rest=None if rest is None else rest_facts(rest, float(t["time"][-1]), setup),
            final_block_speed=float(speed[-1]),
            support_peaks=peaks,
            rope_peaks={f: float(np.max(s)) for f, s in peaks_of.items()},
            brake_elongation_peak=float(np.nanmax([max(e.values()) for e in elongation])),
            energy=dict(closure_error=float(np.max(np.abs(error))), initial_energy=e0,
                        final_error=float(error[-1]),
                        final={k: float(terms[k][-1]) for k in names},
                        mechanisms=fence_mechanisms(terms, components),
                        local_damping_fraction=float(terms["damping"][-1]) / e0,
                        components={c: dict({k: float(v[-1]) for k, v in tally.items()},
                                            elastic_peak=float(np.max(tally["elastic"])))
                                    for c, tally in components.items()}),
            momentum=dict(error=float(np.max(np.linalg.norm(gap, axis=1))),
                          final_error=float(np.linalg.norm(gap[-1]))),
            broken_bonds=len(ruptures), ruptures_by_family=by_family,
            first_rupture=netoutputs.rupture_facts(ruptures[0]) if ruptures else None)

