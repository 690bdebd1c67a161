"""The tensile case kind and the data sheet (issue #40; doc/tensile.md): a single wire's strip
breaks at the wire's breaking load; a strip pulled across the twists against one pulled along
them; the clamps in equilibrium with the applied force; bad tensile keys get one line and exit 2;
the data sheet's case files and the data-sheet figures of the punch report. Each run is small
(a 6-node chain, a 0.48 m x 0.32 m strip)."""

import json
import math
import os
import subprocess
import sys

import pytest

import lmp
from postprocess import datasheet as sheet
from postprocess import report
from runner import api, datasheet
from runner.materials import MATERIALS, SW_CURVE

ROOT = lmp.ROOT
STRIP = ('kind = "tensile"\n[panel]\nnet = "hex"\nwidth = {w}\nheight = {h}\n'
         'placement = "symmetric"\nselvedge = "sides"\n[tensile]\ndirection = "{d}"\n'
         'travel = {travel}\n')


def run_case(text, folder, quick=True):
    os.environ.setdefault("WIRENET_BUILD", str(lmp.BUILD))
    facts = api.run(api.load(text, quick=quick), str(folder), ranks=1)
    (folder / "case.json").write_text(json.dumps(facts, indent=2))
    return facts


def test_a_single_wire_breaks_at_its_breaking_load(tmp_path):
    """specimen = wire: the peak force is the single wire's breaking load, the largest stress of
    the wire's curve (materials.curve) times its area (2.7 mm: 565.85 MPa x 5.73 mm2 = 3240 N),
    at the curve's strain (elongation 0.30-0.35), and the wire then fails."""
    facts = run_case('kind = "tensile"\n[tensile]\nspecimen = "wire"\nquasi_static_check = '
                     'false\n', tmp_path / "wire")
    area = math.pi * MATERIALS["wire_d"] ** 2 / 4
    load = max(s for _, s in SW_CURVE) * area
    assert facts["peak_force"] == pytest.approx(load, rel=0.005), (facts["peak_force"], load)
    assert 0.25 <= facts["elongation_at_peak"] <= 0.36, facts["elongation_at_peak"]
    assert facts["failure"] is not None and facts["broken_bonds"] >= 1
    assert facts["strength_per_metre"] is None       # a wire has no width


@pytest.fixture(scope="module")
def strips(tmp_path_factory):
    folder = tmp_path_factory.mktemp("strips")
    along = run_case(STRIP.format(w=0.48, h=0.32, d="along", travel=0.05), folder / "along")
    # the slower twin only for the strip whose equilibrium is tested
    across = run_case(STRIP.format(w=0.32, h=0.48, d="across", travel=0.12) +
                      "quasi_static_check = false\n", folder / "across")
    return along, across


def test_a_strip_across_the_twists_is_softer_and_stretches_further(strips):
    """The same strip (0.48 m wide, 0.32 m between the clamps) pulled along the twists and
    across them: across, the hexagons open before a wire stretches, so the force at 2 % of
    the clamp distance is a small fraction of the force along, and the peak comes at a larger
    elongation."""
    along, across = strips
    assert along["width"] == across["width"] == pytest.approx(0.48)
    assert along["clamp_distance"] == across["clamp_distance"] == pytest.approx(0.32)
    f_along = along["forces_at"]["0.01"]
    f_across = across["forces_at"]["0.01"]
    assert f_along > 5 * max(f_across, 1.0), (f_along, f_across)
    assert across["elongation_at_peak"] > along["elongation_at_peak"]
    assert along["first_rupture"] is not None


def test_the_clamps_are_in_equilibrium_with_the_applied_force(strips):
    """The fixed clamp's reaction equals the force on the moving clamp within 1 % of the peak
    (quasi-static, before the first rupture), and the 4x slower twin's curve agrees."""
    along, _ = strips
    q = along["quasi_static"]
    assert q["equilibrium_error"] < 0.01, q
    assert q["curve_difference"] < 0.01, q


BAD = [
    ('[tensile]\ndirection = "diagonal"\n', "tensile.direction: must be one of along, across"),
    ('[tensile]\nspeed = -1.0\n', "tensile.speed: must be >= "),
    ('[tensile]\nspecimen = "chain"\n', "tensile.specimen: must be one of net, wire, rope"),
    ('[tensile]\nreport_at = "10 mm"\n', "tensile.report_at"),
    ('[tensile]\nstrength = 1\n', "tensile.strength"),
    ('[punch]\nspeed = 0.01\n', "punch.speed"),
]


def assert_refused(tmp_path, args, message):
    """`runner run ARGS` stops before anything runs: exit 2, one line holding ``message``, no
    output folder."""
    p = subprocess.run([sys.executable, "-P", "-m", "runner", "run", *args, "--out",
                        str(tmp_path / "out")], cwd=ROOT, capture_output=True, text=True,
                       env=dict(os.environ, PYTHONPATH=str(ROOT)), timeout=60)
    assert p.returncode == 2, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and message in lines[0], p.stderr
    assert not (tmp_path / "out").exists()


@pytest.mark.parametrize("section,message", BAD)
def test_bad_tensile_keys_get_one_line_and_exit_2(tmp_path, section, message):
    path = tmp_path / "bad.toml"
    path.write_text('kind = "tensile"\n' + section)
    assert_refused(tmp_path, [str(path)], message)


@pytest.mark.parametrize("args,message", [
    (["datasheet"], "datasheet needs a case file"),
    (["datasheet", "no_such.toml"], "no_such.toml: no such file"),
    (["datasheet", "inputs/cases/beam.toml"], "a data sheet needs a case with a net"),
    (["punch_hex", "extra.toml"], "one target only"),
])
def test_datasheet_mistakes_get_one_line_and_exit_2(tmp_path, args, message):
    assert_refused(tmp_path, args, message)


def test_the_datasheet_case_files_are_the_nets_tests(tmp_path):
    """The data sheet of a punch case file: a strip of its net along and across the twists
    (1 m wide, 0.5 m between the clamps, the roll's edge wire) and the standard punch, each
    with the net and materials the file states and nothing else of it; a rope net gets
    breakable ropes."""
    source = tmp_path / "my_net.toml"
    source.write_text('kind = "impact"\n[panel]\nnet = "hex"\nwidth = 4.0\nplacement = "wire"\n'
                      '[materials]\nwire_d = 0.0022\n[impact]\nmass = 60.0\n')
    paths, net = datasheet.case_files(str(source), str(tmp_path / "cases"))
    assert net == "hex"
    along, across, punch = (api.load(p) for p in paths)
    assert [c.kind for c in (along, across, punch)] == ["tensile", "tensile", "punch"]
    assert (along["panel.width"], along["panel.height"]) == (1.0, 0.5)
    assert (across["panel.width"], across["panel.height"]) == (0.5, 1.0)
    assert along["tensile.direction"] == "along" and across["tensile.direction"] == "across"
    for c in (along, across, punch):
        assert c["materials.wire_d"] == 0.0022 and c["panel.placement"] == "wire"
    assert along["panel.selvedge"] == across["panel.selvedge"] == "sides"
    assert punch["panel.width"] == 3.0 and punch["panel.selvedge"] == "loop"
    rope = tmp_path / "rope.toml"
    rope.write_text('kind = "punch"\n[panel]\nnet = "square"\n')
    paths, net = datasheet.case_files(str(rope), str(tmp_path / "rope"))
    assert net == "square"
    assert all(api.load(p)["materials.rope_strength"] for p in paths)


def test_the_punch_report_gives_the_datasheet_figures(tmp_path):
    """A punch case folder: the report's data-sheet table gives the punch resistance (the
    peak platter force in kN) and the travel at it, beside the nominal value of the mesh type
    with its source; a tensile case its strength in kN/m and elongations."""
    punch = tmp_path / "study" / "p"
    punch.mkdir(parents=True)
    (punch / "platter.csv").write_text("time,displacement,force\n0,0,0\n1,0.1,1000\n"
                                       "2,0.2,30000\n3,0.3,5000\n")
    (punch / "case.json").write_text(json.dumps({"kind": "punch", "status": "ok",
                                                 "panel": "hex"}))
    tensile = tmp_path / "study" / "t"
    tensile.mkdir()
    (tensile / "case.json").write_text(json.dumps({
        "kind": "tensile", "status": "ok", "panel": "square", "direction": "along",
        "width": 1.2, "clamp_distance": 1.2, "peak_force": 240e3, "displacement_at_peak": 0.12,
        "strength_per_metre": 200e3, "elongation_at_peak": 0.1,
        "failure": {"displacement": 0.13, "force": 1e3, "elongation": 0.108}}))
    report.build(str(tmp_path / "study"), figures=False)
    text = (tmp_path / "study" / "report.md").read_text()
    assert "## Data-sheet figures" in text
    assert "| p | hex | punch resistance | 30.0 kN | 23.6 kN" in text
    assert "| p | hex | platter travel at it | 0.200 m |" in text
    assert "| t | square | tensile strength along the twists | 200.0 kN/m | 230 kN/m" in text
    assert "| t | square | elongation at failure (along) | 10.8 % |" in text
    summary = json.loads((tmp_path / "study" / "summary.json").read_text())
    assert summary["cases"]["p"]["datasheet"] == {"punch_resistance": 30000.0,
                                                  "punch_displacement": 0.2}
    for (net, figure), (value, unit, mesh, source) in sheet.NOMINAL.items():
        assert source.startswith(("unverified:", "none:")) or "Table" in source, source


def test_the_report_plots_a_tensile_curve(tmp_path):
    """A tensile case folder gets its F(u) figure (force and the fixed clamp's reaction against
    the clamp's travel, the peak and the first rupture marked) in the report."""
    case = tmp_path / "study" / "strip"
    case.mkdir(parents=True)
    (case / "tensile.csv").write_text("time,displacement,force,reaction,broken\n"
                                      "0.1,0.001,100,99,0\n0.2,0.002,300,298,0\n"
                                      "0.3,0.003,50,49,1\n")
    (case / "case.json").write_text(json.dumps({
        "kind": "tensile", "status": "ok", "panel": "hex", "direction": "along",
        "strength_per_metre": 300.0, "first_rupture": {"displacement": 0.0025}}))
    summary = report.build(str(tmp_path / "study"))
    assert summary["figures"]["tensile_strip"] == ["figures/tensile_strip.png",
                                                   "figures/tensile_strip.svg"]
    assert (tmp_path / "study" / "figures" / "tensile_strip.png").stat().st_size > 1000
