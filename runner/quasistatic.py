"""The quasi-static evidence of a load test (punch, tensile): a run is static when its force
curve does not change with the loading rate, the kinetic energy stays a small part of the work
done, and the load balances the supports' reactions (doc/punch.md, "Quasi-static evidence").

Every function reads a run's table by column name: displacement, force, reaction, weight, ke
and broken (the number of broken bonds), one row per output step.
"""

import numpy as np

SLOW_FACTOR = 4      # the twin runs this many times slower, with the same masses and step
TOLERANCE = 0.01     # 1 %: curve agreement, kinetic energy fraction, equilibrium


def work_done(disp, force):
    """Cumulative work of the platter (trapezoid rule, from 0 at zero travel)."""
    d = np.r_[0.0, disp]
    f = np.r_[0.0, force]
    return np.cumsum(np.r_[0.0, 0.5 * (f[1:] + f[:-1]) * np.diff(d)])[1:]


def rupture_limit(table):
    """Index limit (exclusive) of the rows before the first rupture."""
    broken = np.asarray(table["broken"])
    hit = np.nonzero(broken > 0)[0]
    return int(hit[0]) if hit.size else len(broken)


def snap_events(table, upto=None):
    """Displacement intervals of snap-through events before ``upto`` rows: rows where the
    platter force drops by more than 1 % of its peak from one output row to the next, or the
    kinetic energy jumps above ten times its median. At such a limit point the static path
    itself jumps (a node slips over the platter or off the cone tip); the run crosses it
    dynamically at any speed. Each event covers two output rows either side."""
    n = len(table["force"]) if upto is None else upto
    f, ke, d = table["force"][:n], table["ke"][:n], table["displacement"][:n]
    if n < 3:
        return []
    peak = float(np.max(np.abs(f)))
    drop = np.r_[False, np.diff(f) < -0.01 * peak]
    spike = ke > 10 * max(float(np.median(ke)), 1e-300)
    rows = np.nonzero(drop | spike)[0]
    intervals = []
    for k in rows:
        lo, hi = d[max(k - 2, 0)], d[min(k + 2, n - 1)]
        if intervals and lo <= intervals[-1][1]:
            intervals[-1][1] = max(intervals[-1][1], hi)
        else:
            intervals.append([float(lo), float(hi)])
    return intervals


def _outside(d, intervals):
    keep = np.ones(len(d), bool)
    for lo, hi in intervals:
        keep &= ~((d >= lo) & (d <= hi))
    return keep


def curve_difference(fast, slow):
    """Largest |F_fast - F_slow| on the slow run's displacements up to the first rupture of
    either run, relative to the slow run's peak force there, away from the snap events of
    either run (``max``) and everywhere (``max_all``); and the RMS difference."""
    nf, ns = rupture_limit(fast), rupture_limit(slow)
    d_end = min(fast["displacement"][nf - 1], slow["displacement"][ns - 1])
    keep = slow["displacement"][:ns] <= d_end + 1e-12
    d = slow["displacement"][:ns][keep]
    fs = slow["force"][:ns][keep]
    ff = np.interp(d, fast["displacement"][:nf], fast["force"][:nf])
    peak = float(np.max(np.abs(fs)))
    events = snap_events(fast, nf) + snap_events(slow, ns)
    calm = _outside(d, events)
    if not peak > 0:
        return dict(max=float("nan"), max_all=float("nan"), rms=float("nan"), up_to=float(d_end),
                    snap_events=events)
    gap = np.abs(ff - fs) / peak
    return dict(max=float(np.max(gap[calm])), max_all=float(np.max(gap)),
                rms=float(np.sqrt(np.mean(gap ** 2))), up_to=float(d_end),
                snap_events=sorted(events), calm_fraction=float(np.mean(calm)))


def kinetic_fraction(table, calm=True):
    """Largest KE / W over the output rows before the first rupture where W > 1 % of its
    final value; with calm, away from the snap events."""
    n = rupture_limit(table)
    w = work_done(table["displacement"][:n], table["force"][:n])
    if not n or not w[-1] > 0:
        return float("nan")
    use = w > 0.01 * w[-1]
    if calm:
        use &= _outside(table["displacement"][:n], snap_events(table, n))
    return float(np.max(table["ke"][:n][use] / w[use]))


def equilibrium_error(table, upto=None, relative_to_current=False, calm=True):
    """Largest |F + W - R| over the output rows (platter force F, panel weight W, sum of the
    edge z reactions R), relative to the peak reaction (default) or, with
    relative_to_current, to the current reaction on the rows where F >= 10 % of its peak;
    with calm, away from the snap events."""
    n = len(table["force"]) if upto is None else upto
    if not n:
        return float("nan")
    r = table["reaction"][:n]
    gap = np.abs(r - table["weight"][:n] - table["force"][:n])
    if not np.max(np.abs(r)) > 1e-9 * np.max(np.abs(table["force"][:n])):
        return float("nan")    # the supports carry nothing yet (a fast, dynamic punch)
    use = np.ones(n, bool)
    if calm:
        use &= _outside(table["displacement"][:n], snap_events(table, n))
    if not relative_to_current:
        return float(np.max(gap[use]) / np.max(np.abs(r)))
    use &= table["force"][:n] >= 0.1 * np.max(table["force"][:n])
    return float(np.max(gap[use] / np.abs(r[use])))


def equilibrium_holds_from(table, upto=None, tolerance=None):
    """Smallest platter travel from which the gap |F + W - R| stays within tolerance of the
    current reaction R at every output row up to `upto` (None: never within it)."""
    tolerance = TOLERANCE if tolerance is None else tolerance
    n = len(table["force"]) if upto is None else upto
    if not n:
        return None
    r = table["reaction"][:n]
    bad = np.abs(r - table["weight"][:n] - table["force"][:n]) > tolerance * np.abs(r)
    if not bad.any():
        return 0.0
    last = int(np.nonzero(bad)[0][-1])
    return None if last + 1 >= n else float(table["displacement"][last + 1])


def quasi_static_evidence(fast, slow):
    """The quasi-static evidence of a run (module docstring); the comparison with the slower
    twin is null when the twin was not run."""
    n = rupture_limit(fast)
    ke, eq = kinetic_fraction(fast), equilibrium_error(fast, n)
    evidence = dict(
        slow_factor=None, curve_difference=None, curve_difference_with_snaps=None,
        curve_difference_rms=None, compared_up_to=None, snap_events=snap_events(fast, n),
        kinetic_energy_fraction=ke, kinetic_energy_fraction_slow=None,
        kinetic_energy_fraction_with_snaps=kinetic_fraction(fast, calm=False),
        equilibrium_error=eq, equilibrium_error_slow=None,
        equilibrium_error_with_snaps=equilibrium_error(fast, n, calm=False),
        equilibrium_error_after_rupture=equilibrium_error(fast, calm=False),
        equilibrium_error_of_current=equilibrium_error(fast, n, relative_to_current=True),
        equilibrium_holds_from=equilibrium_holds_from(fast, n), equilibrium_holds_from_slow=None,
        passed=bool(ke <= TOLERANCE and eq <= TOLERANCE))
    if slow is None:
        return evidence
    diff = curve_difference(fast, slow)
    evidence.update(
        slow_factor=SLOW_FACTOR, curve_difference=diff["max"],
        curve_difference_with_snaps=diff["max_all"], curve_difference_rms=diff["rms"],
        compared_up_to=diff["up_to"], snap_events=diff["snap_events"],
        kinetic_energy_fraction_slow=kinetic_fraction(slow),
        equilibrium_error_slow=equilibrium_error(slow, rupture_limit(slow)),
        equilibrium_holds_from_slow=equilibrium_holds_from(slow, rupture_limit(slow)),
        passed=bool(diff["max"] <= TOLERANCE and evidence["passed"]))
    return evidence


