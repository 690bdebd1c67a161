"""fix wirenet/hold: a support that zeroes the held force components (as fix setforce 0) and
reports the support reaction, at the step and as window means summed on each rank (one
collective per output row instead of one per step), optionally per atom (anchors, post bases).

A steel rope of 8 wire bonds hangs between two anchors under gravity; its middle node is shaken
by a sinusoidal force, so reactions change at every step. Checks:
- the trajectory is the one of fix setforce 0 0 0, bit for bit, and the reaction is minus
  setforce's removed force; the window mean is fix ave/time's mean of that reaction;
- at rest the anchors carry the rope's weight, half each (symmetry), and pull inwards equally;
  the per-atom rows add up to the total;
- the same on 1 and 2 MPI ranks; a mean asked between window ends is the last complete window's;
- bad arguments: one ERROR line naming the item.
"""

import math

import numpy as np
import pytest

import lmp

N, L0, D = 8, 0.25, 0.012
A = math.pi * D * D / 4
CURVE = "0.004 4e8 0.02 8e8 0.03 8.5e8"
RHO, G = 7850.0, 9.81
WINDOW, STEPS, DT = 50, 2000, 2e-6


def rope_data(path, box_x=(-1, 3)):
    # anchors 1 and N+1 at the ends; the rope sags by 5 cm in a V so that it starts near its shape
    atoms = []
    for k in range(N + 1):
        z = -0.05 * (1 - abs(2 * k / N - 1))
        atoms.append((k + 1, 1, k * L0 * 0.995, 0.0, z, D, RHO, 1))
    bonds = [(k + 1, 1, k + 1, k + 2) for k in range(N)]
    lmp.write_data(path, atoms, bonds, box=(box_x, (-1, 1), (-1, 1)))


def deck(support, steps=STEPS, extra=(), shake=True, calm=False):
    lines = [lmp.PREAMBLE, "communicate single cutoff 0.6", "read_data rope.data", "bond_style wirenet",
             f"bond_coeff 1 wire diameter {D!r} curve {CURVE} family rope",
             f"timestep {DT!r}", f"group ends id 1 {N + 1}", f"group inner id 2:{N}",
             f"group mid id {N // 2 + 1}",
             "fix integ inner nve/sphere", f"fix grav all gravity {G!r} vector 0 0 -1"]
    if calm:
        lines.append("fix calm inner wirenet/damping 0.7")
    if shake:
        lines.append("variable fs equal 0.5*sin(step*0.02)")
        lines.append("fix shake mid addforce v_fs 0 v_fs")
    lines += list(support) + list(extra) + [f"run {steps}"]
    return "\n".join(lines) + "\n"


def numbers(out, tag):
    rows = [line.split()[1:] for line in out.splitlines() if line.startswith(tag + " ")]
    return np.array(rows, float)


PRINT_HOLD = (f'fix out all print {WINDOW} "H $(step) $(f_h[1]) $(f_h[2]) $(f_h[3]) '
              f'$(f_h[4]) $(f_h[5]) $(f_h[6]) $(x[{N // 2 + 1}]) $(z[{N // 2 + 1}])" screen yes')


def test_hold_is_setforce_with_the_reaction_and_its_window_mean(tmp_path):
    rope_data(tmp_path / "rope.data")
    held = lmp.run_deck(deck([f"fix h ends wirenet/hold 0 0 0 mean {WINDOW}", PRINT_HOLD]), tmp_path)
    ref = lmp.run_deck(deck(["fix h ends setforce 0 0 0",
                             "variable rx equal -f_h[1]", "variable ry equal -f_h[2]", "variable rz equal -f_h[3]",
                             f"fix m all ave/time 1 {WINDOW} {WINDOW} v_rx v_ry v_rz",
                             f'fix out all print {WINDOW} "H $(step) $(v_rx) $(v_ry) $(v_rz) '
                             f'$(f_m[1]) $(f_m[2]) $(f_m[3]) $(x[{N // 2 + 1}]) $(z[{N // 2 + 1}])" screen yes']),
                       tmp_path, name="in.ref")
    h, r = numbers(held, "H"), numbers(ref, "H")
    assert h.shape == r.shape and len(h) == STEPS // WINDOW
    assert np.array_equal(h[:, 7:], r[:, 7:])              # the same trajectory, bit for bit
    scale = np.abs(r[1:, 4:7]).max()
    assert np.abs(h[:, 1:4] - r[:, 1:4]).max() < 1e-12 * scale     # minus the removed force
    assert scale > 0.1                                     # the shaking reaches the anchors
    assert np.abs(h[1:, 4:7] - r[1:, 4:7]).max() < 1e-12 * scale   # fix ave/time's window means
    # the mean is not the step's value: the shaking changes the reaction within a window
    assert np.abs(h[1:, 4:7] - h[1:, 1:4]).max() > 1e-3 * scale


def test_anchors_carry_the_weight_half_each_at_rest(tmp_path):
    rope_data(tmp_path / "rope.data")
    print_each = ('fix out all print 10000 "E $(step) $(f_h[4]) $(f_h[5]) $(f_h[6]) '
                  '$(f_h[1][1]) $(f_h[1][5]) $(f_h[1][6]) $(f_h[1][7]) '
                  '$(f_h[2][1]) $(f_h[2][5]) $(f_h[2][6]) $(f_h[2][7])" screen yes')
    out = lmp.run_deck(deck(["fix h ends wirenet/hold 0 0 0 mean 10000 each", print_each],
                            steps=400000, shake=False, calm=True), tmp_path)
    e = numbers(out, "E")[-1]
    weight = (N + 1) * RHO * math.pi * D ** 3 / 6 * G
    total = e[1:4]
    left, right = e[4:8], e[8:12]
    assert left[0] == 1 and right[0] == N + 1             # rows in ascending atom ID
    assert abs(total[2] - weight) < 1e-6 * weight          # the weight, carried by the supports
    assert abs(left[3] - weight / 2) < 1e-4 * weight       # half each
    assert abs(right[3] - weight / 2) < 1e-4 * weight
    assert left[1] < -0.1 * weight and abs(left[1] + right[1]) < 1e-4 * weight   # inward pull, balanced
    assert np.allclose(left[1:] + right[1:], total, rtol=0, atol=1e-9 * weight)  # rows sum to the total


def test_same_means_on_two_ranks_and_between_window_ends(tmp_path):
    rope_data(tmp_path / "rope.data")
    support = [f"fix h ends wirenet/hold 0 0 0 mean {WINDOW} each",
               # asked 7 steps after each window end: still that window's mean
               f'fix out all print {WINDOW} "H $(step) $(f_h[4]) $(f_h[6]) $(f_h[2][7])" screen yes',
               'fix late all print 1 "L $(step) $(f_h[4]) $(f_h[6]) $(f_h[2][7])" screen yes']
    one = lmp.run_deck(deck(support, steps=500), tmp_path)
    two = lmp.run_deck(deck(support, steps=500), tmp_path, np=2, name="in.two")
    assert "2 by 1 by 1 MPI processor grid" in two     # the rope crosses the ranks' boundary
    h1, h2 = numbers(one, "H"), numbers(two, "H")
    assert h1.shape == h2.shape
    assert np.allclose(h1, h2, rtol=1e-10, atol=1e-9)
    late = numbers(one, "L")
    at_end = {int(r[0]): r[1:] for r in h1}
    checked = 0
    for r in late:
        step = int(r[0])
        if step % WINDOW == 7 and step - 7 in at_end:
            assert np.array_equal(r[1:], at_end[step - 7])
            checked += 1
    assert checked >= 8


def test_held_atoms_that_change_rank_stay_held(tmp_path):
    """The rope, held in z only at its ends, slides 1.5 m along x across the 2-rank split (x = 0):
    every atom changes rank and local index. The held atoms are listed anew after each exchange;
    by Galilean invariance the reactions are those of the rope that does not slide."""
    rope_data(tmp_path / "rope.data", box_x=(-3, 3))
    support = ["fix h ends wirenet/hold NULL NULL 0", "fix integ_ends ends nve/sphere",
               f'fix out all print {WINDOW} "H $(step) $(f_h[1]) $(f_h[2]) $(f_h[3]) $(x[1]) $(z[1]) $(z[{N + 1}])" screen yes']
    speed = -1.5 / (STEPS * DT)
    rest = lmp.run_deck(deck(support), tmp_path, np=2, name="in.rest")
    slide = lmp.run_deck(deck(support + [f"velocity all set {speed!r} 0 0"]), tmp_path, np=2, name="in.slide")
    r, s = numbers(rest, "H"), numbers(slide, "H")
    assert r.shape == s.shape and s[0, 4] > -0.05 and s[-1, 4] < -1.4   # anchor 1 (at x = 0) crossed
    weight = (N + 1) * RHO * math.pi * D ** 3 / 6 * G
    assert abs(r[-1, 3]) > 0.1 * weight                        # the ends carry load in z
    assert np.abs(s[:, 1:4] - r[:, 1:4]).max() < 1e-6 * weight  # the same reactions
    assert np.abs(s[:, 5:] - r[:, 5:]).max() < 1e-9              # the ends stay at their heights
    assert np.abs(r[:, 5:] - r[0, 5:]).max() == 0.0 and abs(r[0, 5]) < 1e-12


BAD = [
    ("wirenet/hold 0 0", "expected 'fix ID GROUP wirenet/hold X Y Z"),
    ("wirenet/hold 0 5 0", "component y must be 0 (held) or NULL (free), got '5'"),
    ("wirenet/hold NULL NULL NULL", "holds nothing"),
    ("wirenet/hold 0 0 0 mean 0", "mean must be >= 1 (got 0)"),
    ("wirenet/hold 0 0 0 mean 2.5", "'mean' must be a whole number of steps, 1 to 1e9 (got '2.5')"),
    ("wirenet/hold 0 0 0 mean 2e9", "'mean' must be a whole number of steps, 1 to 1e9 (got '2e9')"),
    ("wirenet/hold 0 0 0 mean inf", "mean must be a finite number (got 'inf')"),
    ("wirenet/hold 0 0 0 mean", "'mean' needs a value"),
    ("wirenet/hold 0 0 0 every 5", "unknown keyword 'every'"),
]


@pytest.mark.parametrize("args,message", BAD)
def test_bad_arguments_give_one_error_line(tmp_path, args, message):
    rope_data(tmp_path / "rope.data")
    error = lmp.one_error(deck([f"fix h ends {args}"], steps=10), tmp_path)
    assert message in error and "fix wirenet/hold" in error, error


def test_a_run_continued_counts_no_step_twice(tmp_path):
    """The setup of a run that continues at the last run's step recomputes that step's forces:
    the windows must not count it again (run 1010 + run 990 = run 2000)."""
    rope_data(tmp_path / "rope.data")
    support = [f"fix h ends wirenet/hold 0 0 0 mean {WINDOW} each",
               f'fix out all print {WINDOW} "H $(step) $(f_h[4]) $(f_h[6]) $(f_h[2][5]) $(f_h[2][7])" screen yes']
    whole = numbers(lmp.run_deck(deck(support), tmp_path), "H")
    split = numbers(lmp.run_deck(deck(support, steps=1010).replace("run 1010\n", "run 1010\nrun 990\n"),
                                 tmp_path, name="in.split"), "H")
    assert len(whole) == STEPS // WINDOW and np.array_equal(whole, split)
