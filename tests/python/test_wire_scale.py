"""The wire law at a scale (`fix_modify wirenet_bonds scale S`): the envelope F_S(u) = S F(u / S).

The drapery settles first under W times its weight (doc/drapery.md, "A heavier mesh first"); with
its wires at scale W it is as far from yield and rupture as under its own weight. Checked here on
the two-node load path of the YADE reference traces (test_wire_law.py):
- self-similarity: driven through S times the path at scale S, the tension is S times the
  trace's at every step, the bond breaks at the same step, and the plastic-work tally (reported
  at scale 1) is the unscaled run's;
- a change of scale maps the state: yielded at scale 4, unloaded, taken to the same place at
  scale 1 (the elongation / 4) and driven on, the bond follows the trace of a bond that was at
  scale 1 throughout, and its plastic work with it;
- bad values and a restart file while scaled are refused in one line.
"""

import numpy as np
import pytest

import lmp
from test_wire_law import CASES, FRACTIONS, L0, SUBSTEPS, DT, write_two_nodes

TRACE = "type2_dt1_seed-1_lF0.8"   # slack with a softer first branch: every term of the map


def deck(coeff, legs, before=None):
    """Node 2 driven along x through legs (velocity, steps); before[k]: commands before leg k
    (after a run 0 that makes the bonds' history fix, wirenet_bonds)."""
    before = before or {}
    runs = []
    for k, (v, n) in enumerate(legs):
        runs.append(before.get(k, "") + f"\nfix mv{k} moving move linear {v!r} 0 0\nrun {n}\nunfix mv{k}")
    return lmp.PREAMBLE + f"""
read_data two.data
bond_style wirenet
bond_coeff 1 {coeff}
group moving id 2
compute wl all wirenet/local
compute F all reduce sum c_wl[6]
compute nb all reduce sum c_wl[3]
variable u equal x[2]-x[1]-{L0!r}
timestep {DT!r}
run 0
variable wp equal f_wirenet_bonds[3]
thermo_style custom step v_u c_F c_nb v_wp
thermo_modify format float %.16g
thermo 1
""" + "\n".join(runs) + "\n"


def legs_for(fractions, u_rupture, start=0.0):
    legs, prev = [], start
    for f in fractions:
        legs.append(((f - prev) * u_rupture / (SUBSTEPS * DT), SUBSTEPS))
        prev = f
    return legs


def rows(out):
    by_step = {}
    for r in lmp.thermo_rows(out):
        if "u" not in r:
            continue   # a run 0 before the deck's thermo_style
        by_step.setdefault(int(r["Step"]), r)   # a run's first row repeats the last step: the one before
    steps = sorted(s for s in by_step if s >= 1)
    return {k: np.array([by_step[s][k] for s in steps]) for k in ("u", "F", "nb", "wp")}


@pytest.mark.parametrize("scale", [4.0, 16.0])
def test_the_scaled_law_is_the_law_magnified(tmp_path, scale):
    coeff, u_r = CASES[TRACE]
    for d in ("plain", "scaled"):
        (tmp_path / d).mkdir()
        write_two_nodes(tmp_path / d / "two.data")
    plain = rows(lmp.run_deck(deck(coeff, legs_for(FRACTIONS, u_r)), tmp_path / "plain"))
    scaled_dir = tmp_path / "scaled"
    scaled = rows(lmp.run_deck(deck(coeff, legs_for(FRACTIONS, scale * u_r),
                                    {0: f"fix_modify wirenet_bonds scale {scale!r}"}), scaled_dir))
    np.testing.assert_allclose(scaled["u"], scale * plain["u"], rtol=1e-9, atol=1e-15)
    # the same steps intact (the one at the rupture elongation is decided by round-off)
    at_rupture = np.isclose(plain["u"], u_r, rtol=1e-9, atol=0)
    np.testing.assert_array_equal(scaled["nb"][~at_rupture], plain["nb"][~at_rupture])
    assert plain["nb"][-1] == 0 and plain["nb"][0] == 1          # the path breaks the bond
    intact = (plain["nb"] == 1) & ~at_rupture
    fmax = plain["F"].max()
    err = np.abs(scaled["F"][intact] / scale - plain["F"][intact]) / fmax
    assert err.max() < 1e-9
    # plastic work at scale 1: the same as the plain run's, step by step, rupture included
    w_plain, w_scaled = plain["wp"], scaled["wp"]
    assert w_plain[-1] > 0.0
    np.testing.assert_allclose(w_scaled[~at_rupture], w_plain[~at_rupture], rtol=1e-9, atol=1e-12 * w_plain[-1])


def test_a_change_of_scale_keeps_the_bond_on_its_envelope(tmp_path):
    coeff, u_r = CASES[TRACE]
    ref = np.loadtxt(lmp.TRACES / f"{TRACE}.dat")
    write_two_nodes(tmp_path / "two.data")
    s = 4.0
    # at scale 4 to 4 x 0.3 (yielded) and back to 4 x 0.05; then node 2 put at 0.05 u_r, scale
    # 1, and on through the rest of the trace's path (0.6, 0.55, 1.05)
    head = legs_for(FRACTIONS[:4], s * u_r)
    tail = legs_for(FRACTIONS[4:], u_r, start=FRACTIONS[3])
    back = (f"displace_atoms moving move {(FRACTIONS[3] * u_r * (1 - s))!r} 0 0 units box\n"
            "fix_modify wirenet_bonds scale 1")
    out = lmp.run_deck(deck(coeff, head + tail, {0: f"fix_modify wirenet_bonds scale {s!r}", 4: back}), tmp_path)
    got = rows(out)
    n_head = 4 * SUBSTEPS
    # the head, magnified: 4 times the trace
    np.testing.assert_allclose(got["u"][:n_head], s * ref[:n_head, 0], rtol=1e-9, atol=1e-15)
    fmax = np.nanmax(ref[:, 1])
    assert np.abs(got["F"][:n_head] / s - ref[:n_head, 1]).max() < 1e-6 * fmax
    # the tail: the trace itself (the state mapped to scale 1 at the change)
    u_tail, ref_tail = got["u"][n_head:], ref[n_head:]
    np.testing.assert_allclose(u_tail, ref_tail[:, 0], rtol=1e-9, atol=1e-12)
    at_rupture = np.isclose(ref_tail[:, 0], u_r, rtol=1e-9, atol=0)
    intact = ~np.isnan(ref_tail[:, 1]) & ~at_rupture
    assert intact.sum() > SUBSTEPS and (~intact).sum() > 0   # yielding again, then broken
    assert np.abs(got["F"][n_head:][intact] - ref_tail[intact, 1]).max() < 1e-6 * fmax
    # the plastic work of the whole path: that of a bond at scale 1 throughout
    plain_dir = tmp_path / "plain"
    plain_dir.mkdir()
    write_two_nodes(plain_dir / "two.data")
    plain = rows(lmp.run_deck(deck(coeff, legs_for(FRACTIONS, u_r)), plain_dir))
    w, w_plain = got["wp"], plain["wp"]
    np.testing.assert_allclose(w[n_head - 1], w_plain[n_head - 1], rtol=1e-9)
    np.testing.assert_allclose(w[-1], w_plain[-1], rtol=1e-9)


BAD_SCALE = {
    "no value": ("scale", "fix_modify wirenet_bonds: 'scale' needs a value"),
    "zero": ("scale 0", "fix_modify wirenet_bonds: scale must be > 0 (got 0)"),
    "negative": ("scale -2", "fix_modify wirenet_bonds: scale must be > 0 (got -2)"),
    "nan": ("scale nan", "fix_modify wirenet_bonds: scale must be a finite number (got 'nan')"),
    "inf": ("scale inf", "fix_modify wirenet_bonds: scale must be a finite number (got 'inf')"),
    "text": ("scale big", "fix_modify wirenet_bonds: scale must be a finite number (got 'big')"),
}


@pytest.mark.parametrize("case", sorted(BAD_SCALE))
def test_bad_scale_is_refused_in_one_line(tmp_path, case):
    args, phrase = BAD_SCALE[case]
    coeff, _ = CASES[TRACE]
    write_two_nodes(tmp_path / "two.data")
    text = deck(coeff, [(0.0, 1)], {0: f"fix_modify wirenet_bonds {args}"})
    line = lmp.one_error(text, tmp_path)
    assert phrase in line, line


def test_a_restart_keeps_the_scale(tmp_path):
    """Yielded at scale 4 and written to a restart file there; read back, the run goes on at
    scale 4 as the one that never stopped."""
    coeff, u_r = CASES[TRACE]
    s = 4.0
    legs = legs_for(FRACTIONS[:3], s * u_r)
    for d in ("whole", "first"):
        (tmp_path / d).mkdir()
        write_two_nodes(tmp_path / d / "two.data")
    whole = rows(lmp.run_deck(deck(coeff, legs, {0: f"fix_modify wirenet_bonds scale {s!r}"}), tmp_path / "whole"))
    first = deck(coeff, legs[:2], {0: f"fix_modify wirenet_bonds scale {s!r}"}) + "write_restart at2.restart\n"
    lmp.run_deck(first, tmp_path / "first")
    v, n = legs[2]
    second = lmp.PREAMBLE.replace("newton off on\n", "") + f"""read_restart at2.restart
bond_style wirenet
bond_coeff 1 {coeff}
group moving id 2
compute wl all wirenet/local
compute F all reduce sum c_wl[6]
compute nb all reduce sum c_wl[3]
variable u equal x[2]-x[1]-{L0!r}
timestep {DT!r}
run 0
variable wp equal f_wirenet_bonds[3]
thermo_style custom step v_u c_F c_nb v_wp
thermo_modify format float %.16g
thermo 1
fix mv moving move linear {v!r} 0 0
run {n}
"""
    got = rows(lmp.run_deck(second, tmp_path / "first", name="in.second"))
    for k in ("u", "F", "wp"):
        np.testing.assert_allclose(got[k], whole[k][-(n + 1):], rtol=1e-12, atol=1e-15)
    assert whole["wp"][-1] > 0.0
