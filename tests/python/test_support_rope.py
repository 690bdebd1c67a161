"""A fence's support rope as a chain of wire bonds with a rope curve (issue #18: "rope elongation
under load and breaking"), pulled quasi-statically from one anchor to rupture.

Five bonds of 0.4 m in series between an anchor node (held: no integrator) and an end node moved
at 0.5 m/s along the rope; the inner nodes are integrated and damped (fix viscous), so the rope
is in equilibrium at every step (its axial wave crosses it in about 0.6 ms, the pull lasts 0.1 s).
Then every bond carries the same tension T, and the anchor feels T with

    delta = N l0 e(T / A)          (e: the curve's strain at stress T / A, linear between points)

up to the breaking load A s_last, where one bond breaks and the anchor force drops to zero.
"""

import math

import numpy as np

import lmp

N, L0, D = 5, 0.4, 0.016                  # bonds, bond length [m], rope diameter [m]
A = math.pi * D * D / 4
CURVE = [(0.004, 4e8), (0.02, 8e8), (0.03, 8.5e8)]   # a steel rope's strain, stress on A
SPEED, DT = 0.5, 2e-6


def strain_at(stress):
    """The curve's strain at a stress (inverse of the piecewise-linear table through 0)."""
    e = [0.0] + [p[0] for p in CURVE]
    s = [0.0] + [p[1] for p in CURVE]
    return float(np.interp(stress, s, e))


def pull(tmp_path):
    atoms = [(k + 1, 1, k * L0, 0.0, 0.0, D, 7850.0, 1) for k in range(N + 1)]
    bonds = [(k + 1, 1, k + 1, k + 2) for k in range(N)]
    lmp.write_data(tmp_path / "rope.data", atoms, bonds, box=((-1, 3), (-1, 1), (-1, 1)))
    curve = " ".join(f"{e!r} {s!r}" for e, s in CURVE)
    steps = int(1.25 * N * L0 * CURVE[-1][0] / (SPEED * DT))
    deck = [lmp.PREAMBLE, "read_data rope.data", "bond_style wirenet",
            f"bond_coeff 1 wire diameter {D!r} curve {curve} family rope",
            f"timestep {DT!r}", "group inner id 2:5", f"group tip id {N + 1}",
            "fix integ inner nve/sphere", "fix calm inner viscous 20",
            f"fix drive tip move linear {SPEED!r} 0 0",
            "variable F equal fx[1]", f"variable d equal x[{N + 1}]-{N * L0!r}",
            "variable nb equal f_wirenet_bonds",
            "thermo_style custom step v_d v_F v_nb", "thermo_modify format float %.12g",
            "thermo 500", f"run {steps}"]
    out = lmp.run_deck("\n".join(deck) + "\n", tmp_path)
    rows = lmp.thermo_rows(out)
    rows = [r for r in rows if "nb" in r]
    return (np.array([r["d"] for r in rows]), np.array([r["F"] for r in rows]),
            np.array([r["nb"] for r in rows]))


def test_support_rope_stretches_as_its_curve_and_breaks_at_its_breaking_load(tmp_path):
    d, F, broken = pull(tmp_path)
    intact = broken == 0
    assert intact.sum() > 20 and broken[-1] == 1       # it broke, once
    breaking = A * CURVE[-1][1]
    # along the curve, below the breaking load: delta = N l0 e(T / A)
    for dk, fk in zip(d[intact], F[intact]):
        if fk > 0.1 * breaking:   # after the start-up transient of the sudden pull
            expected = N * L0 * strain_at(fk / A)
            assert abs(dk - expected) < 0.005 * expected, (dk, fk, expected)
    # elastic part: the rope's axial stiffness E A / (N l0)
    elastic = intact & (F > 0.3 * A * CURVE[0][1]) & (F < 0.9 * A * CURVE[0][1])
    E = CURVE[0][1] / CURVE[0][0]
    slope = np.polyfit(d[elastic], F[elastic], 1)[0]
    assert abs(slope - E * A / (N * L0)) < 0.01 * E * A / (N * L0)
    # the largest force is the breaking load, and the anchor is free of it once a bond broke
    assert abs(F[intact].max() - breaking) < 0.01 * breaking
    assert np.all(np.abs(F[~intact][1:]) < 0.01 * breaking)
