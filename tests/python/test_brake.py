"""The brake law of bond_style wirenet (`bond_coeff T brake ...`, doc/bond_wirenet.md).

One brake bond between two nodes L0 = 0.5 m apart; node 1 stays put (no integrator), node 2 is
driven along the bond axis at constant speed through a loading path. Every step the bond's
tension (compute wirenet/local), the force on node 1, the plastic-work and released-energy
tallies of fix wirenet/bonds, the broken-bond count and the bond energy are compared with the
idealised brake written out here, independently of the code:

    envelope  F(u) = K u (u <= F_ACT/K), F_ACT (up to F_ACT/K + S), F_ACT + K_LOCK (u - u_end)
    below the largest elongation u_max: F = max(0, F(u_max) - K (u_max - u)); rupture at F_BREAK.

Energies: the work done on the bond (integrated from the force trace) is bond energy F^2/(2K) +
plastic work (+ released energy after a rupture); the plastic work after unloading from the
plateau is F_ACT times the permanent elongation, and from the lock-up branch the area of the
loop. The plastic work is a function of the bond's state (the envelope integrated exactly to the
largest elongation, less the elastic energy unloading gives back), so it matches the loop area to
round-off even on steps across a kink of the envelope, where a trapezoid of the force trace is off
by up to K du^2 / 8 (du: the elongation per step; the legs here put the kinks on step ends, except
in test_plastic_work_is_exact_across_kinks).
"""

import math

import numpy as np
import pytest

import lmp
from test_wire_errors import check_error

L0 = 0.5
F_ACT = 20e3      # N
K = 2e6           # N/m: activation at 10 mm
S = 0.05          # m: stroke ends at 60 mm
K_LOCK = 1e6      # N/m
F_BREAK = 50e3    # N: rupture at 90 mm
U_ACT = F_ACT / K
U_END = U_ACT + S
U_BREAK = U_END + (F_BREAK - F_ACT) / K_LOCK
DT = 1e-5
DU = 1e-4         # elongation per step of every leg (10 m/s)
KINK = K * DU * DU / 8  # a trapezoid's error over a step split in half by the kink at U_ACT [J]

COEFF = f"brake force {F_ACT!r} stroke {S!r} stiffness {K!r} lock {K_LOCK!r} break {F_BREAK!r}"


def envelope(u, k_lock=K_LOCK):
    if u <= 0.0:
        return 0.0
    if u <= U_ACT:
        return K * u
    if u <= U_END:
        return F_ACT
    return F_ACT + k_lock * (u - U_END)


def envelope_area(u, k_lock=K_LOCK):
    """Work along the envelope from 0 to u."""
    a = 0.5 * K * min(u, U_ACT) ** 2
    if u > U_ACT:
        a += F_ACT * (min(u, U_END) - U_ACT)
    if u > U_END:
        a += F_ACT * (u - U_END) + 0.5 * k_lock * (u - U_END) ** 2
    return a


def expected_path(us, k_lock=K_LOCK, u_break=U_BREAK):
    """Tension along a sequence of elongations, and whether the bond is intact there."""
    umax = fmax = 0.0
    broken = False
    forces, intact = [], []
    for u in us:
        if broken or u > u_break:
            broken = True
            forces.append(0.0)
            intact.append(False)
            continue
        if u >= umax:
            umax, fmax = u, envelope(u, k_lock)
            forces.append(fmax)
        else:
            forces.append(max(0.0, fmax - K * (umax - u)))
        intact.append(True)
    return np.array(forces), np.array(intact)


def write_two_nodes(path, x1=0.0, x2=L0):
    path.parent.mkdir(parents=True, exist_ok=True)
    atoms = [(1, 1, x1, 0.0, 0.0, 0.0108, 7850.0, 1), (2, 1, x2, 0.0, 0.0, 0.0108, 7850.0, 1)]
    lmp.write_data(path, atoms, [(1, 1, 1, 2)])


def monitor(l0=L0):
    """Per-step output: elongation, tension, intact bonds, strain, force on node 1, tallies."""
    return f"""compute wl all wirenet/local
compute F all reduce sum c_wl[6]
compute nb all reduce sum c_wl[3]
compute st all reduce sum c_wl[5]
compute eb all pe bond
variable u equal x[2]-x[1]-{l0!r}
variable f1 equal fx[1]
variable wpl equal f_wirenet_bonds[3]
variable erel equal f_wirenet_bonds[2]
variable nbroken equal f_wirenet_bonds
variable eb equal c_eb
thermo_style custom step v_u c_F c_nb c_st v_f1 v_wpl v_erel v_nbroken v_eb
thermo_modify format float %.17g
thermo 1
timestep {DT!r}
"""


def legs_to_runs(targets, start=0.0, first=0):
    """fix move legs through the target elongations at DU per step; returns the deck text."""
    runs, prev = [], start
    for k, target in enumerate(targets, start=first):
        n = int(round(abs(target - prev) / DU))
        v = (target - prev) / (n * DT)
        runs.append(f"fix mv{k} moving move linear {v!r} 0 0\nrun {n}\nunfix mv{k}")
        prev = target
    return "\n".join(runs) + "\n"


def head(coeff=COEFF, processors="", l0=L0):
    return lmp.PREAMBLE + processors + f"""read_data two.data
bond_style wirenet
bond_coeff 1 {coeff}
group moving id 2
""" + monitor(l0)


def rows_by_step(out):
    rows = {}
    for r in lmp.thermo_rows(out):
        rows[int(r["Step"])] = r  # a run's first row repeats the last of the run before
    return [rows[s] for s in sorted(rows)]


def column(rows, name):
    return np.array([r[name] for r in rows])


def drive(tmp_path, targets, coeff=COEFF, processors="", np_=1, x=(0.0, L0)):
    write_two_nodes(tmp_path / "two.data", *x)
    out = lmp.run_deck(head(coeff, processors, x[1] - x[0]) + legs_to_runs(targets), tmp_path, np=np_)
    return out, rows_by_step(out)


def trace_work(u, f, intact):
    """Work done on the bond by the moving node, trapezoid of the force trace over intact steps."""
    w = 0.0
    for k in range(1, len(u)):
        if intact[k]:
            w += 0.5 * (f[k] + f[k - 1]) * (u[k] - u[k - 1])
    return w


# ---- the force-elongation path ---------------------------------------------------------------

def test_envelope_unloading_reloading_and_rupture(tmp_path):
    """Elastic K, the plateau at F_ACT, lock-up K_LOCK, unloading and reloading with K, rupture
    just past F_BREAK; the output columns and the force on the fixed node."""
    targets = [0.08, 0.05, 0.085, 0.095]
    out, rows = drive(tmp_path, targets)
    assert "type 1 brake (brake): force 20000 N, stroke 0.05 m, stiffness 2e+06 N/m, lock 1e+06 N/m, " \
           "breaks at 50000 N" in out
    u, F, nb = column(rows, "u"), column(rows, "F"), column(rows, "nb")
    expected, intact = expected_path(u)
    # each branch is visited
    assert np.any((u > 0) & (u < U_ACT)) and np.any((u > U_ACT) & (u < U_END))
    assert np.any((u > U_END) & intact) and not intact[-1]

    err = np.abs(F - expected)
    assert err.max() <= 1e-9 * F_ACT, \
        f"tension off the idealised brake by {err.max():.3g} N at u = {u[err.argmax()]:.6g} m " \
        f"(got {F[err.argmax()]:.9g} N, expected {expected[err.argmax()]:.9g} N)"
    # the plateau is flat to round-off (not merely within the tolerance above)
    on_plateau = (u > U_ACT + 1e-9) & (u < U_END - 1e-9) & intact
    loading = np.concatenate([[True], np.diff(u) > 0]) & (u >= np.maximum.accumulate(u))
    plateau = on_plateau & loading
    assert plateau.sum() > 100
    assert np.abs(F[plateau] - F_ACT).max() <= 1e-12 * F_ACT, "the sliding plateau is not at F_ACT"
    # lock-up slope K_LOCK and unloading slope K, from finite differences of the trace
    lock = loading & (u > U_END + 2 * DU) & intact
    idx = np.flatnonzero(lock)
    idx = idx[np.isin(idx - 1, idx)]
    slope = (F[idx] - F[idx - 1]) / (u[idx] - u[idx - 1])
    np.testing.assert_allclose(slope, K_LOCK, rtol=1e-6, err_msg="lock-up stiffness")
    unload = np.flatnonzero((np.diff(u) < 0) & (F[1:] > 0) & (F[:-1] > 0)) + 1
    assert len(unload) > 50
    slope = (F[unload] - F[unload - 1]) / (u[unload] - u[unload - 1])
    np.testing.assert_allclose(slope, K, rtol=1e-6, err_msg="unloading stiffness")
    # unloaded from u_max = 0.08 (F = 40 kN), the force reaches zero at 0.06 and stays zero below
    slack = (u < 0.08 - 40e3 / K - 1e-9) & (u < np.maximum.accumulate(u))
    assert slack.sum() > 50 and np.all(F[slack] == 0.0)

    # rupture: at the first step past U_BREAK, with the force of the step before at F_BREAK
    k = int(np.argmax(u > U_BREAK))
    assert nb[k - 1] == 1 and nb[k] == 0 and np.all(nb[k:] == 0) and np.all(F[k:] == 0.0)
    assert column(rows, "nbroken")[k - 1] == 0 and np.all(column(rows, "nbroken")[k:] == 1)
    assert F_BREAK - K_LOCK * DU <= F[k - 1] <= F_BREAK
    np.testing.assert_allclose(column(rows, "erel")[k:], 0.5 * F[k - 1] ** 2 / K, rtol=1e-12,
                               err_msg="released energy at rupture")
    assert np.all(column(rows, "f1")[k:] == 0.0)
    # output columns: strain = elongation / l0, force on node 1 = tension along +x
    np.testing.assert_allclose(column(rows, "st")[:k] * L0, u[:k], rtol=0, atol=1e-12)
    np.testing.assert_allclose(column(rows, "f1")[:k], F[:k], rtol=1e-12, atol=0)
    # bond energy: the elastic energy of the unloading line
    np.testing.assert_allclose(column(rows, "eb")[:k], 0.5 * F[:k] ** 2 / K, rtol=1e-9, atol=1e-12)


def test_tension_only(tmp_path):
    """No force when shortened: pushed towards node 1, then back out to the elastic range."""
    _, rows = drive(tmp_path, [-0.05, 0.005])
    u, F = column(rows, "u"), column(rows, "F")
    assert u.min() < -0.049
    assert np.all(F[u <= 0] == 0.0) and np.all(column(rows, "f1")[u <= 0] == 0.0)
    np.testing.assert_allclose(F[u > 0], K * u[u > 0], rtol=1e-9)
    # elastic: nothing dissipated (the trapezoid rule's round-off only)
    assert np.abs(column(rows, "wpl")).max() <= 1e-9 * 0.5 * K * 0.005 ** 2


def test_unbreakable_without_break(tmp_path):
    """Without `break` the lock-up line goes on: far past the stroke, no rupture; default lock = K."""
    coeff = f"brake force {F_ACT!r} stroke {S!r} stiffness {K!r} family ring"
    out, rows = drive(tmp_path, [0.15], coeff=coeff)
    assert "type 1 brake (ring): force 20000 N, stroke 0.05 m, stiffness 2e+06 N/m, lock 2e+06 N/m, " \
           "never breaks" in out
    u, F = column(rows, "u"), column(rows, "F")
    expected, _ = expected_path(u, k_lock=K, u_break=math.inf)
    np.testing.assert_allclose(F, expected, rtol=0, atol=1e-9 * F_ACT)
    assert F[-1] == pytest.approx(F_ACT + K * (0.15 - U_END), rel=1e-9)   # 200 kN, past a table point
    assert np.all(column(rows, "nbroken") == 0) and np.all(column(rows, "nb") == 1)


# ---- energy ----------------------------------------------------------------------------------

@pytest.mark.parametrize("u_max", [0.04, 0.08], ids=["from_plateau", "from_lock_up"])
def test_dissipated_energy_is_the_loop_area(tmp_path, u_max):
    """Loaded to u_max, unloaded to slack: the plastic-work tally equals the loop's area, the
    work done on the bond (force trace) equals it, and no elastic energy is left. From the
    plateau that area is F_ACT times the permanent elongation."""
    f_max = envelope(u_max)
    u_perm = u_max - f_max / K
    _, rows = drive(tmp_path, [u_max, u_perm - 0.01])
    u, F = column(rows, "u"), column(rows, "F")
    assert abs(u[-1] - (u_perm - 0.01)) < 1e-9 and F[-1] == 0.0 and column(rows, "eb")[-1] == 0.0
    area = envelope_area(u_max) - 0.5 * f_max ** 2 / K
    wpl = column(rows, "wpl")[-1]
    bound = 1e-9 * area
    assert abs(wpl - area) <= bound, f"plastic work {wpl!r} J, loop area {area!r} J"
    work = trace_work(u, F, np.ones(len(u), bool))
    assert abs(work - wpl) <= 1e-9 * area, f"work done {work!r} J, plastic work {wpl!r} J"
    if u_max < U_END:
        assert area == pytest.approx(F_ACT * u_perm, rel=1e-12)
        assert abs(wpl - F_ACT * u_perm) <= bound
    else:
        # softer lock-up: the loop holds more than F_ACT times the permanent set
        assert area > F_ACT * u_perm * (1 + 1e-3)
    # along the way: work done = bond energy + plastic work at every step
    eb = column(rows, "eb")
    for k in range(0, len(u), 50):
        w = trace_work(u[:k + 1], F[:k + 1], np.ones(k + 1, bool))
        assert abs(w - eb[k] - column(rows, "wpl")[k]) <= 1e-9 * area + 1e-9


def test_plastic_work_is_exact_across_kinks(tmp_path):
    """A first leg of 41.5 steps puts the kinks of the envelope (U_ACT, U_END) half way through a
    step: the tally is still the exact loop area, where the force trace's trapezoid (what a
    per-step tally would add up) is off by about K du^2/8 at the kink of U_ACT."""
    _, rows = drive(tmp_path, [0.00415, 0.08, 0.04])
    u, F = column(rows, "u"), column(rows, "F")
    u_max = u.max()
    assert U_END < u_max < U_BREAK and F[-1] == 0.0   # through both kinks, unloaded to slack
    area = envelope_area(u_max) - 0.5 * envelope(u_max) ** 2 / K
    wpl = column(rows, "wpl")[-1]
    assert abs(wpl - area) <= 1e-12 * area, f"plastic work {wpl!r} J, loop area {area!r} J"
    work = trace_work(u, F, np.ones(len(u), bool))
    assert abs(work - area) > 0.5 * KINK, "the steps did not straddle the kinks"


def test_energy_closes_through_rupture(tmp_path):
    """Pulled to rupture: work done = plastic work + released energy."""
    _, rows = drive(tmp_path, [0.095])
    u, F, nb = column(rows, "u"), column(rows, "F"), column(rows, "nb")
    intact = nb == 1
    work = trace_work(u, F, intact)
    wpl, erel = column(rows, "wpl")[-1], column(rows, "erel")[-1]
    assert column(rows, "nbroken")[-1] == 1
    u_last = u[intact][-1]
    f_last = envelope(u_last)
    assert erel == pytest.approx(0.5 * f_last ** 2 / K, rel=1e-9)
    assert wpl == pytest.approx(envelope_area(u_last) - 0.5 * f_last ** 2 / K, rel=1e-9)
    assert abs(work - wpl - erel) <= 1e-9 * work


# ---- restart, ranks --------------------------------------------------------------------------

def test_restart_in_the_plateau_continues_identically(tmp_path):
    """write_restart in the middle of the plateau (no bond_coeff in the continuation): the rest
    of the path (lock-up, unloading, reloading, rupture) is the uninterrupted run's."""
    n1, n2 = 300, 500  # the first leg, 0 -> 0.08 m, is cut at 0.03 m
    v = 0.08 / ((n1 + n2) * DT)
    rest = legs_to_runs([0.05, 0.085, 0.095], start=0.08, first=1)
    ref_dir, first_dir, second_dir = (tmp_path / d for d in ("ref", "first", "second"))
    for d in (ref_dir, first_dir):
        d.mkdir()
        write_two_nodes(d / "two.data")
    ref = rows_by_step(lmp.run_deck(head() + f"fix mv0 moving move linear {v!r} 0 0\nrun {n1 + n2}\nunfix mv0\n"
                                    + rest, ref_dir))
    first = rows_by_step(lmp.run_deck(head() + f"fix mv0 moving move linear {v!r} 0 0\nrun {n1}\n"
                                      "write_restart two.restart\n", first_dir))
    assert U_ACT < first[-1]["u"] < U_END and first[-1]["wpl"] > 0
    second_dir.mkdir()
    (second_dir / "two.restart").write_bytes((first_dir / "two.restart").read_bytes())
    out2 = lmp.run_deck("read_restart two.restart\natom_modify sort 0 0\n" + monitor() +
                        f"fix mv0 moving move linear {v!r} 0 0\nrun {n2}\nunfix mv0\n" + rest, second_dir)
    # the coefficients came from the file
    assert "type 1 brake (brake): force 20000 N, stroke 0.05 m, stiffness 2e+06 N/m, lock 1e+06 N/m, " \
           "breaks at 50000 N" in out2
    second = rows_by_step(out2)
    ref_by_step = {int(r["Step"]): r for r in ref}
    assert int(second[0]["Step"]) == n1 and int(second[-1]["Step"]) == int(ref[-1]["Step"])
    assert second[-1]["nbroken"] == 1
    for r in second:
        q = ref_by_step[int(r["Step"])]
        for name in ("u", "F", "nb", "f1", "wpl", "erel", "nbroken", "eb"):
            assert r[name] == pytest.approx(q[name], rel=1e-12, abs=1e-300), \
                f"step {int(r['Step'])}: {name} {r[name]!r} after the restart, {q[name]!r} uninterrupted"


def test_long_stroke_across_two_ranks(tmp_path):
    """A 0.2 m brake whose nodes sit on two ranks, pulled 0.6 m (three times its length): the
    ghost reach, set at 1.05 times the bond's length when the run starts, grows with it at the
    list builds (the partner stays visible) and the forces are the one-rank run's."""
    coeff = f"brake force {F_ACT!r} stroke 0.5 stiffness {K!r}"
    targets = [0.6]
    x = (-0.1, 0.1)
    one, two = tmp_path / "one", tmp_path / "two"
    _, rows1 = drive(one, targets, coeff=coeff, x=x)
    out2, rows2 = drive(two, targets, coeff=coeff, processors="processors 2 1 1\n", np_=2, x=x)
    assert "2 by 1 by 1 MPI processor grid" in out2
    assert rows2[-1]["u"] == pytest.approx(0.6, abs=1e-9)
    for a, b in zip(rows1, rows2):
        assert a["F"] == pytest.approx(b["F"], rel=1e-12, abs=0)
        assert a["wpl"] == pytest.approx(b["wpl"], rel=1e-12, abs=0)
    assert rows2[-1]["F"] == pytest.approx(F_ACT + K * (0.6 - U_ACT - 0.5), rel=1e-9)


# ---- bad input -------------------------------------------------------------------------------

GOOD = f"brake force {F_ACT!r} stroke {S!r} stiffness {K!r}"
BAD_COEFFS = {
    "force zero": ("brake force 0 stroke 0.05 stiffness 2e6", "brake force must be a finite number > 0 (got 0)"),
    "force negative": ("brake force -2e4 stroke 0.05 stiffness 2e6", "brake force must be a finite number > 0 (got -20000)"),
    "force inf": ("brake force inf stroke 0.05 stiffness 2e6", "brake force must be a finite number > 0 (got inf)"),
    "force nan": ("brake force nan stroke 0.05 stiffness 2e6", "brake force must be a finite number > 0 (got nan)"),
    "force overflow": ("brake force 1e999 stroke 0.05 stiffness 2e6", "brake force must be a finite number > 0 (got inf)"),
    "force text": ("brake force 2e4x stroke 0.05 stiffness 2e6", "brake force must be a number (got '2e4x')"),
    "force value is a keyword": ("brake force stroke 0.05 stiffness 2e6", "brake force must be a number (got 'stroke')"),
    "stroke zero": ("brake force 2e4 stroke 0 stiffness 2e6", "brake stroke must be a finite number > 0 (got 0)"),
    "stroke negative": ("brake force 2e4 stroke -0.05 stiffness 2e6", "brake stroke must be a finite number > 0 (got -0.05)"),
    "stroke -inf": ("brake force 2e4 stroke -inf stiffness 2e6", "brake stroke must be a finite number > 0 (got -inf)"),
    "stiffness zero": ("brake force 2e4 stroke 0.05 stiffness 0", "brake stiffness must be a finite number > 0 (got 0)"),
    "stiffness nan": ("brake force 2e4 stroke 0.05 stiffness nan", "brake stiffness must be a finite number > 0 (got nan)"),
    "lock zero": (f"{GOOD} lock 0", "brake lock must be a finite number > 0 and <= the stiffness 2e+06"),
    "lock stiffer than K": (f"{GOOD} lock 3e6", "brake lock must be a finite number > 0 and <= the stiffness 2e+06 "
                                               "(unloading follows the stiffness; got 3e+06)"),
    "lock inf": (f"{GOOD} lock inf", "got inf)"),
    "break at the force": (f"{GOOD} break 20000", "brake break must be a finite number > the force 20000 (got 20000)"),
    "break below the force": (f"{GOOD} break 1e4", "brake break must be a finite number > the force 20000 (got 10000)"),
    "break nan": (f"{GOOD} break nan", "brake break must be a finite number > the force 20000 (got nan)"),
    "damping negative": (f"{GOOD} damping -0.1", "brake damping must be a finite number >= 0 (got -0.1)"),
    "damping inf": (f"{GOOD} damping inf", "brake damping must be a finite number >= 0 (got inf)"),
    "no parameters": ("brake", "missing brake force"),
    "stroke missing": ("brake force 2e4 stiffness 2e6", "missing brake stroke"),
    "stiffness missing": ("brake force 2e4 stroke 0.05", "missing brake stiffness"),
    "value missing at the end": ("brake force 2e4 stroke 0.05 stiffness", "missing brake stiffness"),
    "break value missing": (f"{GOOD} break", "missing brake break"),
    "family name missing": (f"{GOOD} family", "missing family name"),
    "given twice": (f"{GOOD} force 3e4", "brake force is given twice"),
    "unknown keyword": (f"{GOOD} diameter 0.01", "unknown brake keyword 'diameter'"),
    "number where a keyword is due": (f"{GOOD} 5", "unexpected number '5' in the brake options"),
    "stroke lost to round-off": ("brake force 1e6 stroke 1e-30 stiffness 1", "brake stroke 1e-30 is lost to round-off"),
    "break lost to round-off": ("brake force 1e6 stroke 1e20 stiffness 1e6 break 2e6",
                                "brake break 2e+06 is lost to round-off"),
}


def write_pair(path):
    atoms = [(1, 1, 0.0, 0.0, 0.0, 0.0108, 7850.0, 1), (2, 1, 0.04, 0.0, 0.0, 0.0108, 7850.0, 1)]
    lmp.write_data(path, atoms, [(1, 1, 1, 2)])


@pytest.mark.parametrize("case", sorted(BAD_COEFFS))
def test_bad_brake_coeff(tmp_path, case):
    args, phrase = BAD_COEFFS[case]
    write_pair(tmp_path / "pair.data")
    deck = lmp.PREAMBLE + f"read_data pair.data\nbond_style wirenet\nbond_coeff 1 {args}\nrun 0\n"
    rc, out = lmp.run_deck_rc(deck, tmp_path)
    line = check_error(rc, out, phrase)
    assert "bond_coeff 1:" in line  # names the command and the type


def test_unknown_law_names_brake(tmp_path):
    write_pair(tmp_path / "pair.data")
    deck = lmp.PREAMBLE + "read_data pair.data\nbond_style wirenet\nbond_coeff 1 breaks force 1\n"
    rc, out = lmp.run_deck_rc(deck, tmp_path)
    check_error(rc, out, "unknown law 'breaks' (expected wire, beam or brake)")
