"""Statistics of an ensemble's outputs (numpy and the standard library only; doc/ensembles.md):
the spread of a sample, the probability of an event with its confidence interval, the difference
of two means with its confidence interval, and how the mean and quantiles settle as members are
added.

- Quantiles: numpy's default (linear interpolation between order statistics, Hyndman and Fan's
  type 7), the same as R's and NumPy's default.
- Probability of an event (breakthrough): Wilson's score interval (Wilson 1927). Chosen over
  Clopper-Pearson because it needs no beta quantiles, is not wider than needed (Clopper-Pearson
  is conservative: its coverage exceeds the nominal level), and, unlike the normal (Wald)
  interval, it does not collapse to a point at 0 or n events: 0 breakthroughs in 8 members give
  [0, 0.32] at 95 %, not [0, 0].
- Difference of two means: Welch's t interval (unequal variances, Welch-Satterthwaite degrees of
  freedom); the t quantile from the regularised incomplete beta function (continued fraction,
  Numerical Recipes 6.4).
"""

import math

import numpy as np

CONFIDENCE = 0.95
QUANTILES = (0.05, 0.5, 0.95)


def normal_quantile(p):
    """The standard normal quantile (bisection on math.erf, to round-off)."""
    if not 0 < p < 1:
        raise ValueError(f"probability must lie in (0, 1), got {p}")
    return _bisect(lambda x: 0.5 * math.erfc(-x / math.sqrt(2)), p, -40.0, 40.0)


def _bisect(cdf, p, lo, hi):
    """x with cdf(x) = p for an increasing cdf, cdf(lo) < p < cdf(hi)."""
    for _ in range(200):
        mid = 0.5 * (lo + hi)
        if cdf(mid) < p:
            lo = mid
        else:
            hi = mid
    return 0.5 * (lo + hi)


def _beta_fraction(a, b, x):
    """The continued fraction of the incomplete beta function (modified Lentz)."""
    tiny, qab, qap, qam = 1e-300, a + b, a + 1.0, a - 1.0
    c, d = 1.0, 1.0 - qab * x / qap
    d = 1.0 / (d if abs(d) > tiny else tiny)
    h = d
    for m in range(1, 400):
        m2 = 2 * m
        for aa in (m * (b - m) * x / ((qam + m2) * (a + m2)),
                   -(a + m) * (qab + m) * x / ((a + m2) * (qap + m2))):
            d = 1.0 + aa * d
            d = 1.0 / (d if abs(d) > tiny else tiny)
            c = 1.0 + aa / c
            c = c if abs(c) > tiny else tiny
            h *= d * c
        if abs(d * c - 1.0) < 1e-15:
            break
    return h


def incomplete_beta(a, b, x):
    """The regularised incomplete beta function I_x(a, b)."""
    if x <= 0.0:
        return 0.0
    if x >= 1.0:
        return 1.0
    front = math.exp(math.lgamma(a + b) - math.lgamma(a) - math.lgamma(b) +
                     a * math.log(x) + b * math.log1p(-x))
    if x < (a + 1.0) / (a + b + 2.0):
        return front * _beta_fraction(a, b, x) / a
    return 1.0 - front * _beta_fraction(b, a, 1.0 - x) / b


def t_cdf(t, df):
    """Student's t distribution function with df (> 0, not necessarily whole) degrees of
    freedom."""
    tail = 0.5 * incomplete_beta(df / 2.0, 0.5, df / (df + t * t))
    return 1.0 - tail if t > 0 else tail


def t_quantile(p, df):
    """Student's t quantile (bisection on t_cdf); the normal quantile for infinite df."""
    if not math.isfinite(df):
        return normal_quantile(p)
    if not 0 < p < 1:
        raise ValueError(f"probability must lie in (0, 1), got {p}")
    lo, hi = -1e3, 1e3
    while t_cdf(hi, df) < p:
        hi *= 10
    while t_cdf(lo, df) > p:
        lo *= 10
    return _bisect(lambda t: t_cdf(t, df), p, lo, hi)


def describe(values, confidence=CONFIDENCE):
    """n, mean, standard deviation (n - 1), the 5/50/95 % quantiles (type 7), min, max, and the
    t interval of the mean of a sample (std, interval: None below 2 values)."""
    x = np.asarray([v for v in values if v is not None], float)
    n = int(x.size)
    if n == 0:
        return dict(n=0, mean=None, std=None, q05=None, q50=None, q95=None, min=None, max=None,
                    mean_interval=None)
    q = np.quantile(x, QUANTILES)
    std = float(np.std(x, ddof=1)) if n > 1 else None
    interval = None
    if n > 1:
        half = t_quantile(0.5 + confidence / 2, n - 1) * std / math.sqrt(n)
        interval = [float(x.mean() - half), float(x.mean() + half)]
    return dict(n=n, mean=float(x.mean()), std=std, q05=float(q[0]), q50=float(q[1]),
                q95=float(q[2]), min=float(x.min()), max=float(x.max()), mean_interval=interval)


def wilson(events, n, confidence=CONFIDENCE):
    """Probability of an event seen ``events`` times in ``n`` trials and its Wilson score
    interval: dict(events, n, p, low, high, confidence, method)."""
    if n <= 0:
        return dict(events=events, n=n, p=None, low=None, high=None, confidence=confidence,
                    method="Wilson score")
    z = normal_quantile(0.5 + confidence / 2)
    p = events / n
    centre = (p + z * z / (2 * n)) / (1 + z * z / n)
    half = z / (1 + z * z / n) * math.sqrt(p * (1 - p) / n + z * z / (4 * n * n))
    return dict(events=events, n=n, p=p, low=max(0.0, centre - half),
                high=min(1.0, centre + half), confidence=confidence, method="Wilson score")


def welch(a, b, confidence=CONFIDENCE):
    """The difference of the means of samples a and b (a - b) and its Welch t interval, and
    the ratio of the means: dict(difference, low, high, df, ratio, n_a, n_b); None unless both
    hold 2 values or more."""
    a = np.asarray([v for v in a if v is not None], float)
    b = np.asarray([v for v in b if v is not None], float)
    if a.size < 2 or b.size < 2:
        return None
    va, vb = np.var(a, ddof=1) / a.size, np.var(b, ddof=1) / b.size
    difference = float(a.mean() - b.mean())
    se = math.sqrt(va + vb)
    if se == 0.0:
        df, half = math.inf, 0.0
    else:
        df = (va + vb) ** 2 / (va ** 2 / (a.size - 1) + vb ** 2 / (b.size - 1))
        half = t_quantile(0.5 + confidence / 2, df) * se
    return dict(difference=difference, low=difference - half, high=difference + half,
                df=df if math.isfinite(df) else None, confidence=confidence,
                ratio=float(a.mean() / b.mean()) if b.mean() else None,
                n_a=int(a.size), n_b=int(b.size), method="Welch t")


def running(values):
    """How the mean and the 5/50/95 % quantiles settle as members are added, in member order:
    dict(n=[1..N], mean=[...], q05=[...], q50=[...], q95=[...])."""
    x = np.asarray([v for v in values if v is not None], float)
    out = dict(n=[], mean=[], q05=[], q50=[], q95=[])
    for n in range(1, x.size + 1):
        q = np.quantile(x[:n], QUANTILES)
        out["n"].append(n)
        out["mean"].append(float(x[:n].mean()))
        for name, value in zip(("q05", "q50", "q95"), q):
            out[name].append(float(value))
    return out
