"""Generator metadata (PREFIX.json): zone centre, panel normal and bond-type family names."""

import json

import numpy as np

from .errors import PostprocessError

# The fixed numbering of doc/file_formats.md, used when no JSON is given.
DEFAULT_FAMILIES = {1: "DT", 2: "SW", 3: "selvedge", 4: "rope"}


def read_json(path):
    """Load a JSON file; PostprocessError with file (and line) on failure.

    NaN / Infinity tokens (not JSON, but Python writes them) are read as float NaN / inf; each
    reader decides per key whether that is a missing value or an error."""
    try:
        with open(path, "r", encoding="utf-8") as handle:
            return json.load(handle)
    except OSError as exc:
        raise PostprocessError(f"{path}: {exc.strerror or exc}") from None
    except json.JSONDecodeError as exc:
        raise PostprocessError(f"{path}:{exc.lineno}: invalid JSON: {exc.msg}") from None
    except UnicodeDecodeError as exc:
        raise PostprocessError(f"{path}: not a UTF-8 text file (byte {exc.start})") from None
    except (ValueError, RecursionError) as exc:
        raise PostprocessError(f"{path}: invalid JSON: {exc}") from None


def read_json_object(path):
    """read_json for files that must hold a JSON object ({...})."""
    value = read_json(path)
    if not isinstance(value, dict):
        raise PostprocessError(f"{path}: expected a JSON object {{...}}, got "
                               f"{json_type(value)}")
    return value


def json_type(value):
    """The JSON name of a value's type, for error messages."""
    if value is None:
        return "null"
    if isinstance(value, bool):
        return "a boolean"
    if isinstance(value, (int, float)):
        return "a number"
    if isinstance(value, str):
        return "a string"
    if isinstance(value, list):
        return "a list"
    return "an object"


def _vector(meta, key, path, default):
    value = meta.get(key, default)
    try:
        if any(isinstance(v, (bool, str)) for v in value):
            raise TypeError
        vec = np.asarray(value, dtype=float).reshape(3)
    except (TypeError, ValueError):
        raise PostprocessError(f"{path}: '{key}' must be three numbers, got "
                               f"{json.dumps(value)}") from None
    if not np.all(np.isfinite(vec)):
        raise PostprocessError(f"{path}: '{key}' must be three finite numbers, got "
                               f"{vec.tolist()}")
    return vec


def families_from_meta(meta, path):
    """Bond type (int) -> family name from the JSON's bond_types."""
    raw = meta.get("bond_types")
    if raw is None:
        return dict(DEFAULT_FAMILIES)
    try:
        if not all(isinstance(v, str) and v.strip() for v in raw.values()):
            raise ValueError
        return {int(k): v.strip() for k, v in raw.items()}
    except (AttributeError, ValueError):
        raise PostprocessError(f"{path}: 'bond_types' must map type numbers to names, got "
                               f"{json.dumps(raw)}") from None


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
        meta = read_json_object(json_path) if json_path else {}
        self.centre = (np.asarray(centre, float) if centre is not None
                       else _vector(meta, "centre", json_path, [0.0, 0.0, 0.0]))
        if not np.all(np.isfinite(self.centre)):
            raise PostprocessError(f"argument --centre: expected finite numbers, got "
                                   f"{self.centre.tolist()}")
        where = "argument --normal" if normal is not None else f"{json_path}: 'normal'"
        normal = (np.asarray(normal, float) if normal is not None
                  else _vector(meta, "normal", json_path, [0.0, 0.0, 1.0]))
        length = float(np.linalg.norm(normal))
        if not (length > 0 and np.isfinite(length)):
            raise PostprocessError(f"{where}: expected a non-zero finite vector, got "
                                   f"{' '.join(f'{v:g}' for v in normal)}")
        self.normal = normal / length
        self.families = (dict(families) if families is not None
                         else families_from_meta(meta, json_path))
