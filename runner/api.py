"""WireNet from Python: load a case file (or its text), set keys, run it or a whole study in a
folder, read what it wrote. The same runner as `./wirenet run`: the same checks, kinds, engine,
records and report (doc/python_api.md).

    from runner import api
    case = api.load("inputs/cases/impact_hex.toml", quick=True, set=["impact.mass=60"])
    facts = api.run(case, "out/my_impact", ranks=2)           # one case, its facts
    result = api.study("impact_square", "out/sweep", quick=True,  # a study, its summary
                       set=['ensemble.sweep="impact.mass"', "ensemble.values=[40.0, 60.0]"])
    block = api.table("out/sweep/impact_square/member_001", "block.csv")
"""

import json
import os
import tomllib

from postprocess.csvio import read_csv

from . import casefile, kinds, study as _study
from .kinds.base import RunContext


def load(source, quick=False, set=(), name=None):
    """The checked Case of a case file path, or of case-file text (a string holding a newline
    or an '=' and no such file); ``set``: KEY=VALUE overrides as --set takes them."""
    if os.path.isfile(str(source)) or ("\n" not in str(source) and "=" not in str(source)):
        return casefile.read(str(source), set, quick, name)
    raw = tomllib.loads(source)
    for text in set:
        casefile.apply_override(raw, text, "<text>")
    return casefile.Checker(os.path.abspath(f"{name or 'case'}.toml"), raw, quick,
                            name or "case").case()


def run(case, folder, ranks=1, study_dir=None, unit=0):
    """Run one unit of a case (its first, by default) in ``folder``; return its facts. The
    folder is created; ``study_dir`` is where a case finds what other cases of its study left
    (a calibration, the net of an earlier impact): the folder's parent by default."""
    folder = os.path.abspath(folder)
    os.makedirs(folder, exist_ok=True)
    ctx = RunContext(case_dir=folder, study_dir=study_dir or os.path.dirname(folder),
                     ranks=ranks)
    return kinds.of(case).run(unit, ctx)


def study(target=None, out=None, quick=False, set=(), np=None, partitions=None):
    """What `./wirenet run TARGET --out OUT [--quick] [--set ...] [--np N] [--partitions M]`
    does: a study of inputs/studies/, a case of inputs/cases/ or a case file (ensembles and
    sweeps expanded into their members, cases side by side, resumed where a folder holds them
    done), its report written. Returns a runner.study.Result: .out, .summary (summary.json),
    .names (the cases run), .unsound (those whose status is not sound, name -> entry). Raises
    runner.errors.StudyError on bad input (nothing run; the message is the one line the command
    prints), RunError when a case failed, runner.scheduler.Interrupted on a signal."""
    return _study.execute(target, out, quick, tuple(set), np, partitions)


def summary(folder):
    """summary.json of a study's folder (the report's numbers; doc/file_formats.md)."""
    with open(os.path.join(folder, "summary.json"), encoding="utf-8") as handle:
        return json.load(handle)


def facts(case_folder):
    """case.json of a case's folder: its status, verdict and facts."""
    with open(os.path.join(case_folder, "case.json"), encoding="utf-8") as handle:
        return json.load(handle)


def table(case_folder, name):
    """A CSV a case wrote (block.csv, edges.csv, zone_forces.csv, ...; doc/file_formats.md) as
    {column: numpy array}, read by column name."""
    return read_csv(os.path.join(case_folder, name))
