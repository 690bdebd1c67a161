"""DIR/report.md and DIR/summary.json: per-case peaks, the paper's three claims, the figures.

Only numbers read from the case folders are reported; cases that did not end "ok" are listed with
their status; the paper's claims are judged on the cases that can show them
(postprocess/claims.py), under each dissipation model the study holds.
"""

import json
import os


from . import casefolders, claims, datasheet, ensemble_report, ensembles
from .summary import case_summary
from .claims import CLAIMS
from .output import Outputs, json_text

# --- numbers per case -----------------------------------------------------------------------

def _drop_words(drop):
    """How punch.stop_drop ended a run, for the report's list of endings ('' if it did not)."""
    if not isinstance(drop, dict):
        return ""
    return (f"; stopped at {fmt(drop.get('displacement'))} m, the force down to "
            f"{fmt(drop.get('force'))} N from its peak {fmt(drop.get('peak_force'))} N "
            "(punch.stop_drop)")


def _residual_mark(facts):
    """What the residual height in the fence table is marked with: measured at the impact's end,
    or after a rest that ended at its time limit with the ropes still moving; a block that left
    the fence moving on has no rest (the test failed)."""
    if facts.get("rest_skipped"):
        return " (end: block went on)"
    if facts["residual_height_at"] != "rest":
        return " (end)"
    return " (ropes still moving)" if facts.get("rest_settled") is False else ""


FENCE_NOTE = (
    "EAD 340059-00-0106 results of each fence case (runner/fence.py, doc/fence.md): braking "
    "distance = the block's largest travel along the fence normal after first touch (block "
    "stopped: its velocity along the normal turned; a block that flies over or through the "
    "fence never turns, and its braking distance is how far it flew); residual "
    "height = least vertical distance between top and bottom support rope over the middle module "
    "after the block and the fence have come to rest (fence.rest_time; marked 'end' where it "
    "was measured at the end of the impact, 'end: block went on' where the block left the fence "
    "moving on, a failed test with no rest to find; 'ropes still moving' where the rest ended at its "
    "time limit with the middle module's ropes still moving), over the nominal height (the guideline's "
    "categories: A >= 50 %, B 30-50 %, C < 30 %); an SEL case (fence.impacts = 2) has a second "
    "row for the second impact on the unrepaired fence; weight on the supports, settled = the "
    "vertical reactions of anchors, post bases and ground at the settling's end over the fence's "
    "weight (within 1 % of 100 % when the settling ended at rest; a fence whose settling ran out "
    "of fence.settle_time first is not-settled and released out of equilibrium: doc/fence.md, "
    "\"Settling\"); at rest = the same at the rest's end over the weight of the fence and of "
    "the block if it touches the fence (what it misses, the rest's damping holds: a fence "
    "still creeping when its residual height is read); "
    "peaks are window means of the reactions (fence.row_time). Closure and momentum as for the "
    "impact cases.")


COMPONENT_NOTE = (
    "Where each fence case's energy went (kJ): the bonds' energy of fix wirenet/bonds' per-type "
    "tallies summed per component (runner/fence.py: net = the net's wires and strand ropes, ropes "
    "= support and upslope ropes, brakes, posts), dissipated over the impact (plastic work, "
    "energy released at ruptures) or held (elastic energy: its peak during the impact); the rest "
    "of the budget as its terms at the end of the impact (shackle friction, local and bond "
    "damping, the block's and the ground's contacts, kinetic energy of block and fence).")


def _component_row(name, f):
    """One row of the energy-per-component table, None without the tallies (older cases)."""
    parts, final = f.get("components"), f.get("energy_final") or {}
    if not parts:
        return None

    def kj(value):
        return fmt(value / 1e3 if value is not None else None)

    def part(c, k):
        return (parts.get(c) or {}).get(k)
    damping = sum(final.get(k, 0.0) for k in ("damping", "bond_damping"))
    contacts = sum(final.get(k, 0.0) for k in ("contact", "contact_layers", "ground"))
    kinetic = sum(final.get(k, 0.0) for k in ("ke_block", "ke_net"))
    return [name, kj(f.get("block_energy")), kj(part("net", "plastic")), kj(part("net", "released")),
            kj(part("net", "elastic_peak")), kj(part("ropes", "elastic_peak")),
            kj(part("ropes", "released")), kj(part("brakes", "plastic")),
            kj(part("posts", "elastic_peak")), kj(final.get("friction")), kj(damping),
            kj(contacts), kj(kinetic)]


DRAPERY_NOTE = (
    "A mesh hung on a slope from its top anchors and bolted on a grid, hit by a block or a "
    "debris heap from upslope (runner/kinds/drapery.py, doc/drapery.md). Load energy: the "
    "largest energy of a term of the budget (the load's kinetic energy at the release, or the "
    "potential energy it gives up coming down from rest), to which the closure is relative; "
    "load: where the block ended, or the shares of the debris' spheres; travel: of the block "
    "or the heap's centre of mass, down the slope from the release; bulge: the largest rise "
    "of the mesh off the slope, normal to it, since it settled; bulge before the load: the "
    "mesh's own rise before the load touched it (more than a tenth of the bulge: status "
    "not-settled, doc/drapery.md \"Settling\"); anchors: the largest window-mean force of one "
    "anchor of the top row and of the grid, and of the top row together (fix wirenet/hold "
    "... each).")


def _fence_rows(fences):
    """(row name, facts) of each fence case, and of its second impact (SEL) after it."""
    for name, facts in fences.items():
        yield name, facts
        if facts.get("second"):
            yield f"{name}, 2nd impact", facts["second"]


def fence_comparison(summaries):
    """The paper's post-load claim at fence scale: compound vs square net, same block energy and
    the same dissipation model (the claims' rule, postprocess/claims.py); None without such a pair."""
    fences = {n: s["fence"] for n, s in summaries.items() if s.get("fence") and s["status"] == "ok"}
    for name, c in fences.items():
        for other, q in fences.items():
            if c["net"] == "compound" and q["net"] == "square" and \
                    c["block_energy"] == q["block_energy"] and \
                    c.get("dissipation") == q.get("dissipation") and c["post_base_peak"] and \
                    q["post_base_peak"] and c["anchor_peak"] and q["anchor_peak"]:
                base = c["post_base_peak"] / q["post_base_peak"]
                anchor = c["anchor_peak"] / q["anchor_peak"]
                verdict = ("supported" if base < 1 else "not supported") + \
                    f" at fence scale: the compound net's peak post-base force is {base:.3f} x " \
                    f"the square net's (anchors {anchor:.3f} x)"
                return {"compound": name, "square": other, "post_base_ratio": base,
                        "anchor_ratio": anchor, "verdict": verdict,
                        "mode": summaries[name]["mode"]}
    return None


def panel_post_load_rows(summaries):
    """The paper's post-load conclusion at panel scale: for every group of impacts that differ
    only in their net (postprocess/claims.py), under each dissipation model, the compound
    panel's peak loads over the square panel's: the largest load on one edge (what a post or
    edge support is sized for) and the vector sum of all supports (the block's impulse)."""
    rows = []
    for model in claims.models(summaries):
        for (_, mode), nets in claims.impact_groups(summaries, model).items():
            if "compound" not in nets or "square" not in nets:
                continue
            c = summaries[nets["compound"]].get("impact") or {}
            q = summaries[nets["square"]].get("impact") or {}
            row = {"model": model, "mode": mode, "compound": nets["compound"],
                   "square": nets["square"]}
            for key in ("side_force_peak", "edge_force_peak"):
                a, b = c.get(key), q.get(key)
                row[key] = (a, b, a / b if a is not None and b else None)
            rows.append(row)
    return rows


def _post_load_lines(rows):
    if not rows:
        return []
    lines = ["", "## The post-load conclusion at panel scale", "",
             "The paper concludes that the hexagonal layer of the compound net lowers the load on "
             "the posts. Per dissipation model, the compound panel's peak loads against the square "
             "panel's under the same block: the largest load on one edge (a post or an edge "
             "support is sized for it) and the vector sum of all supports (the net force on the "
             "frame, in which the inward pulls of opposite edges cancel). A ratio below 1 "
             "supports the conclusion.", ""]
    lines += _table(["model", "mode", "compound", "square", "edge: compound [kN]",
                     "edge: square [kN]", "ratio", "sum: compound [kN]", "sum: square [kN]",
                     "ratio"],
                    [[claims.MODELS.get(r["model"], r["model"]), r["mode"], r["compound"],
                      r["square"], kn(r["side_force_peak"][0]), kn(r["side_force_peak"][1]),
                      fmt(r["side_force_peak"][2]), kn(r["edge_force_peak"][0]),
                      kn(r["edge_force_peak"][1]), fmt(r["edge_force_peak"][2])] for r in rows])
    return lines


def _percent(value):
    return "n/a" if value is None else f"{100 * value + 0.0:.3g} %"


# --- impact peak comparison (Figures 5 and 6) -----------------------------------------------

def impact_peak_rows(summaries):
    """Rows (model, family, single case, compound case ...) of the peak comparison single net vs
    compound, for every group of impacts that differ only in their net: peak total and peak
    maximum tension in the zone, and the compound / single ratios."""
    rows = []
    for model in claims.models(summaries):
        for nets in claims.impact_groups(summaries, model).values():
            compound = nets.get("compound")
            if compound is None:
                continue
            for net, families in (("hex", ("DT", "SW")), ("square", ("rope",))):
                single = nets.get(net)
                if single is None:
                    continue
                zone, zone_c = summaries[single].get("zone", {}), summaries[compound].get("zone", {})
                for family in families:
                    a, b = zone.get(family), zone_c.get(family)
                    if a is None and b is None:
                        continue

                    def value(entry, key):
                        return None if entry is None else entry[key]

                    def ratio(key):
                        x, y = value(a, key), value(b, key)
                        return y / x if x and y is not None else None
                    rows.append({"model": model, "family": family, "single": single,
                                 "compound": compound,
                                 "single_peak_total": value(a, "peak_total_tension"),
                                 "compound_peak_total": value(b, "peak_total_tension"),
                                 "ratio_total": ratio("peak_total_tension"),
                                 "single_peak_max": value(a, "peak_max_tension"),
                                 "compound_peak_max": value(b, "peak_max_tension"),
                                 "ratio_max": ratio("peak_max_tension")})
    return rows


# --- the two dissipation models side by side -------------------------------------------------

def dissipation_rows(summaries):
    """Per impact case, under each dissipation model the study holds for the same net and
    block: the energy each mechanism took by the impact's end (J and fractions of E0), closure,
    momentum, peak block and support forces, braking distance and the peak zone tension per
    family."""
    rows = []
    found = claims.models(summaries)
    if len(found) < 2:
        return rows
    by_load = {}
    for model in found:
        for (block, mode), nets in claims.impact_groups(summaries, model).items():
            for net, name in nets.items():
                by_load.setdefault((net, block, mode), []).append((model, name))
    for (net, _, _), cases in sorted(by_load.items(), key=lambda kv: str(kv[0])):
        if len(cases) < 2:
            continue
        for model, name in cases:
            s = summaries[name]
            facts = s.get("impact") or {}
            e0 = s.get("initial_energy")
            mechanisms = s.get("mechanisms") or {}
            rows.append({
                "case": name, "model": model, "mode": s["mode"], "initial_energy": e0,
                "mechanisms": mechanisms,
                "fractions": {k: (v / e0 if e0 else None) for k, v in mechanisms.items()},
                "closure_error": facts.get("closure_error"),
                "momentum_error": facts.get("momentum_error"),
                "peak_block_force": facts.get("peak_block_force"),
                "peak_block_force_windowed": facts.get("peak_block_force_windowed"),
                "force_window": facts.get("force_window"),
                "edge_force_peak": facts.get("edge_force_peak"),
                "side_force_peak": facts.get("side_force_peak"),
                "braking_distance": facts.get("max_displacement"),
                "peak_zone_total": {f: z["peak_total_tension"]
                                    for f, z in (s.get("zone") or {}).items()}})
    return rows


# --- expected cases -------------------------------------------------------------------------

def missing_cases(cases, expected=None):
    """Names of expected cases (the study's, when it says) absent from the directory."""
    return [name for name in (expected or ()) if name not in cases]


# --- markdown -------------------------------------------------------------------------------

def fmt(value, unit=""):
    """A number with 4 significant digits (and unit); n/a for None; other values as text."""
    if value is None:
        return "n/a"
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return str(value)
    return f"{value:.4g}{(' ' + unit) if unit else ''}"


def kn(value, unit=""):
    """A force in N shown in kN (the unit of every force of the report, as of the fence table
    and the paper's figures), 4 significant digits (and unit); n/a for None."""
    return fmt(value / 1e3 if isinstance(value, (int, float)) and not isinstance(value, bool)
               else value, unit)


def fmt_rupture(value):
    """First rupture of case.json: {displacement, force, bond: {...}} of a punch or
    {time, bond: {...}} of an impact (a bare number, from older case files, is a time)."""
    if not isinstance(value, dict):
        return fmt(value, "s")
    bond = value.get("bond") or {}
    where = (f"{fmt(value.get('displacement'), 'm')}, {kn(value.get('force'), 'kN')}"
             if "displacement" in value else fmt(value.get("time"), "s"))
    return f"{where}, {bond.get('family', '?')} bond {bond.get('atom1', '?')}-{bond.get('atom2', '?')}"


def _when(kind, time, displacement):
    """Where a zone peak happened: platter travel for a punch, time for an impact."""
    return fmt(displacement, "m") if kind == "punch" else fmt(time, "s")


IMPACT_NOTE = (
    "Closure: largest departure of the energy budget from its initial value relative to the "
    "initial energy; momentum: largest gap between the change of momentum of block + net and "
    "the impulses of supports, gravity and damping, relative to the block's initial momentum "
    "(case.json, energy.csv, momentum.csv, edges.csv, ruptures.csv).")
QUASI_STATIC_NOTE = (
    "Curve: largest |F - F_slow| against a run K times slower, relative to the peak force, up "
    "to the travel given; kinetic energy relative to the work done; equilibrium: largest gap "
    "between the platter force and the edge reactions relative to the peak reaction (and to the "
    "current one while the force is at least 10 % of its peak), and the travel from which every "
    "row balances within 1 % of its own reaction; all up to the first rupture (case.json, "
    "`quasi_static`; doc/punch.md). Required: 1 % each.")


DATASHEET_NOTE = (
    "The figures of a manufacturer's data sheet (doc/tensile.md): a punch's resistance is the "
    "platter's peak force and the travel at it; a tensile strip's strength is its peak force per "
    "metre of width, its elongation the clamp's travel over the clamp distance, at the peak and "
    "where the strip failed. Nominal values are those of the mesh type named beside them (the "
    "case's net may differ: compare like with like); a source starting with 'unverified:' was "
    "not read in the original, 'none:' means no nominal value was found. The model's punch is "
    "the case's own test (the paper's UNI 11437 set-up by default), not ASTM A975's.")


def datasheet_rows(summaries):
    for name, s in summaries.items():
        figures = s.get("datasheet")
        if figures:
            for label, model, nominal, source in datasheet.rows(s.get("panel"), figures):
                yield [name, str(s.get("panel")), label, model, nominal, source]


def _section(title, text):
    """Lines opening a report section: heading, explanatory paragraph, blank line."""
    return ["", f"## {title}", "", text, ""]


def _table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    lines += ["| " + " | ".join(row) + " |" for row in rows]
    return lines


def _case_rows(summaries):
    for name, s in summaries.items():
        status = s["status"] + (" (unreadable: " + "; ".join(s["errors"]) + ")"
                                if s["errors"] else "")
        yield [name, s["kind"], s["mode"], status, kn(s["peak_platter_force"]),
               kn(s["peak_block_force"]),
               fmt_rupture(s["first_rupture"]), kn(s["edge_force_peak"]),
               fmt(s["wall_time"])]


def _zone_rows(summaries):
    for name, s in summaries.items():
        for family, z in s.get("zone", {}).items():
            yield [name, family, kn(z["peak_total_tension"]),
                   _when(s["kind"], z["time_of_peak_total"], z["displacement_of_peak_total"]),
                   kn(z["peak_max_tension"]),
                   _when(s["kind"], z["time_of_peak_max"], z["displacement_of_peak_max"])]


def _claim_lines(claim):
    lines = [f"{claim['id']}. {claim['statement']}  ", f"   Verdict: **{claim['verdict']}**"]
    for e in claim["evidence"]:
        if claim["id"] == 3:
            lines.append(f"   - {e['square']} rope: peak total {kn(e['square_peak_total'], 'kN')}, "
                         f"peak max {kn(e['square_peak_max'], 'kN')}; {e['compound']} rope: "
                         f"peak total {kn(e['compound_peak_total'], 'kN')}, peak max "
                         f"{kn(e['compound_peak_max'], 'kN')} -> "
                         f"{'holds' if e['holds'] else 'does not hold'}")
        else:
            a, b = [k for k in e if k not in ("case", "holds")]
            lines.append(f"   - {e['case']}: {a} {kn(e[a], 'kN')} vs {b} {kn(e[b], 'kN')} -> "
                         f"{'holds' if e['holds'] else 'does not hold'}")
    lines += [f"   - {note}" for note in claim["notes"]]
    return lines


def _zone_lines(summaries):
    """Every output zone of the cases that have more than one (output.zones): the peak total
    and largest bond tension per family in each."""
    rows = []
    for name, s in summaries.items():
        if not s.get("other_zones"):
            continue
        zones = {"(first)": s.get("zone") or {}, **s["other_zones"]}
        for zone, families in zones.items():
            for family, peaks in families.items():
                rows.append([name, zone, family, kn(peaks["peak_total_tension"]),
                             kn(peaks["peak_max_tension"])])
    if not rows:
        return []
    return ["", "## Output zones", "",
            "Cases with more than one zone (output.zones; the first is zone_forces.csv, the "
            "others zone_forces_NAME.csv): the peak total and the peak largest bond tension of "
            "each family in each zone.", ""] + _table(
        ["case", "zone", "family", "peak total [kN]", "peak largest [kN]"], rows)


def _dissipation_lines(rows, verdicts):
    """The impact cases under each dissipation model (energy by mechanism, forces), and each
    claim's verdict under each."""
    if not rows:
        return []
    lines = ["", "## Dissipation models side by side", "", DISSIPATION_NOTE, ""]
    mechanisms = list(dict.fromkeys(k for r in rows for k in r["mechanisms"]))
    lines += _table(["case", "model", "mode", "E0 [J]"] + [f"{m} / E0" for m in mechanisms] +
                    ["closure", "momentum", "peak block force [kN]",
                     "block force, windowed peak [kN]", "peak support force [kN]",
                     "peak edge force [kN]", "braking distance [m]",
                     "peak zone total per family [kN]"],
                    [[r["case"], r["model"], r["mode"], fmt(r["initial_energy"])] +
                     [_percent(r["fractions"].get(m)) for m in mechanisms] +
                     [_percent(r["closure_error"]), _percent(r["momentum_error"]),
                      kn(r["peak_block_force"]), _windowed(r), kn(r["edge_force_peak"]),
                      kn(r["side_force_peak"]), fmt(r["braking_distance"]),
                      ", ".join(f"{f} {kn(v)}" for f, v in r["peak_zone_total"].items())]
                     for r in rows])
    names = list(verdicts)
    lines += ["", "Verdicts under each model (impact cases of that model; the quasi-static "
              "punches count under every model):", ""]
    lines += _table(["claim"] + [claims.MODELS.get(m, m) for m in names],
                    [[str(n)] + [verdicts[m][n - 1]["verdict"] for m in names]
                     for n in CLAIMS])
    return lines


def _windowed(row):
    """The block force's windowed peak in kN and its window, e.g. '84.5 (5 ms)'."""
    if row.get("peak_block_force_windowed") is None:
        return "-"
    return f"{kn(row['peak_block_force_windowed'])} ({row['force_window'] * 1e3:.3g} ms)"


DISSIPATION_NOTE = (
    "The same impacts under each dissipation model (doc/impact.md, \"Dissipation\"): the "
    "energy each mechanism dissipated by the end of the impact, as fractions of the initial "
    "energy E0 (case.json energy.mechanisms). The physical model damps no absolute velocity "
    "during the impact: plasticity, ruptures, friction and the bonds' structural damping (which "
    "conserves momentum) take the energy, and the supports carry all of the block's momentum. "
    "Local (Cundall) damping acts on each node's absolute motion, like a force to ground: under "
    "the paper's model it takes most of the energy and the supports feel less of the block's "
    "momentum. The peak block force is the largest mean over one output row (0.2 ms), the "
    "windowed peak the largest mean over output.force_window (the contact's plateau without "
    "the first touch's spike; case.json also holds the largest sampled value, "
    "peak_block_force_raw). The peak support force is the vector sum of all supports (the net force on the "
    "frame: the block's impulse); the peak edge force is the largest load on one edge (what "
    "that edge's support is sized for: opposite edges pull against each other, and the sum "
    "cancels that; edges.csv holds each edge's and the corners' reaction over time).")


def _bending_lines(summaries):
    """The rope beams' bending fraction of each case with ropes and where it came from (the
    case file, the study's calibration fit, or the paper's value when no fit exists)."""
    rows = [f"- {n}: {fmt(s['bending'])} ({s.get('bending_source') or 'not recorded'})"
            for n, s in summaries.items()
            if s.get("bending") is not None and s.get("panel") in ("square", "compound")]
    if not rows:
        return []
    return ["", "Bending fraction of the rope beams (materials.bending; doc/case_files.md):",
            ""] + rows


def bending_sensitivity(summaries):
    """What the rope beams' bending fraction changes in the cone punch of the study's
    calibration cases: {fractions: (low, high), peaks: (low, high), spread: (high - low) / low,
    mode}; None with fewer than two such cases. No published strand-rope net punch curve is
    digitised in tests/reference/, so the paper's "calibration" fits nothing here: the cases
    show how much the fraction moves the punch (issue #45)."""
    cases = [(s["bending"], s["peak_platter_force"], s["mode"]) for s in summaries.values()
             if s["kind"] == "calibration" and s["status"] == "ok" and
             s.get("bending") is not None and s.get("peak_platter_force")]
    if len(cases) < 2:
        return None
    peaks = [p for _, p, _ in cases]
    return {"fractions": (min(b for b, _, _ in cases), max(b for b, _, _ in cases)),
            "peaks": (min(peaks), max(peaks)), "spread": (max(peaks) - min(peaks)) / min(peaks),
            "mode": "quick" if any(m == "quick" for _, _, m in cases) else "full"}


def _bending_sensitivity_lines(summaries):
    found = bending_sensitivity(summaries)
    if found is None:
        return []
    (f0, f1), (p0, p1) = found["fractions"], found["peaks"]
    return ["", f"Bending-fraction sensitivity (Figure 2, the paper's \"calibration\"): fractions "
                f"{fmt(f0)} to {fmt(f1)} give cone-punch peaks of {fmt(p0)} to {fmt(p1)} N, a "
                f"spread of {_percent(found['spread'])}" +
                (" (quick cases)" if found["mode"] == "quick" else "") +
                ". No measured strand-rope net punch curve is at hand to fit, so the fraction is "
                "the paper's 0.05, not a calibration: it sets the ropes' bending stiffness (how "
                "the mesh folds over the cone's tip in the first centimetres) and barely moves "
                "the punch beyond them (doc/punch.md, \"What the bending fraction changes\"); "
                "`postprocess calibrate` fits it to a measured curve when one is given."]


def elapsed(records):
    """Seconds from the first start to the last end of cases that record both (case.json
    started, finished), or None when any finished case lacks them."""
    spans = [(r.get("started"), r.get("finished")) for r in records
             if isinstance(r.get("wall_time"), (int, float))]
    if not spans or not all(isinstance(a, (int, float)) and isinstance(b, (int, float))
                            for a, b in spans):
        return None
    return max(b for _, b in spans) - min(a for a, _ in spans)


SOURCES_NOTE = ("Every number of a case has its source beside it (inputs/include/materials.in, "
                "the key tables of doc/case_files.md). These have none that was read: "
                "'unverified' names a standard, paper or catalogue whose table was not read, "
                "'none' is an estimate or a numerical choice. Their sensitivity (each at 0.8x and "
                "1.2x: peak anchor and post-base forces, braking distance, residual height) is "
                "the sensitivity study's (doc/fence.md \"Sources\").")


def unsourced_rows(summaries):
    """[key, value(s), cases, source] of the numbers without a read source, over all cases."""
    seen = {}
    for name, s in summaries.items():
        for item in s.get("unsourced") or ():
            row = seen.setdefault(item["key"], {"values": [], "cases": [],
                                                "source": item["source"]})
            text = json.dumps(item["value"]) if isinstance(item["value"], list) \
                else fmt(item["value"])
            if text not in row["values"]:
                row["values"].append(text)
            row["cases"].append(name)
    return [[f"`{k}`", ", ".join(r["values"]), ", ".join(r["cases"]), r["source"]]
            for k, r in sorted(seen.items())]


def _sources_lines(summaries):
    rows = unsourced_rows(summaries)
    if not rows:
        return []
    return _section("Numbers without a source", SOURCES_NOTE) + _table(
        ["key", "value", "cases", "what is known"], rows)


def markdown(directory, summaries, verdicts, missing, figures, dissipation=(), ensembles_=None,
             comparisons=(), ensemble_figures=None):
    lines = ["# WireNet study report", "", f"Study directory: `{os.path.abspath(directory)}`", "",
             "## Cases", "", "Peak forces are the largest |force| of platter.csv / block.csv; "
             "first rupture, edge-force peak and wall time come from case.json (n/a: not "
             "recorded). Mode: `full` is the paper's case, `quick` the small, short version of "
             "`--quick`; a verdict drawn from quick cases says so.", ""]
    lines += _table(["case", "kind", "mode", "status", "peak platter force [kN]",
                     "peak block force [kN]",
                     "first rupture", "edge-force peak [kN]", "wall time [s]"],
                    list(_case_rows(summaries)))
    walls = [s["wall_time"] for s in summaries.values() if isinstance(s.get("wall_time"), (int, float))]
    if walls:
        lines += ["", f"Wall time of the cases: {sum(walls):.0f} s ({sum(walls) / 60:.1f} min) "
                      f"over {len(walls)} case(s) (each as case.json records it, whenever it ran)."]
        span = elapsed(summaries.values())
        if span is not None:
            lines[-1] += (f" From the first start to the last end: {span:.0f} s ({span / 60:.1f} "
                          "min; cases that ran side by side overlap).")
        cpus = [s["cpu_time"] for s in summaries.values()
                if isinstance(s.get("cpu_time"), (int, float))]
        if span and len(cpus) == len(walls):
            lines[-1] += (f" CPU time of their LIGGGHTS processes: {sum(cpus):.0f} core-seconds, "
                          f"{sum(cpus) / span:.2f} cores busy on average over that span.")
    endings = [f"- {n}: ended by {s['ended_by']}" +
               (f" at {fmt(s['first_rope_rupture']['displacement'])} m of platter travel"
                if s.get("first_rope_rupture") else "") + _drop_words(s.get("ended_at_drop"))
               for n, s in summaries.items() if s.get("ended_by")]
    if endings:
        lines += ["", "How each punch ended (rope strength: doc/bond_wirenet.md):", ""] + endings
    lines += _bending_lines(summaries)
    lines += _bending_sensitivity_lines(summaries)
    lines += ["", "## Tension in the central zone (zone_forces.csv)", ""]
    zone_rows = list(_zone_rows(summaries))
    lines += _table(["case", "family", "peak total tension [kN]", "at",
                     "peak max tension [kN]", "at"], zone_rows) if zone_rows else \
        ["No zone_forces.csv found."]
    impacts = {n: s["impact"] for n, s in summaries.items() if s.get("impact")}
    if impacts:
        lines += _section("Impact cases: energy budget, momentum, supports", IMPACT_NOTE)
        lines += _table(["case", "energy closure [-]", "momentum error [-]",
                         "max block travel [m]", "rebound at [s]", "peak block force [kN]",
                         "peak support force [kN]", "peak edge force [kN]", "broken bonds"],
                        [[n, fmt(i["closure_error"]), fmt(i["momentum_error"]),
                          fmt(i["max_displacement"]), fmt(i["rebound_time"]),
                          kn(i["peak_block_force"]), kn(i["edge_force_peak"]),
                          kn(i.get("side_force_peak")),
                          fmt(i["broken_bonds"])] for n, i in impacts.items()])
    evidence = {n: s["quasi_static"] for n, s in summaries.items() if s.get("quasi_static")}
    if evidence:
        lines += _section("Punch cases: quasi-static evidence", QUASI_STATIC_NOTE)
        lines += _table(["case", "K", "curve vs slower", "compared up to [m]",
                         "kinetic energy / work", "equilibrium / peak (/ current)",
                         "within 1 % of current from [m]", "snap events", "passed"],
                        [[n, fmt(q["slow_factor"]), _percent(q["curve_difference"]),
                          fmt(q["compared_up_to"]), _percent(q["kinetic_energy_fraction"]),
                          f"{_percent(q['equilibrium_error'])} "
                          f"({_percent(q['equilibrium_error_of_current'])})",
                          fmt(q["equilibrium_holds_from"]) if q["equilibrium_holds_from"]
                          is not None else "never", fmt(q["snap_events"]), fmt(q["passed"])]
                         for n, q in evidence.items()])
    sheet = list(datasheet_rows(summaries))
    if sheet:
        lines += _section("Data-sheet figures (punch and tensile cases)", DATASHEET_NOTE)
        lines += _table(["case", "net", "figure", "model", "nominal", "source of the nominal"],
                        sheet)
    peak_rows = impact_peak_rows(summaries)
    if peak_rows:
        lines += ["", "## Impact: peak tension, single net vs compound (Figures 5 and 6)", ""]
        lines += _table(["family", "single-net case", "peak total, single [kN]",
                         "peak total, compound [kN]", "compound / single",
                         "peak max, single [kN]", "peak max, compound [kN]", "compound / single"],
                        [[r["family"], r["single"], kn(r["single_peak_total"]),
                          kn(r["compound_peak_total"]), fmt(r["ratio_total"]),
                          kn(r["single_peak_max"]), kn(r["compound_peak_max"]),
                          fmt(r["ratio_max"])] for r in peak_rows])
    fences = {n: s["fence"] for n, s in summaries.items() if s.get("fence")}
    if fences:
        lines += _section("Fence cases (EAD 340059-00-0106)", FENCE_NOTE)
        lines += _table(["case", "net", "block energy [kJ]", "block stopped", "braking distance [m]",
                         "residual height", "final block speed [m/s]", "peak anchor [kN]",
                         "peak post base [kN]", "brake elongation [m]", "energy closure [-]",
                         "momentum error [-]", "broken bonds", "weight on the supports, settled",
                         "at rest"],
                        [[n, f["net"], fmt(f["block_energy"] / 1e3 if f["block_energy"] else None),
                          {True: "yes", False: "no"}.get(f["block_stopped"], "n/a"),
                          fmt(f["braking_distance"]), _percent(f["residual_height_ratio"]) +
                          _residual_mark(f),
                          fmt(f["final_block_speed"]),
                          f"{fmt(f['anchor_peak'] / 1e3 if f['anchor_peak'] else None)} "
                          f"({f['anchor']})",
                          f"{fmt(f['post_base_peak'] / 1e3 if f['post_base_peak'] else None)} "
                          f"({f['post_base']})",
                          fmt(f["brake_elongation_peak"]), fmt(f["closure_error"]),
                          fmt(f["momentum_error"]), fmt(f["broken_bonds"]),
                          _percent(f.get("weight_carried")),
                          _percent(f.get("weight_carried_rest"))]
                         for n, f in _fence_rows(fences)])
        comparison = fence_comparison(summaries)
        lines += ["", "The paper's post-load claim at fence scale (compound vs square net, same "
                      "fence and block): " + (comparison["verdict"] +
                                              (" (quick cases)" if comparison["mode"] == "quick"
                                               else "") if comparison else
                                              "not evaluated (needs a compound and a square "
                                              "fence case, both ok, with the same block "
                                              "energy and dissipation model).")]
        rows = [r for r in (_component_row(n, f) for n, f in _fence_rows(fences)) if r]
        if rows:
            lines += _section("Fence cases: energy per component", COMPONENT_NOTE)
            lines += _table(["case", "block energy", "net plastic", "net ruptures",
                             "net elastic peak", "ropes elastic peak", "ropes ruptures",
                             "brakes dissipated", "posts elastic peak", "shackle friction",
                             "damping", "contacts", "kinetic at end"], rows)
    draperies = {n: s["drapery"] for n, s in summaries.items() if s.get("drapery")}
    if draperies:
        lines += _section("Drapery cases", DRAPERY_NOTE)
        lines += _table(["case", "net", "slope [deg]", "load energy [kJ]", "load",
                         "travel [m]", "final speed [m/s]", "bulge [m]",
                         "bulge before the load [m]", "peak top anchor [kN]",
                         "peak grid anchor [kN]", "top row [kN]", "energy closure [-]",
                         "broken bonds"],
                        [[n, d["net"], fmt(d["slope"]),
                          fmt(d["block_energy"] / 1e3 if d["block_energy"] else None),
                          d["block_verdict"] or "n/a", fmt(d["travel"]), fmt(d["final_speed"]),
                          fmt(d["bulge"]), fmt(d.get("bulge_before_contact")),
                          kn(d["top_anchor_peak"]), kn(d["grid_anchor_peak"]),
                          kn(d["top_row_force_peak"]), fmt(d["closure_error"]),
                          fmt(d["broken_bonds"])] for n, d in draperies.items()])
    beams = {n: s for n, s in summaries.items() if s.get("beam")}
    for name, s in beams.items():
        lines += ["", f"## Beam check ({name})", ""]
        lines += _table(["elements", "load [N]", "tip deflection [m]", "analytic [m]",
                         "NRMSE [-]"],
                        [[fmt(r["elements"]), fmt(r["load"]), fmt(r["tip_deflection"]),
                          fmt(r["analytic_deflection"]), fmt(r["nrmse"])] for r in s["beam"]])
    for model, verdict in verdicts.items():
        lines += ["", "## The paper's claims" + (f" under {claims.MODELS.get(model, model)}"
                                                 if len(verdicts) > 1 else ""), ""]
        for claim in verdict:
            lines += _claim_lines(claim)
    lines += _zone_lines(summaries)
    lines += _dissipation_lines(list(dissipation), verdicts)
    lines += _post_load_lines(panel_post_load_rows(summaries))
    lines += ensemble_report.ensemble_lines(ensembles_ or {}, comparisons, ensemble_figures or {},
                                            directory)
    lines += _sources_lines(summaries)
    lines += ensemble_report.sensitivity_lines(ensembles_ or {})
    lines += ["", "## Cases that are missing or did not end ok", ""]
    absent = [f"- {name}: missing" for name in missing]
    absent += [f"- {n}: status {s['status']}" + (f": {s['verdict'] or s['error']}"
                                                 if s.get("verdict") or s.get("error") else "")
               for n, s in {**summaries, **ensembles.all_member_summaries(ensembles_ or {})
                            }.items() if s["status"] != "ok"]
    lines += absent or ["None."]
    lines += ["", "## Figures", ""]
    for name, paths in figures.items():
        png = os.path.relpath(paths[0], directory)
        lines += [f"![{name}]({png})", ""]
        if name.startswith("fig4_"):
            case = name[len("fig4_"):]
            lines += [f"Figure 4, {case}: the deformed net at its peak (punch: the frame nearest "
                      "the peak platter force before the first rupture; impact: the block's "
                      "lowest point), bonds coloured by tension, grey slack or compressed, red "
                      "crosses broken bonds. All frames for ParaView: "
                      f"`{case}/{case}.pvd` (net) and `{case}/{case}_body.pvd` (loading body).",
                      ""]
    if not figures:
        lines.append("No figures.")
    return "\n".join(lines) + "\n"


def build(directory, expected=None, figures=True):
    """Write DIR/report.md, DIR/summary.json and the figures, all or none; return the summary."""
    cases = casefolders.discover(directory)
    summaries = {name: case_summary(case) for name, case in cases.items()}
    found = ensembles.discover(directory)
    ensemble_summaries = {name: ensembles.summarize(e) for name, e in found.items()}
    comparisons = ensembles.comparisons(ensemble_summaries)
    verdicts = {}
    if claims.evaluable(summaries):
        verdicts = {m: claims.evaluate(summaries, m) for m in claims.models(summaries) or [None]}
    dissipation = dissipation_rows(summaries)
    missing = missing_cases({**cases, **ensembles.all_member_summaries(ensemble_summaries)},
                            expected)
    with Outputs() as outputs:
        written, ensemble_figures = {}, {}
        if figures:
            from .ensemble_plots import ensemble_figures as draw_ensembles
            from .plots import study_figures
            written = study_figures(directory, cases, outputs, summaries)
            ensemble_figures = draw_ensembles(directory, found, ensemble_summaries, outputs)
        first = next(iter(verdicts.values()), [])
        summary = {"generator": "postprocess report", "cases": summaries, "missing": missing,
                   "claims": first, "claims_by_model": verdicts,
                   "dissipation_models": dissipation,
                   "impact_peaks": impact_peak_rows(summaries),
                   "fence_comparison": fence_comparison(summaries),
                   "panel_post_load": panel_post_load_rows(summaries),
                   "ensembles": ensemble_summaries, "ensemble_comparisons": comparisons,
                   "figures": {k: [os.path.relpath(p, directory) for p in v]
                               for k, v in {**written, **ensemble_figures}.items()}}
        with open(outputs.file(os.path.join(directory, "summary.json")), "w",
                  encoding="utf-8") as handle:
            handle.write(json_text(summary))
        with open(outputs.file(os.path.join(directory, "report.md")), "w",
                  encoding="utf-8") as handle:
            handle.write(markdown(directory, summaries, verdicts, missing, written,
                                  dissipation, ensemble_summaries, comparisons,
                                  ensemble_figures))
    return summary


def all_cases(summary):
    """{case: its summary} of a summary.json's cases and ensemble members ('NAME/member_KKK')."""
    return {**summary["cases"], **ensembles.all_member_summaries(summary.get("ensembles") or {})}


def run(args):
    """The ``report`` subcommand."""
    summary = build(args.dir, args.expect, not args.no_figures)
    for claim in summary["claims"]:
        print(f"claim {claim['id']}: {claim['verdict']}")
    print(f"wrote {os.path.join(args.dir, 'report.md')} and summary.json")
