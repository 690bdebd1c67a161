"""One case-file key, declared once, as YADE declares a parameter: its type, default, unit, range,
meaning, the source of its default and the deck variable it becomes. runner/schema.py holds the
keys every kind shares; each kind module (runner/kinds/) declares the keys of its own section.

A default is a value, or computed from other keys of the same case:
- ``ByKey(path, {value of that key: default})``: a table (the platter's radius by its shape);
- ``Derived(function, text)``: a formula of the case's values (a sphere's height is its radius).
A kind may state its own default for a shared key (``CaseKind.defaults``): the key tables list
the default of each kind.
"""

import math
from dataclasses import dataclass


@dataclass(frozen=True)
class ByKey:
    """A default read from a table by the value of another key."""
    path: str
    table: dict

    def value(self, values):
        return self.table[values[self.path]]

    def text(self):
        return f"by {self.path}: " + ", ".join(f"{k} {_short(v)}" for k, v in self.table.items())


@dataclass(frozen=True)
class Derived:
    """A default computed from the case's other values (``function(values)``); ``text`` says how."""
    function: object
    text_: str

    def value(self, values):
        return self.function(values)

    def text(self):
        return self.text_


def _short(value):
    return f"{value:g}" if isinstance(value, float) else str(value)


def is_computed(default):
    return isinstance(default, (ByKey, Derived))


@dataclass(frozen=True)
class Key:
    """One case-file key.

    ``var``: the deck variable the value becomes (-var NAME VALUE; a vector: one name per
    component, or one name for the whole vector as "x y z"); None: the kind uses the value in
    Python (it shapes the net, the run or the outputs). ``quick``: the value of --quick. ``range``
    (low, high) with ``low_open``/``high_open``: the physical range; a value outside is refused
    before anything runs. ``per_item``: a key of each [[impact]] / [[output.zones]] entry."""
    path: str
    type: str         # number, integer, bool, text, choice, vector2, vector3, quat, pairs,
    #                   list-int, file, bending
    default: object
    unit: str
    doc: str
    source: str
    choices: tuple = ()
    low: float = None
    high: float = None
    low_open: bool = False
    high_open: bool = False
    quick: object = None
    per_item: bool = False
    var: object = None

    @property
    def section(self):
        return self.path.rsplit(".", 1)[0] if "." in self.path else ""

    @property
    def name(self):
        return self.path.rsplit(".", 1)[-1]

    def in_range(self, value):
        """'' when value lies in the key's range, else the rule it breaks ('must be > 0')."""
        if self.low is not None and (value <= self.low if self.low_open else value < self.low):
            return f"must be {'>' if self.low_open else '>='} {self.low:g}"
        if self.high is not None and (value >= self.high if self.high_open else value > self.high):
            return f"must be {'<' if self.high_open else '<='} {self.high:g}"
        return ""

    def range_text(self):
        """The range as the key tables show it ('(0, 0.02]', '>= 0', '')."""
        if self.low is None and self.high is None:
            return ""
        if self.high is None:
            return f"{'>' if self.low_open else '>='} {self.low:g}"
        if self.low is None:
            return f"{'<' if self.high_open else '<='} {self.high:g}"
        return (f"{'(' if self.low_open else '['}{self.low:g}, {self.high:g}"
                f"{')' if self.high_open else ']'}")


def deck_text(value):
    """A value as LIGGGHTS' -var takes it: full precision numbers, a vector as its components
    separated by spaces (one deck word each once substituted), true/false as 1/0."""
    if isinstance(value, bool):
        return "1" if value else "0"
    if isinstance(value, float):
        return repr(value) if math.isfinite(value) else str(value)
    if isinstance(value, (list, tuple)):
        return " ".join(deck_text(v) for v in value)
    return str(value)
