"""The drawing surface every figure shares (matplotlib, Agg backend): the pyplot module, the force
unit, and saving PREFIX.png and PREFIX.svg together or not at all."""

import os

import numpy as np

from .errors import PostprocessError
from .output import Outputs


def pyplot():
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    return plt


def force_scale(values):
    """(divisor, unit) so that the largest |force| reads in N, kN or MN."""
    largest = max((float(np.max(np.abs(v))) for v in values if np.size(v)), default=0.0)
    if largest >= 1e6:
        return 1e6, "MN"
    if largest >= 1e3:
        return 1e3, "kN"
    return 1.0, "N"


def check_prefix(prefix, option="--out"):
    """PostprocessError unless ``prefix`` names files (PREFIX.png, ...), not a folder."""
    if not os.path.basename(str(prefix)):
        raise PostprocessError(f"argument {option}: expected a file prefix such as "
                               f"DIR/figure, got '{prefix}'")
    for ext in ("png", "svg", "json"):
        if os.path.isdir(f"{prefix}.{ext}"):
            raise PostprocessError(f"{prefix}.{ext}: is a directory (an output file was "
                                   f"expected)")


def save(fig, prefix, outputs=None):
    """Save PREFIX.png and PREFIX.svg, both or neither; return both paths.

    With ``outputs`` (an output.Outputs) the files are committed with the other outputs of the
    caller; without, at once."""
    own = outputs is None
    outputs = Outputs() if own else outputs
    paths = []
    try:
        for ext in ("png", "svg"):
            path = f"{prefix}.{ext}"
            tmp = outputs.file(path, "." + ext)
            try:
                fig.savefig(tmp, format=ext, dpi=150)
            except OSError as exc:
                raise PostprocessError(f"{path}: cannot write: {exc.strerror or exc}") from None
            paths.append(path)
        if own:
            outputs.commit()
    except BaseException:
        if own:
            outputs.abort()
        raise
    finally:
        pyplot().close(fig)
    return paths
