"""Bad input to every post-processing command (issue #14): exit code 2, exactly one line on
stderr that names the offending item (file and line, option, key, value), no traceback, and no
output left behind (the working folder is listed before and after).

Each case starts from a folder of good inputs (the same commands succeed on it, see
test_good_inputs_are_accepted), spoils one thing and runs the command line in a subprocess.
"""

import gzip
import json
import os
import re
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from postprocess import synthetic  # noqa: E402

NODES = [(1, 1, 0.0, 0.0, 0.0), (2, 1, 1.0, 0.0, 0.0), (3, 2, 2.0, 0.0, 0.0)]
BONDS = [(1, 2, 1, 10.0), (2, 3, 2, 5.0)]
STEPS = (100, 200)


def bond_rows():
    return [synthetic.bond_row(a, b, t, f, (0.5 * (NODES[a - 1][2] + NODES[b - 1][2]), 0, 0))
            for a, b, t, f in BONDS]


def write_inputs(work):
    """Good inputs of every command in ``work``."""
    (work / "bonds.dump").write_text(synthetic.bond_dump_text([(s, bond_rows()) for s in STEPS]))
    (work / "bonds6.dump").write_text(
        synthetic.bond_dump_text([(s, bond_rows()) for s in STEPS], ncols=6))
    (work / "nodes.dump").write_text(synthetic.node_dump_text([(s, NODES) for s in STEPS]))
    atoms = [(i, t, x, y, z, 0.01, 7850, 1) for i, t, x, y, z in NODES]
    bonds = [(k + 1, t, a, b) for k, (a, b, t, _) in enumerate(BONDS)]
    (work / "panel.data").write_text(synthetic.data_file_text(atoms, bonds))
    (work / "panel.json").write_text(json.dumps(
        {"centre": [1, 0, 0], "normal": [0, 0, 1], "bond_types": {"1": "DT", "2": "SW"}}))
    (work / "platter.csv").write_text("time,displacement,force\n0,0,0\n100,0.1,5\n200,0.2,9\n")
    (work / "measured.csv").write_text("displacement,force\n" + "".join(
        f"{d / 10},{d * 1.5}\n" for d in range(6)))
    study = work / "study"
    for fraction in (0.0, 1.0):
        case = study / f"calib_{fraction:g}"
        case.mkdir(parents=True)
        (case / "platter.csv").write_text("time,displacement,force\n" + "".join(
            f"{d},{d / 10},{d * (1 + fraction)}\n" for d in range(6)))
        (case / "case.json").write_text(json.dumps({"status": "ok", "bending": fraction}))
    hexcase = study / "punch_hex"
    hexcase.mkdir()
    (hexcase / "zone_forces.csv").write_text(
        "time,displacement,family,total_tension,max_tension,bonds\n"
        "0,0,DT,0,0,0\n0,0,SW,0,0,0\n1,0.1,DT,50,20,3\n1,0.1,SW,80,10,9\n")
    (hexcase / "case.json").write_text(json.dumps(
        {"status": "ok", "kind": "punch", "wall_time": 3.5,
         "first_rupture": {"displacement": 0.1, "force": 5.0,
                           "bond": {"atom1": 1, "atom2": 2, "family": "DT"}}}))
    beam = study / "beam"
    beam.mkdir()
    (beam / "beam.csv").write_text("elements,load,tip_deflection,analytic_deflection,nrmse\n"
                                   "5,1,0.01,0.0101,0.01\n10,1,0.0101,0.0101,0.001\n")


def listing(folder):
    """Every path under ``folder`` with its size (a rewritten file changes most of the time)."""
    return sorted((str(p.relative_to(folder)), p.stat().st_size if p.is_file() else -1)
                  for p in folder.rglob("*"))


def run(work, *args):
    result = subprocess.run([sys.executable, "-m", "postprocess", *map(str, args)], cwd=work,
                            capture_output=True, text=True,
                            env={**os.environ, "PYTHONPATH": str(ROOT)})
    return result.returncode, result.stdout, result.stderr


def edit(path, old, new, count=1):
    text = path.read_text()
    assert old in text, (path, old)
    path.write_text(text.replace(old, new, count))


def line_of(path, fragment):
    """1-based number of the first line of ``path`` that contains ``fragment``."""
    for number, line in enumerate(path.read_text().splitlines(), start=1):
        if fragment in line:
            return number
    raise AssertionError(f"{fragment!r} not in {path}")


# --- the spoilers: each takes the work folder and may change files -------------------------

def nan_tension(work):
    edit(work / "bonds.dump", " 5 0.1", " nan 0.1")       # bond 2-3 of step 100: tension


def inf_midpoint(work):
    dump = work / "bonds.dump"
    lines = dump.read_text().splitlines(keepends=True)
    fields = lines[20].split()                            # step 200, bond 1-2
    fields[7] = "inf"
    lines[20] = " ".join(fields) + "\n"
    dump.write_text("".join(lines))


def huge_type(work):
    edit(work / "bonds.dump", "\n2 3 2 0.1", "\n2 3 1e30 0.1")        # step 100, bond 2-3


def fractional_atom(work):
    edit(work / "bonds6.dump", "\n2 3 2 0.1", "\n2.5 3 2 0.1")


def fractional_data_id(work):
    edit(work / "panel.data", "\n2 2 2 3\n", "\n2 2 2.5 3\n")


def nan_node(work):
    edit(work / "nodes.dump", "\n2 1 1 0 0\n", "\n2 1 nan 0 0\n")


def truncated_json(work):
    (work / "panel.json").write_text('{"centre": [1, 0, 0], "normal": [0, 0')


def json_list(work):
    (work / "panel.json").write_text("[1, 0, 0]")


def json_centre_text(work):
    (work / "panel.json").write_text('{"centre": ["a"]}')


def json_normal_nan(work):
    (work / "panel.json").write_text('{"normal": [0, NaN, 1]}')


def json_bond_types(work):
    (work / "panel.json").write_text('{"bond_types": {"1": 5}}')


def nan_displacement(work):
    edit(work / "platter.csv", "100,0.1,5", "100,nan,5")


def damaged_gzip(work):
    data = gzip.compress((work / "bonds.dump").read_bytes())
    (work / "bonds.dump.gz").write_bytes(data[: len(data) // 2])


def output_is_a_directory(work):
    (work / "out.csv").mkdir()


def user_folder_as_vtu_out(work):
    (work / "results").mkdir()
    (work / "results" / "notes.txt").write_text("mine\n")


def pvd_is_a_directory(work):
    (work / "series.pvd").mkdir()


def nan_atom_in_data(work):
    edit(work / "panel.data", "\n2 1 1 0 0 0.01", "\n2 1 1 0 0 nan")


def bond_to_unknown_atom(work):
    edit(work / "panel.data", "\n2 2 2 3\n", "\n2 2 2 9\n")


def inf_platter_force(work):
    edit(work / "study" / "calib_1" / "platter.csv", "2,0.2,4.0\n", "2,0.2,inf\n")


def bending_text(work):
    (work / "study" / "calib_1" / "case.json").write_text('{"bending": "abc"}')


def case_json_truncated(work):
    (work / "study" / "punch_hex" / "case.json").write_text('{"status": "ok",\n "kind": ')


def case_json_list(work):
    (work / "study" / "punch_hex" / "case.json").write_text('["ok"]')


def case_json_energy(work):
    (work / "study" / "punch_hex" / "case.json").write_text('{"energy": 5}')


def case_json_rupture(work):
    (work / "study" / "punch_hex" / "case.json").write_text(
        '{"first_rupture": {"displacement": "x"}}')


def case_json_quasi_static(work):
    (work / "study" / "punch_hex" / "case.json").write_text(
        '{"quasi_static": {"curve_difference": "1 %", "passed": true}}')


def case_json_wall_time(work):
    (work / "study" / "punch_hex" / "case.json").write_text('{"wall_time": "3 s"}')


def case_json_cpu_time(work):
    (work / "study" / "punch_hex" / "case.json").write_text('{"cpu_time": [3]}')


def case_json_drop(work):
    (work / "study" / "punch_hex" / "case.json").write_text('{"ended_at_drop": {"force": "0 N"}}')


def zone_csv_missing_column(work):
    edit(work / "study" / "punch_hex" / "zone_forces.csv", "max_tension,", "peak,")


def nan_measured(work):
    edit(work / "measured.csv", "0.2,3.0", "0.2,nan")


def negative_bending(work):
    (work / "study" / "calib_1" / "case.json").write_text('{"bending": -0.1}')


def nan_bending(work):
    (work / "study" / "calib_1" / "case.json").write_text('{"bending": NaN}')


def same_bending(work):
    (work / "study" / "calib_1" / "case.json").write_text('{"bending": 0}')


def nothing(work):
    pass


STUDY = "study"
CASES = [
    # zone
    ("zone-nan-tension", nan_tension, ["zone", "bonds.dump", "--dt", "1", "-o", "out.csv"],
     "bonds.dump:[[bonds.dump| nan 0.1]]: column c_bonds[6]: not a finite number: 'nan' "
     "(step 100)"),
    ("zone-inf-midpoint", inf_midpoint, ["zone", "bonds.dump", "--dt", "1", "-o", "out.csv"],
     "bonds.dump:21: column c_bonds[8]: not a finite number: 'inf' (step 200)"),
    ("zone-huge-type", huge_type, ["zone", "bonds.dump", "--dt", "1", "-o", "out.csv"],
     "bonds.dump:11: column c_bonds[3]: expected a whole number from 1 to 2147483647, got "
     "1e+30 (step 100)"),
    ("zone-fractional-atom", fractional_atom,
     ["zone", "bonds6.dump", "--nodes", "nodes.dump", "--dt", "1", "-o", "out.csv"],
     "bonds6.dump:11: column c_bonds[1]: expected a whole number from 1 to 2147483647, got 2.5 "
     "(step 100)"),
    ("zone-nan-node", nan_node,
     ["zone", "bonds6.dump", "--nodes", "nodes.dump", "--dt", "1", "-o", "out.csv"],
     "nodes.dump:11: column x: not a finite number: 'nan' (step 100)"),
    ("zone-dt-nan", nothing, ["zone", "bonds.dump", "--dt", "nan", "-o", "out.csv"],
     "argument --dt: expected a finite number > 0, got 'nan'"),
    ("zone-dt-zero", nothing, ["zone", "bonds.dump", "--dt", "0", "-o", "out.csv"],
     "argument --dt: expected a finite number > 0, got '0'"),
    ("zone-radius-inf", nothing,
     ["zone", "bonds.dump", "--dt", "1", "--radius", "inf", "-o", "out.csv"],
     "argument --radius: expected a finite number > 0, got 'inf'"),
    ("zone-radius-negative", nothing,
     ["zone", "bonds.dump", "--dt", "1", "--radius", "-2", "-o", "out.csv"],
     "argument --radius: expected a finite number > 0, got '-2'"),
    ("zone-centre-nan", nothing,
     ["zone", "bonds.dump", "--dt", "1", "--centre", "0", "nan", "0", "-o", "out.csv"],
     "argument --centre/--center: expected a finite number, got 'nan'"),
    ("zone-normal-zero", nothing,
     ["zone", "bonds.dump", "--dt", "1", "--normal", "0", "0", "0", "-o", "out.csv"],
     "argument --normal: expected a non-zero finite vector, got 0 0 0"),
    ("zone-json-truncated", truncated_json,
     ["zone", "bonds.dump", "--dt", "1", "--json", "panel.json", "-o", "out.csv"],
     "panel.json:1: invalid JSON: Expecting ',' delimiter"),
    ("zone-json-list", json_list,
     ["zone", "bonds.dump", "--dt", "1", "--json", "panel.json", "-o", "out.csv"],
     "panel.json: expected a JSON object {...}, got a list"),
    ("zone-json-centre-text", json_centre_text,
     ["zone", "bonds.dump", "--dt", "1", "--json", "panel.json", "-o", "out.csv"],
     "panel.json: 'centre' must be three numbers, got [\"a\"]"),
    ("zone-json-normal-nan", json_normal_nan,
     ["zone", "bonds.dump", "--dt", "1", "--json", "panel.json", "-o", "out.csv"],
     "panel.json: 'normal' must be three finite numbers, got [0.0, nan, 1.0]"),
    ("zone-json-bond-types", json_bond_types,
     ["zone", "bonds.dump", "--dt", "1", "--json", "panel.json", "-o", "out.csv"],
     "panel.json: 'bond_types' must map type numbers to names, got {\"1\": 5}"),
    ("zone-displacement-nan", nan_displacement,
     ["zone", "bonds.dump", "--dt", "1", "--displacement", "platter.csv", "-o", "out.csv"],
     "platter.csv:3: column displacement: not a finite number: 'nan'"),
    ("zone-time-column-missing", nothing,
     ["zone", "bonds.dump", "--dt", "1", "--displacement", "platter.csv", "--time-column", "t",
      "-o", "out.csv"],
     "platter.csv:1: missing column t"),
    ("zone-families", nothing,
     ["zone", "bonds.dump", "--dt", "1", "--families", "1:DT", "-o", "out.csv"],
     "--families: expected TYPE=NAME[,TYPE=NAME...], got '1:DT'"),
    ("zone-damaged-gzip", damaged_gzip, ["zone", "bonds.dump.gz", "--dt", "1", "-o", "out.csv"],
     "bonds.dump.gz:"),
    ("zone-out-is-a-directory", output_is_a_directory,
     ["zone", "bonds.dump", "--dt", "1", "-o", "out.csv"],
     "out.csv: is a directory (an output file was expected)"),
    ("zone-missing-dump", nothing, ["zone", "nope.dump", "--dt", "1", "-o", "out.csv"],
     "nope.dump: No such file or directory"),
    # vtu
    ("vtu-dt-negative", nothing,
     ["vtu", "--nodes", "nodes.dump", "--bonds", "bonds.dump", "--dt", "-1", "-o", "s.pvd"],
     "argument --dt: expected a finite number > 0, got '-1'"),
    ("vtu-dt-inf", nothing,
     ["vtu", "--nodes", "nodes.dump", "--bonds", "bonds.dump", "--dt", "inf", "-o", "s.pvd"],
     "argument --dt: expected a finite number > 0, got 'inf'"),
    ("vtu-nan-tension", nan_tension,
     ["vtu", "--nodes", "nodes.dump", "--bonds", "bonds.dump", "-o", "s.pvd"],
     "bonds.dump:[[bonds.dump| nan 0.1]]: column c_bonds[6]: not a finite number: 'nan'"),
    ("vtu-nan-node", nan_node,
     ["vtu", "--nodes", "nodes.dump", "--bonds", "bonds.dump", "-o", "s.pvd"],
     "nodes.dump:11: column x: not a finite number: 'nan' (step 100)"),
    ("vtu-data-nan-atom", nan_atom_in_data,
     ["vtu", "--nodes", "nodes.dump", "--bonds", "bonds.dump", "--data", "panel.data",
      "-o", "s.pvd"],
     "panel.data:[[panel.data|2 1 1 0 0 nan]]: Atoms column diameter: not a finite number: "
     "'nan'"),
    ("vtu-out-user-folder", user_folder_as_vtu_out,
     ["vtu", "--nodes", "nodes.dump", "--bonds", "bonds.dump", "-o", "results"],
     "results: the folder exists and holds 1 entry that this command did not write "
     "(e.g. 'notes.txt')"),
    ("vtu-pvd-is-a-directory", pvd_is_a_directory,
     ["vtu", "--nodes", "nodes.dump", "--bonds", "bonds.dump", "-o", "series.pvd"],
     "series.pvd: is a directory (an output file was expected)"),
    ("vtu-out-trailing-slash", nothing,
     ["vtu", "--nodes", "nodes.dump", "--bonds", "bonds.dump", "-o", "vtk/"],
     "--out: expected the series file name (e.g. DIR/wirenet.pvd), got 'vtk/'"),
    # data2vtu
    ("data2vtu-nan-atom", nan_atom_in_data, ["data2vtu", "panel.data", "-o", "p.vtu"],
     "panel.data:[[panel.data|2 1 1 0 0 nan]]: Atoms column diameter: not a finite number: "
     "'nan'"),
    ("data2vtu-fractional-atom", fractional_data_id, ["data2vtu", "panel.data", "-o", "p.vtu"],
     "panel.data:[[panel.data|2 2 2.5 3]]: Bonds column atom1: expected a whole number from 1 "
     "to 2147483647, got '2.5'"),
    ("data2vtu-unknown-atom", bond_to_unknown_atom, ["data2vtu", "panel.data", "-o", "p.vtu"],
     "panel.data: bond refers to unknown atom 9"),
    ("data2vtu-out-is-a-directory", output_is_a_directory,
     ["data2vtu", "panel.data", "-o", "out.csv"],
     "out.csv: is a directory (an output file was expected)"),
    # plot
    ("plot-calibration-inf-force", inf_platter_force,
     ["plot", "calibration", f"{STUDY}/calib_0/platter.csv", f"{STUDY}/calib_1/platter.csv",
      "-o", "fig"],
     f"{STUDY}/calib_1/platter.csv:4: column force: not a finite number: 'inf'"),
    ("plot-calibration-bending-text", bending_text,
     ["plot", "calibration", f"{STUDY}/calib_1/platter.csv", "-o", "fig"],
     "calib_1/case.json: 'bending' must be a number >= 0, got a string 'abc'"),
    ("plot-zone-missing-column", zone_csv_missing_column,
     ["plot", "zone", f"{STUDY}/punch_hex/zone_forces.csv", "-o", "fig"],
     f"{STUDY}/punch_hex/zone_forces.csv:1: missing column max_tension"),
    ("plot-beam-prefix-is-a-folder", nothing,
     ["plot", "beam", f"{STUDY}/beam/beam.csv", "-o", "figs/"],
     "argument --out: expected a file prefix such as DIR/figure, got 'figs/'"),
    ("plot-study-case-json-rupture", case_json_rupture, ["plot", "study", STUDY],
     "punch_hex/case.json: 'first_rupture.displacement' must be a number or null, got a "
     "string 'x'"),
    # report (and the study's reading of case folders)
    ("report-case-json-truncated", case_json_truncated, ["report", STUDY, "--no-figures"],
     "punch_hex/case.json:2: invalid JSON: Expecting value"),
    ("report-case-json-list", case_json_list, ["report", STUDY, "--no-figures"],
     "punch_hex/case.json: expected a JSON object {...}, got a list"),
    ("report-case-json-energy", case_json_energy, ["report", STUDY, "--no-figures"],
     "punch_hex/case.json: 'energy' must be an object {...} or null, got a number 5"),
    ("report-case-json-wall-time", case_json_wall_time, ["report", STUDY],
     "punch_hex/case.json: 'wall_time' must be a number or null, got a string '3 s'"),
    ("report-case-json-cpu-time", case_json_cpu_time, ["report", STUDY, "--no-figures"],
     "punch_hex/case.json: 'cpu_time' must be a number or null, got a list [3]"),
    ("report-case-json-drop", case_json_drop, ["report", STUDY, "--no-figures"],
     "punch_hex/case.json: 'ended_at_drop.force' must be a number or null, got a string '0 N'"),
    ("report-bending-text", bending_text, ["report", STUDY],
     "calib_1/case.json: 'bending' must be a number >= 0, got a string 'abc'"),
    ("report-case-json-quasi-static", case_json_quasi_static, ["report", STUDY, "--no-figures"],
     "punch_hex/case.json: 'quasi_static.curve_difference' must be a number or null, got a "
     "string '1 %'"),
    ("report-not-a-directory", nothing, ["report", "platter.csv"],
     "platter.csv: not a directory"),
    # calibrate
    ("calibrate-nan-measured", nan_measured,
     ["calibrate", "measured.csv", "--cases", f"{STUDY}/calib_0", f"{STUDY}/calib_1",
      "-o", "fit"],
     "measured.csv:4: column force: not a finite number: 'nan'"),
    ("calibrate-negative-bending", negative_bending,
     ["calibrate", "measured.csv", "--cases", f"{STUDY}/calib_0", f"{STUDY}/calib_1",
      "-o", "fit"],
     "calib_1/case.json: 'bending' must be a finite number >= 0, got a number -0.1"),
    ("calibrate-nan-bending", nan_bending,
     ["calibrate", "measured.csv", "--cases", f"{STUDY}/calib_0", f"{STUDY}/calib_1",
      "-o", "fit"],
     "calib_1/case.json: 'bending' must be a finite number >= 0, got a number nan"),
    ("calibrate-inf-platter", inf_platter_force,
     ["calibrate", "measured.csv", "--cases", f"{STUDY}/calib_0", f"{STUDY}/calib_1",
      "-o", "fit"],
     f"{STUDY}/calib_1/platter.csv:4: column force: not a finite number: 'inf'"),
    ("calibrate-same-fraction", same_bending,
     ["calibrate", "measured.csv", "--cases", f"{STUDY}/calib_0", f"{STUDY}/calib_1",
      "-o", "fit"],
     f"--cases: {STUDY}/calib_0 and {STUDY}/calib_1 have the same bending fraction 0"),
    ("calibrate-missing-case", nothing,
     ["calibrate", "measured.csv", "--cases", f"{STUDY}/calib_0", f"{STUDY}/calib_7",
      "-o", "fit"],
     f"{STUDY}/calib_7: not a directory (--cases)"),
    ("calibrate-force-column", nothing,
     ["calibrate", "measured.csv", "--cases", f"{STUDY}/calib_0", f"{STUDY}/calib_1",
      "--force-column", "F", "-o", "fit"],
     "measured.csv:1: missing column F"),
    ("calibrate-prefix-is-a-folder", nothing,
     ["calibrate", "measured.csv", "--cases", f"{STUDY}/calib_0", f"{STUDY}/calib_1",
      "-o", "fits/"],
     "argument --out: expected a file prefix such as DIR/figure, got 'fits/'"),
]


def expected_text(work, text):
    """Replace ``[[FILE|fragment]]`` by the number of the line of FILE holding the fragment."""
    return re.sub(r"\[\[([^|\]]+)\|([^\]]+)\]\]",
                  lambda m: str(line_of(work / m.group(1), m.group(2))), text)


@pytest.mark.parametrize("spoil,args,expected", [c[1:] for c in CASES],
                         ids=[c[0] for c in CASES])
def test_bad_input(tmp_path, spoil, args, expected):
    write_inputs(tmp_path)
    spoil(tmp_path)
    expected = expected_text(tmp_path, expected)
    before = listing(tmp_path)
    code, out, err = run(tmp_path, *args)
    assert code == 2, (code, out, err)
    assert "Traceback" not in err, err
    assert err.endswith("\n") and err.count("\n") == 1, err
    command = args[0]
    assert err.startswith(f"postprocess {command}: error: "), err
    assert expected in err, err
    assert ".tmp" not in err, err                      # never a temporary name
    assert listing(tmp_path) == before                 # nothing written, nothing left behind


def test_cases_are_many_and_distinct():
    assert len(CASES) >= 25
    assert len({c[0] for c in CASES}) == len(CASES)
    assert len({(c[1].__name__, tuple(c[2])) for c in CASES}) == len(CASES)
    commands = {c[2][0] for c in CASES}
    assert commands == {"zone", "vtu", "data2vtu", "plot", "report", "calibrate"}


@pytest.mark.parametrize("args", [
    ["zone", "bonds.dump", "--dt", "1", "--json", "panel.json", "--displacement", "platter.csv",
     "-o", "out.csv"],
    ["zone", "bonds6.dump", "--nodes", "nodes.dump", "--dt", "1", "-o", "out.csv"],
    ["vtu", "--nodes", "nodes.dump", "--bonds", "bonds.dump", "--data", "panel.data",
     "-o", "s.pvd"],
    ["data2vtu", "panel.data", "-o", "p.vtu"],
    ["plot", "calibration", f"{STUDY}/calib_0/platter.csv", f"{STUDY}/calib_1/platter.csv",
     "-o", "fig"],
    ["report", STUDY, "--no-figures"],
    ["calibrate", "measured.csv", "--cases", f"{STUDY}/calib_0", f"{STUDY}/calib_1", "-o", "fit"],
], ids=["zone", "zone-nodes", "vtu", "data2vtu", "plot", "report", "calibrate"])
def test_good_inputs_are_accepted(tmp_path, args):
    """The unspoilt folder works, so each failure above is due to its one spoiled item."""
    write_inputs(tmp_path)
    code, out, err = run(tmp_path, *args)
    assert code == 0, err
    assert "error" not in err


def test_nan_in_case_json_reads_as_not_available(tmp_path):
    """The study wrote NaN for values it could not compute (e.g. a quasi-static measure):
    they read as null and summary.json stays strict JSON."""
    write_inputs(tmp_path)
    (tmp_path / STUDY / "punch_hex" / "case.json").write_text(
        '{"status": "ok", "wall_time": NaN, "quasi_static": {"curve_difference": NaN, '
        '"passed": false, "snap_events": []}}')
    code, _, err = run(tmp_path, "report", STUDY, "--no-figures")
    assert code == 0, err
    text = (tmp_path / STUDY / "summary.json").read_text()
    assert "NaN" not in text and "Infinity" not in text
    summary = json.loads(text, parse_constant=lambda name: pytest.fail(f"{name} in JSON"))
    case = summary["cases"]["punch_hex"]
    assert case["wall_time"] is None
    assert case["quasi_static"]["curve_difference"] is None


def test_calibration_fit_json_is_strict(tmp_path):
    write_inputs(tmp_path)
    code, _, err = run(tmp_path, "calibrate", "measured.csv", "--cases", f"{STUDY}/calib_0",
                       f"{STUDY}/calib_1", "-o", "fit")
    assert code == 0, err
    result = json.loads((tmp_path / "fit.json").read_text(),
                        parse_constant=lambda name: pytest.fail(f"{name} in JSON"))
    # measured = the mean of the two curves: half-way between the fractions in log10(f + 1e-3)
    halfway = (1e-3 * 1.001) ** 0.5 - 1e-3
    assert result["best_fraction"] == pytest.approx(halfway, rel=1e-6)
    assert result["rmse"] == pytest.approx(0.0, abs=1e-9)
