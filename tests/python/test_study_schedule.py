"""The study's scheduler (runner/study.run_cases) with stand-in cases that only sleep: the
longest cases start first, a case starts on the core a punch gives back when its run or twin
ends (before the punch ends), the impacts of a sequence wait for each other, a case that starts
from another's pre-load waits for it without holding a core, and a study on one core runs its
cases one after the other."""

import threading
import time

import pytest

from postprocess import liggghts
from runner import cases, punch, study


class FakeCase:
    def __init__(self, name, kind, net, width=1, units=1):
        self.name, self.kind, self.path = name, kind, f"{name}.toml"
        self.values = {"kind": kind, "panel.net": net, "title": name}
        self.impacts, self.zones = [{}] * units, []
        self.width_, self.units_ = width, units

    def __getitem__(self, key):
        return self.values[key]


class FakeRunner:
    """Sleeps; a width-2 case (a punch pair) gives one core back half-way."""
    log, lock = [], threading.Lock()

    def __init__(self, case):
        self.case = case

    def units(self):
        n = self.case.units_
        return [(self.case.name if k == 0 else f"{self.case.name}_{k + 1}", k) for k in range(n)]

    def width(self):
        return self.case.width_

    def run(self, index, case_dir, study_dir, np_):
        name = self.units()[index][0]
        self._note("start", name)
        time.sleep(0.3)
        shared = punch.SHARED_PRELOADS.get(name)
        if shared is not None:       # a source of punch.preload_from: its pre-load is done
            self._note("preloaded", name)
            shared.set()
        if self.case.width_ == 2:
            liggghts.release_cores(liggghts.current_label(), 1)
            self._note("release", name)
        time.sleep(1.5 if self.case.width_ == 2 else 0.3)   # room for the 0.2 s poll
        self._note("end", name)
        return {}

    def _note(self, what, name):
        with self.lock:
            self.log.append((time.monotonic(), what, name))


@pytest.fixture
def fake(monkeypatch):
    FakeRunner.log = []
    monkeypatch.setattr(cases, "runner_of", FakeRunner)
    monkeypatch.setattr(cases, "record_kind", lambda case: case.kind)
    monkeypatch.setattr(study, "CSV_OF_KIND", {"punch": "x.csv", "impact": "x.csv"})
    return FakeRunner


def events(log, what):
    return {name: t for t, w, name in log if w == what}


def test_longest_first_and_a_released_core_is_used(fake, tmp_path):
    loaded = [FakeCase("impact_square", "impact", "square"),
              FakeCase("calibration", "punch", "square", width=2),
              FakeCase("punch_compound", "punch", "compound", width=2),
              FakeCase("impact_hex", "impact", "hex")]
    study.run_cases(loaded, str(tmp_path), quick=True, np_=2)
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
    study.run_cases(loaded, str(tmp_path), quick=True, np_=1)
    spans = sorted((events(fake.log, "start")[n], events(fake.log, "end")[n]) for n in
                   ("impact_compound", "impact_compound_2", "impact_hex"))
    for (s1, e1), (s2, _) in zip(spans, spans[1:]):
        assert s2 >= e1                      # one at a time on one core
    start, end = events(fake.log, "start"), events(fake.log, "end")
    assert start["impact_compound_2"] >= end["impact_compound"]


def test_a_case_from_anothers_preload_waits_for_it_without_a_core(fake, tmp_path):
    """punch.preload_from: the rope case starts once the compound punch's pre-load is written,
    not before and not only at the punch's end; while it waits it holds no core (on 2 cores
    the impact starts beside the compound punch)."""
    for np_ in (2, 3):
        FakeRunner.log = []
        rope = FakeCase("punch_compound_rope", "punch", "compound")
        rope.values["punch.preload_from"] = "punch_compound"
        loaded = [FakeCase("punch_compound", "punch", "compound"), rope,
                  FakeCase("impact_hex", "impact", "hex")]
        study.run_cases(loaded, str(tmp_path / str(np_)), quick=True, np_=np_)
        start, end = events(fake.log, "start"), events(fake.log, "end")
        ready = events(fake.log, "preloaded")["punch_compound"]
        assert start["impact_hex"] < ready <= start["punch_compound_rope"]
        if np_ == 3:       # a free core: it starts at the pre-load, not at the punch's end
            assert start["punch_compound_rope"] < end["punch_compound"]
        assert not punch.SHARED_PRELOADS          # the study's hand-over registry is emptied
