"""The study's scheduler (runner/scheduler.run_cases) with stand-in cases that only sleep: the
longest cases start first, a case starts on the core a punch gives back when its run or twin
ends (before the punch ends), the impacts of a sequence wait for each other, a case that starts
from another's pre-load waits for it without holding a core, and a study on one core runs its
cases one after the other."""

import os
import threading
import time

import pytest

from runner import engine, kinds, scheduler
from runner.kinds.base import CaseKind
from runner.kinds.impact import Impact
from runner.kinds.punch import Punch

# the real kinds' relative costs (the study starts the longest first)
WEIGHT = {"punch": Punch.WEIGHT, "impact": Impact.WEIGHT}


class FakeCase:
    def __init__(self, name, kind, net, width=1, units=1):
        self.name, self.kind, self.path = name, kind, f"{name}.toml"
        self.values = {"kind": kind, "panel.net": net, "title": name}
        self.impacts, self.zones = [{}] * units, []
        self.width_, self.units_ = width, units
        self.member_of = ""          # not a member of an ensemble (runner/ensemble.py)

    def __getitem__(self, key):
        return self.values[key]


class FakeRunner(CaseKind):
    """A kind (on runner/kinds/base.CaseKind) that sleeps; a width-2 case (a punch
    pair) gives one core back half-way; a source of punch.preload_from writes its hand-over
    restart and sets the event the scheduler gave it."""
    log, lock, starts_from = [], threading.Lock(), {}
    finished_file = "x.csv"

    def __init__(self, case):
        super().__init__(case)
        self.width = case.width_

    def units(self):
        n = self.case.units_
        return [(self.case.name if k == 0 else f"{self.case.name}_{k + 1}", k) for k in range(n)]

    def weight(self):
        return WEIGHT[self.case.kind][self.case["panel.net"]]

    def record_kind(self):
        return self.case.kind

    def run(self, index, ctx):
        name = self.units()[index][0]
        self._note("start", name)
        self.starts_from[name] = ctx.start_from
        time.sleep(0.3)
        if ctx.share_event is not None:   # a source of punch.preload_from: its pre-load is done
            os.makedirs(os.path.join(ctx.case_dir, "run"), exist_ok=True)
            with open(os.path.join(ctx.case_dir, "run", "preload.restart"), "w") as fh:
                fh.write("restart\n")
            self._note("preloaded", name)
            ctx.share_event.set()
        if self.case.width_ == 2:
            engine.release_cores(engine.current_label(), 1)
            self._note("release", name)
        time.sleep(1.5 if self.case.width_ == 2 else 0.3)   # room for the 0.2 s poll
        self._note("end", name)
        return {}

    def _note(self, what, name):
        with self.lock:
            self.log.append((time.monotonic(), what, name))


@pytest.fixture
def fake(monkeypatch):
    FakeRunner.log, FakeRunner.starts_from = [], {}
    monkeypatch.setattr(kinds, "of", FakeRunner)
    return FakeRunner


def events(log, what):
    return {name: t for t, w, name in log if w == what}


def test_longest_first_and_a_released_core_is_used(fake, tmp_path):
    loaded = [FakeCase("impact_square", "impact", "square"),
              FakeCase("calibration", "punch", "square", width=2),
              FakeCase("punch_compound", "punch", "compound", width=2),
              FakeCase("impact_hex", "impact", "hex")]
    scheduler.run_cases(loaded, str(tmp_path), quick=True, np_=2)
    start, release, end = (events(fake.log, w) for w in ("start", "release", "end"))
    order = [name for _, w, name in sorted(fake.log) if w == "start"]
    # the compound punch takes both cores first, whatever the list order
    assert order[0] == "punch_compound"
    # impact_hex (next by weight) starts on the core the punch gave back, before the punch ends
    assert release["punch_compound"] <= start["impact_hex"] < end["punch_compound"]
    # the calibration pair waits for a free core (one released or ended), never starts first
    assert start["calibration"] >= min(end["impact_hex"], end["punch_compound"])
    assert set(end) == {c.name for c in loaded}


def test_a_sequence_waits_and_one_core_runs_one_case_at_a_time(fake, tmp_path):
    loaded = [FakeCase("impact_compound", "impact", "compound", units=2),
              FakeCase("impact_hex", "impact", "hex")]
    scheduler.run_cases(loaded, str(tmp_path), quick=True, np_=1)
    spans = sorted((events(fake.log, "start")[n], events(fake.log, "end")[n]) for n in
                   ("impact_compound", "impact_compound_2", "impact_hex"))
    for (s1, e1), (s2, _) in zip(spans, spans[1:]):
        assert s2 >= e1                      # one at a time on one core
    start, end = events(fake.log, "start"), events(fake.log, "end")
    assert start["impact_compound_2"] >= end["impact_compound"]


def test_a_case_from_anothers_preload_waits_for_it_without_a_core(fake, tmp_path):
    """punch.preload_from: the rope case starts once the compound punch's pre-load is written,
    not before and not only at the punch's end; while it waits it holds no core (on 2 cores
    the impact starts beside the compound punch). It starts from the source's restart, which
    the study removes at its end (the hand-over is no output)."""
    for np_ in (2, 3):
        FakeRunner.log, FakeRunner.starts_from = [], {}
        rope = FakeCase("punch_compound_rope", "punch", "compound")
        rope.values["punch.preload_from"] = "punch_compound"
        loaded = [FakeCase("punch_compound", "punch", "compound"), rope,
                  FakeCase("impact_hex", "impact", "hex")]
        out = tmp_path / str(np_)
        scheduler.run_cases(loaded, str(out), quick=True, np_=np_)
        start, end = events(fake.log, "start"), events(fake.log, "end")
        ready = events(fake.log, "preloaded")["punch_compound"]
        assert start["impact_hex"] < ready <= start["punch_compound_rope"]
        if np_ == 3:       # a free core: it starts at the pre-load, not at the punch's end
            assert start["punch_compound_rope"] < end["punch_compound"]
        restart = out / "punch_compound" / "run" / "preload.restart"
        assert fake.starts_from["punch_compound_rope"] == str(restart)
        assert fake.starts_from["punch_compound"] is None and fake.starts_from["impact_hex"] is None
        assert not restart.exists()               # the study's hand-over is removed
