"""An ensemble's statistics (postprocess/statistics.py, postprocess/ensembles.py) against known
answers: textbook values of the quantiles, the t and normal quantiles, Wilson's interval
(Newcombe 1998), Welch's test (the worked example of its Wikipedia page), and a synthetic
ensemble of members whose outputs are known."""

import math

import numpy as np
import pytest

from postprocess import ensembles, statistics


def test_describe_one_to_ten():
    s = statistics.describe(range(1, 11))
    assert s["n"] == 10 and s["mean"] == 5.5
    assert s["std"] == pytest.approx(math.sqrt(55 / 6), rel=1e-14)     # sum (x - 5.5)^2 / 9
    # type 7: h = (n - 1) p, between x[floor h] and x[floor h + 1]
    assert (s["q05"], s["q50"], s["q95"]) == pytest.approx((1.45, 5.5, 9.55), rel=1e-14)
    assert (s["min"], s["max"]) == (1.0, 10.0)
    half = 2.2621571627409915 * math.sqrt(55 / 6) / math.sqrt(10)   # t(0.975, 9)
    assert s["mean_interval"] == pytest.approx([5.5 - half, 5.5 + half], rel=1e-9)


def test_describe_skips_missing_values_and_small_samples():
    assert statistics.describe([None, 2.0])["n"] == 1
    one = statistics.describe([2.0])
    assert one["mean"] == one["q05"] == one["q95"] == 2.0
    assert one["std"] is None and one["mean_interval"] is None
    assert statistics.describe([])["mean"] is None


@pytest.mark.parametrize("p, df, expected", [
    (0.975, 1, 12.706204736174707), (0.975, 9, 2.2621571627409915),
    (0.975, 30, 2.0422724563012373), (0.95, 4.5, 2.065575887144095),
    (0.025, 9, -2.2621571627409915), (0.975, math.inf, 1.959963984540054)])
def test_t_quantile(p, df, expected):
    # reference values: scipy.stats.t.ppf and norm.ppf
    assert statistics.t_quantile(p, df) == pytest.approx(expected, rel=1e-9)


def test_t_quantile_against_scipy_if_installed():
    stats = pytest.importorskip("scipy.stats")
    for df in (1, 2, 3.7, 7, 24.99, 100):
        for p in (0.6, 0.9, 0.975, 0.995):
            assert statistics.t_quantile(p, df) == pytest.approx(stats.t.ppf(p, df), rel=1e-8)


@pytest.mark.parametrize("events, n, low, high", [
    # Newcombe (1998), Statistics in Medicine 17, 857-872, table I, method 3 (score interval)
    (81, 263, 0.2553, 0.3662), (15, 148, 0.0624, 0.1605), (0, 20, 0.0, 0.1611),
    (1, 29, 0.0061, 0.1718)])
def test_wilson_textbook(events, n, low, high):
    w = statistics.wilson(events, n)
    assert w["p"] == events / n
    assert (round(w["low"], 4), round(w["high"], 4)) == (low, high)


def test_wilson_edges():
    # no breakthrough in 8 members is no proof of none: the interval reaches 0.32
    w = statistics.wilson(0, 8)
    assert w["low"] == 0.0 and w["high"] == pytest.approx(0.3244, abs=1e-4)
    w = statistics.wilson(8, 8)
    assert w["high"] == 1.0 and w["low"] == pytest.approx(1 - 0.3244, abs=1e-4)
    assert statistics.wilson(0, 0)["p"] is None


def test_welch_wikipedia_example():
    # Welch's t-test, Wikipedia, example 2: t = -2.46, nu = 24.99, p = 0.021
    a = [27.5, 21.0, 19.0, 23.6, 17.0, 17.9, 16.9, 20.1, 21.9, 22.6, 23.1, 19.6, 19.0, 21.7, 21.4]
    b = [27.1, 22.0, 20.8, 23.4, 23.4, 23.5, 25.8, 22.0, 24.8, 20.2, 21.9, 22.1, 22.9, 20.5, 24.4]
    w = statistics.welch(a, b)
    assert w["difference"] == pytest.approx(np.mean(a) - np.mean(b), rel=1e-12)
    assert w["df"] == pytest.approx(24.99, abs=0.005)
    se = math.sqrt(np.var(a, ddof=1) / 15 + np.var(b, ddof=1) / 15)
    assert w["difference"] / se == pytest.approx(-2.46, abs=0.005)
    half = statistics.t_quantile(0.975, w["df"]) * se
    assert [w["low"], w["high"]] == pytest.approx([w["difference"] - half,
                                                   w["difference"] + half], rel=1e-12)
    assert w["high"] < 0          # p = 0.021 < 0.05: the interval leaves out 0
    assert statistics.welch([1.0], b) is None


def test_running_statistics_settle():
    r = statistics.running([3.0, 1.0, None, 2.0])
    assert r["n"] == [1, 2, 3]
    assert r["mean"] == [3.0, 2.0, 2.0]
    assert r["q50"] == [3.0, 2.0, 2.0]
    assert r["q05"][1] == pytest.approx(1.1) and r["q95"][1] == pytest.approx(2.9)


def _member(value, through, status="ok"):
    return {"status": status, "errors": [], "outputs": {"anchor_peak": value,
                                                        "braking_distance": 1.0},
            "breakthrough": through}


def test_synthetic_ensemble():
    """400 members of a known normal output (mean 100 kN, sd 10 kN), one in four broken
    through, and members that failed or say nothing: the statistics find the known answers."""
    rng = np.random.default_rng(41)
    values = rng.normal(100e3, 10e3, 400)
    members = {f"member_{k:03d}": _member(float(v), k % 4 == 0) for k, v in enumerate(values)}
    members["failed"] = _member(1e9, True, status="failed")
    members["silent"] = _member(None, None)
    outputs = [o for o in ensembles.FENCE_OUTPUTS if o.name in ("anchor_peak",
                                                                "braking_distance")]
    stats, settling = ensembles.statistics_of(members, outputs)
    s = stats["anchor_peak"]
    assert s["n"] == 400                       # the failed member and the silent one left out
    assert s["mean"] == pytest.approx(np.mean(values), rel=1e-12)
    assert s["mean"] == pytest.approx(100e3, abs=3 * 10e3 / 20)       # 3 standard errors
    assert s["std"] == pytest.approx(10e3, rel=0.1)
    assert s["q05"] == pytest.approx(100e3 - 1.6449 * 10e3, abs=2.5e3)
    assert s["q95"] == pytest.approx(100e3 + 1.6449 * 10e3, abs=2.5e3)
    assert s["mean_interval"][0] < 100e3 < s["mean_interval"][1]
    assert stats["braking_distance"]["std"] == 0.0
    assert settling["anchor_peak"]["n"][-1] == 400
    assert settling["anchor_peak"]["mean"][-1] == pytest.approx(s["mean"], rel=1e-12)
    b = ensembles.breakthrough(members)
    assert (b["events"], b["n"]) == (100, 400)     # the silent member does not say
    assert b["low"] < 0.25 < b["high"]


def _ensemble(net, values, kind="fence", mode="random"):
    members = {f"member_{k:03d}": {"status": "ok", "errors": [], "breakthrough": False,
                                   "outputs": {"post_base_peak": v, "anchor_peak": 2 * v}}
               for k, v in enumerate(values)}
    outputs = [dict(name=n, label=n, unit="kN", scale=1e3)
               for n in ("post_base_peak", "anchor_peak")]
    return dict(kind=kind, mode=mode, quick=False, dissipation="physical", net=net,
                members=members, outputs=outputs)


def test_compound_against_square_comparison():
    """The paper's post-load comparison between two ensembles: compound - square with Welch's
    interval, a verdict, and no pairing of ensembles that differ in kind or mode."""
    compound = [100e3, 110e3, 105e3, 95e3]
    square = [150e3, 160e3, 170e3, 140e3]
    summaries = {"c": _ensemble("compound", compound), "s": _ensemble("square", square),
                 "p": _ensemble("square", square, kind="impact"),
                 "w": _ensemble("square", square, mode="sweep")}
    rows = ensembles.comparisons(summaries)
    assert [(r["compound"], r["square"], r["output"]) for r in rows] == [
        ("c", "s", "post_base_peak"), ("c", "s", "anchor_peak")]
    post = rows[0]
    assert post == {**post, **statistics.welch(compound, square)}
    assert post["difference"] == pytest.approx(-52.5e3) and post["high"] < 0
    assert post["ratio"] == pytest.approx(102.5 / 155)
    assert rows[1]["difference"] == pytest.approx(-105e3)
    from postprocess import ensemble_report
    text = "\n".join(ensemble_report.comparison_lines(summaries, rows))
    assert "| c | s | post_base_peak [kN] | 4 / 4 | -52.5 |" in text
    assert text.count("compound lower") == 2


def test_paired_comparison_of_ensembles_that_drew_the_same():
    """Member k of both ensembles drew the same (the same seed and variations): the paired
    difference cancels what the draws do to both nets. Here the square net's load is the
    compound's plus 10 kN plus a little, whatever was drawn: Welch cannot tell, the pairs can."""
    compound = [60e3, 140e3, 100e3, 80e3, 120e3]
    square = [v + 10e3 + d for v, d in zip(compound, (0.0, 1e3, -1e3, 0.5e3, -0.5e3))]
    c, s = _ensemble("compound", compound), _ensemble("square", square)
    for e in (c, s):
        e.update(seed=41, variations={"block speed": "normal factor, COV 0.05"})
        for k, m in enumerate(e["members"].values()):
            m["drawn"] = {"speed_factor": 1 + 0.01 * k}
    rows = ensembles.comparisons({"c": c, "s": s})
    post = rows[0]
    assert post["low"] < 0 < post["high"]                   # Welch: cannot tell
    p = post["paired"]
    assert p["n"] == 5 and p["difference"] == pytest.approx(-10e3)
    half = statistics.t_quantile(0.975, 4) * np.std([0, 1e3, -1e3, 0.5e3, -0.5e3], ddof=1) / \
        math.sqrt(5)
    assert [p["low"], p["high"]] == pytest.approx([-10e3 - half, -10e3 + half])
    assert p["high"] < 0
    from postprocess import ensemble_report
    text = "\n".join(ensemble_report.comparison_lines({"c": c, "s": s}, rows))
    assert "(5 pairs) | " in text and "compound lower" in text
    # another seed: the members drew differently, no pairs
    s["seed"] = 42
    assert ensembles.comparisons({"c": c, "s": s})[0]["paired"] is None
    # a member that drew otherwise is left out of the pairs
    s["seed"] = 41
    next(iter(s["members"].values()))["drawn"] = {"speed_factor": 2.0}
    assert ensembles.comparisons({"c": c, "s": s})[0]["paired"]["n"] == 4


def test_a_block_that_went_on_leaves_no_residual_height_to_average():
    """A fence member whose block left the fence moving on (rest skipped: a failed test) has no
    residual height in the ensemble's statistics; one whose block stopped keeps it."""
    summary = {"fence": {"braking_distance": 6.3, "residual_height_ratio": -0.012,
                         "block_stopped": False}}
    values, through = ensembles.member_outputs(
        "fence", {"residual_height": -0.058, "rest_skipped": True}, summary)
    assert through is True and values["braking_distance"] == 6.3
    assert values["residual_height"] is None and values["residual_height_ratio"] is None
    summary["fence"].update(block_stopped=True, residual_height_ratio=0.62)
    values, through = ensembles.member_outputs(
        "fence", {"residual_height": 3.1, "rest_skipped": False}, summary)
    assert through is False and values["residual_height"] == 3.1
    assert values["residual_height_ratio"] == 0.62
