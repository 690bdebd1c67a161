"""The highest axial frequency of a generated fence, assembled, against the per-bond estimate
that sets the fence's time step (compute wirenet/timestep: 2 k (1/m_i + 1/m_j) per bond).

    PYTHONPATH=. /usr/bin/python3 tests/bench/fence_frequency.py CASE_DIR/setup/fence

reads PREFIX.data and PREFIX.types.in (wirenet-gen fence) and the materials of
inputs/include/materials.in, builds the axial stiffness of every bond at its initial tangent
(wires and support ropes: the first slope of their curve on pi d^2/4; ropes and posts: E A / l0;
brakes: brake_k), and finds the largest eigenvalue of M^-1 K by power iteration, anchors and
post bases held. Bending, twist and the contacts are left out (the estimate's rotation limit
and contact term are printed by the fence deck); the power iteration approaches the largest
eigenvalue from below. docs/PERFORMANCE.md (2026-11-28, the fence's time step) records its
result.
"""

import math
import re
import sys

import numpy as np

from postprocess.datafile import read_data
from runner.materials import MATERIALS


def first_slope(curve):
    """E of a curve's first segment: stress / strain of its first point [Pa]."""
    values = [float(v) for v in curve.split()]
    return values[1] / values[0]


def types(path):
    """{name: number} of PREFIX.types.in (`variable atom_NAME index N`, `bond_NAME`)."""
    found = re.findall(r"^variable\s+((?:atom|bond)_\w+)\s+index\s+(\d+)", open(path).read(), re.M)
    return {name: int(n) for name, n in found}


def bond_stiffness(kind, length, meta_post_area):
    """Axial stiffness [N/m] of the bonds of one type."""
    wire = first_slope(MATERIALS["curve"])
    support = first_slope(MATERIALS["support_curve"])
    area = lambda d: math.pi * d * d / 4     # noqa: E731
    table = {"DT": wire * area(MATERIALS["wire_d"]), "SW": wire * area(MATERIALS["wire_d"]),
             "selvedge": wire * area(MATERIALS["selvedge_d"]),
             "rope": MATERIALS["rope_E"] * area(MATERIALS["rope_d"]),
             "support_rope": support * area(0.022), "upslope": support * area(0.022),
             "post": MATERIALS["post_E"] * meta_post_area}
    if kind in ("brake", "upslope_brake"):
        return np.full_like(length, MATERIALS["brake_k"])
    return table[kind] / length


def main(prefix, iterations=1000):
    data = read_data(prefix + ".data")
    names = types(prefix + ".types.in")
    atom_type = data.atom("type").astype(int)
    d, rho = data.atom("diameter"), data.atom("density")
    mass = math.pi * d ** 3 / 6 * rho
    index = {int(a): k for k, a in enumerate(data.atom("id"))}
    i = np.array([index[int(a)] for a in data.bond("atom1")])
    j = np.array([index[int(a)] for a in data.bond("atom2")])
    x = data.positions
    length = np.linalg.norm(x[j] - x[i], axis=1)
    unit = (x[j] - x[i]) / length[:, None]
    k = np.zeros(len(i))
    bond_type = data.bond("type").astype(int)
    post_area = 0.005383      # HEA 200 (EN 10365), the generator's default post section
    for name, number in names.items():
        if name.startswith("bond_"):
            sel = bond_type == number
            k[sel] = bond_stiffness(name[5:], length[sel], post_area)
    held = np.isin(atom_type, [names["atom_anchor"], names["atom_post_base"]])
    per_bond = 2 * k * (1 / mass[i] + 1 / mass[j])
    worst = int(np.argmax(per_bond))
    inv_name = {v: n for n, v in names.items() if n.startswith("bond_")}

    def apply(u):
        stretch = ((u[j] - u[i]) * unit).sum(1) * k
        f = np.zeros_like(u)
        np.add.at(f, i, stretch[:, None] * unit)
        np.add.at(f, j, -stretch[:, None] * unit)
        f /= mass[:, None]
        f[held] = 0.0
        return f

    u = np.random.default_rng(1).standard_normal(x.shape)
    u[held] = 0.0
    lam = 0.0
    for _ in range(iterations):
        v = apply(u)
        lam = np.linalg.norm(v) / np.linalg.norm(u)
        u = v / np.linalg.norm(v)
    print(f"per-bond estimate: omega^2 {per_bond[worst]:.4e} 1/s^2 (a {inv_name[bond_type[worst]][5:]} "
          f"bond of {length[worst]:.3f} m), 2/omega = {2 / math.sqrt(per_bond[worst]):.4e} s")
    print(f"assembled (power iteration, {iterations} steps): omega^2 >= {lam:.4e} 1/s^2, "
          f"2/omega <= {2 / math.sqrt(lam):.4e} s: omega {math.sqrt(lam / per_bond[worst]):.3f} of the estimate's")


if __name__ == "__main__":
    if len(sys.argv) != 2:
        sys.exit("usage: fence_frequency.py PREFIX   (PREFIX.data and PREFIX.types.in of wirenet-gen fence)")
    main(sys.argv[1])
