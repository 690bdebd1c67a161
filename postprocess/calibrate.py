"""Bending-fraction calibration: the fraction whose punch curve best fits a measured one.

Method. Each calibration case gives a simulated force-displacement curve F_i(d) at a bending
fraction f_i. All curves and the measurement are compared on the measured displacements that
every simulated curve covers. Between two simulated fractions the curve is interpolated point
by point, linearly in s = log10(f + F0) with F0 = 1e-3 (the fractions span two decades and
include 0, and the paper notes that the influence of the fraction decreases progressively, as
for a logarithmic dependence). The root-mean-square error RMSE(f) between the interpolated and
the measured curve is then a continuous function of f over [min f_i, max f_i]: it is scanned on
a fine grid in s and the best grid point is refined by a golden-section search on the bracket
around it. The result is exact at the simulated fractions and needs no further simulation;
its accuracy between them depends on how smoothly the curve changes with log f, which the
RMSE of each simulated fraction (written alongside) lets one judge.

    /usr/bin/python3 -m postprocess calibrate MEASURED.csv --cases DIR [DIR ...]
                     [--out PREFIX] [--displacement-column displacement] [--force-column force]
"""

import math
import os

import numpy as np

from .csvio import read_csv
from .errors import PostprocessError
from .output import Outputs, json_text
from .canvas import check_prefix

F0 = 1e-3


def to_s(fraction):
    return np.log10(np.asarray(fraction, float) + F0)


def from_s(s):
    return float(10 ** s - F0)


def load_case(directory):
    """(fraction, displacement, force) of a case folder: case.json 'bending' (or the last number
    of the folder name) and platter.csv. Errors name the folder, file or key."""
    from .casefolders import BENDING_KEYS, check_bending, read_case_meta
    if not os.path.isdir(directory):
        raise PostprocessError(f"{directory}: not a directory (--cases)")
    fraction = None
    meta_path = os.path.join(directory, "case.json")
    if os.path.isfile(meta_path):
        meta = read_case_meta(meta_path)
        fraction = next((meta[k] for k in BENDING_KEYS if meta.get(k) is not None), None)
    if fraction is None:
        tail = os.path.basename(os.path.normpath(directory)).rsplit("_", 1)[-1]
        try:
            float(tail)
        except ValueError:
            raise PostprocessError(f"{directory}: no bending fraction (case.json 'bending' or a "
                                   f"folder name ending in _FRACTION)") from None
        fraction = check_bending(tail, directory, "bending fraction of the folder name")
    path = os.path.join(directory, "platter.csv")
    table = read_csv(path, required=("displacement", "force"))
    if len(table["displacement"]) < 2:
        raise PostprocessError(f"{path}: fewer than two data rows")
    order = np.argsort(table["displacement"], kind="stable")
    return fraction, table["displacement"][order], table["force"][order], directory


class Family:
    """Simulated curves sampled on common displacements, interpolated in log10(f + F0)."""

    def __init__(self, cases, displacement, source="measured curve"):
        """``cases``: (fraction, displacement, force[, folder]); ``source``: the measured file,
        named in errors."""
        cases = sorted(cases, key=lambda c: c[0])
        fractions = [c[0] for c in cases]
        for a, b in zip(cases, cases[1:]):
            if a[0] == b[0]:
                folders = " and ".join(str(c[3]) if len(c) > 3 else "?" for c in (a, b))
                raise PostprocessError(f"--cases: {folders} have the same bending fraction "
                                       f"{a[0]:g}")
        if len(cases) < 2:
            raise PostprocessError("--cases: need at least two calibration cases with different "
                                   "fractions")
        reach = min(float(c[1].max()) for c in cases)
        keep = (displacement >= 0) & (displacement <= reach)
        if keep.sum() < 3:
            raise PostprocessError(f"{source}: fewer than 3 measured points within the "
                                   f"simulated range 0..{reach:g} m")
        self.keep = keep
        self.d = displacement[keep]
        self.fractions = np.array(fractions)
        self.s = to_s(self.fractions)
        self.curves = np.array([np.interp(self.d, c[1], c[2]) for c in cases])

    def curve(self, fraction):
        s = float(np.clip(to_s(fraction), self.s[0], self.s[-1]))
        k = int(np.clip(np.searchsorted(self.s, s) - 1, 0, len(self.s) - 2))
        w = (s - self.s[k]) / (self.s[k + 1] - self.s[k])
        return (1 - w) * self.curves[k] + w * self.curves[k + 1]

    def rmse(self, fraction, measured):
        return float(np.sqrt(np.mean((self.curve(fraction) - measured) ** 2)))


def best_fraction(family, measured, grid=400, tol=1e-10):
    """Continuous minimiser of the RMSE over [min f, max f]: grid scan in s, then golden
    section on the bracket of the best grid point."""
    ss = np.linspace(family.s[0], family.s[-1], grid)
    errors = np.array([family.rmse(from_s(s), measured) for s in ss])
    k = int(np.argmin(errors))
    lo, hi = ss[max(k - 1, 0)], ss[min(k + 1, grid - 1)]
    g = (math.sqrt(5) - 1) / 2
    a, b = lo + (1 - g) * (hi - lo), lo + g * (hi - lo)
    fa, fb = family.rmse(from_s(a), measured), family.rmse(from_s(b), measured)
    while hi - lo > tol:
        if fa <= fb:
            hi, b, fb = b, a, fa
            a = lo + (1 - g) * (hi - lo)
            fa = family.rmse(from_s(a), measured)
        else:
            lo, a, fa = a, b, fb
            b = lo + g * (hi - lo)
            fb = family.rmse(from_s(b), measured)
    s_best = 0.5 * (lo + hi)
    if errors[k] < family.rmse(from_s(s_best), measured):
        s_best = ss[k]
    f_best = min(max(from_s(s_best), float(family.fractions[0])), float(family.fractions[-1]))
    return f_best, family.rmse(f_best, measured), ss, errors


def calibrate(measured_path, case_dirs, displacement_column="displacement",
              force_column="force"):
    table = read_csv(measured_path, required=(displacement_column, force_column))
    order = np.argsort(table[displacement_column], kind="stable")
    d = table[displacement_column][order]
    f = table[force_column][order]
    family = Family([load_case(c) for c in case_dirs], d, measured_path)
    measured = f[family.keep]
    if not np.any(measured != 0):
        raise PostprocessError(f"{measured_path}: column {force_column} is 0 at every measured "
                               f"point within the simulated range: nothing to fit")
    fraction, rmse, ss, errors = best_fraction(family, measured)
    return dict(best_fraction=fraction, rmse=rmse,
                rmse_relative=rmse / float(np.max(np.abs(measured))),
                points=int(len(measured)), displacement_range=[float(family.d[0]),
                                                               float(family.d[-1])],
                simulated={f"{fr:g}": family.rmse(fr, measured) for fr in family.fractions},
                interpolation="linear in log10(fraction + 1e-3), point by point"), \
        family, measured, (ss, errors)


def plot(result, family, measured, scan, prefix, outputs=None):
    from .canvas import force_scale, pyplot, save
    plt = pyplot()
    fig, (ax, bx) = plt.subplots(1, 2, figsize=(11, 4.5))
    scale, unit = force_scale([measured] + list(family.curves))
    for fr, curve in zip(family.fractions, family.curves):
        ax.plot(family.d, curve / scale, lw=1, alpha=0.6, label=f"simulated, f = {fr:g}")
    ax.plot(family.d, family.curve(result["best_fraction"]) / scale, "k--", lw=2,
            label=f"best fit, f = {result['best_fraction']:.4g}")
    ax.plot(family.d, measured / scale, "ro", ms=3, label="measured")
    ax.set_xlabel("platter displacement [m]")
    ax.set_ylabel(f"platter force [{unit}]")
    ax.legend(fontsize=8)
    ax.set_title("bending-fraction calibration")
    ss, errors = scan
    bx.semilogx(10 ** ss - F0 + F0, errors / scale, "b-")
    bx.axvline(result["best_fraction"] + F0, color="k", ls="--")
    bx.set_xlabel(f"bending fraction + {F0:g}")
    bx.set_ylabel(f"RMSE [{unit}]")
    bx.set_title(f"RMSE minimum {result['rmse'] / scale:.4g} {unit}")
    fig.tight_layout()
    return save(fig, prefix, outputs)


def run(args):
    """The ``calibrate`` subcommand."""
    check_prefix(args.out)
    result, family, measured, scan = calibrate(args.measured, args.cases,
                                               args.displacement_column, args.force_column)
    with Outputs() as outputs:                      # PREFIX.json, .png, .svg: all or none
        result["figures"] = plot(result, family, measured, scan, args.out, outputs)
        with open(outputs.file(args.out + ".json"), "w", encoding="utf-8") as handle:
            handle.write(json_text(result))
    print(f"best bending fraction {result['best_fraction']:.6g} (RMSE {result['rmse']:.6g} N, "
          f"{100 * result['rmse_relative']:.3g} % of the peak) -> {args.out}.json, "
          f"{', '.join(result['figures'])}")
