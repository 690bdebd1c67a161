"""Quasi-static punch (inputs/punch.in through runner/kinds/punch.py) on the quick square panel
(1.2 m, 4 x 4 cells of strand rope, cone centred on the middle crossing), run once for the
module:

- equilibrium: at every output step the platter force plus the panel's weight equals the sum of
  the z reactions of the edge supports within 1 % of the peak reaction, and within 1 % of the
  current reaction once the force exceeds 10 % of its peak;
- quasi-statics: the curve agrees with a run four times slower within 1 % of the peak force and
  the kinetic energy stays below 1 % of the work done by the platter;
- pre-load: the centre sits 1 cm (+- 0.2 mm) below its generated position before the punch;
- symmetry: the centred punch on the symmetric panel loads every bond like its images under the
  mirror x -> -x, y -> -y and the swap x <-> y (within 1 % of the largest tension), and the zone
  forces carry the rope family only.
"""

import csv
import json
import os
import re

import numpy as np
import pytest

import lmp
from runner import INPUTS, api, engine, kinds, quasistatic
from runner.errors import RunError
from runner.kinds import punch
from postprocess.datafile import read_data

SQUARE_CONE = 'kind = "punch"\n[panel]\nnet = "square"\n[punch]\nplatter = "cone"\n' \
    '[materials]\nbending = 0.05\n'


def quick_case(text=SQUARE_CONE, *sets):
    """A checked quick punch case (the case-file text with --set overrides)."""
    return api.load(text, quick=True, set=list(sets))


@pytest.fixture(scope="module")
def case(tmp_path_factory):
    os.environ.setdefault("WIRENET_BUILD", str(lmp.BUILD))
    folder = tmp_path_factory.mktemp("punch")
    facts = api.run(quick_case(), str(folder), ranks=1)
    (folder / "case.json").write_text(json.dumps(facts, indent=2))
    return folder, facts


def test_outputs_have_the_contract_headers(case):
    folder, _ = case
    assert (folder / "platter.csv").read_text().splitlines()[0] == "time,displacement,force"
    assert (folder / "zone_forces.csv").read_text().splitlines()[0] == \
        "time,displacement,family,total_tension,max_tension,bonds"


def test_equilibrium_platter_force_balances_the_edge_reactions(case):
    folder, facts = case
    table = punch.read_table(str(folder / "run"))
    assert len(table["force"]) > 20
    assert facts["quasi_static"]["equilibrium_error"] < 0.01
    assert facts["quasi_static"]["equilibrium_error_of_current"] < 0.01
    # the reaction carries the weight of the whole panel (4.8 kg) on top of the platter force
    assert table["weight"][0] == pytest.approx(4.8 * 9.81, rel=1e-6)
    assert table["force"].max() > 1e4
    # the travel from which every row balances within 1 % of its own reaction, recomputed
    start = facts["quasi_static"]["equilibrium_holds_from"]
    assert start is not None and start < 0.5 * table["displacement"][-1]
    rows = table["displacement"] >= start
    gap = np.abs(table["reaction"] - table["weight"] - table["force"])[rows]
    assert np.all(gap <= 0.01 * np.abs(table["reaction"][rows]))


def test_equilibrium_holds_from_finds_the_last_bad_row():
    table = {"displacement": np.array([0.0, 0.1, 0.2, 0.3, 0.4]),
             "weight": np.full(5, 10.0), "force": np.array([0.0, 5.0, 90.0, 190.0, 290.0]),
             "reaction": np.array([10.5, 15.0, 101.5, 200.5, 300.0])}
    # rows 0 (5 %) and 2 (1.5 %) are off by more than 1 %; row 3 is 0.25 % off
    assert quasistatic.equilibrium_holds_from(table) == pytest.approx(0.3)
    assert quasistatic.equilibrium_holds_from(table, upto=3) is None
    assert quasistatic.equilibrium_holds_from(table, tolerance=0.1) == 0.0


def test_quasi_static_evidence(case):
    _, facts = case
    qs = facts["quasi_static"]
    assert qs["slow_factor"] == 4
    assert qs["curve_difference"] < 0.01
    assert qs["kinetic_energy_fraction"] < 0.01
    assert qs["compared_up_to"] > 0.09


def test_preload_moves_the_centre_by_one_centimetre(case):
    """Measured here from the node positions, not from the deck's own stopping variable: the
    node nearest the panel centre, in the data file and in the first frame of the punch (step
    0, the platter just touching)."""
    folder, facts = case
    data = read_data(str(folder / "setup" / "panel.data"))
    centre = data.atoms[np.argmin(np.hypot(data.atoms[:, 2], data.atoms[:, 3]))]
    text = (folder / "run" / "frames" / "nodes.dump").read_text().split("ITEM: TIMESTEP")[1]
    lines = text.splitlines()
    assert int(lines[1]) == 0, "the first frame is not the punch's step 0"
    rows = np.array([l.split() for l in lines[lines.index(
        next(l for l in lines if l.startswith("ITEM: ATOMS"))) + 1:] if l.strip()], float)
    z_now = rows[rows[:, 0] == centre[0], 4][0]
    assert centre[4] - z_now == pytest.approx(0.01, abs=2e-4)
    assert facts["preload"]["centre_sag"] == pytest.approx(centre[4] - z_now, abs=1e-5)


def test_centred_punch_is_symmetric(case):
    folder, _ = case
    data = read_data(str(folder / "setup" / "panel.data"))
    xy = {int(a[0]): a[2:4] for a in data.atoms}
    ref = {}
    for _, _, a1, a2 in data.bonds.astype(int):
        m = 0.5 * (xy[a1] + xy[a2])
        ref[tuple(np.round(m, 6))] = (min(a1, a2), max(a1, a2))
    # last frame of the bond dump: tension per atom pair
    lines = (folder / "run" / "bonds.dump").read_text().splitlines()
    start = max(i for i, l in enumerate(lines) if l.startswith("ITEM: ENTRIES"))
    names = lines[start].split()[2:]
    rows = np.array([[float(v) for v in l.split()] for l in lines[start + 1:] if l.strip()])
    col = {n: k for k, n in enumerate(names)}
    tension = {(int(min(r[col["c_bonds[1]"]], r[col["c_bonds[2]"]])),
                int(max(r[col["c_bonds[1]"]], r[col["c_bonds[2]"]]))): r[col["c_bonds[6]"]]
               for r in rows}
    tmax = max(abs(t) for t in tension.values())
    assert tmax > 1e3
    worst = 0.0
    for (mx, my), pair in ref.items():
        for image in ((-mx, my), (mx, -my), (my, mx)):
            other = ref[tuple(np.round(image, 6))]
            worst = max(worst, abs(tension[pair] - tension[other]) / tmax)
    assert worst < 0.01
    with open(folder / "zone_forces.csv") as fh:
        fams = {row["family"] for row in csv.DictReader(fh) if float(row["total_tension"]) > 0}
    assert fams == {"rope"}


# ---------------------------------------------------------------------------------------------
# Hexagonal panel on the semi-spheroid: the 3.9 g nodes stay on the platter.

@pytest.mark.parametrize("body_model", ["mesh", "analytic"])
def test_hex_nodes_stay_on_the_spheroid(tmp_path, body_model):
    """Quick hexagonal panel, one run (no slow twin) over 2 cm of travel. With the platter's
    facet edges in the panel's symmetry planes, LIGGGHTS lost the contact of the node pair of
    the central twist until the overlap reached 0.75 mm and then threw it off at 10 m/s (kinetic
    energy 100 times the work of the platter, DT bonds torn). Now the net must stay intact, its
    kinetic energy a small fraction of the work done, and the platter force must grow
    monotonically once it carries the net. The trap is the STL's (the analytic spheroid has no
    facet edges); both platter models must pass."""
    import math
    os.environ.setdefault("WIRENET_BUILD", str(lmp.BUILD))
    case = quick_case('kind = "punch"\n[panel]\nnet = "hex"\n[punch]\nplatter = "spheroid"\n',
                      "punch.travel=0.02", f'punch.body="{body_model}"')
    setup = punch.Setup(kinds.of(case), str(tmp_path / "setup"), 0.05)
    variables, every = setup.variables()
    steps = int(math.ceil(setup.travel / (case["punch.speed"] * setup.dt)))
    engine.run(INPUTS / "punch.in", tmp_path / "run", variables, total_steps=steps, dt=setup.dt,
               phase_marker=punch.PRELOAD_MARKER)
    table = punch.read_table(str(tmp_path / "run"))
    assert table["displacement"][-1] == pytest.approx(0.02, abs=2e-3)
    assert table["broken"].max() == 0
    work = quasistatic.work_done(table["displacement"], table["force"])
    loaded = work > 0.01 * work[-1]
    # quick runs are not quasi-static in the first millimetres (KE/W about 0.13 there, 0.03 at
    # the end); a node thrown off makes it about 70
    assert np.max(table["ke"][loaded] / work[loaded]) < 0.25
    assert table["ke"][-1] < 0.05 * work[-1]
    # the force rises with the travel once the net carries the platter. The exact dome (and a
    # 192-segment STL just the same: 62 -> 45 N) shows a dip of 17 N, 5.5 % of the force at 2 cm,
    # at 0.9 cm, where the quick run is far from static; the 48-segment STL 2.0-2.1 % (the round-
    # off of the wire kernel decides). A node thrown off by the facet trap fails the kinetic-
    # energy and rupture checks above and collapses the force, far beyond this dynamic dip.
    drop = 0.08
    f = table["force"][table["displacement"] > 0.005]
    assert np.all(np.diff(f) > -drop * f.max())
    assert f[-1] > 100


@pytest.mark.parametrize("ke_every", [0, 7])
def test_deck_names_a_bad_ke_every(tmp_path, ke_every):
    """The kinetic-energy sampling interval must divide the output interval; the deck says so
    before it reads anything (LIGGGHTS' own message would be 'Illegal fix ave/time command')."""
    os.environ.setdefault("WIRENET_BUILD", str(lmp.BUILD))
    with pytest.raises(RunError, match=r"ke_every = %d must be a positive divisor "
                       r"of every = 1000" % ke_every):
        engine.run(INPUTS / "punch.in", tmp_path, {"ke_every": ke_every, "every": 1000})


def test_speed_control_speeds_up_in_equilibrium_and_keeps_the_curve(case, tmp_path):
    """The equilibrium-controlled speed (inputs/punch.in, label speed_rule) on the quick square
    case: past the twin's half of the travel the speed rises (rows grow longer in travel) while
    every row still balances within 1 % of the peak reaction, and the force at equal travel
    stays on the constant-speed curve of the module's case within 1 % of its peak. The travel
    of each bond dump (zone_forces.csv) is read off punch.csv, not speed x steps."""
    folder, facts = case
    fast = api.run(quick_case(SQUARE_CONE, "punch.quasi_static_check=false", "punch.speed_max=4.0",
                              "punch.equilibrium_target=0.01"), str(tmp_path), ranks=1)
    control = fast["speed_control"]
    assert control["from_travel"] == pytest.approx(0.05)
    assert 1.5 < control["largest_factor"] <= 4.0 + 1e-9
    assert facts["speed_control"]["largest_factor"] == pytest.approx(1.0, abs=1e-6)
    assert fast["quasi_static"]["equilibrium_error"] < 0.01
    ref = punch.read_table(str(folder / "run"))
    run = punch.read_table(str(tmp_path / "run"))
    assert len(run["force"]) < len(ref["force"])          # fewer steps: faster in travel
    steady = run["displacement"] <= ref["displacement"][-1]
    gap = np.abs(run["force"][steady] - np.interp(run["displacement"][steady],
                                                   ref["displacement"], ref["force"]))
    assert gap.max() < 0.01 * ref["force"].max()
    # each dump's travel lies on the punch.csv curve (interpolated at the dump's time)
    with open(tmp_path / "zone_forces.csv") as fh:
        rows = list(csv.DictReader(fh))
    t = np.array([float(r["time"]) for r in rows])
    d = np.array([float(r["displacement"]) for r in rows])
    assert np.all(np.diff(d[::len(set(r["family"] for r in rows))]) > 0)
    assert np.allclose(d, punch.travel_at(run, t), atol=1e-9)


def test_twin_from_the_runs_preload_is_the_twin_with_its_own(case, tmp_path):
    """The 4x slower twin starts from the restart the run writes after its pre-load
    (runner/kinds/punch.Pair). The same twin with a pre-load of its own gives the same punch.csv
    to the last digit: the restart file carries the whole panel (positions, velocities, scaled
    masses, bond history), and the hand-over file is removed afterwards."""
    folder, _ = case
    setup = punch.Setup(kinds.of(quick_case()), str(tmp_path / "setup"), 0.05)
    travel = setup.travel        # a quick twin runs the whole travel (runner/kinds/punch.Pair)
    variables, _ = setup.variables(quasistatic.SLOW_FACTOR, stop_broken=1, travel=travel,
                                   controlled=False)
    engine.run(INPUTS / "punch.in", str(tmp_path / "slow"), variables)
    own = (tmp_path / "slow" / "punch.csv").read_text()
    shared = (folder / "slow" / "punch.csv").read_text()
    assert len(own.splitlines()) > 10
    assert own == shared
    assert "as left in" in (folder / "slow" / "log.lammps").read_text()
    assert not (folder / "run" / "preload.restart").exists()


def grid(log):
    """The processor grid a LIGGGHTS log reports, as integers."""
    match = re.search(r"(\d+) by (\d+) by (\d+) MPI processor grid", log)
    assert match, "no processor grid in the log"
    return [int(g) for g in match.groups()]


@pytest.mark.parametrize("np_", [3, 4])
def test_three_and_four_ranks_agree(case, tmp_path, np_):
    """The run alone (no twin) on 3 and 4 ranks (materials.in's "* * 1": 3 by 1 and 2 by 2)
    gives the 1-rank force curve within 1e-4 of its peak (the same sums in another order;
    1.2e-5 seen) at every travel, and the same first rupture."""
    folder, facts = case
    many = api.run(quick_case(SQUARE_CONE, "punch.quasi_static_check=false"), str(tmp_path),
                   ranks=np_)
    shape = grid((tmp_path / "run" / "log.lammps").read_text())
    assert np.prod(shape) == np_ and shape[2] == 1
    ref = punch.read_table(str(folder / "run"))
    run = punch.read_table(str(tmp_path / "run"))
    assert len(run["force"]) > 10
    inside = run["displacement"] <= ref["displacement"][-1]
    gap = np.abs(run["force"][inside] - np.interp(run["displacement"][inside],
                                                   ref["displacement"], ref["force"]))
    assert gap.max() < 1e-4 * ref["force"].max(), gap.max()
    first = [(f["first_rupture"] or {}).get("step") for f in (facts, many)]
    assert first[0] == first[1], first


def test_an_odd_rank_count_gives_the_run_the_extra_rank(tmp_path):
    """On 3 ranks the run (the longer of the pair) gets 2 and its 4x slower twin 1, so no rank
    is idle (runner/kinds/punch.Pair)."""
    api.run(quick_case(), str(tmp_path), ranks=3)
    for name, procs in (("run", 2), ("slow", 1)):
        log = (tmp_path / name / "log.lammps").read_text()
        assert re.search(rf"Loop time of \S+ on {procs} procs", log), name
        assert np.prod(grid(log)) == procs, name


@pytest.mark.parametrize("kind_text, check, status", [
    ('kind = "punch"\n', True, "not-quasi-static"),
    ('kind = "punch"\n', False, None),
    ('kind = "tensile"\n', True, "not-quasi-static"),
    ('kind = "tensile"\n', False, None),
])
def test_failed_quasi_static_evidence_decides_the_status_only_when_checked(kind_text, check,
                                                                         status):
    """A full punch or tensile test whose quasi-static evidence failed ends not-quasi-static
    (exit 3); with quasi_static_check = false (a dynamic test as another code runs it: YADE's
    punch and tensile examples, `./wirenet bench --only yade`) the evidence is recorded, not
    judged."""
    from runner import casefile
    name = "punch" if "punch" in kind_text else "tensile"
    case = casefile.parse(kind_text + f"[{name}]\nquasi_static_check = {str(check).lower()}\n")
    facts = dict(peak_force=1.0e4, quasi_static=dict(passed=False, kinetic_energy_fraction=0.17,
                                                     equilibrium_error=0.3))
    verdict = kinds.BY_NAME[name](case).verdict(facts)
    assert (verdict[0] if verdict else None) == status
