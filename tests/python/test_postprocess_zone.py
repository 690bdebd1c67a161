"""postprocess zone: exact totals, maxima and counts on synthetic dumps with known answers."""

import csv
import json
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from postprocess.__main__ import main  # noqa: E402
from postprocess import synthetic, zone  # noqa: E402

HEADER = ["time", "displacement", "family", "total_tension", "max_tension", "bonds"]
CENTRE = (1.0, 1.0, 0.5)
DT = 0.25

# Nodes: id -> (x, y, z). The zone is the circle of radius 1 about (1, 1) in the x-y plane.
NODES = {
    1: (1.25, 1.0, 0.0), 2: (1.75, 1.0, 0.0),      # DT, midpoint (1.5, 1): inside
    3: (1.0, 1.9, -0.9), 4: (1.0, 1.9, -0.7),      # DT, (1, 1.9, -0.8): inside (z ignored)
    5: (2.25, 1.0, 0.0), 6: (2.75, 1.0, 0.0),      # DT, (2.5, 1): outside
    7: (1.7, 1.0, 0.0), 8: (2.1, 1.0, 0.0),        # SW straddling, midpoint (1.9, 1): inside
    9: (1.8, 1.0, 0.0), 10: (2.4, 1.0, 0.0),       # SW straddling, midpoint (2.1, 1): outside
    11: (0.5, 1.0, 0.0), 12: (0.5, 1.5, 0.0),      # SW compressive, inside
    13: (1.0, 0.5, 0.0), 14: (1.0, 0.25, 0.0),     # SW tensile, inside
    15: (1.0, 0.0, 0.0), 16: (1.0, 0.0, 0.0),      # SW on the boundary (distance 1): inside
    17: (3.0, 3.0, 0.0), 18: (3.5, 3.0, 0.0),      # selvedge, outside
}
# (atom1, atom2, type, tension) per frame; rope (type 4) never has bonds.
FRAME1 = [(1, 2, 1, 10.5), (3, 4, 1, 20.25), (5, 6, 1, 1000.0), (7, 8, 2, 2.25),
          (9, 10, 2, 99.0), (11, 12, 2, -50.0), (13, 14, 2, 3.5), (15, 16, 2, 0.125),
          (17, 18, 3, 77.0)]
FRAME3 = [(11, 12, 2, -8.0), (5, 6, 1, 12.0)]
FRAMES = [(100, FRAME1), (200, []), (300, FRAME3)]
EXPECTED = {  # (step, family) -> (total, max, bonds)
    (100, "DT"): (30.75, 20.25, 2), (100, "SW"): (5.875, 3.5, 4),
    (100, "selvedge"): (0.0, 0.0, 0), (100, "rope"): (0.0, 0.0, 0),
    (300, "SW"): (0.0, 0.0, 1), (300, "DT"): (0.0, 0.0, 0),
}


def midpoint(a, b):
    return tuple(0.5 * (p + q) for p, q in zip(NODES[a], NODES[b]))


def bond_rows(bonds):
    return [synthetic.bond_row(a, b, t, f, midpoint(a, b), strain=0.001) for a, b, t, f in bonds]


@pytest.fixture
def run_dir(tmp_path):
    meta = {"centre": list(CENTRE), "normal": [0, 0, 1],
            "bond_types": {"1": "DT", "2": "SW", "3": "selvedge", "4": "rope"}}
    (tmp_path / "panel.json").write_text(json.dumps(meta))
    frames12 = [(s, bond_rows(b)) for s, b in FRAMES]
    (tmp_path / "bonds.dump").write_text(synthetic.bond_dump_text(frames12))
    (tmp_path / "bonds6.dump").write_text(synthetic.bond_dump_text(frames12, ncols=6))
    nodes = [(i, 1, *xyz) for i, xyz in NODES.items()]
    (tmp_path / "nodes.dump").write_text(
        synthetic.node_dump_text([(s, nodes) for s, _ in FRAMES]))
    (tmp_path / "platter.csv").write_text("time,displacement,force\n0,0,0\n100,0.2,5\n")
    return tmp_path


def read_rows(path):
    with open(path, newline="") as handle:
        rows = list(csv.reader(handle))
    return rows[0], rows[1:]


def by_key(rows):
    return {(round(float(r[0]) / DT), r[2]): r for r in rows}


def test_zone_exact_totals_maxima_counts(run_dir):
    out = run_dir / "zone_forces.csv"
    code = main(["zone", str(run_dir / "bonds.dump"), "--dt", str(DT), "--json",
                 str(run_dir / "panel.json"), "--out", str(out)])
    assert code == 0
    header, rows = read_rows(out)
    assert header == HEADER
    assert len(rows) == 3 * 4                       # every step x every family, empty ones too
    assert [r[2] for r in rows[:4]] == ["DT", "SW", "selvedge", "rope"]
    table = by_key(rows)
    for (step, family), (total, largest, bonds) in EXPECTED.items():
        row = table[(step, family)]
        assert float(row[0]) == step * DT
        assert float(row[1]) == 0.0
        assert (float(row[3]), float(row[4]), int(row[5])) == (total, largest, bonds)
    for family in ("DT", "SW", "selvedge", "rope"):    # empty frame: zeros
        row = table[(200, family)]
        assert (float(row[3]), float(row[4]), int(row[5])) == (0.0, 0.0, 0)


def test_node_dump_midpoints_give_the_same_answer(run_dir):
    out12, out6 = run_dir / "a.csv", run_dir / "b.csv"
    common = ["--dt", str(DT), "--json", str(run_dir / "panel.json")]
    assert main(["zone", str(run_dir / "bonds.dump"), *common, "-o", str(out12)]) == 0
    assert main(["zone", str(run_dir / "bonds6.dump"), "--nodes", str(run_dir / "nodes.dump"),
                 *common, "-o", str(out6)]) == 0
    assert out12.read_text() == out6.read_text()


def test_displacement_interpolated_from_csv(run_dir):
    out = run_dir / "z.csv"
    assert main(["zone", str(run_dir / "bonds.dump"), "--dt", str(DT), "--json",
                 str(run_dir / "panel.json"), "--displacement", str(run_dir / "platter.csv"),
                 "-o", str(out)]) == 0
    _, rows = read_rows(out)
    disp = {round(float(r[0]) / DT): float(r[1]) for r in rows}
    assert disp == {100: pytest.approx(0.05), 200: pytest.approx(0.1), 300: pytest.approx(0.15)}


def test_radius_centre_and_family_overrides(run_dir):
    out = run_dir / "z.csv"
    assert main(["zone", str(run_dir / "bonds.dump"), "--dt", str(DT), "--centre", "2.5", "1",
                 "0", "--radius", "0.1", "--families", "1=DT,2=SW", "-o", str(out)]) == 0
    _, rows = read_rows(out)
    table = by_key(rows)
    assert sorted({r[2] for r in rows}) == ["DT", "SW", "type3"]   # unknown type 3 kept
    assert [float(x) for x in table[(100, "DT")][3:]] == [1000.0, 1000.0, 1.0]
    assert [float(x) for x in table[(300, "DT")][3:]] == [12.0, 12.0, 1.0]
    assert [float(x) for x in table[(100, "SW")][3:]] == [0.0, 0.0, 0.0]


def test_defaults_without_json(run_dir):
    """No JSON: centre 0 0 0, radius 1, families of doc/file_formats.md."""
    out = run_dir / "z.csv"
    assert main(["zone", str(run_dir / "bonds.dump"), "--dt", "1", "-o", str(out)]) == 0
    _, rows = read_rows(out)
    assert [r[2] for r in rows[:4]] == ["DT", "SW", "selvedge", "rope"]
    # within 1 m of the origin in frame 1: bond 11-12 (0.5, 1.25) is not; (1, 0) is exactly 1
    row = {r[2]: r for r in rows if float(r[0]) == 100}
    assert [float(x) for x in row["SW"][3:]] == [0.125, 0.125, 1.0]


def test_in_zone_projects_on_the_panel_plane():
    points = np.array([[0.0, 0.0, 5.0], [1.0, 0.0, -3.0], [0.0, 1.0000001, 0.0], [3.0, 0.6, 0.8]])
    inside = zone.in_zone(points, np.zeros(3), np.array([0.0, 0.0, 1.0]), 1.0)
    assert inside.tolist() == [True, True, False, False]
    tilted = zone.in_zone(points, np.zeros(3), np.array([1.0, 0.0, 0.0]), 1.0)
    assert tilted.tolist() == [False, False, False, True]


def test_duplicate_steps_keep_the_last_frame(run_dir):
    later = synthetic.bond_dump_text([(300, bond_rows([(1, 2, 1, 4.0)]))])
    (run_dir / "restart.dump").write_text(later)
    out = run_dir / "z.csv"
    assert main(["zone", str(run_dir / "bonds.dump"), str(run_dir / "restart.dump"), "--dt",
                 str(DT), "--json", str(run_dir / "panel.json"), "-o", str(out)]) == 0
    _, rows = read_rows(out)
    assert len(rows) == 12
    assert [float(x) for x in by_key(rows)[(300, "DT")][3:]] == [4.0, 4.0, 1.0]


def test_normal_option_tilts_the_zone(run_dir):
    """--normal 2 0 0 (normalised to x): the zone is the circle of radius 1 about (y, z) =
    (1, 0.5) in the y-z plane; x no longer matters. Hand-computed from NODES."""
    out = run_dir / "z.csv"
    assert main(["zone", str(run_dir / "bonds.dump"), "--dt", str(DT), "--json",
                 str(run_dir / "panel.json"), "--normal", "2", "0", "0", "-o", str(out)]) == 0
    table = by_key(read_rows(out)[1])
    # DT: 1-2 (dy 0, dz -0.5) and 5-6 (dy 0, dz -0.5) inside, 3-4 (dy 0.9, dz -1.3) outside
    assert [float(x) for x in table[(100, "DT")][3:]] == [1010.5, 1000.0, 2.0]
    # SW: 7-8, 9-10, 11-12 (compressive), 13-14 inside; 15-16 (dy -1, dz -0.5) outside
    assert [float(x) for x in table[(100, "SW")][3:]] == [104.75, 99.0, 4.0]
    assert [float(x) for x in table[(100, "selvedge")][3:]] == [0.0, 0.0, 0.0]


def test_time_column_option(run_dir):
    """--time-column picks the abscissa of --displacement; a decoy 'time' column would give
    other values."""
    (run_dir / "motion.csv").write_text("time,t,disp\n0,0,0\n1,100,0.2\n")
    out = run_dir / "z.csv"
    assert main(["zone", str(run_dir / "bonds.dump"), "--dt", str(DT), "--json",
                 str(run_dir / "panel.json"), "--displacement", str(run_dir / "motion.csv"),
                 "--time-column", "t", "--displacement-column", "disp", "-o", str(out)]) == 0
    disp = {round(float(r[0]) / DT): float(r[1]) for r in read_rows(out)[1]}
    assert disp == {100: pytest.approx(0.05), 200: pytest.approx(0.1), 300: pytest.approx(0.15)}


def test_gzip_dumps_give_the_same_answer(run_dir):
    """.gz bond and node dumps are read transparently."""
    import gzip
    for name in ("bonds.dump", "bonds6.dump", "nodes.dump"):
        (run_dir / (name + ".gz")).write_bytes(gzip.compress((run_dir / name).read_bytes()))
    common = ["--dt", str(DT), "--json", str(run_dir / "panel.json")]
    plain, packed, packed6 = run_dir / "a.csv", run_dir / "b.csv", run_dir / "c.csv"
    assert main(["zone", str(run_dir / "bonds.dump"), *common, "-o", str(plain)]) == 0
    assert main(["zone", str(run_dir / "bonds.dump.gz"), *common, "-o", str(packed)]) == 0
    assert main(["zone", str(run_dir / "bonds6.dump.gz"), "--nodes",
                 str(run_dir / "nodes.dump.gz"), *common, "-o", str(packed6)]) == 0
    assert plain.read_text() == packed.read_text() == packed6.read_text()
    assert len(read_rows(packed)[1]) == 12


def test_nan_tension_is_an_error_not_zero(run_dir, capsys):
    """A NaN tension used to count as 0 (NaN > 0 is False)."""
    dump = run_dir / "bonds.dump"
    lines = dump.read_text().splitlines(keepends=True)
    fields = lines[9].split()                      # first data line of step 100: bond 1-2
    fields[5] = "nan"
    lines[9] = " ".join(fields) + "\n"
    dump.write_text("".join(lines))
    out = run_dir / "z.csv"
    assert main(["zone", str(dump), "--dt", str(DT), "-o", str(out)]) == 2
    err = capsys.readouterr().err
    assert err == (f"postprocess zone: error: {dump}:10: column c_bonds[6]: not a finite number: "
                   f"'nan' (step 100)\n")
    assert not out.exists()
