"""Ensembles in a study folder (runner/ensemble.py writes them; doc/ensembles.md): DIR/NAME/
ensemble.json (what each member changes) and one case folder per member, DIR/NAME/member_KKK.
Here: each member's outputs, their statistics (postprocess/statistics.py), the probability of
breakthrough, how the statistics settle as members are added, a sweep's outputs per value, a
sensitivity study's table, and the difference between a compound-net and a square-net
ensemble. No markdown of the rest of the report and no figures here (ensemble_plots.py)."""

import itertools
import os
from dataclasses import dataclass, field

from . import casefolders, statistics
from .errors import PostprocessError
from .meta import read_json_object
from .summary import case_summary

MANIFEST = "ensemble.json"      # DIR/NAME/ensemble.json: the ensemble's members


@dataclass(frozen=True)
class Output:
    """One output of a member: its name in summary.json, its label and unit in the report
    (values in SI divided by ``scale``)."""
    name: str
    label: str
    unit: str
    scale: float = 1.0


FENCE_OUTPUTS = (
    Output("braking_distance", "braking distance", "m"),
    Output("residual_height", "residual height", "m"),
    Output("residual_height_ratio", "residual height / nominal", "%", 0.01),
    Output("anchor_peak", "peak anchor force", "kN", 1e3),
    Output("post_base_peak", "peak post-base force", "kN", 1e3),
    Output("broken_bonds", "ruptures", "-"),
)
IMPACT_OUTPUTS = (
    Output("max_displacement", "max block travel", "m"),
    Output("peak_block_force", "peak block force", "kN", 1e3),
    Output("edge_force_peak", "peak support force (all supports)", "kN", 1e3),
    Output("side_force_peak", "peak force on one edge", "kN", 1e3),
    Output("broken_bonds", "ruptures", "-"),
)
# the outputs of a sensitivity table and of the compound vs square comparison, per kind
SENSITIVITY = {"fence": ("anchor_peak", "post_base_peak", "braking_distance", "residual_height"),
               "impact": ("peak_block_force", "edge_force_peak", "max_displacement")}
COMPARED = {"fence": ("post_base_peak", "anchor_peak"),
            "impact": ("edge_force_peak", "side_force_peak", "peak_block_force")}


def _family_output(prefix, family, what):
    return Output(f"{prefix}:{family}", f"{what}, {family}", "kN", 1e3)


def member_outputs(kind, meta, summary):
    """{output name: value (SI)} of one member, and whether the block broke through."""
    if kind == "fence":
        f = summary.get("fence") or {}
        values = {o.name: f.get(o.name) for o in FENCE_OUTPUTS if o.name in f}
        values["residual_height"] = meta.get("residual_height")
        if meta.get("rest_skipped"):
            # the block left the fence moving on: a failed test has no residual height (the
            # ropes' gap at the impact's end, torn, is not one to average with the others)
            values["residual_height"] = values["residual_height_ratio"] = None
        for family, peak in sorted((f.get("rope_peaks") or {}).items()):
            values[f"rope:{family}"] = peak
        stopped = f.get("block_stopped")
        return values, None if stopped is None else not stopped
    impact = summary.get("impact") or {}
    values = {o.name: impact.get(o.name) for o in IMPACT_OUTPUTS}
    for family, zone in sorted((summary.get("zone") or {}).items()):
        values[f"zone:{family}"] = zone.get("peak_total_tension")
    verdict = meta.get("block_verdict")
    return values, None if verdict is None else verdict == "passed through"


def outputs_of(kind, members):
    """The Outputs the members hold, in the report's order (the kind's, then the families'
    that carry a load in some member)."""
    fixed = FENCE_OUTPUTS if kind == "fence" else IMPACT_OUTPUTS
    names = list(dict.fromkeys(n for m in members.values() for n in m["outputs"]))
    out = [o for o in fixed if o.name in names]
    for name in names:
        # a family's peak that is 0 in every member is a family the net does not have
        if ":" in name and any(m["outputs"].get(name) for m in members.values()):
            prefix, family = name.split(":", 1)
            out.append(_family_output(prefix, family, "peak rope tension" if prefix == "rope"
                                      else "peak zone tension (total)"))
    return out


@dataclass
class Ensemble:
    name: str
    path: str
    manifest: dict
    members: dict = field(default_factory=dict)     # member name: casefolders.Case or None


def discover(directory):
    """{name: Ensemble} of the sub-folders of ``directory`` holding ensemble.json."""
    found = {}
    for name in sorted(os.listdir(directory)):
        path = os.path.join(directory, name, MANIFEST)
        if name.startswith(".") or not os.path.isfile(path):
            continue
        manifest = read_json_object(path)
        check_manifest(path, manifest)
        ensemble = Ensemble(name, os.path.dirname(path), manifest)
        for member in manifest["members"]:
            folder = os.path.join(ensemble.path, member["name"])
            has_record = os.path.isfile(os.path.join(folder, "case.json"))
            ensemble.members[member["name"]] = \
                casefolders.load_case(folder) if has_record else None
        found[name] = ensemble
    return found


def check_manifest(path, manifest):
    """One PostprocessError line for an ensemble.json the report cannot read: its members a
    list of objects, each named by a folder beside it, what it changes and drew objects."""
    members = manifest.get("members")
    if not isinstance(members, list):
        raise PostprocessError(f"{path}: 'members' must be a list")
    for k, member in enumerate(members):
        where = f"{path}: members[{k}]"
        if not isinstance(member, dict):
            raise PostprocessError(f"{where}: expected an object {{...}}")
        name = member.get("name")
        if not isinstance(name, str) or not name or name in (".", "..") or \
                os.sep in name or "/" in name:
            raise PostprocessError(f"{where}: 'name' must be the name of a folder beside "
                                   f"{MANIFEST}, got {name!r}")
        for key in ("changes", "drawn"):
            if not isinstance(member.get(key) or {}, dict):
                raise PostprocessError(f"{where}: '{key}' must be an object")
    for key in ("sweep", "sensitivity"):
        if not isinstance(manifest.get(key) or {}, dict):
            raise PostprocessError(f"{path}: '{key}' must be an object or null")


def member_summaries(ensemble):
    """{member: its case summary (postprocess/summary.py) with label, outputs, breakthrough,
    what it changes}; a member without a folder: status 'missing'."""
    out = {}
    for member in ensemble.manifest["members"]:
        case = ensemble.members.get(member["name"])
        if case is None:
            summary = {"status": "missing", "kind": ensemble.manifest.get("kind"), "errors": []}
            values, through = {}, None
        else:
            summary = case_summary(case)
            values, through = member_outputs(case.kind, case.meta, summary)
        summary.update(label=member.get("label"), changes=member.get("changes") or {},
                       drawn=member.get("drawn") or {}, sweep_value=member.get("sweep_value"),
                       key=member.get("key"), factor=member.get("factor"),
                       outputs=values, breakthrough=through)
        out[member["name"]] = summary
    return out


def _usable(members):
    return {n: m for n, m in members.items() if m["status"] == "ok" and not m.get("errors")}


def statistics_of(members, outputs):
    """{output: statistics.describe} over the members that ended ok, and how the mean and the
    quantiles settle as members are added (member order)."""
    ok = _usable(members)
    stats, settling = {}, {}
    for o in outputs:
        values = [m["outputs"].get(o.name) for m in ok.values()]
        stats[o.name] = statistics.describe(values)
        settling[o.name] = statistics.running(values)
    return stats, settling


def breakthrough(members):
    """P(breakthrough) over the members that ended ok and say (Wilson's interval)."""
    said = [m["breakthrough"] for m in _usable(members).values() if m["breakthrough"] is not None]
    return statistics.wilson(sum(bool(b) for b in said), len(said))


def sweep_rows(manifest, members, outputs):
    """Per swept value: its members' mean of every output and their P(breakthrough) ({value,
    n, breakthrough, means: {output: mean}})."""
    rows = []
    ok = _usable(members)
    for value in (manifest.get("sweep") or {}).get("values", []):
        group = {k: m for k, m in ok.items() if m["sweep_value"] == value}
        rows.append(dict(value=value, n=len(group), breakthrough=breakthrough(group), means={
            o.name: statistics.describe([m["outputs"].get(o.name) for m in group.values()])[
                "mean"] for o in outputs}))
    return rows


def sensitivity_rows(kind, members):
    """One row per scaled key and factor: the change of each of the kind's sensitivity outputs
    against the base member (absolute, SI, and relative); [] without a base that ended ok."""
    base = next((m for m in members.values() if m["key"] is None), None)
    if base is None or base["status"] != "ok":
        return []
    rows = []
    for name, m in members.items():
        if m["key"] is None:
            continue
        changes = {}
        for output in SENSITIVITY.get(kind, ()):
            b, v = base["outputs"].get(output), m["outputs"].get(output)
            ok = m["status"] == "ok" and b is not None and v is not None
            changes[output] = dict(absolute=v - b if ok else None,
                                   relative=(v - b) / b if ok and b else None)
        rows.append(dict(member=name, key=m["key"], factor=m["factor"], status=m["status"],
                         changes=changes))
    return rows


def summarize(ensemble):
    """The ensemble's part of summary.json."""
    manifest = ensemble.manifest
    members = member_summaries(ensemble)
    kind = manifest.get("kind")
    outputs = outputs_of(kind, members)
    stats, settling = statistics_of(members, outputs)
    return dict(kind=kind, mode=manifest.get("mode"), quick=manifest.get("quick"),
                case_file=manifest.get("case_file"), seed=manifest.get("seed"),
                variations=manifest.get("variations"), sweep=manifest.get("sweep"),
                sensitivity=manifest.get("sensitivity"), net=_net(ensemble),
                dissipation=_dissipation(ensemble),
                outputs=[dict(name=o.name, label=o.label, unit=o.unit, scale=o.scale)
                         for o in outputs],
                members=members, statistics=stats, settling=settling,
                breakthrough=breakthrough(members),
                sweep_rows=sweep_rows(manifest, members, outputs)
                if manifest.get("mode") == "sweep" else [],
                sensitivity_rows=sensitivity_rows(kind, members)
                if manifest.get("mode") == "sensitivity" else [])


def _first_meta(ensemble, key):
    for case in ensemble.members.values():
        if case is not None and case.meta.get(key) is not None:
            return case.meta[key]
    return None


def _net(ensemble):
    fence = _first_meta(ensemble, "fence")
    return fence.get("net") if isinstance(fence, dict) else _first_meta(ensemble, "panel")


def _dissipation(ensemble):
    return _first_meta(ensemble, "dissipation")


def comparisons(summaries):
    """The paper's comparison between ensembles: for every compound-net and square-net
    ensemble of the same kind, mode and dissipation model (random members), the difference of
    the means of the kind's post and anchor (panel: support) loads, compound - square, with
    Welch's interval (independent samples), the ratio of the means, and, where the members
    of the two ensembles drew the same (the same seed and variations: member k of each got the
    same point, speed, turn and factors), the paired difference (paired)."""
    rows = []
    for (a, ea), (b, eb) in itertools.permutations(summaries.items(), 2):
        if not (ea["net"] == "compound" and eb["net"] == "square" and ea["kind"] == eb["kind"]
                and ea["quick"] == eb["quick"] and ea["dissipation"] == eb["dissipation"]
                and ea["mode"] == eb["mode"] == "random"):
            continue
        for output in COMPARED.get(ea["kind"], ()):
            values = [[m["outputs"].get(output) for m in _usable(e["members"]).values()]
                      for e in (ea, eb)]
            result = statistics.welch(*values)
            if result is not None:
                rows.append(dict(compound=a, square=b, output=output, kind=ea["kind"],
                                 quick=ea["quick"], **result,
                                 paired=paired_difference(ea, eb, output)))
    return rows


def _draws(member):
    """What a member drew (its point, speed, turn, factors and slack seed), comparable across
    ensembles; None when it drew nothing."""
    drawn = dict(member.get("drawn") or {})
    seed = (member.get("changes") or {}).get("materials.slack_seed")
    if seed is not None:
        drawn["slack_seed"] = seed
    return drawn or None


def paired_difference(ea, eb, output):
    """The mean of the members' differences a_k - b_k over the members k of the same name that
    drew the same in both ensembles and ended ok (common random numbers: what the draws do to
    both cancels), with its t interval: dict(difference, low, high, n, method); None unless
    the two ensembles share their draws (same seed and variations) and 2 pairs or more."""
    if ea.get("seed") != eb.get("seed") or ea.get("variations") != eb.get("variations"):
        return None
    ok_a, ok_b = _usable(ea["members"]), _usable(eb["members"])
    diffs = []
    for name, ma in ok_a.items():
        mb = ok_b.get(name)
        if mb is None or _draws(ma) is None or _draws(ma) != _draws(mb):
            continue
        va, vb = ma["outputs"].get(output), mb["outputs"].get(output)
        if va is not None and vb is not None:
            diffs.append(va - vb)
    if len(diffs) < 2:
        return None
    s = statistics.describe(diffs)
    low, high = s["mean_interval"]
    return dict(difference=s["mean"], low=low, high=high, n=s["n"],
                method="paired t (the same draws)")


def all_member_summaries(ensembles):
    """{'NAME/member_KKK': member summary} of every ensemble (the study's statuses)."""
    return {f"{name}/{member}": m for name, e in ensembles.items()
            for member, m in e["members"].items()}


def write_manifest(path, manifest):
    """An ensemble's ensemble.json (runner/ensemble.py writes it through this one home)."""
    from .output import write_json
    write_json(path, manifest)
