"""Case folders of a study directory as the report reads them: DIR/CASE/case.json (the record,
postprocess/record.py) and the CSVs (zone_forces, platter, block, beam)."""

import math
import os
import re
import sys
from dataclasses import dataclass, field

import numpy as np

from .csvio import read_csv
from .errors import PostprocessError
from .meta import json_type, read_json_object
from .record import OK, STATUSES, CaseRecord

TABLES = {
    "zone": ("zone_forces.csv", ("time", "displacement", "family", "total_tension",
                                 "max_tension", "bonds")),
    "platter": ("platter.csv", ("time", "displacement", "force")),
    "block": ("block.csv", ("time", "x", "y", "z", "vx", "vy", "vz", "force")),
    "beam": ("beam.csv", ("elements", "load", "tip_deflection", "analytic_deflection", "nrmse")),
    "tensile": ("tensile.csv", ("time", "displacement", "force")),
}
LINE_FILES = ("deflection.csv", "beam_line.csv")


def zone_families(table):
    """{family: dict(time, displacement, total, max, bonds)} of a zone table (zone_forces*.csv
    read by column name)."""
    result = {}
    for family in dict.fromkeys(table["family"]):
        rows = table["family"] == family
        result[family] = {"time": table["time"][rows],
                          "displacement": table["displacement"][rows],
                          "total": table["total_tension"][rows],
                          "max": table["max_tension"][rows],
                          "bonds": table["bonds"][rows]}
    return result


def other_zones(case):
    """{zone name: table} of a case's zones after the first (zone_forces_NAME.csv, written for
    every further [[output.zones]] entry); an unreadable file is left out with a warning."""
    found = {}
    try:
        names = sorted(os.listdir(case.path))
    except OSError:
        return found
    for file in names:
        if not (file.startswith("zone_forces_") and file.endswith(".csv")):
            continue
        try:
            found[file[len("zone_forces_"):-len(".csv")]] = read_csv(
                os.path.join(case.path, file), required=TABLES["zone"][1])
        except PostprocessError as exc:
            print(f"postprocess: warning: {exc}", file=sys.stderr)
    return found
# a folder without case.json (made by hand for `postprocess report`): its kind by its tables
KIND_OF_TABLE = (("beam", "beam"), ("block", "impact"), ("platter", "punch"))


@dataclass
class Case:
    name: str
    path: str
    meta: dict = field(default_factory=dict)
    tables: dict = field(default_factory=dict)
    errors: list = field(default_factory=list)

    @property
    def record(self):
        return CaseRecord.from_json(self.meta)

    @property
    def status(self):
        """case.json's status (postprocess/record.py); 'ok' for a folder without case.json."""
        return str(self.meta.get("status", OK))

    @property
    def usable(self):
        """True when the numbers of this case may be used (status ok, no unreadable file)."""
        return self.status == OK and not self.errors

    @property
    def kind(self):
        """case.json's kind; for a folder without one, the kind its tables show."""
        if self.meta.get("kind"):
            return str(self.meta["kind"])
        return next((kind for table, kind in KIND_OF_TABLE if table in self.tables), "unknown")

    @property
    def bending(self):
        """Bending fraction of a calibration case: case.json bending / bending_fraction /
        bending_ratio (checked by read_case_meta), else the last number in the folder name."""
        for key in BENDING_KEYS:
            if self.meta.get(key) is not None:
                return float(self.meta[key])
        numbers = re.findall(r"\d+(?:\.\d+)?(?:e-?\d+)?", self.name)
        return float(numbers[-1]) if numbers else None

    def zone(self):
        """{family: dict(time, displacement, total, max, bonds)} from zone_forces.csv."""
        table = self.tables.get("zone")
        return {} if table is None else zone_families(table)

    def line_path(self):
        """The optional deflection-line CSV of a beam case."""
        for name in LINE_FILES:
            path = os.path.join(self.path, name)
            if os.path.isfile(path):
                return path
        return None


# case.json keys the readers use, with the JSON types they accept (null = not recorded).
BENDING_KEYS = ("bending", "bending_fraction", "bending_ratio")
TEXT_KEYS = ("status", "kind")
NUMBER_KEYS = ("wall_time", "cpu_time", "edge_force_peak", "broken_bonds", "max_displacement",
               "rebound_time", "peak_block_force", "np")
OBJECT_KEYS = ("energy", "momentum", "quasi_static", "ended_at_drop")
NESTED_NUMBER_KEYS = {               # numbers (or null) inside those objects that are reported
    "energy": ("closure_error",),
    "momentum": ("error",),
    "quasi_static": ("slow_factor", "curve_difference", "compared_up_to",
                     "kinetic_energy_fraction", "equilibrium_error",
                     "equilibrium_error_of_current", "equilibrium_holds_from"),
    "ended_at_drop": ("displacement", "force", "peak_force"),
}


def _is_number(value):
    return isinstance(value, (int, float)) and not isinstance(value, bool)


def _bad(path, key, value, wanted):
    shown = repr(value) if isinstance(value, str) else value
    return PostprocessError(f"{path}: '{key}' must be {wanted}, got {json_type(value)} "
                            f"{shown!s}".rstrip())


def _missing_is_null(value):
    """NaN / infinite numbers anywhere -> None: the study writes NaN for a value it could not
    compute (e.g. a quasi-static measure of a case without force), i.e. 'not available'."""
    if isinstance(value, dict):
        return {k: _missing_is_null(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_missing_is_null(v) for v in value]
    if isinstance(value, float) and not math.isfinite(value):
        return None
    return value


def check_bending(value, path, key):
    """A bending fraction: a finite number >= 0 (a numeric string is accepted)."""
    try:
        if isinstance(value, bool) or not isinstance(value, (int, float, str)):
            raise ValueError
        fraction = float(value)
    except ValueError:
        raise _bad(path, key, value, "a number >= 0") from None
    if not (math.isfinite(fraction) and fraction >= 0):
        raise _bad(path, key, value, "a finite number >= 0")
    return fraction


def read_case_meta(path):
    """case.json of a case folder as a dict, checked key by key.

    Errors (PostprocessError naming the file and the key): not JSON, truncated, not an object,
    a bending fraction that is not a finite number >= 0, status / kind that are not text,
    a recorded number (wall_time, edge_force_peak, ...) that is not a number, energy /
    momentum / quasi_static / ended_at_drop that are not objects (or whose reported numbers are
    not numbers), a first_rupture that is neither a number nor an object with numbers. NaN /
    Infinity elsewhere read as null (not available).
    """
    meta = read_json_object(path)
    for key in BENDING_KEYS:
        if meta.get(key) is not None:
            meta[key] = check_bending(meta[key], path, key)
    for key in TEXT_KEYS:
        if meta.get(key) is not None and not isinstance(meta[key], str):
            raise _bad(path, key, meta[key], "text")
    if meta.get("status") is not None and meta["status"] not in STATUSES:
        raise _bad(path, "status", meta["status"], "one of " + ", ".join(STATUSES))
    for key in NUMBER_KEYS:
        if meta.get(key) is not None and not _is_number(meta[key]):
            raise _bad(path, key, meta[key], "a number or null")
    for key in OBJECT_KEYS:
        if meta.get(key) is not None and not isinstance(meta[key], dict):
            raise _bad(path, key, meta[key], "an object {...} or null")
    for key, names in NESTED_NUMBER_KEYS.items():
        for name in names:
            value = (meta.get(key) or {}).get(name)
            if value is not None and not _is_number(value):
                raise _bad(path, f"{key}.{name}", value, "a number or null")
    passed = (meta.get("quasi_static") or {}).get("passed")
    if passed is not None and not isinstance(passed, bool):
        raise _bad(path, "quasi_static.passed", passed, "true, false or null")
    snaps = (meta.get("quasi_static") or {}).get("snap_events")
    if snaps is not None and not isinstance(snaps, list):
        raise _bad(path, "quasi_static.snap_events", snaps, "a list or null")
    rupture = meta.get("first_rupture")
    if rupture is not None and not _is_number(rupture):
        if not isinstance(rupture, dict):
            raise _bad(path, "first_rupture", rupture, "a number, an object or null")
        for key in ("displacement", "force"):
            if rupture.get(key) is not None and not _is_number(rupture[key]):
                raise _bad(path, f"first_rupture.{key}", rupture[key], "a number or null")
        if rupture.get("bond") is not None and not isinstance(rupture["bond"], dict):
            raise _bad(path, "first_rupture.bond", rupture["bond"], "an object {...} or null")
    return _missing_is_null(meta)


def load_case(path):
    """Read every known file of a case folder. An unreadable CSV is recorded in
    ``case.errors`` (the case is then not used); a corrupt case.json is an error
    (PostprocessError naming the file and the key), since it decides what the case is."""
    case = Case(os.path.basename(os.path.normpath(path)), path)
    meta_path = os.path.join(path, "case.json")
    if os.path.isfile(meta_path):
        case.meta = read_case_meta(meta_path)
    for key, (name, required) in TABLES.items():
        table_path = os.path.join(path, name)
        if os.path.isfile(table_path):
            try:
                case.tables[key] = read_csv(table_path, required=required)
            except PostprocessError as exc:
                case.errors.append(str(exc))
    return case


def natural_key(name):
    """Sort key that reads the numbers in a name as numbers: v6 before v10, 0.05 before 0.25."""
    return [(0, float(part), "") if re.fullmatch(r"\d+(\.\d+)?", part) else (1, 0.0, part)
            for part in re.split(r"(\d+(?:\.\d+)?)", name) if part]


def discover(directory):
    """{name: Case} for the sub-folders of ``directory`` that hold a case file or case.json, in
    natural order (the numbers in the names as numbers)."""
    if not os.path.isdir(directory):
        raise PostprocessError(f"{directory}: not a directory")
    cases = {}
    for name in sorted(os.listdir(directory), key=natural_key):
        path = os.path.join(directory, name)
        if name.startswith(".") or name == "figures" or not os.path.isdir(path):
            continue
        files = [TABLES[k][0] for k in TABLES] + ["case.json"]
        if any(os.path.isfile(os.path.join(path, f)) for f in files):
            cases[name] = load_case(path)
    return cases


def calibration_cases(cases):
    """Usable calibration cases with a platter.csv, sorted by bending fraction."""
    found = [c for c in cases.values()
             if c.kind == "calibration" and c.usable and "platter" in c.tables]
    return sorted(found, key=lambda c: (c.bending is None, c.bending or 0.0, c.name))


def peak(values):
    """Largest value, or None for an empty array."""
    values = np.asarray(values, dtype=float)
    return float(values.max()) if values.size else None
