"""Input errors of bond_style wirenet end the run cleanly.

Every bad `bond_coeff` and every set-up the style cannot run with must stop LIGGGHTS with exactly
one ERROR line that names the problem, a non-zero exit code, and no crash (no signal, no MPI
abort of a crashed rank). Each case asserts the key phrase of its message.
"""

import re
import signal

import pytest

import lmp

SW = ("0.0019230769 2.5e8 0.0192 3.2195e8 0.05 3.8292e8 0.15 5.1219e8 "
      "0.25 5.5854e8 0.30 5.6585e8 0.35 5.6585e8")
GOOD = f"wire diameter 0.0027 curve {SW}"


def write_pair(path, nbond_types=1):
    atoms = [(1, 1, 0.0, 0.0, 0.0, 0.0108, 7850.0, 1), (2, 1, 0.04, 0.0, 0.0, 0.0108, 7850.0, 1),
             (3, 1, 0.08, 0.0, 0.0, 0.0108, 7850.0, 1)]
    bonds = [(1, 1, 1, 2), (2, nbond_types, 2, 3)]
    lmp.write_data(path, atoms, bonds, nbond_types=nbond_types)


def deck(body, preamble=lmp.PREAMBLE, data="pair.data"):
    return preamble + f"read_data {data}\n" + body + "\n"


def check_error(rc, out, phrase):
    """One ERROR line containing phrase, a clean non-zero exit, no crash."""
    assert rc != 0, f"LIGGGHTS accepted the input:\n{out[-2000:]}"
    assert rc > 0 and rc != 128 + signal.SIGSEGV, f"LIGGGHTS crashed (exit {rc}):\n{out[-2000:]}"
    for bad in ("Segmentation fault", "Signal: ", "core dumped", "MPI_ABORT", "terminate called"):
        assert bad not in out, f"crash marker {bad!r} in the output:\n{out[-2000:]}"
    errors = lmp.error_lines(out)
    assert len(errors) == 1, f"expected one ERROR line, got {len(errors)}:\n" + "\n".join(errors)
    assert phrase in errors[0], f"{phrase!r} not in {errors[0]!r}"
    # complete on its line: "ERROR: message (source.cpp:line)", and no second line from the same
    # source location (LIGGGHTS used to append a random "tip of the day" there)
    m = re.search(r"(\([^()]+\.(cpp|h):\d+\))$", errors[0])
    assert m, f"ERROR line does not end with its source location: {errors[0]!r}"
    assert out.count(m.group(1)) == 1, f"more than one line from {m.group(1)}:\n{out[-2000:]}"
    return errors[0]


# (bond_coeff arguments after the type, key phrase of the message)
BAD_COEFFS = {
    "unsorted strains": ("wire diameter 0.0027 curve 0.01 2e8 0.005 3e8", "strains must increase"),
    "repeated strain": ("wire diameter 0.0027 curve 0.01 2e8 0.01 3e8", "strains must increase"),
    "negative strain": ("wire diameter 0.0027 curve -0.01 2e8 0.02 3e8", "strain must be a finite number > 0 (got -0.01)"),
    "zero first stress": ("wire diameter 0.0027 curve 0.01 0 0.02 3e8", "stress must be > 0"),
    "negative stress": ("wire diameter 0.0027 curve 0.01 2e8 0.02 -3e8", "stress must be a finite number >= 0"),
    "odd number of curve values": ("wire diameter 0.0027 curve 0.01 2e8 0.02",
                                   "odd number of values (3)"),
    "missing curve keyword": ("wire diameter 0.0027", "missing wire 'curve'"),
    "curve replaced by an option": ("wire diameter 0.0027 family SW", "expected 'curve', got 'family'"),
    "curve without values": ("wire diameter 0.0027 curve family SW", "wire curve is missing"),
    "zero diameter": (f"wire diameter 0 curve {SW}", "wire diameter must be a finite number > 0 (got 0)"),
    "negative diameter": (f"wire diameter -0.0027 curve {SW}", "wire diameter must be a finite number > 0 (got -0.0027)"),
    "missing diameter": (f"wire curve {SW}", "wire: expected 'diameter', got 'curve'"),
    "unknown keyword": (f"{GOOD} stiffness 3", "unknown wire keyword 'stiffness'"),
    "number after the options": (f"{GOOD} family SW 3", "unexpected number '3'"),
    "unknown law": ("rope diameter 0.01", "unknown law 'rope'"),
    "derived without parameters": (f"{GOOD} derived", "missing derived lambda_eps"),
    "derived with a parameter missing": (f"{GOOD} derived lambda_eps 0.4 nu 0.3",
                                         "derived: expected 'lambda_k', got 'nu'"),
    "derived lambda_k out of range": (f"{GOOD} derived lambda_eps 0.4 lambda_k 1.5 nu 0.3",
                                      "derived lambda_k must be in [0,1] (got 1.5)"),
    "derived lambda_eps zero": (f"{GOOD} derived lambda_eps 0 lambda_k 0.66 nu 0.3",
                                "derived lambda_eps must be a finite number > 0"),
    "slack lambda_f above 1": (f"{GOOD} slack lambda_u 0.2 lambda_f 1.5 seed 1",
                               "slack lambda_f must be in (0,1] (got 1.5)"),
    "slack lambda_f zero": (f"{GOOD} slack lambda_u 0.2 lambda_f 0 seed 1",
                            "slack lambda_f must be in (0,1] (got 0)"),
    "slack negative lambda_u": (f"{GOOD} slack lambda_u -0.1 lambda_f 1 seed 1",
                                "slack lambda_u must be a finite number >= 0"),
    "slack without seed": (f"{GOOD} slack lambda_u 0.2 lambda_f 1", "missing slack seed"),
    "slack fractional seed": (f"{GOOD} slack lambda_u 0.2 lambda_f 1 seed 1.5",
                              "slack seed must be an integer"),
    "non-numeric diameter": (f"wire diameter abc curve {SW}", "wire diameter must be a number (got 'abc')"),
    "non-numeric stress": ("wire diameter 0.0027 curve 0.01 2e8x 0.02 3e8",
                           "wire curve value 2 must be a number (got '2e8x')"),
    "non-numeric first strain": ("wire diameter 0.0027 curve one 2e8", "wire curve value 1 must be a number (got 'one')"),
    "non-numeric area_factor": (f"{GOOD} area_factor two", "area_factor must be a number (got 'two')"),
    "zero area_factor": (f"{GOOD} area_factor 0", "wire area_factor must be a finite number > 0"),
    "non-numeric lambda_u": (f"{GOOD} slack lambda_u x lambda_f 1 seed 1",
                             "slack lambda_u must be a number (got 'x')"),
    "type only": ("", "expected 'bond_coeff T wire ...'"),
    # non-finite numbers: strtod reads "inf", "nan" and overflows, the style must refuse them
    "wire diameter inf": (f"wire diameter inf curve {SW}", "wire diameter must be a finite number > 0 (got inf)"),
    "wire diameter -inf": (f"wire diameter -inf curve {SW}", "wire diameter must be a finite number > 0 (got -inf)"),
    "wire diameter nan": (f"wire diameter nan curve {SW}", "wire diameter must be a finite number > 0 (got nan)"),
    "wire diameter overflow": (f"wire diameter 1e999 curve {SW}", "wire diameter must be a finite number > 0 (got inf)"),
    "curve stress inf": ("wire diameter 0.0027 curve 0.01 2e8 0.02 inf",
                         "wire curve point 2: stress must be a finite number >= 0 (got inf)"),
    "curve stress Infinity": ("wire diameter 0.0027 curve 0.01 Infinity 0.02 3e8",
                              "wire curve point 1: stress must be a finite number >= 0 (got inf)"),
    "curve strain nan": ("wire diameter 0.0027 curve nan 2e8 0.02 3e8",
                         "wire curve point 1: strain must be a finite number > 0 (got nan)"),
    "curve last strain inf": ("wire diameter 0.0027 curve 0.01 2e8 inf 3e8",
                              "wire curve point 2: strain must be a finite number > 0 (got inf)"),
    "area_factor inf": (f"{GOOD} area_factor inf", "wire area_factor must be a finite number > 0 (got inf)"),
    "area_factor nan": (f"{GOOD} area_factor nan", "wire area_factor must be a finite number > 0 (got nan)"),
    "derived lambda_eps inf": (f"{GOOD} derived lambda_eps inf lambda_k 0.66 nu 0.3",
                               "derived lambda_eps must be a finite number > 0 (got inf)"),
    "derived lambda_k nan": (f"{GOOD} derived lambda_eps 0.4 lambda_k nan nu 0.3",
                             "derived lambda_k must be in [0,1] (got nan)"),
    "derived nu inf": (f"{GOOD} derived lambda_eps 0.4 lambda_k 0.66 nu inf", "derived nu must be in (-1,0.5) (got inf)"),
    "derived nu 0.5": (f"{GOOD} derived lambda_eps 0.4 lambda_k 0.66 nu 0.5", "derived nu must be in (-1,0.5) (got 0.5)"),
    "slack lambda_u inf": (f"{GOOD} slack lambda_u inf lambda_f 1 seed 1",
                           "slack lambda_u must be a finite number >= 0 (got inf)"),
    "slack lambda_f nan": (f"{GOOD} slack lambda_u 0.2 lambda_f nan seed 1", "slack lambda_f must be in (0,1] (got nan)"),
    "slack seed inf": (f"{GOOD} slack lambda_u 0.2 lambda_f 1 seed inf", "slack seed must be an integer (got inf)"),
    "slack seed beyond 2^53": (f"{GOOD} slack lambda_u 0.2 lambda_f 1 seed 1e30",
                               "slack seed must be an integer (got 1e+30)"),
    "inf after the options": (f"{GOOD} family SW inf", "unexpected number 'inf'"),
    # beam
    "beam diameter inf": ("beam diameter inf E 6e10 nu 0.3", "beam diameter must be a finite number > 0 (got inf)"),
    "beam diameter -inf": ("beam diameter -inf E 6e10 nu 0.3", "beam diameter must be a finite number > 0 (got -inf)"),
    "beam diameter zero": ("beam diameter 0 E 6e10 nu 0.3", "beam diameter must be a finite number > 0 (got 0)"),
    "beam E inf": ("beam diameter 0.01 E inf nu 0.3", "beam E must be a finite number > 0 (got inf)"),
    "beam E nan": ("beam diameter 0.01 E nan nu 0.3", "beam E must be a finite number > 0 (got nan)"),
    "beam E zero": ("beam diameter 0.01 E 0 nu 0.3", "beam E must be a finite number > 0 (got 0)"),
    "beam nu 0.5": ("beam diameter 0.01 E 6e10 nu 0.5", "beam nu must be in (-1,0.5) (got 0.5)"),
    "beam nu -1": ("beam diameter 0.01 E 6e10 nu -1", "beam nu must be in (-1,0.5) (got -1)"),
    "beam nu nan": ("beam diameter 0.01 E 6e10 nu nan", "beam nu must be in (-1,0.5) (got nan)"),
    "beam nu text": ("beam diameter 0.01 E 6e10 nu x", "beam nu must be a number (got 'x')"),
    "beam bending negative": ("beam diameter 0.01 E 6e10 nu 0.3 bending -0.1",
                              "beam bending fraction must be a finite number >= 0 (got -0.1)"),
    "beam bending inf": ("beam diameter 0.01 E 6e10 nu 0.3 bending inf",
                         "beam bending fraction must be a finite number >= 0 (got inf)"),
    "beam twist -1": ("beam diameter 0.01 E 6e10 nu 0.3 bending 0.05 twist -1",
                      "beam twist fraction must be a finite number >= 0 (got -1)"),
    "beam twist nan": ("beam diameter 0.01 E 6e10 nu 0.3 twist nan",
                       "beam twist fraction must be a finite number >= 0 (got nan)"),
    "beam twist inf": ("beam diameter 0.01 E 6e10 nu 0.3 twist inf",
                       "beam twist fraction must be a finite number >= 0 (got inf)"),
    "beam twist missing": ("beam diameter 0.01 E 6e10 nu 0.3 twist", "missing beam twist fraction"),
    # strength and damping (issue #17)
    "beam strength negative": ("beam diameter 0.01 E 6e10 nu 0.3 strength -1 4e8",
                               "beam strength SIGMA_T must be a finite number > 0 (got -1)"),
    "beam strength inf": ("beam diameter 0.01 E 6e10 nu 0.3 strength inf 4e8",
                          "beam strength SIGMA_T must be a finite number > 0 (got inf)"),
    "beam strength TAU_C nan": ("beam diameter 0.01 E 6e10 nu 0.3 strength 8e8 nan",
                                "beam strength TAU_C must be a finite number > 0 (got nan)"),
    "beam strength TAU_C zero": ("beam diameter 0.01 E 6e10 nu 0.3 strength 8e8 0",
                                 "beam strength TAU_C must be a finite number > 0 (got 0)"),
    "beam strength missing value": ("beam diameter 0.01 E 6e10 nu 0.3 strength 8e8", "missing beam strength TAU_C"),
    "beam strength value replaced by a keyword": ("beam diameter 0.01 E 6e10 nu 0.3 strength 8e8 family rope",
                                                  "beam strength TAU_C must be a number (got 'family')"),
    "beam damping negative": ("beam diameter 0.01 E 6e10 nu 0.3 damping -0.1",
                              "beam damping must be a finite number >= 0 (got -0.1)"),
    "beam damping inf": ("beam diameter 0.01 E 6e10 nu 0.3 damping inf", "beam damping must be a finite number >= 0 (got inf)"),
    "beam damping missing": ("beam diameter 0.01 E 6e10 nu 0.3 damping", "missing beam damping"),
    "wire damping nan": (f"{GOOD} damping nan", "wire damping must be a finite number >= 0 (got nan)"),
    "wire damping negative": (f"{GOOD} family SW damping -0.05", "wire damping must be a finite number >= 0 (got -0.05)"),
    "wire damping missing": (f"{GOOD} damping", "missing wire damping"),
}


@pytest.mark.parametrize("case", sorted(BAD_COEFFS))
def test_bad_bond_coeff(tmp_path, case):
    args, phrase = BAD_COEFFS[case]
    write_pair(tmp_path / "pair.data")
    rc, out = lmp.run_deck_rc(deck(f"bond_style wirenet\nbond_coeff 1 {args}\nrun 0"), tmp_path)
    line = check_error(rc, out, phrase)
    assert "bond_coeff" in line  # names the command


def test_bad_bond_coeff_on_two_ranks(tmp_path):
    """The same clean stop when every rank parses the bad line."""
    write_pair(tmp_path / "pair.data")
    rc, out = lmp.run_deck_rc(deck("bond_style wirenet\nbond_coeff 1 wire diameter 0.0027 curve 0.01 2e8 0.005 3e8"),
                              tmp_path, np=2)
    check_error(rc, out, "strains must increase")


def test_bond_type_out_of_range(tmp_path):
    write_pair(tmp_path / "pair.data")
    rc, out = lmp.run_deck_rc(deck(f"bond_style wirenet\nbond_coeff 2 {GOOD}"), tmp_path)
    check_error(rc, out, "out of bounds")


def test_bond_style_arguments(tmp_path):
    write_pair(tmp_path / "pair.data")
    rc, out = lmp.run_deck_rc(deck("bond_style wirenet wire"), tmp_path)
    check_error(rc, out, "bond_style wirenet takes no arguments")


# ---- checks at the start of a run -------------------------------------------------------------

def test_bond_type_without_coeff(tmp_path):
    write_pair(tmp_path / "pair.data", nbond_types=2)
    rc, out = lmp.run_deck_rc(deck(f"bond_style wirenet\nbond_coeff 1 {GOOD}\nrun 0"), tmp_path)
    check_error(rc, out, "bond type 2 has no bond_coeff")


def test_no_bond_coeff_at_all(tmp_path):
    write_pair(tmp_path / "pair.data")
    rc, out = lmp.run_deck_rc(deck("bond_style wirenet\nrun 0"), tmp_path)
    check_error(rc, out, "no bond_coeff given")


def test_newton_bond_off(tmp_path):
    write_pair(tmp_path / "pair.data")
    pre = lmp.PREAMBLE.replace("newton off on", "newton on off")
    assert pre != lmp.PREAMBLE
    rc, out = lmp.run_deck_rc(deck(f"bond_style wirenet\nbond_coeff 1 {GOOD}\nrun 0", preamble=pre), tmp_path)
    check_error(rc, out, "needs newton_bond on")


def test_atom_style_without_radius(tmp_path):
    # atom_style molecular: bonds but point atoms (this build has no atom_style bond)
    (tmp_path / "bond.data").write_text(
        "LIGGGHTS data file, atom_style molecular\n\n3 atoms\n2 bonds\n1 atom types\n1 bond types\n\n"
        "-1 1 xlo xhi\n-1 1 ylo yhi\n-1 1 zlo zhi\n\nMasses\n\n1 0.0039\n\nAtoms\n\n"
        "1 1 1 0 0 0\n2 1 1 0.04 0 0\n3 1 1 0.08 0 0\n\nBonds\n\n1 1 1 2\n2 1 2 3\n")
    pre = lmp.PREAMBLE.replace("atom_style hybrid granular molecular", "atom_style molecular")
    rc, out = lmp.run_deck_rc(deck(f"bond_style wirenet\nbond_coeff 1 {GOOD}\nrun 0", preamble=pre,
                                   data="bond.data"), tmp_path)
    check_error(rc, out, "needs spheres with bonds")


def test_compute_needs_wirenet(tmp_path):
    write_pair(tmp_path / "pair.data")
    rc, out = lmp.run_deck_rc(deck("bond_style harmonic\nbond_coeff 1 100 0.04\n"
                                   "compute bl all wirenet/local\nrun 0"), tmp_path)
    check_error(rc, out, "compute wirenet/local needs bond_style wirenet")


def test_compute_takes_no_arguments(tmp_path):
    write_pair(tmp_path / "pair.data")
    rc, out = lmp.run_deck_rc(deck(f"bond_style wirenet\nbond_coeff 1 {GOOD}\n"
                                   "compute bl all wirenet/local 5"), tmp_path)
    check_error(rc, out, "compute wirenet/local takes no arguments")


def test_history_fix_id_taken(tmp_path):
    write_pair(tmp_path / "pair.data")
    rc, out = lmp.run_deck_rc(deck(f"bond_style wirenet\nbond_coeff 1 {GOOD}\n"
                                   "fix wirenet_bonds all nve/sphere\nrun 0"), tmp_path)
    check_error(rc, out, "fix ID wirenet_bonds is taken")


# ---- errors found by one rank only (LIGGGHTS' Error::one, which ends in MPI_Abort) ------------

@pytest.mark.parametrize("np_", [1, 2])
def test_zero_length_bond_is_reported(tmp_path, np_):
    """The message of a one-rank error must survive the abort, also when the screen output goes to
    a pipe (as here), and reach the log file when rank 0 found it (only rank 0 writes the log;
    on two ranks both nodes, at x = 0, belong to rank 1)."""
    atoms = [(1, 1, 0.0, 0.0, 0.0, 0.0108, 7850.0, 1), (2, 1, 0.0, 0.0, 0.0, 0.0108, 7850.0, 1)]
    lmp.write_data(tmp_path / "zero.data", atoms, [(1, 1, 1, 2)])
    rc, out = lmp.run_deck_rc(deck(f"bond_style wirenet\nbond_coeff 1 {GOOD}\nrun 0", data="zero.data"),
                              tmp_path, np=np_)
    assert rc != 0 and rc != -signal.SIGSEGV and "Segmentation fault" not in out
    phrase = "bond_style wirenet: bond 1-2 has zero length"
    errors = lmp.error_lines(out)  # OpenMPI may add abort chatter (ORTE_ERROR_LOG ...)
    assert len(errors) == 1 and phrase in errors[0], out[-2000:]
    if np_ == 1:
        assert phrase in (tmp_path / "log.lammps").read_text()


@pytest.mark.parametrize("order", [(1, 2), (2, 1)], ids=["same order", "reversed"])
def test_bond_listed_twice(tmp_path, order):
    """A bond given twice in the data file. With the default special_bonds LIGGGHTS' read_data
    stops first ('1-3 bond count is inconsistent', not ours); with special_bonds lj/coul 0 1 1
    read_data accepts it and the style names the two atoms at the first run."""
    atoms = [(1, 1, 0.0, 0.0, 0.0, 0.0108, 7850.0, 1), (2, 1, 0.04, 0.0, 0.0, 0.0108, 7850.0, 1),
             (3, 1, 0.08, 0.0, 0.0, 0.0108, 7850.0, 1)]
    lmp.write_data(tmp_path / "dup.data", atoms, [(1, 1, 1, 2), (2, 1, order[0], order[1]), (3, 1, 2, 3)])
    pre = lmp.PREAMBLE + "special_bonds lj/coul 0 1 1\n"
    rc, out = lmp.run_deck_rc(deck(f"bond_style wirenet\nbond_coeff 1 {GOOD}\nrun 0", preamble=pre, data="dup.data"),
                              tmp_path, np=1)
    check_error(rc, out, "the bond between atoms 1 and 2 is listed twice")


def test_elastic_energy_per_type_needs_energy_step(tmp_path):
    """The per-type elastic energy exists only where LIGGGHTS computed bond energies: read at a
    thermo step of a thermo without a pe compute, it is an error that says what to add."""
    write_pair(tmp_path / "pair.data")
    rc, out = lmp.run_deck_rc(deck(f"bond_style wirenet\nbond_coeff 1 {GOOD}\nrun 0\n"
                                   "variable el equal f_wirenet_bonds[1][1]\n"
                                   "thermo_style custom step v_el\nthermo 5\nrun 10"), tmp_path)
    check_error(rc, out, "output a compute pe bond at the same steps")


def test_energy_per_type_out_of_range(tmp_path):
    write_pair(tmp_path / "pair.data")
    rc, out = lmp.run_deck_rc(deck(f"bond_style wirenet\nbond_coeff 1 {GOOD}\nrun 0\n"
                                   "variable pl equal f_wirenet_bonds[2][3]\n"
                                   "thermo_style custom step v_pl\nrun 0"), tmp_path)
    check_error(rc, out, "out-of-range")
