"""Every column of `compute wirenet/local` against values computed by hand (doc/compute_wirenet_local.md).

Three nodes with IDs 9, 5, 2 (not in data-file order) at known, generic 3-D positions, joined by a
triangle of bonds of three types:

    bond 1, type 2: wire, plain (SW curve), stored on node 9, partner 5
    bond 2, type 1: beam (E = 60 GPa, bending 0.05, shear eb), stored on node 2, partner 9
    bond 3, type 3: wire with slack (lambda_u 0.1, lambda_f 1, seed -1: dl = 0.1 l0), stored on 5, partner 2

`run 0` sets the initial lengths; then nodes 5 and 2 are moved by known vectors (the wires
stretch into their first loading branch, the beam is shortened and turned, the nodes keep their
orientation) and a `dump local` of all 12 columns at the next `run 0` is compared, column by
column, with:

    atom1 atom2 type                 the data file (atom1 = the node that stores the bond)
    length0                          |x_j - x_i| at the first run
    strain                           (L - L0) / L0, geometric (the slack is not subtracted)
    tension                          wire: F1/u1' u (first branch), u1' = dl + e1 (l0 + dl);
                                     beam: E A / L0 (L - L0) (negative: compressed)
    length                           |x_j - x_i| now
    xm ym zm                         (x_i + x_j) / 2 now
    shear                            wire 0; beam: 4 Cs alpha / L, Cs = 3 f E I / L0
    moment                           wire 0; beam: 2 Cs alpha
                                     (alpha = angle between the current and the initial chord)

The expected values of a row are pairwise distinct, so a swapped or shifted column fails. The
group of the compute selects the bonds with both nodes in it.
"""

import math

import numpy as np
import pytest

import lmp

WIRE_D = 0.0027
SW = [(0.0019230769, 2.5e8), (0.0192, 3.2195e8), (0.05, 3.8292e8), (0.15, 5.1219e8),
      (0.25, 5.5854e8), (0.30, 5.6585e8), (0.35, 5.6585e8)]
CURVE = " ".join(f"{e!r} {s!r}" for e, s in SW)
E1, S1 = SW[0]
A_WIRE = math.pi * WIRE_D**2 / 4
BEAM_D, BEAM_E, BEAM_NU, BEAM_F = 0.012, 6e10, 0.3, 0.05
LAMBDA_U = 0.1

# initial positions (m)
P = {5: np.array([0.011, 0.023, 0.031])}
P[9] = P[5] + 0.040 * np.array([2.0, 1.0, 2.0]) / 3.0
P[2] = P[9] + 0.070 * np.array([1.0, -2.0, 2.0]) / 3.0
# moves after the first run
# node 5: 40 um away from node 9 along the wire 9-5; node 2: 10 um towards node 9 along the beam and
# 25 um across it (normal to the beam and to the wire 5-2); the wire 5-2 stretches by 21 um
MOVE = {5: np.array([-2.667e-05, -1.333e-05, -2.667e-05]), 2: np.array([1.527e-05, 4.6e-07, -2.217e-05])}
BONDS = [(1, 2, 9, 5), (2, 1, 2, 9), (3, 3, 5, 2)]  # id type atom1 atom2

COLUMNS = ("atom1", "atom2", "type", "length0", "strain", "tension", "length", "xm", "ym", "zm",
           "shear", "moment")


def wire_tension(u, l0, dl):
    """First loading branch of the wire law (lambda_f = 1): F1 u / (dl + e1 (l0 + dl))."""
    u1 = dl + E1 * (l0 + dl)
    assert 0 < u < u1, "the move must keep the wire on its first loading branch"
    return S1 * A_WIRE * u / u1


def expected_rows():
    now = {i: P[i] + MOVE.get(i, 0.0) for i in P}
    rows = {}
    for _, btype, i, j in BONDS:
        d0, d = P[j] - P[i], now[j] - now[i]
        l0, L = np.linalg.norm(d0), np.linalg.norm(d)
        if btype == 1:
            r = BEAM_D / 2
            EA, EI = BEAM_E * math.pi * r**2, BEAM_E * math.pi * r**4 / 4
            Cs = 3 * BEAM_F * EI / l0
            e0, e = d0 / l0, d / L
            alpha = math.atan2(np.linalg.norm(np.cross(e0, e)), float(e0 @ e))
            tension, shear, moment = EA / l0 * (L - l0), 4 * Cs * alpha / L, 2 * Cs * alpha
        else:
            dl = LAMBDA_U * l0 if btype == 3 else 0.0
            tension, shear, moment = wire_tension(L - l0, l0, dl), 0.0, 0.0
        mid = 0.5 * (now[i] + now[j])
        rows[(i, j)] = np.array([i, j, btype, l0, (L - l0) / l0, tension, L, *mid, shear, moment])
    return rows


def write_triangle(path):
    atoms = [(k, 1, *map(float, P[k]), 0.0108, 7850.0, 1) for k in (9, 5, 2)]
    lmp.write_data(path, atoms, BONDS, nbond_types=3, box=((-0.1, 0.2), (-0.1, 0.2), (-0.1, 0.2)))


def run_columns(tmp_path, group="all"):
    write_triangle(tmp_path / "tri.data")
    cols = " ".join(f"c_wl[{k}]" for k in range(1, 13))
    moves = "\n".join(f"displace_atoms m{i} move {v[0]!r} {v[1]!r} {v[2]!r} units box" for i, v in MOVE.items())
    deck = lmp.PREAMBLE + f"""read_data tri.data
bond_style wirenet
bond_coeff 1 beam diameter {BEAM_D} E {BEAM_E} nu {BEAM_NU} bending {BEAM_F} shear eb
bond_coeff 2 wire diameter {WIRE_D} curve {CURVE}
bond_coeff 3 wire diameter {WIRE_D} curve {CURVE} slack lambda_u {LAMBDA_U} lambda_f 1.0 seed -1
group m5 id 5
group m2 id 2
group g59 id 5 9
group g29 id 2 9
group g25 id 2 5
run 0
{moves}
compute wl {group} wirenet/local
dump d all local 1 bonds.dump {cols}
dump_modify d format "%.0f %.0f %.0f{' %.17g' * 9}"
run 0
"""
    lmp.run_deck(deck, tmp_path)
    frames = lmp.dump_local_frames(tmp_path / "bonds.dump")
    return frames[max(frames)]


def test_expected_values_are_distinct():
    """Precondition of the column test: within a row, no two columns could be confused."""
    for key, row in expected_rows().items():
        nonzero = [v for v in row if v != 0.0]
        for a in range(len(nonzero)):
            for b in range(a + 1, len(nonzero)):
                assert not math.isclose(nonzero[a], nonzero[b], rel_tol=1e-6), f"bond {key}: two columns ~ {nonzero[a]}"
    beam = expected_rows()[(2, 9)]
    assert beam[5] < 0 and beam[10] > 0 and beam[11] > 0 and beam[10] != beam[11]


def test_every_column(tmp_path):
    got = run_columns(tmp_path)
    want = expected_rows()
    assert got.shape == (3, 12), f"{got.shape[0]} rows x {got.shape[1]} columns, expected 3 x 12"
    for row in got:
        key = (int(row[0]), int(row[1]))
        assert key in want, f"row for atom1 {key[0]}, atom2 {key[1]}: not a bond as stored (expected {sorted(want)})"
        w = want[key]
        for k, name in enumerate(COLUMNS):
            if k < 3:
                assert row[k] == w[k], f"bond {key}: column {k + 1} ({name}) = {row[k]}, expected {w[k]:.0f}"
                continue
            # lengths and positions exact to round-off; forces and strains derived from a
            # difference of lengths (L - L0 ~ 1e-5 m of ~0.05 m): 1e-9 relative
            tol = 1e-9 * abs(w[k]) if w[k] != 0 else 1e-12
            assert abs(row[k] - w[k]) <= tol, \
                f"bond {key}: column {k + 1} ({name}) = {row[k]!r}, expected {w[k]!r} (rel. error {abs(row[k] - w[k]) / max(abs(w[k]), 1e-300):.2e})"


@pytest.mark.parametrize("group,bonds", [("g59", [(9, 5)]), ("g29", [(2, 9)]), ("g25", [(5, 2)])])
def test_group_selects_bonds_with_both_nodes(tmp_path, group, bonds):
    got = run_columns(tmp_path, group)
    ids = [tuple(int(v) for v in r[:2]) for r in got]
    assert ids == bonds, f"compute on group {group}: rows for bonds {ids}, expected {bonds} (both nodes in the group)"
    want = expected_rows()[bonds[0]]
    np.testing.assert_allclose(got[0], want, rtol=1e-9, atol=1e-12)
