"""A small hexagonal net pulled until wires break: shared by the MPI and restart tests.

The net comes from `wirenet-gen hex --width 0.6 --height 0.6` (140 nodes, 215 bonds: DT, SW,
selvedge). Its nodes on the x edge at x = -0.3 are held, those at x = +0.3 move along +x, every
other node is free (fix nve/sphere). All bond types carry wire laws: SW with the reference curve and
a random slack (fixed seed), DT derived from the SW curve (Bertrand et al. 2008 scaling), selvedge
with the SW curve at 3.4 mm. With `processors * 1 1` on two ranks the split plane is x = 0, the
middle of the box; the net is shifted by SHIFT so that the plane cuts it between the centre and
the pulled edge.
"""

import subprocess
from pathlib import Path

import lmp

SW_CURVE = ("0.0019230769 2.5e8 0.0192 3.2195e8 0.05 3.8292e8 0.15 5.1219e8 "
            "0.25 5.5854e8 0.30 5.6585e8 0.35 5.6585e8")

COEFFS = f"""bond_style wirenet
bond_coeff 1 wire diameter 0.0027 curve {SW_CURVE} family DT derived lambda_eps 0.4 lambda_k 0.66 nu 0.3
bond_coeff 2 wire diameter 0.0027 curve {SW_CURVE} family SW slack lambda_u 0.05 lambda_f 0.8 seed 12345
bond_coeff 3 wire diameter 0.0034 curve {SW_CURVE} family selvedge
bond_coeff 4 wire diameter 0.0027 curve {SW_CURVE} family rope_unused
"""

# thermo columns of the energy tallies per bond type (fix wirenet_bonds' global array, through
# variables: the fix does not exist before the first run): el_t, rel_t, pl_t, damp_t for the
# types t = 1..4, the totals rel, pl, damp of its global vector and the bond energy eb
TALLY_THERMO = "compute eb all pe bond\n" + "".join(
    f"variable {name}_{t} equal f_wirenet_bonds[{t}][{col}]\n"
    for t in range(1, 5) for col, name in enumerate(("el", "rel", "pl", "damp"), start=1)) + \
    "variable rel equal f_wirenet_bonds[2]\nvariable pl equal f_wirenet_bonds[3]\nvariable damp equal f_wirenet_bonds[4]\n"
TALLY_COLS = " ".join(f"v_{name}_{t}" for t in range(1, 5) for name in ("el", "rel", "pl", "damp")) + \
    " v_rel v_pl v_damp c_eb"

# columns of compute wirenet/local written by the bond dump
BOND_COLS = "c_bl[1] c_bl[2] c_bl[3] c_bl[4] c_bl[5] c_bl[6]"
# columns of the rupture dump (fix wirenet_bonds local array): step atom1 atom2 type x y z elongation
RUPTURE_COLS = " ".join(f"f_wirenet_bonds[{k}]" for k in range(1, 9))


def outgrown_bond(workdir):
    """A deck whose one bond, across the boundary of two ranks (x = 0.08), outgrows the ghosts'
    reach: neighbour lists rebuilt only every 200 steps unchecked while node 2 is pulled at
    30 m/s (0.2 m, 0.06 m further by step 200). Writes long.data into ``workdir``."""
    atoms = [(1, 1, -0.02, 0.0, 0.0, 0.0108, 7850.0, 1), (2, 1, 0.18, 0.0, 0.0, 0.0108, 7850.0, 1)]
    lmp.write_data(workdir / "long.data", atoms, [(1, 1, 1, 2)])
    return lmp.PREAMBLE + f"""processors * 1 1
read_data long.data
neigh_modify delay 0 every 200 check no
bond_style wirenet
bond_coeff 1 wire diameter 0.0027 curve {SW_CURVE}
group pulled id 2
fix pull pulled move linear 30 0 0
timestep 1e-5
run 400
"""


def make_net(workdir, margin_x=0.6):
    """Write workdir/net.data (and .json) with wirenet-gen; x margin room for the pull (the box
    is x = +-(0.3 + margin_x))."""
    workdir = Path(workdir)
    workdir.mkdir(parents=True, exist_ok=True)
    subprocess.run([str(lmp.GEN), "hex", "--width", "0.6", "--height", "0.6", "--margin-x", repr(margin_x),
                    "--out", str(workdir / "net")], check=True, stdout=subprocess.DEVNULL)
    return workdir / "net.data"


# The net is moved by SHIFT along x after reading, so that the split plane x = 0 of two ranks lies
# between two columns of nodes that travel across it as the net stretches.
SHIFT = -0.1


def setup(speed, gamma=0.0, dt=1e-5):
    """Deck up to (not including) the first run: net, laws, edge motion, integration, outputs."""
    damp = f"fix damp free viscous {gamma!r}\n" if gamma else ""
    return lmp.PREAMBLE + f"""processors * 1 1
read_data net.data
displace_atoms all move {SHIFT!r} 0 0 units box
{COEFFS}
region lhs block INF 0 INF INF INF INF units box
group xedge type 2 4
group lhs region lhs
group left intersect xedge lhs
group right subtract xedge left
group free subtract all xedge
fix hold left move linear 0 0 0
fix pull right move linear {speed!r} 0 0
fix integrate free nve/sphere
{damp}compute bl all wirenet/local
variable nb equal f_wirenet_bonds
{TALLY_THERMO}thermo_style custom step atoms v_nb {TALLY_COLS}
thermo_modify format float %.17g
timestep {dt!r}
"""


def outputs(every, atoms=True, ruptures=True):
    """Dumps of bond tensions, ruptures and node positions/velocities, full precision.
    The rupture dump names the history fix, which exists once a run has initialised the style
    (hence `run 0` before it in a fresh deck)."""
    text = f"""dump bd all local {every} bonds.dump {BOND_COLS}
dump_modify bd format "%.0f %.0f %.0f %.17g %.17g %.17g"
"""
    if ruptures:
        text += f"""dump ru all local {every} ruptures.dump {RUPTURE_COLS}
dump_modify ru format "%.0f %.0f %.0f %.0f %.17g %.17g %.17g %.17g"
"""
    if atoms:
        text += f"""dump at all custom {every} atoms.dump id x y z vx vy vz
dump_modify at format "%d %.17g %.17g %.17g %.17g %.17g %.17g"
"""
    return text


def bonds_by_step(workdir):
    """{step: rows atom1 atom2 type length0 strain tension, sorted by (atom1, atom2)}."""
    return {s: lmp.sort_rows(a) for s, a in lmp.dump_local_frames(Path(workdir) / "bonds.dump").items()}


def ruptures_by_step(workdir):
    """{step: rows step atom1 atom2 type x y z elongation, sorted by (atom1, atom2)}."""
    return {s: lmp.sort_rows(a, keys=(1, 2))
            for s, a in lmp.dump_local_frames(Path(workdir) / "ruptures.dump").items()}
