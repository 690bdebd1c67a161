"""Energy and momentum budgets that bite: a quick hexagonal panel hit hard enough that wires
yield and break, so that every term of the budget is non-zero, run on 1 rank and on 2 ranks
whose split (processors 2 1 1: the plane x = 0 through the impact point) cuts the contact
region. Each term is checked against an independent value where one exists:

- the block's potential energy against -M g dz from its own trajectory (block.csv);
- plastic work and released energy positive (wires yielded and broke), the number of ruptures
  equal to the rows of ruptures.csv;
- closure of the whole budget below 0.5 % of the initial energy and the momentum balance below
  0.2 % of the block's momentum, at every output row;
- the same budget and the same trajectory on 2 ranks as on 1.

Mutations these tests kill (tests/README.md): dropping the block's potential energy, flipping
the sign of the plastic or released term, a factor 2 on the contact work, dropping the net's
weight from the gravity impulse.
"""

import json
import os
import re

import numpy as np
import pytest

import lmp
from runner import api
from runner.kinds import impact
from postprocess.datafile import read_data

SPEED = 30.0        # m/s: 20 kJ into a 1.2 m hexagonal panel, wires yield and break
DURATION = 0.02     # s: the block passes its lowest point and tears through
# The block of these budgets: the STL moved by fix wirenet/rigidmesh, whose 1- and 2-rank runs
# break the same number of bonds. With the analytic block (fix wirenet/body, the runners'
# default) the budgets close as well (1.1e-4 and 1.0e-4 on 1 and 2 ranks) and the trajectories
# agree to 1e-5 of the travel before the first rupture and 2.7e-3 over the run, but the
# round-off of the other summation order reached one rupture: 29 bonds on 1 rank, 28 on 2.
BODY = "mesh"
G = 9.81            # the case's gravity (the schema's default)


def hard_case(*sets):
    """The quick hexagonal impact at SPEED for DURATION under the paper's local damping (0.5, no
    bond damping), with --set overrides."""
    return api.load('kind = "impact"\n[panel]\nnet = "hex"\n[damping]\nlocal = 0.5\nbond = 0.0\n',
                    quick=True,
                    set=[f"impact.velocity=[0.0, 0.0, {-SPEED!r}]", f"impact.duration={DURATION!r}",
                         *sets])


def run(folder, np_):
    os.environ.setdefault("WIRENET_BUILD", str(lmp.BUILD))
    case = hard_case(f'impact.body="{BODY}"')
    with pytest.MonkeyPatch.context() as patch:
        if np_ == 2:      # the split through the impact point: materials.in's procs, as -var
            variables = impact.Setup.variables
            patch.setattr(impact.Setup, "variables",
                          lambda self: dict(variables(self), procs="2 1 1"))
        facts = api.run(case, str(folder), ranks=np_)
    assert facts["gravity"] == G
    (folder / "case.json").write_text(json.dumps(facts, indent=2))
    return facts


@pytest.fixture(scope="module")
def serial(tmp_path_factory):
    folder = tmp_path_factory.mktemp("hard_hex_1")
    return folder, run(folder, 1)


@pytest.fixture(scope="module")
def parallel(tmp_path_factory):
    folder = tmp_path_factory.mktemp("hard_hex_2")
    return folder, run(folder, 2)


def energy_rows(folder):
    data = np.genfromtxt(folder / "energy.csv", delimiter=",", names=True)
    return data


def test_every_term_is_active(serial):
    folder, facts = serial
    final = facts["energy"]["final"]
    e0 = facts["energy"]["initial_energy"]
    assert final["w_plastic"] > 1e-3 * e0, final      # wires yielded
    assert final["e_released"] > 0.0, final            # and broke
    assert facts["broken_bonds"] > 0
    rows = (folder / "ruptures.csv").read_text().splitlines()[1:]
    assert len(rows) == facts["broken_bonds"]
    assert final["damping"] > 0.0 and final["friction_block"] > 0.0


def test_block_potential_energy_is_minus_m_g_dz(serial):
    folder, facts = serial
    e = energy_rows(folder)
    block = np.genfromtxt(folder / "block.csv", delimiter=",", names=True)
    expected = facts["block"]["mass"] * G * (block["z"] - block["z"][0])
    assert np.max(np.abs(e["pe_block"] - expected)) < 1e-6 * facts["energy"]["initial_energy"]
    assert abs(expected[-1]) > 1e-3 * facts["energy"]["initial_energy"]   # the term matters


def test_energy_closes_within_half_a_percent(serial):
    folder, facts = serial
    assert facts["energy"]["closure_error"] < 0.005, facts["energy"]
    e = energy_rows(folder)
    assert np.max(np.abs(e["closure_error"])) < 0.005


def test_momentum_balances_within_0_2_percent(serial):
    folder, facts = serial
    mom = facts["momentum"]
    assert mom["error"] < 0.002, mom


def test_gravity_impulse_is_the_weight_of_block_and_net(serial):
    """jz_gravity of momentum.csv = -(M + m_net) g t, with the net's mass summed here from the
    data file's diameters and densities (a LIGGGHTS granular atom is a solid sphere)."""
    folder, facts = serial
    atoms = read_data(str(folder / "setup" / "panel.data")).atoms
    m_net = float(np.sum(atoms[:, 6] * np.pi * atoms[:, 5] ** 3 / 6))
    mom = np.genfromtxt(folder / "momentum.csv", delimiter=",", names=True)
    expected = -(facts["block"]["mass"] + m_net) * G * mom["time"]
    assert np.allclose(mom["jz_gravity"], expected, rtol=1e-9, atol=1e-12)
    assert m_net * G * mom["time"][-1] > 0.02 * abs(expected[-1])   # the net counts


def test_two_ranks_cutting_the_contact_region_agree(serial, parallel):
    folder2, facts2 = parallel
    log = (folder2 / "run" / "log.lammps").read_text()
    assert "2 by 1 by 1 MPI processor grid" in log, "the split is not through x = 0"
    # the contact region straddles the cut: nodes touched by the block on both sides of x = 0
    block = np.genfromtxt(folder2 / "block.csv", delimiter=",", names=True)
    assert abs(block["x"][0]) < 0.05      # the block hits the centre, on the cut
    assert facts2["energy"]["closure_error"] < 0.005
    assert facts2["momentum"]["error"] < 0.002
    # bonds broke on both ranks' sides of the cut
    x = np.genfromtxt(folder2 / "ruptures.csv", delimiter=",", names=True)["x"]
    assert np.any(x < 0) and np.any(x > 0), x
    assert_same_tearing(serial, parallel)


def assert_same_tearing(reference, other):
    """Two runs of the tearing impact on different rank counts: the same ruptures to the
    chaos of a tearing net (the round-off of the other summation order may tip a bond at the
    edge of rupture one way or the other: 27 and 28 of about 30 seen) and the same path. Not
    bitwise: the block's contact force is summed over ranks in another order, and the ringing
    contacts amplify that round-off. Before the first rupture the trajectories agree to 1e-4
    of the block's travel; over the whole run, where a rupture more or less (27 and 28) parts
    them, to 1e-2 (5.6e-3 seen with 27 and 28; below 5e-3 when the counts agreed)."""
    (folder1, facts1), (folder, facts) = reference, other
    n1, n = facts1["broken_bonds"], facts["broken_bonds"]
    assert n1 > 10 and abs(n - n1) <= max(2, 0.1 * n1), (n1, n)
    b1 = np.genfromtxt(folder1 / "block.csv", delimiter=",", names=True)
    b = np.genfromtxt(folder / "block.csv", delimiter=",", names=True)
    travel = b1["z"].max() - b1["z"].min()
    gap = np.abs(b1["z"] - b["z"])
    intact = b1["time"] < facts1["first_rupture"]["time"]
    assert intact.sum() > 10
    assert gap[intact].max() < 1e-4 * travel, gap[intact].max()
    assert gap.max() < 1e-2 * travel, gap.max()


@pytest.mark.parametrize("np_", [3, 4])
def test_three_and_four_ranks_agree(serial, tmp_path_factory, np_):
    """On 3 and 4 ranks (materials.in's grid "* * 1": 3 by 1 and 2 by 2, a cut through the
    contact region either way) the budget closes, momentum balances, the ruptures agree as on
    2 ranks, and the block's path agrees to 1e-4 of its travel before the first rupture and
    1e-2 over the run."""
    folder = tmp_path_factory.mktemp(f"hard_hex_{np_}")
    facts = run(folder, np_)
    log = (folder / "run" / "log.lammps").read_text()
    grid = re.search(r"(\d+) by (\d+) by (\d+) MPI processor grid", log)
    assert grid and np.prod([int(g) for g in grid.groups()]) == np_ and grid.group(3) == "1"
    assert facts["energy"]["closure_error"] < 0.005
    assert facts["momentum"]["error"] < 0.002
    assert_same_tearing(serial, (folder, facts))


def test_contact_work_matches_the_block_and_enters_the_budget_once(serial):
    """The block feels only contacts and gravity, so the contact work on it equals the change of
    its kinetic + potential energy (to the integrator's accuracy); the budget's contact terms
    (the energy the block's contact springs hold, e_contact, and what their friction took out,
    friction_block) add up to minus the contact work on block and nodes, each counted once."""
    folder, facts = serial
    raw = impact.read_table(str(folder / "run"))
    d = {k: raw[k] - raw[k][0] for k in ("w_contact_block", "w_contact_net", "ke_block",
                                            "pe_block")}
    mechanical = d["ke_block"] + d["pe_block"]
    assert np.max(np.abs(d["w_contact_block"] - mechanical)) < 1e-3 * np.max(np.abs(mechanical))
    e = energy_rows(folder)
    scale = 1e-9 * facts["energy"]["initial_energy"]
    assert np.allclose(e["e_contact"] + e["friction_block"],
                       -(d["w_contact_block"] + d["w_contact_net"]), rtol=1e-9, atol=scale)
    assert np.allclose(e["e_contact"], raw["e_contact_block"], rtol=1e-9, atol=scale)
    assert e["friction_block"][-1] > 0.0


@pytest.fixture(scope="module")
def bond_damped(tmp_path_factory):
    """The same hard impact with bond damping (5 % of critical) instead of local damping: the
    physical model (runner/dissipation.py)."""
    os.environ.setdefault("WIRENET_BUILD", str(lmp.BUILD))
    folder = tmp_path_factory.mktemp("hard_hex_bond")
    facts = api.run(hard_case("damping.local=0.0", "damping.bond=0.05"), str(folder))
    return folder, facts


def test_bond_damping_budget_closes_and_conserves_momentum(bond_damped):
    """Bond damping dissipates through relative motion only: its term is positive, local
    damping takes nothing and gives no impulse, the budget closes and the momentum balance
    holds with the supports and gravity alone."""
    folder, facts = bond_damped
    energy, mom = facts["energy"], facts["momentum"]
    assert facts["dissipation"] == "physical" and facts["damping"] == 0.0
    assert facts["bond_damping"] == 0.05
    assert energy["final"]["bond_damping"] > 1e-3 * energy["initial_energy"], energy["final"]
    assert energy["final"]["damping"] == 0.0
    assert energy["closure_error"] < 0.005, energy
    assert mom["final"]["jz_damping"] == 0.0
    assert mom["error"] < 0.002, mom
    assert energy["final"]["w_plastic"] > 0 and facts["broken_bonds"] > 0


@pytest.mark.parametrize("which", ["serial", "bond_damped"])
def test_every_mechanism_that_matters_is_needed_to_close_the_budget(which, request):
    """Issue #45: the closure is no accident of terms that cancel: leaving out any one term
    that reaches 1 % of E0 (a mechanism, or a stored or potential energy) opens the budget
    beyond its 0.5 % tolerance, under the paper's model (local damping) and the physical one."""
    folder, facts = request.getfixturevalue(which)
    e = energy_rows(folder)
    e0 = facts["energy"]["initial_energy"]
    names = [n for n in e.dtype.names if n not in ("time", "total", "closure_error")]
    total = sum(e[n] for n in names)
    assert np.max(np.abs(total - e0)) < 0.005 * e0          # all terms: closed
    tested = 0
    for name in names:
        if np.max(np.abs(e[name])) < 0.01 * e0:
            continue
        tested += 1
        assert np.max(np.abs(total - e[name] - e0)) > 0.005 * e0, name
    assert tested >= 5, tested    # block, net, bonds and at least two ways the energy left
