"""Writers of synthetic LIGGGHTS dumps and data files (tests and the benchmark)."""

import numpy as np

from .dumps import BOND_COLUMNS


def _number(value):
    value = float(value)
    return str(int(value)) if value.is_integer() else repr(value)


def _lines(rows):
    return ["".join([" ".join(_number(v) for v in row), "\n"]) for row in rows]


def bond_dump_text(frames, ncols=12, compute="bonds"):
    """Text of a ``dump local`` of compute wirenet/local.

    ``frames``: list of (step, rows) with rows of at least ``ncols`` numbers in the
    BOND_COLUMNS order (extra values are dropped).
    """
    names = " ".join(f"c_{compute}[{k}]" for k in range(1, ncols + 1))
    out = []
    for step, rows in frames:
        rows = [list(r)[:ncols] for r in rows]
        out += ["ITEM: TIMESTEP\n", f"{step}\n", "ITEM: NUMBER OF ENTRIES\n", f"{len(rows)}\n",
                "ITEM: BOX BOUNDS ff ff ff\n", "-2 2\n", "-2 2\n", "-2 2\n",
                f"ITEM: ENTRIES {names}\n"]
        out += _lines(rows)
    return "".join(out)


def node_dump_text(frames, names=("id", "type", "x", "y", "z")):
    """Text of a ``dump custom``; ``frames``: list of (step, rows) in ``names`` order."""
    out = []
    for step, rows in frames:
        out += ["ITEM: TIMESTEP\n", f"{step}\n", "ITEM: NUMBER OF ATOMS\n", f"{len(rows)}\n",
                "ITEM: BOX BOUNDS ff ff ff\n", "-2 2\n", "-2 2\n", "-2 2\n",
                f"ITEM: ATOMS {' '.join(names)}\n"]
        out += _lines(rows)
    return "".join(out)


def bond_row(atom1, atom2, btype, tension, mid, strain=0.0, length0=0.1):
    """One 12-column wirenet/local row."""
    length = length0 * (1.0 + strain)
    return [atom1, atom2, btype, length0, strain, tension, length, *mid, 0.0, 0.0]


def data_file_text(atoms, bonds, natom_types=8, nbond_types=4):
    """A minimal data file; atoms: (id type x y z diameter density molecule), bonds: (id type
    a1 a2)."""
    out = ["LIGGGHTS data file from synthetic\n\n", f"{len(atoms)} atoms\n",
           f"{len(bonds)} bonds\n", f"{natom_types} atom types\n", f"{nbond_types} bond types\n\n",
           "-2 2 xlo xhi\n-2 2 ylo yhi\n-2 2 zlo zhi\n\nAtoms # hybrid\n\n"]
    out += _lines(atoms)
    out += ["\nBonds\n\n"]
    out += _lines(bonds)
    return "".join(out)


def random_panel(nbonds, seed=1):
    """Random bonds of a 4 m x 4 m panel: (atom ids, types, tensions, midpoints) as arrays."""
    rng = np.random.default_rng(seed)
    first = np.arange(1, nbonds + 1)
    second = first + 1
    types = rng.integers(1, 5, nbonds)
    tension = rng.normal(100.0, 200.0, nbonds)
    mids = np.column_stack([rng.uniform(-2, 2, nbonds), rng.uniform(-2, 2, nbonds),
                            rng.uniform(-0.5, 0.0, nbonds)])
    return first, second, types, tension, mids


def write_random_bond_dump(path, nframes, nbonds, seed=1):
    """A ``nframes`` x ``nbonds`` 12-column bond dump (benchmark input)."""
    first, second, types, tension, mids = random_panel(nbonds, seed)
    names = " ".join(f"c_bonds[{k}]" for k in range(1, len(BOND_COLUMNS) + 1))
    with open(path, "w", encoding="utf-8") as handle:
        for frame in range(nframes):
            scale = 1.0 + 0.01 * frame
            table = np.column_stack([first, second, types, np.full(nbonds, 0.1),
                                     np.full(nbonds, 1e-3), tension * scale,
                                     np.full(nbonds, 0.1001), mids, np.zeros((nbonds, 2))])
            handle.write(f"ITEM: TIMESTEP\n{frame * 1000}\nITEM: NUMBER OF ENTRIES\n{nbonds}\n"
                         f"ITEM: BOX BOUNDS ff ff ff\n-3 3\n-3 3\n-3 3\nITEM: ENTRIES {names}\n")
            np.savetxt(handle, table, fmt="%.8g")
