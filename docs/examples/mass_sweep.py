#!/usr/bin/python3
"""The paper's post-load comparison as a function of the block's mass, from Python
(doc/python_api.md): the square and the compound panel, each swept over the block mass.

    /usr/bin/python3 docs/examples/mass_sweep.py [OUT] [--full]

Each net is one study (OUT/square, OUT/compound: impact_NET with its [ensemble] made into a sweep
of impact.mass; --quick unless --full), with its own report and sweep figure; this script then
reads both summaries and draws what no single report holds: the peak support force of the two
nets against the mass and their ratio (OUT/mass_sweep.png), and prints the table. Every member
is a case of its own (OUT/NET/impact_NET/member_KKK) and reruns alone from its case.toml.
"""

import os
import sys

sys.path.insert(0, os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", ".."))

import matplotlib  # noqa: E402
matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

from runner import api  # noqa: E402
from runner.errors import RunError, StudyError  # noqa: E402

MASSES = [40.0, 60.0, 80.0]
NETS = ("square", "compound")
OUTPUT = "edge_force_peak"   # the supports' peak force (summary.json: ensembles.*.outputs)


def sweep(net, out, quick):
    result = api.study(f"impact_{net}", os.path.join(out, net), quick=quick,
                       set=['ensemble.sweep="impact.mass"', f"ensemble.values={MASSES}"])
    ens = result.summary["ensembles"][f"impact_{net}"]
    scale = next(o["scale"] for o in ens["outputs"] if o["name"] == OUTPUT)
    return {r["value"]: r["means"][OUTPUT] / scale for r in ens["sweep_rows"]}, result.unsound


def main():
    args = [a for a in sys.argv[1:] if a != "--full"]
    out = os.path.abspath(args[0] if args else os.path.join("out", "mass_sweep"))
    peaks, unsound = {}, {}
    try:
        for net in NETS:
            peaks[net], bad = sweep(net, out, quick="--full" not in sys.argv)
            unsound.update(bad)
    except (StudyError, RunError) as exc:
        print(f"mass_sweep: {exc}", file=sys.stderr)
        return 2
    ratio = [peaks["compound"][m] / peaks["square"][m] for m in MASSES]
    fig, (a, b) = plt.subplots(1, 2, figsize=(8, 3.2))
    for net in NETS:
        a.plot(MASSES, [peaks[net][m] for m in MASSES], "o-", label=net)
    a.set(xlabel="block mass [kg]", ylabel="peak support force [kN]")
    a.legend()
    b.plot(MASSES, ratio, "o-")
    b.axhline(1.0, color="0.6", lw=0.8)
    b.set(xlabel="block mass [kg]", ylabel="compound / square")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "mass_sweep.png"), dpi=120)
    print("mass [kg] | square [kN] | compound [kN] | compound/square")
    for m, r in zip(MASSES, ratio):
        print(f"{m:g} | {peaks['square'][m]:.4g} | {peaks['compound'][m]:.4g} | {r:.3f}")
    print(f"figure: {os.path.join(out, 'mass_sweep.png')}")
    for name, entry in unsound.items():
        print(f"mass_sweep: {name}: {entry['status']}: {entry['verdict']}", file=sys.stderr)
    return 3 if unsound else 0


if __name__ == "__main__":
    sys.exit(main())
