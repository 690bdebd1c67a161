"""Faults of LIGGGHTS' own file handling and error path (issue #43): each ends the run with one
ERROR line naming the file and what is wrong, a non-zero exit, every rank stopping, no hang.

- restart files (cmake/patches/0009): empty, cut in the header, cut among the atoms, a few bytes
  short, on 1 and 2 ranks; a restart written before the patch (no layout record, no end marker) is
  still read when complete and named when cut. LIGGGHTS hung (ignoring SIGTERM), corrupted its heap
  on 2 ranks or accepted a file a few bytes short.
- an error raised on one rank only (Error::one, patch 0008) ends the job without OpenMPI's
  MPI_ABORT banner.
- VTK and STL mesh files (patch 0010): integers read as integers ('2.7' was 2, '4294967300' was 4),
  point indices in range, coordinates finite numbers; the file, line and word named.
- read_data (patch 0011): a data file that ends inside a section names the file and the section.
- `shell mkdir` and the folders dump and write_restart create honour the umask (patch 0012).
- a file given to include, read_data or read_restart that is missing or a directory (patches
  0009, 0011, 0013). LIGGGHTS 3.8.0 has no `molecule` command: it is an unknown command.

Every run has a timeout and is killed with its whole process group if it hangs (a hung rank of
LIGGGHTS ignored SIGTERM).
"""

import os
import signal
import stat
import struct
import subprocess
from pathlib import Path

import pytest

import lmp
import netdeck
from test_input_errors import ATOMS, BONDS
from test_wire_errors import GOOD, check_error

TIMEOUT = 60


def run(deck, workdir, np=1, umask=None, timeout=TIMEOUT):
    """(exit code, output) of a deck; a run past the timeout is killed with its process group and
    fails the test (a hang)."""
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "in.deck").write_text(deck)
    cmd = [str(lmp.LIGGGHTS), "-in", "in.deck", "-log", "log.lammps", "-echo", "none"]
    if np > 1:
        cmd = ["mpirun", "-np", str(np)] + cmd
    env = dict(os.environ, **lmp.MPI_ENV)

    def preexec():
        if umask is not None:
            os.umask(umask)

    p = subprocess.Popen(cmd, cwd=workdir, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         text=True, errors="replace", start_new_session=True, preexec_fn=preexec)
    try:
        out, _ = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        out, _ = p.communicate()
        pytest.fail(f"LIGGGHTS hung (killed after {timeout} s):\n{out[-2000:]}")
    return p.returncode, out


def no_banner(out):
    for bad in ("MPI_ABORT", "NOTE: invoking", "ORTE_ERROR_LOG"):
        assert bad not in out, f"{bad!r} in the output:\n{out[-2000:]}"


# ---- restart files -------------------------------------------------------------------------------

# Four nodes in a row, three wire bonds, a granular pair style (its restart section is read by
# LIGGGHTS' pair code) and the bond history fix (global and per-atom restart data).
RESTART_PREAMBLE = """units si
atom_style hybrid granular molecular
atom_modify map array sort 0 0
boundary f f f
newton off on
communicate single vel yes
processors * 1 1
"""
WRITE_DECK = RESTART_PREAMBLE + f"""read_data net.data
neighbor 0.01 bin
neigh_modify delay 0
pair_style gran model hertz tangential history
pair_coeff * *
{lmp.HERTZ_MATERIALS}bond_style wirenet
bond_coeff 1 {GOOD}
group ends id 1 4
fix pull ends move linear 0.5 0 0
timestep 1e-5
run 20
write_restart net.restart
"""
READ_DECK = RESTART_PREAMBLE + """read_restart {name}
print "read $(atoms) atoms"
"""


@pytest.fixture(scope="module")
def restart_file(tmp_path_factory):
    """A restart file written by this build (with the layout record and the end marker)."""
    wd = tmp_path_factory.mktemp("restart")
    lmp.write_data(wd / "net.data", ATOMS, BONDS)
    rc, out = run(WRITE_DECK, wd)
    assert rc == 0 and not lmp.error_lines(out), out[-2000:]
    return (wd / "net.restart").read_bytes()


def layout(data):
    """(offset of the layout record's values, the 7 values) of a restart written by this build:
    flag 0 (version), its length and text, then flag 1000, count 7 and 7 int64."""
    flag, n = struct.unpack_from("<ii", data, 0)
    assert flag == 0
    at = 8 + n
    flag, count = struct.unpack_from("<ii", data, at)
    assert (flag, count) == (1000, 7), "no layout record after the version record"
    return at, struct.unpack_from("<7q", data, at + 8)


def legacy(data):
    """The same restart as LIGGGHTS wrote it before patch 0009: no layout record, no end marker."""
    at, values = layout(data)
    assert data[values[5]:] == b"WireNet restart\0"
    return data[:at] + data[at + 8 + 56:values[5]]


def read_cut(tmp_path, data, np):
    (tmp_path / "cut.restart").write_bytes(data)
    return run(READ_DECK.format(name="cut.restart"), tmp_path, np=np)


@pytest.mark.parametrize("np_", [1, 2])
def test_complete_restart_is_read(tmp_path, restart_file, np_):
    rc, out = read_cut(tmp_path, restart_file, np_)
    assert rc == 0 and "read 4 atoms" in out and "  3 bonds" in out, out[-2000:]


@pytest.mark.parametrize("np_", [1, 2])
def test_restart_written_before_the_layout_record_is_read(tmp_path, restart_file, np_):
    rc, out = read_cut(tmp_path, legacy(restart_file), np_)
    assert rc == 0 and "read 4 atoms" in out and "  3 bonds" in out, out[-2000:]


def cut_points(data):
    """name -> (bytes kept, phrase of the message)"""
    _, L = layout(data)
    size = L[6]
    assert size == len(data)
    full = f"(the complete file has {size} bytes)"
    return {
        "empty": (0, "restart file 'cut.restart' is empty (0 bytes)"),
        "inside the version record": (20, "is truncated at byte 20, in its header section"),
        "inside the header": (L[0] - 30, f"is truncated at byte {L[0] - 30}, in its header section {full}"),
        "header only": (L[0], f"is truncated at byte {L[0]}, in its groups section {full}"),
        "inside the force fields": (L[3] - 10, f"truncated at byte {L[3] - 10}, in its force fields section {full}"),
        "among the atoms": ((L[4] + L[5]) // 2, f"truncated at byte {(L[4] + L[5]) // 2}, in its atoms section {full}"),
        "a few bytes short": (size - 3, f"truncated at byte {size - 3}, in its end marker section {full}"),
        "without its end marker": (L[5], f"truncated at byte {L[5]}, in its end marker section {full}"),
    }


CUTS = ["empty", "inside the version record", "inside the header", "header only", "inside the force fields",
        "among the atoms", "a few bytes short", "without its end marker"]


@pytest.mark.parametrize("np_", [1, 2])
@pytest.mark.parametrize("cut", CUTS)
def test_truncated_restart_is_named(tmp_path, restart_file, cut, np_):
    keep, phrase = cut_points(restart_file)[cut]
    rc, out = read_cut(tmp_path, restart_file[:keep], np_)
    check_error(rc, out, "read_restart: " if cut != "empty" else phrase)
    assert phrase in lmp.error_lines(out)[0]
    assert "cut.restart" in lmp.error_lines(out)[0]


def legacy_cut_points(data):
    old = legacy(data)
    _, L = layout(data)
    shift = 64  # the layout record is not in the old file
    return old, {
        "header only": (L[0] - shift, f"is truncated at byte {L[0] - shift}, in its groups section"),
        "among the atoms": ((L[4] + L[5]) // 2 - shift, "in its atoms section"),
        "a few bytes short": (len(old) - 3, f"is truncated at byte {len(old) - 3}, in its atoms section"),
        "one atom value short": (len(old) - 8, f"is truncated at byte {len(old) - 8}, in its atoms section"),
        "a byte too many": (len(old) + 1, "has 1 bytes after its last atom chunk"),
    }


@pytest.mark.parametrize("np_", [1, 2])
@pytest.mark.parametrize("cut", ["header only", "among the atoms", "a few bytes short", "one atom value short",
                                 "a byte too many"])
def test_truncated_old_restart_is_named(tmp_path, restart_file, cut, np_):
    """A restart without the layout record is read as it comes, every read checked: a cut is found
    where the reads reach it, and the last atom chunk must end the file."""
    old, cuts = legacy_cut_points(restart_file)
    keep, phrase = cuts[cut]
    data = old[:keep] if keep <= len(old) else old + b"\0"
    rc, out = read_cut(tmp_path, data, np_)
    check_error(rc, out, phrase)


def test_restart_with_data_after_its_end_is_named(tmp_path, restart_file):
    rc, out = read_cut(tmp_path, restart_file + b"x", 1)
    check_error(rc, out, f"has {len(restart_file) + 1} bytes, {len(restart_file)} expected")


def test_not_a_restart_file(tmp_path):
    rc, out = read_cut(tmp_path, b"LIGGGHTS data file\n\n4 atoms\n" * 20, 1)
    check_error(rc, out, "'cut.restart' is not a LIGGGHTS restart file")


def test_restart_whose_writer_did_not_finish(tmp_path, restart_file):
    """write_restart fills the layout in last: zeros there mean the writer stopped halfway."""
    at, _ = layout(restart_file)
    data = restart_file[:at + 8] + bytes(56) + restart_file[at + 8 + 56:]
    rc, out = read_cut(tmp_path, data, 2)
    check_error(rc, out, "is incomplete: the run writing it did not finish it")


@pytest.mark.parametrize("np_", [1, 2])
def test_missing_restart_and_directory(tmp_path, np_):
    (tmp_path / "adir").mkdir()
    rc, out = run(READ_DECK.format(name="nosuch.restart"), tmp_path, np=np_)
    check_error(rc, out, "read_restart: cannot open restart file 'nosuch.restart': No such file or directory")
    rc, out = run(READ_DECK.format(name="adir"), tmp_path, np=np_)
    check_error(rc, out, "read_restart: 'adir' is a directory, not a restart file")


def test_restart_in_one_file_per_processor(tmp_path):
    """`write_restart net.%.restart` (a base file and one file per rank): read on 2 ranks and on 1;
    a per-rank file cut short or missing is named, on every rank alike."""
    lmp.write_data(tmp_path / "net.data", ATOMS, BONDS)
    rc, out = run(WRITE_DECK.replace("net.restart", "net.%.restart"), tmp_path, np=2)
    assert rc == 0 and not lmp.error_lines(out), out[-2000:]
    deck = READ_DECK.format(name="net.%.restart")
    for np_ in (2, 1):
        rc, out = run(deck, tmp_path, np=np_)
        assert rc == 0 and "read 4 atoms" in out, out[-2000:]
    data = (tmp_path / "net.1.restart").read_bytes()
    (tmp_path / "net.1.restart").write_bytes(data[:-5])
    rc, out = run(deck, tmp_path, np=2)
    check_error(rc, out, f"read_restart: restart file 'net.1.restart' is truncated or corrupt ({len(data) - 5} bytes, "
                         f"{len(data)} expected)")
    (tmp_path / "net.1.restart").unlink()
    rc, out = run(deck, tmp_path, np=2)
    check_error(rc, out, "read_restart: cannot open restart file 'net.1.restart': No such file or directory")


# ---- one rank's error -----------------------------------------------------------------------------

def test_one_rank_error_ends_without_the_abort_banner(tmp_path):
    """A bond across the rank boundary outgrows the ghosts: rank 0 alone finds it (Error::one). The
    job ends with its one ERROR line and a non-zero exit, without OpenMPI's MPI_ABORT banner."""
    deck = netdeck.outgrown_bond(tmp_path)
    rc, out = run(deck, tmp_path, np=2)
    errors = lmp.error_lines(out)
    assert rc > 0 and len(errors) == 1, out[-2000:]
    assert errors[0].startswith("ERROR on proc 0: bond_style wirenet: bond 1-2 reaches beyond the ghost atoms")
    no_banner(out)


@pytest.mark.parametrize("np_", [1, 2])
def test_error_on_the_other_rank_ends_without_the_banner(tmp_path, np_):
    """Both nodes of a zero-length bond at x = 0 belong to rank 1 of two: rank 1 alone stops."""
    atoms = [(1, 1, 0.0, 0.0, 0.0, 0.0108, 7850.0, 1), (2, 1, 0.0, 0.0, 0.0, 0.0108, 7850.0, 1)]
    lmp.write_data(tmp_path / "zero.data", atoms, [(1, 1, 1, 2)])
    deck = lmp.PREAMBLE + f"processors * 1 1\nread_data zero.data\nbond_style wirenet\nbond_coeff 1 {GOOD}\nrun 0\n"
    rc, out = run(deck, tmp_path, np=np_)
    errors = lmp.error_lines(out)
    assert rc > 0 and len(errors) == 1, out[-2000:]
    assert f"ERROR on proc {np_ - 1}: bond_style wirenet: bond 1-2 has zero length" in errors[0]
    no_banner(out)


# ---- mesh files ----------------------------------------------------------------------------------

MESH_DECK = lmp.GRANULAR_PREAMBLE + """processors * 1 1
region box block -1 1 -1 1 -1 1 units box
create_box 1 box
""" + lmp.HERTZ_MATERIALS + """{command}
run 0
"""
TRI = "fix wall all mesh/surface file {name} type 1"
TET = "region tet mesh/tet file {name} scale 1 move 0 0 0 rotate 0 0 0 units box"


def tri_vtk(points="POINTS 4 float", cells=("3 0 1 2", "3 0 2 3"), cells_line=None, types=("5", "5"),
            coords=("0 0 0", "0.5 0 0", "0.5 0.5 0", "0 0.5 0")):
    """Two triangles. LIGGGHTS' triangle VTK reader counts the first line only when it is not a
    '#' comment and compares the DATASET line as one word: it takes no standard VTK header, this
    one it does (its own quirk, not changed)."""
    cells_line = cells_line or f"CELLS {len(cells)} {4 * len(cells)}"
    return "\n".join(["vtk DataFile Version 2.0", "two triangles", "ASCII", '"DATASET UNSTRUCTURED_GRID"',
                      points, *coords, cells_line, *cells, f"CELL_TYPES {len(types)}", *types]) + "\n"


def tet_vtk(cell="4 0 1 2 3", ctype="10", points="POINTS 4 float"):
    """One tetrahedron, a standard legacy VTK file (region mesh/tet)."""
    return "\n".join(["# vtk DataFile Version 2.0", "one tet", "ASCII", "DATASET UNSTRUCTURED_GRID",
                      points, "0 0 0", "0.5 0 0", "0 0.5 0", "0 0 0.5", "CELLS 1 5", cell,
                      "CELL_TYPES 1", ctype]) + "\n"


STL_GOOD = """solid t
facet normal 0 0 1
outer loop
vertex 0 0 0
vertex 0.5 0 0
vertex 0.5 0.5 0
endloop
endfacet
endsolid t
"""

# (reader, file name, text, phrase)
BAD_MESHES = {
    "fractional point index": (TRI, "m.vtk", tri_vtk(cells=("3 0 1 2", "3 0 2.7 3")),
                               "mesh file 'm.vtk' line 12: point index '2.7' is not a whole number"),
    "point index beyond int": (TRI, "m.vtk", tri_vtk(cells=("3 0 1 2", "3 0 4294967300 3")),
                               "mesh file 'm.vtk' line 12: point index 4294967300 is out of range (0 to 3)"),
    "point index beyond the points": (TRI, "m.vtk", tri_vtk(cells=("3 0 1 4", "3 0 2 3")),
                                      "mesh file 'm.vtk' line 11: point index 4 is out of range (0 to 3)"),
    "negative point index": (TRI, "m.vtk", tri_vtk(cells=("3 0 1 2", "3 -1 2 3")),
                             "mesh file 'm.vtk' line 12: point index -1 is out of range (0 to 3)"),
    "fractional point count": (TRI, "m.vtk", tri_vtk(points="POINTS 4.5 float"),
                               "mesh file 'm.vtk' line 5: point count '4.5' is not a whole number"),
    "cell count with a suffix": (TRI, "m.vtk", tri_vtk(cells_line="CELLS 2x 8"),
                                 "mesh file 'm.vtk' line 10: cell count '2x' is not a whole number"),
    "cell of 3 points listing 2": (TRI, "m.vtk", tri_vtk(cells=("3 0 1 2", "3 0 2")),
                                   "mesh file 'm.vtk' line 12: cell of 3 points lists 2"),
    "bad coordinate": (TRI, "m.vtk", tri_vtk(coords=("0 0 0", "0.5 0 0", "0.5 0,5 0", "0 0.5 0")),
                       "mesh file 'm.vtk' line 8: coordinate '0,5' is not a finite number"),
    "fractional cell type": (TRI, "m.vtk", tri_vtk(types=("5", "5.0")),
                             "mesh file 'm.vtk' line 15: cell type '5.0' is not a whole number"),
    "file ends among the cells": (TRI, "m.vtk", tri_vtk().split("CELL_TYPES")[0].rsplit("\n", 2)[0] + "\n",
                                  "mesh file 'm.vtk' ends at line 11, inside its CELLS section"),
    "tet fractional point index": (TET, "t.vtk", tet_vtk(cell="4 0 1 2.7 3"),
                                   "mesh file 't.vtk' line 11: point index '2.7' is not a whole number"),
    "tet point index beyond int": (TET, "t.vtk", tet_vtk(cell="4 0 1 4294967298 3"),
                                   "mesh file 't.vtk' line 11: point index 4294967298 is out of range (0 to 3)"),
    "tet fractional point count": (TET, "t.vtk", tet_vtk(points="POINTS 4.0 float"),
                                   "mesh file 't.vtk' line 5: point count '4.0' is not a whole number"),
    "tet cell type with a suffix": (TET, "t.vtk", tet_vtk(ctype="10abc"),
                                    "mesh file 't.vtk' line 13: cell type '10abc' is not a whole number"),
    "stl vertex not a number": (TRI, "m.stl", STL_GOOD.replace("vertex 0.5 0 0", "vertex 0.5 abc 0"),
                                "mesh file 'm.stl' line 5: coordinate 'abc' is not a finite number"),
    "stl vertex of two numbers": (TRI, "m.stl", STL_GOOD.replace("vertex 0.5 0 0", "vertex 0.5 0"),
                                  "mesh file 'm.stl' line 5: a vertex is 'vertex X Y Z'"),
}


@pytest.mark.parametrize("np_", [1, 2])
@pytest.mark.parametrize("case", sorted(BAD_MESHES))
def test_bad_mesh_file_is_named(tmp_path, case, np_):
    reader, name, text, phrase = BAD_MESHES[case]
    (tmp_path / name).write_text(text)
    rc, out = run(MESH_DECK.format(command=reader.format(name=name)), tmp_path, np=np_)
    check_error(rc, out, phrase)


@pytest.mark.parametrize("reader,name,text", [(TRI, "m.vtk", tri_vtk()), (TET, "t.vtk", tet_vtk()),
                                              (TRI, "m.stl", STL_GOOD)], ids=["tri vtk", "tet vtk", "stl"])
def test_good_meshes_are_read(tmp_path, reader, name, text):
    (tmp_path / name).write_text(text)
    rc, out = run(MESH_DECK.format(command=reader.format(name=name)), tmp_path)
    assert rc == 0 and not lmp.error_lines(out), out[-2000:]


def binary_stl(nfacets_written, nfacets_declared):
    facets = [struct.pack("<12fH", 0, 0, 1, 0, 0, 0, 0.5, 0, 0, 0.5, 0.5, 0, 0),
              struct.pack("<12fH", 0, 0, 1, 0, 0, 0, 0.5, 0.5, 0, 0, 0.5, 0, 0)]
    return b"binary STL written by the WireNet tests".ljust(80) + struct.pack("<I", nfacets_declared) + \
        b"".join(facets[:nfacets_written])


@pytest.mark.parametrize("np_", [1, 2])
def test_binary_stl_facet_count_is_checked(tmp_path, np_):
    (tmp_path / "b.stl").write_bytes(binary_stl(2, 3))
    rc, out = run(MESH_DECK.format(command=TRI.format(name="b.stl")), tmp_path, np=np_)
    check_error(rc, out, "mesh file 'b.stl': a binary STL of 3 facets has 234 bytes, this one 184")
    (tmp_path / "good.stl").write_bytes(binary_stl(2, 2))
    rc, out = run(MESH_DECK.format(command=TRI.format(name="good.stl")), tmp_path, np=np_)
    assert rc == 0 and not lmp.error_lines(out), out[-2000:]


# ---- read_data: the section where the file ends ---------------------------------------------------

def data_lines():
    atoms = [" ".join(repr(v) for v in a) for a in ATOMS]
    bonds = [" ".join(str(v) for v in b) for b in BONDS]
    return ["data file", "", "4 atoms", "3 bonds", "1 atom types", "1 bond types", "",
            "-1 1 xlo xhi", "-1 1 ylo yhi", "-1 1 zlo zhi", "", "Atoms", "", *atoms, "", "Bonds", "", *bonds]


ATOMS_AT = 13   # index of the first atom line
BONDS_AT = 20   # index of the first bond line

CUT_DATA = {
    "among the atoms": (ATOMS_AT + 2, "unexpected end of data file 'net.data' in its Atoms section (4 lines expected, 2 found)"),
    "among the bonds": (BONDS_AT + 1, "unexpected end of data file 'net.data' in its Bonds section (3 lines expected, 1 found)"),
    "after the Bonds title": (BONDS_AT - 1, "unexpected end of data file 'net.data' after the title of its Bonds section"),
    "before the Bonds section": (BONDS_AT - 2, "data file 'net.data' has no Bonds section, but its header declares 3 bonds"),
    "before the Atoms section": (ATOMS_AT - 2, "data file 'net.data' has no Atoms section, but its header declares 4 atoms"),
    "empty": (0, "data file 'net.data' is empty"),
}


@pytest.mark.parametrize("np_", [1, 2])
@pytest.mark.parametrize("case", sorted(CUT_DATA))
def test_data_file_ending_early_names_the_section(tmp_path, case, np_):
    keep, phrase = CUT_DATA[case]
    lines = data_lines()[:keep]
    (tmp_path / "net.data").write_text("\n".join(lines) + ("\n" if lines else ""))
    rc, out = run(lmp.PREAMBLE + "read_data net.data\n", tmp_path, np=np_)
    check_error(rc, out, "read_data: " + phrase)
    no_banner(out)


@pytest.mark.parametrize("np_", [1, 2])
def test_data_file_ending_early_without_bonds_names_the_section(tmp_path, np_):
    """atom_style granular reads the Atoms section on every rank (no proc-0 scan first)."""
    lines = ["data file", "", "4 atoms", "1 atom types", "", "-1 1 xlo xhi", "-1 1 ylo yhi", "-1 1 zlo zhi", "",
             "Atoms", "", *[f"{a[0]} {a[1]} {a[5]!r} {a[6]!r} {a[2]!r} {a[3]!r} {a[4]!r}" for a in ATOMS[:3]]]
    (tmp_path / "net.data").write_text("\n".join(lines) + "\n")
    rc, out = run(lmp.GRANULAR_PREAMBLE + "read_data net.data\n", tmp_path, np=np_)
    check_error(rc, out, "read_data: unexpected end of data file 'net.data' in its Atoms section (4 lines expected)")


# ---- missing files and directories ----------------------------------------------------------------

@pytest.mark.parametrize("np_", [1, 2])
@pytest.mark.parametrize("command,what", [("include", "input script"), ("read_data", "data file")])
def test_missing_file_or_directory_is_named(tmp_path, command, what, np_):
    (tmp_path / "adir").mkdir()
    pre = lmp.PREAMBLE if command == "read_data" else ""
    rc, out = run(pre + f"{command} nosuch.file\n", tmp_path / "a", np=np_)
    check_error(rc, out, f"{command}: cannot open {what} 'nosuch.file': No such file or directory")
    (tmp_path / "b").mkdir()
    (tmp_path / "b" / "adir").mkdir()
    rc, out = run(pre + f"{command} adir\n", tmp_path / "b", np=np_)
    check_error(rc, out, f"{command}: 'adir' is a directory, not a{'n' if what[0] == 'i' else ''} {what}")


def test_molecule_is_not_a_command_of_liggghts_3_8(tmp_path):
    rc, out = run("molecule m nosuch.mol\n", tmp_path)
    check_error(rc, out, "Unknown command: molecule")


# ---- folders honour the umask ----------------------------------------------------------------------

@pytest.mark.parametrize("umask,mode", [(0o022, 0o755), (0o077, 0o700), (0o002, 0o775)])
def test_created_folders_honour_the_umask(tmp_path, umask, mode):
    """`shell mkdir` (the decks' run/frames) and the folders that dump and write_restart create for
    their files: 0777 less the umask, as mkdir(1) (LIGGGHTS gave 0750 whatever the umask)."""
    lmp.write_data(tmp_path / "net.data", ATOMS, BONDS)
    deck = lmp.PREAMBLE + """read_data net.data
shell mkdir frames
dump d all custom 1 dumps/nodes.dump id x y z
run 0
write_restart restarts/net.restart
"""
    rc, out = run(deck, tmp_path, umask=umask)
    assert rc == 0 and not lmp.error_lines(out), out[-2000:]
    for folder in ("frames", "dumps", "restarts"):
        got = stat.S_IMODE((tmp_path / folder).stat().st_mode)
        assert got == mode, f"{folder}: mode {got:o} under umask {umask:03o}, expected {mode:o}"
