"""Ensembles (runner/ensemble.py, postprocess/ensembles.py; doc/ensembles.md): the same seed
gives the same members and adding members keeps the first ones; a member's case file reads back
as the member; bad [ensemble] keys give one line and exit 2; and end to end, a 3-member quick
impact ensemble run side by side on one rank each and as a real 2-partition LIGGGHTS job
(mpirun -np 2 liggghts -partition 2x1) gives every member the same result, the same as the
member's own case.toml run alone, with the ensemble's statistics and figures in the report."""

import json
import subprocess
import sys

import pytest

import lmp
from runner import casefile, ensemble
from runner.errors import CaseFileError

CASE = """kind = "impact"
title = "ensemble test"

[panel]
net = "square"

[ensemble]
members = {members}
seed = {seed}
point_radius = 0.05
speed = "normal"
speed_cov = 0.05
orientation = "random"
"""


def members(tmp_path, members=3, seed=7, extra=""):
    case = casefile.parse(CASE.format(members=members, seed=seed) + extra,
                          str(tmp_path / "ens.toml"), True, "ens")
    return ensemble.expand(case, str(tmp_path / "out"))


def texts(found):
    return [c.member_text for c in found.cases]


def test_same_seed_same_members(tmp_path):
    a, b = members(tmp_path), members(tmp_path)
    assert texts(a) == texts(b)
    assert a.manifest() == b.manifest()
    assert len(set(texts(a))) == 3             # the members differ from each other
    assert texts(members(tmp_path, seed=8)) != texts(a)


def test_adding_members_keeps_the_first_ones(tmp_path):
    # member k's draws come from the streams (seed, k, variable)
    assert texts(members(tmp_path, members=5))[:3] == texts(members(tmp_path, members=3))


def test_member_case_file_reads_back_as_the_member(tmp_path):
    found = members(tmp_path)
    for case, member in zip(found.cases, found.members):
        again = casefile.parse(case.member_text, str(tmp_path / "m.toml"), False, "m")
        assert again.values == case.values and again.impacts == case.impacts
        assert not ensemble.active(again)         # a member is a plain case
        assert member.changes and set(member.drawn) == {"point_offset", "speed",
                                                         "speed_factor", "rotation"}
        offset = member.drawn["point_offset"]
        assert offset[0] ** 2 + offset[1] ** 2 <= 0.05 ** 2
        assert case.impacts[0]["point"][:2] == pytest.approx(offset)


def test_sweep_members_share_their_draws(tmp_path):
    extra = '\n'.join(['sweep = "impact.mass"', 'values = [40.0, 60.0]'])
    found = members(tmp_path, members=2, extra=extra + "\n")
    assert found.mode == "sweep" and len(found.cases) == 4
    assert [c.impacts[0]["mass"] for c in found.cases] == [40.0, 40.0, 60.0, 60.0]
    # common random numbers: the r-th member of each value draws the same
    assert found.members[0].drawn == found.members[2].drawn
    assert found.members[0].drawn != found.members[1].drawn


def test_bad_sweep_key_is_one_line(tmp_path):
    with pytest.raises(CaseFileError, match="'impact.mas': not a key of an impact case "
                                            r"\(did you mean 'impact.mass'\?\)"):
        members(tmp_path, extra='sweep = "impact.mas"\nvalues = [1.0]\n')


def run(out, *args, target=None):
    return subprocess.run([sys.executable, "-m", "runner", "run", str(target), *args, "--out",
                           str(out)], cwd=lmp.ROOT, capture_output=True, text=True, timeout=300,
                          env=dict(lmp.MPI_ENV, WIRENET_BUILD=str(lmp.BUILD),
                                   WIRENET_SETUP="skip", PATH="/usr/bin:/bin"))


@pytest.mark.parametrize("setting, message", [
    ("ensemble.members=0", "ensemble.members: must be >= 1, got 0"),
    ('ensemble.speed="weird"', "ensemble.speed: must be one of fixed, normal, uniform"),
    ("ensemble.membrs=3", "ensemble.membrs: unknown key (did you mean 'ensemble.members'?)"),
    ("ensemble.values=[1.0]", "ensemble.values: values without ensemble.sweep"),
    ('ensemble.sweep="impact.mass"', "ensemble.values: the values of impact.mass to sweep"),
    ('ensemble.sensitivity=["impact.mass"]', "ensemble.sensitivity: one key at a time"),
    ("ensemble.slack_seeds=true", "ensemble.slack_seeds: materials.slack_u is 0"),
    ('ensemble.speed="uniform"', "ensemble.speed_range: [0.0, 0.0]: must be [low, high]"),
    ("ensemble.point_radius=-1", "ensemble.point_radius: must be >= 0"),
    ("ensemble.speed_range=[5.0, 9.0]", "a range of speeds is for ensemble.speed = \"uniform\" "
                                        "(it is 'normal')"),
])
def test_bad_ensemble_keys_one_line_exit_2(tmp_path, setting, message):
    path = tmp_path / "ens.toml"
    path.write_text(CASE.format(members=3, seed=7))
    p = run(tmp_path / "out", "--quick", "--set", setting, target=path)
    assert p.returncode == 2, p.stderr
    assert p.stderr.count("\n") == 1 and "Traceback" not in p.stderr
    assert message in p.stderr and str(path) in p.stderr
    assert not (tmp_path / "out").exists()


def test_a_speed_spread_without_a_speed_distribution_is_refused(tmp_path):
    """A coefficient of variation of the speed with ensemble.speed = "fixed" would vary nothing:
    refused, not ignored."""
    path = tmp_path / "ens.toml"
    path.write_text(CASE.format(members=3, seed=7))
    p = run(tmp_path / "out", "--quick", "--set", 'ensemble.speed="fixed"', "--set",
            "ensemble.speed_cov=0.1", target=path)
    assert p.returncode == 2 and p.stderr.count("\n") == 1, p.stderr
    assert "ensemble.speed_cov: 0.1: a coefficient of variation of the speed is for " \
           "ensemble.speed = \"normal\" (it is 'fixed')" in p.stderr
    assert not (tmp_path / "out").exists()


def test_ensemble_keys_without_members_are_refused(tmp_path):
    """An [ensemble] that asks for no members (members = 1, no sweep, no sensitivity) but varies
    something would run the case alone and ignore the rest: refused, naming the first key."""
    path = tmp_path / "ens.toml"
    path.write_text(CASE.format(members=1, seed=7))
    p = run(tmp_path / "out", "--quick", target=path)
    assert p.returncode == 2 and p.stderr.count("\n") == 1, p.stderr
    assert "varies nothing: the [ensemble] asks for no members" in p.stderr
    assert not (tmp_path / "out").exists()


def test_partitions_must_divide_the_ranks(tmp_path):
    path = tmp_path / "ens.toml"
    path.write_text(CASE.format(members=3, seed=7))
    p = run(tmp_path / "out", "--quick", "--np", "3", "--partitions", "2", target=path)
    assert p.returncode == 2 and p.stderr.count("\n") == 1
    assert "--partitions 2: --np 3 is not a multiple of it" in p.stderr


OUTPUTS = ("block.csv", "edges.csv", "zone_forces.csv", "case.toml")


def test_ensemble_alone_side_by_side_and_in_two_partitions(tmp_path):
    """About 30 s: 3 quick members on one rank, then the same as a 2-partition job (two
    batches of mpirun -np 2 liggghts -partition 2x1 for the first two members), then member 1
    alone from its own case.toml: the same numbers to the last digit."""
    path = tmp_path / "ens.toml"
    path.write_text(CASE.format(members=3, seed=7))
    one, two, alone = tmp_path / "one", tmp_path / "two", tmp_path / "alone"
    p = run(one, "--quick", "--np", "1", target=path)
    assert p.returncode == 0, p.stderr
    p = run(two, "--quick", "--np", "2", "--partitions", "2", target=path)
    assert p.returncode == 0, p.stderr
    # a real multi-partition job ran the first two members side by side
    batches = sorted((two / ".partitions").glob("batch_*"))
    assert batches
    command = (batches[-1].parent / "batch_0001" / "command.txt").read_text()
    assert "-partition 2x1" in command and "mpirun -np 2" in command
    assert "member_000" in command and "member_001" in command
    for k in range(3):
        m = f"ens/member_{k:03d}"
        assert json.loads((two / m / "case.json").read_text())["status"] == "ok"
        for name in OUTPUTS:
            assert (one / m / name).read_bytes() == (two / m / name).read_bytes(), (m, name)
    # member 1 alone, from its own case file (no --quick: it states every value)
    p = run(alone, "--np", "1", target=one / "ens" / "member_001" / "case.toml")
    assert p.returncode == 0, p.stderr
    for name in ("block.csv", "edges.csv"):
        assert (alone / "case" / name).read_bytes() == \
            (one / "ens" / "member_001" / name).read_bytes()

    # the report: the ensemble's statistics, P(breakthrough) and figures
    summary = json.loads((two / "summary.json").read_text())
    e = summary["ensembles"]["ens"]
    assert e["mode"] == "random" and e["seed"] == 7 and len(e["members"]) == 3
    assert json.loads((one / "summary.json").read_text())["ensembles"]["ens"]["statistics"] \
        == e["statistics"]
    s = e["statistics"]["peak_block_force"]
    values = [m["outputs"]["peak_block_force"] for m in e["members"].values()]
    assert s["n"] == 3 and s["mean"] == pytest.approx(sum(values) / 3, rel=1e-12)
    assert s["q05"] <= s["q50"] <= s["q95"]
    assert e["settling"]["peak_block_force"]["n"] == [1, 2, 3]
    b = e["breakthrough"]
    assert b["n"] == 3 and 0 <= b["low"] <= b["p"] <= b["high"] <= 1
    for figure in ("distributions", "settling", "travel"):
        assert (two / "figures" / f"ensemble_ens_{figure}.png").is_file()
    report = (two / "report.md").read_text()
    assert "## Ensembles" in report and "P(breakthrough) = " in report
    assert summary["missing"] == []


@pytest.mark.parametrize("manifest, message", [
    ('{"members": "x"}', "'members' must be a list"),
    ('{"members": [3]}', "members[0]: expected an object"),
    ('{"members": [{"nam": "x"}]}', "members[0]: 'name' must be the name of a folder"),
    ('{"members": [{"name": "../../etc"}]}', "'name' must be the name of a folder"),
    ('{"members": [{"name": "m", "drawn": 3}]}', "members[0]: 'drawn' must be an object"),
    ('{"members": [{"name": "m"}], "sweep": 4}', "'sweep' must be an object or null"),
    ('[1]', "expected a JSON object"),
])
def test_report_of_a_bad_ensemble_json_is_one_line(tmp_path, manifest, message):
    (tmp_path / "e").mkdir()
    (tmp_path / "e" / "ensemble.json").write_text(manifest)
    p = subprocess.run([sys.executable, "-m", "postprocess", "report", str(tmp_path)],
                       cwd=lmp.ROOT, capture_output=True, text=True, timeout=120)
    assert p.returncode == 2 and p.stderr.count("\n") == 1, p.stderr
    assert "ensemble.json" in p.stderr and message in p.stderr
    assert not (tmp_path / "report.md").exists()


def test_a_sensitivity_table_says_where_a_factor_turns_the_verdict():
    """The sensitivity rows: each output's change against the base member, the member's own
    value where the base has none (a failed fence's residual height), and the block's verdict,
    in bold with the base's where the factor turned it (the 500 kJ square fence's thicker
    support ropes stop the block the base lets through: doc/fence.md)."""
    from postprocess import ensemble_report, ensembles

    def member(key, factor, through, anchor, rest):
        return dict(key=key, factor=factor, status="ok", breakthrough=through,
                    outputs=dict(anchor_peak=anchor, post_base_peak=3.0e5,
                                 braking_distance=6.0, residual_height=rest))
    members = {"member_000": member(None, None, True, 2.0e5, None),
               "member_001": member("fence.support_rope_d", 0.8, True, 1.5e5, None),
               "member_002": member("fence.support_rope_d", 1.2, False, 3.0e5, 1.6)}
    rows = ensembles.sensitivity_rows("fence", members)
    assert rows[0]["changes"]["anchor_peak"]["relative"] == pytest.approx(-0.25)
    assert rows[1]["changes"]["residual_height"] == dict(absolute=None, relative=None)
    outputs = [dict(name=o.name, label=o.label, unit=o.unit, scale=o.scale)
               for o in ensembles.FENCE_OUTPUTS]
    e = dict(mode="sensitivity", outputs=outputs, sensitivity_rows=rows, members=members,
             sensitivity={})
    table = [line for line in ensemble_report.sensitivity_lines({"fence_square": e})
             if line.startswith("| `")]
    assert "| through |" in table[0] and "-25 %" in table[0]
    assert "| **stopped** (base: through) |" in table[1] and "1.6 m (base: n/a)" in table[1]
