"""wirenet-gen from Python: the net, the fence and the bodies' shapes a kind needs. The generator
is the one home of the nets' geometry and of their atom and bond type numbers, which it writes
to PREFIX.json (and the deck include PREFIX.groups.in) for the runner and the decks to read."""

import os
import subprocess

from . import engine
from .errors import RunError


def generate(kind, out_prefix, *options):
    """Run wirenet-gen KIND OPTIONS --out PREFIX; return the absolute path of PREFIX.data (it is
    handed to LIGGGHTS, which runs in another folder)."""
    out_prefix = os.path.abspath(out_prefix)
    cmd = [str(engine.binary("wirenet-gen")), *kind.split(), *map(str, options), "--out", out_prefix]
    try:
        p = subprocess.run(cmd, capture_output=True, text=True)
    except OSError as exc:          # the binary replaced under us (a rebuild)
        raise RunError(f"cannot start {cmd[0]}: {exc.strerror or exc}") from None
    if p.returncode:
        raise RunError(f"wirenet-gen failed: {p.stderr.strip()}")
    return f"{out_prefix}.data"
