"""wirenet-gen output files: the data file parses and agrees with its JSON, the hex bond-length
histogram matches the cell, masses and boxes are right, STL files are closed and outward with the
analytic volume, and LIGGGHTS 3.8.0 reads the data files and the meshes.

Binary: $WIRENET_BUILD/bin/wirenet-gen (default: <repo>/build/bin). Run with
/usr/bin/python3 -m pytest tests/python/test_generators.py
"""

import csv
import json
import math
import os
import subprocess
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

ROOT = Path(__file__).resolve().parents[2]
BUILD = Path(os.environ.get("WIRENET_BUILD", ROOT / "build"))
GEN = BUILD / "bin" / "wirenet-gen"
LIGGGHTS = BUILD / "bin" / "liggghts"


def gen(tmp_path, *args):
    assert GEN.exists(), f"{GEN} not built (cmake --build build)"
    out = subprocess.run([str(GEN), *args], cwd=tmp_path, capture_output=True, text=True)
    assert out.returncode == 0, out.stderr
    return out.stdout


def read_data(path):
    """Header counts, box, atoms (id type x y z d rho mol) and bonds (id type a b) as arrays."""
    lines = Path(path).read_text().splitlines()
    head = {}
    box = []
    for line in lines[1:]:
        parts = line.split()
        if line.strip() in ("Atoms", "Bonds"):
            break
        if len(parts) == 2 and parts[1] in ("atoms", "bonds"):
            head[parts[1]] = int(parts[0])
        if len(parts) == 4 and parts[2].endswith("lo"):
            box.append((float(parts[0]), float(parts[1])))
    a0 = lines.index("Atoms") + 2
    b0 = lines.index("Bonds") + 2
    atoms = np.array([l.split() for l in lines[a0:a0 + head["atoms"]]], dtype=float)
    bonds = np.array([l.split() for l in lines[b0:b0 + head["bonds"]]], dtype=int)
    return head, np.array(box), atoms, bonds


def bond_lengths(atoms, bonds):
    x = atoms[:, 2:5]
    return np.linalg.norm(x[bonds[:, 2] - 1] - x[bonds[:, 3] - 1], axis=1)


def node_masses(atoms):
    return atoms[:, 6] * math.pi * atoms[:, 5] ** 3 / 6


@pytest.mark.parametrize("kind", ["hex", "square", "compound", "beam"])
def test_data_matches_json(tmp_path, kind):
    gen(tmp_path, kind, "--out", kind)
    head, box, atoms, bonds = read_data(tmp_path / f"{kind}.data")
    meta = json.loads((tmp_path / f"{kind}.json").read_text())
    assert meta["kind"] == kind and meta["generator"] == "wirenet-gen"
    assert meta["counts"]["atoms"] == head["atoms"] == len(atoms)
    assert meta["counts"]["bonds"] == head["bonds"] == len(bonds)
    assert list(atoms[:, 0].astype(int)) == list(range(1, len(atoms) + 1))
    per_type = Counter(atoms[:, 1].astype(int))
    for t, n in meta["counts"]["atoms_per_type"].items():
        assert per_type.get(int(t), 0) == n
    per_bond = Counter(bonds[:, 1])
    for t, n in meta["counts"]["bonds_per_type"].items():
        assert per_bond.get(int(t), 0) == n
    assert bonds[:, 2:].min() >= 1 and bonds[:, 2:].max() <= len(atoms)
    assert np.all(bonds[:, 2] != bonds[:, 3])
    assert np.allclose(box, np.array(meta["box"]).T)
    x = atoms[:, 2:5]
    assert np.all(x >= box[:, 0]) and np.all(x <= box[:, 1])
    assert np.allclose(meta["bbox"], [x.min(axis=0), x.max(axis=0)])
    assert math.isclose(meta["max_bond_length"], bond_lengths(atoms, bonds).max(), rel_tol=1e-9)
    assert math.isclose(meta["total_mass"], node_masses(atoms).sum(), rel_tol=1e-8)


def test_hex_histogram_and_mass(tmp_path):
    gen(tmp_path, "hex", "--out", "h")
    _, _, atoms, bonds = read_data(tmp_path / "h.data")
    lengths = bond_lengths(atoms, bonds)
    dt, sw = lengths[bonds[:, 1] == 1], lengths[bonds[:, 1] == 2]
    # 3 m panel: 37 full-row pairs; every DT a full 40 mm twist, SW 56.6 mm or cut at mid-length.
    assert np.allclose(dt, 0.040, atol=1e-9) and len(dt) == 1387
    full = np.isclose(sw, math.hypot(0.04, 0.04), atol=1e-9)
    half = np.isclose(sw, math.hypot(0.04, 0.04) / 2, atol=1e-9)
    assert np.all(full | half) and full.sum() == 2812 and half.sum() == 76
    assert np.allclose(node_masses(atoms), 0.0039, rtol=1e-9)
    assert np.all(atoms[:, 7] == 1)


def test_areal_mass(tmp_path):
    gen(tmp_path, "hex", "--width", "2", "--height", "1.5", "--areal-mass", "1.3", "--out", "h")
    meta = json.loads((tmp_path / "h.json").read_text())
    assert math.isclose(meta["total_mass"], 1.3 * 3.0, rel_tol=1e-9)
    assert math.isclose(meta["areal_mass"], 1.3, rel_tol=1e-9)


def test_compound_layers(tmp_path):
    gen(tmp_path, "compound", "--ties", "3", "--out", "c")
    _, _, atoms, bonds = read_data(tmp_path / "c.data")
    hexes, squares = atoms[atoms[:, 7] == 1], atoms[atoms[:, 7] == 2]
    assert np.allclose(hexes[:, 4], (0.0108 + 0.010) / 2) and np.all(squares[:, 4] == 0)
    assert set(hexes[:, 1].astype(int)) <= {1, 2, 3, 4} and set(squares[:, 1].astype(int)) <= {5, 6, 7, 8}
    mol = atoms[:, 7]
    cross = mol[bonds[:, 2] - 1] != mol[bonds[:, 3] - 1]
    assert cross.sum() == 9 and np.all(bonds[cross, 1] == 2)


def check_hex_edges(atoms, width, height):
    """Every hex node inside the panel, edge types exactly on their edges (doc/file_formats.md)."""
    x, y, t = atoms[:, 2], atoms[:, 3], atoms[:, 1].astype(int)
    X, Y = width / 2, height / 2
    assert np.all(np.abs(x) <= X) and np.all(np.abs(y) <= Y)
    ex, ey = np.abs(x) == X, np.abs(y) == Y
    expected = np.where(ex & ey, 4, np.where(ex, 2, np.where(ey, 3, 1)))
    assert np.array_equal(t, expected)
    assert (t == 4).sum() == 4


def node_keys(atoms):
    return {(round(x * 1e9), round(y * 1e9), int(t)) for x, y, t in atoms[:, [2, 3, 1]]}


@pytest.mark.parametrize("kind", ["hex", "compound"])
def test_placement_twist_is_the_default(tmp_path, kind):
    gen(tmp_path, kind, "--out", "default")
    gen(tmp_path, kind, "--placement", "twist", "--out", "twist")
    body = [(tmp_path / f"{name}.data").read_text().split("\n", 1)[1] for name in ("default", "twist")]
    assert body[0] == body[1]
    for name in ("default", "twist"):
        cell = json.loads((tmp_path / f"{name}.json").read_text())["cells"]["hex"]
        assert cell["placement"] == "twist" and cell["lattice_origin"] == [0, 0]


@pytest.mark.parametrize("size", [("3", "3"), ("2.5", "1.7"), ("3.13", "2.91")])
def test_placement_wire(tmp_path, size):
    gen(tmp_path, "hex", "--width", size[0], "--height", size[1], "--placement", "wire", "--out", "w")
    _, _, atoms, bonds = read_data(tmp_path / "w.data")
    check_hex_edges(atoms, float(size[0]), float(size[1]))
    x = atoms[:, 2:4]
    mid = np.linalg.norm(0.5 * (x[bonds[:, 2] - 1] + x[bonds[:, 3] - 1]), axis=1)
    nearest = np.argmin(mid)
    assert bonds[nearest, 1] == 2 and mid[nearest] < 1e-9
    # Point symmetric about the SW midpoint, not mirror symmetric (the single wires are inclined).
    keys = node_keys(atoms)
    assert {(-x, -y, t) for x, y, t in keys} == keys
    assert {(-x, y, t) for x, y, t in keys} != keys
    cell = json.loads((tmp_path / "w.json").read_text())["cells"]["hex"]
    assert cell["placement"] == "wire"
    assert np.allclose(cell["lattice_origin"], [-0.02, -0.04], atol=1e-15)


def yade_hexanet_nodes(nx, ny, a, t, h):
    """Node centres of YADE's pack.hexaNet(startAtCorner=True, isSymmetric=False) relative to its
    lower-left corner (py/pack/pack.py): row i of twists from y = i (t + h) to y = i (t + h) + t,
    nx twists per row at x = j a (even rows) or a/2 + j a (odd rows); lx = (nx - 1/2) a,
    ly = ny t + (ny - 1) h; the corner spheres that no twist provides are added."""
    nodes = {(i % 2 * a / 2 + j * a, i * (t + h) + end) for i in range(ny) for j in range(nx) for end in (0, t)}
    lx, ly = (nx - 0.5) * a, ny * t + (ny - 1) * h
    return nodes | {(0, 0), (lx, 0), (0, ly), (lx, ly)}, lx, ly


@pytest.mark.parametrize("nx,ny", [(38, 38), (12, 6), (7, 3)])
def test_placement_corner_matches_yade(tmp_path, nx, ny):
    a, t, h = 0.08, 0.04, 0.04
    expected, lx, ly = yade_hexanet_nodes(nx, ny, a, t, h)
    # 38 x 38 is hexaNet(xLength=3, yLength=3) with its default mos, a, b: the default panel.
    size = [] if nx == ny == 38 else ["--width", repr(lx), "--height", repr(ly)]
    gen(tmp_path, "hex", *size, "--placement", "corner", "--out", "c")
    _, _, atoms, bonds = read_data(tmp_path / "c.data")
    check_hex_edges(atoms, lx, ly)
    rel = atoms[:, 2:4] + [lx / 2, ly / 2]
    assert {(round(x * 1e6), round(y * 1e6)) for x, y in rel} == \
        {(round(x * 1e6), round(y * 1e6)) for x, y in expected}
    assert len(atoms) == 2 * nx * ny + 2
    # The first twist column on x = -W/2: twists of the even rows run along the edge (selvedge).
    left = np.sort(rel[rel[:, 0] == 0, 1])
    rows = np.arange(0, ny, 2) * (t + h)
    assert np.allclose(left[:2 * len(rows)], np.sort(np.concatenate([rows, rows + t])), atol=1e-9)
    per_bond = Counter(bonds[:, 1])
    assert per_bond[1] == nx * ny - ny  # every twist off the x edges keeps its DT bond
    cell = json.loads((tmp_path / "c.json").read_text())["cells"]["hex"]
    assert cell["placement"] == "corner"
    assert np.allclose(cell["lattice_origin"], [-lx / 2, -ly / 2 + t / 2], atol=1e-12)


@pytest.mark.parametrize("kind", ["hex", "compound"])
def test_placement_corner_generic_size(tmp_path, kind):
    """Any size: off the top and right edges every node is a twist end of the lattice started at
    the lower-left corner; the far edges are clipped as usual."""
    W, H, a, t, pitch = 2.5, 1.7, 0.08, 0.04, 0.08
    gen(tmp_path, kind, "--width", str(W), "--height", str(H), "--placement", "corner", "--out", "c")
    _, _, atoms, bonds = read_data(tmp_path / "c.data")
    hexes = atoms[atoms[:, 7] == 1]
    check_hex_edges(hexes, W, H)
    rel = hexes[:, 2:4] + [W / 2, H / 2]
    inner = rel[(hexes[:, 2] != W / 2) & (hexes[:, 3] != H / 2)]
    i = np.round(inner[:, 0] / (a / 2))
    assert np.allclose(i * a / 2, inner[:, 0], atol=1e-9)
    bottom = np.round(inner[:, 1] / pitch)
    top = np.round((inner[:, 1] - t) / pitch)
    is_bottom = np.isclose(bottom * pitch, inner[:, 1], atol=1e-9)
    is_top = np.isclose(top * pitch + t, inner[:, 1], atol=1e-9)
    assert np.all(is_bottom | is_top)
    row = np.where(is_bottom, bottom, top)
    assert np.all((i - row) % 2 == 0)
    assert ((rel[:, 0] == 0) & (np.abs(rel[:, 1] - t) < 1e-9)).sum() == 1


YADE_TENSILE = ROOT / "tests" / "reference" / "yade_tensile"


def read_csv_rows(path):
    with open(path, newline="") as handle:
        return list(csv.DictReader(handle))


def test_placement_symmetric_is_yade_tensile_net(tmp_path):
    """--placement symmetric at 0.96 m x 0.52 m is the net YADE's tensile test builds with
    hexaNet(..., startAtCorner=False, isSymmetric=True) (tests/reference/yade_tensile/): every
    node within 1e-9 m, every one of YADE's 239 links a bond of its family and rest length; the
    only other bonds are the selvedge along the clamped y edges, between nodes of one clamp."""
    gen(tmp_path, "hex", "--width", "0.96", "--height", "0.52", "--placement", "symmetric",
        "--node-radius", "0.0108", "--out", "t")
    _, _, atoms, bonds = read_data(tmp_path / "t.data")
    check_hex_edges(atoms, 0.96, 0.52)
    nodes = read_csv_rows(YADE_TENSILE / "yade_tensile_net.csv")
    links = read_csv_rows(YADE_TENSILE / "yade_tensile_links.csv")
    assert len(nodes) == len(atoms) == 178 and len(links) == 239
    # YADE's frame has the lower-left corner on the origin; WireNet's panel is centred.
    yade = np.array([[float(n["x"]) - 0.48, float(n["y"]) - 0.26, float(n["z"])] for n in nodes])
    x = atoms[:, 2:5]
    dist = np.linalg.norm(yade[:, None, :] - x[None, :, :], axis=2)
    match = dist.argmin(axis=1)  # YADE id -> WireNet atom index
    assert len(set(match)) == 178
    assert dist[np.arange(178), match].max() < 1e-9
    assert np.allclose(atoms[match, 5], [2 * float(n["radius"]) for n in nodes], rtol=0, atol=1e-15)
    assert np.allclose(node_masses(atoms)[match], [float(n["mass"]) for n in nodes], rtol=1e-12)
    # YADE's clamps are WireNet's y edges (types 3, 4), its 3.4 mm edge nodes the x edges (2, 4).
    types = atoms[match, 1].astype(int)
    role = np.array([n["role"] for n in nodes])
    y = x[match, 1]
    assert np.all((role == "fixed") == (y == -0.26)) and np.all((role == "moving") == (y == 0.26))
    assert np.all(np.isin(types[role != "free"], (3, 4))) and np.all(np.isin(types[role == "free"], (1, 2)))
    assert np.all((np.array([n["material"] for n in nodes]) == "edge_3.4mm") == np.isin(types, (2, 4)))
    # Bond by bond: WireNet's bond type of every YADE link, and its length.
    family = {"DT": 1, "SW": 2, "selvedge": 3}
    ours = {frozenset((int(a) - 1, int(b) - 1)): int(t) for t, a, b in bonds[:, 1:4]}
    assert len(ours) == len(bonds)
    length = dict(zip(ours, bond_lengths(atoms, bonds)))
    theirs = set()
    for link in links:
        pair = frozenset((match[int(link["id1"])], match[int(link["id2"])]))
        theirs.add(pair)
        assert ours.get(pair) == family[link["family"]], link
        assert abs(length[pair] - float(link["rest_length"])) < 1e-9, link
    assert Counter(ours[p] for p in theirs) == {1: 81, 2: 144, 3: 14}
    # The rest: 26 selvedge bonds along y = +-0.26 (2 of 0.04 m per edge from the corners, 11 of
    # 0.08 m), both ends in the same clamp (held or moved alike: they never change length).
    extra = [p for p in ours if p not in theirs]
    assert len(extra) == 26 and all(ours[p] == 3 for p in extra)
    inverse = {w: i for i, w in enumerate(match)}
    for p in extra:
        a, b = (inverse[w] for w in p)
        assert role[a] == role[b] != "free" and y[a] == y[b]
    assert Counter(round(length[p], 9) for p in extra) == {0.04: 4, 0.08: 22}
    # The corners (YADE ids 0..3): YADE keeps only the vertical edge-wire link; WireNet that one
    # and the y-edge selvedge.
    for c in range(4):
        at = match[c]
        assert types[c] == 4
        yade_links = [p for p in theirs if at in p]
        ours_at = [p for p in ours if at in p]
        assert len(yade_links) == 1 and len(ours_at) == 2
        (other,) = yade_links[0] - {at}
        assert x[other, 0] == x[at, 0] and abs(abs(x[other, 1] - x[at, 1]) - 0.08) < 1e-9
    cell = json.loads((tmp_path / "t.json").read_text())["cells"]["hex"]
    assert cell["placement"] == "symmetric"
    assert np.allclose(cell["lattice_origin"], [-0.44, -0.24], atol=1e-12)


@pytest.mark.parametrize("size", [("3", "3"), ("2.5", "1.7"), ("0.88", "0.44")])
def test_placement_symmetric_mirror_x(tmp_path, size):
    """Any size: mirror symmetric in x to the bit, row 0 from the lower edge upwards."""
    W, H = float(size[0]), float(size[1])
    gen(tmp_path, "hex", "--width", size[0], "--height", size[1], "--placement", "symmetric", "--out", "s")
    _, _, atoms, _ = read_data(tmp_path / "s.data")
    check_hex_edges(atoms, W, H)
    exact = {(x, y, int(t)) for x, y, t in atoms[:, [2, 3, 1]]}
    assert {(-x + 0.0, y, t) for x, y, t in exact} == exact
    bottom = atoms[atoms[:, 3] == -H / 2]
    assert len(bottom) > 2 and np.all(np.isin(bottom[:, 1], (3, 4)))


def read_stl(path):
    tris = []
    cur = []
    for line in Path(path).read_text().splitlines():
        parts = line.split()
        if parts and parts[0] == "vertex":
            cur.append(tuple(parts[1:4]))
            if len(cur) == 3:
                tris.append(cur)
                cur = []
    return tris


@pytest.mark.parametrize("shape,volume", [
    ("spheroid", 2 / 3 * math.pi * 0.5 ** 2 * 0.15),
    ("cone", math.pi * 0.34 ** 2 * 0.78 / 3),
    ("truncated-cube", 0.45 ** 3 - 4 / 3 * 0.15 ** 3),
])
def test_stl_closed_outward_volume(tmp_path, shape, volume):
    gen(tmp_path, "shape", shape, "--out", "s.stl")
    tris = read_stl(tmp_path / "s.stl")
    edges = Counter()
    for t in tris:
        for i in range(3):
            edges[(t[i], t[(i + 1) % 3])] += 1
    assert all(n == 1 and edges[(b, a)] == 1 for (a, b), n in edges.items())
    p = np.array([[[float(c) for c in v] for v in t] for t in tris])
    v = np.einsum("ij,ij->i", p[:, 0], np.cross(p[:, 1], p[:, 2])).sum() / 6
    assert abs(v / volume - 1) < 0.005
    meta = json.loads((tmp_path / "s.json").read_text())
    assert math.isclose(meta["volume"], v, rel_tol=1e-9)
    if shape == "truncated-cube":
        s, c, m = 0.45, 0.15, 44.5
        h = s / 2
        corner = 2 * (h * h * c ** 3 / 6 - h * c ** 4 / 12 + c ** 5 / 60)
        inertia = m / volume * (s ** 5 / 6 - 8 * corner)
        assert np.allclose(meta["inertia"], inertia * np.eye(3), rtol=1e-9, atol=1e-12)
        assert np.allclose(meta["centroid"], 0, atol=1e-15)
    else:
        z = p[:, :, 2]
        assert z.max() == 0 and math.isclose(z.min(), -meta["parameters"]["height"])


def run_liggghts(tmp_path, deck):
    (tmp_path / "in.deck").write_text(deck)
    out = subprocess.run([str(LIGGGHTS), "-in", "in.deck", "-echo", "none", "-log", "none"],
                         cwd=tmp_path, capture_output=True, text=True, timeout=300)
    return out.returncode, out.stdout + out.stderr


@pytest.mark.skipif(not LIGGGHTS.exists(), reason="LIGGGHTS not built")
@pytest.mark.parametrize("args", [["hex"], ["compound"], ["beam"], ["hex", "--placement", "wire"],
                                  ["compound", "--placement", "corner"], ["hex", "--placement", "symmetric"]])
def test_liggghts_reads_data(tmp_path, args):
    gen(tmp_path, *args, "--out", "net")
    rc, out = run_liggghts(tmp_path, "units si\natom_style hybrid granular molecular\n"
                           "atom_modify map array sort 0 0\nboundary f f f\nnewton off on\n"
                           "read_data net.data\n")
    assert rc == 0 and "ERROR" not in out, out[-2000:]
    meta = json.loads((tmp_path / "net.json").read_text())
    assert f"{meta['counts']['bonds']} bonds" in out


@pytest.mark.skipif(not LIGGGHTS.exists(), reason="LIGGGHTS not built")
def test_liggghts_reads_meshes(tmp_path):
    for shape in ("spheroid", "cone", "truncated-cube"):
        gen(tmp_path, "shape", shape, "--out", f"{shape}.stl")
    deck = """units si
atom_style granular
atom_modify map array sort 0 0
boundary f f f
newton off
communicate single vel yes
region box block -1 1 -1 1 -1 1 units box
create_box 1 box
fix m1 all property/global youngsModulus peratomtype 1e8
fix m2 all property/global poissonsRatio peratomtype 0.3
fix m3 all property/global coefficientRestitution peratomtypepair 1 0.5
fix m4 all property/global coefficientFriction peratomtypepair 1 0.2
pair_style gran model hertz tangential history
pair_coeff * *
timestep 1e-6
fix a all mesh/surface file spheroid.stl type 1
fix b all mesh/surface file cone.stl type 1
fix c all mesh/surface file truncated-cube.stl type 1
fix w all wall/gran model hertz tangential history mesh n_meshes 3 meshes a b c
run 0
"""
    rc, out = run_liggghts(tmp_path, deck)
    assert rc == 0 and "ERROR" not in out, out[-2000:]
    assert out.count("successful") == 3
