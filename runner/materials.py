"""The model's material and contact defaults, read from their one source: the deck include
inputs/include/materials.in (``variable NAME index VALUE   # SOURCE`` lines: the text after the
value's ``#`` is the number's source, shown in the key tables and the report). The decks use
the values as they are; the schema (runner/schema.py) takes them as the keys' defaults."""

import json
import os
import re

from . import INPUTS
from .errors import RunError

MATERIALS_FILE = INPUTS / "include" / "materials.in"
_LINE = re.compile(r'^variable\s+(\w+)\s+index\s+(?:"([^"]*)"|(\S+))\s*(?:#\s*(.*))?$')
NO_SOURCE = "no source (inputs/include/materials.in)"


def read_materials(path=MATERIALS_FILE, sources=None):
    """{name: value} of the index variables of a deck include; numbers as float. ``sources``
    (a dict) receives {name: the text after the value's '#'} (NO_SOURCE without one)."""
    values = {}
    try:
        text = path.read_text()
    except OSError as exc:
        raise RunError(f"{path}: {exc.strerror}") from None
    for line in text.splitlines():
        m = _LINE.match(line)
        if not m:
            continue
        raw = m.group(2) if m.group(2) is not None else m.group(3)
        if sources is not None:
            sources[m.group(1)] = (m.group(4) or "").strip() or NO_SOURCE
        try:
            values[m.group(1)] = float(raw)
        except ValueError:
            values[m.group(1)] = raw
    return values


SOURCES = {}
MATERIALS = read_materials(sources=SOURCES)


def _curve(text):
    numbers = [float(v) for v in text.split()]
    return tuple(zip(numbers[0::2], numbers[1::2]))


SW_CURVE = _curve(MATERIALS["curve"])   # ((strain, stress [Pa]), ...) of the single wire
PAPER_BENDING = MATERIALS["bending"]    # the bending fraction of the paper's best fit
CALIBRATION_FILE = "calibration.json"   # python3 -m postprocess calibrate ... --out DIR/calibration


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


def bending_of(case, study_dir):
    """(fraction, source) of the rope beams: the case's number, or for 'calibrated' the best
    fraction of DIR/calibration.json when the study's bending cases have been fitted, else the
    paper's."""
    value = case["materials.bending"]
    if value != "calibrated":
        return value, "case file"
    path = os.path.join(study_dir, CALIBRATION_FILE)
    try:
        with open(path, encoding="utf-8") as handle:
            best = json.load(handle)["best_fraction"]
        if isinstance(best, (int, float)) and best >= 0:
            return float(best), f"calibrated ({path})"
    except (OSError, ValueError, KeyError, TypeError):
        pass
    return PAPER_BENDING, "the paper's calibrated value (no calibration.json in the study folder)"
