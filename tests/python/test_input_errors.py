"""Bad input to read_data and to the WireNet fixes ends the run with one clear ERROR line.

Issue #14. Every case must stop LIGGGHTS with exactly one ERROR line that names the offending
item and its value, a non-zero exit code, and no crash (no signal, no MPI_ABORT, no traceback):
check_error of test_wire_errors. Data files: an atom outside the box or with a non-finite
coordinate, non-finite or invalid per-atom values, repeated atom IDs and bonds (either order),
bonds to missing atoms; LIGGGHTS' own messages for these ("Did not assign all atoms correctly",
"1-3 bond count is inconsistent", an MPI_Abort of one rank) did not say which. The read_data
checks are cmake/patches/0005-read-data-checks.patch. Fix arguments: non-finite and out-of-range
numbers of fix wirenet/damping, wirenet/rigidmesh and wirenet/contactwork; fix_modify of fix
wirenet/bonds.
"""

import pytest

import lmp
from test_rigid_block import base_deck
from test_wire_errors import check_error

NAN, INF = float("nan"), float("inf")

# A row of four nodes, three bonds: (id, type, x, y, z, diameter, density, molecule)
ATOMS = [(1, 1, -0.6, 0.0, 0.0, 0.0108, 7850.0, 1), (2, 1, -0.2, 0.0, 0.0, 0.0108, 7850.0, 1),
         (3, 1, 0.2, 0.0, 0.0, 0.0108, 7850.0, 1), (4, 1, 0.6, 0.0, 0.0, 0.0108, 7850.0, 1)]
BONDS = [(1, 1, 1, 2), (2, 1, 2, 3), (3, 1, 3, 4)]


def with_atom(k, **changes):
    """ATOMS with atom k (1-based) changed: id, type, x, y, z, d, rho, mol."""
    keys = ("id", "type", "x", "y", "z", "d", "rho", "mol")
    atoms = [list(a) for a in ATOMS]
    for key, value in changes.items():
        atoms[k - 1][keys.index(key)] = value
    return [tuple(a) for a in atoms]


def run_data(tmp_path, atoms=ATOMS, bonds=BONDS, np=1, preamble=lmp.PREAMBLE, text=None):
    if text is None:
        lmp.write_data(tmp_path / "net.data", atoms, bonds)
    else:
        (tmp_path / "net.data").write_text(text)
    return lmp.run_deck_rc(preamble + "read_data net.data\n", tmp_path, np=np, timeout=120)


def check_row_error(tmp_path, commands, phrase):
    """The row of four nodes read, then the deck's commands: one clear error naming phrase."""
    lmp.write_data(tmp_path / "net.data", ATOMS, BONDS)
    rc, out = lmp.run_deck_rc(lmp.PREAMBLE + "read_data net.data\n" + commands, tmp_path, timeout=120)
    check_error(rc, out, phrase)


def data_text(box_x="-1 1", atoms_lines=None, bonds_lines=None):
    atoms_lines = atoms_lines or [" ".join(repr(v) for v in a) for a in ATOMS]
    bonds_lines = bonds_lines or [" ".join(str(v) for v in b) for b in BONDS]
    return "\n".join(["hand-written data file", "", f"{len(atoms_lines)} atoms",
                      f"{len(bonds_lines)} bonds", "1 atom types", "1 bond types", "",
                      f"{box_x} xlo xhi", "-1 1 ylo yhi", "-1 1 zlo zhi", "", "Atoms", "",
                      *atoms_lines, "", "Bonds", "", *bonds_lines]) + "\n"


# (atoms, bonds, key phrase of the message)
BAD_DATA = {
    "atom outside the box": (with_atom(3, x=1.5), BONDS,
                             "read_data: atom 3 at (1.5, 0.0, 0.0) is outside the box or not finite"),
    "atom below the box": (with_atom(1, z=-1.01), BONDS, "atom 1 at (-0.6, 0.0, -1.01) is outside the box"),
    "atom on the upper box bound": (with_atom(4, x=1.0), BONDS,
                                    "atom 4 at (1.0, 0.0, 0.0) is outside the box or not finite (box x [-1, 1)"),
    "nan coordinate": (with_atom(2, y=NAN), BONDS,
                       "read_data: atom 2 at (-0.2, nan, 0.0) is outside the box or not finite"),
    "inf coordinate": (with_atom(2, z=INF), BONDS, "atom 2 at (-0.2, 0.0, inf) is outside the box or not finite"),
    "-inf coordinate": (with_atom(1, x=-INF), BONDS, "atom 1 at (-inf, 0.0, 0.0) is outside the box"),
    "inf diameter": (with_atom(2, d=INF), BONDS, "read_data: atom 2: diameter is not finite (got inf)"),
    "nan diameter": (with_atom(3, d=NAN), BONDS, "read_data: atom 3: diameter is not finite (got nan)"),
    "nan density": (with_atom(2, rho=NAN), BONDS, "read_data: atom 2: density is not finite (got nan)"),
    "inf density": (with_atom(4, rho=INF), BONDS, "read_data: atom 4: density is not finite (got inf)"),
    "negative diameter": (with_atom(2, d=-0.01), BONDS, "read_data: atom 2: diameter must be >= 0 (got -0.01)"),
    "zero density": (with_atom(2, rho=0.0), BONDS, "read_data: atom 2: density must be > 0 (got 0.0)"),
    "atom type out of range": (with_atom(2, type=3), BONDS,
                               "read_data: atom 2 has atom type 3, outside 1..1 (the header declares 1 atom types)"),
    "atom ID listed twice": (with_atom(3, id=2), [(1, 1, 1, 2), (2, 1, 2, 4)],
                             "read_data: atom ID 2 is listed twice in the Atoms section (its lines 2 and 3)"),
    "bond listed twice": (ATOMS, BONDS + [(4, 1, 2, 3)],
                          "read_data: the bond between atoms 2 and 3 is listed twice (bonds 2 and 4)"),
    "bond listed twice in reverse order": (ATOMS, BONDS + [(4, 1, 3, 2)],
                                           "read_data: the bond between atoms 2 and 3 is listed twice (bonds 2 and 4)"),
    "bond to an atom ID beyond the largest": (ATOMS, [(1, 1, 1, 2), (2, 1, 2, 9)],
                                              "read_data: bond 2 names atom 9, which is not in the Atoms section"),
    "bond to a missing atom ID": (with_atom(3, id=5), [(1, 1, 1, 2), (2, 1, 2, 3)],
                                  "read_data: bond 2 names atom 3, which is not in the Atoms section"),
    "bond to atom 0": (ATOMS, [(1, 1, 0, 2)], "read_data: bond 1 names atom 0, which is not in the Atoms section"),
    "bond of an atom to itself": (ATOMS, [(1, 1, 1, 2), (2, 1, 3, 3)], "read_data: bond 2 joins atom 3 to itself"),
    "bond type out of range": (ATOMS, [(1, 1, 1, 2), (2, 5, 2, 3)],
                               "read_data: bond 2 has bond type 5, outside 1..1"),
}


@pytest.mark.parametrize("case", sorted(BAD_DATA))
def test_bad_data_file(tmp_path, case):
    atoms, bonds, phrase = BAD_DATA[case]
    rc, out = run_data(tmp_path, atoms, bonds)
    check_error(rc, out, phrase)


# Hand-written files: (text, key phrase)
atom_lines = [" ".join(repr(v) for v in a) for a in ATOMS]
BAD_TEXT = {
    "nan box bound": (data_text(box_x="nan 1"),
                      "read_data: box bounds xlo xhi must be finite with xlo < xhi (got nan 1)"),
    "inf box bound": (data_text(box_x="-1 inf"),
                      "read_data: box bounds xlo xhi must be finite with xlo < xhi (got -1 inf)"),
    "inverted box": (data_text(box_x="1 -1"), "read_data: box bounds xlo xhi must be finite with xlo < xhi (got 1 -1)"),
    "non-numeric coordinate": (data_text(atoms_lines=atom_lines[:1] + ["2 1 -0.2 abc 0 0.0108 7850 1"] + atom_lines[2:]),
                               "read_data: atom 2: y 'abc' is not a number"),
    "atom line too short": (data_text(atoms_lines=atom_lines[:2] + ["3 1 0.2 0 0 0.0108 7850"] + atom_lines[3:]),
                            "read_data: line 3 of the Atoms section has 7 values, expected 8"),
    "non-integer atom ID": (data_text(atoms_lines=atom_lines[:1] + ["2.5 1 -0.2 0 0 0.0108 7850 1"] + atom_lines[2:]),
                            "read_data: line 2 of the Atoms section: atom ID '2.5' is not an integer >= 1"),
    "atom ID 0": (data_text(atoms_lines=atom_lines[:1] + ["0 1 -0.2 0 0 0.0108 7850 1"] + atom_lines[2:]),
                  "read_data: line 2 of the Atoms section: atom ID '0' is not an integer >= 1"),
    "bond line too short": (data_text(bonds_lines=["1 1 1 2", "2 1 2", "3 1 3 4"]),
                            "read_data: line 2 of the Bonds section has 3 values, expected 4"),
    "non-integer bond atom": (data_text(bonds_lines=["1 1 1 2", "2 1 2 2.5", "3 1 3 4"]),
                              "read_data: line 2 of the Bonds section: second atom ID '2.5' is not an integer"),
}


@pytest.mark.parametrize("case", sorted(BAD_TEXT))
def test_bad_data_text(tmp_path, case):
    text, phrase = BAD_TEXT[case]
    rc, out = run_data(tmp_path, text=text)
    check_error(rc, out, phrase)


PERIODIC = lmp.PREAMBLE.replace("boundary f f f", "boundary p f f")


@pytest.mark.parametrize("x,shown", [(-INF, "-inf"), (1e300, "1e+300")])
def test_far_coordinate_in_a_periodic_box(tmp_path, x, shown):
    """Domain::remap would loop (forever for inf) shifting the atom by one box length at a time."""
    rc, out = run_data(tmp_path, with_atom(2, x=x), preamble=PERIODIC)
    check_error(rc, out, f"read_data: atom 2 at ({shown}, 0.0, 0.0) is outside the box or not finite")


def test_periodic_wrap_is_still_accepted(tmp_path):
    """An atom one box length beyond a periodic bound is wrapped in, as before."""
    rc, out = run_data(tmp_path, with_atom(2, x=1.8), preamble=PERIODIC)
    assert rc == 0 and not lmp.error_lines(out), out[-1500:]


def test_good_data_file_still_reads(tmp_path):
    rc, out = run_data(tmp_path)
    assert rc == 0 and not lmp.error_lines(out), out[-1500:]
    assert "4 atoms" in out and "3 bonds" in out


# On two ranks the atoms at x < 0 and x > 0 belong to different ranks: the repeated pair
# (1, 4) / (4, 1) and the missing atom are found by one rank and reported once, by rank 0.
MPI_CASES = {
    "bond listed twice across ranks": (ATOMS, BONDS + [(4, 1, 4, 1), (5, 1, 1, 4)],
                                       "read_data: the bond between atoms 1 and 4 is listed twice (bonds 4 and 5)"),
    "bond to a missing atom": (with_atom(3, id=5), [(1, 1, 1, 2), (2, 1, 2, 3)],
                               "read_data: bond 2 names atom 3, which is not in the Atoms section"),
    "atom ID listed twice across ranks": (with_atom(4, id=1), [(1, 1, 1, 2)],
                                          "read_data: atom ID 1 is listed twice in the Atoms section (its lines 1 and 4)"),
    "nan coordinate": (with_atom(2, y=NAN), BONDS, "read_data: atom 2 at (-0.2, nan, 0.0) is outside the box"),
}


@pytest.mark.parametrize("case", sorted(MPI_CASES))
def test_bad_data_file_on_two_ranks(tmp_path, case):
    atoms, bonds, phrase = MPI_CASES[case]
    rc, out = run_data(tmp_path, atoms, bonds, np=2)
    check_error(rc, out, phrase)


# ---- fix arguments ------------------------------------------------------------------------------

BAD_DAMPING = {
    "nan": ("nan", "fix wirenet/damping: ALPHA must be in [0, 1) (got nan)"),
    "inf": ("inf", "fix wirenet/damping: ALPHA must be in [0, 1) (got inf)"),
    "overflow": ("1e999", "fix wirenet/damping: ALPHA must be a number (got '1e999')"),
    "above 1": ("1.5", "fix wirenet/damping: ALPHA must be in [0, 1) (got 1.5)"),
    "exactly 1": ("1", "fix wirenet/damping: ALPHA must be in [0, 1) (got 1)"),
    "negative": ("-0.1", "fix wirenet/damping: ALPHA must be in [0, 1) (got -0.1)"),
    "not a number": ("half", "fix wirenet/damping: ALPHA must be a number (got 'half')"),
    "missing": ("", "fix wirenet/damping: expected 'fix ID GROUP wirenet/damping ALPHA [tally yes|no] [integrate yes|no] [viscous C]'"),
    "two values": ("0.5 0.5", "fix wirenet/damping: expected 'fix ID GROUP wirenet/damping ALPHA [tally yes|no] [integrate yes|no] [viscous C]'"),
    "tally without value": ("0.5 tally", "fix wirenet/damping: expected 'fix ID GROUP wirenet/damping ALPHA [tally yes|no] [integrate yes|no] [viscous C]'"),
    "tally maybe": ("0.5 tally maybe", "fix wirenet/damping: tally must be yes or no (got 'maybe')"),
    "unknown keyword": ("0.5 work no", "fix wirenet/damping: unknown keyword 'work' (expected tally, integrate or viscous)"),
    "integrate maybe": ("0.5 integrate maybe", "fix wirenet/damping: integrate must be yes or no (got 'maybe')"),
    "integrate without value": ("0.5 tally no integrate", "fix wirenet/damping: expected 'fix ID GROUP wirenet/damping ALPHA [tally yes|no] [integrate yes|no] [viscous C]'"),
    "viscous negative": ("0.5 viscous -1", "fix wirenet/damping: viscous must be >= 0 (got -1)"),
    "viscous inf": ("0.5 viscous inf", "fix wirenet/damping: viscous must be a finite number (got 'inf')"),
    "viscous not a number": ("0.5 viscous fast", "fix wirenet/damping: viscous must be a finite number (got 'fast')"),
    "viscous without value": ("0.5 viscous", "fix wirenet/damping: expected 'fix ID GROUP wirenet/damping ALPHA [tally yes|no] [integrate yes|no] [viscous C]'"),
}


@pytest.mark.parametrize("case", sorted(BAD_DAMPING))
def test_bad_damping_alpha(tmp_path, case):
    args, phrase = BAD_DAMPING[case]
    check_row_error(tmp_path, f"fix damp all wirenet/damping {args}\nrun 0\n", phrase)


CUBE = """solid cube
{facets}endsolid cube
"""


def write_cube(path, h=0.2):
    """Closed cube of half side h about the origin, outward normals (12 facets)."""
    v = [(x, y, z) for x in (-h, h) for y in (-h, h) for z in (-h, h)]
    quads = [(0, 1, 3, 2), (4, 6, 7, 5), (0, 4, 5, 1), (2, 3, 7, 6), (0, 2, 6, 4), (1, 5, 7, 3)]
    facets = ""
    for a, b, c, d in quads:
        for tri in ((a, b, c), (a, c, d)):
            p = [v[i] for i in tri]
            u = [p[1][k] - p[0][k] for k in range(3)]
            w = [p[2][k] - p[0][k] for k in range(3)]
            n = [u[1] * w[2] - u[2] * w[1], u[2] * w[0] - u[0] * w[2], u[0] * w[1] - u[1] * w[0]]
            facets += "facet normal {} {} {}\n outer loop\n".format(*n)
            facets += "".join("  vertex {} {} {}\n".format(*q) for q in p)
            facets += " endloop\nendfacet\n"
    path.write_text(CUBE.format(facets=facets))


BODY = "mesh block mass 44.5 inertia 1.4 1.4 1.4 0 0 0"
BAD_RIGIDMESH = {
    "mass inf": ("mesh block mass inf inertia 1 1 1 0 0 0", "fix wirenet/rigidmesh: mass must be a finite number (got 'inf')"),
    "mass nan": ("mesh block mass nan inertia 1 1 1 0 0 0", "fix wirenet/rigidmesh: mass must be a finite number (got 'nan')"),
    "mass negative": ("mesh block mass -44.5 inertia 1 1 1 0 0 0", "fix wirenet/rigidmesh: mass must be > 0 (got -44.5)"),
    "mass zero": ("mesh block mass 0 inertia 1 1 1 0 0 0", "fix wirenet/rigidmesh: mass must be > 0 (got 0)"),
    "inertia nan": ("mesh block mass 1 inertia 1 nan 1 0 0 0", "inertia value must be a finite number (got 'nan')"),
    "inertia negative": ("mesh block mass 1 inertia -1 -1 -1 0 0 0", "inertia tensor must be positive definite"),
    "velocity nan": (f"{BODY} vel 0 0 nan", "fix wirenet/rigidmesh: vel value must be a finite number (got 'nan')"),
    "velocity -inf": (f"{BODY} vel -inf 0 0", "fix wirenet/rigidmesh: vel value must be a finite number (got '-inf')"),
    "velocity overflows the energy": (f"{BODY} vel 1e200 0 0",
                                      "'vel 1e+200 0 0' give a non-finite kinetic energy (mass 44.5)"),
    "omega inf": (f"{BODY} omega 0 inf 0", "fix wirenet/rigidmesh: omega value must be a finite number (got 'inf')"),
    "omega overflows the energy": (f"{BODY} omega 0 1e200 0", "give a non-finite rotational kinetic energy"),
    "com nan": (f"{BODY} com nan 0 0", "fix wirenet/rigidmesh: com value must be a finite number (got 'nan')"),
    "gravity overflow": (f"{BODY} gravity 0 0 -1e999", "gravity value must be a finite number (got '-1e999')"),
    "gravity overflows the weight": ("mesh block mass 1e300 inertia 1e300 1e300 1e300 0 0 0 gravity 0 0 -1e10",
                                     "'gravity 0 0 -1e+10' give a non-finite weight"),
}


@pytest.mark.parametrize("case", sorted(BAD_RIGIDMESH))
def test_bad_rigidmesh_arguments(tmp_path, case):
    args, phrase = BAD_RIGIDMESH[case]
    write_cube(tmp_path / "block.stl")
    deck = base_deck("block.stl") + f"fix rb all wirenet/rigidmesh {args}\nrun 0\n"
    rc, out = lmp.run_deck_rc(deck, tmp_path, timeout=120)
    check_error(rc, out, phrase)


BAD_CONTACTWORK = {
    "unknown mode": ("nan", "fix wirenet/contactwork: unknown mode 'nan'"),
    "since without an ID": ("since", "fix wirenet/contactwork: expected 'fix ID GROUP wirenet/contactwork mark'"),
    "mark with a value": ("mark 1", "fix wirenet/contactwork: expected 'fix ID GROUP wirenet/contactwork mark'"),
    "no mode": ("", "fix wirenet/contactwork: expected 'fix ID GROUP wirenet/contactwork mark'"),
    "since a missing fix": ("since nosuch", "fix wirenet/contactwork: mark fix 'nosuch' does not exist"),
}


@pytest.mark.parametrize("case", sorted(BAD_CONTACTWORK))
def test_bad_contactwork_arguments(tmp_path, case):
    args, phrase = BAD_CONTACTWORK[case]
    check_row_error(tmp_path, f"fix cw all wirenet/contactwork {args}\nrun 0\n", phrase)


BAD_BONDS_MODIFY = {
    "unknown keyword": ("tally no", "fix_modify wirenet_bonds: unknown keyword 'tally' (expected damping_tally or scale)"),
    "no value": ("damping_tally", "fix_modify wirenet_bonds: expected 'fix_modify wirenet_bonds damping_tally yes|no'"),
    "not yes or no": ("damping_tally off", "fix_modify wirenet_bonds: damping_tally must be yes or no (got 'off')"),
}


@pytest.mark.parametrize("case", sorted(BAD_BONDS_MODIFY))
def test_bad_bonds_fix_modify(tmp_path, case):
    args, phrase = BAD_BONDS_MODIFY[case]
    check_row_error(tmp_path, "bond_style wirenet\nbond_coeff 1 wire diameter 0.0027 curve 0.01 2.5e8 0.05 5e8\n"
                    f"run 0\nfix_modify wirenet_bonds {args}\nrun 0\n", phrase)
