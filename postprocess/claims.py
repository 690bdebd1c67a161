"""The paper's three claims, judged on whatever cases a study holds. Cases are matched by what
their records say they are (kind, net, dissipation model, block), never by their names:

- claims 1 and 2 (DT and SW bonds) on every punch and impact case of a net with the double
  twist (hex or compound), impacts under one dissipation model at a time;
- claim 3 (the compound panel lowers the rope tension) on each pair of impact cases, a square
  and a compound panel, hit by the same block under the same dissipation model.

The same groups give the study's figures 3, 5 and 6 (postprocess/plots.py).
"""

NOT_EVALUATED = "not evaluated (no case of the study can show it)"
QUICK_NOTE = " (from --quick cases: small panels, not the paper's)"
CLAIMS = {
    1: "DT (double-twist) bonds carry the highest individual force (peak max_tension DT > SW).",
    2: "SW (single-wire) bonds carry most of the total force (peak total_tension SW > DT).",
    3: "Under impact, the compound panel lowers the peak force in the strand-rope mesh "
       "(peak total_tension of family rope: compound < square panel, same block).",
}
# a dissipation model's name as the runner records it (case.json `dissipation`), and its words
MODELS = {"physical": "the physical model (no damping to ground)",
          "local": "local damping (the paper's)",
          "bond": "bond damping (momentum-conserving, no local damping)"}


def model_of(summary):
    """The dissipation model of an impact's summary ('local' for older records)."""
    return summary.get("dissipation") or "local"


def block_of(summary):
    """What identifies an impact's load: the block's mass, speed and point (rounded)."""
    block = summary.get("block") or {}
    return (round(float(block.get("mass") or 0), 6), round(float(block.get("speed") or 0), 6),
            tuple(round(float(v), 6) for v in (block.get("point") or (0.0, 0.0))))


def models(summaries):
    """The dissipation models of the usable impact cases, in a fixed order."""
    found = {model_of(s) for s in summaries.values() if s.get("kind") == "impact"}
    return [m for m in MODELS if m in found] + sorted(found - set(MODELS))


def _usable(summary):
    return summary.get("status") == "ok" and not summary.get("errors") and summary.get("zone")


def twist_cases(summaries, model=None):
    """Usable punch and impact cases of a net with the double twist: punches always (quasi-
    static, not a question of the dissipation), impacts of ``model`` (None: every model)."""
    out = []
    for name, s in summaries.items():
        if not _usable(s) or s.get("panel") not in ("hex", "compound"):
            continue
        if s.get("kind") == "punch" or (s.get("kind") == "impact" and
                                         (model is None or model_of(s) == model)):
            out.append(name)
    return out


def impact_groups(summaries, model):
    """{(block, mode): {net: case name}} of the usable impacts under ``model``: the cases that
    differ only in their net."""
    groups = {}
    for name, s in summaries.items():
        if s.get("kind") != "impact" or not _usable(s) or model_of(s) != model:
            continue
        groups.setdefault((block_of(s), s.get("mode")), {}).setdefault(s.get("panel"), name)
    return groups


def punch_group(summaries):
    """{net: case name} of the usable punch cases with the semi-spheroid on the hex and
    compound panels (Figure 3); the first of each net."""
    group = {}
    for name, s in summaries.items():
        if s.get("kind") == "punch" and _usable(s) and s.get("platter", "spheroid") == "spheroid":
            group.setdefault(s.get("panel"), name)
    return {k: v for k, v in group.items() if k in ("hex", "compound")}


def _peak(summary, family, key):
    entry = (summary.get("zone") or {}).get(family)
    return None if entry is None else entry[key]


def _claim(number, evidence, notes, quick):
    if evidence:
        supported = all(e["holds"] for e in evidence)
        verdict = ("supported" if supported else "not supported") + (QUICK_NOTE if quick else "")
    else:
        verdict, supported = NOT_EVALUATED, None
    return {"id": number, "statement": CLAIMS[number], "verdict": verdict,
            "supported": supported, "evidence": evidence, "notes": notes}


def claim_twist(number, summaries, key, stronger, weaker, model):
    """Claims 1 and 2: family ``stronger`` beats ``weaker`` on peak ``key`` in every case with
    the double twist."""
    evidence, notes = [], []
    for name in twist_cases(summaries, model):
        a, b = (_peak(summaries[name], f, key) for f in (stronger, weaker))
        if a is None or b is None or (a == 0 and b == 0):
            notes.append(f"{name}: not evaluated (no {stronger}/{weaker} forces)")
            continue
        evidence.append({"case": name, stronger: a, weaker: b, "holds": bool(a > b)})
    quick = any(summaries[e["case"]]["mode"] == "quick" for e in evidence)
    return _claim(number, evidence, notes, quick)


def claim_rope(summaries, model):
    """Claim 3: the rope family's peak total tension is lower on the compound panel than on the
    square one, for every pair hit by the same block."""
    evidence, notes = [], []
    for (_, mode), nets in impact_groups(summaries, model).items():
        if "square" not in nets or "compound" not in nets:
            continue
        square = (summaries[nets["square"]].get("zone") or {}).get("rope")
        compound = (summaries[nets["compound"]].get("zone") or {}).get("rope")
        if square is None or compound is None:
            notes.append(f"{nets['square']} / {nets['compound']}: no rope family in the zone")
            continue
        evidence.append({"square": nets["square"], "compound": nets["compound"],
                         "square_peak_total": square["peak_total_tension"],
                         "compound_peak_total": compound["peak_total_tension"],
                         "square_peak_max": square["peak_max_tension"],
                         "compound_peak_max": compound["peak_max_tension"],
                         "mode": mode,
                         "holds": bool(compound["peak_total_tension"] <
                                       square["peak_total_tension"])})
    quick = any(e["mode"] == "quick" for e in evidence)
    return _claim(3, evidence, notes, quick)


def evaluate(summaries, model):
    """The three claims under one dissipation model."""
    return [claim_twist(1, summaries, "peak_max_tension", "DT", "SW", model),
            claim_twist(2, summaries, "peak_total_tension", "SW", "DT", model),
            claim_rope(summaries, model)]


def evaluable(summaries):
    """Whether any case of the study can show one of the claims (the report shows them then)."""
    return bool(twist_cases(summaries)) or any(
        "square" in nets and "compound" in nets
        for m in models(summaries) for nets in impact_groups(summaries, m).values())
