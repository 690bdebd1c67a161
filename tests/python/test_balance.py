"""fix wirenet/balance: the processor grid's cuts moved to the quantiles of the atoms. A shaken
rope of 9 nodes, held at both ends, lies in the first sixth of a 13 m box (x from -1 to 12), so
the uniform cuts of `processors * 1 1` leave most ranks empty. Checks:
- on 2, 3 and 4 ranks the busiest rank's share of the atoms falls from its uniform value
  (9/9, 9/9 and 9/9 of them on one rank: 2, 3 and 4 times the mean) to the quantiles' (5 of 9 on
  2 ranks: 1.11; 3 of 9 on 3: 1.0; 3 of 9 on 4: 1.33), read from the fix's vector and its line;
- the atoms move several ranks away (to ranks whose slab was empty) and the slabs are thinner
  than the ghost cut-off (ghosts from two ranks away): the trajectory equals the 1-rank run's
  to 1e-12, and the held ends still carry the rope;
- bad arguments: one ERROR line naming the item.
"""

import re

import numpy as np
import pytest

import lmp
from test_hold import N, deck, numbers, rope_data

BOX_X = (-1, 12)
PRINT_MID = (f'fix out all print 100 "P $(step) $(x[{N // 2 + 1}]) $(z[{N // 2 + 1}]) '
             f'$(vz[{N // 2 + 1}]) $(f_h[3]) $(f_bal[1]) $(f_bal[2])" screen yes')


def shaken(tmp_path, np_, balance="fix bal all wirenet/balance x"):
    rope_data(tmp_path / "rope.data", box_x=BOX_X)
    text = deck(["fix h ends wirenet/hold 0 0 0", balance, PRINT_MID], steps=2000)
    text = text.replace("read_data rope.data", "processors * 1 1\nread_data rope.data")
    out = lmp.run_deck(text, tmp_path, np=np_, name=f"in.balance{np_}")
    return out, numbers(out, "P")


@pytest.fixture(scope="module")
def one_rank(tmp_path_factory):
    return shaken(tmp_path_factory.mktemp("balance_np1"), 1)


@pytest.mark.parametrize("np_, after", [(2, 5 / 4.5), (3, 1.0), (4, 3 / 2.25)])
def test_the_cuts_follow_the_atoms_and_the_run_is_unchanged(one_rank, tmp_path, np_, after):
    out1, ref = one_rank
    out, rows = shaken(tmp_path, np_)
    assert f"{np_} by 1 by 1 MPI processor grid" in out
    line = re.search(r"fix wirenet/balance: atoms per rank, largest over mean: (\S+) before, "
                     r"(\S+) after", out)
    assert line, out[-2000:]
    assert float(line.group(1)) == pytest.approx(np_, abs=1e-3)       # all on one rank
    assert float(line.group(2)) == pytest.approx(after, abs=1e-3)
    assert rows[-1, 5] == pytest.approx(np_) and rows[-1, 6] == pytest.approx(after)
    assert "fix wirenet/balance" not in out1                          # 1 rank: nothing to do
    assert np.array_equal(ref[:, 5:], np.ones_like(ref[:, 5:]))
    assert rows.shape == ref.shape and len(rows) > 10
    assert np.allclose(rows[:, :5], ref[:, :5], rtol=1e-12, atol=1e-15)
    assert np.abs(ref[:, 4]).max() > 0.1                               # the ends carry the rope


BAD = [
    ("wirenet/balance", "expected 'fix ID GROUP wirenet/balance DIMS'"),
    ("wirenet/balance x y", "expected 'fix ID GROUP wirenet/balance DIMS'"),
    ("wirenet/balance q", "DIMS 'q': 'q' is not x, y or z"),
    ("wirenet/balance xzx", "DIMS 'xzx' names x twice"),
]


@pytest.mark.parametrize("args,message", BAD)
def test_bad_arguments_give_one_error_line(tmp_path, args, message):
    rope_data(tmp_path / "rope.data")
    error = lmp.one_error(deck([f"fix bal all {args}"], steps=10, shake=False), tmp_path)
    assert message in error and "fix wirenet/balance" in error, error


def test_a_periodic_dimension_is_refused(tmp_path):
    rope_data(tmp_path / "rope.data", box_x=BOX_X)
    text = deck(["fix bal all wirenet/balance xy"], steps=10, shake=False)
    text = text.replace("boundary f f f", "boundary f p f")
    error = lmp.one_error(text, tmp_path)
    assert "fix wirenet/balance: dimension y is periodic" in error, error


def test_a_triclinic_box_is_refused(tmp_path):
    rope_data(tmp_path / "rope.data", box_x=BOX_X)
    text = deck(["change_box all triclinic", "fix bal all wirenet/balance x"], steps=10,
                shake=False)
    error = lmp.one_error(text, tmp_path)
    assert "fix wirenet/balance: needs an orthogonal box" in error, error
