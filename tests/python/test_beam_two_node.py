"""Two-node analytic checks of the beam law of bond_style wirenet (doc/bond_wirenet.md, "beam law").

One bond of length L0 = 0.1 m along x between node 1 (held) and node 2, and one prescribed motion
of node 2 at a time, each against the closed form of a cylinder (A = pi r^2, I = pi r^4/4,
J = pi r^4/2, G = E/(2(1+nu))) to 1e-6 relative:

- axial: node 2 moved by +-delta along the bond: F = E A / L0 (L - L0), tension and compression;
- shear: node 2 moved by delta across the bond, no rotation: shear force Ks delta and end moments
  Ks L0 delta / 2, with Ks = 12 f E I / L0^3 (`shear eb`) or G A / L0 (`shear pb`);
- bending: node 2 rotated by theta about z or y (fix move rotate about its own centre): end
  moments 4 f E I theta / L0 (rotated end) and 2 f E I theta / L0 (other end), shear
  6 f E I theta / L0^2 (Euler-Bernoulli, `shear eb`); with `shear pb` the moments are
  (Kb + Cs) theta and (Cs - Kb) theta, Kb = f E I / L0, Cs = G A L0 / 4;
- twist: node 2 rotated by phi about the bond axis: torque f_t G J phi / L0, f_t = `twist`, or
  `bending` when `twist` is not given.

The law is exact in pure stretch, pure end rotation and pure twist (the rotation vectors are
computed exactly); the transverse displacement of the shear check is 1e-5 L0, where the law's
geometric terms are below 1e-7 of the result.
"""

import math

import numpy as np
import pytest

import lmp

D, E, NU, L0 = 0.01, 6e10, 0.3, 0.1
R = D / 2
A = math.pi * R**2
I = math.pi * R**4 / 4
J = math.pi * R**4 / 2
G = E / (2 * (1 + NU))
DT = 1e-6
RTOL = 1e-6
QUANTITIES = ("F1x", "F1y", "F1z", "F2x", "F2y", "F2z", "T1x", "T1y", "T1z", "T2x", "T2y", "T2z")


def run_pair(tmp_path, coeff, motion):
    """Run `run 0` (initial state) then `motion` (deck lines); the last thermo row as a dict with
    forces F1*, F2*, torques T1*, T2*, node 2's position, and the bond's tension, shear and moment
    from compute wirenet/local."""
    atoms = [(1, 1, 0.0, 0.0, 0.0, D, 7850.0, 1), (2, 2, L0, 0.0, 0.0, D, 7850.0, 1)]
    lmp.write_data(tmp_path / "pair.data", atoms, [(1, 1, 1, 2)], natom_types=2)
    vars_ = "\n".join(f"variable {q} equal {'f' if q[0] == 'F' else 'tq'}{q[2]}[{q[1]}]" for q in QUANTITIES)
    deck = lmp.PREAMBLE + f"""read_data pair.data
bond_style wirenet
bond_coeff 1 beam {coeff}
group n2 id 2
compute wl all wirenet/local
compute T all reduce sum c_wl[6]
compute S all reduce sum c_wl[11]
compute M all reduce sum c_wl[12]
{vars_}
variable x2 equal x[2]
variable y2 equal y[2]
variable z2 equal z[2]
thermo_style custom step {' '.join('v_' + q for q in QUANTITIES)} v_x2 v_y2 v_z2 c_T c_S c_M
thermo_modify format float %.17g
timestep {DT!r}
run 0
{motion}
"""
    rows = lmp.thermo_rows(lmp.run_deck(deck, tmp_path))
    row = rows[-1]
    return {k.replace("v_", "").replace("c_", ""): v for k, v in row.items()}


def close(got, want, what, scale=None):
    """|got - want| <= RTOL * scale (scale = |want| by default) with a readable message."""
    scale = abs(want) if scale is None else scale
    assert abs(got - want) <= RTOL * scale, f"{what}: got {got!r}, closed form {want!r} (rel. error {abs(got - want) / scale:.2e})"


def rotate_node2(axis, angle, steps=100):
    """Deck lines rotating node 2 about its own centre by `angle` (rad) in `steps` steps."""
    period = 2 * math.pi * steps * DT / angle
    return f"fix rot n2 move rotate {L0!r} 0 0 {axis[0]} {axis[1]} {axis[2]} {period!r}\nrun {steps}"


@pytest.mark.parametrize("delta", [2e-5, -2e-5], ids=["tension", "compression"])
def test_axial_stiffness(tmp_path, delta):
    row = run_pair(tmp_path, f"diameter {D} E {E} nu {NU} bending 0.05", f"displace_atoms n2 move {delta!r} 0 0 units box\nrun 0")
    L = row["x2"]
    assert abs(L - (L0 + delta)) < 1e-15
    want = E * A / L0 * (L - L0)  # tension > 0
    close(row["T"], want, "tension column (EA/L0 (L - L0))")
    close(row["F1x"], want, "force on node 1 along the bond (EA/L0 (L - L0), towards node 2 in tension)")
    close(row["F2x"], -want, "force on node 2 along the bond")
    # nothing else: no shear, no moment
    scale = abs(want)
    for q in ("F1y", "F1z", "F2y", "F2z", "T1x", "T1y", "T1z", "T2x", "T2y", "T2z", "S"):
        assert abs(row[q]) <= 1e-12 * scale, f"{q} = {row[q]!r} in pure stretch"


@pytest.mark.parametrize("shear,bending", [("eb", 1.0), ("eb", 0.05), ("pb", 0.05)])
def test_shear_stiffness(tmp_path, shear, bending):
    delta = 1e-5 * L0
    row = run_pair(tmp_path, f"diameter {D} E {E} nu {NU} bending {bending} shear {shear}",
                   f"displace_atoms n2 move 0 {delta!r} 0 units box\nrun 0")
    Ks = 12 * bending * E * I / L0**3 if shear == "eb" else G * A / L0
    V, M = Ks * delta, Ks * L0 * delta / 2
    close(row["F1y"], V, f"shear force on node 1 (Ks delta, Ks = {'12 f EI/L0^3' if shear == 'eb' else 'GA/L0'})")
    close(row["F2y"], -V, "shear force on node 2")
    close(row["S"], V, "shear column")
    # no end rotation: equal end moments Ks L0 delta / 2 (6 f EI delta / L0^2 for eb), same sign
    close(row["T1z"], M, "moment on node 1 (Ks L0 delta / 2)")
    close(row["T2z"], M, "moment on node 2 (Ks L0 delta / 2)")
    close(row["M"], M, "moment column")
    for q in ("F1z", "F2z", "T1x", "T1y", "T2x", "T2y"):
        assert abs(row[q]) <= 1e-12 * max(V, M), f"{q} = {row[q]!r} in a y shear"


@pytest.mark.parametrize("axis", [(0, 0, 1), (0, 1, 0)], ids=["about_z", "about_y"])
@pytest.mark.parametrize("bending", [1.0, 0.05])
def test_bending_euler_bernoulli(tmp_path, axis, bending):
    theta = 2e-3
    row = run_pair(tmp_path, f"diameter {D} E {E} nu {NU} bending {bending}", rotate_node2(axis, theta))
    assert max(abs(row["x2"] - L0), abs(row["y2"]), abs(row["z2"])) < 1e-16, "node 2 left its place"
    a = np.array(axis, float)
    EI = bending * E * I
    want_T2 = -4 * EI * theta / L0 * a
    want_T1 = -2 * EI * theta / L0 * a
    # the shear balances the moments: F2 = 6 EI theta / L0^2 (a x e_x)
    want_F2 = 6 * EI * theta / L0**2 * np.cross(a, [1.0, 0.0, 0.0])
    k = int(np.argmax(np.abs(a)))
    s = int(np.argmax(np.abs(want_F2)))
    xyz = "xyz"
    close(row[f"T2{xyz[k]}"], want_T2[k], f"moment on the rotated node (4 f EI theta / L0, f = {bending})")
    close(row[f"T1{xyz[k]}"], want_T1[k], f"moment on the held node (2 f EI theta / L0, f = {bending})")
    close(row[f"F2{xyz[s]}"], want_F2[s], "shear force on the rotated node (6 f EI theta / L0^2)")
    close(row[f"F1{xyz[s]}"], -want_F2[s], "shear force on the held node")
    close(row["M"], 4 * EI * theta / L0, "moment column (the larger end moment)")
    close(row["S"], 6 * EI * theta / L0**2, "shear column")
    # no axial force, no twist
    scale = 4 * EI * theta / L0
    for q in ("F1x", "F2x", "T1x", "T2x", "T"):
        assert abs(row[q]) <= 1e-12 * scale, f"{q} = {row[q]!r} in pure bending"


def test_bending_parallel_bond(tmp_path):
    theta, f = 2e-3, 0.05
    row = run_pair(tmp_path, f"diameter {D} E {E} nu {NU} bending {f} shear pb", rotate_node2((0, 0, 1), theta))
    Kb, Cs = f * E * I / L0, G * A * L0 / 4
    close(row["T2z"], -(Kb + Cs) * theta, "moment on the rotated node ((Kb + Cs) theta)")
    close(row["T1z"], -(Cs - Kb) * theta, "moment on the held node ((Cs - Kb) theta)")
    close(row["F2y"], 2 * Cs * theta / L0, "shear force on the rotated node (2 Cs theta / L0)")


@pytest.mark.parametrize("fractions", [("0.05", None), ("0.05", "0.3"), ("1.0", "0.0")],
                         ids=["twist_default", "twist_0.3", "twist_0"])
def test_twist_torque(tmp_path, fractions):
    bending, twist = fractions
    coeff = f"diameter {D} E {E} nu {NU} bending {bending}" + (f" twist {twist}" if twist else "")
    phi = 3e-3
    row = run_pair(tmp_path, coeff, rotate_node2((1, 0, 0), phi))
    ft = float(twist if twist is not None else bending)
    want = ft * G * J * phi / L0
    scale = max(want, G * J * phi / L0)
    close(row["T2x"], -want, f"torque on the twisted node (f_t GJ phi / L0, f_t = {ft})", scale)
    close(row["T1x"], want, "torque on the held node", scale)
    for q in ("F1x", "F1y", "F1z", "T1y", "T1z", "T2y", "T2z", "S", "M"):
        assert abs(row[q]) <= 1e-12 * scale, f"{q} = {row[q]!r} in pure twist"
