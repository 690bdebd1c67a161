"""Every generated panel runs with bond_style wirenet: wire laws on the hexagonal families, the beam
law on the rope; a few steps under gravity with blocked edges. Every bond is initialised at its
generated length (zero strain at step 0) and the net sags (tension appears, only tension in wires)."""

import json
import subprocess

import numpy as np
import pytest

import lmp

SW = ("0.0019230769 2.5e8 0.0192 3.2195e8 0.05 3.8292e8 0.15 5.1219e8 "
      "0.25 5.5854e8 0.30 5.6585e8 0.35 5.6585e8")
COEFFS = f"""bond_coeff 1 wire diameter 0.0027 curve {SW} derived lambda_eps 0.4 lambda_k 0.66 nu 0.3 family DT
bond_coeff 2 wire diameter 0.0027 curve {SW} family SW
bond_coeff 3 wire diameter 0.0034 curve {SW} family selvedge
bond_coeff 4 beam diameter 0.01 E 6e10 nu 0.3 bending 0.05 family rope
"""


def deck(nbond_types, steps):
    coeffs = COEFFS if nbond_types == 4 else "bond_coeff 1 beam diameter 0.01 E 1e10 nu 0.288\n"
    return lmp.PREAMBLE + f"""read_data net.data
bond_style wirenet
{coeffs}group edges type 2 3 4 6 7 8
group free subtract all edges
fix grav all gravity 9.81 vector 0 0 -1
fix integrate free nve/sphere
timestep 2e-6
compute bonds all wirenet/local
dump b all local {steps} bonds.dump c_bonds[1] c_bonds[2] c_bonds[3] c_bonds[4] c_bonds[5] c_bonds[6]
dump_modify b format "%d %d %d %.16g %.16g %.16g"
run {steps}
"""


@pytest.mark.parametrize("kind,options", [("hex", ["--width", "0.6", "--height", "0.6"]),
                                          ("square", ["--width", "0.9", "--height", "0.9"]),
                                          ("compound", ["--width", "0.9", "--height", "0.9"]),
                                          ("beam", ["--elements", "5"])])
def test_generated_panel_runs(tmp_path, kind, options):
    subprocess.run([str(lmp.GEN), kind, *options, "--out", str(tmp_path / "net")], check=True,
                   capture_output=True)
    meta = json.loads((tmp_path / "net.json").read_text())
    ntypes = len(meta["bond_types"])
    steps = 200
    out = lmp.run_deck(deck(ntypes, steps), tmp_path)
    assert f"{meta['counts']['bonds']} bonds" in out
    frames = (tmp_path / "bonds.dump").read_text().split("ITEM: TIMESTEP")[1:]
    first, last = (np.loadtxt(f.splitlines()[9:], ndmin=2) for f in (frames[0], frames[-1]))
    assert len(first) == meta["counts"]["bonds"]                # every bond reported once
    assert np.abs(first[:, 4]).max() < 1e-12                   # generated length = initial length
    assert meta["max_bond_length"] >= first[:, 3].max() * (1 - 1e-12)
    wires = last[last[:, 2] <= 3] if ntypes == 4 else last[:0]
    assert (wires[:, 5] >= 0).all()                             # wires carry tension only
    assert np.abs(last[:, 5]).max() > 0                         # gravity loads the net
