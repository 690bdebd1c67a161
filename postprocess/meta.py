"""Generator metadata (PREFIX.json): zone centre, panel normal and bond-type family names."""

import json

import numpy as np

from .errors import PostprocessError

# The fixed numbering of doc/file_formats.md, used when no JSON is given.
DEFAULT_FAMILIES = {1: "DT", 2: "SW", 3: "selvedge", 4: "rope"}


def read_json(path):
    """Load a JSON file; PostprocessError with file (and line) on failure."""
    try:
        with open(path, "r", encoding="utf-8") as handle:
            return json.load(handle)
    except OSError as exc:
        raise PostprocessError(f"{path}: {exc.strerror}") from None
    except json.JSONDecodeError as exc:
        raise PostprocessError(f"{path}:{exc.lineno}: invalid JSON: {exc.msg}") from None


def _vector(meta, key, path, default):
    value = meta.get(key, default)
    try:
        vec = np.asarray(value, dtype=float).reshape(3)
    except (TypeError, ValueError):
        raise PostprocessError(f"{path}: '{key}' must be three numbers, got {value!r}") from None
    return vec


def families_from_meta(meta, path):
    """Bond type (int) -> family name from the JSON's bond_types."""
    raw = meta.get("bond_types")
    if raw is None:
        return dict(DEFAULT_FAMILIES)
    try:
        return {int(k): str(v) for k, v in raw.items()}
    except (AttributeError, ValueError):
        raise PostprocessError(f"{path}: 'bond_types' must map type numbers to names") from None


def parse_families(text):
    """Parse ``1=DT,2=SW`` into {1: 'DT', 2: 'SW'}."""
    result = {}
    for item in text.split(","):
        key, sep, name = item.partition("=")
        try:
            if not sep or not name.strip():
                raise ValueError
            result[int(key)] = name.strip()
        except ValueError:
            raise PostprocessError(f"--families: expected TYPE=NAME[,TYPE=NAME...], got "
                                   f"'{text}'") from None
    return result


class PanelInfo:
    """Centre, unit normal and families, from a JSON file and/or command-line overrides."""

    def __init__(self, json_path=None, centre=None, normal=None, families=None):
        meta = read_json(json_path) if json_path else {}
        self.centre = (np.asarray(centre, float) if centre is not None
                       else _vector(meta, "centre", json_path, [0.0, 0.0, 0.0]))
        normal = (np.asarray(normal, float) if normal is not None
                  else _vector(meta, "normal", json_path, [0.0, 0.0, 1.0]))
        length = float(np.linalg.norm(normal))
        if not length > 0:
            raise PostprocessError(f"normal must be a non-zero vector, got {normal.tolist()}")
        self.normal = normal / length
        self.families = (dict(families) if families is not None
                         else families_from_meta(meta, json_path))
