"""Malformed, truncated, empty inputs and missing columns: one-line error naming file and line,
exit code 2, no output file (and no temporary left behind)."""

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

ROOT = Path(__file__).resolve().parents[2]
sys.path.insert(0, str(ROOT))

from postprocess.__main__ import main  # noqa: E402
from postprocess import synthetic  # noqa: E402

GOOD = synthetic.bond_dump_text([
    (1000, [synthetic.bond_row(1, 2, 1, 10.0, (0, 0, 0)),
            synthetic.bond_row(2, 3, 2, 5.0, (0.1, 0, 0))]),
    (2000, [synthetic.bond_row(1, 2, 1, 11.0, (0, 0, 0)),
            synthetic.bond_row(2, 3, 2, 6.0, (0.1, 0, 0))]),
])
LINES = GOOD.splitlines(keepends=True)   # frame 2: header lines 12-20, data lines 21-22


def run_zone(tmp_path, capsys, text, extra=()):
    dump = tmp_path / "bonds.dump"
    dump.write_text(text)
    out = tmp_path / "out" / "zone_forces.csv"
    code = main(["zone", str(dump), "--dt", "1e-5", "-o", str(out), *extra])
    err = capsys.readouterr().err
    return code, err, out


def check_error(tmp_path, code, err, out, expected):
    assert code == 2
    assert err.count("\n") == 1, err
    assert err.startswith("postprocess zone: error: ")
    assert err.strip().endswith(expected), err
    assert not out.exists()
    leftovers = [p for p in tmp_path.rglob("*") if p.is_file() and p.name.startswith(".")]
    assert leftovers == []


def test_good_dump_is_accepted(tmp_path, capsys):
    code, _, out = run_zone(tmp_path, capsys, GOOD)
    assert code == 0 and out.exists()


def test_short_line(tmp_path, capsys):
    text = "".join(LINES[:21]) + "1 2 1\n" + "".join(LINES[22:])
    code, err, out = run_zone(tmp_path, capsys, text)
    check_error(tmp_path, code, err, out, "bonds.dump:22: expected 12 columns, got 3")


def test_truncated_last_line(tmp_path, capsys):
    text = "".join(LINES[:21]) + "2 3 2 0.1 0.0"         # a partly written last line
    code, err, out = run_zone(tmp_path, capsys, text)
    check_error(tmp_path, code, err, out, "bonds.dump:22: expected 12 columns, got 5")


def test_truncated_frame_at_end_of_file(tmp_path, capsys):
    text = "".join(LINES[:21])                         # 1 of 2 entries of the second frame
    code, err, out = run_zone(tmp_path, capsys, text)
    check_error(tmp_path, code, err, out,
                "bonds.dump:22: unexpected end of file: frame at step 2000 expects 2 entries, "
                "got 1")


def test_frame_cut_by_next_header(tmp_path, capsys):
    text = "".join(LINES[:10]) + "".join(LINES[11:])    # first frame lost its second entry
    code, err, out = run_zone(tmp_path, capsys, text)
    check_error(tmp_path, code, err, out,
                "bonds.dump:11: truncated frame at step 1000: expected 2 entries, got 1")


def test_header_only(tmp_path, capsys):
    text = "".join(LINES[:3])
    code, err, out = run_zone(tmp_path, capsys, text)
    check_error(tmp_path, code, err, out, "bonds.dump:4: unexpected end of file after "
                                          "ITEM: NUMBER OF ENTRIES")


def test_not_a_number(tmp_path, capsys):
    text = "".join(LINES[:20]) + LINES[20].replace("11", "1x1", 1) + "".join(LINES[21:])
    code, err, out = run_zone(tmp_path, capsys, text)
    check_error(tmp_path, code, err, out, "bonds.dump:21: not a number: '1x1'")


def test_empty_file(tmp_path, capsys):
    code, err, out = run_zone(tmp_path, capsys, "")
    check_error(tmp_path, code, err, out, "bonds.dump:1: empty file")


def test_bad_timestep(tmp_path, capsys):
    text = "ITEM: TIMESTEP\nabc\n" + "".join(LINES[2:])
    code, err, out = run_zone(tmp_path, capsys, text)
    check_error(tmp_path, code, err, out,
                "bonds.dump:2: expected an integer after ITEM: TIMESTEP, got 'abc'")


def test_missing_tension_column(tmp_path, capsys):
    text = synthetic.bond_dump_text([(0, [synthetic.bond_row(1, 2, 1, 1.0, (0, 0, 0))])],
                                    ncols=5)
    code, err, out = run_zone(tmp_path, capsys, text)
    check_error(tmp_path, code, err, out,
                "bonds.dump:9: missing column tension (c_ID[6]) (needed by zone)")


def test_six_columns_without_nodes(tmp_path, capsys):
    text = synthetic.bond_dump_text([(0, [synthetic.bond_row(1, 2, 1, 1.0, (0, 0, 0))])],
                                    ncols=6)
    code, err, out = run_zone(tmp_path, capsys, text)
    check_error(tmp_path, code, err, out, "bonds.dump:9: no midpoint columns (c_ID[8..10]); "
                                          "give the node dump with --nodes")


def test_node_dump_without_the_step(tmp_path, capsys):
    nodes = tmp_path / "nodes.dump"
    nodes.write_text(synthetic.node_dump_text([(5, [(1, 1, 0, 0, 0), (2, 1, 1, 0, 0)])]))
    text = synthetic.bond_dump_text([(0, [synthetic.bond_row(1, 2, 1, 1.0, (0, 0, 0))])],
                                    ncols=6)
    code, err, out = run_zone(tmp_path, capsys, text, ["--nodes", str(nodes)])
    check_error(tmp_path, code, err, out, f"bonds.dump:9: no frame at step 0 in node dump {nodes}")


def test_node_dump_missing_coordinates(tmp_path, capsys):
    nodes = tmp_path / "nodes.dump"
    nodes.write_text(synthetic.node_dump_text([(0, [(1, 1, 0), (2, 1, 1)])],
                                              names=("id", "type", "x")))
    text = synthetic.bond_dump_text([(0, [synthetic.bond_row(1, 2, 1, 1.0, (0, 0, 0))])],
                                    ncols=6)
    code, err, out = run_zone(tmp_path, capsys, text, ["--nodes", str(nodes)])
    check_error(tmp_path, code, err, out, "nodes.dump:9: missing columns x y z (node dump)")


def test_existing_output_is_left_untouched(tmp_path, capsys):
    out = tmp_path / "out" / "zone_forces.csv"
    out.parent.mkdir()
    out.write_text("old\n")
    code, _, _ = run_zone(tmp_path, capsys, GOOD[:-20])
    assert code == 2 and out.read_text() == "old\n"


def test_displacement_csv_missing_column(tmp_path, capsys):
    csv = tmp_path / "platter.csv"
    csv.write_text("time,force\n0,1\n")
    code, err, out = run_zone(tmp_path, capsys, GOOD, ["--displacement", str(csv)])
    check_error(tmp_path, code, err, out, "platter.csv:1: missing column displacement")


def test_vtu_error_leaves_no_series(tmp_path, capsys):
    nodes = tmp_path / "nodes.dump"
    nodes.write_text(synthetic.node_dump_text([(s, [(1, 1, 0, 0, 0), (2, 1, 1, 0, 0),
                                                    (3, 1, 2, 0, 0)]) for s in (1000, 2000)]))
    bonds = tmp_path / "bonds.dump"
    bonds.write_text("".join(LINES[:21]))
    out = tmp_path / "series.pvd"
    code = main(["vtu", "--nodes", str(nodes), "--bonds", str(bonds), "-o", str(out)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert "bonds.dump:22: unexpected end of file" in err
    assert sorted(os.listdir(tmp_path)) == ["bonds.dump", "nodes.dump"]


def test_command_line_exit_code_and_single_line(tmp_path):
    dump = tmp_path / "bonds.dump"
    dump.write_text("".join(LINES[:21]) + "1 2 1\n")
    result = subprocess.run([sys.executable, "-m", "postprocess", "zone", str(dump), "--dt", "1",
                             "-o", str(tmp_path / "z.csv")], cwd=ROOT, capture_output=True,
                            text=True)
    assert result.returncode == 2
    assert result.stderr == f"postprocess zone: error: {dump}:22: expected 12 columns, got 3\n"
    assert not (tmp_path / "z.csv").exists()


@pytest.mark.parametrize("command", ["zone", "vtu", "data2vtu", "plot", "report"])
def test_help_per_subcommand(command, capsys):
    with pytest.raises(SystemExit) as stop:
        main([command, "--help"])
    assert stop.value.code == 0
    assert f"usage: postprocess {command}" in capsys.readouterr().out


def test_quiet_run_of_a_mesh_deck(tmp_path):
    """engine.run without progress output on a deck that reads an STL mesh: LIGGGHTS 3.8's STL
    reader prints to the screen unchecked, so a run with '-screen none' crashed (segfault)."""
    import lmp
    from runner import engine
    from runner.generator import generate
    os.environ.setdefault("WIRENET_BUILD", str(lmp.BUILD))
    stl = tmp_path / "cone.stl"
    generate("shape cone", stl, "--resolution", 16)
    deck = tmp_path / "in.mesh"
    deck.write_text(f"""units si
atom_style granular
atom_modify sort 0 0
boundary f f f
region box block -1 1 -1 1 -1 1 units box
create_box 1 box
fix m all mesh/surface file {stl} type 1
run 0
""")
    engine.run(deck, tmp_path / "run")
    assert "Reading STL file" in (tmp_path / "run" / "screen.txt").read_text()


# --- file modes: every output honours the umask (issue #14) --------------------------------

def _modes_run(tmp_path, mask):
    """zone, vtu, report and calibrate under ``mask``; {relative path: mode} of what they wrote."""
    work = tmp_path / f"umask{mask:03o}"
    work.mkdir()
    (work / "bonds.dump").write_text(GOOD)
    (work / "nodes.dump").write_text(synthetic.node_dump_text(
        [(s, [(1, 1, 0, 0, 0), (2, 1, 1, 0, 0), (3, 1, 2, 0, 0)]) for s in (1000, 2000)]))
    study = work / "study"
    for fraction in (0.0, 1.0):
        case = study / f"calib_{fraction:g}"
        case.mkdir(parents=True)
        (case / "platter.csv").write_text(
            "time,displacement,force\n" + "".join(f"{d},{d},{d * (1 + fraction)}\n"
                                                  for d in range(6)))
        (case / "case.json").write_text(json.dumps({"bending": fraction}))
    (work / "measured.csv").write_text("displacement,force\n" + "".join(
        f"{d},{d * 1.5}\n" for d in range(6)))
    commands = [
        ["zone", "bonds.dump", "--dt", "1", "-o", "out/zone.csv"],
        ["vtu", "--nodes", "nodes.dump", "--bonds", "bonds.dump", "-o", "out/vtk/series.pvd"],
        ["report", "study", "--no-figures"],
        ["calibrate", "measured.csv", "--cases", str(study / "calib_0"), str(study / "calib_1"),
         "-o", "out/fit"],
    ]
    before = {p for p in work.rglob("*")}
    for command in commands:
        result = subprocess.run([sys.executable, "-m", "postprocess", *command], cwd=work,
                                capture_output=True, text=True,
                                env={**os.environ, "PYTHONPATH": str(ROOT)},
                                preexec_fn=lambda: os.umask(mask))
        assert result.returncode == 0, (command, result.stderr)
    return {str(p.relative_to(work)): p.stat().st_mode & 0o777
            for p in work.rglob("*") if p not in before}


@pytest.mark.parametrize("mask,file_mode,dir_mode", [(0o022, 0o644, 0o755), (0o077, 0o600, 0o700)])
def test_outputs_honour_the_umask(tmp_path, mask, file_mode, dir_mode):
    modes = _modes_run(tmp_path, mask)
    expected = {"out/zone.csv", "out/vtk/series.pvd", "out/vtk/series",
                "out/vtk/series/series_0000001000.vtu", "study/report.md", "study/summary.json",
                "out/fit.json", "out/fit.png", "out/fit.svg"}
    assert expected <= set(modes)
    for name, mode in modes.items():
        is_dir = (tmp_path / f"umask{mask:03o}" / name).is_dir()
        assert mode == (dir_mode if is_dir else file_mode), (name, oct(mode))


def test_write_json_is_strict(tmp_path):
    from postprocess import output
    path = tmp_path / "x.json"
    output.write_json(path, {"a": float("nan"), "b": [1.0, float("inf")], "c": {"d": -float("inf")}})
    text = path.read_text()
    assert "NaN" not in text and "Infinity" not in text
    assert json.loads(text) == {"a": None, "b": [1.0, None], "c": {"d": None}}


# --- atomic outputs: errors name the user's path, never a temporary --------------------------

def test_output_file_that_is_a_directory(tmp_path, capsys):
    (tmp_path / "out").mkdir()
    (tmp_path / "out" / "zone_forces.csv").mkdir()
    code, err, _ = run_zone(tmp_path, capsys, GOOD)
    assert code == 2 and err.count("\n") == 1
    assert err == (f"postprocess zone: error: {tmp_path / 'out' / 'zone_forces.csv'}: is a "
                   f"directory (an output file was expected)\n")
    assert ".tmp" not in err
    assert os.listdir(tmp_path / "out") == ["zone_forces.csv"]


def test_unwritable_output_folder_names_the_target(tmp_path, capsys):
    (tmp_path / "out").write_text("a file, not a folder\n")
    dump = tmp_path / "bonds.dump"
    dump.write_text(GOOD)
    target = tmp_path / "out" / "z.csv"
    code = main(["zone", str(dump), "--dt", "1", "-o", str(target)])
    err = capsys.readouterr().err
    assert code == 2 and err.count("\n") == 1
    assert err.startswith(f"postprocess zone: error: {target}: cannot create its folder ")
    assert ".tmp" not in err


def test_failed_commit_restores_every_previous_output(tmp_path, monkeypatch):
    """Outputs: if the second rename fails, the first target gets its old content back."""
    from postprocess import output
    from postprocess.errors import PostprocessError
    (tmp_path / "a.txt").write_text("old a\n")
    (tmp_path / "b.txt").write_text("old b\n")
    real = os.replace

    def failing(src, dst):
        if str(dst).endswith("b.txt") and ".tmp" in str(src):
            raise OSError(28, "No space left on device", str(src))
        return real(src, dst)
    monkeypatch.setattr(output.os, "replace", failing)
    with pytest.raises(PostprocessError) as caught:
        with output.Outputs() as outputs:
            for name in ("a.txt", "b.txt"):
                with open(outputs.file(str(tmp_path / name)), "w") as handle:
                    handle.write("new\n")
    assert str(caught.value) == f"{tmp_path / 'b.txt'}: cannot write: No space left on device"
    assert (tmp_path / "a.txt").read_text() == "old a\n"
    assert (tmp_path / "b.txt").read_text() == "old b\n"
    assert sorted(os.listdir(tmp_path)) == ["a.txt", "b.txt"]


def test_control_characters_of_a_damaged_dump_stay_on_one_line(tmp_path, capsys):
    code, err, out = run_zone(tmp_path, capsys, "\x0bITEM\x1b[2J\x85: TIMESTEP\n1\n")
    assert code == 2 and err.count("\n") == 1, err
    assert err[:-1].isprintable()
    assert err.endswith("bonds.dump:1: expected an ITEM: line, got 'ITEM\\x1b[2J\\x85: TIMESTEP'\n")
    assert not out.exists()
