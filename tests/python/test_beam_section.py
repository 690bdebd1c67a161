"""General beam sections (`bond_coeff T beam section A IY IZ J orient X Y Z E ... nu ...`,
doc/bond_wirenet.md, "beam law"): a post's steel section with two principal axes.

The section's principal axis y is `orient` projected normal to the bond, z = e x y (e along the
bond); IY is the second moment about y (it resists rotation about y, i.e. deflection along z),
IZ about z. Every expectation below is the closed form of that section, written with the tensor
I = IY y y^T + IZ z z^T:

- two nodes (the set-up of test_beam_two_node: L0 = 0.1 m along x, node 1 held, node 2 moved):
  end rotation theta a: moments -(4 f E / L0) I a theta (rotated end) and -(2 f E / L0) I a theta,
  shear (6 f E / L0^2) (I a theta) x e; transverse offset delta u: end moments
  (6 f E / L0^2) I (e x u) delta, shear (12 f E / L0^3) (I (e x u)) x e delta; axial E A / L0;
  twist G J / L0; for orient along y, then turned by 30 degrees about the bond, then oblique to it;
- a vertical post (4 bonds, 1 m, clamped at the foot, damped to rest with local damping, which
  does not change the rest state): tip deflection F L^3 / (3 E IZ) for a load along y and
  F L^3 / (3 E IY) along z (Euler-Bernoulli elements are exact for a tip load), F L / (E A)
  axially, the foot's reaction torque G J phi / L for a tip turned by phi, and the coupled
  deflection of a section turned by 30 degrees.
"""

import math

import numpy as np
import pytest

import lmp
from test_beam_two_node import DT, L0, rotate_node2, run_pair
from test_wire_errors import check_error

E, NU = 6e10, 0.3
G = E / (2 * (1 + NU))
A, IY, IZ, J = 6e-5, 8e-10, 2e-10, 3e-10  # IY / IZ = 4
RTOL = 1e-6
X = np.array([1.0, 0.0, 0.0])  # the two-node bond's direction
VECS = ("F1", "F2", "T1", "T2")


def section(orient=(0, 1, 0), a=A, iy=IY, iz=IZ, j=J, extra=""):
    o = " ".join(repr(float(c)) for c in orient)
    return f"section {a!r} {iy!r} {iz!r} {j!r} orient {o} E {E!r} nu {NU!r}{extra}"


def inertia(orient, e=X, iy=IY, iz=IZ):
    """I = IY y y^T + IZ z z^T with y = orient projected normal to e, z = e x y."""
    y = np.array(orient, float)
    y = y - y.dot(e) * e
    y /= np.linalg.norm(y)
    z = np.cross(e, y)
    return iy * np.outer(y, y) + iz * np.outer(z, z)


def vectors(row):
    return {v: np.array([row[f"{v}{c}"] for c in "xyz"]) for v in VECS}


def check(row, want, what, scale=None):
    """Every component of the forces (torques) within RTOL of the largest force (torque)."""
    got = vectors(row)
    for v in VECS:
        scale = max(np.abs(want[w]).max() for w in VECS if w[0] == v[0])
        err = np.abs(got[v] - want[v]).max()
        assert err <= RTOL * scale, \
            f"{what}: {v} = {got[v]!r}, closed form {want[v]!r} (error {err / scale:.2e} of the largest)"


def rotation_expected(orient, axis, theta, f=1.0):
    a = np.array(axis, float)
    Ia = f * inertia(orient) @ a * theta
    F2 = 6 * E / L0**2 * np.cross(Ia, X)
    return {"T2": -4 * E / L0 * Ia, "T1": -2 * E / L0 * Ia, "F2": F2, "F1": -F2}, 4 * E / L0 * np.linalg.norm(Ia)


def offset_expected(orient, u, delta, f=1.0):
    Iu = f * inertia(orient) @ np.cross(X, np.array(u, float)) * delta
    F1 = 12 * E / L0**3 * np.cross(Iu, X)
    M = 6 * E / L0**2 * Iu
    return {"T1": M, "T2": M, "F1": F1, "F2": -F1}, np.linalg.norm(M)


# ---- two nodes --------------------------------------------------------------------------------

ORIENTS = {"y": (0, 1, 0), "turned_30deg": (0, math.cos(math.pi / 6), math.sin(math.pi / 6)),
           "oblique_to_the_bond": (0.7, 1.0, 0.0)}


@pytest.mark.parametrize("axis", [(0, 0, 1), (0, 1, 0), (0, 0.6, 0.8)], ids=["about_z", "about_y", "about_yz"])
@pytest.mark.parametrize("orient", sorted(ORIENTS))
def test_end_rotation(tmp_path, orient, axis):
    # small: turning about an axis that is not along the section's normal adds a twist of second
    # order in theta (doc/bond_wirenet.md, "Large rotations": the exact gradient of the section's
    # unequal bending energies), 3e-6 of the moment at 1e-5 rad, 6e-7 at 2e-6 rad
    theta = 2e-6
    row = run_pair(tmp_path, section(ORIENTS[orient]), rotate_node2(axis, theta))
    want, scale = rotation_expected(ORIENTS[orient], axis, theta)
    check(row, want, f"node 2 turned by {theta} about {axis}, orient {orient}", scale)
    assert row["M"] == pytest.approx(scale, rel=RTOL), "moment column (the larger end moment)"
    assert row["S"] == pytest.approx(np.linalg.norm(want["F2"]), rel=RTOL), "shear column"
    assert abs(row["T"]) <= 1e-9 * scale


@pytest.mark.parametrize("u", [(0, 1, 0), (0, 0, 1)], ids=["along_y", "along_z"])
@pytest.mark.parametrize("orient", sorted(ORIENTS))
def test_transverse_offset(tmp_path, orient, u):
    # the offset also stretches the bond (delta^2 / 2 L0) and tilts the chord by delta / L0: the
    # forces along the bond are left out (as in test_beam_two_node), the rest is first order
    delta = 1e-7 * L0
    row = run_pair(tmp_path, section(ORIENTS[orient]),
                   f"displace_atoms n2 move {u[0] * delta!r} {u[1] * delta!r} {u[2] * delta!r} units box\nrun 0")
    want, scale = offset_expected(ORIENTS[orient], u, delta)
    row = dict(row, F1x=0.0, F2x=0.0)
    check(row, want, f"node 2 moved by {delta} along {u}, orient {orient}", scale)


def test_the_two_axes_differ_as_iy_over_iz(tmp_path):
    """Orient along y: a rotation about y meets IY, about z IZ: moments in the ratio IY / IZ."""
    (tmp_path / "y").mkdir()
    (tmp_path / "z").mkdir()
    about_y = run_pair(tmp_path / "y", section(), rotate_node2((0, 1, 0), 2e-3))
    about_z = run_pair(tmp_path / "z", section(), rotate_node2((0, 0, 1), 2e-3))
    assert about_y["T2y"] / about_z["T2z"] == pytest.approx(IY / IZ, rel=RTOL)
    assert about_y["T2y"] == pytest.approx(-4 * E * IY * 2e-3 / L0, rel=RTOL)


def test_axial_and_twist(tmp_path):
    delta, phi = 2e-5, 3e-3
    for d in ("axial", "twist"):
        (tmp_path / d).mkdir()
    row = run_pair(tmp_path / "axial", section(), f"displace_atoms n2 move {delta!r} 0 0 units box\nrun 0")
    assert row["T"] == pytest.approx(E * A / L0 * delta, rel=RTOL), "axial force E A / L0 delta"
    assert row["F1x"] == pytest.approx(E * A / L0 * delta, rel=RTOL)
    row = run_pair(tmp_path / "twist", section(extra=" bending 0.05 twist 0.3"), rotate_node2((1, 0, 0), phi))
    assert row["T2x"] == pytest.approx(-0.3 * G * J * phi / L0, rel=RTOL), "torque f_t G J phi / L0"
    assert row["T1x"] == pytest.approx(0.3 * G * J * phi / L0, rel=RTOL)


@pytest.mark.parametrize("shear", ["eb", "pb"])
def test_bending_fraction_and_shear_model(tmp_path, shear):
    """`bending f` scales both axes; `shear pb` keeps the isotropic parallel-bond coupling
    Cs = G A L0 / 4 with Kb = f E I per axis: moments (Kb + Cs) theta and (Cs - Kb) theta."""
    f, theta = 0.05, 2e-6  # small: the second-order twist of test_end_rotation
    orient = ORIENTS["turned_30deg"]
    row = run_pair(tmp_path, section(orient, extra=f" bending {f} shear {shear}"), rotate_node2((0, 0, 1), theta))
    if shear == "eb":
        want, scale = rotation_expected(orient, (0, 0, 1), theta, f)
    else:
        Kb = f * E / L0 * inertia(orient) @ np.array([0, 0, theta])
        Cs = G * A * L0 / 4 * np.array([0, 0, theta])
        F2 = 2 / L0 * np.cross(Cs, X)
        want, scale = {"T2": -(Kb + Cs), "T1": -(Cs - Kb), "F2": F2, "F1": -F2}, np.linalg.norm(Kb + Cs)
    check(row, want, f"bending {f}, shear {shear}", scale)


def test_circular_section_is_the_diameter(tmp_path):
    """A = pi r^2, IY = IZ = pi r^4 / 4, J = 2 IY through `section` gives the `diameter` bond.
    orient is the reference normal a circular bond picks, e x z = -y: the twist measure depends on
    it at second order in the bending angles (a turn of 3e-3 rad here)."""
    d = 0.01
    r = d / 2
    circle = section((0, -1, 0), math.pi * r**2, math.pi * r**4 / 4, math.pi * r**4 / 4, math.pi * r**4 / 2)
    motion = ("displace_atoms n2 move 3e-6 -2e-6 1e-6 units box\n" + rotate_node2((0.3, 0.5, 0.8), 3e-3))
    (tmp_path / "section").mkdir()
    (tmp_path / "diameter").mkdir()
    a = run_pair(tmp_path / "section", circle, motion)
    b = run_pair(tmp_path / "diameter", f"diameter {d} E {E!r} nu {NU!r}", motion)
    scale = max(abs(v) for k, v in b.items() if k[0] in "FT" and len(k) == 3)
    for k in b:
        if k != "Step":
            assert abs(a[k] - b[k]) <= 1e-12 * max(scale, abs(b[k])), f"{k}: section {a[k]!r}, diameter {b[k]!r}"


def test_restart_keeps_the_section(tmp_path):
    """write_restart, read_restart without bond_coeff: the same moments as the uninterrupted run."""
    orient = ORIENTS["turned_30deg"]
    (tmp_path / "ref").mkdir()
    ref = run_pair(tmp_path / "ref", section(orient), rotate_node2((0, 0, 1), 2e-3))
    # first process: the bond is initialised by run 0 and written; the second turns node 2
    wd = tmp_path / "restart"
    atoms = [(1, 1, 0.0, 0.0, 0.0, 0.01, 7850.0, 1), (2, 2, L0, 0.0, 0.0, 0.01, 7850.0, 1)]
    wd.mkdir()
    lmp.write_data(wd / "pair.data", atoms, [(1, 1, 1, 2)], natom_types=2)
    lmp.run_deck(lmp.PREAMBLE + f"read_data pair.data\nbond_style wirenet\nbond_coeff 1 beam {section(orient)}\n"
                 "group n2 id 2\nrun 0\nwrite_restart pair.restart\n", wd, name="in.first")
    out = lmp.run_deck(f"read_restart pair.restart\natom_modify sort 0 0\ntimestep {DT!r}\n"
                       "variable T2y equal tqy[2]\nvariable T2z equal tqz[2]\n"
                       "thermo_style custom step v_T2y v_T2z\nthermo_modify format float %.17g\n"
                       + rotate_node2((0, 0, 1), 2e-3) + "\n", wd, name="in.second")
    assert "section A = 6e-05 m^2, Iy = 8e-10 m^4, Iz = 2e-10 m^4, J = 3e-10 m^4, orient (0, 0.866025, 0.5)" in out
    row = lmp.thermo_rows(out)[-1]
    assert row["T2y"] == pytest.approx(ref["T2y"], rel=1e-12, abs=1e-12 * abs(ref["T2z"]))
    assert row["T2z"] == pytest.approx(ref["T2z"], rel=1e-12)
    assert abs(row["T2y"]) > 0.1 * abs(row["T2z"])  # the turned section couples the axes


# ---- a post: cantilever of four bonds -----------------------------------------------------------

# HEA 100-like steel section, vertical post of 1 m in 4 bonds, foot clamped (node 1 not integrated)
POST = dict(L=1.0, n=4, E=2.1e11, nu=0.3, A=2.12e-3, IY=3.49e-6, IZ=1.34e-6, J=5.26e-8, node_d=0.2, rho=7850.0)
POST_DT = 4e-5
POST_STEPS = 40000


def viscous_damping():
    """Viscous damping of the nodes' translation, critical for the first bending mode about the
    weaker axis (tip stiffness 3 E IZ / L^3 over a quarter of the mass): every mode decays at
    omega_1. (Local damping creeps here: the fast modes flip the velocity signs it acts on.)"""
    p = POST
    m = p["rho"] * math.pi * p["node_d"] ** 3 / 6
    w1 = math.sqrt(3 * p["E"] * p["IZ"] / p["L"] ** 3 / (0.25 * p["n"] * m))
    return f"fix damp free viscous {2 * w1 * m!r}"


# twist alone is a rotation of the nodes, which viscous damping does not touch: local damping
LOCAL_DAMPING = "fix damp free wirenet/damping 0.8 tally no"


def post_deck(orient, tip_lines, group_free="free subtract all root", damping=None):
    p = POST
    o = " ".join(repr(float(c)) for c in orient)
    n = p["n"]
    return lmp.PREAMBLE + f"""read_data post.data
bond_style wirenet
bond_coeff 1 beam section {p['A']!r} {p['IY']!r} {p['IZ']!r} {p['J']!r} orient {o} E {p['E']!r} nu {p['nu']!r}
group root id 1
group tip id {n + 1}
group {group_free}
fix integrate free nve/sphere
{tip_lines}
{damping or viscous_damping()}
variable tx equal x[{n + 1}]
variable ty equal y[{n + 1}]
variable tz equal z[{n + 1}]
variable q1x equal tqx[1]
variable q1y equal tqy[1]
variable q1z equal tqz[1]
thermo_style custom step v_tx v_ty v_tz v_q1x v_q1y v_q1z
thermo_modify format float %.17g
thermo 5000
timestep {POST_DT!r}
"""


def run_post(tmp_path, orient, tip_lines, runs, group_free="free subtract all root", damping=None,
             rest=("tx", "ty", "tz")):
    p = POST
    n = p["n"]
    atoms = [(k + 1, 1, 0.0, 0.0, p["L"] * k / n, p["node_d"], p["rho"], 1) for k in range(n + 1)]
    bonds = [(k + 1, 1, k + 1, k + 2) for k in range(n)]
    tmp_path.mkdir(parents=True, exist_ok=True)
    lmp.write_data(tmp_path / "post.data", atoms, bonds, box=((-1, 1), (-1, 1), (-0.5, 1.5)))
    out = lmp.run_deck(post_deck(orient, tip_lines, group_free, damping) + runs, tmp_path)
    rows = lmp.thermo_rows(out)
    # at rest: the quantities asserted change by less than 1e-8 of their scale over the last
    # 5000 steps
    a, b = rows[-2], rows[-1]
    ref = {"tx": 0.0, "ty": 0.0, "tz": p["L"]}
    scale = max(abs(b[k] - ref.get(k, 0.0)) for k in rest)
    for k in rest:
        assert abs(a[k] - b[k]) <= 1e-8 * scale, f"not at rest: {k} {a[k]!r} then {b[k]!r}"
    return b


@pytest.mark.parametrize("axis", ["x", "y"])
def test_post_tip_load_along_each_axis(tmp_path, axis):
    """orient along x: y (IY) = x, z (IZ) = e x y = y. A load along x bends about the section's
    z axis (IZ), along y about its y axis (IY)."""
    p = POST
    F = 8.0
    load = f"{F!r} 0 0" if axis == "x" else f"0 {F!r} 0"
    row = run_post(tmp_path, (1, 0, 0), f"fix load tip addforce {load}", f"run {POST_STEPS}\n")
    inertia_ = p["IZ"] if axis == "x" else p["IY"]
    want = F * p["L"] ** 3 / (3 * p["E"] * inertia_)
    got = row["tx"] if axis == "x" else row["ty"]
    assert got == pytest.approx(want, rel=RTOL), \
        f"tip deflection along {axis}: {got!r} m, F L^3/(3 E I) = {want!r} m (I = {'IZ' if axis == 'x' else 'IY'})"
    other = row["ty"] if axis == "x" else row["tx"]
    assert abs(other) <= 1e-9 * want
    assert abs(row["tz"] - p["L"]) <= 1e-3 * want  # second order only


def test_post_axial(tmp_path):
    p = POST
    F = 2e4
    row = run_post(tmp_path, (1, 0, 0), f"fix load tip addforce 0 0 {-F!r}", f"run {POST_STEPS}\n")
    want = -F * p["L"] / (p["E"] * p["A"])
    assert row["tz"] - p["L"] == pytest.approx(want, rel=RTOL), "axial shortening F L / (E A)"


def test_post_torsion(tmp_path):
    """The tip turned by phi about the post's axis and held: the foot's reaction torque is
    G J phi / L (the turn T L / (G J) of a tip torque T)."""
    p = POST
    phi, nrot = 1e-4, 100
    period = 2 * math.pi * nrot * POST_DT / phi
    tip = f"{0.0!r} {0.0!r} {p['L']!r}"
    runs = (f"fix turn tip move rotate {tip} 0 0 1 {period!r}\nrun {nrot}\nunfix turn\n"
            # held: a rotation of period 1e30 s sets the tip's angular velocity to ~0
            f"fix hold tip move rotate {tip} 0 0 1 1e30\nrun {POST_STEPS}\n")
    row = run_post(tmp_path, (1, 0, 0), "", runs, group_free="free subtract all root tip", damping=LOCAL_DAMPING,
                   rest=("q1x", "q1y", "q1z"))
    G_ = p["E"] / (2 * (1 + p["nu"]))
    want = G_ * p["J"] * phi / p["L"]
    assert row["q1z"] == pytest.approx(want, rel=RTOL), f"foot torque {row['q1z']!r}, G J phi / L = {want!r}"
    assert max(abs(row["q1x"]), abs(row["q1y"])) <= 1e-6 * want


def test_post_turned_section_deflects_obliquely(tmp_path):
    """orient turned by 30 degrees about the post: y = (cos a, sin a, 0), z = (-sin a, cos a, 0).
    A load F along x deflects the tip by L^3/(3E) F (cos a / IZ y - sin a / IY z)."""
    p = POST
    F, a = 8.0, math.pi / 6
    row = run_post(tmp_path, (math.cos(a), math.sin(a), 0), f"fix load tip addforce {F!r} 0 0", f"run {POST_STEPS}\n")
    c = p["L"] ** 3 / (3 * p["E"]) * F
    y = np.array([math.cos(a), math.sin(a)])
    z = np.array([-math.sin(a), math.cos(a)])
    want = c * (math.cos(a) / p["IZ"] * y - math.sin(a) / p["IY"] * z)
    got = np.array([row["tx"], row["ty"]])
    assert np.abs(got - want).max() <= RTOL * np.abs(want).max(), f"tip deflection {got!r}, closed form {want!r}"
    assert abs(want[1]) > 0.2 * abs(want[0])  # the coupling is not small


# ---- bad input ---------------------------------------------------------------------------------

GOOD = section()
BAD_COEFFS = {
    "A zero": (section(a=0), "beam section A must be a finite number > 0 (got 0)"),
    "IY negative": (section(iy=-1e-9), "beam section IY must be a finite number > 0 (got -1e-09)"),
    "IZ nan": (f"section {A} {IY} nan {J} orient 0 1 0 E {E} nu {NU}", "beam section IZ must be a finite number > 0 (got nan)"),
    "J inf": (f"section {A} {IY} {IZ} inf orient 0 1 0 E {E} nu {NU}", "beam section J must be a finite number > 0 (got inf)"),
    "J missing": (f"section {A} {IY} {IZ} orient 0 1 0 E {E} nu {NU}", "beam section J must be a number (got 'orient')"),
    "orient missing": (f"section {A} {IY} {IZ} {J} E {E} nu {NU}", "beam section: expected 'orient' after A IY IZ J, got 'E'"),
    "orient zero": (section((0, 0, 0)), "beam orient must be a non-zero vector of finite length (got 0 0 0)"),
    "orient inf": (f"section {A} {IY} {IZ} {J} orient 0 inf 0 E {E} nu {NU}", "beam orient Y must be a finite number (got inf)"),
    "orient short": (f"section {A} {IY} {IZ} {J} orient 0 1 E {E} nu {NU}", "beam orient Z must be a number (got 'E')"),
    "orient overflow": (f"section {A} {IY} {IZ} {J} orient 1e200 1e200 0 E {E} nu {NU}",
                        "beam orient must be a non-zero vector of finite length"),
    "neither diameter nor section": (f"radius 0.01 E {E} nu {NU}", "beam: expected 'diameter' or 'section', got 'radius'"),
    "strength with section": (f"{GOOD} strength 8e8 4e8", "beam strength needs a circular section (diameter)"),
    "damping with section": (f"{GOOD} damping 0.05", "beam damping is not available with section"),
    "E missing": (f"section {A} {IY} {IZ} {J} orient 0 1 0 nu {NU}", "beam: expected 'E', got 'nu'"),
}


@pytest.mark.parametrize("case", sorted(BAD_COEFFS))
def test_bad_section_coeff(tmp_path, case):
    args, phrase = BAD_COEFFS[case]
    atoms = [(1, 1, 0.0, 0.0, 0.0, 0.01, 7850.0, 1), (2, 1, 0.1, 0.0, 0.0, 0.01, 7850.0, 1)]
    lmp.write_data(tmp_path / "pair.data", atoms, [(1, 1, 1, 2)])
    deck = lmp.PREAMBLE + f"read_data pair.data\nbond_style wirenet\nbond_coeff 1 beam {args}\nrun 0\n"
    rc, out = lmp.run_deck_rc(deck, tmp_path)
    line = check_error(rc, out, phrase)
    assert "bond_coeff 1:" in line


@pytest.mark.parametrize("np_", [1, 2])
def test_orient_along_the_bond_is_an_error(tmp_path, np_):
    """orient parallel to a bond leaves its principal axes undefined: one error naming the bond."""
    atoms = [(1, 1, -0.05, 0.0, 0.0, 0.01, 7850.0, 1), (2, 1, 0.05, 0.0, 0.0, 0.01, 7850.0, 1)]
    lmp.write_data(tmp_path / "pair.data", atoms, [(1, 1, 1, 2)])
    deck = lmp.PREAMBLE + f"read_data pair.data\nbond_style wirenet\nbond_coeff 1 beam {section((2, 0, 0))}\nrun 0\n"
    rc, out = lmp.run_deck_rc(deck, tmp_path, np=np_)
    assert rc != 0 and "Segmentation fault" not in out
    errors = lmp.error_lines(out)
    assert errors and all("bond 1-2 (type 1): beam orient (2, 0, 0) is parallel to the bond" in e for e in errors), out[-2000:]
