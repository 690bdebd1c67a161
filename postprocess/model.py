"""The model's material and contact defaults, read from their one source: the deck include
inputs/include/materials.in (``variable NAME index VALUE`` lines). The decks use them as they
are; Python reads the same numbers for the time-step estimate instead of keeping a copy."""

import re

from .errors import PostprocessError
from .liggghts import INPUTS

MATERIALS_FILE = INPUTS / "include" / "materials.in"
_LINE = re.compile(r'^variable\s+(\w+)\s+index\s+(?:"([^"]*)"|(\S+))')


def read_materials(path=MATERIALS_FILE):
    """{name: value} of the index variables of a deck include; numbers as float."""
    values = {}
    try:
        text = path.read_text()
    except OSError as exc:
        raise PostprocessError(f"{path}: {exc.strerror}") from None
    for line in text.splitlines():
        m = _LINE.match(line)
        if not m:
            continue
        raw = m.group(2) if m.group(2) is not None else m.group(3)
        try:
            values[m.group(1)] = float(raw)
        except ValueError:
            values[m.group(1)] = raw
    return values


MATERIALS = read_materials()


def _curve(text):
    numbers = [float(v) for v in text.split()]
    return tuple(zip(numbers[0::2], numbers[1::2]))


SW_CURVE = _curve(MATERIALS["curve"])   # ((strain, stress [Pa]), ...) of the single wire
WIRE = {k: MATERIALS[k] for k in ("wire_d", "selvedge_d", "lambda_eps", "lambda_k", "wire_nu")}
ROPE = {k: MATERIALS[k] for k in ("rope_d", "rope_E", "rope_nu", "shear")}
CONTACT = {k: MATERIALS[k] for k in ("kn", "ks", "mu")}
PAPER_BENDING = MATERIALS["bending"]    # the calibrated bending fraction of the paper
ROPE_STRENGTH = (MATERIALS["rope_sigma_t"], MATERIALS["rope_tau_c"])   # [Pa], see materials.in


def rope_strength(materials=None):
    """(SIGMA_T, TAU_C) of the rope [Pa] with a case's overrides."""
    values = resolve(materials)
    return (float(values["rope_sigma_t"]), float(values["rope_tau_c"]))


def rope_strength_keyword(enabled, materials=None):
    """The rope's bond_coeff tail for a breakable rope ("" keeps the paper's unbreakable one)."""
    return "strength {!r} {!r}".format(*rope_strength(materials)) if enabled else ""


def resolve(overrides=None):
    """The materials.in values with a case's overrides (same names; see runner/schema.py)."""
    values = dict(MATERIALS)
    values.update(overrides or {})
    return values


def sw_curve(values):
    """((strain, stress), ...) of the single wire from a resolved materials dict."""
    return _curve(values["curve"]) if isinstance(values["curve"], str) else tuple(values["curve"])
