"""fix wirenet/damping: Cundall's local damping against its analytical consequences.

Oscillator: node 2 (mass m) on a harmonic bond (stiffness k) to node 1, which is not integrated.
With local damping the net force is (1 - ALPHA) k x while the node moves towards equilibrium and
(1 + ALPHA) k x while it moves away, so each quarter cycle conserves its own energy
m v^2/2 + (1 -+ ALPHA) k x^2/2. Matching them at x = 0 and at the turning points gives the
amplitude ratio sqrt((1 - ALPHA)/(1 + ALPHA)) per half cycle, i.e. ((1 - ALPHA)/(1 + ALPHA))^2 of
the energy kept per cycle (1/9 for ALPHA = 0.5).

Discretisation: in each quarter cycle velocity Verlet conserves a modified energy that differs
from the exact one by O((w dt)^2); the damping force is continuous where x crosses zero and
switches sign at the turning points, where the velocity is O(w^2 A dt) during the one step in
which the switch can be late, so the energy error there is O(ALPHA (w dt)^2) as well. Hence the
ratios are second-order accurate; the test checks the error at w dt = 2 pi/2000 and that halving
dt divides it by about four.
"""

import math

import numpy as np
import pytest

import lmp

L0 = 0.5          # bond rest length, m
D = 0.1           # node diameter, m
RHO = 1000.0      # density, kg/m3
MASS = RHO * math.pi * D ** 3 / 6.0
OMEGA = 2.0 * math.pi              # undamped angular frequency, rad/s (period 1 s)
K = MASS * OMEGA ** 2              # spring stiffness, N/m
A0 = 0.01                          # initial stretch, m


def oscillator_deck(alpha, dt, steps, direction=(1.0, 0.0, 0.0)):
    """Node 2 stretched by A0 along direction; thermo columns: step, displacement, velocity, work."""
    n = np.asarray(direction, float) / np.linalg.norm(direction)
    ux, uy, uz = n
    # LIGGGHTS' bond_style harmonic: E = K (r - r0)^2, so its K is half the spring stiffness.
    return lmp.PREAMBLE + f"""communicate single cutoff {2 * L0!r}
read_data osc.data
bond_style harmonic
bond_coeff 1 {K / 2.0!r} {L0!r}
group mover id 2
fix integ mover nve/sphere
fix damp mover wirenet/damping {alpha!r}
variable u equal ((x[2]-x[1])*{ux!r}+(y[2]-y[1])*{uy!r}+(z[2]-z[1])*{uz!r})-{L0!r}
variable w equal vx[2]*{ux!r}+vy[2]*{uy!r}+vz[2]*{uz!r}
variable r equal sqrt((x[2]-x[1])^2+(y[2]-y[1])^2+(z[2]-z[1])^2)
thermo_style custom step v_u v_w v_r f_damp
thermo_modify format float %.17g
thermo 1
timestep {dt!r}
run {steps}
"""


def write_oscillator(path, direction=(1.0, 0.0, 0.0)):
    n = np.asarray(direction, float) / np.linalg.norm(direction)
    p2 = (L0 + A0) * n
    atoms = [(1, 1, 0.0, 0.0, 0.0, D, RHO, 1), (2, 1, *map(float, p2), D, RHO, 1)]
    lmp.write_data(path, atoms, [(1, 1, 1, 2)])


def run_oscillator(tmp_path, alpha, dt, cycles, np_=1, direction=(1.0, 0.0, 0.0)):
    tmp_path.mkdir(parents=True, exist_ok=True)
    write_oscillator(tmp_path / "osc.data", direction)
    steps = int(round(cycles / dt))
    out = lmp.run_deck(oscillator_deck(alpha, dt, steps, direction), tmp_path, np=np_)
    rows = lmp.thermo_rows(out)
    return {key: np.array([r[key] for r in rows]) for key in rows[0]}


def turning_amplitudes(u):
    """|u| at each turning point, refined by a parabola through the three samples around it."""
    amps = [abs(u[0])]
    for i in range(1, len(u) - 1):
        if abs(u[i]) >= abs(u[i - 1]) and abs(u[i]) > abs(u[i + 1]) and i > 2:
            a, b, c = abs(u[i - 1]), abs(u[i]), abs(u[i + 1])
            denom = a - 2 * b + c
            amps.append(b - (a - c) ** 2 / (8 * denom) if denom else b)
    return np.array(amps)


def ratio_errors(tmp_path, alpha, dt, cycles=3):
    u = run_oscillator(tmp_path, alpha, dt, cycles)["u"]
    amps = turning_amplitudes(u)
    expected = math.sqrt((1 - alpha) / (1 + alpha))
    ratios = amps[1:] / amps[:-1]
    return ratios, np.abs(ratios / expected - 1.0)


@pytest.mark.parametrize("alpha", [0.5, 0.2])
def test_amplitude_ratio_per_half_cycle(tmp_path, alpha):
    dt = 1.0 / 2000.0
    ratios, err = ratio_errors(tmp_path / "a", alpha, dt)
    assert len(ratios) >= 5, ratios
    # (w dt)^2 = 9.9e-6; the bound leaves a factor 10 for the constants of the analysis above
    assert err.max() < 1e-4, (ratios, err)
    # energy kept per full cycle
    kept = (ratios[0::2][:2] * ratios[1::2][:2]) ** 2
    assert np.allclose(kept, ((1 - alpha) / (1 + alpha)) ** 2, rtol=2e-4), kept
    # second order: halving the step divides the error by about four
    _, err_half = ratio_errors(tmp_path / "b", alpha, dt / 2)
    assert err.max() / err_half.max() > 3.0, (err.max(), err_half.max())


def test_undamped_oscillator_keeps_amplitude(tmp_path):
    ratios, _ = ratio_errors(tmp_path, 0.0, 1.0 / 2000.0, cycles=2)
    assert np.allclose(ratios, 1.0, atol=1e-5), ratios


def test_work_closes_the_energy_budget(tmp_path):
    """The reported work equals the change of the oscillator's energy (to the Verlet error)."""
    alpha, dt = 0.5, 1.0 / 4000.0
    d = run_oscillator(tmp_path, alpha, dt, cycles=2.25)
    energy = 0.5 * MASS * d["w"] ** 2 + 0.5 * K * (d["r"] - L0) ** 2
    lost = energy[-1] - energy[0]
    work = d["damp"][-1]
    assert d["damp"][0] == 0.0
    # The damping opposes v(t+dt/2); only in a step where the velocity changes sign between
    # t+dt/2 and t+dt can F_damp . v(t+dt) be positive, and then it is tiny.
    steps = np.diff(d["damp"])
    assert np.all(steps[steps > 0] < 1e-6 * abs(work)), steps.max()
    assert (steps > 0).sum() <= 5
    assert lost < -0.9 * energy[0]
    assert work == pytest.approx(lost, rel=1e-6), (work, lost)


def free_body_deck(alpha, steps, gravity, vz):
    grav = "fix grav all gravity 9.81 vector 0 0 -1\n" if gravity else ""
    return lmp.PREAMBLE + f"""read_data free.data
set atom 1 vx 1.25 vy -0.5 vz {vz!r} omegax 3 omegay -2 omegaz 0.5
fix integ all nve/sphere
{grav}fix damp all wirenet/damping {alpha!r}
variable vx equal vx[1]
variable vy equal vy[1]
variable vz equal vz[1]
variable wx equal omegax[1]
variable wy equal omegay[1]
variable wz equal omegaz[1]
thermo_style custom step v_vx v_vy v_vz v_wx v_wy v_wz f_damp
thermo_modify format float %.17g
thermo 10
timestep 1e-3
run {steps}
"""


def write_free_body(path):
    lmp.write_data(path, [(1, 1, 0.0, 0.0, 0.0, D, RHO, 1)], [], box=((-10, 10), (-10, 10), (-10, 10)))


def test_free_body_keeps_its_velocity_exactly(tmp_path):
    write_free_body(tmp_path / "free.data")
    rows = lmp.thermo_rows(lmp.run_deck(free_body_deck(0.5, 1000, False, 0.75), tmp_path))
    last = rows[-1]
    assert (last["vx"], last["vy"], last["vz"]) == (1.25, -0.5, 0.75)
    assert (last["wx"], last["wy"], last["wz"]) == (3.0, -2.0, 0.5)
    assert last["damp"] == 0.0


def test_constant_force_is_damped_by_the_law(tmp_path):
    """Falling from rest in z under gravity: the setup force (v_z = 0, sign 0) is undamped, every
    later one is (1 - ALPHA) m g, so v_z after N steps = -g dt/2 - (1 - ALPHA) g dt (N - 1/2).
    The force-free horizontal drift and the spin are untouched."""
    alpha, n, dt, g = 0.5, 1000, 1e-3, 9.81
    write_free_body(tmp_path / "free.data")
    rows = lmp.thermo_rows(lmp.run_deck(free_body_deck(alpha, n, True, 0.0), tmp_path))
    last = rows[-1]
    expected = -g * dt / 2 - (1 - alpha) * g * dt * (n - 0.5)
    assert last["vz"] == pytest.approx(expected, rel=1e-12)
    assert (last["vx"], last["vy"]) == (1.25, -0.5)
    assert (last["wx"], last["wy"], last["wz"]) == (3.0, -2.0, 0.5)


@pytest.mark.parametrize("integrate", ["no", "yes"])
def test_viscous_part_decays_a_free_node_geometrically(tmp_path, integrate):
    """`viscous C` adds -C m v and -C I w (I = 0.4 m r^2). On a free node (no force, so the local
    part is zero) velocity Verlet gives, from the setup force -C m v0: v(dt/2) = v0 (1 - C dt/2),
    then (1 - C dt) per step on the half-step velocity and (1 - C dt/2) to the full step:
    v_N = v0 (1 - C dt/2)^2 (1 - C dt)^(N - 1), the spin likewise, to round-off; the work is
    the kinetic energy lost (the tally uses F(t+dt) . v(t+dt), exact only as dt -> 0)."""
    c, n, dt = 5.0, 1000, 1e-3
    write_free_body(tmp_path / "free.data")
    deck = free_body_deck(0.5, n, False, 0.75).replace(
        "wirenet/damping 0.5", f"wirenet/damping 0.5 viscous {c!r} integrate {integrate}")
    if integrate == "yes":
        deck = deck.replace("fix integ all nve/sphere\n", "")
    rows = lmp.thermo_rows(lmp.run_deck(deck, tmp_path))
    factor = (1 - c * dt / 2) ** 2 * (1 - c * dt) ** (n - 1)
    last = rows[-1]
    v0, w0 = np.array([1.25, -0.5, 0.75]), np.array([3.0, -2.0, 0.5])
    assert np.allclose([last["vx"], last["vy"], last["vz"]], factor * v0, rtol=1e-12, atol=0)
    assert np.allclose([last["wx"], last["wy"], last["wz"]], factor * w0, rtol=1e-12, atol=0)
    m, inertia = MASS, 0.4 * MASS * (D / 2) ** 2
    lost = 0.5 * (m * v0 @ v0 + inertia * w0 @ w0) * (factor ** 2 - 1)
    assert last["damp"] == pytest.approx(lost, rel=1e-2)


def test_one_and_two_ranks_agree(tmp_path):
    direction = (1.0, 0.7, -0.4)
    one = run_oscillator(tmp_path / "np1", 0.5, 1.0 / 1000.0, 1.5, np_=1, direction=direction)
    two = run_oscillator(tmp_path / "np2", 0.5, 1.0 / 1000.0, 1.5, np_=2, direction=direction)
    for key in ("u", "w", "damp"):
        assert np.allclose(one[key], two[key], rtol=1e-12, atol=1e-15), key


def test_tally_no_damps_the_same_and_has_no_work_to_output(tmp_path):
    """`tally no` (the punch decks) skips only the bookkeeping: the trajectory is the same to the
    bit, and a reference to the work it did not keep is an error naming the fix."""
    dt, steps = 1.0 / 2000.0, 3000
    for name in ("yes", "no", "ref"):
        (tmp_path / name).mkdir()
        write_oscillator(tmp_path / name / "osc.data")
    base = oscillator_deck(0.3, dt, steps)
    untallied = base.replace("wirenet/damping 0.3", "wirenet/damping 0.3 tally no") \
                    .replace("v_r f_damp", "v_r")
    tallied = lmp.thermo_rows(lmp.run_deck(base, tmp_path / "yes"))
    plain = lmp.thermo_rows(lmp.run_deck(untallied, tmp_path / "no"))
    assert len(plain) == len(tallied) == steps + 1
    assert all(a["u"] == b["u"] and a["w"] == b["w"] for a, b in zip(plain, tallied))
    assert tallied[-1]["damp"] < 0.0
    rc, out = lmp.run_deck_rc(base.replace("wirenet/damping 0.3", "wirenet/damping 0.3 tally no"),
                              tmp_path / "ref")
    assert rc != 0 and lmp.error_lines(out) and "fix wirenet/damping: fix damp keeps no work or " \
        "impulse (tally no); give it 'tally yes' to output f_damp" in lmp.error_lines(out)[0], out[-800:]


def test_integrate_yes_is_nve_sphere_with_the_damping_to_the_bit(tmp_path):
    """`integrate yes`: the fix is the integrator too and damps in the same pass as the second
    half kick, after every post_force fix. A shaken rope under gravity, its anchors held by
    fix wirenet/hold (their v stays 0: the damping leaves them alone in either order): the
    trajectory, the support reaction and the damping's work and impulse are those of
    nve/sphere + wirenet/damping, bit for bit."""
    import test_hold as rope
    rope.rope_data(tmp_path / "rope.data")
    out = ('fix out all print 100 "P $(x[3]) $(z[5]) $(vz[5]) $(omegax[4]) $(f_h[3]) '
           '$(f_damp) $(f_damp[2]) $(f_damp[5])" screen yes')
    base = rope.deck(["fix damp all wirenet/damping 0.4", "fix h ends wirenet/hold 0 0 0", out],
                     steps=3000).replace("fix integ inner nve/sphere", "fix integ all nve/sphere")
    fused = base.replace("fix integ all nve/sphere\n", "") \
                .replace("wirenet/damping 0.4", "wirenet/damping 0.4 integrate yes")
    assert "nve/sphere" not in fused and "integrate yes" in fused
    a = rope.numbers(lmp.run_deck(base, tmp_path, name="in.two"), "P")
    b = rope.numbers(lmp.run_deck(fused, tmp_path, name="in.one"), "P")
    assert len(a) == 30 and np.array_equal(a, b)
    assert a[-1, 5] < 0.0 and np.abs(a[:, 1] - a[0, 1]).max() > 1e-6    # it moved, and damped


@pytest.mark.parametrize("keywords,message", [("integrate yes", "'integrate yes' needs spheres"),
                                              ("viscous 5", "'viscous' needs spheres (per-atom mass and radius)")])
def test_integrate_and_viscous_need_spheres(tmp_path, keywords, message):
    deck = ("units si\natom_style atomic\natom_modify map array\nboundary f f f\n"
            "region b block -1 1 -1 1 -1 1\ncreate_box 1 b\n"
            "mass 1 1.0\ncreate_atoms 1 single 0 0 0\n"
            f"fix damp all wirenet/damping 0.3 {keywords}\nrun 1\n")
    rc, out = lmp.run_deck_rc(deck, tmp_path)
    errors = lmp.error_lines(out)
    assert rc != 0 and len(errors) == 1 and message in errors[0], out[-1500:]


def final_dump(tmp_path, deck, name):
    """Run a deck in tmp_path/name; its final.dump (rows sorted by id) and its output."""
    (tmp_path / name).mkdir()
    out = lmp.run_deck(deck, tmp_path / name)
    return np.loadtxt(tmp_path / name / "final.dump", skiprows=9), out


# The fused pass keeps each atom's dt/2m and dt/2I from one neighbour-list build to the next:
# atoms re-sorted every 50 steps (a build every step) and a tip mass changed between runs; the
# mass changed between two runs without a build in either (LIGGGHTS counts the builds from 0
# again at each run's set-up, so only the run's init clears the factors); or few builds and the
# time step changed within the run (fix dt/reset calls reset_dt).
CHANGES = {"sort_and_set_mass": (["neigh_modify delay 0 every 1 check no"], "sort 50 0.05", ["set group tip mass 0.05"]),
           "set_mass_no_builds": (["neigh_modify delay 5000 every 5000 check no"], "sort 0 0", ["set group tip mass 0.05"]),
           "dt_reset": (["fix dtr free dt/reset 100 1e-6 3e-5 1e-7 units box"], "sort 0 0", [])}


@pytest.mark.parametrize("change", sorted(CHANGES))
def test_integrate_yes_is_nve_sphere_with_the_damping_on_turning_beams(tmp_path, change):
    """`integrate yes` on nodes with torques: a cantilever of beam bonds swung by a tip load,
    over two runs, with the changes of CHANGES. The fused pass kicks the angular velocity only
    of atoms that had a torque. Positions and angular velocities as nve/sphere +
    wirenet/damping's, bit for bit."""
    import test_beam_dynamics as beam
    before, sort, between = CHANGES[change]
    data = beam.make_beam(tmp_path)
    lines = beam.setup_lines(data)
    lines[1] = lines[1].replace("atom_modify map array sort 0 0", "atom_modify map array " + sort)
    # the load before the damping: nve/sphere's damping in post_force damps it too
    lines += before + ["fix load tip addforce 0 0.02 -0.05", "fix damp free wirenet/damping 0.3", "run 1500",
                       *between, "run 1500",
                       "write_dump all custom final.dump id x y z omegax omegay omegaz modify sort id",
                       'print "DT $(dt)"']
    base = "\n".join(lines) + "\n"
    fused = base.replace("fix integrate free nve/sphere\n", "") \
                .replace("wirenet/damping 0.3", "wirenet/damping 0.3 integrate yes")
    assert "nve/sphere" not in fused

    (a, out), (b, _) = final_dump(tmp_path, base, "two"), final_dump(tmp_path, fused, "one")
    assert np.array_equal(a, b)
    assert np.abs(a[:, 4:]).max() > 1e-3               # the nodes turn (torques on the beam)
    if change == "dt_reset":                           # the time step did change
        dt = [float(line.split()[1]) for line in out.splitlines() if line.startswith("DT ")]
        assert len(dt) == 1 and abs(dt[0] / beam.DT - 1.0) > 0.01, dt
    else:                                              # the mass change reaches the motion
        light = final_dump(tmp_path, base.replace("mass 0.05", "mass 0.5"), "light")[0]
        assert np.abs(light[:, 1:4] - a[:, 1:4]).max() > 1e-6


@pytest.mark.parametrize("integrate", ["yes", "no"])
def test_group_all_pass_is_the_per_atom_pass_to_the_bit(tmp_path, integrate):
    """Group all takes the flat pass (the forces two components at a time, the torques per atom
    after them), any other group the per-atom loop. A free beam of 11 nodes (33 force components:
    the odd last one too) swung and twisted by a tip load, torques on every node, with the damping
    as the integrator or after nve/sphere: positions, velocities, angular velocities and the
    damping's work and impulse are the same to the bit whichever pass ran."""
    import test_beam_dynamics as beam
    data = beam.make_beam(tmp_path, n=10)
    lines = beam.setup_lines(data)
    integrator = "fix integrate free nve/sphere"
    assert integrator in lines
    lines[lines.index(integrator)] = "" if integrate == "yes" else "fix integrate all nve/sphere"
    lines += ["group everyone type 1 2 3", "fix load tip addforce 0.01 0.02 -0.05",
              f"fix damp GROUP wirenet/damping 0.3 tally yes integrate {integrate}",
              "thermo_style custom step f_damp[1] f_damp[2] f_damp[3] f_damp[4] f_damp[5]",
              "thermo_modify format float %.17g", "thermo 1000", "run 2000",
              "write_dump all custom final.dump id x y z vx vy vz omegax omegay omegaz modify sort id"]
    deck = "\n".join(lines) + "\n"

    def final(group):
        (tmp_path / group).mkdir()
        rows = lmp.thermo_rows(lmp.run_deck(deck.replace("GROUP", group), tmp_path / group))
        work = np.array([[r[k] for k in sorted(r) if k != "Step"] for r in rows])
        return np.loadtxt(tmp_path / group / "final.dump", skiprows=9), work

    (a, wa), (b, wb) = final("all"), final("everyone")
    assert a.shape == (11, 10) and np.array_equal(a, b)
    assert wa.shape == (3, 5) and np.array_equal(wa, wb)
    assert np.abs(a[:, 7:]).min() > 0.0 and wa[-1, 1] < 0.0   # every node turns; torques damped


@pytest.mark.parametrize("group", ["free", "all"])
def test_alpha_zero_is_nve_sphere_to_the_bit(tmp_path, group):
    """ALPHA 0 without a viscous part (the physical model's impacts, where the fix is only the
    integrator) takes the kick alone, without the damping's pass: a cantilever of beam bonds
    swung and twisted by a tip load over two runs, positions, velocities and angular velocities
    as nve/sphere's to the bit, and the damping's work and impulse zero."""
    import test_beam_dynamics as beam
    data = beam.make_beam(tmp_path)
    lines = beam.setup_lines(data)
    integrator = "fix integrate free nve/sphere"
    assert integrator in lines
    if group == "all":   # every atom integrated (the flat pass), the root held by setforce
        lines = [line.replace("fix integrate free nve/sphere", "fix integrate all nve/sphere") for line in lines]
        lines.append("fix hold root setforce 0 0 0")
    lines += ["fix load tip addforce 0 0.02 -0.05", "run 1500", "run 1500",
              "write_dump all custom final.dump id x y z vx vy vz omegax omegay omegaz modify sort id",
              'print "W $(f_damp) $(f_damp[3]) $(f_damp[4]) $(f_damp[5])"']
    base = "\n".join(lines) + "\n"
    fused = base.replace(f"fix integrate {group} nve/sphere\n",
                         f"fix damp {group} wirenet/damping 0 integrate yes\n")
    base = base.replace('print "W $(f_damp) $(f_damp[3]) $(f_damp[4]) $(f_damp[5])"', "")

    (a, _), (b, out) = final_dump(tmp_path, base, "nve"), final_dump(tmp_path, fused, "fused")
    assert np.array_equal(a, b)
    assert np.abs(a[:, 7:]).max() > 1e-3               # the nodes turn (torques on the beam)
    work = [line.split()[1:] for line in out.splitlines() if line.startswith("W ")]
    assert work == [["0", "0", "0", "0"]], work
