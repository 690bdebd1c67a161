"""Random initial slack of the wire law (`slack lambda_u LU lambda_f LF seed S`, Thoeni et al. 2013).

doc/bond_wirenet.md: each bond gets dl = lambda_u * l0 * r, r in [0, 1] triangular with mode 1/2,
drawn from the seed and the two atom IDs only (not the creation order, not the order of the IDs).

N = 10^4 disjoint two-node pairs in one data file, initial lengths spread over 30-60 mm. After the
first run has set l0, every second node is moved by U = 20 um along its bond and `compute
wirenet/local` gives each bond's length0, length and tension. U lies on the first loading branch of
every bond (below dl + lambda_f e1 l0' for any dl >= 0), where the documented law is

    F = k* u,   k* = lambda_f F1 / (dl + lambda_f e1 l0'),   l0' = l0 + dl,   F1 = s1 A,

so each bond's slack follows exactly: dl = lambda_f (F1 u / F - e1 l0) / (1 + lambda_f e1), and
r = dl / (lambda_u l0). The r sample is checked against the triangular distribution: mean,
variance, range, and a Kolmogorov-Smirnov test (numpy only).

The sample is fixed by the seed, so the statistical checks are deterministic; their thresholds
are those of a two-sided test at ALPHA = 1e-3: a correct sampler fails them for about one seed in
a thousand, a wrong distribution (uniform, constant, not scaled by l0) fails by orders of
magnitude (see tests/README.md).
"""

import math

import numpy as np
import pytest

import lmp

N = 10_000
D = 0.0027
A = math.pi * D**2 / 4
SW = [(0.0019230769, 2.5e8), (0.0192, 3.2195e8), (0.05, 3.8292e8), (0.15, 5.1219e8),
      (0.25, 5.5854e8), (0.30, 5.6585e8), (0.35, 5.6585e8)]
CURVE = " ".join(f"{e!r} {s!r}" for e, s in SW)
E1, S1 = SW[0]
F1 = S1 * A
LU, LF = 0.2, 0.8
U = 2e-5                      # probe elongation: < lambda_f e1 l0 = 4.6e-5 m for the shortest bond
SEED_A, SEED_B = 4711, 987654321
DERIVED = dict(lambda_eps=0.4, lambda_k=0.66, nu=0.3)
ALPHA = 1e-3
Z = 3.2905                    # two-sided normal quantile for ALPHA = 1e-3
SPACING = 0.02                # pairs on a 100 x 100 grid in (y, z), each along x


def pair_lengths():
    return 0.03 + 0.03 * np.random.default_rng(2013).random(N)


def write_pairs(path, permuted=False):
    """Pair k joins atoms 2k+1 (type 1, x = 0) and 2k+2 (type 2, x = l0_k).
    permuted: the same ID pairs and lengths, but each pair at another grid cell, the Atoms and
    Bonds sections shuffled, bond IDs renumbered and the two IDs of every other bond swapped (so
    the other node stores the bond): nothing the documented draw depends on changes."""
    l0 = pair_lengths()
    rng = np.random.default_rng(99)
    cell = rng.permutation(N) if permuted else np.arange(N)
    atoms, bonds = [], []
    for k in range(N):
        y, z = SPACING * (cell[k] % 100), SPACING * (cell[k] // 100)
        a, b = 2 * k + 1, 2 * k + 2
        atoms.append((a, 1, 0.0, y, z, 0.0108, 7850.0, k + 1))
        atoms.append((b, 2, float(l0[k]), y, z, 0.0108, 7850.0, k + 1))
        bonds.append((a, b))
    if permuted:
        atoms = [atoms[i] for i in rng.permutation(len(atoms))]
        bonds = [bonds[i] for i in rng.permutation(N)]
        bonds = [(b, a) if i % 2 else (a, b) for i, (a, b) in enumerate(bonds)]
    bonds = [(i + 1, 1, a, b) for i, (a, b) in enumerate(bonds)]
    lmp.write_data(path, atoms, bonds, natom_types=2,
                   box=((-0.05, 0.12), (-0.05, 100 * SPACING), (-0.05, 100 * SPACING)))


def coeff(seed, derived=False):
    d = " derived lambda_eps {lambda_eps} lambda_k {lambda_k} nu {nu}".format(**DERIVED) if derived else ""
    return f"wire diameter {D} curve {CURVE}{d} slack lambda_u {LU} lambda_f {LF} seed {seed}"


def probe(workdir, data, coeff_text):
    """Rows atom1 atom2 type length0 strain tension length of every bond at elongation U."""
    deck = lmp.PREAMBLE + f"""read_data {data}
bond_style wirenet
bond_coeff 1 {coeff_text}
group far type 2
run 0
displace_atoms far move {U!r} 0 0 units box
compute wl all wirenet/local
dump d all local 1 bonds.dump c_wl[1] c_wl[2] c_wl[3] c_wl[4] c_wl[5] c_wl[6] c_wl[7]
dump_modify d format "%.0f %.0f %.0f %.17g %.17g %.17g %.17g"
run 0
"""
    lmp.run_deck(deck, workdir)
    frames = lmp.dump_local_frames(workdir / "bonds.dump")
    rows = frames[max(frames)]
    assert len(rows) == N, f"{len(rows)} bond rows, expected {N}"
    return rows


def slack_by_pair(rows, scale=1.0):
    """{(min id, max id): dl} from the probe rows; scale = k_D/k for a derived law."""
    l0, L, F = rows[:, 3], rows[:, 6], rows[:, 5]
    u = L - l0
    assert np.all(F > 0), "a bond carries no tension at the probe elongation"
    dl = LF * (scale * F1 * u / F - E1 * l0) / (1 + LF * E1)
    ids = np.sort(rows[:, :2].astype(np.int64), axis=1)
    return {(int(a), int(b)): (d, l) for (a, b), d, l in zip(ids, dl, l0)}


def r_sample(by_pair):
    keys = sorted(by_pair)
    return np.array([by_pair[k][0] / (LU * by_pair[k][1]) for k in keys])


def tri_cdf(r):
    r = np.clip(r, 0.0, 1.0)
    return np.where(r <= 0.5, 2 * r * r, 1 - 2 * (1 - r) ** 2)


def ks_pvalue(d, n):
    """Asymptotic Kolmogorov distribution, P(D_n > d), with Stephens' small-n correction."""
    x = d * (math.sqrt(n) + 0.12 + 0.11 / math.sqrt(n))
    k = np.arange(1, 101)
    return float(min(1.0, max(0.0, 2 * np.sum((-1.0) ** (k - 1) * np.exp(-2 * k * k * x * x)))))


def ks_statistic(sample, cdf):
    x = np.sort(sample)
    n = len(x)
    c = cdf(x)
    return max(np.max(np.arange(1, n + 1) / n - c), np.max(c - np.arange(0, n) / n))


def check_triangular(r, label):
    n = len(r)
    assert r.min() >= -1e-9 and r.max() <= 1 + 1e-9, f"{label}: r outside [0, 1]: [{r.min()}, {r.max()}]"
    # mean 1/2, variance 1/24; sd of the sample variance from the 4th central moment 1/240
    mean, var = r.mean(), r.var(ddof=1)
    tol_mean = Z * math.sqrt(1 / 24 / n)
    tol_var = Z * math.sqrt((1 / 240 - (1 / 24) ** 2) / n)
    assert abs(mean - 0.5) < tol_mean, f"{label}: mean of r {mean:.5f}, expected 0.5 +- {tol_mean:.5f}"
    assert abs(var - 1 / 24) < tol_var, f"{label}: variance of r {var:.6f}, expected {1 / 24:.6f} +- {tol_var:.6f}"
    d = ks_statistic(r, tri_cdf)
    p = ks_pvalue(d, n)
    assert p > ALPHA, f"{label}: KS statistic {d:.4f} against the triangular law, p = {p:.2e} < {ALPHA}"
    return d, p


def kd_over_k(l0):
    """Bertrand et al. (2008) scaling of the derived double-twist law, doc/bond_wirenet.md."""
    alpha = np.arctan(l0 / (3 * math.pi * D))
    kh_over_k = (l0 * D / A) / (48 * np.cos(alpha) * (41 / 9 * (1 + DERIVED["nu"]) + 17 / 4 * np.tan(alpha) ** 2))
    return 2 * (DERIVED["lambda_k"] * kh_over_k + (1 - DERIVED["lambda_k"]))


@pytest.fixture(scope="module")
def base(tmp_path_factory):
    wd = tmp_path_factory.mktemp("slack")
    write_pairs(wd / "pairs.data")
    return wd


@pytest.fixture(scope="module")
def seed_a(base):
    return slack_by_pair(probe(base / "a", "../pairs.data", coeff(SEED_A)))


def test_slack_is_triangular(seed_a):
    r = r_sample(seed_a)
    assert len(r) == N
    check_triangular(r, f"seed {SEED_A}")
    # the slack is proportional to l0 (r does not depend on it): the lower and upper halves of
    # the lengths have the same mean r within the test's tolerance
    l0 = np.array([seed_a[k][1] for k in sorted(seed_a)])
    short, long_ = r[l0 < np.median(l0)], r[l0 >= np.median(l0)]
    tol = Z * math.sqrt(1 / 24 / len(short) + 1 / 24 / len(long_))
    assert abs(short.mean() - long_.mean()) < tol, \
        f"mean r {short.mean():.4f} for short bonds, {long_.mean():.4f} for long ones: dl is not lambda_u l0 r"


def test_same_slack_in_a_permuted_data_file(base, seed_a):
    write_pairs(base / "permuted.data", permuted=True)
    perm = slack_by_pair(probe(base / "perm", "../permuted.data", coeff(SEED_A)))
    assert sorted(perm) == sorted(seed_a)
    a = np.array([seed_a[k][0] for k in sorted(seed_a)])
    b = np.array([perm[k][0] for k in sorted(seed_a)])
    # dl ~ 1e-3 m; the extraction is exact to round-off (~1e-17 m)
    err = np.abs(a - b).max()
    assert err < 1e-12 * LU * 0.06, f"the slack of a bond changed with the order of the data file by {err:.3g} m"


def test_another_seed_gives_another_set(base, seed_a):
    other = slack_by_pair(probe(base / "b", "../pairs.data", coeff(SEED_B)))
    ra, rb = r_sample(seed_a), r_sample(other)
    check_triangular(rb, f"seed {SEED_B}")
    same = np.isclose(ra, rb, rtol=0, atol=1e-9).mean()
    assert same < 1e-3, f"{100 * same:.1f} % of the bonds have the same slack for seeds {SEED_A} and {SEED_B}"
    rho = np.corrcoef(ra, rb)[0, 1]
    assert abs(rho) < Z / math.sqrt(N), f"slacks of the two seeds are correlated (rho = {rho:.4f})"


def test_derived_with_slack_uses_the_same_draw(base, seed_a):
    """`derived` scales the forces of the table by k_D/k (per bond, from l0) and keeps the first
    strain; the slack acts on the derived table with the same draw: the derived bond's force at
    the probe is the plain one times k_D/k, i.e. the dl extracted with F1' = F1 k_D/k is the same."""
    rows = probe(base / "derived", "../pairs.data", coeff(SEED_A, derived=True))
    ids = [tuple(sorted(map(int, r[:2]))) for r in rows]
    scale = kd_over_k(rows[:, 3])
    assert np.all((scale > 0.2) & (scale < 2.0))
    derived = slack_by_pair(rows, scale)
    for k in ids[:: N // 100]:
        assert abs(derived[k][0] - seed_a[k][0]) < 1e-12, f"bond {k}: dl {derived[k][0]} derived, {seed_a[k][0]} plain"
    a = np.array([seed_a[k][0] for k in ids])
    b = np.array([derived[k][0] for k in ids])
    assert np.abs(a - b).max() < 1e-12


def envelope_derived_slack(u, l0, dl, scale):
    """Documented envelope of a derived law with slack (lambda_f < 1 inserts a point)."""
    strain = [E1] + [DERIVED["lambda_eps"] * e for e, _ in SW[1:]]
    force = [scale * s * A for _, s in SW]
    strain, force = [LF * strain[0]] + strain, [LF * force[0]] + force
    l0p = l0 + dl
    us = [0.0] + [e * l0p + dl for e in strain]
    fs = [0.0] + force
    return float(np.interp(u, us, fs))


def test_derived_with_slack_seed_minus_one_closed_form(tmp_path):
    """Seed -1: dl = lambda_u l0 for every bond. One bond driven through the first loading branch,
    the inserted lambda_f point, the elastic point, a derived plastic point, then unloaded: each
    tension against the documented law (k* branch, table, unloading stiffness F1'/(e1 l0'))."""
    l0 = 0.05
    atoms = [(1, 1, 0.0, 0.0, 0.0, 0.0108, 7850.0, 1), (2, 2, l0, 0.0, 0.0, 0.0108, 7850.0, 1)]
    lmp.write_data(tmp_path / "one.data", atoms, [(1, 1, 1, 2)], natom_types=2)
    dl = LU * l0
    scale = float(kd_over_k(np.array(l0)))
    l0p = l0 + dl
    u_lf = dl + LF * E1 * l0p            # inserted point
    u_1 = dl + E1 * l0p                   # elastic point
    u_2 = dl + DERIVED["lambda_eps"] * SW[1][0] * l0p
    path = [0.5 * u_lf, u_lf, 0.5 * (u_lf + u_1), u_1, 0.5 * (u_1 + u_2), u_2, 1.3 * u_2, 1.3 * u_2 - 0.5 * u_1]
    deck = lmp.PREAMBLE + f"""read_data one.data
bond_style wirenet
bond_coeff 1 {coeff(-1, derived=True)}
group far type 2
compute wl all wirenet/local
compute F all reduce sum c_wl[6]
variable u equal x[2]-x[1]-{l0!r}
thermo_style custom step v_u c_F
thermo_modify format float %.17g
run 0
"""
    prev = 0.0
    for u in path:
        deck += f"displace_atoms far move {u - prev!r} 0 0 units box\nrun 0\n"
        prev = u
    rows = lmp.thermo_rows(lmp.run_deck(deck, tmp_path))[1:]
    assert len(rows) == len(path)
    k_u = scale * F1 / (E1 * l0p)
    umax = fmax = 0.0
    for want_u, row in zip(path, rows):
        u, F = row["u"], row["F"]
        assert abs(u - want_u) < 1e-15
        if u >= umax:
            umax, fmax = u, envelope_derived_slack(u, l0, dl, scale)
            want = fmax
        else:
            want = max(0.0, fmax - k_u * (umax - u))
        assert abs(F - want) <= 1e-9 * abs(want), f"u = {u:.6g} m: tension {F!r} N, documented law {want!r} N"
    # the first branch is k* = lambda_f F1' / (dl + lambda_f e1 l0')
    k_star = LF * scale * F1 / (dl + LF * E1 * l0p)
    assert abs(rows[0]["F"] / rows[0]["u"] - k_star) <= 1e-9 * k_star
