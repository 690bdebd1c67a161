"""The runner's architecture as doc/architecture.md states it, checked:

- a finished case is skipped on the next run into the same folder, whatever its kind (a tiny
  fence: the resume once raised KeyError for a fence);
- a deck table names its columns once (impact.in: impact_columns / impact_row;
  include/fence_impact.in: fence_columns / row), as many names as values, and the runner's
  readers ask only for names the deck writes;
- no parameter default is stated twice: no deck states a default for a key's deck variable
  (materials.in, the one home of the material numbers, aside), and no function of a kind
  module restates a key's default in a keyword parameter named like the key;
- a new kind needs only its module: the key tables, the template of `./wirenet new`, the
  checker, the study and the record pick up a kind's keys and facts from its class.
"""

import inspect
import json
import os
import re
import subprocess
import sys

import pytest

import lmp
from runner import schema
from runner.params import is_computed

DRIVER = lmp.ROOT / "wirenet"
INPUTS = lmp.ROOT / "inputs"


# --- the resume of a finished case -----------------------------------------------------------

# (without gravity: nothing to settle, so the settling is still at its first test, after 0.1 s)
TINY_FENCE = ["fence_compound", "--quick", "--np", "1", "--set", "fence.modules=1",
              "--set", "fence.duration=0.02", "--set", "fence.settle_time=0.15",
              "--set", "gravity=0", "--set", "fence.rest_time=0"]


def _wirenet(*args):
    return subprocess.run([str(DRIVER), *args], capture_output=True, text=True, timeout=900,
                          env=dict(os.environ, WIRENET_SETUP="skip", WIRENET_BUILD=str(lmp.BUILD)))


def test_a_finished_fence_is_skipped_on_the_next_run(tmp_path):
    """A tiny quick fence (one module, no gravity, 0.02 s of impact, no rest) run twice into
    the same folder: the second run finds it complete (status ok, block.csv, same mode and
    case values), skips it and exits 0, leaving its record as it was."""
    out = tmp_path / "out"
    first = _wirenet("run", *TINY_FENCE, "--out", str(out))
    assert first.returncode == 0, first.stderr[-2000:]
    record = out / "fence_compound" / "case.json"
    meta = json.loads(record.read_text())
    assert meta["status"] == "ok" and meta["kind"] == "fence" and meta["quick"] is True
    assert (out / "fence_compound" / "block.csv").is_file()
    before = record.read_text()
    second = _wirenet("run", *TINY_FENCE, "--out", str(out))
    assert second.returncode == 0, second.stderr[-2000:]
    assert "[case 1/1] fence_compound: complete, skipped" in second.stdout, second.stdout
    assert "running" not in second.stdout and "Traceback" not in second.stderr
    assert record.read_text() == before
    # another case value is another case: it runs again
    third = _wirenet("run", *TINY_FENCE, "--set", "fence.speed=4.0", "--out", str(out))
    assert third.returncode == 0, third.stderr[-2000:]
    assert "complete, skipped" not in third.stdout and "fence_compound: done" in third.stdout
    assert json.loads(record.read_text())["block"]["speed"] == 4.0


# --- deck tables name their columns once -----------------------------------------------------

def _deck_variable(path, name):
    """The text of `variable NAME string TEXT` in a deck (quotes removed)."""
    for line in path.read_text().splitlines():
        words = line.split(None, 3)
        if words[:3] == ["variable", name, "string"]:
            return words[3].strip().strip('"')
    raise AssertionError(f"{path}: no 'variable {name} string ...'")


def _values(row):
    """The $(...) values of a row, split at the commas outside parentheses; each part must be
    one immediate value."""
    parts, depth, start = [], 0, 0
    for k, c in enumerate(row):
        depth += (c == "(") - (c == ")")
        assert depth >= 0, row[:k + 1]
        if c == "," and depth == 0:
            parts.append(row[start:k])
            start = k + 1
    parts.append(row[start:])
    assert depth == 0
    for part in parts:
        assert part.startswith("$(") and part.endswith(")") and part.count("$(") == 1, part
    return parts


def _read_names(module, monkeypatch, workdir):
    """The column names a kind's read_table asks the deck's table for."""
    asked = []

    def read_deck_table(path, required=()):
        asked.append((os.path.basename(path), tuple(required)))
        return {name: [0.0, 1.0] for name in required}

    monkeypatch.setattr(module, "read_deck_table", read_deck_table)
    module.read_table(str(workdir))
    assert len(asked) == 1
    return asked[0]


@pytest.mark.parametrize("kind, deck, columns, row, table", [
    ("impact", INPUTS / "impact.in", "impact_columns", "impact_row", "impact.csv"),
    ("fence", INPUTS / "include" / "fence_impact.in", "fence_columns", "row", "fence.csv"),
])
def test_deck_tables_name_their_columns_once(kind, deck, columns, row, table, monkeypatch,
                                             tmp_path):
    import importlib
    module = importlib.import_module(f"runner.kinds.{kind}")
    names = _deck_variable(deck, columns).split(",")
    values = _values(_deck_variable(deck, row))
    assert len(names) == len(values), (len(names), len(values))
    assert len(set(names)) == len(names) and all(re.fullmatch(r"[a-z_][a-z0-9_]*", n)
                                                  for n in names), names
    text = deck.read_text()
    # the header once, from the names; every row from the one row variable
    assert re.search(r"^print\s+\$\{%s\} file \$\{out\}/%s" % (columns, table), text, re.M)
    assert len(re.findall(r"\$\{%s\}" % row, text)) >= 2
    # the runner reads by name, and only names the deck writes
    file, required = _read_names(module, monkeypatch, tmp_path)
    assert file == table == module.TABLE
    missing = sorted(set(required) - set(names))
    assert not missing, f"{module.__name__}.read_table asks for columns {deck.name} does not " \
                        f"write: {missing}"
    # every term of the kind's energy budget is made of the deck's columns
    assert {c for term in module.BUDGET for c in term.columns} <= set(names)


def test_the_reader_finds_each_value_by_its_name(tmp_path):
    """impact.csv with the deck's columns in a shuffled order: read_table returns each column
    under its own name (a reader by position would mix them up)."""
    from runner.kinds import impact
    names = _deck_variable(INPUTS / "impact.in", "impact_columns").split(",")
    shuffled = names[::-1]
    rows = [[float(names.index(n) + 1000 * r) for n in shuffled] for r in range(3)]
    (tmp_path / "impact.csv").write_text(",".join(shuffled) + "\n# Fix print output\n" + "".join(
        ",".join(repr(v) for v in row) + "\n" for row in rows))
    table = impact.read_table(str(tmp_path))
    for name in ("step", "vz", "w_bond_damping", "rx_mean", "jz_damp"):
        assert list(table[name]) == [names.index(name) + 1000.0 * r for r in range(3)], name


# --- no parameter default stated twice -------------------------------------------------------

def _key_vars():
    """{deck variable: the paths of the keys that name it} (a punch's and a fence's speed are
    one deck variable of two kinds)."""
    out = {}
    for key in schema.KEYS:
        if key.var is None:
            continue
        for name in ((key.var,) if isinstance(key.var, str) else key.var):
            out.setdefault(name, []).append(key.path)
    return {name: ", ".join(paths) for name, paths in out.items()}


def _deck_defaults(inputs=INPUTS):
    """[(deck, line number, variable, key)] of `variable NAME index VALUE` lines of the decks
    (materials.in aside) whose NAME is a key's deck variable."""
    by_var = _key_vars()
    found = []
    decks = sorted(inputs.glob("*.in")) + sorted((inputs / "include").glob("*.in"))
    for deck in decks:
        if deck.name == "materials.in":
            continue
        for k, line in enumerate(deck.read_text().splitlines(), 1):
            words = line.split()
            if len(words) >= 3 and words[0] == "variable" and words[2] == "index" and \
                    words[1] in by_var:
                found.append((str(deck.relative_to(inputs.parent)), k, words[1],
                              by_var[words[1]]))
    return found


def test_the_deck_check_finds_a_stated_default(tmp_path):
    """The check below bites: the key variables it looks for are there (gravity's g, damping's
    alpha, punch.speed's speed, ...); a deck line stating one is found, in a deck or an
    include, but not in materials.in, nor a deck's own switch or a variable set in an if."""
    by_var = _key_vars()
    assert {"g": "gravity", "alpha": "damping.local", "bond_zeta": "damping.bond",
            "kn": "contact.kn"}.items() <= by_var.items()
    assert "punch.speed" in by_var["speed"]
    inputs = tmp_path / "inputs"
    (inputs / "include").mkdir(parents=True)
    (inputs / "drop.in").write_text("variable out index .\nvariable g       index 9.81\n"
                                    'if "${x} > 0" then "variable alpha index 0.5"\n')
    (inputs / "include" / "part.in").write_text("# variable kn index 1\nvariable speed index 0.01\n")
    (inputs / "include" / "materials.in").write_text("variable kn index 1e9\n")
    assert _deck_defaults(inputs) == [("inputs/drop.in", 2, "g", "gravity"),
                                      ("inputs/include/part.in", 2, "speed", by_var["speed"])]


def test_no_deck_states_a_default_of_a_key():
    """A key's default lives in its declaration (runner/schema.py, runner/kinds/*.py) or, for a
    material number, in materials.in; a deck that states `variable NAME index VALUE` for a key's
    variable holds a second default that a run without the runner would use."""
    found = _deck_defaults()
    assert not found, "decks state defaults of keys: " + "; ".join(
        f"{deck}:{line}: {var} ({key})" for deck, line, var, key in found)


def _key_defaults():
    """{name a parameter may carry: [(key path, default)]} of every key: its name, its deck
    variable and its dotted path with underscores; the defaults of every kind and of --quick
    (computed defaults left out: they are no value)."""
    out = {}
    for key in schema.KEYS:
        values = [key.default, key.quick, *schema.defaults_by_kind(key).values()]
        values = [v for v in values if v is not None and not is_computed(v)]
        names = {key.name, key.path.replace(".", "_")}
        if key.var is not None:
            names |= {key.var} if isinstance(key.var, str) else set(key.var)
        for name in names:
            out.setdefault(name, []).extend((key.path, v) for v in values)
    return out


def _same(a, b):
    if isinstance(a, bool) or isinstance(b, bool):
        return isinstance(a, bool) and isinstance(b, bool) and a == b
    if isinstance(a, (int, float)) and isinstance(b, (int, float)):
        return float(a) == float(b)
    return type(a) is type(b) and a == b


def _kind_callables():
    """(qualified name, callable) of the functions, classes and methods the kind modules
    define."""
    import importlib
    out = []
    for path in sorted((lmp.ROOT / "runner" / "kinds").glob("*.py")):
        module = importlib.import_module(f"runner.kinds.{path.stem}")
        for name, obj in vars(module).items():
            if getattr(obj, "__module__", None) != module.__name__:
                continue
            if inspect.isfunction(obj):
                out.append((f"{path.name}:{name}", obj))
            elif inspect.isclass(obj):
                for attr, member in vars(obj).items():
                    if isinstance(member, (staticmethod, classmethod)):
                        member = member.__func__
                    if inspect.isfunction(member):
                        out.append((f"{path.name}:{name}.{attr}", member))
    return out


def test_no_kind_function_restates_a_key_default():
    """Keyword parameters of the kind modules (runner/kinds/*.py) named like a key (its name,
    deck variable or path) must not default to that key's value: the value comes from the
    checked case, and a second copy of the default goes stale when the key's changes."""
    defaults = _key_defaults()
    callables = _kind_callables()
    assert any(name.endswith("punch.py:Setup.__init__") for name, _ in callables)
    restated = []
    for name, function in callables:
        for parameter in inspect.signature(function).parameters.values():
            if parameter.default is inspect.Parameter.empty:
                continue
            for path, value in defaults.get(parameter.name, ()):
                if _same(parameter.default, value):
                    restated.append(f"{name}({parameter.name}={parameter.default!r}) restates "
                                    f"{path}'s default")
                    break
    assert not restated, "; ".join(restated)


def test_the_signature_check_bites():
    """A function like the old impact.Setup(workdir, dt_fraction=0.5, duration=None, alpha=...,
    mass=44.5) is found: dt_fraction restates impact.dt_fraction's default, alpha (damping.local's
    deck variable) the punch's local damping, mass impact.mass's; duration=None and a number no
    key has are not."""
    defaults = _key_defaults()
    by_path = schema.BY_PATH
    P = inspect.Parameter
    old = inspect.Signature([P("workdir", P.POSITIONAL_OR_KEYWORD)] + [
        P(name, P.POSITIONAL_OR_KEYWORD, default=value) for name, value in (
            ("dt_fraction", schema.default_of(by_path["impact.dt_fraction"], "impact")),
            ("duration", None),
            ("alpha", schema.default_of(by_path["damping.local"], "punch")),
            ("mass", by_path["impact.mass"].default),
            ("side", 12345.0))])
    found = {p.name for p in old.parameters.values()
             if p.default is not inspect.Parameter.empty and
             any(_same(p.default, v) for _, v in defaults.get(p.name, ()))}
    assert found == {"dt_fraction", "alpha", "mass"}


# --- a new kind needs only its module ----------------------------------------------------------

PROBE_KIND = '''
import json, os, sys
sys.path.insert(0, {root!r})
from runner import kinds
from runner.kinds.base import CaseKind
from runner.params import Key


class Probe(CaseKind):
    """A kind made for the test: no deck, its run writes one CSV and returns its facts."""
    name = "probe"
    summary = "a throwaway kind of the architecture test"
    keys = (Key("probe.level", "number", 2.0, "m", "how high the probe sits", "the test",
                low=0.0, high=10.0, quick=1.0, var="probe_level"),
            Key("probe.mode", "choice", "up", "", "where it points", "the test",
                choices=("up", "down")))
    takes = ("title", "gravity", "probe.*")
    defaults = {{"gravity": 0.0}}
    finished_file = "probe.csv"

    def run(self, index, ctx):
        with open(os.path.join(ctx.case_dir, "probe.csv"), "w") as fh:
            fh.write("level\\n%r\\n" % self.case["probe.level"])
        return {{"level": self.case["probe.level"], "mode": self.case["probe.mode"]}}


# the registry (runner/kinds/__init__.py): what listing the class there does
kinds.ALL = kinds.ALL + (Probe,)
kinds.NAMES = tuple(k.name for k in kinds.ALL)
kinds.BY_NAME["probe"] = Probe
# read only now: the schema collects the kinds' keys when it is imported
from runner import __main__ as cli, api, casefile, scheduler, schema, templates
import contextlib, io

out = {{"names": list(kinds.NAMES), "gravity_takers": schema.takers(schema.BY_PATH["gravity"])}}
text = io.StringIO()
with contextlib.redirect_stdout(text):
    out["new_exit"] = cli.main(["new", "probe"])
out["new"] = text.getvalue()
text = io.StringIO()
with contextlib.redirect_stdout(text):
    cli.main(["keys"])
out["keys"] = text.getvalue()
case = api.load('kind = "probe"\\n[probe]\\nmode = "down"\\n')
out["values"] = case.values
out["variables"] = kinds.of(case).key_variables()
out["quick"] = api.load('kind = "probe"\\n', quick=True).values
out["template_values"] = casefile.parse(out["new"], quick=False).values
errors = {{}}
for label, text in (("range", 'kind = "probe"\\n[probe]\\nlevel = 11.0\\n'),
                    ("choice", 'kind = "probe"\\n[probe]\\nmode = "sideways"\\n'),
                    ("foreign", 'kind = "probe"\\n[punch]\\nspeed = 1.0\\n'),
                    ("taken", 'kind = "punch"\\n[probe]\\nlevel = 1.0\\n'),
                    ("kind", 'kind = "probes"\\n')):
    try:
        api.load(text)
        errors[label] = None
    except casefile.CaseFileError as exc:
        errors[label] = str(exc)
out["errors"] = errors
study = {study!r}
scheduler.run_cases([case], study, False, 1)
out["record"] = json.load(open(os.path.join(study, "case", "case.json")))
from postprocess import report
out["summary"] = report.build(study, expected=["case"], figures=False)["cases"]
print("RESULT " + json.dumps(out))
'''


@pytest.fixture(scope="module")
def probe(tmp_path_factory):
    """The throwaway kind registered in a fresh interpreter (the registry is read when
    runner/schema.py is imported), its outputs as JSON."""
    folder = tmp_path_factory.mktemp("probe")
    script = folder / "probe.py"
    script.write_text(PROBE_KIND.format(root=str(lmp.ROOT), study=str(folder / "study")))
    p = subprocess.run([sys.executable, "-P", str(script)], capture_output=True, text=True,
                       cwd=folder, timeout=300)
    assert p.returncode == 0, p.stderr[-3000:]
    line = next(l for l in p.stdout.splitlines() if l.startswith("RESULT "))
    return json.loads(line[len("RESULT "):])


def test_a_new_kind_is_in_the_template_and_the_key_tables(probe):
    assert probe["new_exit"] == 0
    template = probe["new"]
    assert template.startswith("# WireNet case file: a probe case")
    assert 'kind = "probe"' in template and "[probe]" in template
    assert "level = 2.0" in template and 'mode = "up"' in template
    assert "gravity = 0.0" in template                       # its own default of a shared key
    assert "[panel]" not in template and "[punch]" not in template   # only what it takes
    # the template runs as it is: it parses to the kind's defaults
    assert probe["template_values"] == probe["values"] | {"probe.mode": "up"}
    tables = probe["keys"]
    assert "### probe" in tables
    assert "| `level` | number | m | [0, 10] | 2.0 (--quick: 1.0) | probe | how high the probe " \
           "sits | the test |" in tables
    assert "probe: a throwaway kind of the architecture test" in tables   # the `kind` key
    gravity = next(l for l in tables.splitlines() if l.startswith("| `gravity` |"))
    assert probe["gravity_takers"][-1] == "probe"
    assert "probe: 0.0" in gravity and f"| {', '.join(probe['gravity_takers'])} |" in gravity


def test_a_new_kind_is_checked_like_every_other(probe):
    assert probe["values"] == {"title": "", "gravity": 0.0, "probe.level": 2.0,
                               "probe.mode": "down"}
    assert probe["quick"]["probe.level"] == 1.0
    # the deck gets its keys' variables, named by the key
    assert probe["variables"] == {"g": "0.0", "probe_level": "2.0"}
    errors = probe["errors"]
    assert errors["range"].endswith("probe.level: must be <= 10, got 11 [m]"), errors["range"]
    assert "probe.mode: must be one of up, down, got 'sideways'" in errors["choice"]
    assert "punch.speed: only for kind 'punch' (this case is 'probe')" in errors["foreign"]
    assert "probe.level: only for kind 'probe' (this case is 'punch')" in errors["taken"]
    assert probe["names"][-1] == "probe"
    assert {"punch", "impact", "cantilever", "fence"} <= set(probe["names"])
    assert f"kind: must be one of {', '.join(probe['names'])}, got 'probes' (did you mean " \
        "'probe'?)" in errors["kind"]


def test_a_new_kind_runs_in_a_study_and_is_recorded_and_reported(probe):
    record = probe["record"]
    assert record["kind"] == "probe" and record["status"] == "ok"
    assert record["level"] == 2.0 and record["mode"] == "down"
    summary = probe["summary"]["case"]
    assert summary["kind"] == "probe" and summary["status"] == "ok"
