"""WireNet from Python: load a case file (or its text), set keys, run it in a folder, read what
it wrote. The same runner as `./wirenet run`: the same checks, kinds, engine and records.

    from runner import api
    case = api.load("inputs/cases/impact_hex.toml", quick=True, set=["impact.mass=60"])
    facts = api.run(case, "out/my_impact", ranks=2)
"""

import os
import tomllib

from . import casefile, kinds
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
