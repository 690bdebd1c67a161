"""fix wirenet/rigidmesh: the truncated-cube block of wirenet-gen as a 6-DOF rigid body.

- free flight under gravity is ballistic (velocity Verlet is exact for a constant force) and the
  mesh nodes and facet normals follow the rigid motion;
- torque-free rotation: the symmetric top precesses exactly as Poinsot's solution (the splitting is
  exact for axisymmetric bodies), a triaxial body given by a full inertia tensor follows an RK4
  reference of Euler's equations to O(dt^2) and keeps L to round-off;
- the wall velocity: a head-on collision with a free sphere and a viscous contact has the
  restitution coefficient of the spring-dashpot with the reduced mass, and conserves momentum;
- a tilted, spinning block dropped on a fixed plane of spheres (linear elastic contacts, no
  damping, no friction) bounces with its energy conserved (3e-6 of the kinetic energy; 1 % asked);
- 1 and 2 MPI ranks agree; a write_restart / read_restart continuation matches the straight run.
"""

import math

import numpy as np
import pytest

import lmp
from rigid import axis_angle, quat_rotate, vec

MASS = 44.5
I_CUBE = 1.41345292207792     # wirenet-gen truncated cube, 0.45 m, 44.5 kg (isotropic)
HALF = 0.225
G = 9.81

# global vector of fix wirenet/rigidmesh (1-based index -> name)
COLUMNS = ["x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz", "fx", "fy", "fz", "f", "tx", "ty", "tz",
           "ke", "ke_rot", "pe", "lx", "ly", "lz", "qw", "qx", "qy", "qz"]


@pytest.fixture(scope="module")
def stl(tmp_path_factory):
    d = tmp_path_factory.mktemp("block")
    import subprocess
    subprocess.run([str(lmp.GEN), "shape", "truncated-cube", "--out", str(d / "block.stl")],
                   check=True, stdout=subprocess.PIPE)
    return d / "block.stl"


def base_deck(stl_path, mesh_opts="", kn=1e7, gamma=0.0, box=2.0):
    damping = "absolute_damping on" if gamma else ""
    return lmp.GRANULAR_PREAMBLE + f"""region box block {-box} {box} {-box} {box} {-box} {box} units box
create_box 2 box
neighbor 0.01 bin
neigh_modify delay 0
fix m1 all property/global kn peratomtypepair 2 {kn!r} {kn!r} {kn!r} {kn!r}
fix m2 all property/global kt peratomtypepair 2 {kn!r} {kn!r} {kn!r} {kn!r}
fix m3 all property/global gamman_abs peratomtypepair 2 {gamma!r} {gamma!r} {gamma!r} {gamma!r}
fix m4 all property/global gammat_abs peratomtypepair 2 0 0 0 0
fix m5 all property/global gamman peratomtypepair 2 0 0 0 0
fix m6 all property/global gammat peratomtypepair 2 0 0 0 0
fix m7 all property/global coefficientFriction peratomtypepair 2 0 0 0 0
pair_style gran model hooke/stiffness tangential no_history {damping}
pair_coeff * *
fix block all mesh/surface/stress file {stl_path} type 2 {mesh_opts} stress on
fix wall all wall/gran model hooke/stiffness tangential no_history mesh n_meshes 1 meshes block {damping}
"""


def body_line(inertia=(I_CUBE, I_CUBE, I_CUBE, 0, 0, 0), extra=""):
    vals = " ".join(repr(float(v)) for v in inertia)
    return f"fix rb all wirenet/rigidmesh mesh block mass {MASS!r} inertia {vals} {extra}\n"


def thermo_block(every, extra_cols=""):
    cols = " ".join(f"f_rb[{k + 1}]" for k in range(len(COLUMNS)))
    return f"""thermo_style custom step time {cols} {extra_cols}
thermo_modify format float %.17g
thermo {every}
"""


def rows_of(out):
    table = []
    for r in lmp.thermo_rows(out):
        d = {"step": r["Step"], "time": r["Time"]}
        for k, name in enumerate(COLUMNS):
            d[name] = r[f"rb[{k + 1}]"]
        for key, val in r.items():
            if key not in d and not key.startswith("rb["):
                d[key] = val
        table.append(d)
    return table


def read_stl(path):
    normals, verts = [], []
    for line in open(path):
        w = line.split()
        if w[:2] == ["facet", "normal"]:
            normals.append([float(t) for t in w[2:5]])
        elif w[:1] == ["vertex"]:
            verts.append([float(t) for t in w[1:4]])
    return np.array(normals), np.array(verts).reshape(-1, 3, 3)


# ---------------------------------------------------------------------------------------------

def test_ballistic_flight_and_rigid_mesh(tmp_path, stl):
    v0, w0, dt, n = np.array([1.0, -0.5, 3.0]), np.array([2.0, -1.0, 3.0]), 1e-3, 500
    deck = (base_deck(stl, box=5.0) +
            body_line(extra=f"vel {v0[0]} {v0[1]} {v0[2]} omega {w0[0]} {w0[1]} {w0[2]} gravity 0 0 {-G}") +
            f"timestep {dt}\n" + thermo_block(100) +
            f"dump st all mesh/stl {n} mesh*.stl block\nrun {n}\n")
    rows = rows_of(lmp.run_deck(deck, tmp_path))
    last = rows[-1]
    t = n * dt
    g = np.array([0.0, 0.0, -G])
    assert np.allclose(vec(last, "x", "y", "z"), v0 * t + 0.5 * g * t * t, rtol=1e-13, atol=1e-13)
    assert np.allclose(vec(last, "vx", "vy", "vz"), v0 + g * t, rtol=1e-13, atol=1e-13)
    # isotropic body: constant omega, rotation by |w| t about w
    assert np.allclose(vec(last, "wx", "wy", "wz"), w0, rtol=1e-13)
    q = vec(last, "qw", "qx", "qy", "qz")
    assert np.allclose(q, axis_angle(w0, np.linalg.norm(w0) * t), atol=1e-12)
    # energy bookkeeping of the output
    ke = 0.5 * MASS * np.dot(v0 + g * t, v0 + g * t) + 0.5 * I_CUBE * np.dot(w0, w0)
    assert last["ke"] == pytest.approx(ke, rel=1e-13)
    assert last["pe"] == pytest.approx(MASS * G * last["z"], rel=1e-13)
    # the dumped mesh: every vertex and facet normal moved rigidly (dump precision %g)
    n0, v_ref = read_stl(stl)
    n1, v_now = read_stl(tmp_path / f"mesh{n}.stl")
    assert v_now.shape == v_ref.shape
    x = vec(last, "x", "y", "z")
    moved = np.array([[quat_rotate(q, p) + x for p in tri] for tri in v_ref])
    order_ref = np.lexsort(moved.reshape(len(moved), -1).T.round(4))
    order_now = np.lexsort(v_now.reshape(len(v_now), -1).T.round(4))
    assert np.allclose(moved[order_ref], v_now[order_now], atol=5e-6)
    assert np.allclose(np.array([quat_rotate(q, m) for m in n0])[order_ref], n1[order_now], atol=5e-6)


def test_symmetric_top_precesses_exactly(tmp_path, stl):
    """Poinsot: omega(t) = L/I1 + (1/I3 - 1/I1)(L.e3) e3(t), e3 turning about L at |L|/I1."""
    i1, i3 = 1.0, 1.8
    w0 = np.array([2.0, 0.0, 5.0])
    dt, n = 2e-3, 1500
    deck = (base_deck(stl, box=5.0) + body_line((i1, i1, i3, 0, 0, 0), f"omega {w0[0]} {w0[1]} {w0[2]}") +
            f"timestep {dt}\n" + thermo_block(50) + f"run {n}\n")
    rows = rows_of(lmp.run_deck(deck, tmp_path))
    L = np.array([i1 * w0[0], i1 * w0[1], i3 * w0[2]])
    rate = np.linalg.norm(L) / i1
    e3_0 = np.array([0.0, 0.0, 1.0])
    worst = 0.0
    for r in rows:
        e3 = quat_rotate(axis_angle(L, rate * r["time"]), e3_0)
        w = L / i1 + (1 / i3 - 1 / i1) * np.dot(L, e3) * e3
        worst = max(worst, np.abs(vec(r, "wx", "wy", "wz") - w).max())
        assert np.allclose(vec(r, "lx", "ly", "lz"), L, rtol=1e-13, atol=1e-13)
    assert worst < 1e-10, worst
    assert rows[-1]["time"] * rate > 4 * math.pi  # at least two precession turns


def euler_rk4(inertia_body, w0, t_end, h):
    """Reference: Euler's equations in the principal frame, classical RK4."""
    I = np.asarray(inertia_body, float)

    def f(w):
        return np.array([(I[1] - I[2]) * w[1] * w[2] / I[0],
                         (I[2] - I[0]) * w[2] * w[0] / I[1],
                         (I[0] - I[1]) * w[0] * w[1] / I[2]])
    w = np.array(w0, float)
    out = [w.copy()]
    for _ in range(int(round(t_end / h))):
        k1 = f(w); k2 = f(w + h / 2 * k1); k3 = f(w + h / 2 * k2); k4 = f(w + h * k3)
        w = w + h / 6 * (k1 + 2 * k2 + 2 * k3 + k4)
        out.append(w.copy())
    return np.array(out)


def test_triaxial_body_follows_euler_equations(tmp_path, stl):
    """Full inertia tensor (principal axes rotated off the STL axes): |omega_body| history vs RK4,
    L exact, rotational energy bounded O(dt^2)."""
    moments = np.array([1.0, 1.4, 1.8])
    r0 = axis_angle([1.0, 2.0, 0.5], 0.7)
    axes = np.array([quat_rotate(r0, e) for e in np.eye(3)]).T      # columns: principal axes
    tensor = axes @ np.diag(moments) @ axes.T
    wb0 = np.array([0.3, 3.0, 0.4])                                   # near the middle axis: tumbling
    w0 = axes @ wb0
    comps = (tensor[0, 0], tensor[1, 1], tensor[2, 2], tensor[0, 1], tensor[0, 2], tensor[1, 2])
    dt, t_end = 1e-3, 3.0
    deck = (base_deck(stl, box=5.0) + body_line(comps, f"omega {w0[0]!r} {w0[1]!r} {w0[2]!r}") +
            f"timestep {dt}\n" + thermo_block(10) + f"run {int(round(t_end / dt))}\n")
    rows = rows_of(lmp.run_deck(deck, tmp_path))
    h = 1e-4
    ref = euler_rk4(moments, wb0, t_end, h)
    L0 = tensor @ w0
    e0 = 0.5 * wb0 @ (moments * wb0)
    err_w, err_e = 0.0, 0.0
    for r in rows:
        k = int(round(r["time"] / h))
        w = vec(r, "wx", "wy", "wz")
        # body components: project on the rotated principal axes
        q = vec(r, "qw", "qx", "qy", "qz")
        wb = np.array([np.dot(w, quat_rotate(q, axes[:, i])) for i in range(3)])
        err_w = max(err_w, np.abs(wb - ref[k]).max() / np.linalg.norm(wb0))
        err_e = max(err_e, abs(r["ke_rot"] / e0 - 1))
        assert np.allclose(vec(r, "lx", "ly", "lz"), L0, rtol=1e-12, atol=1e-12)
    assert err_w < 1e-6, err_w          # measured 4.5e-8 (the correction terms are small)
    assert err_e < 1e-7, err_e          # measured 4e-9


def test_head_on_collision_restitution(tmp_path, stl):
    """Block (vz = -1) on a free sphere below its bottom face, linear spring-dashpot normal contact:
    e = exp(-pi z / sqrt(1 - z^2)), z = gamma / (2 sqrt(k m*)), m* the reduced mass. Uses the wall
    velocity (a static wall would give another e) and checks momentum conservation."""
    kn, gamma, r, rho = 1e6, 400.0, 0.05, 7850.0
    mp = rho * 4 / 3 * math.pi * r ** 3
    mstar = mp * MASS / (mp + MASS)
    zeta = gamma / (2 * math.sqrt(kn * mstar))
    e_expected = math.exp(-math.pi * zeta / math.sqrt(1 - zeta ** 2))
    zc = r + 0.002 + HALF
    deck = (base_deck(stl, f"move 0 0 {zc!r}", kn=kn, gamma=gamma) +
            f"create_atoms 1 single 0 0 0 units box\nset atom 1 diameter {2 * r!r} density {rho!r}\n"
            "group ball id 1\nfix integ ball nve/sphere\n" +
            body_line(extra="vel 0 0 -1") + "variable pz equal vz[1]\n" +
            "timestep 1e-5\n" + thermo_block(100, "v_pz") + "run 3000\n")
    rows = rows_of(lmp.run_deck(deck, tmp_path))
    last = rows[-1]
    assert last["f"] == 0.0 and max(r["f"] for r in rows) > 0.0
    e = (last["pz"] - last["vz"]) / (-1.0 - 0.0)
    assert e == pytest.approx(e_expected, rel=2e-3), (e, e_expected)
    assert MASS * last["vz"] + mp * last["pz"] == pytest.approx(-MASS, rel=1e-12)
    assert abs(last["vx"]) + abs(last["vy"]) + abs(last["wx"]) + abs(last["wy"]) < 1e-12


def planar_reference(mp, r, kn, gamma, xp, y0, w, t_end, h=1e-6, spin_wall=True):
    """Block (face x' = HALF, rotating in the x-y plane) + sphere, linear spring-dashpot normal
    contact on the overlap with the face plane, damping on the normal velocity relative to the
    face point under the sphere (v_block + w x r, or v_block alone if not spin_wall); fine-step
    velocity Verlet. Returns the final velocities."""
    bx = by = th = vbx = vby = 0.0
    om, px, py, vpx, vpy = w, xp, y0, 0.0, 0.0

    def forces():
        nx, ny = math.cos(th), math.sin(th)
        d = nx * (px - bx) + ny * (py - by) - HALF
        if d >= r:
            return 0.0, 0.0, 0.0
        cx, cy = px - d * nx, py - d * ny
        vwx, vwy = vbx, vby
        if spin_wall:
            vwx, vwy = vwx - om * (cy - by), vwy + om * (cx - bx)
        fn = kn * (r - d) - gamma * ((vpx - vwx) * nx + (vpy - vwy) * ny)
        fx, fy = fn * nx, fn * ny                      # on the sphere
        return fx, fy, (cx - bx) * fy - (cy - by) * fx  # torque on the block is minus the last
    f = forces()
    for _ in range(int(round(t_end / h))):
        for _half in (0, 1):
            vpx += 0.5 * h * f[0] / mp; vpy += 0.5 * h * f[1] / mp
            vbx -= 0.5 * h * f[0] / MASS; vby -= 0.5 * h * f[1] / MASS; om -= 0.5 * h * f[2] / I_CUBE
            if _half == 0:
                px += h * vpx; py += h * vpy; bx += h * vbx; by += h * vby; th += h * om
                f = forces()
    return np.array([vpx, vpy, vbx, vby, om])


def test_spinning_block_hits_sphere(tmp_path, stl):
    """The block spins about z without translating; its face x = +0.225 sweeps onto a free sphere
    at y0 < 0 (normal speed -w y0 from the omega x r part of the wall velocity). The viscous
    contact makes the outcome depend on that wall velocity: compare with a fine-step planar
    reference (agreement 2e-5; a reference with a static wall differs by 4 %) and check that linear
    and angular momentum of block + sphere are conserved."""
    kn, gamma, r, rho, w, y0 = 1e6, 400.0, 0.05, 7850.0, 2.0, -0.15
    mp = rho * 4 / 3 * math.pi * r ** 3
    xp = HALF + r + 0.001
    steps, dt = 2500, 1e-5
    deck = (base_deck(stl, kn=kn, gamma=gamma) +
            f"create_atoms 1 single {xp!r} {y0!r} 0 units box\nset atom 1 diameter {2 * r!r} density {rho!r}\n"
            "group ball id 1\nfix integ ball nve/sphere\n" +
            body_line(extra=f"omega 0 0 {w!r}") +
            "variable px equal x[1]\nvariable py equal y[1]\nvariable pvx equal vx[1]\nvariable pvy equal vy[1]\n"
            f"timestep {dt}\n" + thermo_block(50, "v_px v_py v_pvx v_pvy") + f"run {steps}\n")
    rows = rows_of(lmp.run_deck(deck, tmp_path))
    first, last = rows[0], rows[-1]
    assert max(r["f"] for r in rows) > 0.0 and last["f"] == 0.0

    def momenta(row):
        p = MASS * vec(row, "vx", "vy", "vz") + mp * np.array([row["pvx"], row["pvy"], 0.0])
        lz = (row["lz"] + MASS * (row["x"] * row["vy"] - row["y"] * row["vx"]) +
              mp * (row["px"] * row["pvy"] - row["py"] * row["pvx"]))
        return p, lz
    p0, l0 = momenta(first)
    p1, l1 = momenta(last)
    assert np.allclose(p1, p0, atol=1e-10 * MASS)
    assert l1 == pytest.approx(l0, rel=1e-6)
    got = np.array([last["pvx"], last["pvy"], last["vx"], last["vy"], last["wz"]])
    ref = planar_reference(mp, r, kn, gamma, xp, y0, w, steps * dt)
    static = planar_reference(mp, r, kn, gamma, xp, y0, w, steps * dt, spin_wall=False)
    scale = np.array([ref[0], ref[0], ref[2], ref[2], w])   # natural size of each component
    tol = 1e-4
    assert np.all(np.abs(got - ref) / np.abs(scale) < tol), (got, ref)
    assert np.max(np.abs(static - ref) / np.abs(scale)) > 100 * tol


def drop_deck(stl, steps=7000):
    # plane of fixed spheres (not integrated), tops at z = 0.03
    tilt = axis_angle([1.0, 1.0, 0.0], math.radians(25))
    _, verts = read_stl(stl)
    low = min(quat_rotate(tilt, p)[2] for p in verts.reshape(-1, 3))
    zc = 0.03 + 0.005 - low
    return (base_deck(stl, f"rotate axis 1 1 0 angle 25 move 0 0 {zc!r}") +
            "lattice sc 0.065\nregion plane block -0.4 0.4 -0.4 0.4 -0.001 0.001 units box\n"
            "create_atoms 1 region plane\nset type 1 diameter 0.06 density 2500\n" +
            body_line(extra="vel 0.2 0 -1 omega 0.5 -0.3 1.0 gravity 0 0 -9.81") +
            "timestep 1e-5\n" + thermo_block(100) + f"run {steps}\n")


def test_drop_on_fixed_spheres_conserves_energy(tmp_path, stl):
    """The corner hit turns the fall into tipping; the second corner hit throws the block up."""
    rows = rows_of(lmp.run_deck(drop_deck(stl, 12000), tmp_path))
    first, last = rows[0], rows[-1]
    energy = [r["ke"] + r["pe"] for r in rows]
    assert max(r["f"] for r in rows) > 1e3           # it hit
    assert last["f"] == 0.0 and last["vz"] > 0.3     # and bounced off
    assert abs(last["wx"] - 0.5) + abs(last["wy"] + 0.3) > 0.1  # the corner impact changed the spin
    drift = abs(energy[-1] - energy[0]) / first["ke"]
    assert drift < 1e-4, drift          # brief: 1 %; measured 3e-6


def test_one_and_two_ranks_agree(tmp_path, stl):
    one = rows_of(lmp.run_deck(drop_deck(stl), tmp_path / "np1"))
    two = rows_of(lmp.run_deck(drop_deck(stl), tmp_path / "np2", np=2))
    assert len(one) == len(two)
    for a, b in zip(one, two):
        for key in ("x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz", "fx", "fy", "fz", "ke"):
            assert a[key] == pytest.approx(b[key], rel=1e-9, abs=1e-9 * max(1.0, abs(a[key]))), key


def test_restart_continues_the_motion(tmp_path, stl):
    straight = rows_of(lmp.run_deck(drop_deck(stl, 4000), tmp_path / "a"))
    first = drop_deck(stl, 2000) + "write_restart half.restart\n"
    lmp.run_deck(first, tmp_path / "b")
    lines = drop_deck(stl).splitlines()
    # same deck after read_restart: box, atoms and mesh state come from the file
    keep = [l for l in lines if not l.startswith(("units", "atom_style", "atom_modify", "boundary", "newton",
                                                   "region box", "create_box", "lattice", "region plane",
                                                   "create_atoms", "set type", "run "))]
    second = "read_restart half.restart\n" + "\n".join(keep) + "\nrun 2000\n"
    (tmp_path / "b" / "block.stl").write_text(stl.read_text())
    out = lmp.run_deck(second.replace(str(stl), "block.stl"), tmp_path / "b")
    cont = rows_of(out)
    a, b = straight[-1], cont[-1]
    assert b["step"] == a["step"] == 4000
    for key in ("x", "y", "z", "vx", "vy", "vz", "wx", "wy", "wz", "ke", "qw", "qx"):
        assert b[key] == pytest.approx(a[key], rel=1e-9, abs=1e-12), key


@pytest.mark.parametrize("args,message", [
    ("mesh nosuch mass 1 inertia 1 1 1 0 0 0", "mesh 'nosuch' is not a fix mesh/surface"),
    ("mesh block mass -2 inertia 1 1 1 0 0 0", "mass must be > 0 (got -2)"),
    ("mesh block mass 1 inertia 1 1 3 0 0 0", "violates I1 + I2 >= I3"),
    ("mesh block mass 1 inertia 1 1 1 0 0 0 vel 1 2", "'vel' needs 3 values"),
    ("mesh block mass 1 inertia 1 1 1 0 0 0 spin 3", "unknown keyword 'spin'"),
    ("mesh block inertia 1 1 1 0 0 0", "missing 'mass M'"),
])
def test_bad_arguments_are_named(tmp_path, stl, args, message):
    deck = base_deck(stl) + f"fix rb all wirenet/rigidmesh {args}\n"
    out = lmp.run_deck(deck, tmp_path, check=False)
    errors = lmp.error_lines(out)
    assert errors and message in errors[0], out[-1500:]
