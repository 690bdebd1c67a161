"""fix wirenet/gravity: the weight m g of every atom of the group, as LIGGGHTS' fix gravity in
its vector form, without fix gravity's per-step energy sum. Checks:
- a shaken, damped rope held at both ends moves as under fix gravity, bit for bit;
- a free rope falls as one body: z(t) = z0 - g t^2 / 2 (velocity Verlet is exact for a constant
  acceleration) and its bonds keep their lengths; the fix reports g along its direction;
- the same on 1 and 2 MPI ranks;
- bad arguments: one ERROR line naming the item.
"""

import math

import numpy as np
import pytest

import lmp
from test_hold import N, DT, G, deck, numbers, rope_data

PRINT_MID = f'fix out all print 50 "P $(step) $(x[{N // 2 + 1}]) $(z[{N // 2 + 1}]) $(vz[{N // 2 + 1}])" screen yes'


def with_gravity(text, fix):
    return text.replace(f"fix grav all gravity {G!r} vector 0 0 -1", fix)


def test_the_trajectory_is_fix_gravitys_bit_for_bit(tmp_path):
    rope_data(tmp_path / "rope.data")
    held = deck(["fix h ends wirenet/hold 0 0 0", PRINT_MID], calm=True)
    ref = numbers(lmp.run_deck(held, tmp_path), "P")
    ours = numbers(lmp.run_deck(with_gravity(held, f"fix grav all wirenet/gravity {G!r} vector 0 0 -1"),
                                tmp_path, name="in.ours"), "P")
    assert ref.shape == ours.shape and len(ref) > 10
    assert np.array_equal(ref, ours)
    assert ref[-1, 2] < ref[0, 2] - 1e-7                  # the taut rope did sag under its weight


def free_fall(tmp_path, np_=1, direction="0 0 -2"):
    rope_data(tmp_path / "rope.data")
    text = with_gravity(deck([], steps=1000, shake=False),
                        f"fix grav all wirenet/gravity {G!r} vector {direction}")
    # every node free: the inner nodes' integrator on all of them
    text = text.replace("fix integ inner nve/sphere", "fix integ all nve/sphere")
    text = text.replace("run 1000", 'fix out all print 100 "F $(step) $(z[1]) $(z[5]) $(vz[9]) '
                        '$(f_grav[1]) $(f_grav[2]) $(f_grav[3])" screen yes\nrun 1000')
    return numbers(lmp.run_deck(text, tmp_path, np=np_, name=f"in.fall{np_}"), "F")


def test_a_free_rope_falls_as_one_body(tmp_path):
    rows = free_fall(tmp_path)
    z0 = [-0.0, -0.05 * (1 - abs(2 * 4 / N - 1))]
    t = rows[:, 0] * DT
    assert np.allclose(rows[:, 1], z0[0] - 0.5 * G * t ** 2, rtol=0, atol=1e-12)
    assert np.allclose(rows[:, 2], z0[1] - 0.5 * G * t ** 2, rtol=0, atol=1e-12)
    assert np.allclose(rows[:, 3], -G * t, rtol=1e-12, atol=1e-12)
    assert rows[-1, 3] < -0.01                             # it did fall
    # the direction is normalised: vector 0 0 -2 is g along -z
    assert np.array_equal(rows[0, 4:7], [0.0, 0.0, -G])


def test_the_same_on_two_ranks(tmp_path):
    one = free_fall(tmp_path, direction="1 0 -1")
    two = free_fall(tmp_path, np_=2, direction="1 0 -1")
    assert one.shape == two.shape
    assert np.allclose(one, two, rtol=1e-12, atol=1e-15)
    assert one[0, 4] == pytest.approx(G / math.sqrt(2), rel=1e-15)


BAD = [
    ("wirenet/gravity 9.81", "expected 'fix ID GROUP wirenet/gravity G vector X Y Z'"),
    ("wirenet/gravity 9.81 chute 10", "expected 'fix ID GROUP wirenet/gravity G vector X Y Z'"),
    ("wirenet/gravity 9.81 vector 0 0", "expected 'fix ID GROUP wirenet/gravity G vector X Y Z'"),
    ("wirenet/gravity nan vector 0 0 -1", "G must be a finite number (got 'nan')"),
    ("wirenet/gravity 9.81 vector 0 x -1", "vector Y must be a finite number (got 'x')"),
    ("wirenet/gravity 9.81 vector 0 0 0", "the vector X Y Z must have a finite, non-zero length"),
    ("wirenet/gravity 9.81 vector 1e300 1e300 0", "the vector X Y Z must have a finite, non-zero length"),
]


@pytest.mark.parametrize("args,message", BAD)
def test_bad_arguments_give_one_error_line(tmp_path, args, message):
    rope_data(tmp_path / "rope.data")
    error = lmp.one_error(with_gravity(deck([], steps=10, shake=False), f"fix grav all {args}"),
                          tmp_path)
    assert message in error and "fix wirenet/gravity" in error, error
