"""fix wirenet/body floor: a free body on fixed planes (the ground, a slope).

- the contact points: every corner of a polyhedron below a plane, a smooth body's deepest point,
  on two floors at once (kn depth^2 / 2 each, closed form);
- a block dropped flat without friction and damping rebounds to its drop height, KE + PE +
  the floor's spring energy constant; with damping it comes to rest on its face at the height
  side/2 - M g / (N kn), N its corners on that face (8 for the truncated cube, 4 for a box; 1
  for a spheroid on its pole);
- a block sliding with friction stops after v0^2 / (2 mu g), and the floor's dissipation output
  is the energy lost; the floor's work is minus its stored and dissipated energy;
- a sphere on a slope rolls without slipping at (5/7) g sin(theta), and slides at
  g (sin(theta) - mu cos(theta)) when mu is small;
- momentum: the body's change of momentum is the floor's impulse output plus the weight's;
- write_restart / read_restart mid-slide continues the trajectory (the corners' springs); a
  restart file with other floors, or whose record is of another version, is refused;
- 1 and 2 MPI ranks give the same block (floor and nodes on both sides of the cut);
- bad floor arguments stop with one ERROR line naming the keyword and value.
"""

import math

import numpy as np
import pytest

import lmp
from rigid import axis_angle, quat_rotate, vec
from test_body import COLUMNS, header, node, rows_of, thermo
from test_wire_errors import check_error

G = 9.81
TC = "truncated-cube 0.45 0.15"    # the impact block: side 0.45 m, corner cut 0.15 m
TC_MASS = 44.5
TC_HALF = 0.225
KN = 1e6


def body_deck(body, steps, every, dt=1e-5, extra_header="", nodes=None, after=""):
    """A free body (fix b) and, unless nodes are given, one node far from it (LIGGGHTS needs an
    atom; the body's node contacts are not used here)."""
    deck = header(5.0, extra_header) + (nodes if nodes is not None else node(1, (4.5, 4.5, 4.5), 0.01))
    return deck + f"fix b all wirenet/body {body}\n{after}timestep {dt!r}\n" + thermo(["b"], every) + f"run {steps}\n"


def body_rows(deck, workdir, np=1):
    return [r["b"] | {"time": r["time"], "step": r["step"]} for r in rows_of(lmp.run_deck(deck, workdir, np=np), ["b"])]


def energy(r):
    return r["ke"] + r["pe"] + r["e_floor"]


def tc_corners():
    h, k = TC_HALF, TC_HALF - 0.15
    return np.array([[sx * a, sy * b, sz * c] for sx in (-1, 1) for sy in (-1, 1) for sz in (-1, 1)
                     for a, b, c in ((k, h, h), (h, k, h), (h, h, k))])


# ---- contact points -------------------------------------------------------------------------

def test_contact_points_are_the_corners_below_each_floor(tmp_path):
    """A tilted truncated cube pushed into a slope and the ground at once, and a tilted spheroid
    into a slope: the setup (run 0) counts the corners below each plane and the spheroid's
    deepest point, and stores kn depth^2 / 2 for each (depth of the corner, or of the spheroid's
    support point R A^2 R^T (-n) / |A R^T n|)."""
    q = axis_angle([1.0, 2.0, 0.5], 0.4)
    corners = np.array([quat_rotate(q, c) for c in tc_corners()])
    centre = np.array([0.1, -0.2, 0.3])
    slope_n = np.array([0.3, 0.0, 1.0]) / math.hypot(0.3, 1.0)
    ground_n = np.array([0.0, 0.0, 1.0])
    pts = centre + corners
    # the planes cut off the 3 lowest corners along each normal (and not the 4th)
    floors, expect_n, expect_e = [], 0, 0.0
    for n, kn in ((slope_n, 2e6), (ground_n, 1e6)):
        h = np.sort(pts @ n)
        level = 0.5 * (h[2] + h[3])
        point = level * n
        depth = level - pts @ n
        below = depth[depth > 0]
        assert len(below) == 3
        expect_n += 3
        expect_e += 0.5 * kn * np.sum(below ** 2)
        floors.append(f"floor {point[0]!r} {point[1]!r} {point[2]!r} {n[0]!r} {n[1]!r} {n[2]!r} kn {kn} kt 1e5 mu 0.3")
    qs = " ".join(repr(float(v)) for v in q)
    body = (f"{TC} centre {centre[0]} {centre[1]} {centre[2]} quat {qs} kn 1e6 mass {TC_MASS} " + " ".join(floors))
    r = body_rows(body_deck(body, 0, 1), tmp_path / "cube")[-1]
    assert r["n_floor"] == expect_n
    assert r["e_floor"] == pytest.approx(expect_e, rel=1e-9)
    assert r["d_floor"] == 0 and r["w_floor"] == 0

    axes = np.array([0.3, 0.2, 0.1])
    qe = axis_angle([0.5, -1.0, 0.2], 0.7)
    rot = np.array([quat_rotate(qe, e) for e in np.eye(3)]).T
    support = np.sqrt(slope_n @ rot @ np.diag(axes ** 2) @ rot.T @ slope_n)   # reach of the body along -n
    depth = 0.004
    c = (support - depth) * slope_n                    # plane through the origin
    qs = " ".join(repr(float(v)) for v in qe)
    body = (f"spheroid {axes[0]} {axes[1]} {axes[2]} centre {c[0]!r} {c[1]!r} {c[2]!r} quat {qs} kn 1e6 mass 10 "
            f"floor 0 0 0 {slope_n[0]!r} {slope_n[1]!r} {slope_n[2]!r} kn {KN} kt 1e5 mu 0.3")
    r = body_rows(body_deck(body, 0, 1), tmp_path / "spheroid")[-1]
    assert r["n_floor"] == 1
    assert r["e_floor"] == pytest.approx(0.5 * KN * depth ** 2, rel=1e-9)


# ---- dropped block --------------------------------------------------------------------------

def test_block_dropped_flat_without_friction_rebounds_to_its_height(tmp_path):
    """Dropped 0.1 m onto a frictionless, undamped floor, flat on its octagonal face: it lands
    on its 8 corners, KE + PE + the floor's spring energy stays constant, no energy is
    dissipated, and it rises back to its drop height without turning."""
    h = 0.1
    z0 = TC_HALF + h
    body = f"{TC} centre 0 0 {z0} kn 1e6 mass {TC_MASS} gravity 0 0 -{G} floor 0 0 0 0 0 1 kn {KN} kt 0 mu 0"
    rows = body_rows(body_deck(body, 32000, 10), tmp_path)
    scale = TC_MASS * G * h
    e0 = energy(rows[0])
    assert max(abs(energy(r) - e0) for r in rows) < 1e-4 * scale
    touching = [k for k, r in enumerate(rows) if r["n_floor"] > 0]
    assert touching and max(rows[k]["n_floor"] for k in touching) == 8
    after = rows[touching[-1] + 1:]
    assert after and all(r["n_floor"] == 0 for r in after)
    apex = max(r["z"] for r in after)
    assert apex == pytest.approx(z0, abs=1e-4 * h)
    assert after[-1]["vz"] < 0                       # past the apex: it came back to it
    assert all(r["d_floor"] == 0.0 for r in rows)
    assert max(np.linalg.norm(vec(r, "wx", "wy", "wz")) for r in rows) < 1e-9
    # the floor gave back what it took: its work is minus its stored energy, during the contact to
    # O(omega dt) of it (dt F.v at the end-of-step velocity: measured 2e-3, omega dt = 0.004), then
    # to round-off
    assert max(abs(r["w_floor"] + r["e_floor"]) for r in rows) < 3e-3 * scale
    assert abs(after[-1]["w_floor"]) < 1e-4 * scale


@pytest.mark.parametrize("shape, mass, half, points, gamma", [
    (TC, TC_MASS, TC_HALF, 8, 53.0),           # the octagonal face's 8 corners
    ("box 0.4 0.3 0.2", 20.0, 0.1, 4, 110.0),  # 4 corners
    ("spheroid 0.3 0.2 0.1", 10.0, 0.1, 1, 300.0),  # its pole: one support point
])
def test_block_comes_to_rest_on_its_face(tmp_path, shape, mass, half, points, gamma):
    """Dropped 2 mm with normal damping (about half the critical damping on its N corners:
    gamma_n = sqrt(kn / (N M))), it comes to rest level, each corner pressed M g / (N kn) into
    the floor, and the floor's work is minus its stored plus dissipated energy."""
    body = (f"{shape} centre 0 0 {half + 0.002} kn 1e6 mass {mass} gravity 0 0 -{G} "
            f"floor 0 0 0 0 0 1 kn {KN} kt 1e5 mu 0.5 gamma_n {gamma}")
    rows = body_rows(body_deck(body, 30000, 1000), tmp_path)
    last = rows[-1]
    overlap = mass * G / (points * KN)
    assert last["n_floor"] == points
    assert half - last["z"] == pytest.approx(overlap, rel=1e-6)
    assert np.linalg.norm(vec(last, "vx", "vy", "vz")) < 1e-9
    assert np.linalg.norm(vec(last, "wx", "wy", "wz")) < 1e-9
    assert np.allclose(vec(last, "qw", "qx", "qy", "qz"), [1, 0, 0, 0], atol=1e-12)
    assert last["e_floor"] == pytest.approx(points * 0.5 * KN * overlap ** 2, rel=1e-6)
    # the drop's energy went into the floor's spring and its damping
    lost = energy(rows[0]) - energy(last)
    assert lost > 0.9 * mass * G * 0.002
    assert last["d_floor"] == pytest.approx(lost, rel=1e-3)
    assert last["w_floor"] == pytest.approx(-(last["e_floor"] + last["d_floor"]), rel=1e-3)


# ---- friction -------------------------------------------------------------------------------

def slide_body(v0, mu, gamma, kt=1e4):
    """The truncated cube set on the floor (touching) at v0 along +x."""
    return (f"{TC} centre 0 0 {TC_HALF} kn 1e6 mass {TC_MASS} vel {v0} 0 0 gravity 0 0 -{G} "
            f"floor 0 0 0 0 0 1 kn {KN} kt {kt} mu {mu} gamma_n {gamma}")


def test_sliding_block_stops_after_v2_over_2_mu_g(tmp_path):
    """Sliding at 2 m/s with mu 0.4 on its 8 corners it stops after v0^2 / (2 mu g) = 0.51 m, and
    static friction holds it there: it only sways on the corners' tangential springs (no
    tangential damping), by up to F_cap / kt = mu M g / (8 kt) = 2.2 mm. The floor's dissipation
    (the sliders' and the damping's) is the energy lost, and the floor's work is minus its
    stored and dissipated energy, both to 1e-4 (measured 2e-5)."""
    v0, mu, kt = 2.0, 0.4, 1e4
    rows = body_rows(body_deck(slide_body(v0, mu, 50.0, kt), 60000, 100), tmp_path)
    assert all(r["n_floor"] == 8 for r in rows[1:])
    assert max(abs(r["wy"]) for r in rows[10:]) < 0.1              # it slides flat, it does not tip
    stop = next(k for k, r in enumerate(rows) if r["vx"] <= 0.0)
    assert rows[stop]["x"] == pytest.approx(v0 ** 2 / (2 * mu * G), rel=0.01)
    sway = mu * TC_MASS * G / (8 * kt)
    assert all(abs(r["x"] - rows[stop]["x"]) < 2.2 * sway for r in rows[stop:])
    assert rows[-1]["time"] > 1.15 * v0 / (mu * G)
    lost = energy(rows[0]) - energy(rows[-1])
    assert lost == pytest.approx(0.5 * TC_MASS * v0 ** 2, rel=5e-3)  # less the sway's energy
    assert rows[-1]["d_floor"] == pytest.approx(lost, rel=1e-4)
    for r in rows:
        assert abs(r["w_floor"] + r["e_floor"] + r["d_floor"]) < 1e-4 * lost, r["step"]


@pytest.mark.parametrize("mu, rolls", [(0.5, True), (0.05, False)])
def test_sphere_on_a_slope_rolls_or_slides(tmp_path, mu, rolls):
    """A solid sphere released on a 20 degree slope: with mu 0.5 > (2/7) tan(theta) it rolls
    without slipping at (5/7) g sin(theta) (its contact point at rest, v = R w); with mu 0.05 it
    slides at g (sin(theta) - mu cos(theta)) and its spin grows only by the friction's torque."""
    theta, R, M = math.radians(20.0), 0.2, 10.0
    n = np.array([math.sin(theta), 0.0, math.cos(theta)])      # the slope falls towards +x
    down = np.array([math.cos(theta), 0.0, -math.sin(theta)])
    c = R * n
    body = (f"sphere {R} centre {c[0]!r} {c[1]!r} {c[2]!r} kn 1e6 mass {M} gravity 0 0 -{G} "
            f"floor 0 0 0 {n[0]!r} {n[1]!r} {n[2]!r} kn {KN} kt 1e5 mu {mu} gamma_n 200")
    rows = body_rows(body_deck(body, 50000, 100), tmp_path)
    t = np.array([r["time"] for r in rows])
    s = np.array([vec(r, "x", "y", "z") @ down for r in rows])
    fit = t > 0.05                                 # after the landing's normal ringing
    a = 2 * np.polyfit(t[fit], s[fit], 2)[0]
    expect = 5 / 7 * G * math.sin(theta) if rolls else G * (math.sin(theta) - mu * math.cos(theta))
    assert a == pytest.approx(expect, rel=1e-3)   # measured 2e-5 rolling, 2e-8 sliding
    assert all(r["n_floor"] == 1 for r in rows[1:])
    last = rows[-1]
    turned = R * 2 * math.atan2(last["qy"], last["qw"])      # about +y, rolling towards +x
    if rolls:
        # the contact point stays where it was, up to the spring's stretch F / kt = 0.1 mm
        assert turned == pytest.approx(s[-1] - s[0], abs=1e-4)
        assert abs(last["d_floor"]) < 1e-3 * last["ke"]
    else:
        # the friction's torque mu M g cos R spins it up: R w = (5/2) mu g cos t (less the few ms
        # of the landing, the spring's loading)
        assert last["wy"] * R == pytest.approx(2.5 * mu * G * math.cos(theta) * last["time"], rel=1e-2)
        assert turned < 0.5 * (s[-1] - s[0])
        assert last["d_floor"] > 0.05 * last["ke"]
    assert abs(last["w_floor"] + last["e_floor"] + last["d_floor"]) < 1e-4 * last["ke"]


# ---- momentum, restart, ranks ---------------------------------------------------------------

def tumble_body(gamma=40.0):
    """The truncated cube tilted, spinning and moving sideways, 1 cm above a rough floor."""
    q = axis_angle([1.0, -0.5, 0.3], 0.5)
    low = max(-(quat_rotate(q, c)[2]) for c in tc_corners())
    qs = " ".join(repr(float(v)) for v in q)
    return (f"{TC} centre 0.003 -0.002 {low + 0.01!r} quat {qs} kn 1e5 kt 3e4 mu 0.4 mass {TC_MASS} "
            f"vel 0.5 0.2 -1.5 omega 3 -2 1 gravity 0 0 -{G} floor 0 0 0 0 0 1 kn {KN} kt 1e5 mu 0.5 gamma_n {gamma}")


def test_momentum_change_is_the_floor_and_weight_impulse(tmp_path):
    """Over a tumbling bounce on a corner with friction (two runs), M (v - v0) = J_floor + M g t
    at every output, to round-off; and the floor's work is minus its stored and dissipated
    energy (measured 1e-6 of the dissipation once the corner left)."""
    deck = body_deck(tumble_body(), 3000, 20).replace("run 3000\n", "run 3000\nrun 3000\n")
    rows = body_rows(deck, tmp_path)
    assert max(r["n_floor"] for r in rows) >= 1 and rows[-1]["n_floor"] == 0
    v0 = np.array([0.5, 0.2, -1.5])
    assert rows[-1]["jz"] > TC_MASS * 1.5                       # it bounced
    last = rows[-1]
    assert last["d_floor"] > 10.0
    assert abs(last["w_floor"] + last["e_floor"] + last["d_floor"]) < 1e-5 * last["d_floor"]
    for r in rows:
        dp = TC_MASS * (vec(r, "vx", "vy", "vz") - v0)
        expect = vec(r, "jx", "jy", "jz") + np.array([0.0, 0.0, -TC_MASS * G * r["time"]])
        assert np.allclose(dp, expect, rtol=0, atol=1e-12 * TC_MASS * 10), r["step"]


def restart_deck(body, steps):
    return ("read_restart half.restart\natom_modify sort 0 0\nneighbor 0.01 bin\nneigh_modify delay 0\n"
            f"fix b all wirenet/body {body}\ntimestep 1e-5\n" + thermo(["b"], 100) + f"run {steps}\n")


def test_restart_mid_slide_continues_the_trajectory(tmp_path):
    """Without viscous damping (the setup recomputes the forces with the end-of-step velocity):
    split mid-slide by write_restart / read_restart, the run ends where the straight one does
    (the corners' springs, the floor's sums and the body state come from the file)."""
    body = slide_body(2.0, 0.4, 0.0)
    straight = body_rows(body_deck(body, 30000, 100), tmp_path / "a")
    lmp.run_deck(body_deck(body, 15000, 100) + "write_restart half.restart\n", tmp_path / "b")
    cont = body_rows(restart_deck(body, 15000), tmp_path / "b")
    mid = [r for r in straight if r["step"] == 15000][0]
    assert mid["n_floor"] >= 4 and mid["d_floor"] > 10.0 and abs(mid["vx"]) > 0.5
    a, b = straight[-1], cont[-1]
    assert a["step"] == b["step"] == 30000
    for key in COLUMNS:
        x, y = a[key], b[key]
        assert y == pytest.approx(x, rel=1e-9, abs=1e-9 * max(1.0, abs(x))), key


def test_restart_with_other_floors_is_refused(tmp_path):
    body = slide_body(2.0, 0.4, 0.0)
    lmp.run_deck(body_deck(body, 100, 100) + "write_restart half.restart\n", tmp_path)
    two = body + " floor 0 0 -1 0 0 1 kn 1e6 kt 0 mu 0"
    rc, out = lmp.run_deck_rc(restart_deck(two, 10), tmp_path)
    check_error(rc, out, "fix wirenet/body: the restart file holds 1 floor(s) of 24 contact point(s) each, "
                         "this fix defines 2 of 24")


@pytest.mark.parametrize("first, named", [(1.0, "1 or 2 (WireNet before the floors)"), (7.0, "7")])
def test_restart_record_of_another_version_is_refused(tmp_path, first, named):
    """The record begins with its version (3); earlier builds' records began with the free flag
    (0 or 1). A file whose record is of another version (here: the version patched) stops
    read_restart with one error naming the version found."""
    import struct
    body = slide_body(2.0, 0.4, 0.0)
    lmp.run_deck(body_deck(body, 10, 10) + "write_restart half.restart\n", tmp_path)
    path = tmp_path / "half.restart"
    data = bytearray(path.read_bytes())
    at = data.index(b"wirenet/body")
    head = data.index(struct.pack("<dd", 3.0, 1.0), at)      # version 3, a free body
    data[head:head + 8] = struct.pack("<d", first)
    path.write_bytes(bytes(data))
    rc, out = lmp.run_deck_rc(restart_deck(body, 10), tmp_path)
    check_error(rc, out, f"fix wirenet/body: the restart file's record is of version {named}, "
                         "this build reads version 3 only")


def ranks_deck(extra_header=""):
    """The tumbling block falls on the floor and on a fixed 9 x 9 grid of nodes lying on it,
    which two ranks cut at x = 0."""
    nodes, k = "", 0
    for i in range(9):
        for j in range(9):
            k += 1
            nodes += node(k, (-0.2 + 0.05 * i + 0.0001, -0.2 + 0.05 * j, 0.0), 0.01)
    return body_deck(tumble_body(), 4000, 50, extra_header=extra_header, nodes=nodes,
                     after="dump d all custom 100 forces.*.dump id x y z fx fy fz\n"
                           'dump_modify d format "%d %.17g %.17g %.17g %.17g %.17g %.17g"\n')


def test_one_and_two_ranks_agree(tmp_path):
    one = body_rows(ranks_deck(), tmp_path / "np1")
    two = body_rows(ranks_deck("processors 2 1 1"), tmp_path / "np2", np=2)
    assert len(one) == len(two) > 10
    assert max(r["n_floor"] for r in one) >= 1 and max(r["n"] for r in one) >= 1
    for a, b in zip(one, two):
        for key in COLUMNS:
            x, y = a[key], b[key]
            assert y == pytest.approx(x, rel=1e-9, abs=1e-9 * max(1.0, abs(x))), (a["step"], key)
    # the block pressed nodes on both ranks (either side of x = 0)
    frames = [rows for path in (tmp_path / "np2").glob("forces.*.dump")
              for _, rows in lmp.dump_atom_frames(path).values()]
    touched = np.concatenate([rows[np.abs(rows[:, 4:7]).sum(axis=1) > 0][:, 1] for rows in frames])
    assert (touched < 0).any() and (touched > 0).any()


# ---- bad arguments --------------------------------------------------------------------------

FLOOR = "floor 0 0 0 0 0 1 kn 1e6 kt 1e5 mu 0.3"
BAD = {
    "zero normal": ("floor 0 0 0 0 0 0 kn 1e6 kt 1e5 mu 0.3", "floor normal must not be 0 0 0"),
    "zero kn": ("floor 0 0 0 0 0 1 kn 0 kt 1e5 mu 0.3", "floor kn must be > 0 (got 0)"),
    "negative kn": ("floor 0 0 0 0 0 1 kn -1e6 kt 1e5 mu 0.3", "floor kn must be > 0 (got -1e6)"),
    "negative kt": ("floor 0 0 0 0 0 1 kn 1e6 kt -1 mu 0.3", "floor kt must be >= 0 (got -1)"),
    "negative mu": ("floor 0 0 0 0 0 1 kn 1e6 kt 1e5 mu -0.1", "floor mu must be >= 0 (got -0.1)"),
    "negative gamma_n": (FLOOR + " gamma_n -2", "floor gamma_n must be >= 0 (got -2)"),
    "nan normal": ("floor 0 0 0 0 nan 1 kn 1e6 kt 1e5 mu 0.3", "floor normal value must be a finite number (got 'nan')"),
    "inf point": ("floor 0 0 inf 0 0 1 kn 1e6 kt 1e5 mu 0.3", "floor point value must be a finite number (got 'inf')"),
    "nan kn": ("floor 0 0 0 0 0 1 kn nan kt 1e5 mu 0.3", "floor kn must be a finite number (got 'nan')"),
    "inf mu": ("floor 0 0 0 0 0 1 kn 1e6 kt 1e5 mu inf", "floor mu must be a finite number (got 'inf')"),
    "missing kt": ("floor 0 0 0 0 0 1 kn 1e6 mu 0.3", "floor needs 'kt' after its kn (got 'mu')"),
    "missing law": ("floor 0 0 0 0 0 1", "floor needs 'kn' after its normal (got nothing)"),
    "short": ("floor 0 0 0 0 0", "'floor' needs a point and a normal"),
    "friction without kt": ("floor 0 0 0 0 0 1 kn 1e6 kt 0 mu 0.3", "floor mu 0.3 needs a tangential stiffness: floor kt > 0"),
}


@pytest.mark.parametrize("case", sorted(BAD) + ["kinematic body"])
def test_bad_floor_arguments_are_named(tmp_path, case):
    if case == "kinematic body":
        args, phrase = f"sphere 0.1 kn 1e6 {FLOOR}", "'floor' needs a free body: give 'mass M'"
    else:
        args, phrase = f"sphere 0.1 kn 1e6 mass 1 centre 0 0 0.5 {BAD[case][0]}", BAD[case][1]
    deck = header(1.0) + node(1, (0.0, 0.0, 0.0), 0.01) + f"fix b all wirenet/body {args}\nrun 0\n"
    rc, out = lmp.run_deck_rc(deck, tmp_path)
    check_error(rc, out, "fix wirenet/body: " + phrase)
