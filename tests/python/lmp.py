"""Small harness for running LIGGGHTS decks from tests: paths, data files, runs, thermo parsing."""

import os
import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BUILD = Path(os.environ.get("WIRENET_BUILD", ROOT / "build"))
LIGGGHTS = BUILD / "bin" / "liggghts"
GEN = BUILD / "bin" / "wirenet-gen"
# YADE reference traces of the wire law, copied into the repository (provenance in its README)
TRACES = ROOT / "tests" / "reference" / "wire_law_traces"

MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
           "OMPI_MCA_rmaps_base_oversubscribe": "1"}

# Deck preamble for node spheres with bonds and no pair style.
PREAMBLE = """units si
atom_style hybrid granular molecular
atom_modify map array sort 0 0
boundary f f f
newton off on
"""

# The material properties `pair_style gran model hertz` needs for one atom type (the test decks'
# soft contact: E 1e7 Pa, nu 0.3, restitution and friction 0.5).
HERTZ_MATERIALS = """fix m1 all property/global youngsModulus peratomtype 1e7
fix m2 all property/global poissonsRatio peratomtype 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5
fix m4 all property/global coefficientFriction peratomtypepair 1 0.5
"""

# Deck preamble for bare granular spheres (no bonds) that touch walls or bodies.
GRANULAR_PREAMBLE = """units si
atom_style granular
atom_modify map array sort 0 0
boundary f f f
newton off
communicate single vel yes
"""


_ERROR_LINE = re.compile(r"\bERROR( on proc \d+)?: ")


def error_lines(output):
    """LIGGGHTS' own ERROR lines (not OpenMPI's abort chatter such as ORTE_ERROR_LOG)."""
    return [l for l in output.splitlines() if _ERROR_LINE.search(l)]


class LiggghtsError(RuntimeError):
    """A deck failed; .output holds stdout+stderr, .error the first ERROR line."""

    def __init__(self, output):
        self.output = output
        errors = error_lines(output)
        self.error = errors[0] if errors else output.strip().splitlines()[-1:] or [""]
        super().__init__(self.error if isinstance(self.error, str) else str(self.error))


def run_deck_rc(deck, workdir, np=1, timeout=600, name="in.deck"):
    """Run a deck text in workdir (with np MPI ranks); return (exit code, combined output).
    A negative exit code is the signal that killed LIGGGHTS (without mpirun)."""
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / name).write_text(deck)
    cmd = [str(LIGGGHTS), "-in", name, "-log", "log.lammps", "-echo", "none"]
    if np > 1:
        cmd = ["mpirun", "-np", str(np)] + cmd
    env = dict(os.environ, **MPI_ENV)
    p = subprocess.run(cmd, cwd=workdir, env=env, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True, errors="replace", timeout=timeout)
    return p.returncode, p.stdout


def one_error(deck, workdir, np=1):
    """The one ERROR line of a deck that must fail: a non-zero exit and a single line."""
    rc, out = run_deck_rc(deck, workdir, np=np)
    errors = error_lines(out)
    assert rc != 0 and len(errors) == 1, out[-2000:]
    return errors[0]


def run_deck(deck, workdir, np=1, timeout=600, check=True, name="in.deck"):
    """Run a deck text in workdir (with np MPI ranks); return the combined output."""
    rc, out = run_deck_rc(deck, workdir, np=np, timeout=timeout, name=name)
    if check and (rc != 0 or "ERROR" in out):
        raise LiggghtsError(out)
    return out


def write_data(path, atoms, bonds, natom_types=1, nbond_types=1, box=((-1, 1), (-1, 1), (-1, 1))):
    """atoms: (id, type, x, y, z, diameter, density, molecule); bonds: (id, type, a1, a2)."""
    lines = ["LIGGGHTS data file written by the WireNet tests", "",
             f"{len(atoms)} atoms", f"{len(bonds)} bonds",
             f"{natom_types} atom types", f"{nbond_types} bond types", ""]
    for (lo, hi), ax in zip(box, "xyz"):
        lines.append(f"{lo!r} {hi!r} {ax}lo {ax}hi")
    lines += ["", "Atoms", ""]
    lines += [" ".join(repr(v) for v in a) for a in atoms]
    if bonds:
        lines += ["", "Bonds", ""]
        lines += [" ".join(str(v) for v in b) for b in bonds]
    Path(path).write_text("\n".join(lines) + "\n")


_NUM = re.compile(r"^[-+0-9.eE]+$|^-?nan$|^-?inf$", re.I)


def thermo_rows(output):
    """All thermo rows as dicts (column name -> float), in output order, across runs."""
    rows, header = [], None
    for line in output.splitlines():
        words = line.split()
        if words and words[0] == "Step":
            header = words
            continue
        if header and len(words) == len(header) and all(_NUM.match(w) for w in words):
            rows.append(dict(zip(header, map(float, words))))
        elif header and line.startswith("Loop time"):
            header = None
    return rows


def _dump_frames(path):
    """(step, column names, 2-d array of the rows) for every frame of a LIGGGHTS dump file."""
    import numpy as np
    lines = Path(path).read_text().splitlines()
    k = 0
    while k < len(lines):
        if not lines[k].startswith("ITEM: TIMESTEP"):
            k += 1
            continue
        # TIMESTEP, step, NUMBER, n, BOX BOUNDS + 3 lines, then the ENTRIES/ATOMS header
        step, n = int(lines[k + 1]), int(lines[k + 3])
        cols = lines[k + 8].split()[2:]
        start = k + 9
        rows = [[float(w) for w in l.split()] for l in lines[start:start + n]]
        yield step, cols, np.array(rows, dtype=float).reshape(n, -1) if n else np.zeros((0, 0))
        k = start + n


def dump_local_frames(path):
    """Frames of a `dump local` file: {step: 2-d numpy array of the entries}."""
    return {step: rows for step, _, rows in _dump_frames(path)}


def dump_atom_frames(path):
    """Frames of a `dump custom` file: {step: (column names, 2-d numpy array sorted by column 1)}."""
    import numpy as np
    return {step: (cols, rows.reshape(len(rows), len(cols))[np.argsort(rows[:, 0])])
            for step, cols, rows in _dump_frames(path)}


def sort_rows(a, keys=(0, 1)):
    """Rows of a sorted by the given columns (first key most significant)."""
    import numpy as np
    if len(a) == 0:
        return a
    return a[np.lexsort(tuple(a[:, k] for k in reversed(keys)))]
