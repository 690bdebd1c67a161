"""Reading a fence impact (inputs/fence.in with steps > 0; include/fence_impact.in): the rows of
fence.csv, the per-support rows of anchors.txt / bases.txt, the energy budget and the momentum
balance. Each budget term is measured by its own mechanism in LIGGGHTS; this module only adds
them up (doc/fence.md lists the terms and their sources)."""

import os

import numpy as np

from .csvio import read_deck_table
from .errors import PostprocessError, at

COLUMNS = ("step", "time", "x", "y", "z", "vx", "vy", "vz", "force", "ke_block", "pe_block",
           "w_contact_block", "w_contact_net", "ke_net", "pe_net", "e_elastic", "w_plastic",
           "e_released", "broken", "w_damping", "w_bond_damping", "w_contact_pair", "e_shackle",
           "w_friction", "w_shackle_damping", "sliding", "px_net", "py_net", "pz_net", "jx_damp",
           "jy_damp", "jz_damp", "anchors_x", "anchors_y", "anchors_z", "bases_x", "bases_y",
           "bases_z", "w_ground", "ground_x", "ground_y", "ground_z")

# stored energies and dissipations, in the order of energy.csv
ENERGY_TERMS = ("ke_block", "ke_net", "pe_block", "pe_net", "e_elastic", "e_shackle", "w_plastic",
                "e_released", "damping", "bond_damping", "contact", "contact_layers", "ground",
                "friction", "shackle_damping")


def read_table(workdir):
    """fence.csv as {column: array}."""
    return read_deck_table(os.path.join(workdir, "fence.csv"), COLUMNS)


# the columns of bond_types.txt (fix ave/time mode vector of fix wirenet/bonds' array): per bond
# type, its bonds' elastic energy, energy released at ruptures, plastic work, bond damping (J)
BOND_TALLIES = ("elastic", "released", "plastic", "bond_damping")


def read_support_rows(path):
    """anchors.txt / bases.txt (fix ave/time mode vector of fix wirenet/hold ... each): returns
    (steps, ids, forces) with forces[row, atom, xyz] the window-mean reactions (N)."""
    steps, rows = read_vector_rows(path, 4)
    return steps, rows[0, :, 0].astype(int), rows[:, :, 1:]


def read_bond_types(workdir):
    """bond_types.txt: (steps, tallies[row, type - 1, BOND_TALLIES])."""
    return read_vector_rows(os.path.join(workdir, "bond_types.txt"), len(BOND_TALLIES))


def component_energies(tallies, components):
    """{component: {tally: series}} for components {name: bond types}: elastic energy as it is,
    the dissipations (released, plastic, bond damping) from the first row on."""
    out = {}
    for name, types in components.items():
        cols = tallies[:, [t - 1 for t in types], :].sum(axis=1)
        out[name] = {k: cols[:, j] - (cols[0, j] if k != "elastic" else 0.0)
                     for j, k in enumerate(BOND_TALLIES)}
    return out


def read_vector_rows(path, ncols):
    """A fix ave/time mode vector file ('step rows' lines, each followed by that many 'index
    values' rows): (steps, values[row, index, ncols])."""
    try:
        lines = [l.split() for l in open(path) if l.strip() and not l.startswith("#")]
    except OSError as exc:
        raise PostprocessError(f"{path}: {exc.strerror or exc}") from None
    steps, blocks, k = [], [], 0
    while k < len(lines):
        head = lines[k]
        try:
            step, n = int(head[0]), int(head[1])
            if len(head) != 2:
                raise ValueError
            block = np.array([[float(v) for v in row[1:]] for row in lines[k + 1:k + 1 + n]])
        except (ValueError, IndexError):
            raise at(path, k + 1, "expected a 'step rows' line and its rows of numbers") from None
        if block.shape != (n, ncols) or not np.all(np.isfinite(block)):
            raise at(path, k + 1, f"expected {n} rows of {ncols} finite values")
        steps.append(step)
        blocks.append(block)
        k += n + 1
    if not blocks:
        raise PostprocessError(f"{path}: no rows")
    return np.array(steps), np.array(blocks)


def energy_budget(t):
    """Per row: every term measured from the first row (potential energies as changes,
    dissipations as positive amounts), their sum, the energy at the first row E0 and the
    closure error (sum - E0) / E0."""
    def change(k):
        return t[k] - t[k][0]
    terms = {
        "ke_block": t["ke_block"], "ke_net": t["ke_net"],
        "pe_block": change("pe_block"), "pe_net": change("pe_net"),
        "e_elastic": t["e_elastic"], "e_shackle": t["e_shackle"],
        "w_plastic": change("w_plastic"),          # wires and brakes
        "e_released": change("e_released"),
        "damping": -change("w_damping"),
        "bond_damping": change("w_bond_damping"),
        "contact": -(change("w_contact_block") + change("w_contact_net")),
        "contact_layers": -change("w_contact_pair"),
        "ground": -change("w_ground"),             # stored in and dissipated by the ground contacts
        "friction": change("w_friction"),
        "shackle_damping": change("w_shackle_damping"),
    }
    total = sum(terms[k] for k in ENERGY_TERMS)
    e0 = float(total[0])
    return terms, total, e0, (total - e0) / e0


def momentum_balance(t, block_mass, fence_mass, g):
    """Change of the momentum of block and fence against the impulses of the support reactions
    and of the ground (window means x window length), of gravity and of the damping; the gap relative to the
    block's initial momentum, per row and component."""
    p_block = block_mass * np.column_stack([t["vx"], t["vy"], t["vz"]])
    p_net = np.column_stack([t["px_net"], t["py_net"], t["pz_net"]])
    dp = (p_block - p_block[0]) + (p_net - p_net[0])
    reactions = np.column_stack([t["anchors_x"] + t["bases_x"], t["anchors_y"] + t["bases_y"],
                                 t["anchors_z"] + t["bases_z"]])
    window = np.r_[0.0, np.diff(t["time"])]
    j_react = np.cumsum(reactions * window[:, None], axis=0)
    j_grav = np.zeros_like(dp)
    j_grav[:, 2] = -(block_mass + fence_mass) * g * (t["time"] - t["time"][0])
    j_damp = np.column_stack([t["jx_damp"], t["jy_damp"], t["jz_damp"]])
    # the ground pushes the nodes with minus the nodes' force on it
    j_ground = -np.cumsum(np.column_stack([t["ground_x"], t["ground_y"], t["ground_z"]])
                          * window[:, None], axis=0)
    gap = dp - (j_react + j_grav + j_ground + (j_damp - j_damp[0]))
    return gap / float(np.linalg.norm(p_block[0]))
