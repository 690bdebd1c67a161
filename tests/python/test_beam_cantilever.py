"""Beam law of bond_style wirenet: the paper's cantilever check (Fig. 1) against beam theory,
through the same code path as `./wirenet run beam` (runner.kinds.cantilever.cantilever).

Cantilever 2 m, d = 1 cm, E = 10 GPa, nu = 0.288, tip load P along -z, clamped root, damped to rest
with viscous damping critical for the first bending mode (damping does not change the rest state).
"""

import pytest

from runner.kinds.cantilever import BEAM, bending_stiffness, cantilever

L = BEAM["length"]


@pytest.mark.parametrize("n", [5, 11, 21])
def test_euler_bernoulli_cantilever_is_exact(tmp_path, n):
    r = cantilever(str(tmp_path), n, load=0.01)
    tip = r.load * L**3 / (3 * bending_stiffness())
    assert abs(r.tip - tip) / tip < 1e-4
    assert r.nrmse < 1e-3          # the paper reports < 2.5 %
    assert r.deflection[0] == 0.0  # the clamped root does not move


@pytest.mark.parametrize("n", [5, 11])
def test_parallel_bond_shear_is_stiffer_by_one_over_4n2(tmp_path, n):
    r = cantilever(str(tmp_path), n, load=0.01, shear="pb", node_diameter=0.1, dt=1e-5, t_end=8.0)
    ratio = r.tip / (r.load * L**3 / (3 * bending_stiffness()))
    assert abs(ratio - (1 - 1 / (4 * n * n))) < 1e-3


def test_bending_fraction_scales_deflection(tmp_path):
    # 5 % of EI with 1/20 of the load: the same deflection line, i.e. compliance x 20
    r = cantilever(str(tmp_path), 5, load=0.01 / 20, bending=0.05)
    tip = r.load * L**3 / (3 * bending_stiffness(0.05))
    assert abs(r.tip - tip) / tip < 1e-4
    assert abs(r.tip - 0.01 * L**3 / (3 * bending_stiffness())) / r.tip < 1e-4
