"""Beam strength (`bond_coeff T beam ... strength SIGMA_T TAU_C`): the parallel-bond rupture
criterion of Potyondy & Cundall (2004), issue #17.

A beam bond breaks when its largest tensile fibre stress F_n/A + |M_b| R/I reaches SIGMA_T or its
largest shear stress |F_s|/A + |M_t| R/J reaches TAU_C, with A, I, J = 2 I and R = D/2 of the
geometric section of diameter D. Two nodes 0.1 m apart: node 1 is clamped (neither integrated nor
rotated), node 2 is driven quasi-statically by `fix move` (a prescribed velocity or rotation), so
the bond's load at every step is known exactly. The load read at the step before the rupture
must lie within 0.1 % below the analytic limit.
"""

import math

import pytest

import lmp

D, E, NU = 0.01, 6e10, 0.3
G = E / (2 * (1 + NU))
A = math.pi * D**2 / 4
I = math.pi * D**4 / 64
J = 2 * I
R = D / 2
L0 = 0.1
SIGMA_T = 8.0e8
TAU_C = SIGMA_T / math.sqrt(3)
DT = 1e-5


def write_pair(path):
    # x = -0.05 and 0.05: two ranks split along x put the two nodes on different ranks
    atoms = [(1, 1, -0.05, 0.0, 0.0, D, 7850.0, 1), (2, 1, 0.05, 0.0, 0.0, D, 7850.0, 1)]
    lmp.write_data(path, atoms, [(1, 1, 1, 2)])


COEFF = f"bond_coeff 1 beam diameter {D} E {E} nu {NU} strength {SIGMA_T!r} {TAU_C!r} family rope"

# node 2 driven: (fix move arguments, thermo variable of the load on node 2, analytic limit of it)
# tension: F = EA u/L0 breaks at SIGMA_T A;
# bending: node 2 turns about y on its own centre, the end moment there (Kb + Cs) theta is the
#          largest one; breaks at |M| = SIGMA_T I / R (the shear stress stays far below TAU_C);
# twist:   node 2 turns about the bond axis; breaks at |M_t| = TAU_C J / R.
V_PULL = 0.01                                  # m/s: 1e-7 m per step, the break after ~13000 steps
W_BEND = SIGMA_T * L0 / (4 * E * R) / (1.2e4 * DT)  # rad/s: the break after ~12000 steps
W_TWIST = TAU_C * L0 / (G * R) / (1.2e4 * DT)
MODES = {
    "tension": (f"linear {V_PULL!r} 0 0", "fx[2]", SIGMA_T * A),
    "bending": (f"rotate 0.05 0 0 0 1 0 {2 * math.pi / W_BEND!r}", "tqy[2]", SIGMA_T * I / R),
    "twist": (f"rotate 0.05 0 0 1 0 0 {2 * math.pi / W_TWIST!r}", "tqx[2]", TAU_C * J / R),
}


def pair_setup(mode, processors=""):
    move = MODES[mode][0]
    return "\n".join([processors, lmp.PREAMBLE, "read_data pair.data", "bond_style wirenet", COEFF,
                      "group two id 2", f"fix drive two move {move}", f"timestep {DT!r}", ""])


def outputs(mode):
    var = MODES[mode][1]
    return "\n".join([f"variable load equal {var}", "variable nb equal f_wirenet_bonds",
                      "thermo_style custom step v_load v_nb", "thermo_modify format float %.17g",
                      "thermo 1", ""])


def break_step(rows):
    """(step of the rupture, load on node 2 at the step before)."""
    k = next(k for k, r in enumerate(rows) if r["nb"] > 0)
    return int(rows[k]["Step"]), rows[k - 1]["load"], rows[k]["load"]


def run_mode(tmp_path, mode, np_=1, processors=""):
    tmp_path.mkdir(parents=True, exist_ok=True)
    write_pair(tmp_path / "pair.data")
    out = lmp.run_deck(pair_setup(mode, processors) + outputs(mode) + "run 16000\n", tmp_path, np=np_)
    return out, lmp.thermo_rows(out)


@pytest.mark.parametrize("mode", sorted(MODES))
def test_breaks_at_the_analytic_limit(tmp_path, mode):
    out, rows = run_mode(tmp_path, mode)
    step, before, at = break_step(rows)
    limit = MODES[mode][2]
    # below the limit one step before, within 0.1 %; no force once broken
    assert 0.0 <= (limit - abs(before)) / limit < 1e-3, (mode, before, limit)
    assert at == 0.0
    assert rows[-1]["nb"] == 1 and rows[-1]["load"] == 0.0
    # quasi-static: the load grows by well under 0.1 % per step
    assert step > 5000


def test_tension_break_elongation(tmp_path):
    """The rupture record: the elongation at the breaking step is the first one whose axial force
    E A u / L0 reaches SIGMA_T A (the bond is pulled at V_PULL from its initial length)."""
    write_pair(tmp_path / "pair.data")
    deck = pair_setup("tension") + "run 0\ncompute u all reduce max f_wirenet_bonds[8]\nvariable u equal c_u\n" \
        "variable nb equal f_wirenet_bonds\nthermo_style custom step v_nb v_u\nthermo_modify format float %.17g\n" \
        "thermo 16000\nrun 16000\n"
    rows = lmp.thermo_rows(lmp.run_deck(deck, tmp_path))
    u = rows[-1]["u"]
    force = E * A / L0 * u
    assert 1.0 <= force / (SIGMA_T * A) < 1.0 + 1e-3
    assert rows[-1]["nb"] == 1


def test_no_strength_never_breaks(tmp_path):
    write_pair(tmp_path / "pair.data")
    deck = pair_setup("tension").replace(f" strength {SIGMA_T!r} {TAU_C!r}", "") + outputs("tension") + "run 16000\n"
    assert "strength" not in deck
    rows = lmp.thermo_rows(lmp.run_deck(deck, tmp_path))
    assert rows[-1]["nb"] == 0 and abs(rows[-1]["load"]) > 1.1 * SIGMA_T * A


@pytest.mark.parametrize("mode", ["tension", "bending"])
def test_two_ranks_break_at_the_same_step(tmp_path, mode):
    _, one = run_mode(tmp_path / "np1", mode, 1, "processors * 1 1")
    out, two = run_mode(tmp_path / "np2", mode, 2, "processors * 1 1")
    assert "2 by 1 by 1 MPI processor grid" in out
    s1, b1, _ = break_step(one)
    s2, b2, _ = break_step(two)
    assert s1 == s2
    assert b1 == b2


def test_restart_before_rupture_breaks_at_the_same_step(tmp_path):
    _, straight = run_mode(tmp_path / "straight", "tension")
    step, before, _ = break_step(straight)
    wd = tmp_path / "split"
    wd.mkdir()
    write_pair(wd / "pair.data")
    lmp.run_deck(pair_setup("tension") + "run 6000\nwrite_restart half.restart\n", wd)
    resume = "\n".join(["units si", "atom_modify map array sort 0 0", "read_restart half.restart",
                        "atom_modify sort 0 0", f"timestep {DT!r}", "group two id 2",
                        f"fix drive two move {MODES['tension'][0]}", ""])
    rows = lmp.thermo_rows(lmp.run_deck(resume + outputs("tension") + "run 10000\n", wd, name="in.resume"))
    s, b, _ = break_step(rows)
    assert s == step and b == before


SCALE = 2.5   # not a power of two: the strengths' products are rounded


@pytest.mark.parametrize("mode", sorted(MODES))
def test_at_a_scale_the_strength_is_s_times(tmp_path, mode):
    """fix_modify wirenet_bonds scale S: the beam law is linear, its magnification S F(u / S) is the
    law itself with S times the strengths; driven as before, the bond breaks at S times the limit."""
    write_pair(tmp_path / "pair.data")
    deck = pair_setup(mode) + "run 0\n" + f"fix_modify wirenet_bonds scale {SCALE!r}\n" + outputs(mode) + \
        f"run {int(16000 * SCALE)}\n"
    rows = [r for r in lmp.thermo_rows(lmp.run_deck(deck, tmp_path)) if "nb" in r]   # not run 0's
    _, before, at = break_step(rows)
    limit = SCALE * MODES[mode][2]
    assert 0.0 <= (limit - abs(before)) / limit < 1e-3, (mode, before, limit)
    assert at == 0.0


def test_back_at_scale_one_the_strength_is_the_beams(tmp_path):
    """Loaded at scale S to 1.5 times the strength at scale 1 and intact, then at scale 1: the bond
    breaks at the next force evaluation, the set-up of the run at scale 1 (its load is above its
    own strength), not later."""
    write_pair(tmp_path / "pair.data")
    steps_to_limit = SIGMA_T * L0 / E / (V_PULL * DT)   # F = EA u / L0 = SIGMA_T A
    first = int(1.5 * steps_to_limit)
    deck = pair_setup("tension") + "run 0\n" + f"fix_modify wirenet_bonds scale {SCALE!r}\n" + \
        outputs("tension") + f"run {first}\nfix_modify wirenet_bonds scale 1\nrun 10\n"
    rows = [r for r in lmp.thermo_rows(lmp.run_deck(deck, tmp_path)) if "nb" in r]
    scaled, unscaled = rows[:first + 1], rows[first + 1:]   # run 1: steps 0..first; run 2: first..
    assert scaled[-1]["Step"] == first and unscaled[0]["Step"] == first
    assert scaled[-1]["nb"] == 0 and abs(scaled[-1]["load"]) > 1.4 * SIGMA_T * A
    assert unscaled[0]["nb"] == 1 and unscaled[0]["load"] == 0.0
