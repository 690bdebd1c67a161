"""Reader for the generator's LIGGGHTS data file (PREFIX.data, doc/file_formats.md).

Atoms lines: ``id type x y z diameter density molecule`` (trailing image flags are ignored);
Bonds lines: ``id type atom1 atom2``. Other sections are skipped.
"""

import math
import re
from dataclasses import dataclass

import numpy as np

from .errors import PostprocessError, at

ATOM_FIELDS = ("id", "type", "x", "y", "z", "diameter", "density", "molecule")
BOND_FIELDS = ("id", "type", "atom1", "atom2")
INTEGER_FIELDS = ("id", "type", "atom1", "atom2")      # molecule may be 0
MAX_ID = 2 ** 31 - 1
_COUNT = re.compile(r"^\s*(\d+)\s+(atoms|bonds)\s*$")


@dataclass
class DataFile:
    atoms: np.ndarray        # rows sorted by id, columns ATOM_FIELDS
    bonds: np.ndarray        # rows sorted by id, columns BOND_FIELDS (integers)

    def atom(self, field):
        """An Atoms column by its name (ATOM_FIELDS)."""
        return self.atoms[:, ATOM_FIELDS.index(field)]

    def bond(self, field):
        """A Bonds column by its name (BOND_FIELDS)."""
        return self.bonds[:, BOND_FIELDS.index(field)]

    @property
    def atom_ids(self):
        return self.atom("id").astype(np.int64)

    @property
    def positions(self):
        return np.column_stack([self.atom(c) for c in ("x", "y", "z")])


def _section_rows(path, lines, start, count, width, name):
    """Parse ``count`` non-blank lines after a section header at index ``start``."""
    rows, index = [], start + 1
    while len(rows) < count:
        if index >= len(lines):
            raise at(path, index + 1, f"unexpected end of file in {name}: expected {count} "
                                      f"lines, got {len(rows)}")
        fields = lines[index].split("#")[0].split()
        index += 1
        if not fields:
            continue
        if len(fields) < width:
            raise at(path, index, f"expected {width} columns in {name}, got {len(fields)}")
        try:
            values = [float(v) for v in fields[:width]]
        except ValueError:
            raise at(path, index, f"not a number in {name}: '{lines[index - 1].strip()}'") from None
        bad = next((k for k, v in enumerate(values) if not math.isfinite(v)), None)
        if bad is not None:
            field_names = ATOM_FIELDS if name == "Atoms" else BOND_FIELDS
            raise at(path, index, f"{name} column {field_names[bad]}: not a finite number: "
                                  f"'{fields[bad]}'")
        field_names = ATOM_FIELDS if name == "Atoms" else BOND_FIELDS
        for k, value in enumerate(values):
            if field_names[k] in INTEGER_FIELDS and not (value == int(value) and
                                                         1 <= value <= MAX_ID):
                raise at(path, index, f"{name} column {field_names[k]}: expected a whole number "
                                      f"from 1 to {MAX_ID}, got '{fields[k]}'")
        rows.append(values)
    return np.array(rows, dtype=float).reshape(count, width), index


def read_data(path):
    """Read atoms and bonds of a data file; PostprocessError naming file:line on bad input."""
    try:
        with open(path, "r", encoding="utf-8", errors="replace") as handle:
            lines = handle.read().splitlines()
    except OSError as exc:
        raise PostprocessError(f"{path}: {exc.strerror or exc}") from None
    if not any(line.strip() for line in lines):
        raise at(path, 1, "empty file")
    counts = {"atoms": None, "bonds": 0}
    atoms = bonds = None
    index = 1                                  # line 1 is the title
    while index < len(lines):
        text = lines[index].split("#")[0].strip()
        match = _COUNT.match(text)
        if match:
            counts[match.group(2)] = int(match.group(1))
        elif text == "Atoms":
            if counts["atoms"] is None:
                raise at(path, index + 1, "Atoms section before the 'N atoms' header line")
            atoms, index = _section_rows(path, lines, index, counts["atoms"], 8, "Atoms")
            continue
        elif text == "Bonds":
            bonds, index = _section_rows(path, lines, index, counts["bonds"], 4, "Bonds")
            continue
        index += 1
    if atoms is None:
        raise at(path, len(lines), "no Atoms section")
    if bonds is None:
        bonds = np.zeros((0, 4))
    atoms = atoms[np.argsort(atoms[:, ATOM_FIELDS.index("id")], kind="stable")]
    bonds = bonds[np.argsort(bonds[:, BOND_FIELDS.index("id")], kind="stable")].astype(np.int64)
    return DataFile(atoms, bonds)
