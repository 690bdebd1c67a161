"""The rupture record of fix wirenet_bonds: thermo count, `dump local` and `compute reduce`.

A chain of three nodes 40 mm apart; node 3 moves away at 20 m/s, so bond 2-3 passes its last
table point (0.35 x 40 mm) near step 700 and breaks, while bond 1-2 stays intact.
"""

import numpy as np

import lmp

SW = ("0.0019230769 2.5e8 0.0192 3.2195e8 0.05 3.8292e8 0.15 5.1219e8 "
      "0.25 5.5854e8 0.30 5.6585e8 0.35 5.6585e8")


def test_rupture_dump_and_count(tmp_path):
    atoms = [(1, 1, 0.0, 0.0, 0.0, 0.0108, 7850.0, 1), (2, 1, 0.04, 0.0, 0.0, 0.0108, 7850.0, 1),
             (3, 1, 0.08, 0.0, 0.0, 0.0108, 7850.0, 1)]
    lmp.write_data(tmp_path / "chain.data", atoms, [(1, 1, 1, 2), (2, 1, 2, 3)])
    cols = " ".join(f"f_wirenet_bonds[{k}]" for k in range(1, 9))
    deck = lmp.PREAMBLE + f"""read_data chain.data
bond_style wirenet
bond_coeff 1 wire diameter 0.0027 curve {SW}
group end id 3
fix pull end move linear 20 0 0
variable nb equal f_wirenet_bonds
thermo_style custom step v_nb
thermo 100
timestep 1e-6
run 0
dump rup all local 250 ruptures.dump {cols}
dump_modify rup format "%.0f %.0f %.0f %.0f %.17g %.17g %.17g %.17g"
compute umax all reduce max f_wirenet_bonds[8]
variable umax equal c_umax
thermo_style custom step v_nb v_umax
thermo_modify format float %.17g
run 1000
"""
    out = lmp.run_deck(deck, tmp_path)
    rows = {int(r["Step"]): r for r in lmp.thermo_rows(out)}
    assert rows[600]["nb"] == 0 and rows[800]["nb"] == 1 and rows[1000]["nb"] == 1

    frames = lmp.dump_local_frames(tmp_path / "ruptures.dump")
    assert sorted(frames) == [0, 250, 500, 750, 1000]
    assert all(len(frames[s]) == 0 for s in (0, 250, 500))
    # the array holds every rupture so far: the same single row in the later frames
    np.testing.assert_array_equal(frames[750], frames[1000])
    (step, a1, a2, btype, x, y, z, u), = frames[1000]
    assert (a1, a2, btype) == (2, 3, 1)
    assert 690 <= step <= 710
    u_last = 0.35 * 0.04
    assert u_last < u < u_last + 20 * 1e-6 * 1.001  # past the last point by less than one step
    # midpoint of the bond at the step it broke: node 2 at 0.04, node 3 at 0.08 + 20 m/s * t
    x3 = 0.08 + 20.0 * 1e-6 * step
    assert abs(x - 0.5 * (0.04 + x3)) < 1e-12 and y == 0.0 and z == 0.0
    assert abs(u - (x3 - 0.04 - 0.04)) < 1e-12
    assert rows[1000]["umax"] == u
