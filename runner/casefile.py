"""Case files: read (tomllib), apply --set overrides, check every key against runner/schema.py,
fill the defaults. A mistake is one CaseFileError naming the file and the key.

The result, a ``Case``, holds a value for every key of its kind (defaults filled, --quick
defaults where they differ) and the lists of impacts and output zones.
"""

import difflib
import math
import os
import tomllib
from dataclasses import dataclass, field

from . import kinds
from .errors import CaseFileError
from .params import is_computed
from .schema import BY_PATH, KEYS, LIST_SECTIONS, SECTIONS, applies, default_of, has_quick, takers

__all__ = ["Case", "CaseFileError", "read", "parse", "apply_override"]


@dataclass
class Case:
    name: str                       # the file's stem: the case folder's name
    path: str                       # absolute path of the case file
    kind: str
    values: dict                    # dotted key -> value (every scalar key of the kind)
    impacts: list = field(default_factory=list)    # one dict name -> value per impact
    zones: list = field(default_factory=list)      # one dict name -> value per zone
    quick: bool = False
    stated: frozenset = frozenset()                # the keys the file (or --set) states
    keys: dict = field(default_factory=dict, repr=False)   # path -> its params.Key (the schema's)
    # --quick: stated keys whose value differs from the default and keeps the case large or long
    kept_long: tuple = ()
    # a member of an ensemble (runner/ensemble.py): the ensemble's name and the case-file text
    # the member was checked from (written to its folder as case.toml)
    member_of: str = ""
    member_text: str = field(default="", repr=False)

    def __getitem__(self, path):
        return self.values[path]


# ---------------------------------------------------------------------------------------------
# reading

def read(path, overrides=(), quick=False, name=None):
    """The Case of a case file with ``overrides`` ("KEY=VALUE" strings) applied."""
    path = os.path.abspath(path)
    try:
        with open(path, "rb") as handle:
            raw = tomllib.load(handle)
    except FileNotFoundError:
        raise CaseFileError(f"{path}: no such case file") from None
    except OSError as exc:
        raise CaseFileError(f"{path}: {exc.strerror}") from None
    except (tomllib.TOMLDecodeError, UnicodeDecodeError) as exc:
        raise CaseFileError(f"{path}: not valid TOML: {exc}") from None
    for text in overrides:
        apply_override(raw, text, path)
    return Checker(path, raw, quick, name).case()


def parse(text, path="<text>", quick=False, name="case"):
    """The Case of case-file text (tests, templates)."""
    path = os.path.abspath(path)
    try:
        raw = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise CaseFileError(f"{path}: not valid TOML: {exc}") from None
    return Checker(path, raw, quick, name).case()


def apply_override(raw, text, path):
    """--set KEY=VALUE: VALUE is read as a TOML value (a bare word is text). KEY is dotted;
    impact.N.KEY / output.zones.N.KEY address the N-th entry (from 1) of a list section, a
    list section's KEY without N every entry."""
    key, sep, value = text.partition("=")
    key = key.strip()
    if not sep or not key:
        raise CaseFileError(f"--set {text}: expected KEY=VALUE")
    try:
        parsed = tomllib.loads(f"v = {value.strip()}")["v"]
    except tomllib.TOMLDecodeError:
        parsed = value.strip()
    parts = key.split(".")
    for section in LIST_SECTIONS:
        depth = section.count(".") + 1
        if parts[:depth] == section.split(".") and len(parts) > depth:
            entries = _entries(raw, section)
            rest = parts[depth:]
            if rest[0].isdigit():
                k = int(rest[0])
                if not 1 <= k <= len(entries):
                    raise CaseFileError(f"--set {key}: the case file has {len(entries)} "
                                        f"{section} entries")
                targets, rest = [entries[k - 1]], rest[1:]
            else:
                targets = entries or [_new_entry(raw, section)]
            for entry in targets:
                entry[".".join(rest)] = parsed
            return
    table = raw
    for part in parts[:-1]:
        table = table.setdefault(part, {})
        if not isinstance(table, dict):
            raise CaseFileError(f"--set {key}: '{part}' is not a table")
    table[parts[-1]] = parsed


def _entries(raw, section):
    table = raw
    for part in section.split(".")[:-1]:
        table = table.get(part, {})
    value = table.get(section.split(".")[-1]) if isinstance(table, dict) else None
    if isinstance(value, dict):
        return [value]
    return value if isinstance(value, list) else []


def _new_entry(raw, section):
    table = raw
    parts = section.split(".")
    for part in parts[:-1]:
        table = table.setdefault(part, {})
    entry = {}
    table[parts[-1]] = entry
    return entry


# ---------------------------------------------------------------------------------------------
# checking

def resolve(values):
    """Replace computed defaults (params.ByKey, params.Derived) by their values, in as many
    passes as their dependencies need."""
    for _ in range(len(values) + 1):
        pending = [p for p, v in values.items() if is_computed(v)]
        if not pending:
            return values
        for path in pending:
            default = values[path]
            needed = [default.path] if hasattr(default, "path") else []
            if any(is_computed(values.get(n)) for n in needed):
                continue
            try:
                values[path] = default.value(values)
            except KeyError:
                continue          # it depends on a computed value not resolved yet
    raise RuntimeError(f"schema: computed defaults depend on each other: {pending}")


def _suggest(word, candidates):
    match = difflib.get_close_matches(word, candidates, n=1, cutoff=0.6)
    return f" (did you mean '{match[0]}'?)" if match else ""


def _kind_name(value):
    return {bool: "true/false", int: "a number", float: "a number", str: "text",
            list: "a list", dict: "a table"}.get(type(value), type(value).__name__)


class Checker:
    """Walks the raw TOML of one case file against the schema."""

    def __init__(self, path, raw, quick, name):
        self.path, self.raw, self.quick = path, raw, quick
        self.name = name or os.path.splitext(os.path.basename(path))[0]

    def fail(self, key, message):
        raise CaseFileError(f"{self.path}: {key}: {message}")

    def case(self):
        kind = self.raw.get("kind")
        if kind is None:
            self.fail("kind", f"missing ({', '.join(kinds.NAMES)})")
        kind = self.value(BY_PATH["kind"], kind, "kind")
        flat = {}
        self.flatten(self.raw, "", flat)
        flat.pop("kind")
        stated = frozenset(flat)
        values = {}
        for key in KEYS:
            if key.per_item or key.path == "kind" or not applies(key, kind):
                continue
            if key.path in flat:
                values[key.path] = self.value(key, flat.pop(key.path), key.path)
            else:
                values[key.path] = default_of(key, kind, self.quick)
        for path in sorted(flat):
            self.not_for_this_kind(path, kind)
            self.unknown(path)
        for section in LIST_SECTIONS:
            if _entries(self.raw, section) and not any(
                    applies(k, kind) for k in KEYS if k.section == section):
                first = _entries(self.raw, section)[0]
                name = next(iter(first), "") if isinstance(first, dict) else ""
                key = BY_PATH.get(f"{section}.{name}") or next(
                    k for k in KEYS if k.section == section)
                self.not_for_this_kind(key.path, kind,
                                       label=f"{section}.{name}".rstrip(".")
                                       if section == "impact" else section)
        resolve(values)
        kept = self.quick_over_stated(values, stated, kind)
        impacts = self.items("impact", kind) if applies(BY_PATH["impact.mass"], kind) else []
        if applies(BY_PATH["impact.mass"], kind) and not impacts:
            impacts = [self.item_defaults("impact", kind)]
        kept += self.quick_items(impacts, "impact", kind)
        zones = []
        if applies(BY_PATH["output.zones.name"], kind):
            zones = self.items("output.zones", kind) or [self.item_defaults("output.zones", kind)]
        case = Case(self.name, self.path, kind, values, impacts, zones, self.quick, stated,
                    BY_PATH, tuple(kept))
        self.cross_checks(case)
        return case

    def quick_over_stated(self, values, stated, kind):
        """--quick is always quick: a stated value that equals the full default (a template
        states them all) takes the quick value as an unstated key does; a value that differs is
        the user's choice and is kept (returned, so that the run says which keys keep it
        large)."""
        if not self.quick:
            return []
        kept = []
        for path in sorted(stated):
            key = BY_PATH.get(path)
            if key is None or not has_quick(key, kind) or key.per_item:
                continue
            full = resolve({**values, path: default_of(key, kind, False)})[path]
            if values[path] == full:
                values[path] = default_of(key, kind, True)
            else:
                kept.append((path, values[path]))
        resolve(values)
        return kept

    def quick_items(self, items, section, kind):
        """quick_over_stated for the entries of a list section (each [[impact]])."""
        if not self.quick:
            return []
        kept = []
        for k, item in enumerate(items, 1):
            for name, value in item.items():
                key = BY_PATH[f"{section}.{name}"]
                if key.quick is None:
                    continue
                if value == default_of(key, kind, False):
                    item[name] = default_of(key, kind, True)
                elif value != default_of(key, kind, True):
                    kept.append((f"{section}[{k}].{name}" if len(items) > 1
                                 else f"{section}.{name}", value))
        return kept

    def not_for_this_kind(self, path, kind, label=None):
        """Refuse a known key that this kind does not take, naming the kinds that do (``label``:
        what the message names, the key by default)."""
        label = label or path
        key = BY_PATH.get(path)
        if key is None:
            section = path.split(".")[0]
            if not any(k.path.startswith(path + ".") for k in KEYS) or path == section and \
                    any(applies(k, kind) for k in KEYS if k.section == section):
                return
            keys = [k for k in KEYS if k.path.startswith(path + ".")]
        else:
            keys = [key]
        if any(applies(k, kind) for k in keys):
            return
        note = kinds.BY_NAME[kind].not_taken
        if note and path.split(".")[0] in ("panel", "supports", "preload", "output"):
            self.fail(label, note)
        others = sorted({n for k in keys for n in takers(k)})
        names = ", ".join(f"'{n}'" for n in others)
        self.fail(label, f"only for kind{'s' if len(others) > 1 else ''} {names} "
                        f"(this case is '{kind}')")

    def flatten(self, table, prefix, out):
        for name, value in table.items():
            path = f"{prefix}{name}"
            if path in LIST_SECTIONS:
                continue
            if isinstance(value, dict) and path not in BY_PATH:
                if path not in SECTIONS:
                    self.unknown(path)
                self.flatten(value, path + ".", out)
            else:
                out[path] = value

    def unknown(self, path):
        if path in SECTIONS:
            self.fail(path, f"is a section of keys ([{path}] in the file, {path}.KEY with --set), "
                            "not a value")
        known = [k.path for k in KEYS] + SECTIONS
        self.fail(path, "unknown key" + _suggest(path, known))

    def items(self, section, kind):
        entries = _entries(self.raw, section)
        raw = self.raw
        for part in section.split(".")[:-1]:
            raw = raw.get(part, {}) if isinstance(raw, dict) else {}
        value = raw.get(section.split(".")[-1]) if isinstance(raw, dict) else None
        if value is not None and not isinstance(value, (dict, list)):
            self.fail(section, f"must be a table [{section}] or tables [[{section}]], got "
                               f"{_kind_name(value)} {value!r}")
        out = []
        for k, entry in enumerate(entries, 1):
            if not isinstance(entry, dict):
                self.fail(f"{section}[{k}]", "must be a table")
            item = self.item_defaults(section, kind)
            for name, value in entry.items():
                path = f"{section}.{name}"
                key = BY_PATH.get(path)
                label = f"{section}[{k}].{name}" if len(entries) > 1 else path
                if key is None:
                    names = [p.rsplit(".", 1)[1] for p in BY_PATH if p.startswith(section + ".")]
                    self.fail(label, "unknown key" + _suggest(name, names))
                item[name] = self.value(key, value, label)
            out.append(item)
        return out

    def item_defaults(self, section, kind):
        return {k.name: default_of(k, kind, self.quick) for k in KEYS
                if k.per_item and k.section == section}

    # --- one value ----------------------------------------------------------------------------
    def value(self, key, value, label):
        check = getattr(self, "_" + key.type.replace("-", "_"))
        return check(key, value, label)

    def _number(self, key, value, label):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            self.fail(label, f"must be a number [{key.unit or '-'}], got {_kind_name(value)} "
                             f"{value!r}")
        if not math.isfinite(value):
            self.fail(label, f"must be a finite number, got {value}")
        rule = key.in_range(value)
        if rule:
            self.fail(label, f"{rule}, got {value:g}" + (f" [{key.unit}]" if key.unit else ""))
        return float(value)

    def _integer(self, key, value, label):
        if isinstance(value, bool) or not isinstance(value, int):
            self.fail(label, f"must be an integer, got {_kind_name(value)} {value!r}")
        rule = key.in_range(value)
        if rule:
            self.fail(label, f"{rule}, got {value}")
        return value

    def _text(self, key, value, label):
        if not isinstance(value, str):
            self.fail(label, f"must be text, got {_kind_name(value)} {value!r}")
        return value

    def _file(self, key, value, label):
        return self._text(key, value, label)

    def _bool(self, key, value, label):
        if not isinstance(value, bool):
            self.fail(label, f"must be true or false, got {value!r}")
        return value

    def _choice(self, key, value, label):
        if not isinstance(value, str) or value not in key.choices:
            self.fail(label, f"must be one of {', '.join(key.choices)}, got {value!r}"
                             + (_suggest(value, key.choices) if isinstance(value, str) else ""))
        return value

    def _bending(self, key, value, label):
        if value == "calibrated":
            return value
        if isinstance(value, str):
            self.fail(label, f"must be a number >= 0 or 'calibrated', got {value!r}")
        return self._number(key, value, label)

    def _vector(self, key, value, label, n):
        if (not isinstance(value, list) or len(value) != n or
                any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in value)):
            self.fail(label, f"must be a list of {n} numbers [{key.unit or '-'}], got {value!r}")
        if not all(math.isfinite(v) for v in value):
            self.fail(label, f"must be finite numbers, got {value!r}")
        return [float(v) for v in value]

    def _vector2(self, key, value, label):
        return self._vector(key, value, label, 2)

    def _vector3(self, key, value, label):
        vector = self._vector(key, value, label, 3)
        if not any(vector):
            self.fail(label, "must not be zero")
        return vector

    def _quat(self, key, value, label):
        q = self._vector(key, value, label, 4)
        norm = math.sqrt(sum(v * v for v in q))
        if not norm > 1e-12:
            self.fail(label, "must be a non-zero quaternion [w, x, y, z]")
        return [v / norm for v in q]

    def _pairs(self, key, value, label):
        if not isinstance(value, list) or not value:
            self.fail(label, f"must be a list of [strain, stress] pairs, got {value!r}")
        pairs = [self._vector(key, p, f"{label}[{k}]", 2) for k, p in enumerate(value, 1)]
        strains = [p[0] for p in pairs]
        if strains[0] <= 0 or any(b <= a for a, b in zip(strains, strains[1:])):
            self.fail(label, "strains must be > 0 and increasing")
        if any(p[1] <= 0 for p in pairs):
            self.fail(label, "stresses must be > 0")
        return pairs

    def _list_number(self, key, value, label):
        if (not isinstance(value, list) or not value or
                any(isinstance(v, bool) or not isinstance(v, (int, float)) for v in value)):
            self.fail(label, f"must be a list of numbers [{key.unit or '-'}], got {value!r}")
        return [self._number(key, v, f"{label}[{k}]") for k, v in enumerate(value, 1)]

    def _values(self, key, value, label):
        """A list of values of another key (a sweep's): each is checked as that key takes it
        when the members are made (runner/ensemble.py); here only that it is a list."""
        if not isinstance(value, list):
            self.fail(label, f"must be a list of values, got {_kind_name(value)} {value!r}")
        return value

    def _keys(self, key, value, label):
        """A list of key paths (text), or the word 'unsourced'."""
        if value == "unsourced":
            return value
        if not isinstance(value, list) or not all(isinstance(v, str) for v in value):
            self.fail(label, f"must be a list of keys or 'unsourced', got {value!r}")
        return value

    def _list_int(self, key, value, label):
        if (not isinstance(value, list) or not value or
                any(isinstance(v, bool) or not isinstance(v, int) or v < 1 for v in value)):
            self.fail(label, f"must be a list of integers >= 1, got {value!r}")
        return value

    # --- keys that depend on each other ---------------------------------------------------------
    def cross_checks(self, case):
        """The rules of the kind (CaseKind.check), each failing with one line naming a key."""
        kinds.BY_NAME[case.kind].check(case, self.fail)
