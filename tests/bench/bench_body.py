"""Steps per second of a punch with the analytic platter (fix wirenet/body) and with the STL
platter (fix mesh/surface/stress + wall/gran + move/mesh), run back to back on 1 rank (not a
test; docs/PERFORMANCE.md, "Analytic platter against the STL platter").

    WIRENET_BUILD=build /usr/bin/python3 tests/bench/bench_body.py [--panel hex] [--full]
        [--steps 20000] [--repeat 2] [--out /tmp/bench_body]
        [--steps-per-m N]

Only the punch phase is timed: the loop times LIGGGHTS prints for the runs after the deck's
line "pre-load: centre sag". --full uses the 3 m panel with a short pre-load (relax_steps 2000,
preload_tol 1: two relaxations of at most 2000 steps, so the sag is not the 1 cm of the study;
the platter still meets the centre nodes at once), the quick panel its normal pre-load.
"""

import argparse
import os
import re
import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))   # the repository's packages
from runner import INPUTS, api, engine, kinds, materials  # noqa: E402
from runner.kinds import punch  # noqa: E402

LOOP = re.compile(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps")
PRELOAD_DONE = punch.PRELOAD_MARKER   # the punch deck's line before the timed phase


def loop_times(text, after=None):
    """(steps, seconds) summed over the runs of a LIGGGHTS log, or of those after the line
    starting with ``after``."""
    if after is not None:
        text = text.split(after, 1)[1]
    pairs = [(int(n), float(t)) for t, n in LOOP.findall(text)]
    return sum(n for n, _ in pairs), sum(t for _, t in pairs)


def run(panel, full, steps, body_model, out, steps_per_m=None, np_=1):
    """(steps, seconds) of `steps` punch steps after a pre-load (short on the full panel)."""
    platter = "cone" if panel == "square" else "spheroid"
    sets = [f'punch.body="{body_model}"'] + \
        ([f"punch.steps_per_metre={float(steps_per_m)!r}"] if steps_per_m else [])
    case = api.load(f'kind = "punch"\n[panel]\nnet = "{panel}"\n[punch]\nplatter = "{platter}"\n',
                    quick=not full, set=sets)
    setup = punch.Setup(kinds.of(case), os.path.join(out, "setup"),
                        materials.bending_of(case, out)[0])
    travel = steps * case["punch.speed"] * setup.dt
    variables, _ = setup.variables(travel=travel, every=1000)
    variables.update(dump_every=10 ** 9, frame_every=10 ** 9)
    if full:
        variables.update(relax_steps=2000, preload_tol=1)
    workdir = os.path.join(out, "run")
    engine.run(INPUTS / "punch.in", workdir, variables, np=np_,
               total_steps=steps, dt=setup.dt, phase_marker=PRELOAD_DONE)
    with open(os.path.join(workdir, "log.lammps"), errors="replace") as handle:
        return loop_times(handle.read(), PRELOAD_DONE)


def main(argv=None):
    p = argparse.ArgumentParser(prog="tests/bench/bench_body.py")
    p.add_argument("--panel", default="hex", choices=("hex", "square", "compound"))
    p.add_argument("--full", action="store_true")
    p.add_argument("--steps", type=int, default=20000)
    p.add_argument("--repeat", type=int, default=2)
    p.add_argument("--out", default="/tmp/bench_body")
    p.add_argument("--steps-per-m", type=float, default=None,
                   help="steps per metre of travel (default: the study's); fewer steps per metre "
                        "reach a deeper, more contact-rich state in the timed steps")
    a = p.parse_args(argv)
    for k in range(a.repeat):
        rates = {}
        for model in ("mesh", "analytic"):
            n, t = run(a.panel, a.full, a.steps, model, os.path.join(a.out, f"{model}{k}"),
                       a.steps_per_m)
            rates[model] = n / t
            print(f"{a.panel} {'full' if a.full else 'quick'} {model}: {n} steps in {t:.2f} s, "
                  f"{n / t:.0f} steps/s", flush=True)
        print(f"  ratio analytic/mesh {rates['analytic'] / rates['mesh']:.2f}", flush=True)


if __name__ == "__main__":
    main()
