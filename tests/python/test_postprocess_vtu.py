"""postprocess vtu / data2vtu: the files read back with meshio with the same points, cells, data."""

import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from postprocess.__main__ import main  # noqa: E402
from postprocess import synthetic  # noqa: E402

# Node dump rows (id type x y z vx) deliberately not sorted by id.
NODES_100 = [(3, 2, 2.0, 0.0, 0.0, 0.5), (1, 1, 0.0, 0.0, 0.0, 0.0), (2, 1, 1.0, 0.0, 0.0, 0.25),
             (4, 4, 1.0, 1.0, 0.0, 0.0)]
NODES_200 = [(1, 1, 0.0, 0.0, -0.5, 0.0), (2, 1, 1.0, 0.0, -0.75, 0.0), (3, 2, 2.0, 0.0, -0.5, 0.0),
             (4, 4, 1.0, 1.0, -0.25, 0.0)]
# Bonds: (atom1, atom2, type, tension, strain)
BONDS_100 = [(1, 2, 1, 10.5, 0.001), (2, 3, 2, -2.0, -0.0005), (2, 4, 4, 7.25, 0.002)]
BONDS_200 = [(2, 1, 1, 30.0, 0.004), (2, 4, 4, 9.5, 0.003)]          # 2-3 broke; 1-2 reversed
DT = 0.5


def rows(bonds):
    return [synthetic.bond_row(a, b, t, f, (0, 0, 0), strain=e) for a, b, t, f, e in bonds]


@pytest.fixture
def run_dir(tmp_path):
    (tmp_path / "nodes.dump").write_text(synthetic.node_dump_text(
        [(100, NODES_100), (200, NODES_200)], names=("id", "type", "x", "y", "z", "vx")))
    (tmp_path / "bonds.dump").write_text(synthetic.bond_dump_text(
        [(100, rows(BONDS_100)), (200, rows(BONDS_200))]))
    atoms = [(i, t, x, y, z, 0.01, 7850, 1) for i, t, x, y, z, _ in sorted(NODES_100)]
    bonds = [(k + 1, t, a, b) for k, (a, b, t, _, _) in enumerate(BONDS_100)]
    (tmp_path / "panel.data").write_text(synthetic.data_file_text(atoms, bonds))
    return tmp_path


def read_series(pvd):
    root = ET.parse(pvd).getroot()
    assert root.get("type") == "Collection"
    sets = root.find("Collection").findall("DataSet")
    return [(float(d.get("timestep")), pvd.parent / d.get("file")) for d in sets]


def check_frames(series):
    assert [t for t, _ in series] == [100 * DT, 200 * DT]
    first = meshio.read(series[0][1])
    np.testing.assert_array_equal(first.points, [[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 1, 0]])
    np.testing.assert_array_equal(first.point_data["id"], [1, 2, 3, 4])
    np.testing.assert_array_equal(first.point_data["type"], [1, 1, 2, 4])
    np.testing.assert_array_equal(first.point_data["vx"], [0, 0.25, 0.5, 0])
    assert first.cells[0].type == "line"
    np.testing.assert_array_equal(first.cells[0].data, [[0, 1], [1, 2], [1, 3]])
    np.testing.assert_array_equal(first.cell_data["tension"][0], [10.5, -2.0, 7.25])
    np.testing.assert_array_equal(first.cell_data["strain"][0], [0.001, -0.0005, 0.002])
    np.testing.assert_array_equal(first.cell_data["family"][0], [1, 2, 4])
    np.testing.assert_array_equal(first.cell_data["broken"][0], [0, 0, 0])
    second = meshio.read(series[1][1])
    np.testing.assert_array_equal(second.points[:, 2], [-0.5, -0.75, -0.5, -0.25])
    np.testing.assert_array_equal(second.cells[0].data, [[1, 0], [1, 3], [1, 2]])
    np.testing.assert_array_equal(second.cell_data["tension"][0], [30.0, 9.5, 0.0])
    np.testing.assert_array_equal(second.cell_data["family"][0], [1, 4, 2])
    np.testing.assert_array_equal(second.cell_data["broken"][0], [0, 0, 1])


@pytest.mark.parametrize("extra", [["--data", "panel.data"], [], ["--ascii"]])
def test_series_reads_back(run_dir, extra, monkeypatch):
    monkeypatch.chdir(run_dir)
    code = main(["vtu", "--nodes", "nodes.dump", "--bonds", "bonds.dump", "--dt", str(DT),
                 "-o", "out/series.pvd", *extra])
    assert code == 0
    series = read_series(run_dir / "out" / "series.pvd")
    assert all(path.parent == run_dir / "out" / "series" for _, path in series)
    check_frames(series)


def test_rerun_replaces_the_series(run_dir, monkeypatch):
    monkeypatch.chdir(run_dir)
    args = ["vtu", "--nodes", "nodes.dump", "--bonds", "bonds.dump", "-o", "series.pvd"]
    assert main(args) == 0
    assert main(args) == 0
    assert sorted(p.name for p in (run_dir / "series").iterdir()) == [
        "series_0000000100.vtu", "series_0000000200.vtu"]
    assert sorted(p.name for p in run_dir.iterdir()) == [
        "bonds.dump", "nodes.dump", "panel.data", "series", "series.pvd"]


def test_data2vtu(run_dir):
    out = run_dir / "panel.vtu"
    assert main(["data2vtu", str(run_dir / "panel.data")]) == 0
    mesh = meshio.read(out)
    np.testing.assert_array_equal(mesh.points, [[0, 0, 0], [1, 0, 0], [2, 0, 0], [1, 1, 0]])
    np.testing.assert_array_equal(mesh.point_data["id"], [1, 2, 3, 4])
    np.testing.assert_array_equal(mesh.point_data["type"], [1, 1, 2, 4])
    np.testing.assert_array_equal(mesh.point_data["diameter"], [0.01] * 4)
    np.testing.assert_array_equal(mesh.point_data["molecule"], [1] * 4)
    np.testing.assert_array_equal(mesh.cells[0].data, [[0, 1], [1, 2], [1, 3]])
    np.testing.assert_array_equal(mesh.cell_data["family"][0], [1, 2, 4])
    np.testing.assert_array_equal(mesh.cell_data["bond_id"][0], [1, 2, 3])


def test_data2vtu_bad_bond_line(run_dir, capsys):
    data = run_dir / "panel.data"
    data.write_text(data.read_text().replace("\n3 4 2 4\n", "\n3 4 2\n"))
    assert main(["data2vtu", str(data), "-o", str(run_dir / "x.vtu")]) == 2
    err = capsys.readouterr().err
    assert err == f"postprocess data2vtu: error: {data}:23: expected 4 columns in Bonds, got 3\n"
    assert not (run_dir / "x.vtu").exists()


def test_ascii_option_writes_ascii_xml(run_dir, monkeypatch):
    """--ascii: every DataArray is inline ASCII text; without it none is."""
    monkeypatch.chdir(run_dir)
    base = ["vtu", "--nodes", "nodes.dump", "--bonds", "bonds.dump"]
    assert main([*base, "--ascii", "-o", "a.pvd"]) == 0
    assert main([*base, "-o", "b.pvd"]) == 0
    text = (run_dir / "a" / "a_0000000100.vtu").read_text()
    root = ET.fromstring(text)
    arrays = root.iter("DataArray")
    formats = {a.get("format") for a in arrays}
    assert formats == {"ascii"}
    tension = next(a for a in root.iter("DataArray") if a.get("Name") == "tension")
    assert [float(v) for v in tension.text.split()] == [10.5, -2.0, 7.25]
    binary = (run_dir / "b" / "b_0000000100.vtu").read_bytes()
    formats = {a.get("format") for a in ET.fromstring(binary).iter("DataArray")}
    assert "ascii" not in formats and formats <= {"binary", "appended"}


def test_data_bonds_missing_from_every_frame_are_broken(run_dir, monkeypatch):
    """--data: a data-file bond absent from the first frame already is a broken cell (the
    first-frame reference would not know it)."""
    monkeypatch.chdir(run_dir)
    atoms = [(i, t, x, y, z, 0.01, 7850, 1) for i, t, x, y, z, _ in sorted(NODES_100)]
    bonds = [(k + 1, t, a, b) for k, (a, b, t, _, _) in enumerate(BONDS_100)] + [(4, 3, 3, 4)]
    (run_dir / "panel.data").write_text(synthetic.data_file_text(atoms, bonds))
    base = ["vtu", "--nodes", "nodes.dump", "--bonds", "bonds.dump"]
    assert main([*base, "--data", "panel.data", "-o", "with.pvd"]) == 0
    assert main([*base, "-o", "without.pvd"]) == 0
    first = meshio.read(run_dir / "with" / "with_0000000100.vtu")
    np.testing.assert_array_equal(first.cells[0].data, [[0, 1], [1, 2], [1, 3], [2, 3]])
    np.testing.assert_array_equal(first.cell_data["broken"][0], [0, 0, 0, 1])
    np.testing.assert_array_equal(first.cell_data["family"][0], [1, 2, 4, 3])
    np.testing.assert_array_equal(first.cell_data["tension"][0], [10.5, -2.0, 7.25, 0.0])
    second = meshio.read(run_dir / "with" / "with_0000000200.vtu")
    np.testing.assert_array_equal(second.cell_data["broken"][0], [0, 0, 1, 1])
    plain = meshio.read(run_dir / "without" / "without_0000000100.vtu")
    assert len(plain.cells[0].data) == 3


def _listing(folder):
    return sorted(str(p.relative_to(folder)) for p in folder.rglob("*"))


def test_out_naming_a_folder_of_the_user_is_refused(run_dir, capsys):
    """--out DIR where DIR holds the user's files: nothing is replaced or written."""
    (run_dir / "results").mkdir()
    (run_dir / "results" / "notes.txt").write_text("mine\n")
    before = _listing(run_dir)
    code = main(["vtu", "--nodes", str(run_dir / "nodes.dump"), "--bonds",
                 str(run_dir / "bonds.dump"), "-o", str(run_dir / "results")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1 and "Traceback" not in err
    assert err.startswith(f"postprocess vtu: error: {run_dir / 'results'}: the folder exists "
                          f"and holds 1 entry that this command did not write (e.g. 'notes.txt')")
    assert _listing(run_dir) == before


def test_out_with_a_trailing_slash_is_refused(run_dir, capsys):
    before = _listing(run_dir)
    code = main(["vtu", "--nodes", str(run_dir / "nodes.dump"), "--bonds",
                 str(run_dir / "bonds.dump"), "-o", str(run_dir) + "/"])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert "--out: expected the series file name (e.g. DIR/wirenet.pvd)" in err
    assert _listing(run_dir) == before


def test_pvd_that_cannot_be_written_leaves_no_frames(run_dir, capsys):
    (run_dir / "series.pvd").mkdir()
    before = _listing(run_dir)
    code = main(["vtu", "--nodes", str(run_dir / "nodes.dump"), "--bonds",
                 str(run_dir / "bonds.dump"), "-o", str(run_dir / "series.pvd")])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert err == (f"postprocess vtu: error: {run_dir / 'series.pvd'}: is a directory (an "
                   f"output file was expected)\n")
    assert _listing(run_dir) == before


def test_failed_pvd_rename_keeps_the_previous_series(run_dir, monkeypatch, capsys):
    """The frames folder and the .pvd are committed together: if the .pvd cannot be renamed
    into place, the previous frames folder is restored."""
    from postprocess import output
    monkeypatch.chdir(run_dir)
    args = ["vtu", "--nodes", "nodes.dump", "--bonds", "bonds.dump", "-o", "series.pvd"]
    assert main(args) == 0
    (run_dir / "series" / "series_0000000100.vtu").write_text("previous\n")
    old_pvd = (run_dir / "series.pvd").read_text()
    before = _listing(run_dir)
    real = output.os.replace

    def failing(src, dst):
        if str(dst) == "series.pvd" and ".tmp" in str(src):
            raise OSError(28, "No space left on device", str(src))
        return real(src, dst)
    monkeypatch.setattr(output.os, "replace", failing)
    assert main(args) == 2
    err = capsys.readouterr().err
    assert err == "postprocess vtu: error: series.pvd: cannot write: No space left on device\n"
    assert _listing(run_dir) == before
    assert (run_dir / "series" / "series_0000000100.vtu").read_text() == "previous\n"
    assert (run_dir / "series.pvd").read_text() == old_pvd
