#!/usr/bin/python3
"""The cases an engineer brought (issue #42), from Python (doc/python_api.md): an oblique impact
on a 4 m x 6 m double-twist panel, an off-centre punch of a 5 m square net, a two-module 250 kJ
fence, the paper's block at 40 m/s, and the paper's block at five speeds on the square panel.

    /usr/bin/python3 docs/examples/engineer.py [OUT] [--full] [--np N]

It runs the study docs/examples/engineer/study.toml (--quick unless --full) exactly as

    ./wirenet run docs/examples/engineer/study.toml --quick --out OUT

does (the same cases, files and report: runner.api.study is the command's runner), then reads
each case's facts and prints the design outputs a designer sizes a structure for, in kN, kJ and
m (the CSVs stay in SI): what became of the block, the supports' and anchors' peaks, the block
force as its peak row mean and as a windowed mean, and the sweep's outputs against the speed.
Exit 0 when every case is sound, 3 when one is not (its status printed), 2 on bad input or a
failed case.
"""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

from runner import api  # noqa: E402
from runner.errors import RunError, StudyError  # noqa: E402

STUDY = os.path.join(os.path.dirname(os.path.abspath(__file__)), "engineer", "study.toml")
SWEEP = "speed_sweep"


def kn(newtons):
    return "n/a" if newtons is None else f"{newtons / 1e3:.4g}"


def impact_row(name, f):
    """An impact's design outputs: the block's verdict and largest travel, its force (the
    largest mean over one output row, and the windowed peak with its window: the plateau to
    design with; the raw samples can miss the first touch's spike, doc/impact.md), the most
    loaded edge's and all supports' peak."""
    edges = f["support_peaks"]
    worst = max(edges, key=lambda p: edges[p]["force"])
    return (f"{name}: {f['block_verdict']}, largest travel {f['max_displacement']:.3f} m; "
            f"block force {kn(f['peak_block_force'])} kN peak (row mean), "
            f"{kn(f['peak_block_force_windowed'])} kN over {f['force_window'] * 1e3:.3g} ms; "
            f"supports {kn(f['edge_force_peak'])} kN together, edge {worst} "
            f"{kn(edges[worst]['force'])} kN; {f['broken_bonds']} bonds broken")


def punch_row(name, f):
    return (f"{name}: peak platter force {kn(f['peak_force'])} kN, first rupture "
            f"{'none' if not f.get('first_rupture') else f['first_rupture']['bond']['family']}, "
            f"quasi-static {f['quasi_static']['passed']}")


def fence_row(name, f):
    """A fence's design outputs: braking distance, residual height, the most loaded anchor
    (lateral and upslope ropes' anchors) and post base, what the block brought."""
    peaks = f["support_peaks"]
    anchors = {k: p["peak"] for k, p in peaks.items() if not k.startswith("post_base")}
    bases = {k: p["peak"] for k, p in peaks.items() if k.startswith("post_base")}
    anchor, base = max(anchors, key=anchors.get), max(bases, key=bases.get)
    residual = f["residual_height"]
    return (f"{name}: block {'stopped' if f['block_stopped'] else 'not stopped'}, braking "
            f"distance {f['braking_distance']:.3f} m, residual height "
            f"{'n/a' if residual is None else f'{residual:.3f}'} m; anchor {anchor} "
            f"{kn(anchors[anchor])} kN, {base} {kn(bases[base])} kN; block energy "
            f"{f['block']['energy'] / 1e3:.4g} kJ")


def speed_of(velocity):
    return sum(c * c for c in velocity) ** 0.5


ROWS = {"impact": impact_row, "punch": punch_row, "fence": fence_row}


def main():
    args = sys.argv[1:]
    np_ = None
    if "--np" in args:
        k = args.index("--np")
        np_ = int(args[k + 1])
        del args[k:k + 2]
    full = "--full" in args
    args = [a for a in args if a != "--full"]
    out = os.path.abspath(args[0] if args else os.path.join("out", "engineer"))
    try:
        result = api.study(STUDY, out, quick=not full, np=np_)
    except (StudyError, RunError) as exc:
        print(f"engineer: {exc}", file=sys.stderr)
        return 2
    for name in sorted(result.summary["cases"]):
        if name.startswith(SWEEP + "/"):
            continue
        facts = api.facts(os.path.join(out, name))
        print(ROWS[facts["kind"]](name, facts))
    sweep = result.summary["ensembles"][SWEEP]
    print(f"{SWEEP}: speed [m/s] | supports [kN] | block force windowed [kN] | verdict")
    members = sorted(sweep["members"].items(), key=lambda m: speed_of(m[1]["sweep_value"]))
    for member, entry in members:
        facts = api.facts(os.path.join(out, SWEEP, member))
        print(f"{speed_of(entry['sweep_value']):g} | {kn(facts['edge_force_peak'])} | "
              f"{kn(facts['peak_block_force_windowed'])} | {facts['block_verdict']}")
    print(f"report: {os.path.join(out, 'report.md')}")
    for name, entry in result.unsound.items():
        print(f"engineer: {name}: {entry['status']}: {entry['verdict']}", file=sys.stderr)
    return 3 if result.unsound else 0


if __name__ == "__main__":
    sys.exit(main())
