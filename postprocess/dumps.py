"""Readers for LIGGGHTS text dumps: ``dump local`` (bonds) and ``dump custom`` (nodes).

Both have the same frame layout::

    ITEM: TIMESTEP / step / ITEM: NUMBER OF ENTRIES|ATOMS / n / ITEM: BOX BOUNDS ... / 3 lines /
    ITEM: ENTRIES|ATOMS name1 name2 ... / n data lines

Frames are read one at a time (``iter_frames``); every data block is parsed with one numpy call.
Any deviation raises PostprocessError naming the file and the line.
"""

import contextlib
import gzip
import itertools
import re
import zlib
from dataclasses import dataclass

import numpy as np

from .errors import at

# Largest atom id or type accepted (LIGGGHTS' default tagint is a 32-bit int).
MAX_ID = 2 ** 31 - 1

# Columns of compute wirenet/local, 1-based as c_ID[k] (doc/file_formats.md).
BOND_COLUMNS = ("atom1", "atom2", "type", "length0", "strain", "tension", "length",
                "xm", "ym", "zm", "shear", "moment")
_COMPUTE_COLUMN = re.compile(r"^c_[A-Za-z0-9_]+\[(\d+)\]$")


@dataclass
class Frame:
    """One dump frame: ``data[:, names.index(col)]`` is a column."""
    path: str
    step: int
    names: list
    data: np.ndarray
    header_line: int            # line number of the ITEM: ENTRIES / ITEM: ATOMS line
    box: np.ndarray

    def column(self, name):
        return self.data[:, self.names.index(name)]

    def integers(self, index, low=1, high=MAX_ID):
        """Column ``index`` as int64; PostprocessError naming the line and the column when a
        value is not a whole number in [low, high] (ids and types; 1.5 or 1e30 would otherwise
        be truncated or overflow silently)."""
        values = self.data[:, index]
        bad = (values != np.round(values)) | (values < low) | (values > high)
        if bad.any():
            row = int(np.flatnonzero(bad)[0])
            raise at(self.path, self.header_line + 1 + row,
                     f"column {self.names[index]}: expected a whole number from {low} to {high}, "
                     f"got {_number_text(values[row])} (step {self.step})")
        return values.astype(np.int64)


def _number_text(value):
    value = float(value)
    return str(int(value)) if value.is_integer() and abs(value) < 1e15 else repr(value)


def _open(path):
    if str(path).endswith(".gz"):
        return gzip.open(path, "rt", encoding="utf-8", errors="replace")
    return open(path, "r", encoding="utf-8", errors="replace")


class _Lines:
    """Line iterator that knows the current line number (1-based)."""

    def __init__(self, handle, path):
        self.handle = handle
        self.path = path
        self.number = 0

    def next(self):
        """Return the next line without its newline, or None at end of file."""
        with self._damage():
            line = self.handle.readline()
        if not line:
            return None
        self.number += 1
        return line.rstrip("\r\n")

    def block(self, count):
        """Return up to ``count`` raw lines (fewer at end of file)."""
        lines = []
        with self._damage():
            lines.extend(itertools.islice(self.handle, count))
        self.number += len(lines)
        return lines

    @contextlib.contextmanager
    def _damage(self):
        """A damaged .gz (not gzip, truncated, bad CRC) is an error at the line reached."""
        try:
            yield
        except (EOFError, gzip.BadGzipFile, zlib.error) as exc:
            reason = str(exc) or type(exc).__name__
            raise self.error(f"damaged compressed file: {reason}", self.number + 1) from None

    def error(self, message, line=None):
        return at(self.path, self.number if line is None else line, message)


def _read_value(lines, kind, item):
    text = lines.next()
    if text is None:
        raise lines.error(f"unexpected end of file after ITEM: {item}", lines.number + 1)
    fields = text.split()
    try:
        return kind(fields[0])
    except (ValueError, IndexError):
        raise lines.error(f"expected {'an integer' if kind is int else 'a number'} after "
                          f"ITEM: {item}, got '{text.strip()}'") from None


def _read_box(lines):
    rows = []
    for _ in range(3):
        text = lines.next()
        if text is None:
            raise lines.error("unexpected end of file in ITEM: BOX BOUNDS", lines.number + 1)
        try:
            rows.append([float(v) for v in text.split()])
        except ValueError:
            raise lines.error(f"expected box bounds, got '{text.strip()}'") from None
        if not all(np.isfinite(rows[-1])):
            raise lines.error(f"box bounds must be finite numbers, got '{text.strip()}'")
        if len(rows[-1]) not in (2, 3):
            raise lines.error(f"expected 2 or 3 box bound values, got {len(rows[-1])}")
    return np.array([r[:2] for r in rows])


def _locate_bad_line(lines, block, first, ncol, step, expected):
    """Slow path after a failed parse: raise the error for the first offending line."""
    for offset, raw in enumerate(block):
        text = raw.strip()
        number = first + offset
        if text.startswith("ITEM:"):
            raise lines.error(f"truncated frame at step {step}: expected {expected} entries, "
                              f"got {offset}", number)
        fields = text.split()
        if len(fields) != ncol:
            raise lines.error(f"expected {ncol} columns, got {len(fields)}", number)
        for field in fields:
            try:
                float(field)
            except ValueError:
                raise lines.error(f"not a number: '{field}'", number) from None
    raise lines.error(f"unexpected end of file: frame at step {step} expects {expected} entries, "
                      f"got {len(block)}", lines.number + 1)


def _check_finite(lines, block, first, names, data, step):
    """Raise for the first NaN / infinite value of a parsed block: file:line, column, step."""
    bad = ~np.isfinite(data)
    if not bad.any():
        return
    row, col = np.argwhere(bad)[0]
    field = block[row].split()[col]
    raise lines.error(f"column {names[col]}: not a finite number: '{field}' (step {step})",
                      first + int(row))


def _read_data(lines, names, count, step):
    first = lines.number + 1
    block = lines.block(count)
    ncol = len(names)
    if len(block) == count:
        if count == 0:
            return np.zeros((0, ncol))
        try:
            data = np.loadtxt(block, ndmin=2, comments=None)
            if data.shape == (count, ncol):
                _check_finite(lines, block, first, names, data, step)
                return data
        except ValueError:
            pass
    _locate_bad_line(lines, block, first, ncol, step, count)
    raise lines.error("cannot parse data block", first)  # not reached


def iter_frames(path):
    """Yield the Frames of one dump file in file order."""
    with _open(path) as handle:
        lines = _Lines(handle, str(path))
        step = count = box = None
        seen_any = False
        while True:
            text = lines.next()
            if text is None:
                break
            stripped = text.strip()
            if not stripped:
                continue
            seen_any = True
            if not stripped.startswith("ITEM:"):
                raise lines.error(f"expected an ITEM: line, got '{stripped[:40]}'")
            item = stripped[5:].strip()
            if item == "TIMESTEP":
                step, count, box = _read_value(lines, int, item), None, None
            elif step is None:
                raise lines.error(f"ITEM: {item} before ITEM: TIMESTEP")
            elif item.startswith("NUMBER OF"):
                count = _read_value(lines, int, item)
                if count < 0:
                    raise lines.error(f"negative count {count}")
            elif item.startswith("BOX BOUNDS"):
                box = _read_box(lines)
            elif item in ("TIME", "UNITS"):
                lines.next()
            elif item.startswith("ENTRIES") or item.startswith("ATOMS"):
                if count is None:
                    raise lines.error(f"ITEM: {item.split()[0]} without ITEM: NUMBER OF ...")
                names = item.split()[1:]
                if not names:
                    raise lines.error("no column names")
                header = lines.number
                data = _read_data(lines, names, count, step)
                yield Frame(str(path), step, names, data, header, box)
                step = count = box = None
            else:
                raise lines.error(f"unknown item 'ITEM: {item}'")
        if not seen_any:
            raise at(path, 1, "empty file")
        if step is not None:
            raise lines.error(f"unexpected end of file: frame at step {step} has no data section",
                              lines.number + 1)


def iter_files(paths):
    """Frames of several files in order (e.g. ``dump ... bonds.*.dump`` or restarted runs)."""
    for path in paths:
        yield from iter_frames(path)


# --- bond dumps -----------------------------------------------------------------------------

def bond_column_map(frame):
    """Map canonical bond column names (BOND_COLUMNS) to column indices of ``frame``.

    ``c_ID[k]`` maps to the k-th wirenet/local column; a canonical name maps to itself; other
    names (``index``, variables) are ignored.
    """
    mapping = {}
    for index, name in enumerate(frame.names):
        match = _COMPUTE_COLUMN.match(name)
        if match:
            k = int(match.group(1))
            if 1 <= k <= len(BOND_COLUMNS):
                mapping.setdefault(BOND_COLUMNS[k - 1], index)
        elif name in BOND_COLUMNS:
            mapping.setdefault(name, index)
    return mapping


def require_columns(frame, mapping, wanted, what):
    """Raise (file:line of the column header) when a column of ``wanted`` is missing."""
    missing = [name for name in wanted if name not in mapping]
    if missing:
        labels = ", ".join(_label(name) for name in missing)
        raise at(frame.path, frame.header_line,
                 f"missing column{'s' if len(missing) > 1 else ''} {labels} ({what})")


def _label(name):
    if name in BOND_COLUMNS:
        return f"{name} (c_ID[{BOND_COLUMNS.index(name) + 1}])"
    return name


# --- node dumps -----------------------------------------------------------------------------

_POSITION_SETS = (("x", "y", "z"), ("xu", "yu", "zu"), ("xs", "ys", "zs"))


@dataclass
class Nodes:
    """Node positions of one frame, sorted by id."""
    step: int
    ids: np.ndarray
    types: np.ndarray
    xyz: np.ndarray
    extra: dict              # other numeric columns, by name

    def index_of(self, ids, path, line):
        """Row indices of ``ids``; PostprocessError (path:line) if an id is unknown."""
        ids = np.asarray(ids, dtype=np.int64)
        if len(ids) == 0:
            return np.zeros(0, dtype=np.int64)
        pos = np.searchsorted(self.ids, ids).clip(0, max(len(self.ids) - 1, 0))
        ok = self.ids[pos] == ids if len(self.ids) else np.zeros(len(ids), bool)
        if not np.all(ok):
            bad = int(ids[~ok][0])
            raise at(path, line, f"atom {bad} is not in the node dump at step {self.step}")
        return pos


def nodes_from_frame(frame):
    """Build Nodes from a ``dump custom`` frame with at least id and x y z (or xu.. / xs..)."""
    names = frame.names
    if "id" not in names:
        raise at(frame.path, frame.header_line, "missing column id (node dump)")
    cols = next((s for s in _POSITION_SETS if all(c in names for c in s)), None)
    if cols is None:
        raise at(frame.path, frame.header_line, "missing columns x y z (node dump)")
    xyz = np.column_stack([frame.column(c) for c in cols])
    if cols[0] == "xs":
        if frame.box is None:
            raise at(frame.path, frame.header_line, "scaled coordinates without box bounds")
        xyz = frame.box[:, 0] + xyz * (frame.box[:, 1] - frame.box[:, 0])
    ids = frame.integers(names.index("id"))
    order = np.argsort(ids, kind="stable")
    types = (frame.integers(names.index("type"), low=0) if "type" in names
             else np.zeros(len(ids), np.int64))
    skip = {"id", "type", *cols}
    extra = {n: frame.column(n)[order] for n in names if n not in skip}
    return Nodes(frame.step, ids[order], types[order], xyz[order], extra)


class NodeSeries:
    """All frames of one or more node dumps, looked up by time step."""

    def __init__(self, paths):
        self.paths = list(paths)
        self.frames = {}
        for frame in iter_files(self.paths):
            self.frames[frame.step] = nodes_from_frame(frame)

    def at_step(self, step, needed_by, line):
        """Nodes at exactly ``step``; error naming the bond dump line that needs them."""
        nodes = self.frames.get(step)
        if nodes is None:
            names = ", ".join(self.paths)
            raise at(needed_by, line, f"no frame at step {step} in node dump {names}")
        return nodes
