"""Ensembles, sweeps and one-at-a-time sensitivity studies: the [ensemble] section of a case file
(its keys: runner/schema.py ENSEMBLE; doc/ensembles.md) made into members, each a plain case.

A member is the case with some keys changed:
- random (ensemble.members > 1): the variations the section asks, drawn per member;
- a sweep (ensemble.sweep, ensemble.values): each value, ensemble.members random members each;
- sensitivity (ensemble.sensitivity, ensemble.factors): member 0 the case itself, then each key
  times each factor, alone.
A member's values are written out in full (member_case_text: DIR/NAME/member_KKK/case.toml) and
the member is checked from exactly those values, so that `./wirenet run that/case.toml` runs the
same case alone. DIR/NAME/ensemble.json (manifest) says what each member changes; the report
(postprocess/ensembles.py) reads it.

Draws: member k's draw of variable v comes from numpy's default_rng([seed, k, v]), so adding
members or another variation leaves every other draw as it was; the r-th member of each swept
value has the same draws (common random numbers: the sweep's differences are not blurred by them).
"""

import copy
import json
import math
import os
import tomllib
from dataclasses import dataclass, field

import numpy as np

from postprocess import ensembles

from . import casefile, schema
from .block import compose
from .errors import CaseFileError

# the draws' streams (default_rng([seed, member, STREAM])): never renumber
SLACK, POINT, SPEED, ORIENTATION, WIRES, ROPES, FRICTION = range(1, 8)
TRUNCATE = 3.0      # normal factors are truncated at this many standard deviations
# what a material factor scales: the wires' stress-strain table, the ropes' modulus, strengths and
# (fence) the support ropes' table
WIRE_KEYS = ("materials.curve",)
ROPE_KEYS = ("materials.rope_E", "materials.rope_sigma_t", "materials.rope_tau_c",
             "fence.support_curve")
SCALABLE = ("number", "pairs")


@dataclass
class Member:
    """One member: its folder name, what it changes from the case (key: value as written in its
    case file; a key of [[impact]]: its first entry's), what was drawn, and its place in a sweep
    or sensitivity study."""
    name: str
    index: int
    label: str
    changes: dict = field(default_factory=dict)
    drawn: dict = field(default_factory=dict)
    sweep_value: object = None
    key: str = None          # sensitivity: the key scaled (None: the base member)
    factor: float = None


@dataclass
class Ensemble:
    """The members of one case file and their checked cases."""
    name: str
    case: object             # the case file's Case (with its [ensemble] section)
    mode: str                # random, sweep or sensitivity
    members: list
    cases: list
    skipped: list = field(default_factory=list)   # sensitivity: unsourced keys left out, why

    def manifest(self):
        v = self.case.values
        return {
            "name": self.name, "case_file": self.case.path, "kind": self.case.kind,
            "mode": self.mode, "quick": bool(self.case.quick), "seed": v["ensemble.seed"],
            "members_per_value": v["ensemble.members"], "variations": variations(self.case),
            "sweep": {"key": v["ensemble.sweep"], "values": v["ensemble.values"],
                      "unit": schema.BY_PATH[v["ensemble.sweep"]].unit}
            if self.mode == "sweep" else None,
            "sensitivity": {"keys": sorted({m.key for m in self.members if m.key}),
                            "factors": v["ensemble.factors"], "skipped": self.skipped}
            if self.mode == "sensitivity" else None,
            "members": [dict(name=m.name, index=m.index, label=m.label, changes=m.changes,
                             drawn=m.drawn, sweep_value=m.sweep_value, key=m.key,
                             factor=m.factor) for m in self.members]}


def active(case):
    """Whether the case file asks for members (an [ensemble] section that does something)."""
    v = case.values
    return "ensemble.members" in v and (v["ensemble.members"] > 1 or bool(v["ensemble.sweep"])
                                        or bool(v["ensemble.sensitivity"]))


def check_inactive(case):
    """A case whose [ensemble] asks for no members (members 1, no sweep, no sensitivity) must not
    state an ensemble key at another value than its default: it would vary nothing, silently."""
    stated = [path for path in sorted(case.stated) if path.startswith("ensemble.")
              and path in case.values and case.values[path] != schema.BY_PATH[path].default]
    if stated:
        raise CaseFileError(f"{case.path}: {stated[0]}: {case.values[stated[0]]!r} varies nothing: "
                            "the [ensemble] asks for no members (set ensemble.members > 1, or a "
                            "sweep or a sensitivity study)")


def variations(case):
    """{variation: how} of the random variations the case asks (the report's header)."""
    v = case.values
    out = {}
    if v["ensemble.slack_seeds"]:
        out["slack seed"] = "materials.slack_seed drawn per member"
    if v["ensemble.point_radius"] > 0:
        out["impact point"] = f"uniform over a disc of radius {v['ensemble.point_radius']:g} m"
    if v["ensemble.speed"] == "normal":
        out["block speed"] = f"normal factor, COV {v['ensemble.speed_cov']:g}"
    elif v["ensemble.speed"] == "uniform":
        lo, hi = v["ensemble.speed_range"]
        out["block speed"] = f"uniform on [{lo:g}, {hi:g}] m/s"
    if v["ensemble.orientation"] == "random":
        out["block orientation"] = "uniformly random rotation"
    if v["ensemble.material_cov"] > 0:
        out["material"] = f"wire and rope stress factors, COV {v['ensemble.material_cov']:g}"
    if v["ensemble.friction_cov"] > 0:
        out["friction"] = f"factor on contact.mu, COV {v['ensemble.friction_cov']:g}"
    return out


# ---------------------------------------------------------------------------------------------
# a case as a TOML tree, and back

def case_tree(case):
    """The case's values as a case file's tree, every key stated, the [ensemble] section left
    out (a member is a plain case)."""
    tree = {"kind": case.kind}
    for path, value in case.values.items():
        if schema.BY_PATH[path].section != "ensemble":
            _put(tree, path, copy.deepcopy(value))
    if case.impacts:
        tree["impact"] = copy.deepcopy(case.impacts)
    if case.zones:
        tree.setdefault("output", {})["zones"] = copy.deepcopy(case.zones)
    return tree


def _put(tree, path, value):
    *sections, name = path.split(".")
    for section in sections:
        tree = tree.setdefault(section, {})
    tree[name] = value


def _get(tree, path):
    for part in path.split("."):
        tree = tree[part]
    return tree


def _first(tree, path):
    """A key's value in a tree; a key of [[impact]]: its first entry's."""
    key = schema.BY_PATH[path]
    return tree[key.section][0][key.name] if key.per_item else _get(tree, path)


def _toml_value(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return json.dumps(value)        # a JSON string is a TOML basic string
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, list):
        return "[" + ", ".join(_toml_value(v) for v in value) + "]"
    return str(value)


def toml_text(tree, prefix=""):
    """TOML of a tree: a table's values, then its sub-tables, then its arrays of tables."""
    lines = [f"{k} = {_toml_value(v)}" for k, v in tree.items()
             if not isinstance(v, dict) and not _is_tables(v)]
    for k, v in tree.items():
        name = f"{prefix}{k}"
        if isinstance(v, dict):
            lines += ["", f"[{name}]", toml_text(v, name + ".")]
        elif _is_tables(v):
            for entry in v:
                lines += ["", f"[[{name}]]", toml_text(entry, name + ".")]
    return "\n".join(lines).strip("\n")


def _is_tables(value):
    return isinstance(value, list) and bool(value) and all(isinstance(v, dict) for v in value)


def member_text(tree, name, ensemble_name):
    """A member's case file: every value stated, headed by where it comes from and the command
    that runs it alone."""
    head = [f"# Member {name} of the ensemble {ensemble_name} (../{ensembles.MANIFEST}: what it "
            "changes), written by",
            "# ./wirenet run (runner/ensemble.py) with every value stated. Alone it runs as it "
            "ran in the ensemble",
            "# (the same values on the same number of ranks give the same result):",
            "#   ./wirenet run case.toml --np 1 --out DIR",
            "# (no --quick: it would turn a stated value equal to a full default into its "
            "quick value)"]
    return "\n".join(head) + "\n\n" + toml_text(tree) + "\n"


def write_member_file(case, folder):
    """FOLDER/case.toml of a member (the study writes it when the member starts, into its
    fresh folder): the text the member was checked from."""
    with open(os.path.join(folder, "case.toml"), "w", encoding="utf-8") as handle:
        handle.write(case.member_text)


# ---------------------------------------------------------------------------------------------
# draws

def _rng(seed, member, stream):
    return np.random.default_rng([seed, member, stream])


def _normal_factor(rng, cov):
    """A factor of mean 1 and coefficient of variation cov, normal, truncated at TRUNCATE
    standard deviations (redrawn beyond)."""
    while True:
        z = rng.standard_normal()
        if abs(z) <= TRUNCATE:
            return float(1.0 + cov * z)


def _disc(rng, radius):
    """A point uniform over a disc of the radius, about the origin."""
    u, v = rng.random(2)
    r, angle = radius * math.sqrt(u), 2 * math.pi * v
    return [r * math.cos(angle), r * math.sin(angle)]


def random_quaternion(rng):
    """A uniformly random rotation, unit quaternion [w, x, y, z] (Shoemake 1992)."""
    u1, u2, u3 = rng.random(3)
    a, b = math.sqrt(1 - u1), math.sqrt(u1)
    return [b * math.cos(2 * math.pi * u3), a * math.sin(2 * math.pi * u2),
            a * math.cos(2 * math.pi * u2), b * math.sin(2 * math.pi * u3)]


def _scaled(value, factor):
    """A number or a [[strain, stress], ...] table (its stresses) times factor."""
    if isinstance(value, list):
        return [[e, s * factor] for e, s in value]
    return value * factor


def _set_speed(case, tree, factor, speed):
    """The block speed(s) times factor, or set to speed (factor None), each [[impact]]
    entry's direction kept; returns the (first) speed."""
    if case.kind == "fence":
        fence = tree["fence"]
        fence["speed"] = speed if factor is None else fence["speed"] * factor
        return fence["speed"]
    for item in tree["impact"]:
        velocity = np.asarray(item["velocity"], float)
        norm = float(np.linalg.norm(velocity))
        new = speed if factor is None else norm * factor
        item["velocity"] = [float(c) for c in velocity * (new / norm)]
    return float(np.linalg.norm(tree["impact"][0]["velocity"]))


def draw(case, tree, k):
    """Apply member k's random draws to a tree; return (changes, drawn): the keys as the
    member states them, and what was drawn (speed [m/s], point offset [m], rotation, factors)."""
    v, seed = case.values, case.values["ensemble.seed"]
    changes, drawn = {}, {}
    point_key = "fence.impact_point" if case.kind == "fence" else "impact.point"
    turn_key = "fence.block_orientation" if case.kind == "fence" else "impact.orientation"
    items = [tree["fence"]] if case.kind == "fence" else tree.get("impact", [])
    if v["ensemble.slack_seeds"]:
        tree["materials"]["slack_seed"] = int(_rng(seed, k, SLACK).integers(0, 2 ** 31 - 1))
        changes["materials.slack_seed"] = tree["materials"]["slack_seed"]
    if v["ensemble.point_radius"] > 0:
        dx, dy = _disc(_rng(seed, k, POINT), v["ensemble.point_radius"])
        drawn["point_offset"] = [dx, dy]
        name = point_key.split(".")[1]
        for item in items:
            item[name] = [item[name][0] + dx, item[name][1] + dy]
        changes[point_key] = _first(tree, point_key)
    if v["ensemble.speed"] != "fixed":
        rng = _rng(seed, k, SPEED)
        if v["ensemble.speed"] == "normal":
            factor, speed = _normal_factor(rng, v["ensemble.speed_cov"]), None
            drawn["speed_factor"] = factor
        else:
            factor, speed = None, float(rng.uniform(*v["ensemble.speed_range"]))
        drawn["speed"] = _set_speed(case, tree, factor, speed)
        speed_key = "fence.speed" if case.kind == "fence" else "impact.velocity"
        changes[speed_key] = _first(tree, speed_key)
    if v["ensemble.orientation"] == "random":
        q = random_quaternion(_rng(seed, k, ORIENTATION))
        drawn["rotation"] = q
        name = turn_key.split(".")[1]
        for item in items:
            item[name] = list(compose(q, item[name]))
        changes[turn_key] = _first(tree, turn_key)
    if v["ensemble.material_cov"] > 0:
        for stream, keys, label in ((WIRES, WIRE_KEYS, "wires"), (ROPES, ROPE_KEYS, "ropes")):
            factor = _normal_factor(_rng(seed, k, stream), v["ensemble.material_cov"])
            drawn[f"{label}_factor"] = factor
            for path in keys:
                if path in case.values:
                    _put(tree, path, _scaled(_get(tree, path), factor))
    if v["ensemble.friction_cov"] > 0:
        factor = _normal_factor(_rng(seed, k, FRICTION), v["ensemble.friction_cov"])
        drawn["friction_factor"] = factor
        tree["contact"]["mu"] = tree["contact"]["mu"] * factor
        changes["contact.mu"] = tree["contact"]["mu"]
    return changes, drawn


def varied_keys(case):
    """The keys the random variations change (a sweep or a sensitivity study must not)."""
    v = case.values
    fence = case.kind == "fence"
    keys = []
    if v["ensemble.slack_seeds"]:
        keys.append("materials.slack_seed")
    if v["ensemble.point_radius"] > 0:
        keys.append("fence.impact_point" if fence else "impact.point")
    if v["ensemble.speed"] != "fixed":
        keys.append("fence.speed" if fence else "impact.velocity")
    if v["ensemble.orientation"] == "random":
        keys.append("fence.block_orientation" if fence else "impact.orientation")
    if v["ensemble.material_cov"] > 0:
        keys += [p for p in WIRE_KEYS + ROPE_KEYS if p in v]
    if v["ensemble.friction_cov"] > 0:
        keys.append("contact.mu")
    return keys


# ---------------------------------------------------------------------------------------------
# checks and members

def _a(word):
    """The word with its indefinite article ('an impact', 'a fence')."""
    return ("an " if word[:1] in "aeiou" else "a ") + word


class _Checks:
    """The rules of the [ensemble] keys beyond each key's own (one CaseFileError each)."""

    def __init__(self, case):
        self.case, self.v = case, case.values

    def fail(self, key, message):
        raise CaseFileError(f"{self.case.path}: {key}: {message}")

    def all(self):
        v = self.v
        if v["ensemble.slack_seeds"] and not v["materials.slack_u"] > 0:
            self.fail("ensemble.slack_seeds", "materials.slack_u is 0: the wires have no slack "
                                              "to draw (set materials.slack_u > 0)")
        if v["ensemble.speed"] != "uniform" and list(v["ensemble.speed_range"]) != [0.0, 0.0]:
            self.fail("ensemble.speed_range", f"{v['ensemble.speed_range']}: a range of speeds "
                                              "is for ensemble.speed = \"uniform\" (it is "
                                              f"{v['ensemble.speed']!r})")
        cov = schema.BY_PATH["ensemble.speed_cov"]
        if (v["ensemble.speed"] != "normal" and "ensemble.speed_cov" in self.case.stated
                and v["ensemble.speed_cov"] != cov.default):
            self.fail("ensemble.speed_cov", f"{v['ensemble.speed_cov']:g}: a coefficient of "
                                            "variation of the speed is for ensemble.speed = "
                                            f"\"normal\" (it is {v['ensemble.speed']!r})")
        if v["ensemble.speed"] == "uniform":
            lo, hi = v["ensemble.speed_range"]
            if not 0 < lo < hi:
                self.fail("ensemble.speed_range", f"{[lo, hi]}: must be [low, high] with 0 < "
                                                  "low < high [m/s] for ensemble.speed = uniform")
        if v["ensemble.sweep"] and v["ensemble.sensitivity"]:
            self.fail("ensemble.sweep", "a sweep and a sensitivity study are two ensembles: "
                                        "one case file each")
        if v["ensemble.values"] and not v["ensemble.sweep"]:
            self.fail("ensemble.values", "values without ensemble.sweep (the key they are of)")
        if v["ensemble.sweep"]:
            self.sweep()
        if v["ensemble.sensitivity"]:
            if v["ensemble.members"] > 1 or varied_keys(self.case):
                self.fail("ensemble.sensitivity", "one key at a time against one base case: no "
                                                  "random members or variations beside it "
                                                  "(ensemble.members = 1)")

    def known(self, label, path):
        """The Key of a path the case takes, or one line naming what is wrong with it."""
        key = schema.BY_PATH.get(path)
        if key is None or key.section == "ensemble" or path in ("kind", "title"):
            names = [k.path for k in schema.KEYS if schema.applies(k, self.case.kind)
                     and k.section != "ensemble"]
            self.fail(label, f"{path!r}: not a key of {_a(self.case.kind)} case" +
                      casefile._suggest(path, names))
        if not schema.applies(key, self.case.kind):
            self.fail(label, f"{path}: not a key of {_a(self.case.kind)} case")
        return key

    def sweep(self):
        path = self.v["ensemble.sweep"]
        self.known("ensemble.sweep", path)
        if not self.v["ensemble.values"]:
            self.fail("ensemble.values", f"the values of {path} to sweep (a list of at least one)")
        if path in varied_keys(self.case):
            self.fail("ensemble.sweep", f"{path} is also drawn at random by the [ensemble] "
                                        "variations; sweep it or draw it, not both")

    def sensitivity_keys(self):
        """(keys to scale, [(unsourced key, why it is left out)])."""
        asked = self.v["ensemble.sensitivity"]
        if asked == "unsourced":
            keys, skipped = [], []
            for item in schema.unsourced(self.case):
                key = schema.BY_PATH[item["key"]]
                if key.type not in SCALABLE:
                    article = "an" if key.type[0] in "aeiou" else "a"
                    skipped.append((key.path, f"{article} {key.type}: a factor does not scale "
                                              "it"))
                elif self._is_zero(key.path):
                    skipped.append((key.path, "0: no factor changes it"))
                else:
                    keys.append(key.path)
            if not keys:
                self.fail("ensemble.sensitivity", "'unsourced': every number of this case has a "
                                                  "source; name the keys to vary instead")
            return keys, skipped
        for path in asked:
            key = self.known("ensemble.sensitivity", path)
            if key.type not in SCALABLE:
                self.fail("ensemble.sensitivity", f"{path} is a {key.type}; a factor scales "
                                                  "numbers and [[strain, stress]] tables")
            if self._is_zero(path):
                self.fail("ensemble.sensitivity", f"{path} is 0 in this case: no factor "
                                                  "changes it")
        if len(set(asked)) != len(asked):
            self.fail("ensemble.sensitivity", f"a key named twice: {asked}")
        return list(asked), []

    def _is_zero(self, path):
        key = schema.BY_PATH[path]
        if key.per_item:
            return all(not item[key.name] for item in self.case.impacts)
        return not self.case.values[path]


def _set_key(case, tree, path, value):
    """Set a key in a tree: a key of [[impact]] in every entry."""
    key = schema.BY_PATH[path]
    if key.per_item:
        for item in tree[key.section]:
            item[key.name] = copy.deepcopy(value)
    else:
        _put(tree, path, copy.deepcopy(value))


def _scale_key(case, tree, path, factor):
    key = schema.BY_PATH[path]
    if key.per_item:
        for item in tree[key.section]:
            item[key.name] = _scaled(item[key.name], factor)
        return tree[key.section][0][key.name]
    _put(tree, path, _scaled(_get(tree, path), factor))
    return _get(tree, path)


def plan(case):
    """(mode, [(Member, tree)]) of the case's [ensemble] section, and the unsourced keys a
    sensitivity study leaves out."""
    checks = _Checks(case)
    checks.all()
    v = case.values
    n = v["ensemble.members"]
    base = case_tree(case)
    out, skipped = [], []
    if v["ensemble.sensitivity"]:
        keys, skipped = checks.sensitivity_keys()
        out.append((Member("member_000", 0, "base"), copy.deepcopy(base)))
        for key in keys:
            for factor in v["ensemble.factors"]:
                tree = copy.deepcopy(base)
                scaled = _scale_key(case, tree, key, factor)
                k = len(out)
                out.append((Member(f"member_{k:03d}", k, f"{key} x {factor:g}", {key: scaled},
                                   key=key, factor=factor), tree))
        return "sensitivity", out, skipped
    if v["ensemble.sweep"]:
        path = v["ensemble.sweep"]
        for j, value in enumerate(v["ensemble.values"]):
            for r in range(n):
                tree = copy.deepcopy(base)
                _set_key(case, tree, path, value)
                changes, drawn = draw(case, tree, r)
                k = j * n + r
                label = f"{path} = {_toml_value(value)}" + (f", draw {r}" if n > 1 else "")
                out.append((Member(f"member_{k:03d}", k, label, {path: value, **changes},
                                   drawn, sweep_value=value), tree))
        return "sweep", out, skipped
    for k in range(n):
        tree = copy.deepcopy(base)
        changes, drawn = draw(case, tree, k)
        out.append((Member(f"member_{k:03d}", k, f"draw {k}", changes, drawn), tree))
    return "random", out, skipped


def _where(case, member):
    """The [ensemble] key a member's failed check goes back to (the one-line error's label)."""
    v = case.values
    if member.key:
        return f"ensemble.sensitivity ({member.label})"
    if member.sweep_value is not None:
        return f"ensemble.values[{member.index // v['ensemble.members'] + 1}]"
    return f"ensemble ({member.name}, seed {v['ensemble.seed']})"


def expand(case, out):
    """The Ensemble of a case whose [ensemble] section is active: its members as checked Cases
    named NAME/member_KKK, each checked from the text of its case file (member_text), which the
    study writes to OUT/NAME/member_KKK/case.toml (``out``: the study folder, absolute; nothing
    is written here)."""
    mode, planned, skipped = plan(case)
    cases = []
    for member, tree in planned:
        name = f"{case.name}/{member.name}"
        path = os.path.join(out, case.name, member.name, "case.toml")
        text = member_text(tree, member.name, case.name)
        try:
            # every value is stated: checked as a full case whatever the mode (--quick turns a
            # stated value equal to a full default into its quick value), then marked quick
            member_case = casefile.Checker(path, tomllib.loads(text), False, name).case()
        except CaseFileError as exc:
            inner = str(exc)[len(path) + 2:] if str(exc).startswith(path) else str(exc)
            raise CaseFileError(f"{case.path}: {_where(case, member)}: {inner}") from None
        member_case.quick = case.quick
        member_case.member_of, member_case.member_text = case.name, text
        cases.append(member_case)
    return Ensemble(case.name, case, mode, [m for m, _ in planned], cases,
                    [dict(key=k, why=w) for k, w in skipped])


def write_manifest(out, ensemble):
    """OUT/NAME/ensemble.json: what each member of the ensemble changes."""
    ensembles.write_manifest(os.path.join(out, ensemble.name, ensembles.MANIFEST),
                             ensemble.manifest())
