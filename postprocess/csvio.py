"""Small CSV reader/writer for the study files (numeric columns plus named text columns)."""

import csv
import io
import math
import os

import numpy as np

from .errors import PostprocessError, at
from .output import write_text


def read_csv(path, required=(), text_columns=("family", "case", "status")):
    """Read a CSV with a header into {column: array}; numeric unless in ``text_columns``.

    Errors (missing file, empty file, missing columns, ragged rows, non-numbers, NaN or infinite
    numbers) name the file and the line.
    """
    try:
        with open(path, "r", encoding="utf-8", newline="") as handle:
            rows = list(csv.reader(handle))
    except OSError as exc:
        raise PostprocessError(f"{path}: {exc.strerror or exc}") from None
    except UnicodeDecodeError as exc:
        raise PostprocessError(f"{path}: not a UTF-8 text file (byte {exc.start})") from None
    except csv.Error as exc:
        raise PostprocessError(f"{path}: not a CSV file: {exc}") from None
    if not rows or not any(cell.strip() for cell in rows[0]):
        raise at(path, 1, "empty file (no header)")
    header = [cell.strip() for cell in rows[0]]
    missing = [name for name in required if name not in header]
    if missing:
        raise at(path, 1, f"missing column{'s' if len(missing) > 1 else ''} "
                          f"{', '.join(missing)}")
    body = []
    for number, row in enumerate(rows[1:], start=2):
        if not row or not any(cell.strip() for cell in row):
            continue
        if len(row) != len(header):
            raise at(path, number, f"expected {len(header)} columns, got {len(row)}")
        body.append((number, row))
    columns = {}
    for index, name in enumerate(header):
        cells = [row[index].strip() for _, row in body]
        if name in text_columns:
            columns[name] = np.array(cells, dtype=object)
            continue
        try:
            columns[name] = np.array(cells, dtype=float) if cells else np.zeros(0)
        except ValueError:
            for number, row in body:
                try:
                    float(row[index])
                except ValueError:
                    raise at(path, number, f"column {name}: not a number: "
                                           f"'{row[index].strip()}'") from None
        bad = np.flatnonzero(~np.isfinite(columns[name]))
        if bad.size:
            number, row = body[int(bad[0])]
            raise at(path, number, f"column {name}: not a finite number: "
                                   f"'{row[index].strip()}'")
    return columns


def read_deck_table(path, required=()):
    """A deck's CSV written by print + fix print ... append (impact.csv, fence.csv): the comment
    line fix print adds when it appends is dropped (into NAME_rows.csv beside it, which
    read_csv then reads with its checks); fewer than two rows is an error."""
    clean = os.path.splitext(path)[0] + "_rows.csv"
    try:
        with open(path) as src, open(clean, "w") as dst:
            dst.writelines(line for line in src if not line.startswith("#"))
    except OSError as exc:
        raise PostprocessError(f"{path}: {exc.strerror or exc}") from None
    table = read_csv(clean, required=required)
    if len(table[required[0] if required else next(iter(table))]) < 2:
        raise PostprocessError(f"{path}: fewer than two rows")
    return table


def format_number(value):
    """Shortest faithful text for a float (integers without a decimal point); NaN and infinite
    values are written as nan / inf (read_csv refuses them)."""
    value = float(value)
    if not math.isfinite(value):
        return repr(value)
    if value.is_integer() and abs(value) < 1e15:
        return str(int(value))
    return repr(value)


def write_csv(path, header, rows):
    """Write rows (sequences of str/float) atomically; floats via format_number."""
    buffer = io.StringIO()
    writer = csv.writer(buffer, lineterminator="\n")
    writer.writerow(header)
    for row in rows:
        writer.writerow([cell if isinstance(cell, str) else format_number(cell) for cell in row])
    write_text(path, buffer.getvalue())
