"""Small harness for running LIGGGHTS decks from tests: paths, data files, runs, thermo parsing."""

import os
import re
import subprocess
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]
BUILD = Path(os.environ.get("WIRENET_BUILD", ROOT / "build"))
LIGGGHTS = BUILD / "bin" / "liggghts"
GEN = BUILD / "bin" / "wirenet-gen"
TRACES = ROOT.parent / "shared" / "reference" / "wire_law_traces"

MPI_ENV = {"OMPI_ALLOW_RUN_AS_ROOT": "1", "OMPI_ALLOW_RUN_AS_ROOT_CONFIRM": "1",
           "OMPI_MCA_rmaps_base_oversubscribe": "1"}

# Deck preamble for node spheres with bonds and no pair style.
PREAMBLE = """units si
atom_style hybrid granular molecular
atom_modify map array sort 0 0
boundary f f f
newton off on
"""


class LiggghtsError(RuntimeError):
    """A deck failed; .output holds stdout+stderr, .error the first ERROR line."""

    def __init__(self, output):
        self.output = output
        errors = [l for l in output.splitlines() if "ERROR" in l]
        self.error = errors[0] if errors else output.strip().splitlines()[-1:] or [""]
        super().__init__(self.error if isinstance(self.error, str) else str(self.error))


def run_deck(deck, workdir, np=1, timeout=600, check=True):
    """Run a deck text in workdir (with np MPI ranks); return the combined output.

    Undecodable bytes are replaced: LIGGGHTS-PUBLIC's Error::all sometimes appends a "tip of the
    day" through a dangling pointer (error_special.h), i.e. random bytes after the ERROR line."""
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "in.deck").write_text(deck)
    cmd = [str(LIGGGHTS), "-in", "in.deck", "-log", "log.lammps", "-echo", "none"]
    if np > 1:
        cmd = ["mpirun", "-np", str(np)] + cmd
    env = dict(os.environ, **MPI_ENV)
    p = subprocess.run(cmd, cwd=workdir, env=env, stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True, errors="replace", timeout=timeout)
    if check and (p.returncode != 0 or "ERROR" in p.stdout):
        raise LiggghtsError(p.stdout)
    return p.stdout


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
