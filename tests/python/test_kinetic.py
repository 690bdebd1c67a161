"""fix wirenet/kinetic: kinetic damping, the fence's settling (doc/fix_wirenet_kinetic.md). Checks:
- one mass hanging from a spring, released at the spring's rest length: its kinetic energy
  peaks at the static equilibrium, a quarter of Verlet's period after the release, at
  (m g)^2 / 2k; the fix stops it there, and it stays within omega dt of the equilibrium;
- a rope held at both ends comes to the static state of the long locally damped run (the
  supports carry half the weight each, the same sag to 10 um) in a fifth of its steps, where
  local damping alone is still 0.1 mm from it;
- the same stops and states on 1 and 2 MPI ranks;
- bad arguments: one ERROR line naming the fix.
"""

import math

import numpy as np
import pytest

import lmp
from test_hold import N, G, RHO, D, deck, numbers, rope_data

K, L0 = 2.0e6, 0.25                # harmonic bond: E = K (r - r0)^2, so the spring is 2K [N/m]
MASS_DENSITY = 7850.0e4            # a 71 kg sphere of 12 mm: a sag of 0.17 mm
DT = 1.0e-5


def spring_deck():
    m = MASS_DENSITY * math.pi * D ** 3 / 6
    lines = [lmp.PREAMBLE, "read_data spring.data", "bond_style harmonic", f"bond_coeff 1 {K!r} {L0!r}",
             f"timestep {DT!r}", "group free id 2", "fix integ free nve/sphere",
             f"fix grav free wirenet/gravity {G!r} vector 0 0 -1", "fix kin free wirenet/kinetic",
             'fix out all print 1 "S $(step) $(z[2]) $(f_kin[1]) $(f_kin[2]) $(f_kin[3]) $(f_kin[4])" screen yes',
             "run 3000"]
    return "\n".join(lines) + "\n", m


def test_one_mode_stops_at_its_static_equilibrium(tmp_path):
    lmp.write_data(tmp_path / "spring.data",
                   [(1, 1, 0.0, 0.0, 0.0, D, RHO, 1), (2, 1, 0.0, 0.0, -L0, D, MASS_DENSITY, 1)],
                   [(1, 1, 1, 2)])
    text, m = spring_deck()
    rows = numbers(lmp.run_deck(text, tmp_path), "S")
    k = 2 * K
    delta = m * G / k                                       # the static stretch
    z_eq = -L0 - delta
    omega = math.sqrt(k / m)
    # Verlet's discrete frequency: sin(w' dt / 2) = w dt / 2
    quarter = (math.pi / 2) / (2 * math.asin(omega * DT / 2) / DT)
    first = rows[np.argmax(rows[:, 2] > 0)]
    assert abs(first[0] * DT - quarter) <= 2 * DT           # a quarter period after the release
    assert first[3] == pytest.approx(0.5 * k * delta ** 2, rel=1e-3)   # the peak: (m g)^2 / 2k
    assert abs(first[1] - z_eq) < 2 * omega * DT * delta    # stopped at the equilibrium
    after = rows[rows[:, 0] >= first[0]]
    assert np.abs(after[:, 1] - z_eq).max() < 2 * omega * DT * delta   # and it stays there
    assert omega * DT < 0.01 and delta > 1e-4               # the bounds above are tight ones
    assert rows[-1, 2] > 1                                  # later stops take what was left


def settle_rope(tmp_path, steps, kinetic, np_=1):
    """The rope of test_hold between its held ends, released from its V: with kinetic damping
    alone, or with local damping 0.7 alone; the last row: step, the two ends' vertical
    reactions (means over the last 1000 steps), the middle node's z, node 3's x."""
    rope_data(tmp_path / "rope.data")
    extra = ["fix kin inner wirenet/kinetic"] if kinetic else []
    out = lmp.run_deck(deck(["fix h ends wirenet/hold 0 0 0 mean 1000 each",
                             f'fix out all print {steps} "E $(step) $(f_h[1][7]) $(f_h[2][7]) '
                             f'$(z[{N // 2 + 1}]) $(x[3])" screen yes'] + extra,
                            steps=steps, shake=False, calm=not kinetic),
                       tmp_path, np=np_, name=f"in.rope{int(kinetic)}{np_}{steps}")
    return numbers(out, "E")[-1]


def test_a_rope_settles_in_a_fifth_of_the_steps(tmp_path):
    """The rope's slowest mode (its sag) takes about 0.08 s a swing: local damping creeps
    towards the static state, kinetic damping stops the rope as it passes through it."""
    weight = (N + 1) * RHO * math.pi * D ** 3 / 6 * G
    slow = settle_rope(tmp_path, 400000, kinetic=False)
    fast = settle_rope(tmp_path, 80000, kinetic=True)
    short = settle_rope(tmp_path, 80000, kinetic=False)
    assert abs(slow[1] - weight / 2) < 1e-6 * weight and abs(slow[2] - weight / 2) < 1e-6 * weight
    assert abs(fast[1] - weight / 2) < 2e-3 * weight and abs(fast[2] - weight / 2) < 2e-3 * weight
    assert abs(fast[3] - slow[3]) < 1e-5 and abs(fast[4] - slow[4]) < 1e-6    # the same sag
    # local damping alone, after the same steps, is still 0.1 mm or more from it
    assert abs(short[3] - slow[3]) > 1e-4


def test_the_same_on_two_ranks(tmp_path):
    one = settle_rope(tmp_path, 40000, kinetic=True)
    two = settle_rope(tmp_path, 40000, kinetic=True, np_=2)
    assert np.allclose(one, two, rtol=1e-10, atol=1e-13)


@pytest.mark.parametrize("args", ["wirenet/kinetic 1", "wirenet/kinetic yes no"])
def test_bad_arguments_give_one_error_line(tmp_path, args):
    rope_data(tmp_path / "rope.data")
    error = lmp.one_error(deck([f"fix kin inner {args}"], steps=10, shake=False), tmp_path)
    assert "fix wirenet/kinetic: expected 'fix ID GROUP wirenet/kinetic'" in error, error
