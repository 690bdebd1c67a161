"""Progress lines of a running deck (runner.engine.Progress) from a log being written."""

import sys
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from runner import engine  # noqa: E402
from runner.engine import Progress  # noqa: E402

THERMO = "Step Atoms KinEng\n"


def test_preparation_phase_is_not_counted_and_lines_only_on_new_steps(tmp_path, capsys,
                                                                      monkeypatch):
    clock = [1000.0]
    monkeypatch.setattr(engine.time, "time", lambda: clock[0])
    log = tmp_path / "log.lammps"
    log.write_text(THERMO + "5000 10 0.1\n9000 10 0.2\n")
    progress = Progress(log, total=1000, label="run", dt=0.5, phase_marker="pre-load: done")
    progress.report()
    progress.report()                        # same step: no second line
    log.write_text(log.read_text() + "pre-load: done\n" + THERMO + "0 10 0\n250 10 0.1\n")
    progress.report()
    clock[0] += 60.0
    log.write_text(log.read_text() + "500 10 0.2\n")
    progress.report()
    lines = capsys.readouterr().err.splitlines()
    assert lines[0].strip() == "run: preparing (step 9000)"
    assert len(lines) == 3
    # the pre-load's step 9000 must not count against the punch's 1000 steps; no rate yet
    assert lines[1].strip() == "run: step 250/1000 (25 %, t = 125 s), ETA n/a"
    # the rate comes from the steps done since the phase began: 250 more take as long again
    assert lines[2].strip() == "run: step 500/1000 (50 %, t = 250 s), ETA 120 s"


def test_without_marker_every_step_counts(tmp_path, capsys):
    log = tmp_path / "log.lammps"
    log.write_text(THERMO + "100 10 0.1\n")
    Progress(log, total=400, label="impact", dt=None).report()
    assert capsys.readouterr().err.strip().startswith("impact: step 100/400 (25 %), ETA")


def test_steps_beyond_the_count_belong_to_the_following_phase(tmp_path, capsys):
    """A fence impact of 400 steps, then a rest of at most 200 (it ends when the motion has
    died down): step 450 is the rest's 50th, not 112 % of the impact."""
    log = tmp_path / "log.lammps"
    log.write_text(THERMO + "450 10 0.1\n")
    Progress(log, total=400, label="fence", dt=0.01, then=("rest", 200)).report()
    assert capsys.readouterr().err.strip() == "fence: rest: step 50/200 at most, t = 4.5 s"


def test_a_named_preparation_phase_counts_its_steps_against_its_most(tmp_path, capsys):
    """A fence that settles (at most 3000 steps, it ends once still) before its block is
    released: the settling by name and its count, not 'preparing'."""
    log = tmp_path / "log.lammps"
    log.write_text(THERMO + "1200 10 0.1\n")
    Progress(log, total=400, label="fence", dt=0.01, phase_marker="impact: block released",
             before=("settling", 3000)).report()
    assert capsys.readouterr().err.strip() == "fence: settling: step 1200/3000 at most"


def test_a_deck_that_stops_before_its_end_marker_is_not_complete(tmp_path):
    """LIGGGHTS ends early and exits 0 when killed from outside (a forced restart); a deck that
    prints the end marker as its last line must have printed it, or the run is an error."""
    import pytest
    from runner.errors import RunError
    early = tmp_path / "early.in"
    early.write_text(f'print "start"\njump SELF skip\nprint "{engine.END_MARKER}"\n'
                     'label skip\n')
    with pytest.raises(RunError, match="stopped before the end of early.in"):
        engine.run(early, tmp_path / "a")
    whole = tmp_path / "whole.in"
    whole.write_text(f'print "start"\nprint "{engine.END_MARKER}"\n')
    engine.run(whole, tmp_path / "b")


def test_a_preparation_phase_of_fixed_length_is_not_at_most(tmp_path, capsys):
    """A drapery's or an impact's settling runs its steps to the end: no 'at most'."""
    log = tmp_path / "log.lammps"
    log.write_text(THERMO + "1200 10 0.1\n")
    Progress(log, total=400, label="drapery", dt=0.01, phase_marker="drapery: block released",
             before=("settling", 3000, False)).report()
    assert capsys.readouterr().err.strip() == "drapery: settling: step 1200/3000"
