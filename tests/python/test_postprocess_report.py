"""postprocess plot / report on small synthetic case folders: files, numbers and the claims.
The claims are judged on the cases their records say they are (case.json: kind, panel, block,
dissipation; postprocess/claims.py), under each dissipation model the records hold; the folder
names only label them."""

import json
import sys
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from postprocess.__main__ import main  # noqa: E402
from postprocess import claims as claims_module  # noqa: E402
from postprocess import report as report_module  # noqa: E402
from test_figure4 import make_case, write_series  # noqa: E402

FIGURES = ("fig1_beam", "fig2_calibration", "fig3_punch", "fig5_impact_hex",
           "fig6_impact_square")
TIMES = (0.0, 0.1, 0.2)


def write_zone(folder, peaks):
    """zone_forces.csv whose family rises to (peak total, peak max) at t = 0.1 and falls."""
    folder.mkdir(parents=True, exist_ok=True)
    lines = ["time,displacement,family,total_tension,max_tension,bonds"]
    for i, time in enumerate(TIMES):
        factor = (0.0, 1.0, 0.5)[i]
        for family, (total, largest) in peaks.items():
            lines.append(f"{time},{time / 10},{family},{total * factor},{largest * factor},7")
    (folder / "zone_forces.csv").write_text("\n".join(lines) + "\n")


def write_csv(path, header, rows):
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(header + "\n" + "".join(",".join(map(str, r)) + "\n" for r in rows))


# what each case's record says it is (the facts the claims match cases by)
BLOCK = {"mass": 44.5, "speed": 10.0, "point": [0.0, 0.0]}
FACTS = {"punch_hex": {"kind": "punch", "panel": "hex", "platter": "spheroid"},
         "punch_compound": {"kind": "punch", "panel": "compound", "platter": "spheroid"},
         "impact_hex": {"kind": "impact", "panel": "hex", "block": BLOCK, "dissipation": "local"},
         "impact_compound": {"kind": "impact", "panel": "compound", "block": BLOCK,
                             "dissipation": "local"},
         "impact_square": {"kind": "impact", "panel": "square", "block": BLOCK,
                           "dissipation": "local"}}
STUDY = ("beam", "calib_0", "calib_0.05", "punch_hex", "punch_compound", "impact_hex",
         "impact_square", "impact_compound")


def set_meta(folder, **fields):
    """Add fields to a case folder's case.json (made if absent)."""
    path = folder / "case.json"
    meta = json.loads(path.read_text()) if path.is_file() else {}
    meta.update(fields)
    folder.mkdir(parents=True, exist_ok=True)
    path.write_text(json.dumps(meta))


def make_study(root, hex_peaks=None, rope=(4e5, 9e3), square_rope=(5e5, 1e4), skip=()):
    """A study folder in which all three claims hold unless the peaks say otherwise."""
    hex_peaks = hex_peaks or {}
    default = {"DT": (1000.0, 120.0), "SW": (3000.0, 80.0)}
    for name in ("punch_hex", "punch_compound", "impact_hex", "impact_compound"):
        if name in skip:
            continue
        peaks = dict(hex_peaks.get(name, default))
        if name.endswith("compound"):
            peaks["rope"] = rope
        write_zone(root / name, peaks)
    if "impact_square" not in skip:
        write_zone(root / "impact_square", {"rope": square_rope})
    for name in ("punch_hex", "punch_compound"):
        if name not in skip:
            write_csv(root / name / "platter.csv", "time,displacement,force",
                      [(0, 0, 0), (10, 0.1, 2.5e5), (20, 0.2, -3e5)])
    for name in ("impact_hex", "impact_compound", "impact_square"):
        if name not in skip:
            write_csv(root / name / "block.csv", "time,x,y,z,vx,vy,vz,force",
                      [(0, 0, 0, 1, 0, 0, -10, 0), (0.1, 0, 0, 0, 0, 0, 0, 7.5e5)])
    for name, facts in FACTS.items():
        if name not in skip:
            set_meta(root / name, status="ok", **facts)
    if "impact_hex" not in skip:
        set_meta(root / "impact_hex", **
            {"wall_time": 12.5, "first_rupture": 0.031, "edge_force_peak": 2.5e5,
             "status": "ok"})
    if "punch_hex" not in skip:
        set_meta(root / "punch_hex", **
            {"status": "ok", "wall_time": 900.0,
             "first_rupture": {"displacement": 0.3, "force": 2.5e5, "step": 1200,
                               "bond": {"atom1": 17, "atom2": 18, "type": 1, "family": "DT"}},
             "quasi_static": {"slow_factor": 4, "curve_difference": 0.0043,
                              "compared_up_to": 0.123, "kinetic_energy_fraction": 0.00053,
                              "equilibrium_error": 0.00079,
                              "equilibrium_error_of_current": 0.0051,
                              "equilibrium_holds_from": 0.12,
                              "snap_events": [], "passed": True}})
    if "calibration" not in skip:
        for fraction in ("0", "0.05"):
            write_csv(root / f"calib_{fraction}" / "platter.csv", "time,displacement,force",
                      [(0, 0, 0), (1, 0.1, 1e4 * (1 + float(fraction)))])
        for fraction in ("0", "0.05"):
            set_meta(root / f"calib_{fraction}", status="ok", kind="calibration", panel="square",
                     platter="cone", bending=float(fraction))
    if "beam" not in skip:
        write_csv(root / "beam" / "beam.csv", "elements,load,tip_deflection,"
                  "analytic_deflection,nrmse",
                  [(5, 10, 0.0101, 0.01, 0.02), (11, 10, 0.01004, 0.01, 0.005),
                   (21, 10, 0.01001, 0.01, 0.001)])
        write_csv(root / "beam" / "deflection.csv", "elements,x,deflection,analytic_deflection",
                  [(5, 0, 0, 0), (5, 1, 0.004, 0.0039), (5, 2, 0.0101, 0.01)])
    return root


def report(root, figures=False, expect=()):
    args = ["report", str(root)] + ([] if figures else ["--no-figures"]) + \
        (["--expect", *expect] if expect else [])
    assert main(args) == 0
    summary = json.loads((root / "summary.json").read_text())
    return summary, (root / "report.md").read_text()


def assert_drawn(png):
    """A PNG with a picture in it, not only a valid signature: decodable, not blank (pixel
    spread), with ink on a fair part of the page and some colour (the curves)."""
    from matplotlib import image
    assert png.read_bytes()[:8] == b"\x89PNG\r\n\x1a\n"
    pixels = image.imread(str(png))[..., :3]
    assert pixels.shape[0] > 300 and pixels.shape[1] > 300, pixels.shape
    assert pixels.std() > 0.05, f"{png}: blank"
    assert np.mean(pixels.min(axis=2) < 0.9) > 0.01, f"{png}: almost no ink"
    colour = pixels.max(axis=2) - pixels.min(axis=2) > 0.3
    assert colour.sum() > 500, f"{png}: no coloured curve"


def verdicts(summary):
    return [(c["verdict"], c["supported"]) for c in summary["claims"]]


def test_full_report_with_figures(tmp_path):
    summary, text = report(make_study(tmp_path), figures=True)
    for name in FIGURES:
        for ext in ("png", "svg"):
            path = tmp_path / "figures" / f"{name}.{ext}"
            assert path.stat().st_size > 1000, path
        assert_drawn(tmp_path / "figures" / f"{name}.png")
        assert "<svg" in (tmp_path / "figures" / f"{name}.svg").read_text()[:2000]
        assert f"![{name}](figures/{name}.png)" in text
    assert verdicts(summary) == [("supported", True)] * 3
    assert summary["missing"] == [] and "not_implemented" not in summary
    assert list(summary["claims_by_model"]) == ["local"]
    assert summary["claims"] == summary["claims_by_model"]["local"]
    hexcase = summary["cases"]["impact_hex"]
    assert (hexcase["wall_time"], hexcase["first_rupture"], hexcase["edge_force_peak"]) == (
        12.5, 0.031, 2.5e5)
    assert hexcase["peak_block_force"] == 7.5e5
    assert summary["cases"]["punch_hex"]["peak_platter_force"] == 3e5
    assert summary["cases"]["punch_hex"]["peak_block_force"] is None
    assert summary["cases"]["impact_compound"]["zone"]["rope"] == {
        "peak_total_tension": 4e5, "time_of_peak_total": 0.1, "displacement_of_peak_total": 0.01,
        "peak_max_tension": 9e3, "time_of_peak_max": 0.1, "displacement_of_peak_max": 0.01}
    assert summary["cases"]["beam"]["beam_max_nrmse"] == 0.02
    assert summary["cases"]["calib_0.05"]["kind"] == "calibration"
    assert "| impact_hex | impact | unknown | ok | n/a | 750 | 0.031 s | 250 | 12.5 |" in text
    assert ("| punch_hex | punch | unknown | ok | 300 | n/a | 0.3 m, 250 kN, DT bond 17-18 | n/a "
            "| 900 |") in text
    assert "| impact_square | rope | 500 | 0.1 s | 10 | 0.1 s |" in text
    assert ("| punch_hex | 4 | 0.43 % | 0.123 | 0.053 % | 0.079 % (0.51 %) | 0.12 | 0 | True |"
            in text)
    assert summary["cases"]["punch_hex"]["quasi_static"]["curve_difference"] == 0.0043
    # punch peaks are placed by platter travel, not by time
    assert "| punch_hex | DT | 1 | 0.01 m | 0.12 | 0.01 m |" in text
    assert "   - punch_hex: DT 0.12 kN vs SW 0.08 kN -> holds" in text
    assert text.count("**supported**") == 3


def test_claim_1_false(tmp_path):
    flipped = {"punch_compound": {"DT": (1000.0, 70.0), "SW": (3000.0, 80.0)}}
    summary, text = report(make_study(tmp_path, hex_peaks=flipped))
    assert verdicts(summary) == [("not supported", False), ("supported", True),
                                 ("supported", True)]
    evidence = summary["claims"][0]["evidence"]
    assert {e["case"]: e["holds"] for e in evidence} == {
        "punch_hex": True, "punch_compound": False, "impact_hex": True,
        "impact_compound": True}
    assert len(evidence) == 4
    assert "   - punch_compound: DT 0.07 kN vs SW 0.08 kN -> does not hold" in text


def test_claim_2_false(tmp_path):
    flipped = {"impact_hex": {"DT": (4000.0, 120.0), "SW": (3000.0, 80.0)}}
    summary, _ = report(make_study(tmp_path, hex_peaks=flipped))
    assert verdicts(summary) == [("supported", True), ("not supported", False),
                                 ("supported", True)]


def test_claim_3_false(tmp_path):
    summary, text = report(make_study(tmp_path, rope=(6e5, 9e3)))
    assert verdicts(summary)[2] == ("not supported", False)
    assert summary["claims"][2]["evidence"][0]["compound_peak_total"] == 6e5
    assert summary["claims"][2]["evidence"][0]["square_peak_total"] == 5e5
    assert "**not supported**" in text


def test_missing_cases_not_evaluated(tmp_path):
    """Claims 1 and 2 rest on the one punch with the double twist left; claim 3 has no pair of
    impacts; the missing cases are those the study expected (--expect), in its order."""
    skip = ("punch_compound", "impact_hex", "impact_compound", "impact_square", "beam",
            "calibration")
    summary, text = report(make_study(tmp_path, skip=skip), expect=STUDY)
    not_evaluated = claims_module.NOT_EVALUATED
    assert verdicts(summary) == [("supported", True), ("supported", True),
                                 (not_evaluated, None)]
    assert [e["case"] for e in summary["claims"][0]["evidence"]] == ["punch_hex"]
    assert summary["missing"] == ["beam", "calib_0", "calib_0.05", "punch_compound",
                                  "impact_hex", "impact_square", "impact_compound"]
    assert "- impact_square: missing" in text
    assert f"**{not_evaluated}**" in text
    # without the study's list nothing is missing: the folder holds what it holds
    summary, _ = report(tmp_path)
    assert summary["missing"] == []


def test_empty_study_evaluates_nothing(tmp_path):
    summary, text = report(tmp_path)
    assert summary["claims"] == [] and summary["claims_by_model"] == {}
    assert summary["cases"] == {}
    assert "No figures." in text or "## Figures" in text


def test_a_case_that_did_not_end_ok_is_listed_and_not_used(tmp_path):
    """A failed case (postprocess/record.py's statuses) is listed with its status and error and
    never used for a claim: without the square impact claim 3 has no pair."""
    make_study(tmp_path, skip=("impact_square",))
    set_meta(tmp_path / "impact_square", status="failed", error="LIGGGHTS failed: ERROR: x",
             **FACTS["impact_square"])
    write_zone(tmp_path / "impact_square", {"rope": (1.0, 1.0)})
    summary, text = report(tmp_path)
    assert verdicts(summary)[2] == (claims_module.NOT_EVALUATED, None)
    assert summary["claims"][2]["evidence"] == []
    assert "- impact_square: status failed: LIGGGHTS failed: ERROR: x" in text
    assert "| impact_square | impact | unknown | failed |" in text


def test_claims_follow_the_records_not_the_folder_names(tmp_path):
    """The same study under other folder names gives the same verdicts; a folder named
    impact_square whose record says it is a hexagonal panel is no square panel for claim 3."""
    import shutil
    make_study(tmp_path / "named")
    for k, name in enumerate(sorted(FACTS)):
        shutil.copytree(tmp_path / "named" / name, tmp_path / "renamed" / f"case{k}")
    summary, _ = report(tmp_path / "renamed")
    assert verdicts(summary) == [("supported", True)] * 3
    assert len(summary["claims"][2]["evidence"]) == 1
    set_meta(tmp_path / "named" / "impact_square", panel="hex")
    summary, _ = report(tmp_path / "named")
    assert verdicts(summary)[2] == (claims_module.NOT_EVALUATED, None)


def test_claims_are_judged_under_each_dissipation_model(tmp_path):
    """Impacts under bond damping (case.json dissipation 'bond') beside the local-damping ones:
    each model's impacts are compared among themselves. Here the bond-damped compound panel
    carries more rope tension than the bond-damped square one: claim 3 holds under local damping
    and not under bond damping; "claims" are the first model's (local)."""
    make_study(tmp_path)
    for net, rope in (("compound", (6e5, 9e3)), ("square", (5e5, 1e4))):
        folder = tmp_path / f"impact_{net}_bonddamp"
        peaks = {"rope": rope} if net == "square" else {
            "DT": (1000.0, 120.0), "SW": (3000.0, 80.0), "rope": rope}
        write_zone(folder, peaks)
        write_csv(folder / "block.csv", "time,x,y,z,vx,vy,vz,force",
                  [(0, 0, 0, 1, 0, 0, -10, 0), (0.1, 0, 0, 0, 0, 0, 0, 7.5e5)])
        set_meta(folder, **dict(FACTS[f"impact_{net}"], status="ok", dissipation="bond"))
    summary, text = report(tmp_path)
    by_model = summary["claims_by_model"]
    assert list(by_model) == ["local", "bond"]
    assert summary["claims"] == by_model["local"]
    assert [(c["verdict"], c["supported"]) for c in by_model["local"]] == [("supported", True)] * 3
    assert (by_model["bond"][2]["verdict"], by_model["bond"][2]["supported"]) == \
        ("not supported", False)
    assert by_model["bond"][2]["evidence"][0]["compound"] == "impact_compound_bonddamp"
    assert by_model["bond"][2]["evidence"][0]["square"] == "impact_square_bonddamp"
    # claims 1 and 2 under bond damping: the punches and the bond-damped compound impact
    assert {e["case"] for e in by_model["bond"][0]["evidence"]} == {
        "punch_hex", "punch_compound", "impact_compound_bonddamp"}
    assert f"## The paper's claims under {claims_module.MODELS['bond']}" in text
    assert f"## The paper's claims under {claims_module.MODELS['local']}" in text


def test_unreadable_case_is_reported_not_used(tmp_path):
    make_study(tmp_path)
    (tmp_path / "impact_square" / "zone_forces.csv").write_text(
        "time,displacement,family,total_tension,max_tension,bonds\n0,0,rope,1\n")
    summary, text = report(tmp_path)
    assert verdicts(summary)[2] == (claims_module.NOT_EVALUATED, None)
    errors = summary["cases"]["impact_square"]["errors"]
    assert len(errors) == 1 and errors[0].endswith("zone_forces.csv:2: expected 6 columns, got 4")
    assert "unreadable" in text


def test_plot_subcommands(tmp_path):
    make_study(tmp_path)
    out = tmp_path / "plots"
    assert main(["plot", "beam", str(tmp_path / "beam" / "beam.csv"), "--line",
                 str(tmp_path / "beam" / "deflection.csv"), "-o", str(out / "beam")]) == 0
    assert main(["plot", "calibration", str(tmp_path / "calib_0" / "platter.csv"),
                 str(tmp_path / "calib_0.05" / "platter.csv"), "-o", str(out / "calib")]) == 0
    assert main(["plot", "zone", str(tmp_path / "punch_hex" / "zone_forces.csv"),
                 str(tmp_path / "punch_compound" / "zone_forces.csv"), "--x", "displacement",
                 "--families", "DT", "SW", "--labels", "hex", "compound",
                 "-o", str(out / "punch")]) == 0
    for name in ("beam", "calib", "punch"):
        assert_drawn(out / f"{name}.png")
        assert (out / f"{name}.svg").stat().st_size > 1000


def test_plot_labels_count_mismatch(tmp_path, capsys):
    make_study(tmp_path, skip=("beam",))
    code = main(["plot", "zone", str(tmp_path / "punch_hex" / "zone_forces.csv"), "--labels",
                 "a", "b", "-o", str(tmp_path / "x")])
    assert code == 2
    assert capsys.readouterr().err == "postprocess plot: error: --labels: 2 labels for 1 files\n"
    assert not list(tmp_path.glob("x.*"))


def test_calibration_difference_panel_is_the_relative_force_gap():
    """Panel (b) of Figure 2: a curve 10 % above the reference on another displacement grid
    reads 10 % wherever the reference force is above the floor, and nothing below it."""
    import numpy as np
    from postprocess.plots import relative_to_first
    x_ref = np.linspace(0.0, 0.5, 51)
    x_other = np.linspace(0.0, 0.5, 201)
    reference = ("0", x_ref, 1e6 * x_ref ** 2)
    stiffer = ("1", x_other, 1.1e6 * x_other ** 2)
    (label, x, percent), = relative_to_first([reference, stiffer], floor=0.01)
    assert label == "1"
    assert x[0] >= 0.05 - 1e-12 and x[-1] == 0.5
    assert np.allclose(percent, 10.0, atol=0.05)
    # an empty curve (a case that wrote no rows yet) is left out, not a crash
    empty = ("0.5", np.array([]), np.array([]))
    assert [r[0] for r in relative_to_first([reference, empty, stiffer])] == ["1"]
    assert relative_to_first([empty, stiffer]) == []


def test_first_rupture_marker_position():
    from postprocess.plots import first_rupture_at
    punch_record = {"displacement": 0.42, "force": 2.3e4, "bond": {"family": "DT"}}
    assert first_rupture_at(punch_record, "displacement") == 0.42
    assert first_rupture_at(punch_record, "time") is None
    assert first_rupture_at(0.031, "time") == 0.031          # impact: a time
    assert first_rupture_at(0.031, "displacement") is None
    assert first_rupture_at(None, "time") is None


def test_quick_cases_are_named_in_the_table_and_the_verdicts(tmp_path):
    """A verdict drawn from --quick cases says so; the table names each case's mode. Claim 3
    compares impacts of the same mode (a quick square panel is no match for a full compound
    one): the quick pair makes it, with the note."""
    root = make_study(tmp_path)
    set_meta(root / "impact_square", status="ok", quick=True)
    set_meta(root / "impact_compound", status="ok", quick=True)
    set_meta(root / "impact_hex", status="ok", quick=False)
    summary, text = report(root)
    assert summary["cases"]["impact_square"]["mode"] == "quick"
    assert summary["cases"]["impact_hex"]["mode"] == "full"
    assert "| impact_square | impact | quick | ok |" in text
    assert "| impact_hex | impact | full | ok |" in text
    assert summary["claims"][2]["verdict"] == "supported" + claims_module.QUICK_NOTE
    # claims 1 and 2 rest on every case with the double twist, the quick compound impact among
    # them: they say so as well; without it (the full hex impact and the punches) they do not
    assert [c["verdict"] for c in summary["claims"][:2]] == \
        ["supported" + claims_module.QUICK_NOTE] * 2
    set_meta(root / "impact_compound", status="ok", quick=False)
    summary, _ = report(root)
    assert [c["verdict"] for c in summary["claims"][:2]] == ["supported", "supported"]


def test_report_shows_figure4_for_each_case_with_a_series(tmp_path):
    """Figure 4 (the deformed net at the peak) of every punch / impact case whose folder holds its
    ParaView series, in figures/ and in report.md, drawn (not blank)."""
    for name in ("impact_hex", "punch_hex"):
        write_series(make_case(tmp_path, name, "impact" if name.startswith("impact") else "punch"))
    summary, text = report(make_study(tmp_path), figures=True)
    for name in ("fig4_impact_hex", "fig4_punch_hex"):
        assert_drawn(tmp_path / "figures" / f"{name}.png")
        assert f"![{name}](figures/{name}.png)" in text
        assert summary["figures"][name] == [f"figures/{name}.png", f"figures/{name}.svg"]
    assert "`impact_hex/impact_hex.pvd` (net)" in text
    # cases without a series (impact_square, impact_compound, ...) get no Figure 4
    assert "fig4_impact_square" not in summary["figures"]


def test_report_says_where_the_bending_fraction_came_from(tmp_path):
    """Each case with ropes shows its bending fraction and its source (the calibration fit or
    the paper's value); a hexagonal panel has no ropes and no line."""
    root = make_study(tmp_path)
    (root / "punch_compound" / "case.json").write_text(json.dumps(
        {"status": "ok", "panel": "compound", "bending": 0.0123,
         "bending_source": "calibrated (out/calibration.json)"}))
    (root / "impact_compound" / "case.json").write_text(json.dumps(
        {"status": "ok", "panel": "compound", "bending": 0.05,
         "bending_source": "the paper's calibrated value (no calibration.json in the study folder)"}))
    (root / "punch_hex" / "case.json").write_text(json.dumps(
        {"status": "ok", "panel": "hex", "bending": 0.05, "bending_source": "case file"}))
    report(root)
    text = (root / "report.md").read_text()
    assert "- punch_compound: 0.0123 (calibrated (out/calibration.json))" in text
    assert "- impact_compound: 0.05 (the paper's calibrated value (no calibration.json" in text
    block = text.split("Bending fraction of the rope beams")[1].split("\n## ")[0]
    assert "- punch_compound" in block and "- punch_hex" not in block


def test_report_sums_the_cases_wall_times(tmp_path):
    root = make_study(tmp_path)     # punch_hex 900 s and impact_hex 12.5 s in their case.json
    _, text = report(root)
    assert "Wall time of the cases: 912 s (15.2 min) over 2 case(s)" in text


def test_fence_energy_per_component_row():
    """The report's energy-per-component row: the components' tallies and the budget's other
    terms in kJ (damping = local + bond damping, contacts = block + layers + ground); a case.json
    from before the tallies has no row."""
    parts = {c: {"plastic": 1e3 * k, "released": 0.0, "elastic_peak": 2e3 * k}
             for k, c in enumerate(("net", "ropes", "brakes", "posts"), 1)}
    final = {"friction": 4e3, "damping": 1e4, "bond_damping": 500.0, "contact": 300.0,
             "contact_layers": 200.0, "ground": 0.0, "ke_block": 1e3, "ke_net": 0.0}
    facts = {"block_energy": 5e5, "components": parts, "energy_final": final}
    row = report_module._component_row("fence_x", facts)
    assert row == ["fence_x", "500", "1", "0", "2", "4", "0", "3", "8", "4", "10.5", "0.5", "1"]
    assert report_module._component_row("old", {"block_energy": 5e5, "energy_final": final}) is None


def test_fence_rest_settled():
    """A residual height after a rest that ended at its time limit with the ropes moving is
    marked; one below the energy limit or with the ropes still is not; no rest: None."""
    from postprocess import summary as summary_module
    settled = summary_module._rest_settled
    assert settled({"reached": False, "still": False}) is False
    assert settled({"reached": False, "still": True}) is True
    assert settled({"reached": True}) is True
    assert settled(None) is None

    mark = report_module._residual_mark
    assert mark({"residual_height_at": "end of impact"}) == " (end)"
    assert mark({"residual_height_at": "end of impact", "rest_skipped": True}) == " (end: block went on)"
    assert mark({"residual_height_at": "rest", "rest_settled": False}) == " (ropes still moving)"
    assert mark({"residual_height_at": "rest", "rest_settled": True}) == ""


def test_fence_comparison_pairs_fences_of_one_dissipation_model():
    """The post-load claim at fence scale compares a compound and a square fence hit by the
    same block under the same dissipation model (as the claims do, postprocess/claims.py): a
    compound fence under the physical model is no match for a square one under local damping."""
    def fence(net, model, base):
        return {"kind": "fence", "status": "ok", "mode": "quick", "dissipation": model,
                "fence": {"net": net, "block_energy": 1250.0, "post_base_peak": base,
                          "anchor_peak": 2.0 * base, "dissipation": model}}
    summaries = {"fence_compound": fence("compound", "physical", 1.0),
                 "fence_square_local": fence("square", "local", 4.0)}
    assert report_module.fence_comparison(summaries) is None
    summaries["fence_square"] = fence("square", "physical", 2.0)
    comparison = report_module.fence_comparison(summaries)
    assert (comparison["compound"], comparison["square"]) == ("fence_compound", "fence_square")
    assert comparison["post_base_ratio"] == 0.5


def test_bending_sensitivity_states_the_spread_not_a_calibration():
    """Issue #45: the cone punches at several fractions are a sensitivity study (no measured curve
    to fit): the report gives the peaks' spread from the calibration cases that ended ok."""
    def cone(bending, peak, status="ok"):
        return {"kind": "calibration", "status": status, "mode": "full", "bending": bending,
                "peak_platter_force": peak}
    summaries = {"c0": cone(0.0, 627e3), "c1": cone(1.0, 631e3), "c05": cone(0.05, 628e3),
                 "broken": cone(0.25, 10.0, status="failed")}
    found = report_module.bending_sensitivity(summaries)
    assert found["fractions"] == (0.0, 1.0) and found["peaks"] == (627e3, 631e3)
    assert found["spread"] == pytest.approx(4e3 / 627e3)
    assert report_module.bending_sensitivity({"c0": cone(0.0, 627e3)}) is None
    text = "\n".join(report_module._bending_sensitivity_lines(summaries))
    assert "not a calibration" in text and "0.638 %" in text


def test_cases_are_listed_in_natural_order():
    """Issue #42: a speed sweep's cases in the report read v6, v10, v20, not v10, v20, v6."""
    from postprocess.casefolders import natural_key
    names = ["speed_v10", "speed_v6", "calibration_0.25", "calibration_0.05", "speed_v20",
             "calibration_1", "impact_hex_paper", "impact_hex"]
    assert sorted(names, key=natural_key) == [
        "calibration_0.05", "calibration_0.25", "calibration_1", "impact_hex", "impact_hex_paper",
        "speed_v6", "speed_v10", "speed_v20"]


def test_panel_post_load_compares_edge_and_summed_loads_per_model():
    """The paper's post-load conclusion at panel scale (issue #45): per dissipation model, the
    compound panel's largest edge load and summed support load over the square panel's, from
    the impacts that differ only in their net; a group without both nets gives no row."""
    def impact(net, model, side, total, mass=44.5):
        return {"kind": "impact", "status": "ok", "errors": [], "zone": {"rope": {}},
                "panel": net, "dissipation": model, "mode": "full",
                "block": {"mass": mass, "speed": 10.0, "point": [0.0, 0.0]},
                "impact": {"side_force_peak": side, "edge_force_peak": total}}
    summaries = {"c": impact("compound", "physical", 174.8e3, 66.3e3),
                 "s": impact("square", "physical", 144.6e3, 64.0e3),
                 "cp": impact("compound", "local", 80e3, 7e3),
                 "sp": impact("square", "local", 100e3, 10e3),
                 "lonely": impact("compound", "physical", 1.0, 1.0, mass=60.0)}
    rows = report_module.panel_post_load_rows(summaries)
    assert [(r["model"], r["compound"], r["square"]) for r in rows] == [
        ("physical", "c", "s"), ("local", "cp", "sp")]
    assert rows[0]["side_force_peak"] == (174.8e3, 144.6e3, pytest.approx(174.8 / 144.6))
    assert rows[1]["edge_force_peak"][2] == pytest.approx(0.7)
    text = "\n".join(report_module._post_load_lines(rows))
    assert "| 174.8 | 144.6 | 1.209 |" in text
