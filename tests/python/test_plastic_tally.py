"""The plastic-work tally of bond_style wirenet is a sum over the bonds' state, taken when it is read.

A wire's plastic work is a function of its largest elongation (WireLaw::plastic_work: the work
along the envelope up to it, less the elastic energy unloading gives back); the tally adds up the
change of that sum since it was last read, and a bond's value for good when it breaks. So the
tally cannot depend on when, or how often, it is read: not even across runs, between which the
bonds that broke are removed and the bond style's list is rebuilt, so the tally must be brought up
to date before that (fix wirenet/bonds' post_run).

The pulled, tearing net of netdeck.py is run for STEPS steps in four runs, once with the tallies
read every 100 steps and once read only after the last run: the plastic work, the released energy
and the broken count agree to round-off. (Both cut the steps alike: the list rebuilt between runs
orders the bond forces differently, which a tearing net amplifies to 1e-8 by the end.)
"""

import lmp
import netdeck

SPEED, GAMMA, DT = 2.0, 200.0, 1e-5
STEPS = 8000       # wires yield from about step 1500 and break from about step 3500 (test_wire_mpi)
READ = "print \"tallies $(f_wirenet_bonds[1]) $(f_wirenet_bonds[2]) $(f_wirenet_bonds[3])\"\n"  # 15 digits


def tallies(out):
    rows = [l.split()[1:] for l in out.splitlines() if l.startswith("tallies ")]
    assert len(rows) == 1, out[-2000:]
    return [float(v) for v in rows[0]]


def run(tmp_path, name, runs, read_every_step):
    wd = tmp_path / name
    netdeck.make_net(wd)
    thermo = "thermo 100\n" if read_every_step else "thermo_style custom step atoms\nthermo 100000\n"
    body = "".join(f"run {STEPS // runs}\n" for _ in range(runs))
    return tallies(lmp.run_deck(netdeck.setup(SPEED, GAMMA, DT) + thermo + body + READ, wd))


def test_tally_does_not_depend_on_reads_or_runs(tmp_path):
    one = run(tmp_path, "read_often", 4, True)
    four = run(tmp_path, "read_once", 4, False)
    broken, released, plastic = one
    assert broken >= 5 and released > 0.0, one
    assert plastic > 10.0 * released, one        # the net yields far more than it releases
    assert four[0] == broken
    assert abs(four[1] - released) <= 1e-12 * released, (four, one)
    assert abs(four[2] - plastic) <= 1e-12 * plastic, (four, one)



def test_bonds_turned_off_between_runs_keep_their_work(tmp_path):
    """`delete_bonds all bond 2` between two runs turns the yielded SW wires off (LIGGGHTS makes
    their type negative; the bond style skips them from then on): the work they did stays in the
    tally, which a `run 0` afterwards must not change (the sum the tally follows restarts at each
    run's set-up from the bonds present then). The DT and selvedge wires keep loading afterwards."""
    wd = tmp_path / "turned_off"
    netdeck.make_net(wd)
    deck = (netdeck.setup(SPEED, GAMMA, DT) + "thermo_style custom step atoms\nthermo 100000\n"
            + "run 3000\n" + READ + "delete_bonds all bond 2\nrun 0\n" + READ + "run 1000\n" + READ)
    out = lmp.run_deck(deck, wd)
    rows = [[float(v) for v in l.split()[1:]] for l in out.splitlines() if l.startswith("tallies ")]
    assert len(rows) == 3 and rows[0][2] > 10.0, rows   # the wires have yielded
    assert rows[1] == rows[0]
    assert rows[2][2] > rows[1][2], rows                # the others go on yielding
