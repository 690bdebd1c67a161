"""`./wirenet run --quick` end to end: every case folder, report.md and summary.json with the
contract's headers; every case of the study runs and ends ok (none is missing), and the claims
are judged under each dissipation model the records hold."""

import json
import subprocess
import sys

import lmp

HEADERS = {"beam.csv": "elements,load,tip_deflection,analytic_deflection,nrmse",
           "zone_forces.csv": "time,displacement,family,total_tension,max_tension,bonds",
           "platter.csv": "time,displacement,force",
           "block.csv": "time,x,y,z,vx,vy,vz,force"}


def run_study(out, *args):
    return subprocess.run([sys.executable, "-m", "runner", "run", *args, "--out", str(out)],
                          cwd=lmp.ROOT, capture_output=True, text=True,
                          env=dict(lmp.MPI_ENV, WIRENET_BUILD=str(lmp.BUILD), PATH="/usr/bin:/bin"))


def test_quick_study_end_to_end(tmp_path):
    out = tmp_path / "study"
    p = run_study(out, "--quick")
    assert p.returncode == 0, p.stderr
    assert "[case 1/15] beam" in p.stdout
    summary = json.loads((out / "summary.json").read_text())
    assert (out / "report.md").is_file()
    assert len(summary["cases"]) == 15 and summary["missing"] == []
    for name, case in summary["cases"].items():
        folder = out / name
        meta = json.loads((folder / "case.json").read_text())
        assert meta["status"] == "ok", (name, meta.get("error"))
        # the CPU time of its LIGGGHTS processes (all ranks): some, and no more than its
        # ranks could spend in its wall time
        assert 0 < meta["cpu_time"] <= meta["wall_time"] * meta["np"] * 1.05 + 0.5, name
        csvs = [f for f in HEADERS if (folder / f).is_file()]
        assert csvs, name
        for f in csvs:
            assert (folder / f).read_text().splitlines()[0] == HEADERS[f]
    assert summary["cases"]["beam"]["status"] == "ok"
    # the impacts ran under the physical model (impact_*) and the paper's local damping
    # (impact_*_paper): the claims are judged under each model, "claims" are the first's
    assert list(summary["claims_by_model"]) == ["physical", "local"]
    assert summary["claims"] == summary["claims_by_model"]["physical"]
    assert [c["id"] for c in summary["claims"]] == [1, 2, 3]
    assert "core-seconds" in (out / "report.md").read_text()
    # a second run in the same mode resumes: the finished case is skipped
    p = run_study(out, "beam", "--quick")
    assert p.returncode == 0 and "complete, skipped" in p.stdout


def test_unknown_case_is_a_clear_error(tmp_path):
    p = run_study(tmp_path / "x", "no_such_case")
    assert p.returncode == 2
    assert "unknown study or case 'no_such_case'" in p.stderr
    assert not (tmp_path / "x").exists()
