"""The report's text of the ensembles (postprocess/ensembles.py summarizes them): per ensemble
its members, the statistics of each output, the probability of breakthrough, a sweep's table
and the figures; the compound vs square comparison; the sensitivity tables, which stand next to
the report's "Numbers without a source"."""

import os

ENSEMBLE_NOTE = (
    "Each ensemble is the members of one case file's [ensemble] section (runner/ensemble.py, "
    "doc/ensembles.md): random members (what varies is listed), a sweep of one key, or a "
    "sensitivity study; every member is a case of its own in NAME/member_KKK (its case.toml "
    "runs it alone). Statistics over the members that ended ok: mean, standard deviation "
    "(n - 1), the 5, 50 and 95 % quantiles (linear interpolation between order statistics, "
    "type 7) and the mean's 95 % t interval; 'first half' is the mean of the first half of the "
    "members (how far the mean has settled). P(breakthrough): the fraction of members whose "
    "block broke through (a fence: its velocity along the normal never turned; a panel: it "
    "passed through) with its 95 % Wilson score interval (postprocess/statistics.py).")
COMPARISON_NOTE = (
    "The paper's post-load comparison over ensembles: the mean of each load over the compound "
    "net's members minus the mean over the square net's, with Welch's 95 % t interval (unequal "
    "variances), and the ratio of the means. Where the two ensembles drew the same (the same "
    "seed and variations: member k of each had the same impact point, speed, turn and factors), "
    "the paired difference too: the mean of the members' differences with its 95 % t interval, "
    "in which what the draws do to both nets cancels (common random numbers; the verdict then "
    "reads it). The interval below 0: the compound net's load is lower at that confidence; an "
    "interval holding 0: the ensembles cannot tell.")
SENSITIVITY_NOTE = (
    "One-at-a-time sensitivity (ensemble.sensitivity): each key times each factor alone, every "
    "other number as in the base case (member 0); the change of each output against the base, "
    "relative and absolute (in the output's unit); 'block': whether the block broke through, in "
    "bold where the factor changed the base's verdict. A number whose change moves an output by "
    "more than the ensembles' spread, or turns the verdict, deserves a source first.")


def _num(value, digits=4):
    if value is None:
        return "n/a"
    if isinstance(value, bool) or not isinstance(value, (int, float)):
        return str(value)
    return f"{value:.{digits}g}"


def _scaled(value, output):
    return None if value is None else value / output["scale"]


def _table(header, rows):
    lines = ["| " + " | ".join(header) + " |", "|" + "---|" * len(header)]
    return lines + ["| " + " | ".join(row) + " |" for row in rows]


def _drawn_text(member):
    """What a member changes, short: the sweep's value or the sensitivity's key x factor (its
    label), and what was drawn."""
    d = member.get("drawn") or {}
    parts = [] if (member.get("label") or "").startswith("draw") else [member.get("label")]
    if "speed" in d:
        parts.append(f"v {_num(d['speed'], 3)} m/s")
    if "point_offset" in d:
        parts.append("point " + "/".join(f"{v:+.2f}" for v in d["point_offset"]) + " m")
    if "rotation" in d:
        parts.append("turned")
    for name in ("wires", "ropes", "friction"):
        if f"{name}_factor" in d:
            parts.append(f"{name} x{d[name + '_factor']:.3f}")
    if "materials.slack_seed" in (member.get("changes") or {}):
        parts.append(f"slack seed {member['changes']['materials.slack_seed']}")
    return ", ".join(p for p in parts if p) or "-"


def _header(name, e):
    n = len(e["members"])
    what = {"random": "random members, varying " + (
                "; ".join(f"{k}: {v}" for k, v in (e["variations"] or {}).items()) or "nothing"),
            "sweep": f"a sweep of {(e['sweep'] or {}).get('key')} over "
                     f"{(e['sweep'] or {}).get('values')}",
            "sensitivity": "a one-at-a-time sensitivity study (table: 'Sensitivity of the "
                           "outputs' below)"}.get(e["mode"], e["mode"])
    mode = "quick" if e["quick"] else "full"
    return [f"### {name}", "", f"{n} members of `{e['case_file']}` ({e['kind']}, {mode}, "
            f"seed {e['seed']}): {what}.", ""]


def _member_rows(e):
    for member, m in e["members"].items():
        yield [member, _drawn_text(m), m["status"]] + [
            _num(_scaled(m["outputs"].get(o["name"]), o)) for o in e["outputs"]] + [
            {True: "yes", False: "no"}.get(m["breakthrough"], "n/a")]


def _first_half(e, output):
    run = e["settling"][output["name"]]
    return run["mean"][(len(run["n"]) + 1) // 2 - 1] if run["n"] else None


def _statistics_rows(e):
    for o in e["outputs"]:
        s = e["statistics"][o["name"]]
        interval = s["mean_interval"]
        yield [f"{o['label']} [{o['unit']}]", str(s["n"])] + [
            _num(_scaled(s[k], o)) for k in ("mean", "std", "q05", "q50", "q95")] + [
            "n/a" if interval is None else
            f"[{_num(_scaled(interval[0], o))}, {_num(_scaled(interval[1], o))}]",
            _num(_scaled(_first_half(e, o), o))]


def _breakthrough_line(e):
    b = e["breakthrough"]
    if not b["n"]:
        return "P(breakthrough): n/a (no member that ended ok says)."
    return (f"Block stopped in {b['n'] - b['events']} of {b['n']} members. "
            f"P(breakthrough) = {b['events']}/{b['n']} = {b['p']:.3g}, 95 % Wilson interval "
            f"[{b['low']:.3g}, {b['high']:.3g}].")


def _sweep_lines(e):
    if not e["sweep_rows"]:
        return []
    key = e["sweep"]["key"]
    unit = f" [{e['sweep']['unit']}]" if e["sweep"].get("unit") else ""
    return ["", f"Mean of each output per value of {key} (members that ended ok), and how "
                "many broke through:", ""] + _table(
        [key + unit, "n"] + [f"{o['label']} [{o['unit']}]" for o in e["outputs"]] +
        ["broke through"],
        [[str(r["value"]), str(r["n"])] + [_num(_scaled(r["means"][o["name"]], o))
                                            for o in e["outputs"]] +
         [f"{r['breakthrough']['events']}/{r['breakthrough']['n']}"] for r in e["sweep_rows"]])


def _figure_lines(name, figures, directory):
    lines = []
    for figure, paths in figures.items():
        if figure.startswith(f"ensemble_{name}_"):
            lines += [f"![{figure}]({os.path.relpath(paths[0], directory)})", ""]
    return lines


def ensemble_lines(ensembles, comparisons, figures, directory):
    """The report's section "Ensembles" (empty without ensembles)."""
    if not ensembles:
        return []
    lines = ["", "## Ensembles", "", ENSEMBLE_NOTE, ""]
    for name, e in ensembles.items():
        lines += _header(name, e)
        lines += _table(["member", "changes", "status"] +
                        [f"{o['label']} [{o['unit']}]" for o in e["outputs"]] +
                        ["broke through"], list(_member_rows(e)))
        if e["mode"] == "random":
            heading = "Statistics of the members that ended ok" + (
                " (the residual height: of those whose block stayed in the fence; where it went "
                "on, the test failed)" if e["kind"] == "fence" else "")
            lines += ["", heading + ":", ""]
            lines += _table(["output", "n", "mean", "std", "5 %", "50 %", "95 %",
                             "mean's 95 % interval", "first half's mean"],
                            list(_statistics_rows(e)))
            lines += ["", _breakthrough_line(e)]
        lines += _sweep_lines(e)
        lines += [""] + _figure_lines(name, figures, directory)
    lines += comparison_lines(ensembles, comparisons)
    return lines


def _verdict(low, high):
    return "compound lower" if high < 0 else "compound higher" if low > 0 else "cannot tell"


def comparison_lines(ensembles, comparisons):
    if not comparisons:
        return []
    rows = []
    for c in comparisons:
        output = next(o for o in ensembles[c["compound"]]["outputs"] if o["name"] == c["output"])
        paired = c.get("paired")
        # the paired interval where the members drew the same: the draws' own spread cancels
        verdict = _verdict(*((paired["low"], paired["high"]) if paired else (c["low"], c["high"])))
        rows.append([c["compound"], c["square"], f"{output['label']} [{output['unit']}]",
                     f"{c['n_a']} / {c['n_b']}", _num(_scaled(c["difference"], output)),
                     f"[{_num(_scaled(c['low'], output))}, {_num(_scaled(c['high'], output))}]",
                     "n/a" if not paired else
                     f"{_num(_scaled(paired['difference'], output))} "
                     f"[{_num(_scaled(paired['low'], output))}, "
                     f"{_num(_scaled(paired['high'], output))}] ({paired['n']} pairs)",
                     _num(c["ratio"]), verdict + (" (quick)" if c["quick"] else "")])
    return ["", "### Compound against square net", "", COMPARISON_NOTE, ""] + _table(
        ["compound", "square", "load", "members", "difference of the means",
         "Welch 95 % interval", "paired difference, 95 % interval", "ratio of the means",
         "verdict"], rows)


def _verdict_change(through, base_through):
    """A member's block (through, stopped), in bold with the base's when the factor changed it."""
    if through is None:
        return "n/a"
    word = "through" if through else "stopped"
    if base_through is None or bool(base_through) == bool(through):
        return word
    return f"**{word}** (base: {'through' if base_through else 'stopped'})"


def sensitivity_lines(ensembles):
    """The sensitivity tables of the sensitivity ensembles (next to the unsourced numbers)."""
    studies = {n: e for n, e in ensembles.items() if e["mode"] == "sensitivity"}
    if not studies:
        return []
    lines = ["", "## Sensitivity of the outputs", "", SENSITIVITY_NOTE, ""]
    for name, e in studies.items():
        outputs = {o["name"]: o for o in e["outputs"]}
        shown = [outputs[n] for n in (e["sensitivity_rows"][0]["changes"]
                                      if e["sensitivity_rows"] else ()) if n in outputs]
        base = next((m for m in e["members"].values() if m["key"] is None), {})
        lines += [f"{name} (base: member_000; " + ", ".join(
            f"{o['label']} {_num(_scaled(base.get('outputs', {}).get(o['name']), o))} {o['unit']}"
            for o in shown) + "):", ""]
        # each row's member: its verdict and its own values (members that ended ok)
        ran = {r["member"]: e["members"][r["member"]] for r in e["sensitivity_rows"]
               if r["status"] == "ok"}
        verdicts = any(m.get("breakthrough") is not None for m in [base, *ran.values()])
        rows = []
        for r in e["sensitivity_rows"]:
            member = ran.get(r["member"], {})
            cells = [_verdict_change(member.get("breakthrough"), base.get("breakthrough"))] \
                if verdicts else []
            for o in shown:
                change = r["changes"][o["name"]]
                value = member.get("outputs", {}).get(o["name"])
                if change["absolute"] is None and value is not None:
                    # the base has none (a fence that failed has no residual height): the value
                    cells.append(f"{_num(_scaled(value, o))} {o['unit']} (base: n/a)")
                    continue
                cells.append("n/a" if change["absolute"] is None else
                             (f"{100 * change['relative']:+.3g} %"
                              if change["relative"] is not None else "-") +
                             f" ({_scaled(change['absolute'], o):+.4g} {o['unit']})")
            rows.append([f"`{r['key']}`", f"{r['factor']:g}", r["status"]] + cells)
        lines += _table(["key", "factor", "status"] + (["block"] if verdicts else []) +
                        [o["label"] for o in shown], rows)
        skipped = (e["sensitivity"] or {}).get("skipped") or []
        if skipped:
            lines += ["", "Left out: " + "; ".join(f"`{s['key']}` ({s['why']})"
                                                   for s in skipped) + "."]
        lines.append("")
    return lines
