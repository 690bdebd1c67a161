"""write_restart / read_restart with bond_style wirenet.

The wire law is history dependent (largest elongation reached, initial length, slack), and ruptured
bonds must stay ruptured: a run continued from a restart file in a new LIGGGHTS process must be
the run that was never interrupted. The net of netdeck.py is pulled (undamped, so every force
depends on positions only) until wires break; the restart point lies after the first ruptures.

LIGGGHTS stores the bond coefficients in the restart file, and the history fix `wirenet_bonds` is
re-created by the bond style at the first run with its ID and style, which hands it the per-atom
history and the broken-bond count saved in the file. A restart deck needs no bond_style/bond_coeff.
"""

import numpy as np
import pytest

import lmp
import netdeck

SPEED = 8.0       # m/s: first ruptures near step 4000
DT = 5e-6         # s
N = 5000          # steps before and after the restart
EVERY = 500
TOL = 1e-12       # relative

# what a restart deck has to say again: the fixes (same IDs, so fix move resumes its motion), the
# outputs, the time step and `atom_modify sort 0 0` (LIGGGHTS 3.8 keeps neither in restart files;
# without a pair style its atom sorting has no bin size). No bond_style, bond_coeff, history fix
# or `run 0`.
RESUME = f"""atom_modify sort 0 0
timestep {DT!r}
fix hold left move linear 0 0 0
fix pull right move linear {SPEED!r} 0 0
fix integrate free nve/sphere
compute bl all wirenet/local
variable nb equal f_wirenet_bonds
{netdeck.TALLY_THERMO}thermo_style custom step atoms v_nb {netdeck.TALLY_COLS}
thermo_modify format float %.17g
thermo {EVERY}
"""



# broken-bond count and intact bonds of the three-node chain, every thermo step
CHAIN_MONITOR = """compute bl all wirenet/local
compute nbonds all reduce sum c_bl[3]
variable nb equal f_wirenet_bonds
variable intact equal c_nbonds
thermo_style custom step v_nb v_intact
"""

def first_part(n):
    return netdeck.setup(SPEED, 0.0, DT) + f"thermo {EVERY}\nrun 0\n" + netdeck.outputs(EVERY) + f"run {n}\n"


def compare_bonds(ref, got, steps):
    for step in steps:
        a, b = ref[step], got[step]
        assert np.array_equal(a[:, :3], b[:, :3]), f"step {step}: different intact bonds"
        # initial lengths come back from the history, bit for bit
        np.testing.assert_array_equal(a[:, 3], b[:, 3])
        tmax = np.abs(a[:, 5]).max()
        err = np.abs(a[:, 5] - b[:, 5]) / np.maximum(np.abs(a[:, 5]), 1e-3 * max(tmax, 1e-300))
        assert err.max() <= TOL, f"step {step}: tension differs by {err.max():.3g}"
        err = np.abs(a[:, 4] - b[:, 4]) / np.maximum(np.abs(a[:, 4]), 1e-6)
        assert err.max() <= TOL, f"step {step}: strain differs by {err.max():.3g}"


def compare_atoms(ref, got, steps):
    for step in steps:
        (cols, a), (cols_b, b) = ref[step], got[step]
        assert cols == cols_b
        np.testing.assert_array_equal(a[:, 0], b[:, 0])
        scale = np.maximum(np.abs(a[:, 1:]).max(axis=0), 1e-300)  # vz = z = 0 in a flat net
        err = (np.abs(a[:, 1:] - b[:, 1:]) / scale).max()
        assert err <= TOL, f"step {step}: positions/velocities differ by {err:.3g}"


@pytest.fixture(scope="module")
def uninterrupted(tmp_path_factory):
    wd = tmp_path_factory.mktemp("uninterrupted")
    netdeck.make_net(wd)
    out = lmp.run_deck(first_part(2 * N), wd)
    return wd, out


@pytest.mark.parametrize("coeffs_again", [False, True], ids=["read_restart_only", "bond_coeff_again"])
def test_restart_matches_uninterrupted(tmp_path, uninterrupted, coeffs_again):
    ref_wd, ref_out = uninterrupted
    # first half, then the restart file
    netdeck.make_net(tmp_path)
    out1 = lmp.run_deck(first_part(N) + "write_restart net.restart\n", tmp_path, name="in.first")
    broken_at_restart = lmp.thermo_rows(out1)[-1]["nb"]
    assert broken_at_restart >= 2, "no wire broke before the restart: the test would miss that path"

    # second half in a new process, from the restart file alone
    wd2 = tmp_path / "second"
    wd2.mkdir()
    (wd2 / "net.restart").write_bytes((tmp_path / "net.restart").read_bytes())
    again = netdeck.COEFFS if coeffs_again else ""
    deck = "processors * 1 1\nread_restart net.restart\n" + again + RESUME + netdeck.outputs(EVERY, ruptures=False) + f"run {N}\n"
    out2 = lmp.run_deck(deck, wd2)
    assert "Resetting per-atom state of Fix wirenet_bonds" in out2
    assert "Resetting global state of Fix wirenet_bonds" in out2

    ref_rows = {int(r["Step"]): r for r in lmp.thermo_rows(ref_out)}
    rows2 = {int(r["Step"]): r for r in lmp.thermo_rows(out2)}
    # the broken count continues from the file and follows the uninterrupted run
    assert rows2[N]["nb"] == broken_at_restart == ref_rows[N]["nb"]
    assert rows2[2 * N]["nb"] == ref_rows[2 * N]["nb"] > broken_at_restart, "no wire broke after the restart"
    # the energy tallies of every bond type continue from the file (fix wirenet/bonds' array)
    for step in (N, 2 * N):
        for name in netdeck.TALLY_COLS.split():
            key = name[2:] if name.startswith(("v_", "c_")) else name
            ref, got = ref_rows[step][key], rows2[step][key]
            assert abs(got - ref) <= TOL * max(abs(ref), 1e-6), f"step {step}: {key} {got} != {ref}"
    assert rows2[2 * N]["pl_2"] > rows2[N]["pl_2"] > 0.0 and rows2[2 * N]["rel_2"] > 0.0

    ref_bonds = netdeck.bonds_by_step(ref_wd)
    bonds2 = netdeck.bonds_by_step(wd2)
    steps = list(range(N, 2 * N + 1, EVERY))
    assert sorted(bonds2) == steps
    compare_bonds(ref_bonds, bonds2, steps)
    compare_atoms(lmp.dump_atom_frames(ref_wd / "atoms.dump"), lmp.dump_atom_frames(wd2 / "atoms.dump"), steps)

    # broken bonds stay broken: every bond missing at the restart is missing afterwards
    before = {tuple(r) for r in ref_bonds[0][:, :2].astype(int)}
    at_restart = {tuple(r) for r in bonds2[N][:, :2].astype(int)}
    assert len(before - at_restart) == broken_at_restart
    for step in steps:
        assert not ({tuple(r) for r in bonds2[step][:, :2].astype(int)} - at_restart)


def test_restart_on_two_ranks(tmp_path):
    """Written on 2 ranks and read on 2 ranks: the continuation equals the same process going on."""
    netdeck.make_net(tmp_path)
    # reference: the first process writes the file and carries on
    lmp.run_deck(first_part(N) + f"write_restart net.restart\nrun {N}\n", tmp_path, np=2, name="in.first")
    wd2 = tmp_path / "second"
    wd2.mkdir()
    (wd2 / "net.restart").write_bytes((tmp_path / "net.restart").read_bytes())
    deck = "processors * 1 1\nread_restart net.restart\n" + RESUME + netdeck.outputs(EVERY, ruptures=False) + f"run {N}\n"
    out2 = lmp.run_deck(deck, wd2, np=2)
    assert "2 by 1 by 1 MPI processor grid" in out2
    steps = list(range(N, 2 * N + 1, EVERY))
    ref = netdeck.bonds_by_step(tmp_path)
    got = netdeck.bonds_by_step(wd2)
    assert len(ref[0]) - len(ref[N]) >= 2 and len(ref[N]) > len(ref[2 * N])
    compare_bonds(ref, got, steps)
    compare_atoms(lmp.dump_atom_frames(tmp_path / "atoms.dump"), lmp.dump_atom_frames(wd2 / "atoms.dump"), steps)


def test_restart_file_written_mid_run_keeps_flagged_ruptures(tmp_path):
    """The `restart` command writes files at the end of a step. A bond that broke in that very
    step is only flagged (it leaves the bond list at the next re-neighbouring; LIGGGHTS
    re-neighbours at the start of a restart step, not after the forces). Read back, that bond must
    still count as broken and must not come back."""
    atoms = [(1, 1, 0.0, 0.0, 0.0, 0.0108, 7850.0, 1), (2, 1, 0.04, 0.0, 0.0, 0.0108, 7850.0, 1),
             (3, 1, 0.08, 0.0, 0.0, 0.0108, 7850.0, 1)]
    lmp.write_data(tmp_path / "chain.data", atoms, [(1, 1, 1, 2), (2, 1, 2, 3)])
    # node 3 moves at 20 m/s: bond 2-3 (l0 = 40 mm) passes 0.35 x 40 mm near step 700; a restart
    # file is written at every step around it
    deck = lmp.PREAMBLE + f"""read_data chain.data
bond_style wirenet
bond_coeff 1 wire diameter 0.0027 curve {netdeck.SW_CURVE}
group end id 3
fix pull end move linear 20 0 0
{CHAIN_MONITOR}thermo 1
timestep 1e-6
run 690
restart 1 chain.restart.*
run 20
"""
    out = lmp.run_deck(deck, tmp_path, name="in.first")
    rows = {int(r["Step"]): r for r in lmp.thermo_rows(out)}
    step = min(s for s, r in rows.items() if r["nb"] > 0)
    assert 690 < step <= 710 and rows[step]["nb"] == 1 and rows[step]["intact"] == 1
    assert (tmp_path / f"chain.restart.{step}").exists()
    resume = f"""read_restart chain.restart.{step}
atom_modify sort 0 0
timestep 1e-6
fix pull end move linear 20 0 0
{CHAIN_MONITOR}thermo 100
run 300
"""
    out2 = lmp.run_deck(resume, tmp_path, name="in.second")
    rows2 = lmp.thermo_rows(out2)
    assert [r["nb"] for r in rows2] == [1.0] * len(rows2)
    assert [r["intact"] for r in rows2] == [1.0] * len(rows2)
