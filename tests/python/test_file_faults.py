"""Faults of LIGGGHTS' own file handling and error path (issue #43): each ends the run with one
ERROR line naming the file and what is wrong, a non-zero exit, every rank stopping, no hang.

- an error raised on one rank only (Error::one, patch 0008) ends the job without OpenMPI's
  MPI_ABORT banner.

Every run has a timeout and is killed with its whole process group if it hangs (a hung rank of
LIGGGHTS ignored SIGTERM).
"""

import os
import signal
import stat
import struct
import subprocess
from pathlib import Path

import pytest

import lmp
from test_input_errors import ATOMS, BONDS
from test_wire_errors import GOOD, check_error

TIMEOUT = 60


def run(deck, workdir, np=1, umask=None, timeout=TIMEOUT):
    """(exit code, output) of a deck; a run past the timeout is killed with its process group and
    fails the test (a hang)."""
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    (workdir / "in.deck").write_text(deck)
    cmd = [str(lmp.LIGGGHTS), "-in", "in.deck", "-log", "log.lammps", "-echo", "none"]
    if np > 1:
        cmd = ["mpirun", "-np", str(np)] + cmd
    env = dict(os.environ, **lmp.MPI_ENV)

    def preexec():
        if umask is not None:
            os.umask(umask)

    p = subprocess.Popen(cmd, cwd=workdir, env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                         text=True, errors="replace", start_new_session=True, preexec_fn=preexec)
    try:
        out, _ = p.communicate(timeout=timeout)
    except subprocess.TimeoutExpired:
        os.killpg(p.pid, signal.SIGKILL)
        out, _ = p.communicate()
        pytest.fail(f"LIGGGHTS hung (killed after {timeout} s):\n{out[-2000:]}")
    return p.returncode, out


def no_banner(out):
    for bad in ("MPI_ABORT", "NOTE: invoking", "ORTE_ERROR_LOG"):
        assert bad not in out, f"{bad!r} in the output:\n{out[-2000:]}"


# ---- one rank's error -----------------------------------------------------------------------------

def test_one_rank_error_ends_without_the_abort_banner(tmp_path):
    """A bond across the rank boundary outgrows the ghosts: rank 0 alone finds it (Error::one). The
    job ends with its one ERROR line and a non-zero exit, without OpenMPI's MPI_ABORT banner."""
    atoms = [(1, 1, -0.02, 0.0, 0.0, 0.0108, 7850.0, 1), (2, 1, 0.18, 0.0, 0.0, 0.0108, 7850.0, 1)]
    lmp.write_data(tmp_path / "long.data", atoms, [(1, 1, 1, 2)])
    deck = lmp.PREAMBLE + f"""processors * 1 1
read_data long.data
neigh_modify delay 0 every 200 check no
bond_style wirenet
bond_coeff 1 {GOOD}
group pulled id 2
fix pull pulled move linear 30 0 0
timestep 1e-5
run 400
"""
    rc, out = run(deck, tmp_path, np=2)
    errors = lmp.error_lines(out)
    assert rc > 0 and len(errors) == 1, out[-2000:]
    assert errors[0].startswith("ERROR on proc 0: bond_style wirenet: bond 1-2 reaches beyond the ghost atoms")
    no_banner(out)


@pytest.mark.parametrize("np_", [1, 2])
def test_error_on_the_other_rank_ends_without_the_banner(tmp_path, np_):
    """Both nodes of a zero-length bond at x = 0 belong to rank 1 of two: rank 1 alone stops."""
    atoms = [(1, 1, 0.0, 0.0, 0.0, 0.0108, 7850.0, 1), (2, 1, 0.0, 0.0, 0.0, 0.0108, 7850.0, 1)]
    lmp.write_data(tmp_path / "zero.data", atoms, [(1, 1, 1, 2)])
    deck = lmp.PREAMBLE + f"processors * 1 1\nread_data zero.data\nbond_style wirenet\nbond_coeff 1 {GOOD}\nrun 0\n"
    rc, out = run(deck, tmp_path, np=np_)
    errors = lmp.error_lines(out)
    assert rc > 0 and len(errors) == 1, out[-2000:]
    assert f"ERROR on proc {np_ - 1}: bond_style wirenet: bond 1-2 has zero length" in errors[0]
    no_banner(out)
