"""Breakable ropes in a punch case (issue #17): the quick square cone punch with the rope
strength of materials.in ends by rope failure, and the rope's tension when the first rope bond
breaks is bounded by the strength criterion: F/A + |M| R/I >= SIGMA_T with F <= SIGMA_T A, so
the largest rope tension recorded before the break lies below SIGMA_T A (and the break does come
from tension, not from a rope far below it)."""

import json
import math
import os

import numpy as np
import pytest

import lmp
from postprocess import study
from runner import punch
from postprocess.model import ROPE, ROPE_STRENGTH


@pytest.fixture(scope="module")
def rope_case(tmp_path_factory):
    os.environ.setdefault("WIRENET_BUILD", str(lmp.BUILD))
    folder = tmp_path_factory.mktemp("punch_rope")
    facts = punch.run_case(str(folder), "square", "cone", quick=True, rope_strength=True)
    (folder / "case.json").write_text(json.dumps(facts, indent=2))
    return folder, facts


def test_the_punch_ends_by_rope_failure(rope_case):
    folder, facts = rope_case
    assert facts["rope_strength"] == list(ROPE_STRENGTH)
    assert facts["ended_by"] == "rope failure", facts["ended_by"]
    assert facts["first_rope_rupture"]["displacement"] > 0
    assert facts["first_rupture"]["bond"]["family"] == "rope"


def test_rope_tension_before_the_break_is_below_the_tensile_limit(rope_case):
    folder, facts = rope_case
    limit = ROPE_STRENGTH[0] * math.pi * ROPE["rope_d"] ** 2 / 4      # SIGMA_T A = 63 kN
    zone = study.load_case(str(folder)).zone()["rope"]
    before = zone["displacement"] < facts["first_rope_rupture"]["displacement"]
    peak = float(np.max(zone["max"][before]))
    assert peak <= limit * 1.0001, (peak, limit)
    assert peak > 0.5 * limit, (peak, limit)     # the ropes were loaded near their strength
