"""From a checked case file (runner/casefile.Case) to its runs: one class per kind of case turns
the keys into the generator's options and the deck's set-up (runner/punch.py Setup,
runner/impact.py Setup, runner/cantilever.py), runs them and returns the facts for case.json.

A case with several [[impact]] entries is a sequence: its units are CASE (the first impact),
CASE_impact2, ... each a case folder of its own, each starting from the net the previous one
left (its run/net.restart).
"""

import json
import os

from postprocess.model import MATERIALS, PAPER_BENDING, rope_strength_keyword

from . import cantilever, fence, impact, punch, supports
from .schema import BY_PATH, KEYS

CALIBRATION_FILE = "calibration.json"   # python3 -m postprocess calibrate ... --out DIR/calibration


def bending_of(case, study_dir):
    """(fraction, source) of the rope beams: the case's number, or for 'calibrated' the best
    fraction of DIR/calibration.json when the calibration has been fitted, else the paper's."""
    value = case["materials.bending"]
    if value != "calibrated":
        return value, "case file"
    path = os.path.join(study_dir, CALIBRATION_FILE)
    try:
        with open(path, encoding="utf-8") as handle:
            best = json.load(handle)["best_fraction"]
        if isinstance(best, (int, float)) and best >= 0:
            return float(best), f"calibrated ({path})"
    except (OSError, ValueError, KeyError, TypeError):
        pass
    return PAPER_BENDING, "the paper's calibrated value (no calibration.json in the study folder)"


def materials_of(case):
    """materials.in overrides: the case's material and contact keys that differ from it (a key
    whose default depends on the kind, from materials.in's value)."""
    out = {}
    for key in KEYS:
        if key.section not in ("materials", "contact") or key.name in ("bending", "rope_strength",
                                                                        "zeta"):
            continue
        value = case[key.path]
        if value != (MATERIALS[key.name] if isinstance(key.default, dict) else key.default):
            out[key.name] = value
    return out


# case key -> wirenet-gen option for each net (compound prefixes its layers' options)
_GENERATOR_OPTIONS = (
    ("panel.placement", {"hex": "--placement", "compound": "--placement"}),
    ("panel.selvedge", {"hex": "--selvedge", "compound": "--selvedge"}),
    ("panel.hex_node_radius", {"hex": "--node-radius", "compound": "--hex-node-radius"}),
    ("panel.hex_node_mass", {"hex": "--node-mass", "compound": "--hex-node-mass"}),
    ("panel.square_node_radius", {"square": "--node-radius", "compound": "--square-node-radius"}),
    ("panel.rope_mass", {"square": "--rope-mass", "compound": "--rope-mass"}),
)


def generator_options(case):
    """wirenet-gen options beyond the net and size: only those a case changes from the schema's
    defaults (a node radius of 0 is the generator's own), so that a case with the defaults
    generates the generator's default panel."""
    options = []
    net = "compound" if case.kind == "fence" else case["panel.net"]   # fence: --hex-.., --square-..
    for path, by_net in _GENERATOR_OPTIONS:
        value, option = case[path], by_net.get(net)
        if option and value != BY_PATH[path].default and value != 0.0:
            options += [option, value]
    return options


def write_supports(case, setup_dir):
    """The deck variables of the case's supports: its rendered include and the matching unfix
    file; none for the paper's (inputs/include/hold.in, unfix_supports.in)."""
    chosen = {e: case[f"supports.{e}"] for e in supports.EDGES}
    if chosen == supports.PAPER:
        return None
    os.makedirs(setup_dir, exist_ok=True)
    paths = {"supports": os.path.join(setup_dir, "supports.in"),
             "unfix_supports": os.path.join(setup_dir, "unfix_supports.in")}
    for name, text in (("supports", supports.render(chosen)),
                       ("unfix_supports", supports.render_unfix(chosen))):
        with open(paths[name], "w", encoding="utf-8") as handle:
            handle.write(text)
    return paths


def output_options(case):
    """Row, dump and frame intervals of the case's [output] keys (a fence dumps its ropes at
    every row)."""
    if case.kind == "fence":
        return {"row_time": case["fence.row_time"], "frames": case["output.frames"]}
    rows = {"punch": ("row_travel", "output.row_travel"), "impact": ("row_time", "output.row_time"),
            "fence": ("row_time", "fence.row_time")}
    name, path = rows[case.kind]
    return {name: case[path], "dump_rows": case["output.dump_rows"], "frames": case["output.frames"]}


def zones_of(case):
    return tuple((z["name"], tuple(z["centre"]), z["radius"]) for z in case.zones)


def common_options(case):
    return dict(width=case["panel.width"], height=case["panel.height"],
                gen_options=generator_options(case), gravity=case["gravity"],
                alpha=case["damping.local"], bond_zeta=case["damping.bond"],
                materials=materials_of(case), rope_strength=case["materials.rope_strength"])


class CaseRunner:
    """A case of one kind: its case folders (units) and how each runs."""

    def __init__(self, case):
        self.case = case

    def units(self):
        """(folder name, index) of each run of the case: one, except for impact sequences."""
        return [(self.case.name, 0)]

    def width(self):
        """LIGGGHTS runs of a unit at the same time: the ranks it can keep busy when cases of a
        study run side by side (runner/study.py)."""
        return 1


class PunchCase(CaseRunner):
    """A quasi-static punch (runner/punch.py, inputs/punch.in)."""

    # another case's run/preload.restart to start from (punch.preload_from; set by the study
    # once that case's pre-load is done; None: pre-load its own)
    preload_restart = None

    def width(self):
        return 2 if self.case["punch.quasi_static_check"] else 1

    def run(self, index, case_dir, study_dir, np_):
        c = self.case
        bending, source = bending_of(c, study_dir)
        platter = c["punch.platter"]
        shape = dict(punch.PLATTERS[platter])
        for name in ("radius", "height", "tip_radius"):
            if c[f"punch.{name}"] is not None:
                shape[name] = c[f"punch.{name}"]
        if platter == "sphere" and c["punch.height"] is None:
            shape["height"] = shape["radius"]
        options = dict(common_options(c), shape=shape, position=c["punch.position"],
                       speed=c["punch.speed"], travel=c["punch.travel"] if not c.quick else None,
                       mass_scaling=c["punch.mass_scaling"],
                       steps_per_m=c["punch.steps_per_metre"],
                       quasi_static=c["punch.quasi_static_check"],
                       slow_travel=c["punch.check_travel"], body_model=c["punch.body"],
                       speed_max=c["punch.speed_max"],
                       eq_target=c["punch.equilibrium_target"],
                       stop_drop=c["punch.stop_drop"],
                       contact_zeta=c["contact.zeta"],
                       preload_mode={"sag": 2, "settle": 1, "none": 0}[c["preload.mode"]],
                       preload=c["preload.sag"],
                       supports=write_supports(c, os.path.join(case_dir, "setup")),
                       **output_options(c))
        facts = punch.run_case(case_dir, c["panel.net"], platter, bending, c.quick, np_,
                               zones=zones_of(c), preload_from=self.preload_restart, **options)
        return dict(facts, bending_source=source)


class ImpactCase(CaseRunner):
    """One block impact or a sequence of them on the same net (runner/impact.py,
    inputs/impact.in)."""

    def units(self):
        n = len(self.case.impacts)
        return [(self.case.name if k == 0 else f"{self.case.name}_impact{k + 1}", k)
                for k in range(n)]

    def run(self, index, case_dir, study_dir, np_):
        c = self.case
        item = c.impacts[index]
        bending, source = bending_of(c, study_dir)
        previous = None
        if index > 0:
            name = self.units()[index - 1][0]
            previous = os.path.join(study_dir, name, "run", "net.restart")
        settle = c["preload.settle_time"] if c["preload.mode"] == "settle" else 0.0
        options = dict(common_options(c), mass=item["mass"], side=item["side"],
                       velocity=item["velocity"], point=item["point"], quat=item["orientation"],
                       duration=item["duration"], body_model=item["body"],
                       dt_fraction=item["dt_fraction"],
                       stl=item["stl"] or None, relax=settle,
                       supports=write_supports(c, os.path.join(case_dir, "setup")),
                       restart=previous, save_net=index + 1 < len(c.impacts),
                       **output_options(c))
        facts = impact.run_case(case_dir, c["panel.net"], bending, c.quick, np_,
                                zones=zones_of(c), **options)
        return dict(facts, bending_source=source, sequence=dict(
            index=index + 1, of=len(c.impacts),
            previous=self.units()[index - 1][0] if index else None))


class CantileverCase(CaseRunner):
    """The cantilever check of the beam law (runner/cantilever.py, inputs/cantilever.in)."""

    def run(self, index, case_dir, study_dir, np_):
        return cantilever.run_beam_case(case_dir, self.case["cantilever.elements"], np_=np_)


class FenceCase(CaseRunner):
    """A block impact on a whole fence (runner/fence.py, inputs/fence.in)."""

    def width(self):
        return 2

    def run(self, index, case_dir, study_dir, np_):
        c = self.case
        bending, source = bending_of(c, study_dir)
        materials = dict(materials_of(c), bending=bending)
        if c["materials.rope_strength"]:
            materials["rope_strength"] = rope_strength_keyword(True, materials)
        facts = fence.run_case(
            case_dir, np_=np_, modules=c["fence.modules"], spacing=c["fence.spacing"],
            height=c["fence.height"], net=c["panel.net"], post_tilt=c["fence.post_tilt"],
            head_guides=c["fence.head_guides"], mass=c["fence.block_mass"],
            side=c["fence.block_side"], speed=c["fence.speed"], duration=c["fence.duration"],
            settle_time=c["fence.settle_time"], rest_time=c["fence.rest_time"],
            impacts=c["fence.impacts"], dt=c["fence.dt"], alpha=c["damping.local"],
            bond_zeta=c["damping.bond"], gravity=c["gravity"], materials=materials,
            gen_options=generator_options(c), **output_options(c))
        return dict(facts, bending_source=source)


RUNNERS = {"punch": PunchCase, "impact": ImpactCase, "cantilever": CantileverCase,
           "fence": FenceCase}


def runner_of(case):
    return RUNNERS[case.kind](case)


# the kind a case folder's case.json records, and the CSV that shows it finished
def record_kind(case):
    """case.json 'kind': beam, calibration (the cone punches on the square mesh), punch, impact."""
    if case.kind == "cantilever":
        return "beam"
    if case.kind == "punch" and case.name.startswith("calibration"):
        return "calibration"
    return case.kind

