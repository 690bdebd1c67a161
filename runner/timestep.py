"""The time step of a case: the stable step of its bonds and contacts (2 / omega_max).

Bonds: per bond, the two-node axial and rotational frequencies doubled (a node shared by two
bonds moving in antiphase), as bond_style wirenet estimates them; the stiffest contact on the
lightest node adds omega^2 = c (kn + 2.5 ks) / m (c = 2 where a compound panel's two layers can
press a node from both sides), combined as omega^2 = omega_bond^2 + omega_contact^2.
"""

import math

import numpy as np

from .materials import resolve, sw_curve


def stable(panel, bending, materials, contact=True):
    """Stable step of a generated panel (runner/panel.Panel) with the true masses; ``contact``:
    a loading body or the other layer may press on the nodes."""
    data, mass = panel.data, panel.masses
    mat = resolve(materials)
    ids = data.atoms[:, 0].astype(int)
    index = {i: k for k, i in enumerate(ids)}
    radius = data.atoms[:, 5] / 2
    pos = data.atoms[:, 2:5]
    w2 = 0.0
    eps1, sig1 = sw_curve(mat)[0]
    rope_r = mat["rope_d"] / 2
    area = math.pi * rope_r ** 2
    inertia = math.pi * rope_r ** 4 / 4
    shear_mod = mat["rope_E"] / (2 * (1 + mat["rope_nu"]))
    for _, btype, a1, a2 in data.bonds.astype(int):
        i, j = index[a1], index[a2]
        l0 = float(np.linalg.norm(pos[i] - pos[j]))
        inv_m = 1 / mass[i] + 1 / mass[j]
        if btype in (1, 2, 3):
            d = mat["selvedge_d"] if btype == 3 else mat["wire_d"]
            k = sig1 * math.pi * d * d / 4 / (eps1 * l0)
            w2 = max(w2, 2 * (2 * k if btype == 1 else k) * inv_m)
        else:
            kax = mat["rope_E"] * area / l0
            kb = bending * mat["rope_E"] * inertia / l0
            kt = bending * shear_mod * 2 * inertia / l0
            kr = 6 * kb + 2 * kt
            inv_i = 1 / (0.4 * mass[i] * radius[i] ** 2) + 1 / (0.4 * mass[j] * radius[j] ** 2)
            w2 = max(w2, 2 * max(kax, 12 * kb / l0 ** 2) * inv_m, 2 * kr * inv_i)
    m_min = float(mass.min())
    if contact or panel.layers > 1:
        w2 += (2.0 if panel.layers > 1 else 1.0) * (mat["kn"] + 2.5 * mat["ks"]) / m_min
    return 2.0 / math.sqrt(w2)
