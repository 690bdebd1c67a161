"""bond_style wirenet gives the same answer on 1, 2 and 3 MPI ranks.

The net of netdeck.py is pulled along +x until wires break, with the rank split planes (x = 0 on
2 ranks, x = +-0.15 m on 3) through the net: bonds straddle the subdomains all the time, and nodes
migrate between ranks as the net stretches. On 3 ranks the middle one exchanges ghosts with both
neighbours in the same swap pair, which LIGGGHTS' communication (cmake/patches/0006) runs at once. The per-bond history must travel with its atom, bonds
whose partner is a ghost must see the same elongation, and ruptures must be decided identically.

Only the order of floating-point additions differs between the two decompositions (a node's force
is summed from local and ghost contributions). In an undamped tearing net those 1e-16 differences
grow exponentially, so the test damps the free nodes (fix viscous) and pulls slowly: the
comparison then checks the decomposition, not the chaos.
"""

import numpy as np
import pytest

import lmp
import netdeck

SPEED = 2.0        # m/s, x edge at +0.3
GAMMA = 200.0      # N s/m per node (node mass 3.9 g: strongly damped, quasi-static pull)
DT = 1e-5          # s (stable limit about 1.4e-5 for these nodes and wires)
STEPS = 10000      # the edge moves 0.2 m; wires break from about step 3500
EVERY = 1000
RTOL = 1e-10


def run(tmp_path, np_, margin_x=0.6):
    wd = tmp_path / f"np{np_}"
    netdeck.make_net(wd, margin_x)
    deck = netdeck.setup(SPEED, GAMMA, DT) + "thermo 1000\nrun 0\n" + netdeck.outputs(EVERY) + f"run {STEPS}\n"
    out = lmp.run_deck(deck, wd, np=np_)
    return wd, out


def rel_err(a, b, floor):
    return np.abs(a - b) / np.maximum(np.maximum(np.abs(a), np.abs(b)), floor)


# (ranks, x margin of the box): 3 ranks in a box of x = +-0.45 m cut at x = +-0.15 m, both planes
# inside the net (x = -0.4 ... 0.2 m, the pulled edge ends at 0.4 m)
LAYOUTS = [(2, 0.6), (3, 0.15)]


@pytest.mark.parametrize("np_,margin_x", LAYOUTS, ids=[f"np{n}" for n, _ in LAYOUTS])
def test_one_rank_and_more_agree(tmp_path, np_, margin_x):
    wd1, out1 = run(tmp_path, 1, margin_x)
    wd2, out2 = run(tmp_path, np_, margin_x)
    assert "1 by 1 by 1 MPI processor grid" in out1
    assert f"{np_} by 1 by 1 MPI processor grid" in out2

    b1, b2 = netdeck.bonds_by_step(wd1), netdeck.bonds_by_step(wd2)
    assert sorted(b1) == sorted(b2) == list(range(0, STEPS + 1, EVERY))
    initial = {tuple(r) for r in b1[0][:, :2].astype(int)}
    assert len(initial) == 215
    for step in b1:
        a, b = b1[step], b2[step]
        # same intact bonds (atom pairs and types)
        assert a.shape == b.shape, f"step {step}: {len(a)} bonds on 1 rank, {len(b)} on 2"
        assert np.array_equal(a[:, :3], b[:, :3]), f"step {step}: different intact bonds"
        if step == 0:
            continue
        tmax = np.abs(a[:, 5]).max()
        assert tmax > 100.0, f"step {step}: the net is not loaded (max tension {tmax} N)"
        # per-bond tension and strain. One unit in the last place of a node coordinate (5e-17 m)
        # times a wire stiffness of 2e7 N/m is 1e-9 N: relative to a nearly slack bond that is no
        # longer small, so the ratio is taken against at least 1 % of the largest value.
        err = rel_err(a[:, 5], b[:, 5], 1e-2 * tmax)
        assert err.max() < RTOL, f"step {step}: tension differs by {err.max():.3g} (bond {a[err.argmax(), :2]})"
        err = rel_err(a[:, 4], b[:, 4], 1e-2 * np.abs(a[:, 4]).max())
        assert err.max() < RTOL, f"step {step}: strain differs by {err.max():.3g}"
        np.testing.assert_array_equal(a[:, 3], b[:, 3])  # initial lengths: exactly the same

    # ruptures: the same bonds, at the same step, at the same elongation
    final = b1[STEPS]
    intact = {tuple(r) for r in final[:, :2].astype(int)}
    broken = initial - intact
    assert len(broken) >= 5, f"only {len(broken)} bonds broke"
    assert len(intact) >= 150, "the net fell apart: the comparison would test nothing"
    r1, r2 = netdeck.ruptures_by_step(wd1)[STEPS], netdeck.ruptures_by_step(wd2)[STEPS]
    assert {tuple(r) for r in r1[:, 1:3].astype(int)} == broken
    assert {tuple(r) for r in r2[:, 1:3].astype(int)} == broken
    np.testing.assert_array_equal(r1[:, :4], r2[:, :4])  # step atom1 atom2 type
    assert rel_err(r1[:, 7], r2[:, 7], 1e-6).max() < RTOL  # elongation at rupture
    assert np.abs(r1[:, 4:7] - r2[:, 4:7]).max() < 1e-12  # rupture position (m)

    # the broken count of the history fix (thermo) matches on both
    n1 = [r["nb"] for r in lmp.thermo_rows(out1)]
    n2 = [r["nb"] for r in lmp.thermo_rows(out2)]
    assert n1 == n2 and n1[-1] == len(broken)

    # energy per bond type (fix wirenet_bonds' array): the types add up to the totals at every
    # row, each type's tallies agree between the decompositions, a type releases energy exactly
    # when one of its bonds broke, and the unused type 4 has nothing
    for out, ruptures in ((out1, r1), (out2, r2)):
        for row in lmp.thermo_rows(out):
            for name, total in (("el", "eb"), ("rel", "rel"), ("pl", "pl"), ("damp", "damp")):
                parts = sum(row[f"{name}_{t}"] for t in range(1, 5))
                assert abs(parts - row[total]) <= 1e-12 * max(abs(row[total]), 1e-9), (name, row)
                assert row[f"{name}_4"] == 0.0
            broken_types = set(ruptures[:, 3].astype(int))
            if row["Step"] == STEPS:
                assert {t for t in (1, 2, 3) if row[f"rel_{t}"] > 0.0} == broken_types
                assert row["pl_1"] > 0.0 and row["pl_2"] > 0.0
    for a, b in zip(lmp.thermo_rows(out1), lmp.thermo_rows(out2)):
        for name in ("el", "rel", "pl"):
            for t in (1, 2, 3):
                assert rel_err(a[f"{name}_{t}"], b[f"{name}_{t}"], 1e-6) < 1e-9, (a["Step"], name, t)

    # the decomposition did something: bonds straddle every split plane throughout, and nodes
    # crossed them (migrated between ranks) during the run
    half = 0.3 + margin_x
    cuts = [-half + 2 * half * k / np_ for k in range(1, np_)]
    atoms = lmp.dump_atom_frames(wd2 / "atoms.dump")
    rank0 = None
    crossed = set()
    for step, (cols, a) in sorted(atoms.items()):
        x = dict(zip(a[:, 0].astype(int), a[:, cols.index("x")]))
        rank = {i: int(np.searchsorted(cuts, xi, side="right")) for i, xi in x.items()}
        pairs = [tuple(r) for r in b2[step][:, :2].astype(int)]
        for cut in cuts:
            straddling = [1 for (i, j) in pairs if (x[i] >= cut) != (x[j] >= cut)]
            assert len(straddling) >= 5, f"step {step}: only {len(straddling)} bonds cross x = {cut:g}"
        if rank0 is None:
            rank0 = rank
        crossed |= {i for i in rank if rank[i] != rank0[i]}
    assert len(crossed) >= 5, f"only {len(crossed)} nodes changed rank"


def test_long_bond_across_ranks(tmp_path):
    """A bond much longer than the default ghost cutoff, split by the rank boundary, needs no
    `communicate cutoff`: the style extends the ghost cutoff itself (LIGGGHTS halves it for
    spheres, which the extension must allow for)."""
    results = {}
    for np_ in (1, 2):
        wd = tmp_path / f"np{np_}"
        wd.mkdir()
        # node 1 just left of the split plane, node 2 0.18 m right of it: the bond is stored on
        # node 1 (rank 0) and node 2 must be a ghost there
        atoms = [(1, 1, -0.02, 0.0, 0.0, 0.0108, 7850.0, 1), (2, 1, 0.18, 0.0, 0.0, 0.0108, 7850.0, 1)]
        lmp.write_data(wd / "long.data", atoms, [(1, 1, 1, 2)])
        deck = lmp.PREAMBLE + f"""processors * 1 1
read_data long.data
bond_style wirenet
bond_coeff 1 wire diameter 0.0027 curve {netdeck.SW_CURVE}
group pulled id 2
fix pull pulled move linear 1 0 0
compute bl all wirenet/local
compute T all reduce sum c_bl[6]
variable T equal c_T
thermo_style custom step v_T
thermo_modify format float %.17g
thermo 100
timestep 1e-5
run 1000
"""
        out = lmp.run_deck(deck, wd, np=np_)
        results[np_] = [r["T"] for r in lmp.thermo_rows(out)]
    assert results[1] == results[2]
    assert results[1][-1] > 1000.0  # loaded (elongation 10 mm on 0.2 m)


def test_partner_beyond_the_ghosts_is_a_clear_error(tmp_path):
    """The ghosts follow the longest bond from one list build to the next, which holds while no
    atom moves more than half the skin in between. A deck that rebuilds only every 200 steps
    without checking (`check no`) lets a bond across the rank boundary outgrow the reach (0.2 m
    pulled 0.06 m in 200 steps): the run stops with one line that names the bond and the setting
    to raise, not LIGGGHTS' generic 'Bond atoms missing'."""
    deck = netdeck.outgrown_bond(tmp_path)
    rc, out = lmp.run_deck_rc(deck, tmp_path, np=2)
    errors = lmp.error_lines(out)
    assert rc != 0 and len(errors) == 1, out[-1500:]
    assert "bond_style wirenet: bond 1-2 reaches beyond the ghost atoms" in errors[0], errors[0]
    assert "at step 200" in errors[0] and "communicate single cutoff C" in errors[0], errors[0]
