"""Beam law of bond_style wirenet: the paper's cantilever check (Fig. 1) against beam theory.

Cantilever 2 m, d = 1 cm, E = 10 GPa, nu = 0.288, tip load P along -z, clamped root, damped to rest
with viscous damping tuned to the first bending mode (damping does not change the rest state).
"""

import math
import subprocess

import numpy as np
import pytest

import lmp

L, D, E, NU = 2.0, 0.01, 1e10, 0.288
RHO = 7850.0
EI = E * math.pi * D**4 / 64
DECK = lmp.ROOT / "inputs" / "cantilever.in"


def w_analytic(x, P, ei):
    return P * x**2 * (3 * L - x) / (6 * ei)


def run_cantilever(tmp_path, n, P=0.01, bending=1.0, shear="eb", node_d=0.05, dt=None, t_end=12.0, np_=1):
    prefix = tmp_path / f"beam{n}"
    subprocess.run([str(lmp.GEN), "beam", "--elements", str(n), "--node-diameter", str(node_d),
                    "--out", str(prefix)], check=True, capture_output=True)
    # critical viscous damping of the first bending mode: gamma = 2 omega_1 m_node
    omega1 = 1.875104**2 * math.sqrt(bending * EI / (RHO * math.pi * D**2 / 4 * L**4))
    m_node = RHO * math.pi * D**2 / 4 * L / n
    gamma = 2.0 * omega1 * m_node
    dt = dt or {5: 1e-4, 11: 6e-5, 21: 3e-5}[n]
    steps = int(t_end * math.sqrt(1.0 / bending) / dt)
    deck = DECK.read_text()
    variables = {"data": f"{prefix}.data", "P": P, "bending": bending, "shear": shear, "dt": dt,
                 "steps": steps, "gamma": gamma, "thermo_every": steps, "out": "final.dump"}
    header = "".join(f"variable {k} index {v}\n" for k, v in variables.items())
    lmp.run_deck(header + deck, tmp_path, np=np_)
    rows = np.loadtxt(tmp_path / "final.dump", skiprows=9)
    rows = rows[np.argsort(rows[:, 0])]
    return rows[:, 1], -rows[:, 3]  # x, deflection (positive down)


def nrmse(x, w, P, ei):
    wa = w_analytic(x, P, ei)
    return math.sqrt(np.mean((w - wa) ** 2)) / (wa.max() - wa.min())


@pytest.mark.parametrize("n", [5, 11, 21])
def test_euler_bernoulli_cantilever_is_exact(tmp_path, n):
    P = 0.01
    x, w = run_cantilever(tmp_path, n, P=P)
    tip = P * L**3 / (3 * EI)
    assert abs(w[-1] - tip) / tip < 1e-4
    assert nrmse(x, w, P, EI) < 1e-3          # paper: < 2.5 %
    assert w[0] == 0.0                         # clamped root does not move


@pytest.mark.parametrize("n", [5, 11])
def test_parallel_bond_shear_is_stiffer_by_one_over_4n2(tmp_path, n):
    P = 0.01
    x, w = run_cantilever(tmp_path, n, P=P, shear="pb", node_d=0.1, dt=1e-5, t_end=8.0)
    ratio = w[-1] / (P * L**3 / (3 * EI))
    assert abs(ratio - (1 - 1 / (4 * n * n))) < 1e-3


def test_bending_fraction_scales_deflection(tmp_path):
    # 5 % of EI with 1/20 of the load: the same deflection line, i.e. compliance x 20
    P = 0.01 / 20
    x, w = run_cantilever(tmp_path, 5, P=P, bending=0.05)
    tip = P * L**3 / (3 * 0.05 * EI)
    assert abs(w[-1] - tip) / tip < 1e-4
