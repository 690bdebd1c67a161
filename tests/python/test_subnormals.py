"""The executable flushes subnormal numbers to zero (cmake/patches/0007): a product below 2.2e-308
is 0 on every rank, WIRENET_SUBNORMALS=keep restores IEEE gradual underflow, and any other value
stops the program with one error line before it reads its input.

Why it matters: a wave entering a resting net takes its displacements, velocities and forces through
the subnormal range, where each operation is microcoded and slow (docs/PERFORMANCE.md, twenty-second
session). Without the patch the first test fails."""

import pytest

import lmp

# Two resting spheres, one on each side of x = 0 (so one per rank on 2 ranks), with a velocity whose
# product with 1e-10 is subnormal; the per-atom product's maximum over all ranks goes to thermo.
DECK = lmp.GRANULAR_PREAMBLE + """region box block -1 1 -1 1 -1 1
create_box 1 box
create_atoms 1 single -0.5 0 0
create_atoms 1 single 0.5 0 0
set group all diameter 0.1 density 1000
velocity all set 1e-300 0 0
variable tiny atom vx*1e-10
compute tiny all reduce max v_tiny
thermo_style custom step c_tiny
thermo_modify format float %.6g
run 0
"""


def tiny_value(tmp_path, np):
    out = lmp.run_deck(DECK, tmp_path, np=np)
    return lmp.thermo_rows(out)[-1]["tiny"]


@pytest.mark.parametrize("np", [1, 2])
def test_subnormal_products_are_zero_on_every_rank(tmp_path, np):
    assert tiny_value(tmp_path, np) == 0.0


def test_keep_restores_gradual_underflow(tmp_path, monkeypatch):
    monkeypatch.setenv("WIRENET_SUBNORMALS", "keep")
    assert tiny_value(tmp_path, 2) == pytest.approx(1e-310, rel=1e-6)


@pytest.mark.parametrize("np", [1, 2])
def test_a_bad_mode_stops_before_the_input_with_one_line(tmp_path, monkeypatch, np):
    monkeypatch.setenv("WIRENET_SUBNORMALS", "kep")
    rc, out = lmp.run_deck_rc(DECK, tmp_path, np=np)
    assert rc != 0 and lmp.error_lines(out) == \
        ["ERROR: WIRENET_SUBNORMALS must be keep or flush (got 'kep')"], out[-1500:]
    assert not (tmp_path / "log.lammps").exists()      # it read no input
