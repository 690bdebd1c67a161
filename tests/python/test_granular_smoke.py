"""Smoke test of the plain LIGGGHTS granular stack of this build, on 1 and 2 MPI ranks.

Four spheres under gravity with a Hertz granular pair style (no walls):
- spheres 1 and 2 fly freely across the rank split plane x = 0 (in opposite directions). Velocity
  Verlet is exact for a constant force, so their positions must follow x0 + v0 t + g t^2 / 2 to
  round-off (1e-12 relative to the size of the trajectory);
- spheres 3 and 4 collide head-on at the split plane (sphere 3 on rank 0, sphere 4 on rank 1 on two
  ranks): momentum is conserved, they rebound with less than their approach speed, and their
  vertical motion stays ballistic (the contact acts along x only).
Both ranks counts must give the same trajectories.
"""

import numpy as np
import pytest

import lmp

G = 9.81
DT = 1e-4
STEPS = 4000
T = DT * STEPS
DIAMETER = 0.05
DENSITY = 2500.0

# id: (position, velocity)
SPHERES = {
    1: ((-0.3, -0.5, 0.5), (1.5, 0.1, 3.0)),
    2: ((0.3, 0.5, 0.5), (-1.5, -0.1, 2.0)),
    3: ((-0.3, 0.0, -0.5), (1.0, 0.0, 2.0)),
    4: ((0.3, 0.0, -0.5), (-1.0, 0.0, 2.0)),
}


def deck():
    lines = [lmp.GRANULAR_PREAMBLE + """processors * 1 1
region box block -1 1 -1 1 -2 2 units box
create_box 1 box
neighbor 0.01 bin
neigh_modify delay 0
pair_style gran model hertz tangential history
pair_coeff * *
""" + lmp.HERTZ_MATERIALS]
    for i, (x, v) in SPHERES.items():
        lines.append(f"create_atoms 1 single {x[0]!r} {x[1]!r} {x[2]!r} units box")
    for i, (x, v) in SPHERES.items():
        lines.append(f"group s{i} id {i}")
        lines.append(f"set group s{i} diameter {DIAMETER!r} density {DENSITY!r}")
        lines.append(f"velocity s{i} set {v[0]!r} {v[1]!r} {v[2]!r} units box")
    cols = []
    for i in SPHERES:
        for q in ("x", "y", "z", "vx", "vy", "vz"):
            lines.append(f"variable {q}{i} equal {q}[{i}]")
            cols.append(f"v_{q}{i}")
    lines.append(f"""fix gravi all gravity {G!r} vector 0 0 -1
fix integrate all nve/sphere
timestep {DT!r}
thermo_style custom step {' '.join(cols)}
thermo_modify format float %.17g
thermo 100
run {STEPS}
""")
    return "\n".join(lines)


@pytest.fixture(scope="module")
def runs(tmp_path_factory):
    out = {}
    for np_ in (1, 2):
        wd = tmp_path_factory.mktemp(f"gran_np{np_}")
        text = lmp.run_deck(deck(), wd, np=np_)
        assert f"{np_} by 1 by 1 MPI processor grid" in text
        out[np_] = lmp.thermo_rows(text)
    return out


def ballistic(i, t):
    x0, v0 = (np.array(a, dtype=float) for a in SPHERES[i])
    g = np.array([0.0, 0.0, -G])
    return x0 + v0 * t + 0.5 * g * t * t, v0 + g * t


def state(rows, i):
    t = np.array([r["Step"] * DT for r in rows])
    x = np.array([[r[f"{q}{i}"] for q in ("x", "y", "z")] for r in rows])
    v = np.array([[r[f"v{q}{i}"] for q in ("x", "y", "z")] for r in rows])
    return t, x, v


@pytest.mark.parametrize("np_", [1, 2])
@pytest.mark.parametrize("i", [1, 2])
def test_free_flight_is_ballistic(runs, np_, i):
    rows = runs[np_]
    assert rows[-1]["Step"] == STEPS
    t, x, v = state(rows, i)
    xe, ve = ballistic(i, t[:, None])
    x0, v0 = (np.array(a) for a in SPHERES[i])
    scale = np.abs(x0).max() + np.abs(v0).max() * T + 0.5 * G * T * T
    assert np.abs(x - xe).max() / scale < 1e-12
    assert np.abs(v - ve).max() / (np.abs(v0).max() + G * T) < 1e-12
    # it crossed the split plane x = 0
    assert np.sign(x[0, 0]) != np.sign(x[-1, 0])


def test_ranks_agree(runs):
    a, b = runs[1], runs[2]
    assert [r["Step"] for r in a] == [r["Step"] for r in b]
    for ra, rb in zip(a, b):
        for key in ra:
            assert abs(ra[key] - rb[key]) <= 1e-12 * max(1.0, abs(ra[key])), (ra["Step"], key)


@pytest.mark.parametrize("np_", [1, 2])
def test_collision_across_ranks(runs, np_):
    rows = runs[np_]
    t, x3, v3 = state(rows, 3)
    _, x4, v4 = state(rows, 4)
    # they approached until touching (centre gap one diameter), then moved apart
    gap = np.linalg.norm(x4 - x3, axis=1)
    assert gap.min() < 1.5 * DIAMETER and gap[-1] > 2 * DIAMETER
    # rebound: each reversed its x velocity, slower than before (restitution 0.5)
    assert v3[-1, 0] < 0 < v4[-1, 0]
    assert 0.2 < -v3[-1, 0] < 0.9 and 0.2 < v4[-1, 0] < 0.9
    # equal masses, equal and opposite contact forces: momentum along x stays zero
    assert np.abs(v3[:, 0] + v4[:, 0]).max() < 1e-12
    # the contact is along x: the vertical motion is untouched by it
    for i, xi, vi in ((3, x3, v3), (4, x4, v4)):
        xe, ve = ballistic(i, t[:, None])
        assert np.abs(xi[:, 2] - xe[:, 2]).max() < 1e-12 * 2.0
        assert np.abs(xi[:, 1]).max() < 1e-12
