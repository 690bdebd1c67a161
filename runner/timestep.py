"""The stable time step of a case, from its one estimator: compute wirenet/timestep (C++,
doc/compute_wirenet_timestep.md), which counts the bonds' frequencies as bond_style wirenet
does and adds a contact on the lightest node. The runner reads the line a deck prints after a
run of no steps (inputs/include/timestep.in); no formula of it is repeated in Python.
"""

import os
import re
from dataclasses import dataclass

from . import INPUTS, engine
from .errors import RunError

LINE = r"^wirenet: stable time step{tag} (\S+) s loaded, (\S+) s free \(bonds (\S+) s: " \
       r"translation (\S+) s, rotation (\S+) s; contact (\S+) s\)"


@dataclass(frozen=True)
class StableStep:
    """The stable steps (s) of a net: under a loading body (``loaded``), alone (``free``: a
    compound panel's layers still press each other), and their parts."""
    loaded: float
    free: float
    bonds: float
    translation: float
    rotation: float
    contact: float


def read(workdir, tag=""):
    """The StableStep a deck printed into workdir/log.lammps (``tag``: the line's label after
    'stable time step', e.g. ' settling')."""
    path = os.path.join(workdir, "log.lammps")
    try:
        with open(path, errors="replace") as fh:
            found = re.search(LINE.format(tag=re.escape(tag)), fh.read(), re.M)
    except OSError as exc:
        raise RunError(f"{path}: {exc.strerror or exc}") from None
    if not found:
        raise RunError(f"{path}: no line 'wirenet: stable time step{tag} ...'")
    return StableStep(*(float(v) for v in found.groups()))


def of_panel(panel, variables, workdir, name="timestep"):
    """The stable steps of a generated panel (runner/panel.Panel) with the true masses and the
    materials of the case's deck variables: inputs/timestep.in, one rank, in workdir/name."""
    probe = os.path.join(workdir, name)
    engine.run(INPUTS / "timestep.in", probe,
               dict(variables, data=os.path.abspath(panel.data_path),
                    types=os.path.abspath(panel.types_path), layers=panel.layers),
               label="stable step")
    return read(probe)
