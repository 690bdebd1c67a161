"""postprocess calibrate: the continuous best bending fraction of a measured punch curve.

Synthetic calibration cases: F(d; f) = d^3 k(f) + c d with k growing with log f and saturating
(as the paper describes the influence of the fraction); the 'measured' curve is the same family
at a known fraction. At a simulated fraction the fit is exact; between two of them the
interpolation in log10(f + 1e-3) recovers the fraction to a few per cent.
"""

import json
import math
import subprocess
import sys

import numpy as np
import pytest

import lmp

FRACTIONS = (0.0, 0.01, 0.05, 0.25, 1.0)


def force(d, f):
    k = 2e5 * (1 + 0.8 * math.tanh(0.6 * (math.log10(f + 1e-3) + 3)))
    return k * d ** 3 + 2e3 * d


def write_case(folder, f, dmax=0.5):
    folder.mkdir(parents=True)
    d = np.linspace(0, dmax, 126)
    rows = ["time,displacement,force"] + [f"{x / 0.01!r},{x!r},{force(x, f)!r}" for x in d]
    (folder / "platter.csv").write_text("\n".join(rows) + "\n")
    (folder / "case.json").write_text(json.dumps({"status": "ok", "bending": f}))


def calibrate(tmp_path, true_f, noise=0.0):
    cases = []
    for f in FRACTIONS:
        write_case(tmp_path / f"calibration_{f:g}", f)
        cases.append(str(tmp_path / f"calibration_{f:g}"))
    d = np.linspace(0, 0.5, 126)[:115:3]   # on the simulated samples: no resampling error
    rng = np.random.default_rng(1)
    meas = np.array([force(x, true_f) for x in d])
    meas = meas * (1 + noise * rng.standard_normal(len(d)))
    (tmp_path / "measured.csv").write_text(
        "displacement,force\n" + "".join(f"{x!r},{y!r}\n" for x, y in zip(d, meas)))
    out = tmp_path / "fit"
    p = subprocess.run([sys.executable, "-m", "postprocess", "calibrate",
                        str(tmp_path / "measured.csv"), "--cases", *cases, "--out", str(out)],
                       cwd=lmp.ROOT, capture_output=True, text=True)
    assert p.returncode == 0, p.stderr
    assert (tmp_path / "fit.png").stat().st_size > 0 and (tmp_path / "fit.svg").stat().st_size > 0
    return json.loads((tmp_path / "fit.json").read_text())


@pytest.mark.parametrize("true_f", [0.05, 0.25])
def test_recovers_a_simulated_fraction_exactly(tmp_path, true_f):
    result = calibrate(tmp_path, true_f)
    assert result["best_fraction"] == pytest.approx(true_f, rel=1e-6)
    assert result["rmse"] < 1e-6 * max(force(0.45, true_f), 1)


@pytest.mark.parametrize("true_f", [0.02, 0.1, 0.5])
def test_recovers_a_fraction_between_the_simulated_ones(tmp_path, true_f):
    result = calibrate(tmp_path, true_f, noise=0.002)
    # continuous answer, not snapped to the five simulated values
    assert all(abs(result["best_fraction"] - f) > 1e-3 for f in FRACTIONS)
    assert result["best_fraction"] == pytest.approx(true_f, rel=0.15)
    assert result["rmse_relative"] < 0.01


def test_bad_input_is_one_line(tmp_path):
    write_case(tmp_path / "calibration_0.05", 0.05)
    (tmp_path / "m.csv").write_text("displacement,force\n0,0\n")
    p = subprocess.run([sys.executable, "-m", "postprocess", "calibrate", str(tmp_path / "m.csv"),
                        "--cases", str(tmp_path / "calibration_0.05")],
                       cwd=lmp.ROOT, capture_output=True, text=True)
    assert p.returncode == 2
    assert p.stderr.strip().startswith("postprocess calibrate: error:")
    assert len(p.stderr.strip().splitlines()) == 1
