"""The figures of an ensemble (matplotlib, Agg; each saved as PREFIX.png and PREFIX.svg):
the distribution of every output, the block's travel of every member on one plot, how the mean
and the quantiles settle as members are added, and a sweep's outputs against the swept value."""

import math
import os

import numpy as np

from .canvas import pyplot, save


def _grid(plt, n, width=3.6, height=2.9):
    cols = min(n, 3)
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(width * cols, height * rows),
                             layout="constrained", squeeze=False)
    for ax in axes.flat[n:]:
        ax.set_visible(False)
    return fig, list(axes.flat[:n])


def _axis_label(output):
    return f"{output['label']} [{output['unit']}]"


def _values(summary, output, members=None):
    members = members if members is not None else summary["members"]
    return [m["outputs"][output["name"]] / output["scale"] for m in members.values()
            if m["status"] == "ok" and m["outputs"].get(output["name"]) is not None]


def bins(n):
    """The histogram's number of bins for n members: Sturges' rule (1 + log2 n), at least 3."""
    return max(3, int(math.ceil(1 + math.log2(max(n, 1)))))


def figure_distributions(name, summary, prefix, outputs=None):
    """One panel per output: the histogram of the members' values (Sturges' bins), each member
    as a tick under it, the mean (solid) and the 5 and 95 % quantiles (dashed)."""
    plt = pyplot()
    fig, axes = _grid(plt, len(summary["outputs"]))
    for ax, output in zip(axes, summary["outputs"]):
        values = np.asarray(_values(summary, output), float)
        stats = summary["statistics"][output["name"]]
        if values.size:
            ax.hist(values, bins=bins(values.size), color="tab:blue", alpha=0.6,
                    edgecolor="white")
            ax.plot(values, np.zeros(values.size), "|", color="k", ms=12, label="members")
            ax.axvline(stats["mean"] / output["scale"], color="tab:red", label="mean")
            for q in ("q05", "q95"):
                ax.axvline(stats[q] / output["scale"], color="tab:red", ls="--",
                           label="5 / 95 %" if q == "q05" else None)
        else:
            # (a fence's residual height when every block went on: a failed test has none)
            ax.text(0.5, 0.5, "no member has a value", ha="center", va="center",
                    transform=ax.transAxes, color="0.4")
            ax.set_xticks([])
            ax.set_yticks([])
        ax.set_xlabel(_axis_label(output))
        ax.set_ylabel("members")
    axes[0].legend(fontsize="x-small")
    fig.suptitle(f"{name}: distribution of each output over {_n(summary)} members")
    return save(fig, prefix, outputs)


def _n(summary):
    return sum(m["status"] == "ok" for m in summary["members"].values())


def _travel(table):
    """The block's travel: block.csv's travel (a fence: along the normal), else its drop."""
    if "travel" in table:
        return table["travel"]
    return table["z"][0] - table["z"]


def figure_travel(name, summary, cases, prefix, outputs=None):
    """The block's travel against time of every member on one plot; a member whose block broke
    through in red. ``cases``: {member: casefolders.Case}."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7, 4.5), layout="constrained")
    for member, case in cases.items():
        m = summary["members"].get(member) or {}
        if case is None or m.get("status") != "ok" or "block" not in case.tables:
            continue
        table = case.tables["block"]
        ax.plot(table["time"], _travel(table), lw=1,
                color="tab:red" if m.get("breakthrough") else "tab:blue", alpha=0.8)
    ax.set_xlabel("time after release [s]")
    ax.set_ylabel("block travel [m]")
    ax.set_title(f"{name}: block travel of every member (red: broke through)")
    return save(fig, prefix, outputs)


def figure_settling(name, summary, prefix, outputs=None):
    """How the mean and the 5/50/95 % quantiles of each output settle as members are added."""
    plt = pyplot()
    fig, axes = _grid(plt, len(summary["outputs"]))
    for ax, output in zip(axes, summary["outputs"]):
        run = summary["settling"][output["name"]]
        n = run["n"]
        ax.plot(n, np.asarray(run["mean"]) / output["scale"], "o-", ms=3, color="tab:red",
                label="mean")
        for q, style in (("q05", ":"), ("q50", "--"), ("q95", ":")):
            ax.plot(n, np.asarray(run[q]) / output["scale"], style, color="k",
                    label={"q05": "5 / 95 %", "q50": "median"}.get(q))
        ax.set_xlabel("members")
        ax.set_ylabel(_axis_label(output))
    axes[0].legend(fontsize="x-small")
    fig.suptitle(f"{name}: the statistics as members are added")
    return save(fig, prefix, outputs)


def _number(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool)


def _sweep_axis(values):
    """(x positions, tick labels or None, axis name or None) of a sweep's values: the numbers
    themselves; vectors along one direction (a sweep of impact.velocity's speed) by their
    length, named '|key|'; else their places, labelled with the values."""
    if all(_number(v) for v in values):
        return [float(v) for v in values], None, None
    if all(isinstance(v, list) and v and all(_number(c) for c in v) for v in values):
        vectors = np.array(values, dtype=float) if len({len(v) for v in values}) == 1 else None
        if vectors is not None:
            lengths = np.linalg.norm(vectors, axis=1)
            if np.all(lengths > 0) and len(set(lengths)) == len(lengths):
                units = vectors / lengths[:, None]
                if np.allclose(units, units[0], rtol=0.0, atol=1e-9):
                    return [float(x) for x in lengths], None, "length"
    return list(range(len(values))), [str(v) for v in values], None


def figure_sweep(name, summary, prefix, outputs=None):
    """Each output against the swept value: every member (points) and the mean per value."""
    plt = pyplot()
    sweep = summary["sweep"]
    x_of, labels, measure = _sweep_axis(sweep["values"])
    fig, axes = _grid(plt, len(summary["outputs"]))
    for ax, output in zip(axes, summary["outputs"]):
        for value, x in zip(sweep["values"], x_of):
            group = {k: m for k, m in summary["members"].items() if m["sweep_value"] == value}
            ys = _values(summary, output, group)
            ax.plot([x] * len(ys), ys, "o", color="tab:blue", alpha=0.5, ms=4)
        means = [row["means"][output["name"]] for row in summary["sweep_rows"]]
        xs = [x for x, m in zip(x_of, means) if m is not None]
        ax.plot(xs, [m / output["scale"] for m in means if m is not None], "-", color="tab:red",
                label="mean")
        if labels:
            ax.set_xticks(x_of, labels, fontsize="x-small", rotation=20)
        axis = f"|{sweep['key']}|" if measure == "length" else sweep["key"]
        ax.set_xlabel(axis + (f" [{sweep['unit']}]" if sweep.get("unit") else ""))
        ax.set_ylabel(_axis_label(output))
    axes[0].legend(fontsize="x-small")
    fig.suptitle(f"{name}: each output against {sweep['key']}")
    return save(fig, prefix, outputs)


def ensemble_figures(directory, found, summaries, outputs):
    """{figure name: paths} of every ensemble (found: postprocess/ensembles.discover's)."""
    out = os.path.join(directory, "figures")
    written = {}
    for name, summary in summaries.items():
        if not _n(summary):
            continue
        prefix = os.path.join(out, f"ensemble_{name}")
        if summary["mode"] == "sweep":
            written[f"ensemble_{name}_sweep"] = figure_sweep(name, summary, prefix + "_sweep",
                                                             outputs)
        elif summary["mode"] == "random":
            written[f"ensemble_{name}_distributions"] = figure_distributions(
                name, summary, prefix + "_distributions", outputs)
            written[f"ensemble_{name}_settling"] = figure_settling(
                name, summary, prefix + "_settling", outputs)
        written[f"ensemble_{name}_travel"] = figure_travel(name, summary, found[name].members,
                                                           prefix + "_travel", outputs)
    return written
