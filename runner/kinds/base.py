"""What every kind of case is: the keys it takes, the deck it runs, the case folders (units) it
writes, how wide and how long it runs (for the study's scheduler), and its run, which turns a
checked case (runner/casefile.Case) into deck variables, runs the deck through the engine, reads
the deck's outputs by name and returns the facts that case.json records.

A new kind is one module of runner/kinds/ with a subclass of CaseKind (listed in
runner/kinds/__init__.py), its deck in inputs/ (sharing inputs/include/) and its keys; nothing
else (doc/architecture.md).
"""

import threading
from dataclasses import dataclass

from postprocess import record

from .. import engine
from ..params import deck_text


@dataclass
class RunContext:
    """Where and how a unit of a case runs: its folder, the study's folder, the MPI ranks it may
    use, and the study's hand-over of cores and pre-loads."""
    case_dir: str
    study_dir: str
    ranks: int = 1
    label: str = None                 # the name progress lines carry (the case folder)
    # a restart file another case left that this one starts from (punch.preload_from), and the
    # event this case sets once its own restart for others is written
    start_from: str = None
    share_event: threading.Event = None

    def lend(self, cores):
        """Give cores back to the scheduler while part of the case has ended (negative: take
        them back)."""
        if self.label is not None:
            engine.release_cores(self.label, cores)


class CaseKind:
    """A kind of case. Subclasses set the class attributes and implement run()."""

    name = ""              # the case file's `kind`
    summary = ""           # one line for the key tables
    deck = ""              # inputs/NAME.in
    keys = ()              # the keys of its own section (runner/params.Key)
    takes = ()             # fnmatch patterns of every key it takes (its own and shared ones)
    defaults = {}          # its own defaults of shared keys: {path: value, ByKey or Derived}
    default_sources = {}   # the sources of those of its own defaults that are not the key's
    quick_defaults = {}    # its own --quick defaults of shared keys (a drapery's quick mesh is
                           # smaller than its full 10 m one, larger than the quick panel)
    not_taken = ""         # why a shared key it does not take is refused (completes the message)
    finished_file = ""     # the CSV of a case folder that shows the unit ended (resume)
    width = 1              # LIGGGHTS runs of a unit at the same time (the study's scheduler)

    def __init__(self, case):
        self.case = case

    # --- the case file ------------------------------------------------------------------------
    @classmethod
    def check(cls, case, fail):
        """Rules between keys (one kind's values that cannot make a test): ``fail(key,
        message)`` refuses the case. The base checks what every kind with a pre-load or output
        zones shares."""
        v = case.values
        if v.get("preload.mode") in ("sag", "settle") and not v["gravity"] > 0:
            fail("preload.mode", f"'{v['preload.mode']}' needs gravity > 0 (or preload.mode = "
                                 "'none')")
        names = [z["name"] for z in case.zones]
        if len(set(names)) != len(names):
            fail("output.zones", f"zone names must differ, got {names}")
        for z in case.zones:
            if not z["name"].replace("_", "").replace("-", "").isalnum():
                fail("output.zones.name", f"letters, digits, - and _ only, got {z['name']!r}")

    # --- the study's view ---------------------------------------------------------------------
    def units(self):
        """(case folder name, index) of each run of the case: one, except for sequences."""
        return [(self.case.name, 0)]

    def weight(self):
        """Relative cost, for the study to start the longest cases first."""
        return 1

    def record_kind(self):
        """case.json's kind (the report groups the cases by it)."""
        return self.name

    def run(self, index, ctx):
        """Run unit ``index`` in ctx.case_dir; return the facts for case.json."""
        raise NotImplementedError

    def verdict(self, facts):
        """(status, what happened and what to change) when the run did not do what the case
        says (postprocess/record.py's unsound statuses), None when it did."""
        return None

    # --- helpers ------------------------------------------------------------------------------
    def budget_verdict(self, facts):
        """BUDGET_OPEN when the energy budget or the momentum balance did not close to
        output.budget_tolerance, else None."""
        tol = self.case["output.budget_tolerance"]
        closure = (facts.get("energy") or {}).get("closure_error")
        momentum = (facts.get("momentum") or {}).get("error")
        for name, value in (("energy budget", closure), ("momentum balance", momentum)):
            if value is not None and not value <= tol:
                return (record.BUDGET_OPEN,
                        f"the {name} closes only to {value:.2%} (output.budget_tolerance "
                        f"{tol:.2%}): a mechanism is missing from it or the step is too large "
                        "(a smaller impact.dt_fraction / fence.dt shows which)")
        return None

    def material_values(self):
        """{materials.in name: value} of the case's materials and contact keys."""
        return {k.rsplit(".", 1)[1]: v for k, v in self.case.values.items()
                if k.startswith(("materials.", "contact."))}

    def item_variables(self, item, section):
        """-var values of the keys of one [[section]] entry (an impact) that name a deck
        variable."""
        return self._variables((self.case.keys[f"{section}.{name}"], value)
                               for name, value in item.items())

    def key_variables(self, *sections):
        """-var values of every key of these sections (all when none given) that names a deck
        variable: one home for the key -> deck variable step."""
        keys = self.case.keys
        return self._variables((keys[path], value) for path, value in self.case.values.items()
                               if not sections or keys[path].section in sections)

    @staticmethod
    def _variables(pairs):
        out = {}
        for key, value in pairs:
            if key.var is None:
                continue
            names = (key.var,) if isinstance(key.var, str) else key.var
            if len(names) == 1:
                out[names[0]] = deck_text(value)
            else:
                out.update((n, deck_text(v)) for n, v in zip(names, value))
        return out
