"""fix wirenet/body: analytic rigid bodies (exact geometry, no facets) in contact with node spheres.

- a node pressed a known overlap into a sphere, a spheroid, a cone flank, the cone's flat tip and
  its rim, a round cone tip, a plane, and a truncated cube's face, edge and vertex gets kn * overlap along the
  exact normal (closed form, 1e-9 relative);
- the spheroid's nearest point (Eberly's bisection) against an independent numerical
  minimisation (scipy) for random points inside and outside;
- friction: the tangential spring grows as kt * v * t, then the force stays at mu * Fn;
- a kinematic body follows its prescribed motion (ramp, then constant velocity; spin) exactly,
  also after fix_modify vel changed its velocity between runs (ramped from the current one), and
  a restart continues the changed motion;
- a free sphere dropped on free nodes conserves momentum plus the impulse of its weight, and its
  energy budget closes with the contact-work outputs;
- 1 and 2 MPI ranks give the same body history with the cut through the contact region;
- write_restart / read_restart continues the same trajectory (body state and friction history);
- a free body's local damping (keyword and fix_modify): in free flight it falls at (1 - A) g and
  rises against (1 + A) g, keeps the velocity and spin no force or torque acts on, and its work
  output is its whole energy change;
- bad arguments stop with one ERROR line naming the keyword and value.
"""

import math

import numpy as np
import pytest

import lmp
from rigid import axis_angle, quat_rotate, vec
from test_wire_errors import check_error

# global vector of fix wirenet/body (1-based index -> name)
COLUMNS = ["fx", "fy", "fz", "tx", "ty", "tz", "x", "y", "z", "vx", "vy", "vz", "n", "w_nodes", "w_body",
           "wx", "wy", "wz", "ke", "pe", "qw", "qx", "qy", "qz", "e_el", "fmx", "fmy", "fmz", "w_damp",
           # the floors' (test_body_floor.py)
           "w_floor", "e_floor", "jx", "jy", "jz", "n_floor", "d_floor"]

KN = 1e6
MDROP = 1.0


def header(box=5.0, extra=""):
    return lmp.GRANULAR_PREAMBLE + f"""{extra}
region box block {-box} {box} {-box} {box} {-box} {box} units box
create_box 1 box
neighbor 0.01 bin
neigh_modify delay 0
"""


def node(k, p, r, rho=7850.0):
    return (f"create_atoms 1 single {p[0]!r} {p[1]!r} {p[2]!r} units box\n"
            f"set atom {k} diameter {2 * r!r} density {rho!r}\n")


def thermo(fixes, every, extra="", names=COLUMNS):
    cols = " ".join(f"f_{f}[{COLUMNS.index(n) + 1}]" for f in fixes for n in names)
    return f"thermo_style custom step time {cols} {extra}\nthermo_modify format float %.17g\nthermo {every}\n"


def rows_of(out, fixes):
    table = []
    for r in lmp.thermo_rows(out):
        d = {"step": r["Step"], "time": r["Time"]}
        for f in fixes:
            d[f] = {name: r[f"{f}[{k + 1}]"] for k, name in enumerate(COLUMNS) if f"{f}[{k + 1}]" in r}
        for key, val in r.items():
            if "[" not in key:
                d[key] = val
        table.append(d)
    return table


def from_z(axis):
    """Quaternion of the minimal rotation taking +z to axis (Eigen's FromTwoVectors)."""
    a = np.asarray(axis, float) / np.linalg.norm(axis)
    z = np.array([0.0, 0.0, 1.0])
    c = np.dot(z, a)
    if c < -1 + 1e-15:
        return np.array([0.0, 1.0, 0.0, 0.0])
    q = np.concatenate([[1 + c], np.cross(z, a)])
    return q / np.linalg.norm(q)


# ---- closed-form contacts -------------------------------------------------------------------

def contact_cases():
    """(name, shape args and placement, centre, orientation quaternion, local surface point,
    local outward normal at it): the node sits at distance d = r - overlap along the normal."""
    cases = []
    cases.append(("sphere", "sphere 0.3", (0.1, -0.2, 0.05), (1.0, 0, 0, 0),
                  0.3 * np.array([0.36, 0.48, 0.8]), np.array([0.36, 0.48, 0.8])))
    # equal semi-axes: the spheroid's closed-form sphere branch (YADE's punch sphere)
    cases.append(("spheroid-sphere", "spheroid 0.3 0.3 0.3", (0.1, -0.2, 0.05), from_z([0.3, -0.2, 1.0]),
                  0.3 * np.array([-0.48, 0.36, -0.8]), np.array([-0.48, 0.36, -0.8])))
    # spheroid, axis tilted: the semi-spheroid platter's full spheroid
    a, b, c = 0.5, 0.5, 0.15
    th, ph = 0.7, 2.1
    s = np.array([a * math.sin(th) * math.cos(ph), b * math.sin(th) * math.sin(ph), c * math.cos(th)])
    n = s / np.array([a, b, c]) ** 2
    cases.append(("spheroid", f"spheroid {a} {b} {c}", (0.0, 0.1, -0.2), from_z([0.3, -0.2, 1.0]), s,
                  n / np.linalg.norm(n)))
    # triaxial, near the pole of the smallest axis
    a, b, c = 0.5, 0.3, 0.15
    th, ph = 0.15, 0.4
    s = np.array([a * math.sin(th) * math.cos(ph), b * math.sin(th) * math.sin(ph), -c * math.cos(th)])
    n = s / np.array([a, b, c]) ** 2
    cases.append(("ellipsoid", f"spheroid {a} {b} {c}", (0.2, 0.0, 0.1), (1.0, 0, 0, 0), s, n / np.linalg.norm(n)))
    # cone R 0.34, h 0.78, tip radius 0.02, tip pointing down (as wirenet-gen's, axis 0 0 -1)
    R, h, tip = 0.34, 0.78, 0.02
    rho = 0.2
    nf = np.array([h, R - tip]) / math.hypot(h, R - tip)
    phi = 0.3
    u = np.array([math.cos(phi), math.sin(phi), 0.0])
    cone = f"cone {R} {h} {tip}"
    down = from_z([0, 0, -1])
    cases.append(("cone flank", cone, (0.0, 0.0, 1.0), down,
                  rho * u + np.array([0, 0, h * (R - rho) / (R - tip)]), nf[0] * u + np.array([0, 0, nf[1]])))
    cases.append(("cone tip", cone, (0.0, 0.0, 1.0), down, np.array([0.004, -0.007, h]), np.array([0.0, 0.0, 1.0])))
    # beyond the rim of the tip disc: the nearest point is the rim, the normal bisects
    nr = np.array([1.0, 0.0, 1.0]) / math.sqrt(2)
    cases.append(("cone rim", cone, (0.0, 0.0, 1.0), down, np.array([tip, 0.0, h]), nr))
    # round tip of radius 0.05 (same height): cap about (0, h - a), tangent to the flank from the rim
    ar = 0.05
    hr = h - ar
    phi_t = math.acos(ar / math.hypot(R, hr)) - math.atan2(hr, R)
    nt = np.array([math.cos(phi_t), math.sin(phi_t)])
    tpt = np.array([0.0, hr]) + ar * nt
    th = 0.5 * (phi_t + math.pi / 2)
    dcap = np.array([math.cos(th), math.sin(th)])
    round_cone = f"cone {R} {h} {ar} tip round"
    cases.append(("round cap", round_cone, (0.0, 0.0, 1.0), down,
                  (ar * dcap[0]) * u + np.array([0, 0, hr + ar * dcap[1]]), dcap[0] * u + np.array([0, 0, dcap[1]])))
    fl = np.array([R, 0.0]) + 0.6 * (tpt - np.array([R, 0.0]))
    cases.append(("round flank", round_cone, (0.0, 0.0, 1.0), down,
                  fl[0] * u + np.array([0, 0, fl[1]]), nt[0] * u + np.array([0, 0, nt[1]])))
    cases.append(("plane", "plane", (0.0, 0.0, 0.1), from_z([1.0, 1.0, 1.0]), np.array([0.2, -0.1, 0.0]),
                  np.array([0.0, 0.0, 1.0])))
    # truncated cube 0.45, cut 0.15: face, edge (between two octagons), vertex
    hh, k = 0.225, 0.075
    tc = "truncated-cube 0.45 0.15"
    tilt = axis_angle([1.0, 2.0, 0.5], 0.4)
    cases.append(("cube face", tc, (0.0, 0.0, 0.0), tilt, np.array([hh, 0.05, 0.02]), np.array([1.0, 0, 0])))
    cases.append(("cube edge", tc, (0.0, 0.0, 0.0), tilt, np.array([hh, hh, 0.03]),
                  np.array([1.0, 1.0, 0.0]) / math.sqrt(2)))
    nv = np.array([1.0, 1.0, 0.0]) + np.array([1.0, 1.0, 1.0]) / math.sqrt(3)
    cases.append(("cube vertex", tc, (0.0, 0.0, 0.0), tilt, np.array([hh, hh, k]), nv / np.linalg.norm(nv)))
    cases.append(("cut face", tc, (0.0, 0.0, 0.0), tilt, np.array([hh - 0.04, hh - 0.04, hh - 0.07]),
                  np.array([1.0, 1.0, 1.0]) / math.sqrt(3)))
    cases.append(("box corner", "box 0.4 0.3 0.2", (0.0, 0.0, 0.0), (1.0, 0, 0, 0), np.array([0.2, 0.15, 0.1]),
                  np.array([1.0, 2.0, 3.0]) / math.sqrt(14)))
    # octahedron |x| + |y| + |z| <= 0.2 from an OBJ file (written by the test): face and vertex
    cases.append(("obj face", "polyhedron octa.obj", (0.0, 0.0, 0.0), axis_angle([0.0, 1.0, 1.0], 0.3),
                  np.array([0.05, 0.07, 0.08]), np.array([1.0, 1.0, 1.0]) / math.sqrt(3)))
    cases.append(("obj vertex", "polyhedron octa.obj", (0.0, 0.0, 0.0), (1.0, 0, 0, 0), np.array([0.0, 0.0, -0.2]),
                  np.array([0.1, -0.2, -1.0]) / math.sqrt(1.05)))
    return cases


def test_pressed_node_gets_kn_overlap_along_the_exact_normal(tmp_path):
    r, overlap = 0.01, 1e-3
    d = r - overlap
    cases = contact_cases()
    octa = ["v 0.2 0 0", "v -0.2 0 0", "v 0 0.2 0", "v 0 -0.2 0", "v 0 0 0.2", "v 0 0 -0.2"]
    octa += [f"f {i} {j} {k}" for i in (1, 2) for j in (3, 4) for k in (5, 6)]
    tmp_path.mkdir(parents=True, exist_ok=True)
    (tmp_path / "octa.obj").write_text("# octahedron\n" + "\n".join(octa) + "\n")
    deck = header(box=40.0)
    fixes, expect = [], []
    for k, (name, shape, centre, q, s, n) in enumerate(cases):
        shift = np.array([6.0 * (k % 10) - 27.0, 6.0 * (k // 10) - 3.0, 0.0])   # one body per 6 m cell
        c = np.array(centre) + shift
        p = c + quat_rotate(q, s + d * n)
        deck += node(k + 1, p, r) + f"group g{k + 1} id {k + 1}\n"
        qs = " ".join(repr(float(v)) for v in q)
        deck += (f"fix b{k + 1} g{k + 1} wirenet/body {shape} centre {c[0]!r} {c[1]!r} {c[2]!r} quat {qs} "
                 f"kn {KN!r} kt 1e5 mu 0.3\n")
        fixes.append(f"b{k + 1}")
        expect.append((name, -KN * overlap * quat_rotate(q, n), c, p))
    deck += thermo(fixes, 1, names=["fx", "fy", "fz", "tx", "ty", "tz", "n", "e_el"]) + "run 0\n"
    row = rows_of(lmp.run_deck(deck, tmp_path), fixes)[-1]
    for f, (name, force, c, p) in zip(fixes, expect):
        got = vec(row[f], "fx", "fy", "fz")
        assert row[f]["n"] == 1, name
        assert np.linalg.norm(got - force) < 1e-9 * np.linalg.norm(force), (name, got, force)
        # the torque about the reference point is that of the force at the middle of the overlap
        nn = -force / np.linalg.norm(force)
        cp = p - (r - overlap / 2) * nn
        torque = np.cross(cp - c, force)
        assert np.linalg.norm(vec(row[f], "tx", "ty", "tz") - torque) < 1e-9 * np.linalg.norm(force) * 1.0, name
        assert row[f]["e_el"] == pytest.approx(0.5 * KN * overlap ** 2, rel=1e-9), name


def test_spheroid_distance_matches_numerical_minimisation(tmp_path):
    """Random points around a tilted triaxial ellipsoid and a spheroid, inside and outside; each
    node's dumped force gives the signed distance d = r - |F|/kn and the normal F/|F|."""
    from scipy.optimize import minimize
    rng = np.random.default_rng(7)
    r = 0.3
    bodies = [((0.5, 0.3, 0.15), np.array([0.0, 0.0, 0.0]), axis_angle([0.3, 1.0, -0.4], 0.9)),
              ((0.5, 0.5, 0.15), np.array([3.0, 0.0, 0.0]), (1.0, 0.0, 0.0, 0.0))]
    deck = header(box=6.0)
    pts, k = [], 0
    for j, (axes, c, q) in enumerate(bodies):
        g = []
        for _ in range(12):
            u = rng.normal(size=3)
            u /= np.linalg.norm(u)
            local = u * np.array(axes) * rng.uniform(0.3, 1.5)      # inside and outside
            k += 1
            p = c + quat_rotate(q, local)
            deck += node(k, p, r)
            g.append(str(k))
            pts.append((k, axes, c, q, local, p))
        qs = " ".join(repr(float(v)) for v in q)
        deck += (f"group s{j} id {' '.join(g)}\nfix e{j} s{j} wirenet/body spheroid {axes[0]} {axes[1]} {axes[2]} "
                 f"centre {c[0]!r} {c[1]!r} {c[2]!r} quat {qs} kn {KN!r}\n")
    deck += ("dump d all custom 1 forces.dump id fx fy fz\n"
             'dump_modify d format "%d %.17g %.17g %.17g"\nrun 0\n')
    lmp.run_deck(deck, tmp_path)
    _, frame = lmp.dump_atom_frames(tmp_path / "forces.dump")[0]
    for (k, axes, c, q, local, p), f in zip(pts, frame):
        assert f[0] == k
        force = f[1:4]
        d_fix = r - np.linalg.norm(force) / KN
        a = np.array(axes)

        def dist2(t):
            s = a * np.array([math.sin(t[0]) * math.cos(t[1]), math.sin(t[0]) * math.sin(t[1]), math.cos(t[0])])
            return np.sum((local - s) ** 2)
        starts = [(th, ph) for th in np.linspace(0.1, 3.0, 7) for ph in np.linspace(-3.0, 3.0, 9)]
        best = min(starts, key=dist2)
        res = minimize(dist2, best, method="Nelder-Mead", options={"xatol": 1e-14, "fatol": 1e-30, "maxiter": 20000})
        inside = np.sum((local / a) ** 2) < 1
        d_ref = math.sqrt(res.fun) * (-1 if inside else 1)
        assert d_fix == pytest.approx(d_ref, abs=1e-9), (k, d_fix, d_ref)
        t = res.x
        s = a * np.array([math.sin(t[0]) * math.cos(t[1]), math.sin(t[0]) * math.sin(t[1]), math.cos(t[0])])
        normal = quat_rotate(q, s / a ** 2)
        normal /= np.linalg.norm(normal)
        assert np.allclose(force / np.linalg.norm(force), normal, atol=1e-6), k


# ---- friction, kinematics -------------------------------------------------------------------

def test_sliding_node_reaches_coulomb_limit(tmp_path):
    """A fixed node pressed 1 mm into a plane that slides along x: the tangential spring grows
    as kt v t (exactly, one increment per step), then the friction force stays at mu kn overlap."""
    r, overlap, kt, mu, v, dt = 0.01, 1e-3, 1e6, 0.3, 1.0, 1e-5
    deck = (header(1.0) + node(1, (0.0, 0.0, r - overlap), r) +
            f"fix p all wirenet/body plane centre 0 0 0 kn {KN!r} kt {kt!r} mu {mu!r} vel {v!r} 0 0\n"
            f"timestep {dt!r}\n" + thermo(["p"], 1) + "run 100\n")
    rows = rows_of(lmp.run_deck(deck, tmp_path), ["p"])
    fn = KN * overlap
    limit = mu * fn
    n_slip = limit / (kt * v * dt)
    assert 20 < n_slip < 350
    for row in rows[1:]:
        n = row["step"]
        ft = -row["p"]["fx"]                  # the node is dragged along +x, the plane held back
        assert row["p"]["fz"] == pytest.approx(-fn, rel=1e-12)
        assert abs(row["p"]["fy"]) < 1e-12 * fn
        expected = min(kt * v * n * dt, limit)
        assert ft == pytest.approx(expected, rel=1e-9), n
    assert rows[-1]["p"]["w_body"] < 0.0      # the node does negative work on the sliding plane
    assert rows[-1]["p"]["w_nodes"] == 0.0    # the node does not move


def test_soften_keeps_each_contact_force_and_scales_the_stiffness(tmp_path):
    """fix_modify soften S (a static search's softer contact, the drapery's settling): the
    node of the test above, pressed 1 mm into a plane sliding along x, sticking. At the switch
    each force stays what it was: the tangential spring is stretched by S and the node moved
    along the normal to S times the overlap (normal force kn/S times it: unchanged); then the
    friction force grows by kt v dt / S a step. `soften 1` gives back the defined law and the
    node its overlap, the forces again continuous. Exact to round-off: each phase is one more
    linear increment."""
    r, overlap, kt, mu, v, dt, soft = 0.01, 1e-3, 1e4, 0.3, 1.0, 1e-5, 4.0
    deck = (header(1.0) + node(1, (0.0, 0.0, r - overlap), r) +
            f"fix p all wirenet/body plane centre 0 0 0 kn {KN!r} kt {kt!r} mu {mu!r} vel {v!r} 0 0\n"
            f"variable z1 equal z[1]\ntimestep {dt!r}\n" + thermo(["p"], 1, "v_z1") +
            f"run 30\nfix_modify p soften {soft!r}\nrun 10\nfix_modify p soften 1\nrun 10\n")
    rows = rows_of(lmp.run_deck(deck, tmp_path), ["p"])
    assert len(rows) == 3 + 50                       # each run's setup row, then one per step
    step = kt * v * dt                               # the spring's force increment per step
    # (the phases: steps 0-30 defined, 30-40 soft, 40-50 defined; each setup row as its phase)
    expected = [(n, n * step, 1.0) for n in range(31)] + \
        [(n, 30 * step + (n - 30) * step / soft, soft) for n in range(30, 41)] + \
        [(n, 30 * step + 10 * step / soft + (n - 40) * step, 1.0) for n in range(40, 51)]
    assert [row["step"] for row in rows] == [n for n, _, _ in expected]
    for row, (n, ft, s) in zip(rows, expected):
        assert -row["p"]["fx"] == pytest.approx(ft, rel=1e-9, abs=1e-12), n
        assert row["p"]["fz"] == pytest.approx(-KN * overlap, rel=1e-9), n
        assert row["z1"] == pytest.approx(r - s * overlap, rel=1e-12), n
    assert 50 * step < mu * KN * overlap             # sticking all along: no slip hides a jump


def test_a_moving_body_finds_nodes_that_never_moved(tmp_path):
    """The fix searches contacts only among the nodes near the body, listed again when atoms are
    re-neighboured and when the body has moved half the skin. Here nothing else moves (the nodes
    are not integrated, so LIGGGHTS never re-neighbours): a sphere 0.3 m away arrives at 1 m/s
    and must press every node of the 3 x 3 grid under it by its overlap, kn delta each."""
    deck = header(1.0)
    k = 0
    for i in (-1, 0, 1):
        for j in (-1, 0, 1):
            k += 1
            deck += node(k, (0.004 * i, 0.004 * j, 0.0), 0.002)
    r, z0, v, dt, n = 0.2, 0.5, 1.0, 1e-5, 29900     # bottom of the sphere: 0.3 - v t
    deck += (f"fix s all wirenet/body sphere {r} centre 0 0 {z0} kn {KN} vel 0 0 {-v}\n"
             f"timestep {dt}\n" + thermo(["s"], 100) + f"run {n}\n")
    rows = rows_of(lmp.run_deck(deck, tmp_path), ["s"])
    bottom = z0 - r - v * n * dt
    assert rows[-1]["s"]["n"] == 9
    # each node's overlap: its radius minus its distance to the sphere's surface
    centre = np.array([0.0, 0.0, z0 - v * n * dt])
    fz = sum(KN * (0.002 - (np.linalg.norm(np.array([0.004 * i, 0.004 * j, 0.0]) - centre) - r))
             * (centre[2] - 0.0) / np.linalg.norm(np.array([0.004 * i, 0.004 * j, 0.0]) - centre)
             for i in (-1, 0, 1) for j in (-1, 0, 1))
    assert rows[-1]["s"]["fz"] == pytest.approx(fz, rel=1e-9)      # the nodes push the body up
    assert 0.0 < bottom < 0.002


def test_kinematic_body_follows_its_prescribed_motion(tmp_path):
    v = np.array([0.3, -0.1, -1.2])
    w = np.array([0.0, 2.0, 1.0])
    ramp, dt, n = 0.002, 1e-5, 500
    x0 = np.array([0.1, 0.2, 0.3])
    deck = (header(2.0) + node(1, (1.5, 1.5, 1.5), 0.01) +
            f"fix c all wirenet/body cone 0.34 0.78 0.02 centre {x0[0]} {x0[1]} {x0[2]} axis 0 0 -1 kn 1e6 "
            f"vel {v[0]} {v[1]} {v[2]} ramp {ramp} omega {w[0]} {w[1]} {w[2]}\n"
            f"timestep {dt}\n" + thermo(["c"], 50) + f"run {n}\n")
    rows = rows_of(lmp.run_deck(deck, tmp_path), ["c"])
    for row in rows:
        t = row["step"] * dt
        if t < ramp:
            x, vel = x0 + v * t * t / (2 * ramp), v * t / ramp
        else:
            x, vel = x0 + v * (t - ramp / 2), v
        assert np.allclose(vec(row["c"], "x", "y", "z"), x, rtol=0, atol=1e-14), row["step"]
        assert np.allclose(vec(row["c"], "vx", "vy", "vz"), vel, rtol=0, atol=1e-14), row["step"]
        assert np.allclose(vec(row["c"], "wx", "wy", "wz"), w, rtol=0, atol=0)
        q = axis_angle(w, np.linalg.norm(w) * t)
        assert np.allclose(vec(row["c"], "qw", "qx", "qy", "qz"), q, atol=1e-13)
    assert rows[-1]["step"] * dt > 2 * ramp



def speed_change_deck(n1, n2, extra=""):
    """A spinning cone ramped to v1, then (fix_modify) ramped from v1 to v2 over ramp2."""
    return (header(2.0) + node(1, (1.5, 1.5, 1.5), 0.01) +
            "fix c all wirenet/body cone 0.34 0.78 0.02 centre 0.1 0.2 0.3 axis 0 0 -1 kn 1e6 "
            "vel 0.3 -0.1 -1.2 ramp 0.002 omega 0 2 1\n"
            "timestep 1e-5\n" + thermo(["c"], 50) + f"run {n1}\n"
            f"fix_modify c vel 0.6 0.1 -4.8 ramp 0.003\n{extra}run {n2}\n")


def speed_change_motion(t, t1):
    """Closed form of speed_change_deck: position and velocity at time t (change at t1)."""
    x0, v1, v2 = np.array([0.1, 0.2, 0.3]), np.array([0.3, -0.1, -1.2]), np.array([0.6, 0.1, -4.8])
    r1, r2 = 0.002, 0.003
    if t <= t1:
        return (x0 + v1 * t * t / (2 * r1), v1 * t / r1) if t < r1 else (x0 + v1 * (t - r1 / 2), v1)
    x1, s = x0 + v1 * (t1 - r1 / 2), t - t1
    if s < r2:
        return x1 + v1 * s + (v2 - v1) * s * s / (2 * r2), v1 + (v2 - v1) * s / r2
    return x1 + v1 * r2 + (v2 - v1) * r2 / 2 + v2 * (s - r2), v2


def test_fix_modify_vel_ramps_from_the_current_velocity(tmp_path):
    """fix_modify vel between runs: the body goes on from where it is, its velocity changing
    linearly from the old to the new one over the new ramp (no jump in position or velocity);
    the spin and its orientation go on unchanged."""
    n1, n2, dt = 400, 600, 1e-5
    rows = rows_of(lmp.run_deck(speed_change_deck(n1, n2), tmp_path), ["c"])
    w = np.array([0.0, 2.0, 1.0])
    assert rows[-1]["step"] == n1 + n2
    for row in rows:
        t = row["step"] * dt
        x, vel = speed_change_motion(t, n1 * dt)
        assert np.allclose(vec(row["c"], "x", "y", "z"), x, rtol=0, atol=1e-13), row["step"]
        assert np.allclose(vec(row["c"], "vx", "vy", "vz"), vel, rtol=0, atol=1e-12), row["step"]
        q = axis_angle(w, np.linalg.norm(w) * t)
        assert np.allclose(vec(row["c"], "qw", "qx", "qy", "qz"), q, atol=1e-12), row["step"]


def test_restart_continues_a_changed_motion(tmp_path):
    """A restart written after fix_modify vel holds the changed motion: the fix defined again
    with its first 'vel' goes on with the changed one, as the uninterrupted run."""
    n1, n2, dt = 400, 600, 1e-5
    first = speed_change_deck(n1, 100).replace("run 100\n", "run 100\nwrite_restart c.restart\n")
    lmp.run_deck(first, tmp_path)
    second = ("read_restart c.restart\natom_modify sort 0 0\nneighbor 0.01 bin\nneigh_modify delay 0\n" +
              "fix c all wirenet/body cone 0.34 0.78 0.02 centre 0.1 0.2 0.3 axis 0 0 -1 kn 1e6 "
              "vel 0.3 -0.1 -1.2 ramp 0.002 omega 0 2 1\n"
              "timestep 1e-5\n" + thermo(["c"], 50) + f"run {n2 - 100}\n")
    rows = rows_of(lmp.run_deck(second, tmp_path), ["c"])
    assert rows[-1]["step"] == n1 + n2
    for row in rows:
        x, vel = speed_change_motion(row["step"] * dt, n1 * dt)
        assert np.allclose(vec(row["c"], "x", "y", "z"), x, rtol=0, atol=1e-12), row["step"]
        assert np.allclose(vec(row["c"], "vx", "vy", "vz"), vel, rtol=0, atol=1e-12), row["step"]


# ---- free body ------------------------------------------------------------------------------

def test_default_inertia_of_the_truncated_cube(tmp_path):
    """Without 'inertia' a free body has the inertia of its uniform solid: the truncated cube of
    wirenet-gen (0.45 m, cut 0.15 m, 44.5 kg) has I = 1.41345292207792 kg m2 on every axis
    (doc/wirenet-gen.md); torque-free, tilted, it spins at constant omega with KE = I w^2 / 2."""
    w = np.array([1.0, -2.0, 3.0])
    deck = (header(2.0) + node(1, (1.5, 1.5, 1.5), 0.01) +
            f"fix b all wirenet/body truncated-cube 0.45 0.15 axis 1 2 3 kn 1e6 mass 44.5 omega {w[0]} {w[1]} {w[2]}\n"
            "timestep 1e-4\n" + thermo(["b"], 100) + "run 300\n")
    rows = rows_of(lmp.run_deck(deck, tmp_path), ["b"])
    for r in rows:
        assert r["b"]["ke"] == pytest.approx(0.5 * 1.41345292207792 * np.dot(w, w), rel=1e-12)
        assert np.allclose(vec(r["b"], "wx", "wy", "wz"), w, rtol=1e-12)
    q = vec(rows[-1]["b"], "qw", "qx", "qy", "qz")
    assert np.allclose(q, axis_angle(w, np.linalg.norm(w) * 300 * 1e-4), atol=1e-12)


def drop_deck(steps, gamma=0.0, mu=0.0, nodes_free=True, extra=""):
    """A free sphere (R 0.1 m, 1 kg) falls at 1 m/s onto four node spheres (33 g each) below it."""
    r = 0.01
    deck = header(1.0)
    for k, (x, y) in enumerate([(0.04, 0.0), (-0.04, 0.0), (0.0, 0.04), (0.0, -0.04)]):
        deck += node(k + 1, (x, y, 0.0), r)
    if nodes_free:
        deck += "fix integ all nve/sphere\n"
    deck += (f"fix s all wirenet/body sphere 0.1 centre 0.003 -0.002 0.1055 kn 1e5 kt 5e4 mu {mu} "
             f"gamma_n {gamma} mass {MDROP} vel 0.05 0 -1 omega 0 1 0 gravity 0 0 -9.81 {extra}\n"
             "compute ke all ke\ncompute kr all erotate/sphere\nvariable mn equal mass(all)\n"
             "variable px equal v_mn*vcm(all,x)\nvariable py equal v_mn*vcm(all,y)\nvariable pz equal v_mn*vcm(all,z)\n"
             "variable ekn equal c_ke+c_kr\n"
             "timestep 1e-5\n" + thermo(["s"], 100, "v_px v_py v_pz v_ekn") + f"run {steps}\n")
    return deck


def test_free_sphere_momentum_and_energy_budget(tmp_path):
    """Undamped and frictionless, the total energy of sphere + nodes + contact springs is
    conserved; with viscous damping and friction, energy is lost, and in both cases the change
    of the body's energy is the contact work on the body and that of the nodes the contact work
    on the nodes. Momentum of body + nodes = initial + weight impulse, to round-off."""
    M, g = MDROP, 9.81
    for label, gamma, mu in (("elastic", 0.0, 0.0), ("dissipative", 700.0, 0.4)):
        rows = rows_of(lmp.run_deck(drop_deck(3000, gamma, mu), tmp_path / label), ["s"])
        first = rows[0]
        assert max(r["s"]["n"] for r in rows) >= 2, label     # it hit several nodes at once
        e0 = first["s"]["ke"] + first["s"]["pe"]
        worst = [0.0, 0.0, 0.0]
        for r in rows:
            s = r["s"]
            t = r["time"]
            p = M * vec(s, "vx", "vy", "vz") + vec(r, "px", "py", "pz")
            p0 = M * np.array([0.05, 0.0, -1.0]) + np.array([0.0, 0.0, -M * g * t])
            assert np.allclose(p, p0, rtol=0, atol=1e-11 * M), (label, r["step"])
            e_body = s["ke"] + s["pe"] - e0
            scale = first["s"]["ke"]
            worst[0] = max(worst[0], abs(e_body - s["w_body"]) / scale)
            worst[1] = max(worst[1], abs(r["ekn"] - s["w_nodes"]) / scale)
            if gamma == 0.0:
                worst[2] = max(worst[2], abs(-(s["w_body"] + s["w_nodes"]) - s["e_el"]) / scale)
        # F(t+dt).v(t+dt) dt sums to the change of the half-step kinetic energy: during a contact
        # it differs from the end-of-step energy by O(omega dt) (measured 1e-3 here) ...
        assert max(worst) < 3e-3, (label, worst)
        # ... and once the nodes fly free (only contact forces act on them) the two agree exactly
        assert rows[-1]["ekn"] == pytest.approx(rows[-1]["s"]["w_nodes"], rel=1e-10), label
        last = rows[-1]["s"]
        assert last["n"] == 0, label                            # the nodes flew off
        assert np.linalg.norm(vec(rows[-1], "px", "py", "pz")) > 0.1 * M, label
        lost = -(last["w_body"] + last["w_nodes"])
        if gamma > 0.0:
            assert lost > 0.01 * first["s"]["ke"], label
        else:
            assert abs(lost) < 3e-4 * first["s"]["ke"], label


GRID_AXES = (0.2, 0.15, 0.08)
GRID_AXIS = (0.2, 0.1, 1.0)


def grid_deck(steps, extra_header="", gamma=500.0):
    """A tilted, spinning free spheroid with friction and damping dropped on a fixed 17 x 17 grid
    of nodes (2.5 cm apart) centred on x = 0, where two ranks cut the box; it starts 0.5 mm
    above the node tops and stays in contact for several hundred steps."""
    deck = header(1.0, extra_header)
    k = 0
    for i in range(17):
        for j in range(17):
            k += 1
            deck += node(k, (-0.2 + 0.025 * i + 0.0001, -0.2 + 0.025 * j, 0.0), 0.01)
    # lowest point of the tilted spheroid: s = -M ez / sqrt(ez . M ez), M = R diag(a^2) R^T;
    # the centre is placed so that it lies 0.5 mm above the node tops at x = 0.002
    rot = np.array([quat_rotate(from_z(GRID_AXIS), e) for e in np.eye(3)]).T
    m = rot @ np.diag(np.array(GRID_AXES) ** 2) @ rot.T
    ez = np.array([0.0, 0.0, 1.0])
    low = -m @ ez / math.sqrt(ez @ m @ ez)
    centre = np.array([0.002, -0.003, 0.0105]) - low
    a = GRID_AXES
    deck += (f"fix s all wirenet/body spheroid {a[0]} {a[1]} {a[2]} centre {centre[0]!r} {centre[1]!r} {centre[2]!r} "
             f"axis {GRID_AXIS[0]} {GRID_AXIS[1]} {GRID_AXIS[2]} kn 1e5 kt 3e4 "
             f"mu 0.4 gamma_n {gamma} mass 12 vel 0.1 0.05 -1 omega 1 -2 3 gravity 0 0 -9.81\n"
             "dump d all custom 400 forces.*.dump id x y z fx fy fz\n"
             'dump_modify d format "%d %.17g %.17g %.17g %.17g %.17g %.17g"\n'
             "timestep 1e-5\n" + thermo(["s"], 50))
    return deck + f"run {steps}\n"


def test_one_and_two_ranks_agree(tmp_path):
    one = rows_of(lmp.run_deck(grid_deck(800), tmp_path / "np1"), ["s"])
    two = rows_of(lmp.run_deck(grid_deck(800, "processors 2 1 1"), tmp_path / "np2", np=2), ["s"])
    assert len(one) == len(two) > 10
    assert max(r["s"]["n"] for r in one) >= 6
    for a, b in zip(one, two):
        for key in COLUMNS:
            x, y = a["s"][key], b["s"][key]
            assert y == pytest.approx(x, rel=1e-9, abs=1e-9 * max(1.0, abs(x))), (a["step"], key)
    # the contact region straddles the cut at x = 0: nodes touched on both ranks
    _, rows = lmp.dump_atom_frames(tmp_path / "np2" / "forces.400.dump")[400]
    touched = rows[np.abs(rows[:, 4:7]).sum(axis=1) > 0]
    assert (touched[:, 1] < 0).any() and (touched[:, 1] > 0).any(), touched[:, :4]


def drag_deck(extra_header=""):
    """Six nodes at rest (z held by setforce) on a plane that slides along +x at 1 m/s: static
    friction (the spring stays below mu Fn) drags them along, and they oscillate about the plane's
    velocity on the tangential springs (rolling at about 2/7 of it) while they cross x = 0, where
    two ranks cut the box."""
    deck = header(0.5, extra_header)
    for k in range(6):
        deck += node(k + 1, (-0.015 + 0.002 * k, 0.025 * k - 0.06, 0.01 - 0.001), 0.01)
    deck += ("fix integ all nve/sphere\n"
             "fix p all wirenet/body plane kn 1e5 kt 1e4 mu 0.5 vel 1 0 0\n"
             "fix hold all setforce NULL NULL 0\n"
             "variable x1 equal x[1]\nvariable x6 equal x[6]\nvariable v1 equal vx[1]\n"
             "timestep 1e-5\n" + thermo(["p"], 100, "v_x1 v_x6 v_v1") + "run 9000\n")
    return deck


def test_friction_history_migrates_between_ranks(tmp_path):
    one = rows_of(lmp.run_deck(drag_deck(), tmp_path / "np1"), ["p"])
    two = rows_of(lmp.run_deck(drag_deck("processors 2 1 1"), tmp_path / "np2", np=2), ["p"])
    assert all(r["p"]["n"] == 6 for r in one)            # every node stays in contact
    assert one[0]["x6"] < 0.0 < one[-1]["x1"]             # all of them crossed the cut (migrated)
    # sticking: the spring force stays below mu Fn, the nodes oscillate about the plane's speed
    assert max(abs(r["p"]["fx"]) for r in one) < 0.9 * 0.5 * 6 * 1e5 * 1e-3
    assert min(r["v1"] for r in one[10:]) > 0.0
    for a, b in zip(one, two):
        for key in ("fx", "fy", "fz", "tx", "ty", "tz", "w_nodes", "w_body", "e_el"):
            x, y = a["p"][key], b["p"][key]
            assert y == pytest.approx(x, rel=1e-9, abs=1e-12), (a["step"], key)
        assert b["x1"] == pytest.approx(a["x1"], rel=1e-12) and b["v1"] == pytest.approx(a["v1"], rel=1e-9)


def test_restart_continues_the_trajectory(tmp_path):
    """Without viscous damping: a restarted run recomputes the setup forces with the velocities at
    the end of the step, where the running one had the half-step velocities (LIGGGHTS' own
    velocity-dependent contacts restart the same way)."""
    straight = rows_of(lmp.run_deck(grid_deck(800, gamma=0.0), tmp_path / "a"), ["s"])
    lmp.run_deck(grid_deck(400, gamma=0.0) + "write_restart half.restart\n", tmp_path / "b")
    keep = [l for l in grid_deck(0, gamma=0.0).splitlines()
            if not l.startswith(("units", "atom_style", "atom_modify", "boundary", "newton", "region box",
                                 "create_box", "create_atoms", "set atom", "run "))]
    second = "read_restart half.restart\natom_modify sort 0 0\n" + "\n".join(keep) + "\nrun 400\n"
    cont = rows_of(lmp.run_deck(second, tmp_path / "b"), ["s"])
    mid = [r for r in straight if r["step"] == 400][0]
    assert mid["s"]["n"] >= 3                  # sliding contacts carry friction history across
    a, b = straight[-1], cont[-1]
    assert a["step"] == b["step"] == 800
    for key in COLUMNS:
        x, y = a["s"][key], b["s"][key]
        assert y == pytest.approx(x, rel=1e-9, abs=1e-9 * max(1.0, abs(x))), key


# ---- bad arguments --------------------------------------------------------------------------

BAD = {
    "unknown keyword": ("sphere 0.1 kn 1e6 spin 3", "unknown keyword 'spin'"),
    "mean zero": ("sphere 0.1 kn 1e6 mean 0", "mean must be >= 1 (got 0)"),
    "mean fraction": ("sphere 0.1 kn 1e6 mean 2.5", "'mean' must be a whole number of steps, 1 to 1e9 (got '2.5')"),
    "mean missing": ("sphere 0.1 kn 1e6 mean", "'mean' needs a value"),
    "unknown shape": ("cube 0.1 kn 1e6", "unknown shape 'cube'"),
    "missing kn": ("sphere 0.1", "missing 'kn K'"),
    "negative kn": ("sphere 0.1 kn -5", "kn must be > 0 (got -5)"),
    "nan kt": ("sphere 0.1 kn 1e6 kt nan", "kt must be a finite number (got 'nan')"),
    "inf radius": ("sphere inf kn 1e6", "sphere parameter must be a finite number (got 'inf')"),
    "zero radius": ("sphere 0 kn 1e6", "sphere radius must be a finite number > 0 (got 0)"),
    "vel with 2 values": ("sphere 0.1 kn 1e6 vel 1 2", "'vel' needs 3 values"),
    "kn without value": ("sphere 0.1 kn", "'kn' needs a value"),
    "spheroid with 2 axes": ("spheroid 0.5 0.5 kn 1e6", "'spheroid' needs 3 semi-axes a b c (got 'kn')"),
    "cone tip too wide": ("cone 0.3 0.7 0.3 kn 1e6", "cone tip radius must be in [0, base radius) (got 0.3)"),
    "negative mu": ("sphere 0.1 kn 1e6 kt 1 mu -0.2", "mu must be >= 0 (got -0.2)"),
    "friction without kt": ("sphere 0.1 kn 1e6 mu 0.2", "mu 0.2 needs a tangential stiffness 'kt' > 0"),
    "zero axis": ("plane kn 1e6 axis 0 0 0", "axis must not be 0 0 0"),
    "free cone": ("cone 0.3 0.7 0 kn 1e6 mass 3", "a cone cannot be a free body"),
    "ramp on a free body": ("sphere 0.1 kn 1e6 mass 3 ramp 0.1", "'ramp' is for a kinematic body"),
    "gravity on a kinematic body": ("sphere 0.1 kn 1e6 gravity 0 0 -9.81", "'gravity' acts on a free body only"),
    "bad inertia": ("sphere 0.1 kn 1e6 mass 1 inertia 1 1 3 0 0 0", "inertia tensor violates I1 + I2 >= I3"),
    "bad corner cut": ("truncated-cube 0.45 0.3 kn 1e6", "truncated-cube corner cut must be in (0, side/2) (got 0.3)"),
    "missing obj": ("polyhedron nosuch.obj kn 1e6", "polyhedron: cannot open 'nosuch.obj'"),
    "bad cone tip": ("cone 0.3 0.7 0.02 tip pointy kn 1e6", "tip must be 'flat' or 'round' (got 'pointy')"),
    "negative ramp": ("sphere 0.1 kn 1e6 vel 0 0 1 ramp -1", "ramp must be >= 0 (got -1)"),
    "damping of 1": ("sphere 0.1 kn 1e6 mass 1 damping 1", "damping must be in [0, 1) (got 1)"),
    "nan damping": ("sphere 0.1 kn 1e6 mass 1 damping nan", "damping must be a finite number (got 'nan')"),
    "damping of a kinematic body": ("sphere 0.1 kn 1e6 damping 0.5", "'damping' acts on a free body only"),
}


@pytest.mark.parametrize("case", sorted(BAD))
def test_bad_arguments_are_named(tmp_path, case):
    args, phrase = BAD[case]
    deck = header(1.0) + node(1, (0.0, 0.0, 0.0), 0.01) + f"fix b all wirenet/body {args}\nrun 0\n"
    rc, out = lmp.run_deck_rc(deck, tmp_path)
    check_error(rc, out, "fix wirenet/body: " + phrase)


OCTA_V = ["v 0.2 0 0", "v -0.2 0 0", "v 0 0.2 0", "v 0 -0.2 0", "v 0 0 0.2", "v 0 0 -0.2"]
OCTA_F = [f"f {i} {j} {k}" for i in (1, 2) for j in (3, 4) for k in (5, 6)]

# OBJ files with one word that is not what it must be (issue #43: face indices were read with
# atoi, so '2.7' was vertex 2 and '4294967300' vertex 4): (vertex lines, face lines, phrase)
BAD_OBJ = {
    "fractional face index": (OCTA_V, OCTA_F[:-1] + ["f 2 4 6.7"], "line 14: face index '6.7' is not a whole number"),
    "face index beyond int": (OCTA_V, OCTA_F[:-1] + ["f 2 4 4294967300"],
                              "line 14: face index '4294967300' is not a whole number from 1 to 2147483647"),
    "negative face index": (OCTA_V, ["f -1 3 5"] + OCTA_F[1:], "line 7: face index '-1' is not a whole number"),
    "face index with a sign": (OCTA_V, ["f +1 3 5"] + OCTA_F[1:], "line 7: face index '+1' is not a whole number"),
    "bad texture index": (OCTA_V, ["f 1/x 3 5"] + OCTA_F[1:], "line 7: face index '1/x' is not a whole number"),
    "face index beyond the vertices": (OCTA_V, OCTA_F[:-1] + ["f 2 4 7"],
                                       "line 14: face index 7 names a vertex the file does not have (it has 6)"),
    "vertex coordinate with a suffix": (OCTA_V[:2] + ["v 0 0.2abc 0"] + OCTA_V[3:], OCTA_F,
                                        "line 3: vertex coordinate '0.2abc' is not a finite number"),
    "vertex of two numbers": (OCTA_V[:2] + ["v 0 0.2"] + OCTA_V[3:], OCTA_F, "line 3: a vertex is 'v X Y Z'"),
}


@pytest.mark.parametrize("case", sorted(BAD_OBJ))
def test_bad_obj_file_is_named(tmp_path, case):
    vertices, faces, phrase = BAD_OBJ[case]
    (tmp_path / "bad.obj").write_text("\n".join(vertices + faces) + "\n")
    deck = header(1.0) + node(1, (0.0, 0.0, 0.5), 0.01) + "fix b all wirenet/body polyhedron bad.obj kn 1e6\nrun 0\n"
    rc, out = lmp.run_deck_rc(deck, tmp_path, timeout=60)
    check_error(rc, out, "fix wirenet/body: polyhedron: 'bad.obj' " + phrase)


def test_obj_index_forms_are_read(tmp_path):
    """'i', 'i/t', 'i/t/n' and 'i//n' all name vertex i."""
    faces = ["f 1/1 3 5", "f 1 3/1/1 6", "f 1//2 4 5", "f 1 4 6/2"] + OCTA_F[4:]
    (tmp_path / "forms.obj").write_text("\n".join(OCTA_V + faces) + "\n")
    deck = header(1.0) + node(1, (0.0, 0.0, 0.5), 0.01) + "fix b all wirenet/body polyhedron forms.obj kn 1e6\nrun 0\n"
    lmp.run_deck(deck, tmp_path, timeout=60)


def test_window_mean_force_is_the_mean_of_fix_ave_time_on_one_and_two_ranks(tmp_path):
    """`mean N`: outputs 26-28 are the mean force over the window of N steps up to the last
    multiple of N, summed on each rank and reduced once per output; fix ave/time takes the same
    mean of the reduced force at every step. The plane drags six nodes across the ranks' cut."""
    def deck(extra_header=""):
        d = drag_deck(extra_header).replace("vel 1 0 0\n", "vel 1 0 0 mean 100\n")
        return d.replace("run 9000\n", "fix m all ave/time 1 100 100 f_p[1] f_p[2] f_p[3]\n"
                         'fix out all print 100 "M $(step) $(f_p[26]) $(f_p[27]) $(f_p[28]) '
                         '$(f_m[1]) $(f_m[2]) $(f_m[3])" screen yes\nrun 4030\nrun 2970\n')

    def means(out):
        return np.array([line.split()[1:] for line in out.splitlines() if line.startswith("M ")], float)

    one = means(lmp.run_deck(deck(), tmp_path / "np1"))
    two = means(lmp.run_deck(deck("processors 2 1 1"), tmp_path / "np2", np=2))
    assert len(one) == 70 and list(one[:, 0]) == list(range(100, 7001, 100))
    scale = np.abs(one[:, 4:7]).max()
    assert scale > 1.0
    assert np.abs(one[:, 1:4] - one[:, 4:7]).max() < 1e-12 * scale   # two runs: no step twice
    assert np.abs(two[:, 1:4] - one[:, 1:4]).max() < 1e-9 * scale


@pytest.mark.parametrize("vz0", [-1.0, 0.5])
def test_local_damping_of_a_free_body_in_flight(tmp_path, vz0):
    """With no contacts the resultant is the weight: falling, the damping takes A of it
    (acceleration (1 - A) g), rising it adds A ((1 + A) g); the horizontal velocity and the spin
    see no force or torque and keep their values; KE + PE - initial = W_damping. The first run is
    undamped (exact free flight), fix_modify then switches the damping on."""
    A, g, dt, n = 0.7, 9.81, 1e-5, 1000
    deck = header(5.0) + node(1, (4.0, 4.0, 4.0), 0.01) + (
        f"fix b all wirenet/body sphere 0.1 kn 1e5 mass 2 vel 0.3 0 {vz0} omega 1 2 3 "
        f"gravity 0 0 -{g}\ntimestep {dt}\n" + thermo(["b"], n) +
        f"run {n}\nfix_modify b damping {A}\nrun {n}\n")
    rows = rows_of(lmp.run_deck(deck, tmp_path), ["b"])
    t = n * dt
    start, mid, end = rows[0]["b"], rows[1]["b"], rows[-1]["b"]
    assert mid["w_damp"] == 0.0
    assert mid["vz"] == pytest.approx(vz0 - g * t, rel=1e-12)
    effective = g * (1 - A) if vz0 < 0 else g * (1 + A)
    assert end["vz"] == pytest.approx(mid["vz"] - effective * t, rel=1e-12)
    assert end["z"] - mid["z"] == pytest.approx(mid["vz"] * t - 0.5 * effective * t * t, rel=1e-9)
    assert end["vx"] == pytest.approx(0.3, rel=1e-14) and end["x"] == pytest.approx(0.6 * t, rel=1e-9)
    assert np.allclose(vec(end, "wx", "wy", "wz"), [1, 2, 3], rtol=1e-12)
    energy = end["ke"] + end["pe"] - (start["ke"] + start["pe"])
    assert end["w_damp"] < 0
    assert energy == pytest.approx(end["w_damp"], rel=1e-9)


# bad fix_modify arguments: (body keywords, fix_modify arguments, the message after "fix_modify
# wirenet/body: "); a kinematic body (no mass) follows its prescribed motion, so damping it
# would be ignored, and a free body moves by its forces, so a prescribed velocity would be
BAD_MODIFY = {
    "negative damping": ("mass 1", "damping -0.1", "damping must be >= 0 (got -0.1)"),
    "damping without value": ("mass 1", "damping", "'damping' needs a value"),
    "damping of 1": ("mass 1", "damping 1", "damping must be in [0, 1) (got 1)"),
    "damping of a kinematic body": ("", "damping 0.5", "'damping' acts on a free body only: give 'mass M'"),
    "vel with 2 values": ("", "vel 0 0", "'vel' needs 3 values"),
    "nan vel": ("", "vel 0 0 nan", "vel value must be a finite number (got 'nan')"),
    "negative ramp": ("", "vel 0 0 -1 ramp -2", "ramp must be >= 0 (got -2)"),
    "unknown keyword after vel": ("", "vel 0 0 -1 spin 2",
                                  "unknown keyword 'spin' after 'vel vx vy vz' (only 'ramp T')"),
    "extra value after ramp": ("", "vel 0 0 -1 ramp 1 2", "unexpected '2' after 'ramp T'"),
    "vel of a free body": ("mass 1", "vel 0 0 1", "'vel' sets the motion of a kinematic body"),
    "soften below 1": ("", "soften 0.5", "soften must be >= 1 (got 0.5)"),
    "soften without a factor": ("", "soften", "'soften' needs a value"),
    "inf soften": ("", "soften inf", "soften must be a finite number (got 'inf')"),
    "extra value after soften": ("", "soften 4 2", "unexpected '2' after 'soften S'"),
}


@pytest.mark.parametrize("case", sorted(BAD_MODIFY))
def test_fix_modify_errors_are_named(tmp_path, case):
    body, args, phrase = BAD_MODIFY[case]
    deck = (header(1.0) + node(1, (0.0, 0.0, 0.0), 0.01) +
            f"fix b all wirenet/body sphere 0.1 kn 1e6 {body} centre 0 0 0.5\nfix_modify b {args}\nrun 0\n")
    rc, out = lmp.run_deck_rc(deck, tmp_path)
    check_error(rc, out, "fix_modify wirenet/body: " + phrase)
