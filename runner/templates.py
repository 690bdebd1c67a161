"""Text made from the schema: the case-file templates of `./wirenet new` and the key tables of
doc/case_files.md (tests/python/test_case_files.py keeps the doc equal to them)."""

import textwrap

from .params import is_computed
from .schema import KEYS, PAPER, applies, default_of, defaults_by_kind, source_of

SECTION_TITLES = {
    "": "the case", "panel": "[panel] the net (wirenet-gen)", "supports": "[supports] edges",
    "preload": "[preload] before the load", "materials": "[materials] wires and ropes",
    "contact": "[contact] net-body and node-node contacts", "damping": "[damping]",
    "punch": "[punch] the platter", "impact": "[impact] the block ([[impact]] tables: "
    "successive impacts on the same net)", "cantilever": "[cantilever]",
    "fence": "[fence] the fence and its block (kind fence; doc/fence.md)",
    "output": "[output] intervals of the outputs",
    "output.zones": "[[output.zones]] circles whose bond tensions are summed per family",
    "ensemble": "[ensemble] members, sweeps and sensitivity studies of the case (doc/ensembles.md)"}


def toml_value(value):
    if isinstance(value, bool):
        return "true" if value else "false"
    if isinstance(value, str):
        return f'"{value}"'
    if isinstance(value, float):
        return repr(value)
    if isinstance(value, list):
        return "[" + ", ".join(toml_value(v) for v in value) + "]"
    return str(value)


def _applies(key, kind):
    return applies(key, kind) and key.path != "kind"


def _sections(kind):
    order = []
    for key in KEYS:
        if _applies(key, kind) and key.section not in order:
            order.append(key.section)
    return order


def template(kind):
    """A case file with every key of the kind at its default, each with its meaning, unit and
    source: it runs as it is (the paper's case of that kind on the hexagonal panel)."""
    lines = [f"# WireNet case file: a {kind} case (doc/case_files.md). Every key below is at its",
             "# default; delete what you do not change. Run: ./wirenet run THIS.toml [--quick]",
             "", f'kind = "{kind}"']
    for section in _sections(kind):
        keys = [k for k in KEYS if _applies(k, kind) and k.section == section]
        if section:
            header = f"[[{section}]]" if section == "output.zones" else f"[{section}]"
            lines += ["", header]
        for key in keys:
            doc = f"{key.doc}" + (f" [{key.unit}]" if key.unit else "")
            lines += [f"# {line}" for line in textwrap.wrap(doc, 94)]
            value = default_of(key, kind)
            if is_computed(value):
                lines.append(f"# {key.name} = ...   (default: {value.text()})")
            else:
                lines.append(f"{key.name} = {toml_value(value)}")
    return "\n".join(lines) + "\n"


def _value_text(value):
    return value.text() if is_computed(value) else toml_value(value)


def _default_text(key):
    by_kind = defaults_by_kind(key)
    values = list(by_kind.values())
    if key.path == "kind":
        text = "(required)"
    elif values and all(v == values[0] for v in values):
        text = _value_text(values[0])
    else:
        text = ", ".join(f"{k}: {_value_text(v)}" for k, v in by_kind.items())
    quick = kinds_with_quick(key)
    parts = [f"{k.name}: {_value_text(k.quick_defaults[key.path])}" for k in quick]
    if key.quick is not None:
        own = [k.name for k in kinds_with_own(key) if k not in quick]
        parts.insert(0, _value_text(key.quick) + (
            f"; {', '.join(own)}: {'its' if len(own) == 1 else 'their'} own" if own else ""))
    if parts:
        text += " (--quick: " + "; ".join(parts) + ")"
    return text.replace("|", "\\|")


def _type_text(key):
    if key.choices:
        return " \\| ".join(key.choices)
    return {"vector2": "[x, y]", "vector3": "[x, y, z]", "quat": "[w, x, y, z]",
            "pairs": "[[e, s], ...]", "list-int": "[n, ...]", "list-number": "[x, ...]",
            "values": "[value, ...]", "keys": "[\"key\", ...] or \"unsourced\"",
            "bending": "number or \"calibrated\""}.get(key.type, key.type)


def kinds_with_own(key):
    """The kinds that state their own default of the key (it stands in --quick too)."""
    from . import kinds
    return [k for k in kinds.ALL if key.path in k.defaults and applies(key, k.name)]


def kinds_with_quick(key):
    """The kinds that state their own --quick default of the key."""
    from . import kinds
    return [k for k in kinds.ALL if key.path in k.quick_defaults and applies(key, k.name)]


def kind_names():
    from . import kinds
    return kinds.NAMES


def _source_text(key, taken):
    """The key's source, and a kind's own where it states its own default with another."""
    text = (key.source or "-").replace(PAPER, "paper")
    own = [f"{n}: {source_of(key, n)}" for n in taken if source_of(key, n) != key.source]
    return "; ".join([text] + own).replace("|", "/")


def key_tables():
    """Markdown tables of every key, one per section."""
    out = []
    for section in [""] + sorted({k.section for k in KEYS if k.section},
                                 key=lambda s: [k.section for k in KEYS].index(s)):
        keys = [k for k in KEYS if k.section == section]
        out += [f"### {SECTION_TITLES.get(section, section)}", "",
                "| key | type | unit | range | default | kinds | meaning | source |",
                "|---|---|---|---|---|---|---|---|"]
        for k in keys:
            taken = [n for n in kind_names() if applies(k, n)]
            out.append(f"| `{k.name}` | {_type_text(k)} | {k.unit or '-'} | "
                       f"{k.range_text() or '-'} | {_default_text(k)} | "
                       f"{', '.join(taken) if len(taken) < len(kind_names()) else 'all'} | "
                       f"{k.doc.replace('|', '/')} | "
                       f"{_source_text(k, taken)} |")
        out.append("")
    return "\n".join(out)
