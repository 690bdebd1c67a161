"""Beam law: objectivity under large rigid rotations, and pure twist."""

import math

import numpy as np
import pytest

import lmp

D, E, NU = 0.01, 1e10, 0.288
G = E / (2 * (1 + NU))
J = math.pi * D**4 / 32
DT = 1e-6


def rotation(axis, angle):
    u = np.asarray(axis, float)
    u /= np.linalg.norm(u)
    K = np.array([[0, -u[2], u[1]], [u[2], 0, -u[0]], [-u[1], u[0], 0]])
    return np.eye(3) + math.sin(angle) * K + (1 - math.cos(angle)) * K @ K


def pair_deck(prebend):
    """Two nodes with a beam bond; optionally bent, twisted and stretched before the rotations."""
    lines = [lmp.PREAMBLE, "read_data pair.data",
             "bond_style wirenet",
             f"bond_coeff 1 beam diameter {D} E {E} nu {NU} bending 0.7 shear eb",
             "timestep 1e-6",
             "variable F1x equal fx[1]\nvariable F1y equal fy[1]\nvariable F1z equal fz[1]",
             "variable T1x equal tqx[1]\nvariable T1y equal tqy[1]\nvariable T1z equal tqz[1]",
             "variable T2x equal tqx[2]\nvariable T2y equal tqy[2]\nvariable T2z equal tqz[2]",
             "thermo_style custom step v_F1x v_F1y v_F1z v_T1x v_T1y v_T1z v_T2x v_T2y v_T2z",
             "thermo_modify format float %.17g",
             "group two id 2",
             "run 0"]
    if prebend:
        # bend node 2 about y and twist it about x (rotations about its own centre), then stretch
        lines += ["fix b two move rotate 0.1 0 0 0 1 0 1e-3\nrun 25\nunfix b",
                  "fix t two move rotate 0.1 0 0 1 0 0 2e-3\nrun 20\nunfix t",
                  "displace_atoms two move 1e-5 0 0"]
    return "\n".join(lines) + "\n"


def write_pair(path):
    atoms = [(1, 1, 0.0, 0.0, 0.0, D, 7850.0, 1), (2, 1, 0.1, 0.0, 0.0, D, 7850.0, 1)]
    lmp.write_data(path, atoms, [(1, 1, 1, 2)])


def state(row):
    v = [row[k] for k in ("F1x", "F1y", "F1z", "T1x", "T1y", "T1z", "T2x", "T2y", "T2z")]
    return np.array(v).reshape(3, 3)


@pytest.mark.parametrize("prebend", [False, True], ids=["unloaded", "prebent"])
@pytest.mark.parametrize("axis", [(1, 0, 0), (0, 1, 0), (0, 0, 1), (1, 1, 1), (0.3, -0.5, 0.8)])
def test_rigid_rotation_creates_no_force(tmp_path, prebend, axis):
    write_pair(tmp_path / "pair.data")
    steps_90 = 500
    period = 4 * steps_90 * DT
    deck = pair_deck(prebend)
    deck += "run 0\n"  # the reference state, after the node 2 rotations stopped
    # rigid rotation of the pair (positions and node orientations) about an axis through the midpoint
    deck += f"fix rr all move rotate 0.05 0 0 {axis[0]} {axis[1]} {axis[2]} {period!r}\n"
    deck += f"run {steps_90}\nrun {steps_90}\nrun {2 * steps_90}\n"
    out = lmp.run_deck(deck, tmp_path)
    rows = lmp.thermo_rows(out)
    by_step = {}
    for r in rows:
        by_step[int(r["Step"])] = r
    steps = sorted(by_step)
    s0 = steps[-1] - 4 * steps_90
    ref = state(by_step[s0])
    scale = np.abs(ref).max() if prebend else 1.0
    if prebend:
        assert scale > 1e-3  # the pre-bent pair carries real forces and moments
    for quarter, angle in ((1, 0.5 * math.pi), (2, math.pi), (4, 2 * math.pi)):
        got = state(by_step[s0 + quarter * steps_90])
        want = (rotation(axis, angle) @ ref.T).T
        assert np.abs(got - want).max() <= 1e-9 * scale, f"rotation {math.degrees(angle):.0f} deg"


def test_pure_twist_matches_GJ(tmp_path):
    """Chain of 5 beam bonds twisted by a linear rotation field phi(x) = phi_tip x / L (the static
    solution of uniform torsion): the reaction torque at the root is GJ phi_tip / L."""
    n, L = 5, 2.0
    atoms = [(k + 1, 1, L * k / n, 0.0, 0.0, D, 7850.0, 1) for k in range(n + 1)]
    bonds = [(k + 1, 1, k + 1, k + 2) for k in range(n)]
    lmp.write_data(tmp_path / "chain.data", atoms, bonds, box=((-1, 3), (-1, 1), (-1, 1)))
    steps, omega_tip = 1000, 10.0  # tip twist 0.01 rad
    deck = [lmp.PREAMBLE, "read_data chain.data", "bond_style wirenet",
            f"bond_coeff 1 beam diameter {D} E {E} nu {NU} bending 0.05 twist 0.3",
            f"timestep {DT!r}"]
    for k in range(1, n + 1):
        period = 2 * math.pi / (omega_tip * k / n)
        deck += [f"group n{k} id {k + 1}", f"fix r{k} n{k} move rotate 0 0 0 1 0 0 {period!r}"]
    deck += ["variable T equal tqx[1]", "thermo_style custom step v_T",
             "thermo_modify format float %.17g", f"run {steps}"]
    out = lmp.run_deck("\n".join(deck) + "\n", tmp_path)
    T = lmp.thermo_rows(out)[-1]["T"]
    phi = omega_tip * steps * DT
    expected = 0.3 * G * J * phi / L
    assert abs(T - expected) / expected < 1e-4


@pytest.mark.parametrize("np_", [1, 2])
def test_rigid_half_turn_across_ranks(tmp_path, np_):
    """A bent and twisted chain of beam bonds (and two nodes without bonds) turned rigidly by half
    a turn about z: every node crosses the split plane of a 2-rank run and migrates, with atoms
    exchanged at every step. Only the ends of beam bonds carry an orientation, found again after
    each exchange (a node whose orientation were lost there would feel spurious moments)."""
    n, L = 6, 1.0
    atoms = [(k + 1, 1, -0.5 + L * k / (n - 1), 0.05, 0.0, D, 7850.0, 1) for k in range(n)]
    atoms += [(n + 1, 1, 0.3, -0.4, 0.0, D, 7850.0, 2), (n + 2, 1, -0.3, 0.4, 0.0, D, 7850.0, 3)]
    bonds = [(k + 1, 1, k + 1, k + 2) for k in range(n - 1)]
    lmp.write_data(tmp_path / "chain.data", atoms, bonds)
    steps_half = 1000
    period = 2 * steps_half * DT
    names = [f"{q}{a}{i}" for i in (1, n) for q in "FT" for a in "xyz"]
    deck = [lmp.PREAMBLE, f"processors {np_} 1 1", "read_data chain.data", "bond_style wirenet",
            f"bond_coeff 1 beam diameter {D} E {E} nu {NU} bending 0.7 shear eb",
            f"timestep {DT!r}", "neigh_modify every 1 delay 0 check no",
            f"group tip id {n}",
            # bend and twist the tip node about its own centre, then hold the shape
            "fix b tip move rotate 0.5 0.05 0 0 1 0 1e-3\nrun 25\nunfix b",
            "fix t tip move rotate 0.5 0.05 0 1 0 0 2e-3\nrun 20\nunfix t"]
    for i in (1, n):
        deck += [f"variable Fx{i} equal fx[{i}]\nvariable Fy{i} equal fy[{i}]\nvariable Fz{i} equal fz[{i}]",
                 f"variable Tx{i} equal tqx[{i}]\nvariable Ty{i} equal tqy[{i}]\nvariable Tz{i} equal tqz[{i}]"]
    deck += ["thermo_style custom step " + " ".join(f"v_{k}" for k in names),
             "thermo_modify format float %.17g", "thermo 1", "run 0",
             f"fix rr all move rotate 0 0 0 0 0 1 {period!r}", f"thermo {steps_half}",
             f"run {steps_half}"]
    out = lmp.run_deck("\n".join(deck) + "\n", tmp_path, np=np_)
    by_step = {int(r["Step"]): r for r in lmp.thermo_rows(out) if names[0] in r}
    end = max(by_step)
    ref = np.array([by_step[end - steps_half][k] for k in names]).reshape(4, 3)
    got = np.array([by_step[end][k] for k in names]).reshape(4, 3)
    assert np.abs(ref).max() > 1e-3  # the bent chain carries real forces and moments
    want = (rotation((0, 0, 1), math.pi) @ ref.T).T
    assert np.abs(got - want).max() <= 1e-9 * np.abs(ref).max()
    if np_ == 2:
        assert "2 by 1 by 1 MPI processor grid" in out
