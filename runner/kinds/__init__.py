"""The kinds of case, one module each, on the base class of kinds/base.py. A case file's
`kind` names one of them; its module declares the keys of its own section."""

from .cantilever import Cantilever
from .drapery import Drapery
from .fence import Fence
from .impact import Impact
from .punch import Punch
from .tensile import Tensile

ALL = (Punch, Impact, Tensile, Cantilever, Fence, Drapery)
NAMES = tuple(k.name for k in ALL)
BY_NAME = {k.name: k for k in ALL}


def of(case):
    """The kind object that runs a checked case."""
    return BY_NAME[case.kind](case)
