"""Benchmark of ``zone``: a 100-frame dump of a 10 000-bond panel (not a test).

    /usr/bin/python3 -m postprocess.benchmark [--frames 100] [--bonds 10000]
"""

import argparse
import os
import tempfile
import time

from .__main__ import main
from .synthetic import write_random_bond_dump


def run(frames, bonds):
    with tempfile.TemporaryDirectory() as tmp:
        dump = os.path.join(tmp, "bonds.dump")
        start = time.perf_counter()
        write_random_bond_dump(dump, frames, bonds)
        written = time.perf_counter()
        size = os.path.getsize(dump) / 1e6
        code = main(["zone", dump, "--dt", "1e-5", "--out", os.path.join(tmp, "zone.csv")])
        done = time.perf_counter()
    print(f"dump {frames} frames x {bonds} bonds ({size:.0f} MB) written in "
          f"{written - start:.1f} s; zone: {done - written:.2f} s (exit {code})")
    return done - written


if __name__ == "__main__":
    parser = argparse.ArgumentParser(prog="python3 -m postprocess.benchmark")
    parser.add_argument("--frames", type=int, default=100)
    parser.add_argument("--bonds", type=int, default=10000)
    options = parser.parse_args()
    run(options.frames, options.bonds)
