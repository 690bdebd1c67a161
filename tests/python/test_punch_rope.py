"""Breakable ropes in a punch case (issue #17): the quick square cone punch with the rope
strength of materials.in ends by rope failure, and the rope's tension when the first rope bond
breaks is bounded by the strength criterion: F/A + |M| R/I >= SIGMA_T with F <= SIGMA_T A, so
the largest rope tension recorded before the break lies below SIGMA_T A (and the break does come
from tension, not from a rope far below it)."""

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

import lmp
from postprocess import casefolders
from runner import api
from runner.errors import RunError
from runner.kinds import punch
from runner.materials import MATERIALS, rope_strength

ROPE_STRENGTH = rope_strength()           # (SIGMA_T, TAU_C) of materials.in
ROPE_TEXT = 'kind = "punch"\n[panel]\nnet = "square"\n[punch]\nplatter = "cone"\n' \
    '[materials]\nrope_strength = true\n'


@pytest.fixture(scope="module")
def rope_case(tmp_path_factory):
    os.environ.setdefault("WIRENET_BUILD", str(lmp.BUILD))
    folder = tmp_path_factory.mktemp("punch_rope")
    facts = api.run(api.load(ROPE_TEXT, quick=True), str(folder), ranks=1)
    (folder / "case.json").write_text(json.dumps(facts, indent=2))
    return folder, facts


def test_the_punch_ends_by_rope_failure(rope_case):
    folder, facts = rope_case
    assert facts["rope_strength"] == list(ROPE_STRENGTH)
    assert facts["ended_by"] == "rope failure", facts["ended_by"]
    assert facts["first_rope_rupture"]["displacement"] > 0
    assert facts["first_rupture"]["bond"]["family"] == "rope"


def test_rope_tension_before_the_break_is_below_the_tensile_limit(rope_case):
    folder, facts = rope_case
    limit = ROPE_STRENGTH[0] * math.pi * MATERIALS["rope_d"] ** 2 / 4      # SIGMA_T A = 63 kN
    zone = casefolders.load_case(str(folder)).zone()["rope"]
    before = zone["displacement"] < facts["first_rope_rupture"]["displacement"]
    peak = float(np.max(zone["max"][before]))
    assert peak <= limit * 1.0001, (peak, limit)
    assert peak > 0.5 * limit, (peak, limit)     # the ropes were loaded near their strength


def test_stop_drop_ends_the_run_where_the_net_has_failed_and_changes_nothing_before(
        rope_case, tmp_path):
    """punch.stop_drop = 0.5: the same run, row for row and digit for digit, up to the first
    row after a rupture whose force is below half the peak so far; there it stops (the run
    without it goes on to the end of the travel)."""
    folder, facts = rope_case
    drop = api.run(api.load(ROPE_TEXT, quick=True, set=["punch.quasi_static_check=false",
                                                        "punch.stop_drop=0.5"]),
                   str(tmp_path), ranks=1)
    whole = (folder / "run" / "punch.csv").read_text().splitlines()
    part = (tmp_path / "run" / "punch.csv").read_text().splitlines()
    assert len(part) < len(whole) and whole[:len(part)] == part
    assert facts["ended_at_drop"] is None and facts["stop_drop"] == 0.0
    end = drop["ended_at_drop"]
    force = np.array([float(row.split(",")[2]) for row in part[1:]])
    broken = np.array([int(float(row.split(",")[6])) for row in part[1:]])
    assert end["peak_force"] == pytest.approx(force.max(), rel=1e-12)
    assert end["force"] == pytest.approx(force[-1], rel=1e-12, abs=1e-9)
    assert force[-1] < 0.5 * force.max() and broken[-1] > 0
    # no earlier row after a rupture was below half the peak before it
    peaks = np.maximum.accumulate(force)
    assert not np.any((force[:-1] < 0.5 * peaks[:-1]) & (broken[:-1] > 0))
    assert drop["first_rope_rupture"] == facts["first_rope_rupture"]


def test_the_drop_line_is_read_or_refused(tmp_path):
    (tmp_path / "log.lammps").write_text("run 10\n")
    assert punch.drop_end(str(tmp_path)) is None
    (tmp_path / "log.lammps").write_text(
        "punch: ended by the drop: force 4.5 N below 0.5 of the peak 10 N at 0.25 m\n")
    assert punch.drop_end(str(tmp_path)) == dict(displacement=0.25, force=4.5, peak_force=10.0)
    (tmp_path / "log.lammps").write_text("punch: ended by the drop: force x N\n")
    with pytest.raises(RunError, match="log.lammps: unreadable line 'punch: ended by"):
        punch.drop_end(str(tmp_path))


@pytest.mark.parametrize("strength,rope_end,drop,ended_by", [
    (True, {"displacement": 0.2}, {"force": 1.0}, "rope failure"),
    (True, None, None, "end of travel"),
    (False, None, {"force": 1.0}, "force drop"),       # a wire mesh that tore
    (False, None, None, "end of travel (ropes unbreakable)"),
])
def test_how_a_punch_ended(strength, rope_end, drop, ended_by):
    assert punch.ending(strength, rope_end, drop) == ended_by


CASE_A = '''kind = "punch"
title = "square cone punch"
[panel]
net = "square"
[punch]
platter = "cone"
quasi_static_check = false
'''
CASE_B = CASE_A.replace('title = "square cone punch"', 'title = "the same, breakable ropes"') \
    .replace("[punch]", "[materials]\nrope_strength = true\n[punch]\npreload_from = \"a\"")


def _wirenet_run(*args):
    return subprocess.run([sys.executable, "-P", "-m", "runner", "run", *args], cwd=lmp.ROOT,
                          capture_output=True, text=True,
                          env=dict(lmp.MPI_ENV, WIRENET_BUILD=str(lmp.BUILD),
                                   PYTHONPATH=str(lmp.ROOT), PATH="/usr/bin:/bin"))


def test_a_case_from_another_cases_preload_is_the_case_with_its_own(tmp_path):
    """punch.preload_from: in a study, the breakable-rope case starts from the other case's
    pre-loaded panel (its restart) instead of pre-loading its own; run alone it pre-loads its
    own. Both give the same punch.csv to the last digit (the ropes do not fail in the pre-load,
    and the restart carries the whole panel); the hand-over restart is removed afterwards, and
    the case's preload.csv is the source's record."""
    (tmp_path / "a.toml").write_text(CASE_A)
    (tmp_path / "b.toml").write_text(CASE_B)
    (tmp_path / "pair.toml").write_text('cases = ["a.toml", "b.toml"]\n')
    study = _wirenet_run(str(tmp_path / "pair.toml"), "--quick", "--np", "2",
                         "--out", str(tmp_path / "study"))
    assert study.returncode == 0, study.stderr
    alone = _wirenet_run(str(tmp_path / "b.toml"), "--quick", "--np", "1",
                         "--out", str(tmp_path / "alone"))
    assert alone.returncode == 0, alone.stderr
    shared, own = tmp_path / "study" / "b", tmp_path / "alone" / "b"
    assert "as left in" in (shared / "run" / "log.lammps").read_text()
    assert "as left in" not in (own / "run" / "log.lammps").read_text()
    table = (shared / "run" / "punch.csv").read_text()
    assert len(table.splitlines()) > 10
    assert table == (own / "run" / "punch.csv").read_text()
    assert (shared / "run" / "preload.csv").read_text() == \
        (tmp_path / "study" / "a" / "run" / "preload.csv").read_text()
    facts = json.loads((shared / "case.json").read_text())
    assert facts["preload_from"] == "a" and json.loads((own / "case.json").read_text())[
        "preload_from"] is None
    assert facts["preload"] == json.loads((own / "case.json").read_text())["preload"]
    assert not list((tmp_path / "study").glob("*/run/preload.restart"))


def test_preload_from_a_case_that_differs_before_the_punch_is_refused(tmp_path):
    (tmp_path / "a.toml").write_text(CASE_A)
    (tmp_path / "b.toml").write_text(CASE_B.replace("[punch]", "[damping]\nlocal = 0.5\n[punch]"))
    (tmp_path / "pair.toml").write_text('cases = ["a.toml", "b.toml"]\n')
    p = _wirenet_run(str(tmp_path / "pair.toml"), "--quick", "--out", str(tmp_path / "out"))
    assert p.returncode == 2
    assert "punch.preload_from: a has damping.local = 0.7" in p.stderr, p.stderr
    assert not (tmp_path / "out" / "b").exists()


def test_preload_from_a_panel_where_ropes_fail_at_once_is_refused(tmp_path):
    """Rope strength may differ from the source's (it acts only through failures), but a rope
    that fails at once on the shared panel would have failed in the case's own pre-load: the
    case stops with one line (runner/kinds/punch.check_preload_bonds)."""
    (tmp_path / "a.toml").write_text(CASE_A)
    (tmp_path / "b.toml").write_text(CASE_B.replace("rope_strength = true",
                                                    "rope_strength = true\nrope_sigma_t = 1e3"))
    (tmp_path / "pair.toml").write_text('cases = ["a.toml", "b.toml"]\n')
    p = _wirenet_run(str(tmp_path / "pair.toml"), "--quick", "--np", "2",
                     "--out", str(tmp_path / "out"))
    assert p.returncode != 0
    assert "bonds break at once on the pre-loaded panel of a" in p.stderr, p.stderr
    assert "Traceback" not in p.stderr
    assert json.loads((tmp_path / "out" / "b" / "case.json").read_text())["status"] == "failed"


CASE_C = CASE_B.replace('preload_from = "a"', 'preload_from = "b"')
REFUSED = [
    ("itself", {"b.toml": CASE_B.replace('preload_from = "a"', 'preload_from = "b"')},
     "punch.preload_from: names the case itself"),
    ("not a punch", {"a.toml": 'kind = "impact"\n[panel]\nnet = "square"\n'},
     "punch.preload_from: a is not a punch (kind = 'impact')"),
    ("a chain", {"c.toml": CASE_C}, "punch.preload_from: b starts from the pre-load of a; "
     "name that case instead"),
]


@pytest.mark.parametrize("files,message", [r[1:] for r in REFUSED], ids=[r[0] for r in REFUSED])
def test_a_bad_preload_source_is_refused_before_anything_runs(tmp_path, files, message):
    """The study checks punch.preload_from before any case runs: one line, exit 2, no folder."""
    cases = {"a.toml": CASE_A, "b.toml": CASE_B, **files}
    for name, text in cases.items():
        (tmp_path / name).write_text(text)
    (tmp_path / "all.toml").write_text(f"cases = {sorted(cases)!r}\n".replace("'", '"'))
    p = _wirenet_run(str(tmp_path / "all.toml"), "--quick", "--out", str(tmp_path / "out"))
    assert p.returncode == 2, p.stderr
    assert message in p.stderr, p.stderr
    assert len(p.stderr.strip().splitlines()) == 1
    assert not list((tmp_path / "out").glob("*/case.json"))


def test_a_source_outside_the_run_is_said_and_the_case_preloads_its_own(tmp_path):
    """A case run alone (or a misspelt source) pre-loads its own panel, and the run says so."""
    (tmp_path / "b.toml").write_text(CASE_B.replace('preload_from = "a"', 'preload_from = "ax"'))
    p = _wirenet_run(str(tmp_path / "b.toml"), "--quick", "--np", "1", "--out",
                     str(tmp_path / "out"))
    assert p.returncode == 0, p.stderr
    assert "b: punch.preload_from: ax is not in this run; the case pre-loads its own panel" \
        in p.stdout
    assert "as left in" not in (tmp_path / "out" / "b" / "run" / "log.lammps").read_text()
