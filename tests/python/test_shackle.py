"""fix wirenet/shackle (doc/fix_wirenet_shackle.md): a node held on a rope by a shackle that slides
along it with Coulomb friction (issue #18).

A straight rope of 4 segments of 0.05 m along x (atoms 1..5) and a shackle node S (atom 6) of
mass m, held across the rope by the normal spring kn and along it by the stick spring kt capped
at mu |F_n|. S starts at the offset y = -N/kn under a load -N along y, so the normal spring holds
N from the first step (no normal oscillation) and the friction cap is mu N. Analytic results:

  stick  (P < mu N, damped): S settles at x0 + P/kt; the rope atoms of its segment carry
         -(1-s) F and -s F (F: the shackle force on S), together (P, -N);
  slide  (P > mu N): after the stick phase x - x0 = (P/kt)(1 - cos w t), w^2 = kt/m, reached
         the cap at cos w t_c = 1 - mu N/P, S accelerates at a = (P - mu N)/m; velocity Verlet
         integrates a constant force exactly, so every second difference of x is a dt^2 (round-off)
         across the segment boundaries too; friction work = mu N (travel - mu N/kt), the slip;
  pulled at constant velocity: the force along the rope rises with slope kt to mu N and stays
         there; reversed, it crosses to +mu N over the travel 2 mu N/kt;
  free rope, no external force: total momentum conserved to round-off (1 and 2 ranks);
  damping ZETA: the normal swing decays as a damped oscillator, its work is the energy lost;
  rest initial: a tension-only link of the initial offset (slack inside it, kn (|d| - r0) beyond);
  1 and 2 MPI ranks (rope and slide across the rank boundary) and a restart mid-slide agree with
  the serial, uninterrupted run to round-off.

Mutations checked by hand when the tests were written (2026-11-23; each made the tests named
fail, then was undone):
  friction cap dropped (no Coulomb limit)      -> slide, end stop, plateau, 1 vs 2 ranks, restart
  friction force's sign flipped                -> stick, slide, plateau, 1 vs 2 ranks
  (1-s, s) split of the reaction swapped       -> stick
  no walk to the next segment                  -> slide, 1 vs 2 ranks
  reverse communication of ghost forces skipped -> momentum on 2 ranks, 1 vs 2 ranks
  setup pass moving the history (xi += v dt)   -> restart (1 and 2 ranks)
  xi not carried by pack/unpack_exchange       -> 1 vs 2 ranks, restart on 2 ranks
  xi not restored by unpack_restart            -> restart (1 and 2 ranks)
  offset always projected across the segment   -> convex vertex and end, end stop
  rest-offset link two-sided (pushes when slack) -> rest initial
"""

import math

import numpy as np
import pytest

import lmp
from test_wire_errors import check_error

L = 0.05             # segment length [m]
NSEG = 4
D_S, RHO = 0.02, 7850.0
M_S = RHO * math.pi / 6 * D_S ** 3
KN, KT, MU = 1e5, 1e5, 0.3
N_LOAD = 100.0       # N across the rope
DT = 1e-5
OFFSET = N_LOAD / KN


def rope_file(path, nrope=NSEG + 1, shackle=NSEG + 2):
    ids = " ".join(str(k) for k in range(1, nrope + 1))
    path.write_text(f"# test rope\nropes 1\nR1 {nrope} {ids}\nshackles 1\n{shackle} R1\n")


def write_setup(wd, x_s, y_s=-OFFSET, x0=0.0, rope_density=RHO, nrope=NSEG + 1):
    wd.mkdir(parents=True, exist_ok=True)
    atoms = [(k + 1, 1, x0 + k * L, 0.0, 0.0, 0.01, rope_density, 1) for k in range(nrope)]
    atoms.append((nrope + 1, 1, x_s, y_s, 0.0, D_S, RHO, 1))
    lmp.write_data(wd / "rope.data", atoms, [], nbond_types=0)
    rope_file(wd / "rope.shackles", nrope, nrope + 1)


def monitor(nrope=NSEG + 1, every=1):
    s = nrope + 1
    cols = [f"x[{s}]", f"y[{s}]", f"fx[{s}]", f"fy[{s}]"]
    names = ["xs", "ys", "fxs", "fys"]
    for k in range(1, nrope + 1):
        cols += [f"fx[{k}]", f"fy[{k}]", f"x[{k}]", f"y[{k}]"]
        names += [f"fx{k}", f"fy{k}", f"x{k}", f"y{k}"]
    lines = [f"variable {n} equal {c}" for n, c in zip(names, cols)]
    lines += ["variable w equal f_sh", "variable w1 equal f_sh[1]", "variable el equal f_sh[2]",
              "variable nsl equal f_sh[3]", "variable fmax equal f_sh[4]",
              "variable px equal vcm(all,x)*mass(all)", "variable py equal vcm(all,y)*mass(all)"]
    lines.append("thermo_style custom step " + " ".join(f"v_{n}" for n in names + ["w", "w1", "el", "nsl", "fmax", "px", "py"]))
    lines += ["thermo_modify format float %.17g", f"thermo {every}", f"timestep {DT!r}"]
    return "\n".join(lines) + "\n"


def head(extra="", processors="", coeffs=f"kn {KN!r} kt {KT!r} mu {MU!r}"):
    return lmp.PREAMBLE + processors + f"""read_data rope.data
group rope id 1:5
group S id 6
{extra}fix sh all wirenet/shackle file rope.shackles {coeffs}
"""


def rows_by_step(out):
    rows = {}
    for r in lmp.thermo_rows(out):
        rows[int(r["Step"])] = r
    return [rows[k] for k in sorted(rows)]


def col(rows, name):
    return np.array([r[name] for r in rows])


# ---- 1. stick ---------------------------------------------------------------------------------

def test_stick_holds_at_p_over_kt_and_splits_the_reaction(tmp_path):
    P, X0 = 12.0, 0.07          # 2 P < mu N: not even the first undamped swing slips
    write_setup(tmp_path, X0)
    deck = head() + f"""fix integ S nve/sphere
fix load S addforce {P!r} {-N_LOAD!r} 0
fix calm S viscous 50
""" + monitor(every=100) + "run 4000\n"
    rows = rows_by_step(lmp.run_deck(deck, tmp_path))
    last = rows[-1]
    assert max(col(rows, "nsl")) == 0 and max(col(rows, "w")) == 0.0, "a sticking shackle slid"
    assert last["xs"] - X0 == pytest.approx(P / KT, rel=1e-8)
    assert last["ys"] == pytest.approx(-OFFSET, rel=1e-9)
    # the shackle force on S is (-P, +N); the rope atoms of segment 2-3 carry -(1-s) F and -s F
    s = (last["xs"] - L) / L
    assert 0.4 < s < 0.5
    for k, w in ((2, 1 - s), (3, s)):
        assert last[f"fx{k}"] == pytest.approx(w * P, rel=1e-8)
        assert last[f"fy{k}"] == pytest.approx(-w * N_LOAD, rel=1e-8)
    for k in (1, 4, 5):
        assert last[f"fx{k}"] == 0.0 and last[f"fy{k}"] == 0.0
    assert last["el"] == pytest.approx(0.5 * N_LOAD ** 2 / KN + 0.5 * P ** 2 / KT, rel=1e-7)
    assert last["fmax"] == pytest.approx(math.hypot(P, N_LOAD), rel=1e-8)


# ---- 2. slide at the friction force -----------------------------------------------------------

def slide_deck(P, steps, extra="", every=1):
    """S integrated and loaded; the rope atoms held (not integrated)."""
    return head() + f"""fix integ S nve/sphere
fix load S addforce {P!r} {-N_LOAD!r} 0
{extra}""" + monitor(every=every) + f"run {steps}\n"


def test_slide_accelerates_at_p_minus_mu_n_over_m(tmp_path):
    P, X0, steps = 50.0, 0.02, 2000
    write_setup(tmp_path, X0)
    rows = rows_by_step(lmp.run_deck(slide_deck(P, steps), tmp_path))
    x, nsl = col(rows, "xs") - X0, col(rows, "nsl")
    t = np.arange(len(x)) * DT
    a = (P - MU * N_LOAD) / M_S
    # stick phase, then the cap (analytic transition time)
    w = math.sqrt(KT / M_S)
    tc = math.acos(1 - MU * N_LOAD / P) / w
    first = int(np.argmax(nsl > 0))
    assert abs(first * DT - tc) <= 1.5 * DT, (first * DT, tc)
    assert np.all(nsl[first:] == 1) and np.all(nsl[:first] == 0)
    # from one step into the slide on: every second difference is a dt^2, across the segment
    # boundaries at x = 0.05 and 0.10 too (no jump)
    assert x[-1] + X0 > 2 * L + 0.01, "did not cross two segment boundaries"
    d2 = x[first + 2:] - 2 * x[first + 1:-1] + x[first:-2]
    np.testing.assert_allclose(d2, a * DT * DT, rtol=1e-6)
    # the whole trajectory against the analytic stick-then-slide motion; the tolerance is the
    # discretisation of the stick phase and of the step that reaches the cap: a velocity error
    # of at most (P/m) dt carried over the slide
    xc = (P / KT) * (1 - math.cos(w * tc))
    vc = (P / (M_S * w)) * math.sin(w * tc)
    tau = np.maximum(t - tc, 0.0)
    exact = np.where(t < tc, (P / KT) * (1 - np.cos(w * t)), xc + vc * tau + 0.5 * a * tau ** 2)
    assert np.abs(x - exact).max() <= (P / M_S) * DT * t[-1] + 1e-9
    # friction work = mu N times the slip (travel less the elastic stick displacement)
    slip = x[-1] - MU * N_LOAD / KT
    assert col(rows, "w")[-1] == pytest.approx(MU * N_LOAD * slip, rel=1e-9)
    assert col(rows, "w1")[-1] == col(rows, "w")[-1]
    # the rope carries (mu N, -N) in total, on the segment under S
    last = rows[-1]
    fx = sum(last[f"fx{k}"] for k in range(1, 6))
    fy = sum(last[f"fy{k}"] for k in range(1, 6))
    assert fx == pytest.approx(MU * N_LOAD, rel=1e-9) and fy == pytest.approx(-N_LOAD, rel=1e-9)
    assert last["fx1"] == last["fx2"] == 0.0 and last["fx3"] != 0.0 and last["fx4"] != 0.0
    assert last["fmax"] == pytest.approx(math.hypot(MU * N_LOAD, N_LOAD), rel=1e-9)


def test_shackle_stops_at_the_rope_end(tmp_path):
    """Pulled past the last rope atom, the shackle stays there: the end acts as a stop, held by
    the normal spring on the whole offset from the end atom, which takes the whole load."""
    P, X0 = 50.0, 0.19
    write_setup(tmp_path, X0)
    rows = rows_by_step(lmp.run_deck(slide_deck(P, 10000, "fix calm S viscous 50\n", every=100), tmp_path))
    last = rows[-1]
    end = NSEG * L
    # at rest beyond the end by (P - F_t)/kn, F_t the friction left in the stick spring (|F_t| <= mu |F_n|)
    cap = MU * math.hypot(N_LOAD, 2 * P)
    assert (P - cap) / KN <= last["xs"] - end <= (P + cap) / KN
    assert max(col(rows, "xs")) <= end + 2 * (P + cap) / KN
    assert last["fx5"] == pytest.approx(P, rel=1e-6) and last["fy5"] == pytest.approx(-N_LOAD, rel=1e-6)
    assert last["fx4"] == 0.0 and last["fy4"] == 0.0


# ---- geometry: convex vertex and rope end ------------------------------------------------------

def test_convex_vertex_and_rope_end_clamp_to_the_atom(tmp_path):
    """A rope bent by 30 degrees at atom 2 and three shackles held still (setup pass, no history):
    one in the wedge outside the bend (closest point: the vertex), one beyond the rope's end
    (closest point: the end atom), one inside segment 1. F = -kn (S - P) on each, and the whole
    reaction on the vertex / end atom, (1-s, s) inside the segment."""
    th = math.radians(30.0)
    r = [np.array([-0.1, 0.0, 0.0]), np.zeros(3), np.array([0.1 * math.cos(th), 0.1 * math.sin(th), 0.0])]
    t2 = (r[2] - r[1]) / 0.1
    n2 = np.array([t2[1], -t2[0], 0.0])                          # right of segment 2
    bis = (np.array([0.0, -1.0, 0.0]) + n2) / np.linalg.norm(np.array([0.0, -1.0, 0.0]) + n2)
    s_wedge = r[1] + 0.002 * bis
    s_end = r[2] + 0.003 * t2 + 0.001 * n2
    s_mid = np.array([-0.06, 0.001, 0.0])
    atoms = [(k + 1, 1, *map(float, r[k]), 0.01, RHO, 1) for k in range(3)]
    atoms += [(4 + k, 1, *map(float, p), D_S, RHO, 1) for k, p in enumerate((s_wedge, s_end, s_mid))]
    lmp.write_data(tmp_path / "rope.data", atoms, [], nbond_types=0)
    (tmp_path / "rope.shackles").write_text("ropes 1\nbent 3 1 2 3\nshackles 3\n4 bent\n5 bent\n6 bent\n")
    names = [f"f{c}{k}" for k in range(1, 7) for c in "xyz"]
    deck = lmp.PREAMBLE + f"read_data rope.data\nfix sh all wirenet/shackle file rope.shackles {GOOD}\n" + \
        "".join(f"variable f{c}{k} equal f{c}[{k}]\n" for k in range(1, 7) for c in "xyz") + \
        "variable el equal f_sh[2]\nthermo_style custom step " + " ".join(f"v_{n}" for n in names) + \
        " v_el\nthermo_modify format float %.17g\nrun 0\n"
    row = rows_by_step(lmp.run_deck(deck, tmp_path))[-1]
    f = {k: np.array([row[f"f{c}{k}"] for c in "xyz"]) for k in range(1, 7)}
    F_wedge, F_end = -KN * (s_wedge - r[1]), -KN * (s_end - r[2])
    F_mid = np.array([0.0, -KN * 0.001, 0.0])
    np.testing.assert_allclose(f[4], F_wedge, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(f[5], F_end, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(f[6], F_mid, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(f[1], -0.6 * F_mid, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(f[2], -F_wedge - 0.4 * F_mid, rtol=1e-9, atol=1e-9)
    np.testing.assert_allclose(f[3], -F_end, rtol=1e-9, atol=1e-9)
    d2 = sum(float(np.dot(x, x)) for x in (s_wedge - r[1], s_end - r[2], np.array([0, 0.001, 0])))
    assert row["el"] == pytest.approx(0.5 * KN * d2, rel=1e-9)


# ---- 3. pulled at constant velocity -----------------------------------------------------------

def test_pulled_at_constant_velocity_plateau_is_mu_n(tmp_path):
    V, X0, n = 0.5, 0.03, 1000
    write_setup(tmp_path, X0)
    deck = head() + f"fix drive S move linear {V!r} 0 0\n" + monitor() + f"run {n}\nunfix drive\n" + \
        f"fix back S move linear {-V!r} 0 0\nrun {n}\n"
    rows = rows_by_step(lmp.run_deck(deck, tmp_path))
    x, f, w = col(rows, "xs") - X0, col(rows, "fxs"), col(rows, "w")
    assert np.all(col(rows, "fys") == pytest.approx(N_LOAD, rel=1e-9))
    cap = MU * N_LOAD
    out = np.arange(len(x)) <= n
    # loading with slope kt up to the cap, then the plateau -mu N
    stick = out & (KT * x < cap - 1e-9)
    np.testing.assert_allclose(f[stick], -KT * x[stick], rtol=1e-9, atol=1e-9)
    plateau = out & (KT * x > cap + 1e-9)
    assert plateau.sum() > 800
    np.testing.assert_allclose(f[plateau], -cap, rtol=1e-12)
    # back: the force crosses to +mu N over the travel 2 mu N / kt, then the plateau +mu N
    back = np.arange(len(x)) > n
    xr = x[n] - x
    ramp = back & (KT * xr < 2 * cap - 1e-9)
    np.testing.assert_allclose(f[ramp], -cap + KT * xr[ramp], rtol=1e-9, atol=1e-9)
    plateau2 = back & (KT * xr > 2 * cap + 1e-9)
    assert plateau2.sum() > 700
    np.testing.assert_allclose(f[plateau2], cap, rtol=1e-12)
    # friction work: mu N V dt per step on the plateaus, nothing while sticking
    dw = np.diff(w)
    np.testing.assert_allclose(dw[np.flatnonzero(plateau[1:] & plateau[:-1])], cap * V * DT, rtol=1e-6)
    assert np.all(dw[np.flatnonzero(stick[1:] & stick[:-1])] == 0.0)


# ---- rest offset: a link of finite length ------------------------------------------------------

def test_rest_initial_is_a_tension_only_link_of_the_initial_offset(tmp_path):
    """`rest initial`: S placed G = 50 mm from the rope (as wirenet-gen fence hangs the net) feels
    nothing there; moved towards the rope the link is slack (no force, no friction); moved out
    beyond G it pulls back with kn (|d| - G) and, sliding along the rope at the same time, the
    friction is mu times that."""
    G, V, W, n = 0.05, 0.5, 0.01, 500
    write_setup(tmp_path, 0.03, y_s=-G)
    deck = head(coeffs=f"kn {KN!r} kt {KT!r} mu {MU!r} rest initial") + \
        f"fix in S move linear {V!r} {W!r} 0\n" + monitor() + f"run {n}\nunfix in\n" + \
        f"fix out S move linear {V!r} {-W!r} 0\nrun {3 * n}\n"
    rows = rows_by_step(lmp.run_deck(deck, tmp_path))
    y, fx, fy = col(rows, "ys"), col(rows, "fxs"), col(rows, "fys")
    stretch = -y - G
    slack = stretch < -1e-12
    taut = stretch > 1e-12
    assert slack.sum() > 900 and taut.sum() > 900
    assert np.all(fx[slack] == 0.0) and np.all(fy[slack] == 0.0) and np.all(col(rows, "el")[slack] == 0.0)
    nsl = col(rows, "nsl")
    assert np.all(nsl[slack] == 0) and np.all(nsl[taut] == 1)   # a slack link moves freely: not "sliding"
    np.testing.assert_allclose(fy[taut], KN * stretch[taut], rtol=1e-9)
    np.testing.assert_allclose(fx[taut], -MU * fy[taut], rtol=1e-9)   # sliding: kt V >> mu kn W
    np.testing.assert_allclose(col(rows, "el")[taut],
                               0.5 * fy[taut] ** 2 / KN + 0.5 * (MU * fy[taut]) ** 2 / KT, rtol=1e-9)
    w = col(rows, "w")
    assert np.all(w[slack] == 0.0)
    # friction work per step: the cap times the slip, the travel V dt less the stick spring's growth
    # as the cap rises, mu F_n (V dt - (mu F_n - mu F_n,prev) / kt)
    k = np.flatnonzero(taut[1:] & taut[:-1]) + 1
    cap = MU * fy
    np.testing.assert_allclose(np.diff(w)[k - 1], cap[k] * (V * DT - (cap[k] - cap[k - 1]) / KT), rtol=1e-6)
    # the rope carries -F
    last = rows[-1]
    assert sum(last[f"fy{j}"] for j in range(1, 6)) == pytest.approx(-last["fys"], rel=1e-12)
    assert sum(last[f"fx{j}"] for j in range(1, 6)) == pytest.approx(-last["fxs"], rel=1e-12)


# ---- damping across the rope ------------------------------------------------------------------

def test_normal_damping_decays_at_its_fraction_of_critical(tmp_path):
    """`damping ZETA`: S released at twice its equilibrium offset swings about it as a damped
    oscillator of kn and m: successive maxima of the offset shrink by exp(-2 pi ZETA / sqrt(1 -
    ZETA^2)); the damping work [5] is the mechanical energy lost (spring, load and kinetic)."""
    zeta = 0.05
    write_setup(tmp_path, 0.07, y_s=-2 * OFFSET)
    deck = head(coeffs=f"kn {KN!r} kt {KT!r} mu {MU!r} damping {zeta!r}") + \
        f"fix integ S nve/sphere\nfix load S addforce 0 {-N_LOAD!r} 0\nvariable vy equal vy[6]\nvariable wd equal f_sh[5]\n" + \
        monitor().replace("thermo_style custom step", "thermo_style custom step v_vy v_wd") + "run 3000\n"
    rows = rows_by_step(lmp.run_deck(deck, tmp_path))
    u = col(rows, "ys") + OFFSET            # displacement from equilibrium
    peaks = [k for k in range(1, len(u) - 1) if u[k] < u[k - 1] and u[k] <= u[k + 1]]
    assert len(peaks) >= 4
    ratio = u[peaks[1:4]] / u[peaks[0:3]]
    # measured 1.4e-4 off: Verlet's period error (w dt)^2 / 24 and the sampling of the minima
    np.testing.assert_allclose(ratio, math.exp(-2 * math.pi * zeta / math.sqrt(1 - zeta ** 2)), rtol=2e-3)
    # energy: the kinetic energy at the half steps is where Verlet's budget closes only to O(dt^2)
    vy, y = col(rows, "vy"), col(rows, "ys")
    energy = 0.5 * M_S * vy ** 2 + 0.5 * KN * y ** 2 + N_LOAD * y
    wd = col(rows, "wd")
    lost = energy[0] - energy[-1]
    assert lost > 0.9 * (energy[0] - energy.min())
    assert wd[-1] == pytest.approx(lost, rel=1e-4)   # measured 3.5e-6
    assert col(rows, "nsl").max() == 0      # nothing moved it along the rope


# ---- 4. momentum ------------------------------------------------------------------------------

@pytest.mark.parametrize("np_", [1, 2])
def test_free_rope_and_shackle_conserve_momentum(tmp_path, np_):
    """No external force: the shackle force and its two reactions cancel. On 2 ranks the shackle
    starts left of the rank boundary at x = 0 with the rope vertex right of it (a ghost)."""
    write_setup(tmp_path, -0.0005, y_s=-2 * OFFSET, x0=-L, rope_density=10 * RHO)
    procs = "processors 2 1 1\n" if np_ == 2 else ""
    deck = head(extra="communicate single cutoff 0.5\n", processors=procs) + \
        "fix integ all nve/sphere\nvelocity S set 2 0.5 0\n" + monitor(every=10) + "run 1500\n"
    rows = rows_by_step(lmp.run_deck(deck, tmp_path, np=np_))
    px, py = col(rows, "px"), col(rows, "py")
    p0 = M_S * math.hypot(2, 0.5)
    assert px[0] == pytest.approx(2 * M_S, rel=1e-12)
    assert np.abs(px - px[0]).max() < 1e-12 * p0 and np.abs(py - py[0]).max() < 1e-12 * p0
    assert col(rows, "w")[-1] > 0 and col(rows, "xs").max() > 0.0   # it slid, across the vertex
    assert max(abs(col(rows, "fx3"))) > 0                           # the rope was loaded


# ---- 5. MPI ranks and restart -----------------------------------------------------------------

MPI_X0 = -0.2   # rope of 8 segments of 0.05 m from -0.2 to 0.2 m along x: the ranks split at x = 0


def mpi_setup(wd):
    """The rope held (its atoms are not integrated: their forces are the shackle's reactions, which
    on 2 ranks reach the owners of ghost rope atoms only by the fix's reverse communication)."""
    write_setup(wd, -0.08, x0=MPI_X0, nrope=9)


def mpi_head(processors, extra=""):
    return lmp.PREAMBLE + processors + """read_data rope.data
communicate single cutoff 0.5
""" + extra + f"""fix sh all wirenet/shackle file rope.shackles kn {KN!r} kt {KT!r} mu {MU!r}
"""


MPI_RUN = f"""group S id 10
fix integ S nve/sphere
fix load S addforce 50 {-N_LOAD!r} 0
"""


def test_slide_across_ranks_matches_serial(tmp_path):
    results = {}
    for np_ in (1, 2):
        wd = tmp_path / f"np{np_}"
        mpi_setup(wd)
        deck = mpi_head("processors 2 1 1\n" if np_ == 2 else "") + MPI_RUN + monitor(nrope=9, every=20) + "run 2400\n"
        results[np_] = rows_by_step(lmp.run_deck(deck, wd, np=np_))
    one, two = results[1], results[2]
    assert len(one) == len(two)
    xs = col(one, "xs")
    assert xs[0] < -0.05 and xs[-1] > 0.05, "the shackle did not cross the rank boundary"
    # the rope atoms on both sides of the boundary carried the shackle's reactions
    assert np.abs(col(one, "fy4")).max() > 0 and np.abs(col(one, "fy6")).max() > 0
    for name in one[0]:
        a, b = col(one, name), col(two, name)
        scale = max(np.abs(a).max(), 1e-30)
        assert np.abs(a - b).max() <= 1e-12 * scale, f"{name} differs between 1 and 2 ranks"


@pytest.mark.parametrize("np_", [1, 2])
def test_restart_mid_slide_continues_identically(tmp_path, np_):
    procs = "processors 2 1 1\n" if np_ == 2 else ""
    ref_dir, a_dir, b_dir = tmp_path / "ref", tmp_path / "a", tmp_path / "b"
    for wd in (ref_dir, a_dir):
        mpi_setup(wd)
    ref = rows_by_step(lmp.run_deck(mpi_head(procs) + MPI_RUN + monitor(nrope=9, every=20) +
                                    "run 2400\n", ref_dir, np=np_))
    first = rows_by_step(lmp.run_deck(mpi_head(procs) + MPI_RUN + monitor(nrope=9, every=20) +
                                      "run 1200\nwrite_restart mid.restart\n", a_dir, np=np_))
    assert first[-1]["nsl"] == 1 and first[-1]["w"] > 0, "not sliding at the restart"
    b_dir.mkdir()
    (b_dir / "mid.restart").write_bytes((a_dir / "mid.restart").read_bytes())
    (b_dir / "rope.shackles").write_bytes((a_dir / "rope.shackles").read_bytes())
    deck = procs + """read_restart mid.restart
atom_modify sort 0 0
communicate single cutoff 0.5
""" + f"fix sh all wirenet/shackle file rope.shackles kn {KN!r} kt {KT!r} mu {MU!r}\n" + \
        f"fix integ S nve/sphere\nfix load S addforce 50 {-N_LOAD!r} 0\n" + monitor(nrope=9, every=20) + "run 1200\n"
    second = rows_by_step(lmp.run_deck(deck, b_dir, np=np_))
    ref_by = {int(r["Step"]): r for r in ref}
    assert int(second[-1]["Step"]) == 2400
    for r in second:
        e = ref_by[int(r["Step"])]
        for name in r:
            assert r[name] == pytest.approx(e[name], rel=1e-12, abs=1e-15), \
                f"{name} at step {int(r['Step'])}: {r[name]!r} after the restart, {e[name]!r} uninterrupted"


# ---- 6. bad input -----------------------------------------------------------------------------

GOOD = f"kn {KN!r} kt {KT!r} mu {MU!r}"
BAD_ARGS = {
    "missing file": (GOOD, "missing keyword 'file PATH'"),
    "missing kn": ("file rope.shackles kt 1 mu 0.3", "missing keyword 'kn KN'"),
    "missing mu": ("file rope.shackles kn 1 kt 1", "missing keyword 'mu MU'"),
    "unknown keyword": (f"file rope.shackles {GOOD} friction 2", "unknown keyword 'friction'"),
    "kn zero": ("file rope.shackles kn 0 kt 1 mu 0.3", "kn must be > 0 (got 0)"),
    "kt negative": ("file rope.shackles kn 1 kt -1 mu 0.3", "kt must be > 0 (got -1)"),
    "mu negative": ("file rope.shackles kn 1 kt 1 mu -0.1", "mu must be >= 0 (got -0.1)"),
    "kn nan": ("file rope.shackles kn nan kt 1 mu 0.3", "kn must be a finite number (got 'nan')"),
    "mu inf": ("file rope.shackles kn 1 kt 1 mu inf", "mu must be a finite number (got 'inf')"),
    "kt no value": ("file rope.shackles kn 1 mu 0.3 kt", "'kt' needs a value"),
    "damping negative": (f"file rope.shackles {GOOD} damping -1", "damping must be >= 0 (got -1)"),
    "rest unknown": (f"file rope.shackles {GOOD} rest maybe", "rest must be zero or initial (got 'maybe')"),
    "rest no value": (f"file rope.shackles {GOOD} rest", "'rest' needs a value: zero or initial"),
    "unreadable file": (f"file nowhere.shackles {GOOD}", "cannot read the shackle file 'nowhere.shackles'"),
}

BAD_FILES = {
    "no ropes line": ("R1 2 1 2\nshackles 1\n6 R1\n", "line 1: expected 'ropes COUNT' (got 'R1')"),
    "count not a number": ("ropes two\n", "line 1: ropes count must be a whole number >= 0 (got 'two')"),
    "rope count short": ("ropes 1\nR1 3 1 2\nshackles 1\n6 R1\n", "line 2: rope 'R1' says 3 atoms but lists 2"),
    "one-atom rope": ("ropes 1\nR1 1 1\nshackles 1\n6 R1\n", "rope 'R1' has 1 atom(s) (a rope needs at least 2)"),
    "bad atom id": ("ropes 1\nR1 2 1 x\nshackles 1\n6 R1\n", "rope 'R1' atom ID must be a whole number >= 1 (got 'x')"),
    "fractional atom id": ("ropes 1\nR1 2 1 2.7\nshackles 1\n6 R1\n", "line 2: rope 'R1' atom ID must be a whole number >= 1 (got '2.7')"),
    "atom id with a sign": ("ropes 1\nR1 2 1 +2\nshackles 1\n6 R1\n", "rope 'R1' atom ID must be a whole number >= 1 (got '+2')"),
    "atom id beyond int": ("ropes 1\nR1 2 1 2\nshackles 1\n4294967302 R1\n",
                           "line 4: shackle atom ID 4294967302 is too large (at most 2147483647)"),
    "fewer ropes": ("ropes 2\nR1 2 1 2\nshackles 1\n6 R1\n", "line 3: expected 2 rope lines"),
    "rope twice": ("ropes 2\nR1 2 1 2\nR1 2 3 4\nshackles 1\n6 R1\n", "line 3: rope 'R1' is listed twice"),
    "atom twice on a rope": ("ropes 1\nR1 3 1 2 1\nshackles 1\n6 R1\n", "rope 'R1' lists atom 1 twice"),
    "unknown rope": ("ropes 1\nR1 5 1 2 3 4 5\nshackles 1\n6 R2\n", "line 4: shackle atom 6: unknown rope 'R2'"),
    "shackle on its own rope": ("ropes 1\nR1 5 1 2 3 4 5\nshackles 1\n3 R1\n",
                                "shackle atom 3 is an atom of its own rope 'R1'"),
    "duplicate shackle": ("ropes 1\nR1 4 1 2 3 4\nshackles 2\n6 R1\n6 R1\n",
                          "line 5: shackle atom 6 is listed twice (first on line 4)"),
    "malformed shackle line": ("ropes 1\nR1 5 1 2 3 4 5\nshackles 1\n6\n", "line 4: a shackle line is 'ATOM_ID ROPE_ID' (got 1 words)"),
    "missing shackles": ("ropes 1\nR1 5 1 2 3 4 5\nshackles 2\n6 R1\n", "expected 2 shackle lines 'ATOM_ID ROPE_ID', found 1"),
    "extra line": ("ropes 1\nR1 5 1 2 3 4 5\nshackles 1\n6 R1\n7 R1\n", "line 5: unexpected line after the 1 shackle lines"),
    "unknown shackle atom": ("ropes 1\nR1 5 1 2 3 4 5\nshackles 1\n99 R1\n", "shackle atom 99 does not exist"),
    "unknown rope atom": ("ropes 1\nR1 5 1 2 3 4 77\nshackles 1\n6 R1\n", "rope 'R1': atom 77 does not exist"),
}


def bad_deck(args):
    return lmp.PREAMBLE + f"read_data rope.data\nfix sh all wirenet/shackle {args}\nrun 1\n"


@pytest.mark.parametrize("case", sorted(BAD_ARGS))
def test_bad_arguments(tmp_path, case):
    args, phrase = BAD_ARGS[case]
    write_setup(tmp_path, 0.07)
    rc, out = lmp.run_deck_rc(bad_deck(args), tmp_path)
    line = check_error(rc, out, phrase)
    assert "fix wirenet/shackle" in line


@pytest.mark.parametrize("case", sorted(BAD_FILES))
def test_bad_files(tmp_path, case):
    text, phrase = BAD_FILES[case]
    write_setup(tmp_path, 0.07)
    (tmp_path / "bad.shackles").write_text(text)
    rc, out = lmp.run_deck_rc(bad_deck(f"file bad.shackles {GOOD}"), tmp_path)
    line = check_error(rc, out, phrase)
    assert "bad.shackles" in line


def test_bad_file_on_two_ranks(tmp_path):
    write_setup(tmp_path, 0.07)
    (tmp_path / "bad.shackles").write_text("ropes 1\nR1 5 1 2 3 4 5\nshackles 1\n6 R2\n")
    rc, out = lmp.run_deck_rc("processors 2 1 1\n" + bad_deck(f"file bad.shackles {GOOD}"), tmp_path, np=2)
    check_error(rc, out, "unknown rope 'R2'")


def test_rope_out_of_ghost_reach_names_the_shackle(tmp_path):
    """Two ranks, the shackle's segment 0.4 m long across the boundary, the default ghost cutoff."""
    tmp_path.mkdir(exist_ok=True)
    atoms = [(1, 1, -0.3, 0.0, 0.0, 0.01, RHO, 1), (2, 1, 0.1, 0.0, 0.0, 0.01, RHO, 1),
             (3, 1, -0.25, -OFFSET, 0.0, D_S, RHO, 1)]
    lmp.write_data(tmp_path / "rope.data", atoms, [], nbond_types=0)
    (tmp_path / "rope.shackles").write_text("ropes 1\nR1 2 1 2\nshackles 1\n3 R1\n")
    rc, out = lmp.run_deck_rc("processors 2 1 1\n" + bad_deck(f"file rope.shackles {GOOD}"), tmp_path, np=2)
    line = check_error(rc, out, "shackle atom 3: the rope atoms of its segment are not within the ghost cutoff")
    assert "now 2 x 0.401 m" in line   # segment 0.4 m, offset 1 mm


def test_warns_when_damping_comes_first(tmp_path):
    """The decks damp every internal force with fix wirenet/damping, defined after the forces."""
    write_setup(tmp_path, 0.07)
    deck = lmp.PREAMBLE + f"read_data rope.data\nfix damp all wirenet/damping 0.5\n" \
        f"fix sh all wirenet/shackle file rope.shackles {GOOD}\nrun 1\n"
    out = lmp.run_deck(deck, tmp_path)
    assert "WARNING: fix wirenet/shackle: fix damp (wirenet/damping) comes earlier" in out
    deck = lmp.PREAMBLE + f"read_data rope.data\nfix sh all wirenet/shackle file rope.shackles {GOOD}\n" \
        "fix damp all wirenet/damping 0.5\nrun 1\n"
    assert "WARNING" not in lmp.run_deck(deck, tmp_path)


# ---- the file wirenet-gen fence writes --------------------------------------------------------

@pytest.mark.parametrize("np_", [1, 2])
def test_reads_the_shackles_of_a_generated_fence(tmp_path, np_):
    """A small fence from `wirenet-gen fence` (doc/wirenet-gen.md): the fix reads its .shackles file,
    finds every atom and places every shackle. With `rest initial` no shackle pulls at the start;
    with `rest zero` the largest pull is kn times the largest distance of a shackle from its rope,
    which the generator reports in the JSON (the larger of the gaps, the post gap of the side
    shackles: why fence decks want `rest initial`)."""
    import json
    import subprocess
    subprocess.run([str(lmp.GEN), "fence", "--modules", "1", "--spacing", "3", "--height", "2",
                    "--net", "square", "--out", str(tmp_path / "f")], check=True, capture_output=True)
    meta = json.loads((tmp_path / "f.json").read_text())
    far, longest = meta["shackles"]["max_distance"], meta["max_bond_length"]
    assert meta["shackles"]["count"] > 50 and far > 0.01
    kn = 1e6
    procs = "processors 2 1 1\n" if np_ == 2 else ""
    out = {}
    for rest in ("initial", "zero"):
        deck = lmp.PREAMBLE + procs + f"""read_data f.data
bond_style harmonic
bond_coeff * 0.0 0.1
communicate single cutoff {2.1 * (longest + far)!r}
fix sh all wirenet/shackle file f.shackles kn {kn!r} kt {kn!r} mu 0.2 rest {rest}
variable el equal f_sh[2]
variable fm equal f_sh[4]
thermo_style custom step v_el v_fm
thermo_modify format float %.17g
run 0
"""
        out[rest] = lmp.thermo_rows(lmp.run_deck(deck, tmp_path, np=np_, name=f"in.{rest}"))[-1]
    assert out["initial"]["el"] == 0.0 and out["initial"]["fm"] == 0.0
    assert out["zero"]["fm"] == pytest.approx(kn * far, rel=1e-9)
