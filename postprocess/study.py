"""Case folders of a study directory: DIR/CASE/{zone_forces,platter,block,beam}.csv + case.json."""

import os
import re
from dataclasses import dataclass, field

import numpy as np

from .csvio import read_csv
from .errors import PostprocessError
from .meta import read_json

TABLES = {
    "zone": ("zone_forces.csv", ("time", "displacement", "family", "total_tension",
                                 "max_tension", "bonds")),
    "platter": ("platter.csv", ("time", "displacement", "force")),
    "block": ("block.csv", ("time", "x", "y", "z", "vx", "vy", "vz", "force")),
    "beam": ("beam.csv", ("elements", "load", "tip_deflection", "analytic_deflection", "nrmse")),
}
LINE_FILES = ("deflection.csv", "beam_line.csv")
KINDS = ("beam", "calibration", "punch", "impact")
OK_STATUSES = ("ok", "done", "completed", "success")


@dataclass
class Case:
    name: str
    path: str
    meta: dict = field(default_factory=dict)
    tables: dict = field(default_factory=dict)
    errors: list = field(default_factory=list)

    @property
    def status(self):
        """Normalised status: 'ok' unless case.json says otherwise (e.g. 'not-implemented')."""
        raw = str(self.meta.get("status", "ok")).strip().lower()
        raw = re.sub(r"[\s_]+", "-", raw)
        return "ok" if raw in OK_STATUSES else raw

    @property
    def usable(self):
        """True when the numbers of this case may be used (status ok, no unreadable file)."""
        return self.status == "ok" and not self.errors

    @property
    def kind(self):
        meta_kind = str(self.meta.get("kind", "")).lower()
        for kind in KINDS:
            if meta_kind.startswith(kind[:5]) or (not meta_kind and
                                                  self.name.lower().startswith(kind[:5])):
                return kind
        if "beam" in self.tables:
            return "beam"
        if "block" in self.tables:
            return "impact"
        if "platter" in self.tables:
            return "punch"
        return meta_kind or "unknown"

    @property
    def bending(self):
        """Bending fraction of a calibration case: case.json bending / bending_fraction /
        bending_ratio, else the last number in the folder name."""
        for key in ("bending", "bending_fraction", "bending_ratio"):
            if key in self.meta:
                try:
                    return float(self.meta[key])
                except (TypeError, ValueError):
                    return None
        numbers = re.findall(r"\d+(?:\.\d+)?(?:e-?\d+)?", self.name)
        return float(numbers[-1]) if numbers else None

    def zone(self):
        """{family: dict(time, displacement, total, max, bonds)} from zone_forces.csv."""
        table = self.tables.get("zone")
        if table is None:
            return {}
        result = {}
        for family in dict.fromkeys(table["family"]):
            rows = table["family"] == family
            result[family] = {"time": table["time"][rows],
                              "displacement": table["displacement"][rows],
                              "total": table["total_tension"][rows],
                              "max": table["max_tension"][rows],
                              "bonds": table["bonds"][rows]}
        return result

    def line_path(self):
        """The optional deflection-line CSV of a beam case."""
        for name in LINE_FILES:
            path = os.path.join(self.path, name)
            if os.path.isfile(path):
                return path
        return None


def load_case(path):
    """Read every known file of a case folder; unreadable files are recorded, not fatal."""
    case = Case(os.path.basename(os.path.normpath(path)), path)
    meta_path = os.path.join(path, "case.json")
    if os.path.isfile(meta_path):
        try:
            meta = read_json(meta_path)
            case.meta = meta if isinstance(meta, dict) else {}
        except PostprocessError as exc:
            case.errors.append(str(exc))
    for key, (name, required) in TABLES.items():
        table_path = os.path.join(path, name)
        if os.path.isfile(table_path):
            try:
                case.tables[key] = read_csv(table_path, required=required)
            except PostprocessError as exc:
                case.errors.append(str(exc))
    return case


def discover(directory):
    """{name: Case} for the sub-folders of ``directory`` that hold a case file or case.json."""
    if not os.path.isdir(directory):
        raise PostprocessError(f"{directory}: not a directory")
    cases = {}
    for name in sorted(os.listdir(directory)):
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
