"""Block impact (inputs/impact.in through runner/kinds/impact.py) and the energy tallies it uses.

- a single wire bond pulled past yield, released, reloaded and pulled to rupture: the plastic work
  tallied by the wire-law evaluation equals the area under the envelope minus the elastic
  triangle, and the energy released at rupture is the elastic energy it stored (both against
  numbers computed here from the stress-strain table);
- fix wirenet/contactwork: the work and impulse of a wall/gran contact on a sphere equal the
  sphere's change of kinetic energy and momentum (no other force acts);
- the quick square panel hit by the block (10 m/s, 44.5 kg): the energy budget closes within
  5 % of the initial energy at every output row, and the change of momentum of block + net equals
  the impulse of the support reactions + gravity (block and net) + the local damping within 2 %
  of the block's initial momentum; the budget is not vacuous (the block stops and rebounds, the
  damping and the contacts take out measurable energy);
- the study case writes the contract's CSVs; bad arguments are one-line errors.
"""

import json
import math
import os
import subprocess
import sys

import numpy as np
import pytest

import lmp
from runner import api, casefile, kinds, timestep
from runner.kinds import impact

SW = ((0.0019230769, 2.5e8), (0.0192, 3.2195e8), (0.05, 3.8292e8), (0.15, 5.1219e8),
      (0.25, 5.5854e8), (0.30, 5.6585e8), (0.35, 5.6585e8))
SW_TEXT = " ".join(f"{e!r} {s!r}" for e, s in SW)


# ---------------------------------------------------------------------------------------------
# wire-law tallies

def envelope_area(u, l0, area):
    """Integral of the force-elongation envelope from 0 to u (piecewise linear)."""
    pts = [(0.0, 0.0)] + [(e * l0, s * area) for e, s in SW]
    total = 0.0
    for (u0, f0), (u1, f1) in zip(pts[:-1], pts[1:]):
        if u <= u0:
            break
        hi = min(u, u1)
        fh = f0 + (f1 - f0) * (hi - u0) / (u1 - u0)
        total += 0.5 * (f0 + fh) * (hi - u0)
    return total


def envelope(u, l0, area):
    pts = [(0.0, 0.0)] + [(e * l0, s * area) for e, s in SW]
    us, fs = zip(*pts)
    return float(np.interp(u, us, fs))


def test_plastic_work_and_released_energy_of_one_wire(tmp_path):
    l0, d = 0.04, 0.0027
    area = math.pi * d * d / 4
    ku = SW[0][1] * area / (SW[0][0] * l0)
    atoms = [(1, 1, 0.0, 0.0, 0.0, 0.0108, 7850.0, 1), (2, 1, l0, 0.0, 0.0, 0.0108, 7850.0, 1)]
    lmp.write_data(tmp_path / "pair.data", atoms, [(1, 1, 1, 2)])
    # node 2 is moved: out to u1 = 0.1 l0 (plastic), back to 0.02 l0 (slack, F = 0), out past the
    # last point (rupture at 0.35 l0)
    v, dt = 1.0, 1e-6
    n1 = int(round(0.1 * l0 / (v * dt)))
    n2 = int(round(0.08 * l0 / (v * dt)))
    n3 = int(round(0.36 * l0 / (v * dt)))
    deck = lmp.PREAMBLE + f"""read_data pair.data
bond_style wirenet
bond_coeff 1 wire diameter {d} curve {SW_TEXT}
group end id 2
compute eb all pe bond
variable wpl equal f_wirenet_bonds[3]
variable erel equal f_wirenet_bonds[2]
variable nb equal f_wirenet_bonds[1]
variable eb equal c_eb
thermo_style custom step v_wpl v_erel v_nb v_eb
thermo_modify format float %.17g
timestep {dt}
fix pull end move linear {v} 0 0
thermo {n1}
run {n1}
unfix pull
fix push end move linear {-v} 0 0
thermo {n2}
run {n2}
unfix push
fix pull end move linear {v} 0 0
thermo 100
run {n3}
"""
    rows = lmp.thermo_rows(lmp.run_deck(deck, tmp_path))
    by_step = {int(r["Step"]): r for r in rows}
    u1 = n1 * v * dt
    f1 = envelope(u1, l0, area)
    w_expected = envelope_area(u1, l0, area) - 0.5 * f1 * f1 / ku
    after_pull = by_step[n1]
    assert after_pull["wpl"] == pytest.approx(w_expected, rel=2e-3)
    assert after_pull["eb"] == pytest.approx(0.5 * f1 * f1 / ku, rel=2e-3)
    after_push = by_step[n1 + n2]
    assert after_push["wpl"] == pytest.approx(after_pull["wpl"], rel=1e-12)  # elastic unloading
    assert after_push["eb"] == 0.0                                          # slack
    last = rows[-1]
    assert last["nb"] == 1
    # released: the elastic energy at the last point of the curve; plastic work: the whole
    # envelope up to there minus that elastic energy
    u_last = SW[-1][0] * l0
    f_last = SW[-1][1] * area
    assert last["erel"] == pytest.approx(0.5 * f_last * f_last / ku, rel=5e-3)
    assert last["wpl"] == pytest.approx(envelope_area(u_last, l0, area) - 0.5 * f_last ** 2 / ku,
                                        rel=5e-3)


# ---------------------------------------------------------------------------------------------
# contact work

def test_contactwork_matches_the_kinetic_energy_and_momentum_of_a_bouncing_sphere(tmp_path):
    """A sphere thrown obliquely onto a fixed plane mesh (friction, no gravity, no damping):
    contact work = change of kinetic energy (translation + rotation), impulse = change of
    momentum; friction makes the work negative."""
    gen = subprocess.run([str(lmp.GEN), "shape", "truncated-cube", "--out",
                          str(tmp_path / "cube.stl")], capture_output=True, text=True)
    assert gen.returncode == 0, gen.stderr
    r, rho = 0.01, 7850.0
    m = rho * 4 / 3 * math.pi * r ** 3
    deck = f"""units si
atom_style granular
atom_modify map array sort 0 0
boundary f f f
newton off
communicate single vel yes
region box block -1 1 -1 1 -1 1 units box
create_box 2 box
neighbor 0.005 bin
neigh_modify delay 0
fix m1 all property/global kn peratomtypepair 2 1e6 1e6 1e6 1e6
fix m2 all property/global kt peratomtypepair 2 1e5 1e5 1e5 1e5
fix m3 all property/global gamman peratomtypepair 2 0 0 0 0
fix m4 all property/global gammat peratomtypepair 2 0 0 0 0
fix m5 all property/global coefficientFriction peratomtypepair 2 0.3 0.3 0.3 0.3
fix cube all mesh/surface file cube.stl type 2
create_atoms 1 single 0 0 {0.225 + r + 0.001} units box
set atom 1 diameter {2 * r} density {rho}
velocity all set 1.0 0 -1.0 units box
fix integ all nve/sphere
fix cw0 all wirenet/contactwork mark
fix wall all wall/gran model hooke/stiffness tangential history mesh n_meshes 1 meshes cube
fix cw all wirenet/contactwork since cw0
compute ke all ke
compute kr all erotate/sphere
variable ek equal c_ke+c_kr
variable px equal {m!r}*vx[1]
variable pz equal {m!r}*vz[1]
thermo_style custom step v_ek v_px v_pz f_cw f_cw[1] f_cw[2] f_cw[3] f_cw[5]
thermo_modify format float %.17g
thermo 100
timestep 2e-6
run 3000
"""
    (tmp_path / "in.deck").write_text(deck)
    rows = lmp.thermo_rows(lmp.run_deck(deck, tmp_path))
    first, last = rows[0], rows[-1]
    assert last["pz"] > 0                       # it bounced
    dke = last["ek"] - first["ek"]
    assert last["cw"] < -1e-4 * first["ek"]   # friction took energy out
    assert last["cw"] == pytest.approx(dke, rel=0.01, abs=1e-3 * first["ek"])
    assert last["cw[3]"] == pytest.approx(last["px"] - first["px"], rel=1e-3)
    assert last["cw[5]"] == pytest.approx(last["pz"] - first["pz"], rel=1e-3)


# one granular sphere at rest in a box, integrated: the frame of the contactwork argument tests
ONE_SPHERE = """units si
atom_style granular
boundary f f f
region box block -1 1 -1 1 -1 1 units box
create_box 1 box
create_atoms 1 single 0 0 0 units box
fix integ all nve/sphere
"""


@pytest.mark.parametrize("args,message", [
    ("sinse cw0", "unknown mode 'sinse'"),
    ("pair", "needs bond_style wirenet"),
    ("since", "expected 'fix ID GROUP wirenet/contactwork mark'"),
    ("since nosuch", "mark fix 'nosuch' does not exist"),
    ("since integ", "fix 'integ' is not a 'fix wirenet/contactwork mark'"),
])
def test_contactwork_bad_arguments(tmp_path, args, message):
    deck = ONE_SPHERE + """fix cw all wirenet/contactwork """ + args + "\nrun 1\n"
    out = lmp.run_deck(deck, tmp_path, check=False)
    errors = lmp.error_lines(out)
    assert errors and message in errors[0], out[-1500:]


def test_contactwork_mark_must_come_first(tmp_path):
    deck = ONE_SPHERE + """fix cw all wirenet/contactwork since cw0
fix cw0 all wirenet/contactwork mark
run 1
"""
    out = lmp.run_deck(deck, tmp_path, check=False)
    errors = lmp.error_lines(out)
    assert errors and "define the mark fix 'cw0' before this fix" in errors[0], out[-1500:]


# ---------------------------------------------------------------------------------------------
# the quick square impact

def square_case(*sets):
    """The quick impact on the square panel as the paper modelled it (local damping 0.5 on the
    net's nodes, no bond damping: inputs/cases/impact_square_paper.toml), with --set
    overrides."""
    return api.load('kind = "impact"\n[panel]\nnet = "square"\n[damping]\nlocal = 0.5\n'
                    'bond = 0.0\n', quick=True, set=list(sets))


@pytest.fixture(scope="module")
def square(tmp_path_factory):
    os.environ.setdefault("WIRENET_BUILD", str(lmp.BUILD))
    folder = tmp_path_factory.mktemp("impact")
    facts = api.run(square_case(), str(folder), ranks=1)
    (folder / "case.json").write_text(json.dumps(facts, indent=2))
    return folder, facts


def test_energy_budget_closes(square):
    folder, facts = square
    energy = facts["energy"]
    assert energy["closure_error"] < 0.05, energy
    # E0 is the block's kinetic energy (2225 J) plus a little from the settling net
    assert energy["initial_energy"] == pytest.approx(0.5 * 44.5 * 10.0 ** 2, rel=0.02)
    # not vacuous: the block was stopped, the damping and the contacts took energy out
    at_low = energy["at_lowest_point"]
    assert at_low["ke_block"] < 0.05 * energy["initial_energy"]
    assert at_low["e_elastic"] > 0.2 * energy["initial_energy"]
    assert energy["final"]["damping"] > 0.01 * energy["initial_energy"]
    # the block's contacts: the energy their springs hold plus what their friction took out
    assert energy["final"]["friction_block"] > 0.0
    assert energy["final"]["friction_block"] + energy["final"]["e_contact"] > 0.0
    rows = (folder / "energy.csv").read_text().splitlines()
    assert rows[0].startswith("time,ke_block,ke_net,pe_block,pe_net,e_elastic,w_plastic")


def test_momentum_balance(square):
    folder, facts = square
    mom = facts["momentum"]
    assert mom["error"] < 0.02, mom
    final = mom["final"]
    # the block was stopped and thrown back: its momentum changed by more than 445 N s
    assert final["dpz_block"] > 445.0
    # the supports carried most of it
    assert final["jz_reactions"] > 0.5 * final["dpz_block"]


def test_outputs(square):
    folder, facts = square
    head = {f: (folder / f).read_text().splitlines()[0] for f in
            ("block.csv", "zone_forces.csv", "edges.csv", "ruptures.csv", "momentum.csv")}
    assert head["block.csv"] == "time,x,y,z,vx,vy,vz,force"
    assert head["zone_forces.csv"] == "time,displacement,family,total_tension,max_tension,bonds"
    assert head["edges.csv"].startswith("time,rx,ry,rz,force,left_rx,left_ry,left_rz,left_force,")
    assert head["edges.csv"].endswith(",corners_rx,corners_ry,corners_rz,corners_force")
    assert head["ruptures.csv"] == "time,atom1,atom2,type,family,x,y,z,elongation"
    edges = np.loadtxt(folder / "edges.csv", delimiter=",", skiprows=1)
    assert facts["edge_force_peak"] == pytest.approx(edges[:, 4].max(), rel=1e-12)
    assert facts["edge_force_peak"] > 1e4
    block = np.loadtxt(folder / "block.csv", delimiter=",", skiprows=1)
    assert block[0, 6] == pytest.approx(-10.0, abs=0.01) and block[-1, 6] > 0
    assert facts["broken_bonds"] == 0      # strand ropes are elastic
    # the block force three ways: a 5 ms mean <= a 0.2 ms row mean; the largest instantaneous
    # value sampled at the rows (the first touch's spikes: above the row means here, though a
    # sample need not catch the largest); the windowed peak is the largest 5 ms mean of
    # block.csv's row means
    assert facts["peak_block_force_windowed"] <= facts["peak_block_force"]
    raw = np.genfromtxt(folder / "run" / "impact.csv", delimiter=",", names=True)["force"]
    assert facts["peak_block_force_raw"] == raw.max() > facts["peak_block_force"]
    rows = int(round(facts["force_window"] / (block[1, 0] - block[0, 0])))
    assert facts["force_window"] == pytest.approx(0.005, abs=block[1, 0] - block[0, 0])
    means = np.convolve(block[:, 7], np.ones(rows) / rows, mode="valid")
    assert facts["peak_block_force_windowed"] == pytest.approx(means.max(), rel=1e-9)


def test_edge_loads_add_up_to_the_total_and_mirror_across_the_panel(square):
    """edges.csv's parts (four edges, the corners) are the hold fixes' own reactions: they add up
    to the total to round-off; the block hits the middle of a square panel, so opposite edges
    pull inwards alike (their in-plane pulls cancel in the total, which is why the per-edge
    load is the design load) and carry the same vertical load (the generated mesh and the
    settling are symmetric to a few percent)."""
    folder, facts = square
    e = np.genfromtxt(folder / "edges.csv", delimiter=",", names=True)
    parts = ("left", "right", "bottom", "top", "corners")
    for c in ("rx", "ry", "rz"):
        total = sum(e[f"{p}_{c}"] for p in parts)
        assert np.allclose(total, e[c], rtol=1e-9, atol=1e-9 * np.abs(e[c]).max())
    k = int(np.argmax(e["left_force"]))
    pull = abs(e["left_rx"][k])
    assert pull > 0.2 * e["left_force"][k]                  # an edge is pulled in, not only down
    assert abs(e["left_rx"][k] + e["right_rx"][k]) < 0.1 * pull    # and mirrored by the other
    for a, b in (("left", "right"), ("bottom", "top")):
        assert facts["support_peaks"][a]["force"] == pytest.approx(
            facts["support_peaks"][b]["force"], rel=0.1)
    assert facts["side_force_peak"] == max(facts["support_peaks"][p]["force"] for p in parts[:4])
    assert facts["side_force_peak"] == pytest.approx(max(e[f"{p}_force"].max() for p in parts[:4]))


def test_bad_impact_arguments(tmp_path):
    with pytest.raises(casefile.CaseFileError,
                       match="panel.net: must be one of hex, square, compound, got 'triangle'"):
        api.load('kind = "impact"\n[panel]\nnet = "triangle"\n', quick=True)
    with pytest.raises(casefile.CaseFileError, match="impact.mass: must be >= 0.001, got -1"):
        square_case("impact.mass=-1")
    p = subprocess.run([sys.executable, "-m", "runner", "run", "impact_sqaure", "--out",
                        str(tmp_path / "x")], cwd=lmp.ROOT, capture_output=True, text=True,
                       env=dict(lmp.MPI_ENV, WIRENET_BUILD=str(lmp.BUILD), PATH="/usr/bin:/bin"))
    assert p.returncode != 0
    assert "unknown study or case 'impact_sqaure'" in p.stderr
    assert len(p.stderr.strip().splitlines()) == 1


def test_time_step_is_the_asked_fraction_of_the_stable_step(tmp_path):
    """impact.dt_fraction scales the one stable-step estimate (runner/timestep.py: compute
    wirenet/timestep's step under a loading body) and nothing else: the steps follow the
    duration; outside (0, 1] is refused with the key's name."""
    def setup(folder, fraction):
        case = square_case(f"impact.dt_fraction={fraction}")
        return impact.Setup(kinds.of(case), str(folder), case.impacts[0], 0.05)
    half = setup(tmp_path / "a", 0.5)
    whole = setup(tmp_path / "b", 1.0)
    assert whole.dt == pytest.approx(2 * half.dt, rel=1e-15)
    assert half.dt == 0.5 * timestep.read(tmp_path / "a" / "timestep").loaded
    assert whole.steps == math.ceil(whole.duration / whole.dt)
    with pytest.raises(casefile.CaseFileError, match="impact.dt_fraction: must be <= 1, got 1.5"):
        square_case("impact.dt_fraction=1.5")
    with pytest.raises(casefile.CaseFileError, match="impact.dt_fraction: must be > 0, got 0"):
        square_case("impact.dt_fraction=0.0")
    with pytest.raises(casefile.CaseFileError, match="impact.dt_fraction: must be <= 1"):
        casefile.parse('kind = "impact"\n[impact]\ndt_fraction = 1.2\n')


def test_undamped_impact_momentum_is_carried_by_the_supports(tmp_path):
    """Without local damping (alpha 0) nothing but the supports and gravity acts on block + net
    from outside: their impulses alone equal the change of momentum, and the elastic rope net
    keeps the energy (no damping, no plasticity): the budget closes with kinetic + elastic +
    potential energy and the contact term."""
    os.environ.setdefault("WIRENET_BUILD", str(lmp.BUILD))
    facts = api.run(square_case("damping.local=0.0", "impact.duration=0.03"), str(tmp_path))
    mom = facts["momentum"]
    assert mom["final"]["jz_damping"] == 0.0
    assert mom["error"] < 0.02, mom
    final = mom["final"]
    balance = final["jz_reactions"] + final["jz_gravity"]
    assert final["dpz_total"] == pytest.approx(balance, abs=0.02 * 445.0)
    energy = facts["energy"]
    assert energy["closure_error"] < 0.05, energy
    assert energy["final"]["damping"] == 0.0


def test_contactwork_pair_matches_the_kinetic_energy_of_two_colliding_nodes(tmp_path):
    """Two free node spheres collide off-centre through pair_style gran (friction, no damping);
    a bonded pair elsewhere makes bond_style wirenet present. The work of the pair forces equals
    the change of kinetic energy of the two spheres, the total pair impulse is zero."""
    r, rho = 0.005, 7850.0
    atoms = [(1, 1, 0.0, 0.0, 0.0, 2 * r, rho, 1), (2, 1, 0.0125, 0.004, 0.0, 2 * r, rho, 2),
             (3, 1, 0.5, 0.5, 0.0, 2 * r, rho, 3), (4, 1, 0.54, 0.5, 0.0, 2 * r, rho, 3)]
    lmp.write_data(tmp_path / "four.data", atoms, [(1, 1, 3, 4)])
    deck = lmp.PREAMBLE + f"""communicate single vel yes
read_data four.data
bond_style wirenet
bond_coeff 1 wire diameter 0.0027 curve {SW_TEXT}
fix m1 all property/global kn peratomtypepair 1 1e6
fix m2 all property/global kt peratomtypepair 1 1e5
fix m3 all property/global gamman peratomtypepair 1 0
fix m4 all property/global gammat peratomtypepair 1 0
fix m5 all property/global coefficientFriction peratomtypepair 1 0.4
pair_style gran model hooke/stiffness tangential history
pair_coeff * *
neighbor 0.002 bin
neigh_modify delay 0
group two id 1 2
velocity all set 0 0 0 units box
set atom 1 vx 1.0
set atom 1 vy 0.2
fix integ all nve/sphere
fix cwp all wirenet/contactwork pair
compute ke two ke
compute kr two erotate/sphere
variable ek equal c_ke+c_kr
variable px equal vx[1]
thermo_style custom step v_ek f_cwp f_cwp[3] f_cwp[4] f_cwp[5] v_px
thermo_modify format float %.17g
thermo 100
timestep 1e-6
run 6000
"""
    rows = lmp.thermo_rows(lmp.run_deck(deck, tmp_path))
    first, last = rows[0], rows[-1]
    assert last["px"] < 0.9                             # they collided
    assert last["cwp"] < -1e-3 * first["ek"]            # friction took energy out
    assert last["cwp"] == pytest.approx(last["ek"] - first["ek"], rel=1e-3, abs=1e-6 * first["ek"])
    for k in (3, 4, 5):                                 # action = reaction
        assert abs(last[f"cwp[{k}]"]) < 1e-9
