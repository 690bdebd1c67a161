"""`wirenet-gen fence` (issue #18): a rockfall fence in the form of EAD 340059-00-0106 (ETAG 027).

Checked against the options alone (closed forms of doc/wirenet-gen.md, "fence"): atoms and bonds
per type and family, post and anchor positions, the rope chains (consecutive atoms bonded by a
rope or brake bond of the right type, brakes next to the anchors), the shackles file (format,
consistency with the data file, every shackle within the stated distance of its rope and not one
of its atoms), the mass of every component, the mirror symmetry about the middle module's centre,
bad input (one line, exit 2, no file) and LIGGGHTS reading the fence with a coefficient for every
bond type.

Binaries: $WIRENET_BUILD/bin/wirenet-gen and $WIRENET_BUILD/bin/liggghts (default <repo>/build).
"""

import json
import math
import os
import subprocess
from collections import Counter
from pathlib import Path

import numpy as np
import pytest

import lmp

ROOT = Path(__file__).resolve().parents[2]
BUILD = Path(os.environ.get("WIRENET_BUILD", ROOT / "build"))
GEN = BUILD / "bin" / "wirenet-gen"
LIGGGHTS = BUILD / "bin" / "liggghts"

STEEL = 7850.0
HEA200 = (53.83e-4, 3692e-8, 1336e-8, 20.98e-8)   # A, Iy, Iz, It (EN 10365, HEA 200)
HEA200_WIDTH = 0.2                                  # flange width b (EN 10365: 200 mm), the post spheres


def run_gen(cwd, *args):
    assert GEN.exists(), f"{GEN} not built (cmake --build build --target wirenet-gen)"
    return subprocess.run([str(GEN), *args], cwd=cwd, capture_output=True, text=True, timeout=120)


def gen(cwd, *args):
    p = run_gen(cwd, *args)
    assert p.returncode == 0, p.stderr
    return p.stdout


def read_data(path):
    """Header counts, box (3x2), atoms (id type x y z d rho mol), bonds (id type a b)."""
    lines = Path(path).read_text().splitlines()
    head, box = {}, []
    for line in lines[1:]:
        parts = line.split()
        if line.strip() == "Atoms":
            break
        if len(parts) == 2 and parts[1] in ("atoms", "bonds"):
            head[parts[1]] = int(parts[0])
        if len(parts) == 3 and parts[1] in ("atom", "bond"):
            head[parts[1] + "_types"] = int(parts[0])
        if len(parts) == 4 and parts[2].endswith("lo"):
            box.append((float(parts[0]), float(parts[1])))
    a0, b0 = lines.index("Atoms") + 2, lines.index("Bonds") + 2
    atoms = np.array([l.split() for l in lines[a0:a0 + head["atoms"]]], dtype=float)
    bonds = np.array([l.split() for l in lines[b0:b0 + head["bonds"]]], dtype=int)
    return head, np.array(box), atoms, bonds


def read_shackles(path):
    """The .shackles file, strictly: '#' comments, 'ropes R', R rope lines, 'shackles S', S lines."""
    lines = [l for l in Path(path).read_text().splitlines() if not l.startswith("#")]
    words = lines[0].split()
    assert words[0] == "ropes" and len(words) == 2
    nr = int(words[1])
    ropes = {}
    for line in lines[1:1 + nr]:
        v = [int(w) for w in line.split()]
        assert len(v) == v[1] + 2, line[:80]
        assert v[0] not in ropes
        ropes[v[0]] = v[2:]
    words = lines[1 + nr].split()
    assert words[0] == "shackles" and len(words) == 2
    ns = int(words[1])
    shackles = [tuple(int(w) for w in l.split()) for l in lines[2 + nr:2 + nr + ns]]
    assert all(len(s) == 2 for s in shackles)
    assert len(lines) == 2 + nr + ns           # nothing after the shackles
    return ropes, shackles


# the closed forms below are for upright posts with the top rope sliding through the heads; the
# generator's defaults (10 degree lean, clamped heads) are checked on their own
UPRIGHT = ["--post-tilt", "0", "--head-guides", "slide"]


class Fence:
    """A generated fence: data, JSON, shackles, and the options it was made with (UPRIGHT)."""

    def __init__(self, tmp_path, args=(), name="f"):
        self.dir = Path(tmp_path)
        self.args = list(args)
        self.stdout = gen(self.dir, "fence", *UPRIGHT, *self.args, "--out", name)
        self.head, self.box, self.atoms, self.bonds = read_data(self.dir / f"{name}.data")
        self.meta = json.loads((self.dir / f"{name}.json").read_text())
        self.ropes, self.shackles = read_shackles(self.dir / f"{name}.shackles")
        self.x = self.atoms[:, 2:5]
        self.type = self.atoms[:, 1].astype(int)
        self.mass = self.atoms[:, 6] * math.pi * self.atoms[:, 5] ** 3 / 6
        opts = dict(zip(self.args[0::2], self.args[1::2]))
        self.o = lambda k, d: type(d)(opts.get("--" + k, d))

    def pos(self, atom_id):
        return self.x[atom_id - 1]

    def bonded(self):
        """{(min id, max id): bond type}"""
        return {(min(a, b), max(a, b)): t for _, t, a, b in self.bonds}


def nround(v):
    """C's round(): halves away from zero (Python's round() rounds halves to even)."""
    return math.floor(v + 0.5)


def expected(f):
    """Closed-form counts from the options (doc/wirenet-gen.md, "fence")."""
    N, s, H = f.o("modules", 3), f.o("spacing", 10.0), f.o("height", 5.0)
    seg, A, Ab = f.o("rope-segment", 0.5), f.o("anchor-distance", 5.0), f.o("bottom-anchor-distance", 2.5)
    U, zu = f.o("upslope-distance", 10.0), f.o("upslope-height", 0.0)
    b, ub, P = f.o("brakes", 1), f.o("upslope-brakes", 1), f.o("post-elements", 5)
    n = max(1, nround(s / seg))
    a = s / n
    mt = max(1, nround((math.hypot(A, H) - a / 2) / seg))
    mb = max(1, nround((Ab - a / 2) / seg))
    mu = max(1, nround(math.hypot(U, H - zu) / seg))
    # the top and bottom edges hang the shackle gap from their ropes' axes, the sides the post gap
    # from their posts' axes: by default the shackle gap from the post's face (its sphere),
    # rounded up to the cm
    gap = f.o("shackle-gap", 0.05)
    post_d, rope_d = f.o("post-node-diameter", HEA200_WIDTH), f.o("support-rope-diameter", 0.022)
    post_gap = f.o("post-gap", math.ceil(100 * (gap + post_d / 2) - 1e-9) / 100)
    return dict(N=N, s=s, H=H, a=a, n=n, mt=mt, mb=mb, mu=mu, b=b, ub=ub, P=P, A=A, Ab=Ab, U=U, zu=zu,
                gap=gap, post_gap=post_gap, post_d=post_d, rope_d=rope_d)


def panel_args(f):
    """The panel subcommand and options that make one module's net."""
    e = expected(f)
    net = f.o("net", "compound")
    skip = {"--modules", "--spacing", "--height", "--net", "--shackle-gap", "--post-gap", "--side-shackles",
            "--rope-segment",
            "--support-rope-diameter", "--upslope-rope-diameter", "--rope-fill", "--anchor-distance",
            "--bottom-anchor-distance", "--brakes", "--upslope-distance", "--upslope-height",
            "--upslope-brakes", "--post-elements", "--post-area", "--post-iy", "--post-iz", "--post-j",
            "--post-node-diameter", "--density", "--margin", "--ylo"}
    rest = []
    for k, v in zip(f.args[0::2], f.args[1::2]):
        if k in skip:
            continue
        if net != "compound":   # the fence takes the node options with the layer's prefix
            k = k.replace("--hex-", "--").replace("--square-", "--")
        rest += [k, v]
    w, h = e["s"] - 2 * e["post_gap"], e["H"] - 2 * e["gap"]
    return [net, "--width", repr(w), "--height", repr(h), *rest]


def panel(tmp_path, f):
    d = Path(tmp_path) / "panel"
    d.mkdir(exist_ok=True)
    gen(d, *panel_args(f), "--out", "p")
    _, _, atoms, bonds = read_data(d / "p.data")
    return atoms, bonds, json.loads((d / "p.json").read_text())


CASES = {
    "default": [],
    "hex2": ["--net", "hex", "--modules", "2", "--spacing", "6", "--height", "4", "--brakes", "2",
             "--upslope-brakes", "0", "--side-shackles", "none", "--rope-segment", "0.7",
             "--post-elements", "3", "--hex-node-mass", "wire"],
    "square1": ["--net", "square", "--modules", "1", "--spacing", "8", "--height", "3", "--anchor-distance", "4",
                "--bottom-anchor-distance", "3", "--upslope-distance", "6", "--upslope-height", "1.5",
                "--upslope-brakes", "3", "--elements", "2"],
    "compound5": ["--modules", "5", "--spacing", "4", "--height", "3", "--ties", "2", "--shackle-gap", "0.08",
                  "--support-rope-diameter", "0.016", "--upslope-rope-diameter", "0.018", "--rope-fill", "0.6",
                  "--post-elements", "4", "--rope-segment", "0.45"],
    # the post gap and the post spheres as given (the 50 mm spheres, both gaps 0.05 m, of the
    # generator before the posts' spheres became the profile's width)
    "posts": ["--modules", "2", "--spacing", "5", "--height", "3", "--post-node-diameter", "0.05",
              "--post-gap", "0.05", "--hex-node-mass", "wire"],
}


@pytest.fixture(scope="module", params=list(CASES))
def fence(request, tmp_path_factory):
    tmp = tmp_path_factory.mktemp(request.param)
    f = Fence(tmp, CASES[request.param])
    f.panel = panel(tmp, f)
    return f


def test_counts_per_type_and_family(fence):
    f, e = fence, expected(fence)
    N, P, n, mt, mb, mu, b, ub = (e[k] for k in ("N", "P", "n", "mt", "mb", "mu", "b", "ub"))
    patoms, pbonds, _ = f.panel
    pa, pb = Counter(patoms[:, 1].astype(int)), Counter(pbonds[:, 1])
    atoms = Counter(f.type)
    for t in range(1, 9):
        assert atoms.get(t, 0) == N * pa.get(t, 0), t
    assert atoms[9] == 2 * mt + 2 * mb + 2 * N * n            # support rope nodes
    assert atoms[10] == (N + 1) * (mu - 1)                      # upslope rope nodes
    assert atoms[11] == (N + 1) * (P - 1)
    assert atoms[12] == atoms[13] == N + 1
    assert atoms[14] == 4 + N + 1                               # lateral and upslope anchors
    assert set(atoms) <= set(range(1, 15))
    bonds = Counter(f.bonds[:, 1])
    for t in range(1, 5):
        assert bonds.get(t, 0) == N * pb.get(t, 0), t
    top, bottom = 1 + 2 * mt + N * n, 1 + 2 * mb + N * n
    assert bonds[5] == top + bottom - 4 * b and bonds.get(6, 0) == 4 * b
    assert bonds[7] == (N + 1) * (mu - ub) and bonds.get(8, 0) == (N + 1) * ub
    assert bonds[9] == (N + 1) * P
    assert f.head["atom_types"] == 14 and f.head["bond_types"] == 9
    m = f.meta
    assert m["counts"]["atoms"] == len(f.atoms) and m["counts"]["bonds"] == len(f.bonds)
    assert {int(k): v for k, v in m["counts"]["atoms_per_type"].items() if v} == dict(atoms)
    assert {int(k): v for k, v in m["counts"]["bonds_per_type"].items() if v} == dict(bonds)
    assert m["bond_families"] == {"1": "DT", "2": "SW", "3": "selvedge", "4": "rope", "5": "rope", "6": "brake",
                                  "7": "upslope", "8": "brake", "9": "post"}
    assert m["atom_types"]["14"] == "anchor" and m["atom_types"]["12"] == "post_base"
    # the molecules: 1 hex, 2 square, 3 top rope, 4 bottom rope, 5 upslope, 6 posts, 7 anchors
    mol = f.atoms[:, 7].astype(int)
    assert np.all(mol[np.isin(f.type, [1, 2, 3, 4])] == 1) and np.all(mol[np.isin(f.type, [5, 6, 7, 8])] == 2)
    assert np.all(mol[f.type == 14] == 7) and np.all(mol[np.isin(f.type, [11, 12, 13])] == 6)
    assert np.all(mol[f.type == 10] == 5)
    assert Counter(mol[f.type == 9]) == {3: 2 * mt + N * n, 4: 2 * mb + N * n}


def test_posts_anchors_and_net_positions(fence):
    f, e = fence, expected(fence)
    N, s, H, P = e["N"], e["s"], e["H"], e["P"]
    post_x = [(i - N / 2) * s for i in range(N + 1)]
    assert np.allclose(f.meta["fence"]["post_x"], post_x, atol=1e-12)
    assert all(math.isclose(post_x[i + 1] - post_x[i], s) for i in range(N))
    bases, heads = f.meta["post_bases"], f.meta["post_heads"]
    bonded = f.bonded()
    for i, (b, h) in enumerate(zip(bases, heads)):
        assert f.type[b - 1] == 12 and f.type[h - 1] == 13
        assert np.allclose(f.pos(b), [post_x[i], 0, 0], atol=1e-12)
        assert np.allclose(f.pos(h), [post_x[i], 0, H], atol=1e-12)
        chain = list(range(b, h + 1))                       # base .. head, P beam elements
        assert len(chain) == P + 1
        for k, a in enumerate(chain):
            assert np.allclose(f.pos(a), [post_x[i], 0, H * k / P], atol=1e-12)
        assert all(bonded.get((c, c + 1)) == 9 for c in chain[:-1])
    anchors = {a["name"]: a for a in f.meta["anchors"]}
    X = N * s / 2
    want = {"lateral_left_top": (-X - e["A"], 0, 0), "lateral_right_top": (X + e["A"], 0, 0),
            "lateral_left_bottom": (-X - e["Ab"], 0, 0), "lateral_right_bottom": (X + e["Ab"], 0, 0)}
    for i in range(N + 1):
        want[f"upslope_{i}"] = (post_x[i], e["U"], e["zu"])
    assert set(anchors) == set(want)
    for name, p in want.items():
        a = anchors[name]
        assert f.type[a["id"] - 1] == 14 and np.allclose(f.pos(a["id"]), p, atol=1e-12), name
        assert np.allclose(a["position"], p, atol=1e-12)
    assert sorted(a["id"] for a in anchors.values()) == sorted(np.flatnonzero(f.type == 14) + 1)
    # every net node inside its module, clear of the posts by the post gap and of the support
    # ropes by the shackle gap, the edges exactly there
    g, gp = e["gap"], e["post_gap"]
    net = np.isin(f.type, range(1, 9))
    xn, zn = f.x[net, 0], f.x[net, 2]
    module = np.floor((xn + X) / s)
    assert np.all((module >= 0) & (module < N))
    local = xn + X - module * s
    assert math.isclose(local.min(), gp, abs_tol=1e-9) and math.isclose(local.max(), s - gp, abs_tol=1e-9)
    assert zn.min() >= g - 1e-9 and zn.max() <= H - g + 1e-9
    assert math.isclose(zn.min(), g, abs_tol=1e-9) and math.isclose(zn.max(), H - g, abs_tol=1e-9)
    assert math.isclose(f.meta["fence"]["shackle_gap"], g) and math.isclose(f.meta["fence"]["post_gap"], gp)
    # no net sphere touches a post or support-rope sphere; by default the side nodes clear the post
    # spheres by at least what the top and bottom nodes clear the rope spheres
    r = f.atoms[:, 5] / 2
    assert np.allclose(r[np.isin(f.type, [11, 12, 13])], e["post_d"] / 2)
    assert np.allclose(r[f.type == 9], e["rope_d"] / 2)
    r_net = r[net].max()
    for part in ([11, 12, 13], [9]):
        clear = min((np.linalg.norm(f.x[net] - f.x[j], axis=1) - r[net] - r[j]).min()
                    for j in np.flatnonzero(np.isin(f.type, part)))
        assert clear > 0, part
        if part == [11, 12, 13] and "--post-gap" not in f.args:
            assert gp - r_net - e["post_d"] / 2 >= g - r_net - e["rope_d"] / 2
    # the square layer (or a lone hex layer) in the plane of the posts; a compound's hex layer upslope
    y = f.x[net, 1]
    if f.o("net", "compound") == "compound":
        assert set(np.round(y, 12)) == {0.0, round(f.meta["fence"]["hex_y"], 12)} and f.meta["fence"]["hex_y"] > 0
    else:
        assert np.all(y == 0)
    target = f.meta["impact_target"]
    assert np.allclose(target, [post_x[N // 2] + s / 2, 0, H / 2], atol=1e-12)
    assert f.meta["normal"] == [0, 1, 0]
    # the box holds every node
    assert np.all(f.x >= f.box[:, 0]) and np.all(f.x < f.box[:, 1])


def test_ropes_are_chains_of_rope_and_brake_bonds(fence):
    f, e = fence, expected(fence)
    bonded = f.bonded()
    meta_ropes = {r["id"]: r for r in f.meta["shackles"]["ropes"]}
    assert set(meta_ropes) == set(f.ropes)
    assert meta_ropes[1]["name"] == "top_support" and meta_ropes[2]["name"] == "bottom_support"
    anchors = {a["name"]: a["id"] for a in f.meta["anchors"]}
    b = e["b"]
    for rid, level, leg in ((1, "top", e["mt"]), (2, "bottom", e["mb"])):
        ids = f.ropes[rid]
        assert meta_ropes[rid]["atoms"] == len(ids) == 2 + 2 * leg + e["N"] * e["n"]
        assert ids[0] == anchors[f"lateral_left_{level}"] and ids[-1] == anchors[f"lateral_right_{level}"]
        assert all(f.type[i - 1] == 9 for i in ids[1:-1])
        types = [bonded.get((min(p, q), max(p, q))) for p, q in zip(ids, ids[1:])]
        assert types == [6] * b + [5] * (len(types) - 2 * b) + [6] * b
        # the horizontal part: straight at the post heads' (bases') level, post spacing / n apart
        z = e["H"] if level == "top" else 0.0
        xs = f.x[np.array(ids) - 1]
        horiz = xs[1 + leg:1 + leg + e["N"] * e["n"]]
        assert np.allclose(horiz[:, 2], z, atol=1e-12) and np.allclose(horiz[:, 1], 0, atol=1e-12)
        assert np.allclose(np.diff(horiz[:, 0]), e["a"], atol=1e-9)
        assert math.isclose(horiz[0, 0], -e["N"] * e["s"] / 2 + e["a"] / 2, abs_tol=1e-9)
        # the legs: straight from the anchor towards the end post, ending half a span bond before it
        X = e["N"] * e["s"] / 2
        for sign, part in ((-1, xs[:leg + 1]), (1, xs[-leg - 1:][::-1])):
            post = np.array([sign * X, 0, z])
            towards = (post - part[0]) / np.linalg.norm(post - part[0])
            assert np.allclose(part[-1], post - e["a"] / 2 * towards, atol=1e-9)
            d = np.diff(part, axis=0)
            assert np.allclose(np.cross(d, d[0]), 0, atol=1e-9)
            assert np.allclose(np.linalg.norm(d, axis=1), np.linalg.norm(d[0]), atol=1e-9)
    # upslope ropes: post head .. upslope anchor, brakes next to the anchor
    ups = f.meta["ropes"]["upslope"]["atoms"]
    assert len(ups) == e["N"] + 1
    for i, ids in enumerate(ups):
        assert ids[0] == f.meta["post_heads"][i] and ids[-1] == anchors[f"upslope_{i}"]
        assert len(ids) == e["mu"] + 1 and all(f.type[k - 1] == 10 for k in ids[1:-1])
        types = [bonded.get((min(p, q), max(p, q))) for p, q in zip(ids, ids[1:])]
        assert types == [7] * (e["mu"] - e["ub"]) + [8] * e["ub"]
        # hanging with the installed sag below the chord: node j at s = j / mu lies on the
        # parabola head + s (anchor - head) - 4 f s (1 - s) z, f = --upslope-sag x the chord
        head, anchor = f.pos(ids[0]), f.pos(ids[-1])
        s = np.arange(len(ids))[:, None] / e["mu"]
        sag = f.o("upslope-sag", 0.1) * np.linalg.norm(anchor - head)
        want = head + s * (anchor - head) - 4 * sag * s * (1 - s) * np.array([0.0, 0.0, 1.0])
        # ... lying on the ground where the parabola would go under it (the deck's ground plane is
        # the support rope's radius below z = 0: a thicker upslope rope lies higher)
        ground = max(0.0, (f.o("upslope-rope-diameter", 0.022) - e["rope_d"]) / 2)
        want[1:-1, 2] = np.maximum(want[1:-1, 2], ground)
        assert np.allclose(f.x[np.array(ids) - 1], want, atol=1e-9)
        assert f.meta["fence"]["upslope_sag"] == f.o("upslope-sag", 0.1)
    # every rope/brake/upslope/post bond is one of these chains
    chains = set()
    for ids in list(f.ropes.values()) + ups:
        chains |= {(min(p, q), max(p, q)) for p, q in zip(ids, ids[1:])}
    for _, t, p, q in f.bonds:
        if t >= 5:
            if t == 9 and f.meta["shackles"]["side"] == "none":
                continue
            assert (min(p, q), max(p, q)) in chains


def seg_distance(p, a, b):
    ab = b - a
    t = np.clip(((p - a) @ ab) / (ab @ ab), 0, 1)
    return np.linalg.norm(p - (a + t * ab))


def test_shackles_file_and_distances(fence):
    f, e = fence, expected(fence)
    g, gp = e["gap"], e["post_gap"]
    meta = f.meta["shackles"]
    assert meta["count"] == len(f.shackles) and meta["file"] == "f.shackles"
    assert math.isclose(meta["gap"], g) and math.isclose(meta["post_gap"], gp)
    atoms = [s[0] for s in f.shackles]
    assert len(set(atoms)) == len(atoms) and atoms == sorted(atoms)
    assert all(1 <= a <= len(f.atoms) for r in f.ropes.values() for a in r)
    per_rope = Counter(r for _, r in f.shackles)
    assert {r["id"]: r["shackles"] for r in meta["ropes"]} == {r: per_rope.get(r, 0) for r in f.ropes}
    side = meta["side"] == "post"
    assert set(f.ropes) == ({1, 2} | (set(range(3, 4 + e["N"])) if side else set()))
    # who hangs where: net edges by type, post heads on the top rope, bases on the bottom rope
    want = {}
    H = e["H"]
    for i in np.flatnonzero(np.isin(f.type, [3, 4, 7, 8])):
        want[i + 1] = 1 if f.x[i, 2] > H / 2 else 2
    if side:
        X = e["N"] * e["s"] / 2
        for i in np.flatnonzero(np.isin(f.type, [2, 6])):
            left = np.floor((f.x[i, 0] + X) / e["s"])
            local = f.x[i, 0] + X - left * e["s"]
            want[i + 1] = 3 + int(left) + (0 if local < e["s"] / 2 else 1)
    for h in f.meta["post_heads"]:
        want[h] = 1
    for b in f.meta["post_bases"]:
        want[b] = 2
    assert dict(f.shackles) == want
    radius = f.atoms[:, 5] / 2
    dmax = 0
    for a, r in f.shackles:
        ids = f.ropes[r]
        assert a not in ids                                   # never an atom of its own rope
        poly = f.x[np.array(ids) - 1]
        p = f.pos(a)
        d = min(seg_distance(p, poly[k], poly[k + 1]) for k in range(len(poly) - 1))
        dmax = max(dmax, d)
        # not on a rope atom: the spheres are clear of each other
        near = np.linalg.norm(poly - p, axis=1)
        assert np.all(near > radius[np.array(ids) - 1] + radius[a - 1]), (a, r)
        if f.type[a - 1] <= 8:
            # a net node away from the end posts' rope corners hangs exactly the gap from its
            # support rope, a module side's node the post gap from its post
            if r <= 2 and abs(p[0]) > e["N"] * e["s"] / 2 - e["a"]:
                continue
            assert math.isclose(d, math.hypot(g if r <= 2 else gp, p[1]), rel_tol=1e-9, abs_tol=1e-12), (a, r, d)
        elif f.type[a - 1] in (12, 13):
            # the rope passes the post base/head at a bond midpoint (the end posts: at a corner)
            assert d <= e["a"] / 2
    assert math.isclose(meta["max_distance"], dmax, rel_tol=1e-9)
    # the farthest: a post head or base at a rope corner, or a side node from its post
    hex_y = f.meta["fence"].get("hex_y", 0.0)
    assert dmax <= max(e["a"] / 2, math.hypot(gp, hex_y) if side else 0.0) + 1e-12


def test_mass_is_the_sum_of_its_components(fence):
    f, e = fence, expected(fence)
    patoms, _, pmeta = f.panel
    lengths = np.linalg.norm(f.x[f.bonds[:, 2] - 1] - f.x[f.bonds[:, 3] - 1], axis=1)
    fill = f.o("rope-fill", 0.65)
    rho = f.o("density", STEEL)
    mu_s = fill * rho * math.pi / 4 * f.o("support-rope-diameter", 0.022) ** 2
    mu_u = fill * rho * math.pi / 4 * f.o("upslope-rope-diameter", 0.022) ** 2
    area = f.o("post-area", HEA200[0])
    t = f.bonds[:, 1]
    support = mu_s * lengths[np.isin(t, [5, 6])].sum()
    upslope = mu_u * lengths[np.isin(t, [7, 8])].sum()
    posts = rho * area * e["H"] * (e["N"] + 1)
    assert math.isclose(rho * area * lengths[t == 9].sum(), posts, rel_tol=1e-12)
    net = e["N"] * pmeta["total_mass"]
    total = f.mass.sum()
    assert math.isclose(total, net + support + upslope + posts, rel_tol=1e-9)
    m = f.meta["mass"]
    for key, v in (("net", net), ("support_ropes", support), ("upslope_ropes", upslope), ("posts", posts),
                   ("total", total)):
        assert math.isclose(m[key], v, rel_tol=1e-9), key
    assert math.isclose(f.meta["total_mass"], total, rel_tol=1e-9)
    # the net's nodes keep the panel's masses; no node is massless
    net_nodes = np.isin(f.type, range(1, 9))
    assert math.isclose(f.mass[net_nodes].sum(), net, rel_tol=1e-9)
    assert np.all(f.mass > 0)
    # the support rope's length: N s between the end posts' neighbours plus the legs, near the geometry
    X = e["N"] * e["s"] / 2
    geometric = e["N"] * e["s"] + 2 * math.hypot(e["A"], e["H"]) + e["N"] * e["s"] + 2 * e["Ab"]
    assert 0.99 * geometric < lengths[np.isin(t, [5, 6])].sum() <= geometric + 1e-9
    assert X > 0


def test_json_records_the_sections_and_types(fence):
    f = fence
    posts = f.meta["posts"]
    A, Iy, Iz, J = (f.o(k, v) for k, v in zip(("post-area", "post-iy", "post-iz", "post-j"), HEA200))
    assert [posts["section"][k] for k in ("A", "Iy", "Iz", "J")] == pytest.approx([A, Iy, Iz, J], rel=1e-12)
    assert posts["orient"] == [1, 0, 0] and posts["bond_type"] == 9 and posts["family"] == "post"
    assert posts["E"] == 2.1e11 and posts["nu"] == 0.3
    user = {"--post-area", "--post-iy", "--post-iz", "--post-j"} & set(f.args[0::2])
    assert posts["section"]["profile"] == ("user" if user else "HEA 200")
    # the post spheres: the HEA 200's width unless given
    assert posts["node_diameter"] == f.o("post-node-diameter", HEA200_WIDTH)
    assert ("node_diameter_note" in posts) == (posts["node_diameter"] == HEA200_WIDTH)
    r = f.meta["ropes"]
    assert (r["support"]["bond_type"], r["support"]["brake_bond_type"], r["support"]["family"]) == (5, 6, "rope")
    assert (r["upslope"]["bond_type"], r["upslope"]["brake_bond_type"], r["upslope"]["family"]) == (7, 8, "upslope")


def test_symmetric_about_the_middle_module(tmp_path):
    f = Fence(tmp_path, [])          # 3 modules: the middle module's centre is x = 0
    c = np.array(f.meta["impact_target"])
    assert c[0] == 0
    mirrored = f.x * [-1, 1, 1] + [2 * c[0], 0, 0]
    key = lambda x, t: [tuple(r) for r in np.column_stack([np.round(x, 9) + 0.0, t])]
    assert sorted(key(f.x, f.type)) == sorted(key(mirrored, f.type))
    # bonds map onto bonds of the same type
    index = {k: i for i, k in enumerate(key(f.x, f.type))}
    mk = key(mirrored, f.type)
    image = np.array([index[k] for k in mk]) + 1
    bonds = {(min(a, b), max(a, b), t) for _, t, a, b in f.bonds}
    assert {(min(image[a - 1], image[b - 1]), max(image[a - 1], image[b - 1]), t) for a, b, t in bonds} == bonds
    # and the shackles onto shackles (ropes of the posts onto the mirror posts)
    N = f.meta["fence"]["modules"]
    mirror_rope = lambda r: r if r <= 2 else 3 + N - (r - 3)
    assert {(image[a - 1], mirror_rope(r)) for a, r in f.shackles} == set(f.shackles)


@pytest.mark.parametrize("args", [[], ["--modules", "1", "--spacing", "4", "--height", "2"]], ids=["default", "quick"])
def test_default_post_gap_keeps_the_net_on_its_lattice(tmp_path, args):
    """The default post gap (0.15 m: the shackle gap from the 0.2 m post spheres' surface) leaves
    the side edges 10 mm beyond a column of the hexagonal mesh, which the panel merges: no net bond
    is shorter than the lattice's 40 mm, as the stable time step wants (0.14 m, the bare equal
    clearance, left 15 and 20 mm bonds and cut the step by 20-30 %; doc/wirenet-gen.md)."""
    gen(tmp_path, "fence", *args, "--out", "f")
    _, _, atoms, bonds = read_data(tmp_path / "f.data")
    meta = json.loads((tmp_path / "f.json").read_text())
    assert meta["fence"]["post_gap"] == 0.15 and meta["posts"]["node_diameter"] == HEA200_WIDTH
    x = {int(a[0]): a[2:5] for a in atoms}
    net = bonds[bonds[:, 1] <= 4]
    lengths = np.linalg.norm(np.array([x[a] - x[b] for a, b in net[:, 2:4]]), axis=1)
    assert lengths.min() >= 0.04 - 1e-9


BAD = [
    (["--modules", "0"], "--modules must be >= 1 (got 0)"),
    (["--spacing", "-10"], "--spacing must be > 0 (got -10)"),
    (["--height", "nan"], "--height must be a number (got nan)"),
    (["--net", "chain"], "--net must be hex, square or compound (got chain)"),
    (["--side-shackles", "rope"], "--side-shackles must be post or none (got rope)"),
    (["--shackle-gap", "3"], "--shackle-gap must be < --height/2 (got 3)"),
    (["--shackle-gap", "0.01"],
     "--shackle-gap must be > 0.0164, a net node's radius plus a support rope node's radius (got 0.01)"),
    (["--post-gap", "0.1"], "--post-gap must be > 0.1054, a net node's radius plus a post node's radius (got 0.1)"),
    (["--post-gap", "5"], "--post-gap must be < --spacing/2 (got 5)"),
    (["--post-gap", "0"], "--post-gap must be > 0 (got 0)"),
    (["--post-node-diameter", "10"],
     "--post-gap must be < --spacing/2 (got 5.05, its default from --shackle-gap and --post-node-diameter)"),
    (["--rope-segment", "0"], "--rope-segment must be > 0 (got 0)"),
    (["--rope-segment", "0.02"], "--rope-segment 0.02 gives the support rope's bond"),
    (["--brakes", "-1"], "--brakes must be >= 0 (got -1)"),
    (["--brakes", "6"], "--brakes must be <= 5, the bonds between a lateral anchor and the end post (got 6)"),
    (["--upslope-brakes", "25"], "--upslope-brakes must be <= 24, the bonds of an upslope rope (got 25)"),
    (["--upslope-height", "5"], "--upslope-height must be < --height (got 5 >= 5)"),
    (["--bottom-anchor-distance", "0.3"], "--bottom-anchor-distance must be >= the support rope's bond"),
    (["--rope-fill", "1.5"], "--rope-fill must be <= 1 (got 1.5)"),
    (["--ties", "2", "--net", "hex"], "--ties needs --net compound (got --net hex)"),
    (["--hex-axis-distance", "1"], "unknown option --hex-axis-distance"),
    (["--axis-distance", "20"], "--axis-distance must be <= --spacing - 2 x --post-gap (got 20 > 9.7)"),
    (["--cell", "6", "--net", "square"], "--cell must be <= (--height - 2 x --shackle-gap) (got 6 > 4.9)"),
    (["--post-iy", "0"], "--post-iy must be > 0 (got 0)"),
    (["--post-elements", "2.5"], "--post-elements must be an integer (got 2.5)"),
    (["--ylo", "0"], "--ylo must be below the nodes (got 0)"),
    (["--modules", "1000000"], "more than --max-nodes 5000000"),
    (["--rope-segment", "1e-6", "--post-node-diameter", "1e-9", "--support-rope-diameter", "1e-9"],
     "more than --max-nodes 5000000"),
    (["--colour", "red"], "unknown option --colour"),
    (["--post-tilt", "45"], "--post-tilt must be >= 0 and < 45 degrees (got 45)"),
    (["--head-guides", "glue"], "--head-guides must be slide or clamp (got glue)"),
    (["--post-tilt", "-1"], "--post-tilt must be >= 0 and < 45 degrees (got -1)"),
    (["--post-tilt", "nan"], "--post-tilt must be a number (got nan)"),
    (["--upslope-sag", "-0.1"], "--upslope-sag must be >= 0 (got -0.1)"),
    (["--upslope-sag", "0.6"], "--upslope-sag must be <= 0.5 (got 0.6)"),
]


@pytest.mark.parametrize("args,message", BAD, ids=[" ".join(a) for a, _ in BAD])
def test_bad_input(tmp_path, args, message):
    p = run_gen(tmp_path, "fence", *args, "--out", "f")
    assert p.returncode == 2, (p.returncode, p.stderr)
    lines = p.stderr.splitlines()
    assert len(lines) == 1 and lines[0].startswith("wirenet-gen fence: error: "), p.stderr
    assert message in lines[0], lines[0]
    assert list(tmp_path.iterdir()) == []


# a small fence (two 4 m x 2 m hexagonal modules) for the layout options' checks
SMALL = ["--modules", "2", "--spacing", "4", "--height", "2", "--net", "hex",
         "--anchor-distance", "2", "--bottom-anchor-distance", "1", "--upslope-distance", "3"]


def test_post_tilt_leans_posts_net_and_support_ropes_about_the_ground_line(tmp_path):
    """--post-tilt t turns every part but the upslope ropes about the x axis at the ground:
    (y, z) -> (y cos t - z sin t, y sin t + z cos t); the anchors on the ground stay, each
    upslope rope runs from its leaned head to its anchor (with --upslope-sag 0: straight)."""
    gen(tmp_path, "fence", *SMALL, *UPRIGHT, "--out", "v")
    gen(tmp_path, "fence", *SMALL, "--post-tilt", "12", "--head-guides", "slide", "--out", "t")
    _, _, upright, _ = read_data(tmp_path / "v.data")
    _, _, leaned, _ = read_data(tmp_path / "t.data")
    mv, mt = json.loads((tmp_path / "v.json").read_text()), json.loads((tmp_path / "t.json").read_text())
    t = math.radians(12.0)
    turn = np.array([[1, 0, 0], [0, math.cos(t), -math.sin(t)], [0, math.sin(t), math.cos(t)]])
    ids = upright[:, 0].astype(int)
    upslope = {a for rope in mv["ropes"]["upslope"]["atoms"] for a in rope}
    upslope -= set(mv["post_heads"])                      # the heads lean with the posts
    fixed_part = [i for i in ids if i not in upslope]
    pos_v = {int(r[0]): r[2:5] for r in upright}
    pos_t = {int(r[0]): r[2:5] for r in leaned}
    for i in fixed_part:                                  # same IDs: built in the same order
        assert np.allclose(pos_t[i], turn @ pos_v[i], atol=1e-9), i
    for head in mt["post_heads"]:
        assert pos_t[head][1] == pytest.approx(-2 * math.sin(t)) and pos_t[head][2] == pytest.approx(2 * math.cos(t))
    for a in mt["anchors"]:
        if a["name"].startswith("lateral"):
            assert np.allclose(pos_t[a["id"]], pos_v[a["id"]], atol=1e-12)
        else:
            assert pos_t[a["id"]][1] == pytest.approx(3.0) and pos_t[a["id"]][2] == pytest.approx(0.0)
    assert np.allclose(mt["normal"], [0, math.cos(t), math.sin(t)])
    assert mt["impact_target"] == pytest.approx(list(turn @ np.array(mv["impact_target"])))
    assert mt["fence"]["post_tilt_deg"] == 12


def test_clamped_heads_join_the_top_rope(tmp_path):
    """--head-guides clamp: each post head is an atom of the top rope (the rope bond it sat on
    split in two through it) instead of a shackle sliding on it: one bond more and one shackle
    less per post, the same atoms."""
    gen(tmp_path, "fence", *SMALL, *UPRIGHT, "--out", "s")
    gen(tmp_path, "fence", *SMALL, "--post-tilt", "0", "--head-guides", "clamp", "--out", "c")
    hs = read_data(tmp_path / "s.data")[0]
    hc, _, _, bonds_c = read_data(tmp_path / "c.data")
    meta = json.loads((tmp_path / "c.json").read_text())
    heads = meta["post_heads"]
    assert hc["atoms"] == hs["atoms"] and hc["bonds"] == hs["bonds"] + len(heads)
    ropes_s, shackles_s = read_shackles(tmp_path / "s.shackles")
    ropes_c, shackles_c = read_shackles(tmp_path / "c.shackles")
    assert len(shackles_c) == len(shackles_s) - len(heads)
    assert not set(heads) & {a for a, _ in shackles_c}
    # a long command line: the title stays within LIGGGHTS' 256-byte line (the rest would be read
    # as the next line of the header)
    deep = tmp_path / ("folder_" + "d" * 120)
    deep.mkdir()
    gen(tmp_path, "fence", *SMALL, "--head-guides", "clamp", "--post-tilt", "10", "--out", str(deep / "c"))
    title = (deep / "c.data").read_text().splitlines()[0]
    assert len(title) <= 200 and title.endswith(" ...")
    top = ropes_c[1]
    assert all(h in top for h in heads) and len(top) == len(ropes_s[1]) + len(heads)
    pairs = {frozenset((int(b[2]), int(b[3]))): int(b[1]) for b in bonds_c}
    for a, b in zip(top, top[1:]):                         # a chain of rope or brake bonds
        assert pairs[frozenset((a, b))] in (5, 6), (a, b)


def test_defaults_are_the_fence_that_comes_to_rest(tmp_path):
    """Without options the fence leans 10 degrees and clamps the top rope at the post heads
    (inputs/fence.in brings that fence to rest: tests/python/test_fence.py)."""
    gen(tmp_path, "fence", *SMALL, "--out", "d")
    gen(tmp_path, "fence", *SMALL, "--post-tilt", "10", "--head-guides", "clamp", "--out", "e")
    assert (tmp_path / "d.data").read_text().split("\n", 1)[1] == \
        (tmp_path / "e.data").read_text().split("\n", 1)[1]
    assert json.loads((tmp_path / "d.json").read_text())["fence"]["post_tilt_deg"] == 10


def test_bad_out_leaves_no_file(tmp_path):
    (tmp_path / "f.shackles").mkdir()
    p = run_gen(tmp_path, "fence", "--out", "f")
    assert p.returncode == 2 and p.stderr.count("\n") == 1 and "f.shackles" in p.stderr
    assert sorted(x.name for x in tmp_path.iterdir()) == ["f.shackles"]
    p = run_gen(tmp_path, "fence")
    assert p.returncode == 2 and "--out is required" in p.stderr


def test_help_lists_every_option_with_units_and_defaults(tmp_path):
    out = gen(tmp_path, "fence", "--help")
    for opt in ("--modules", "--spacing", "--height", "--net", "--rope-segment", "--anchor-distance",
                "--bottom-anchor-distance", "--brakes", "--upslope-distance", "--upslope-height",
                "--upslope-brakes", "--post-elements", "--post-area", "--post-iy", "--post-iz", "--post-j",
                "--shackle-gap", "--post-gap", "--post-node-diameter", "--side-shackles", "--axis-distance",
                "--cell", "--hex-node-diameter",
                "--square-node-diameter", "--ties", "--max-nodes", "--out"):
        assert f"  {opt} " in out, opt
    assert "[m] (default: 10)" in out and "(default: compound)" in out
    assert "rounded up to the cm: 0.15)" in out and "EN 10365" in out
    assert list(tmp_path.iterdir()) == []


SUPPORT_CURVE = "0.004 4e8 0.02 8e8 0.03 8.5e8"
SW_CURVE = "0.0019230769 2.5e8 0.0192 3.2195e8 0.35 5.6585e8"


def coefficients(meta):
    """A bond_coeff line for every bond type of the fence, the post section from the JSON."""
    s = meta["posts"]["section"]
    o = meta["posts"]["orient"]
    sup, ups = meta["ropes"]["support"], meta["ropes"]["upslope"]
    lines = {
        1: f"wire diameter 0.0027 curve {SW_CURVE} family DT derived lambda_eps 0.4 lambda_k 0.66 nu 0.3",
        2: f"wire diameter 0.0027 curve {SW_CURVE} family SW",
        3: f"wire diameter 0.0034 curve {SW_CURVE} family selvedge",
        4: "beam diameter 0.01 E 6e10 nu 0.3 bending 0.05 family rope",
        sup["bond_type"]: f"wire diameter {sup['diameter']!r} curve {SUPPORT_CURVE} family rope",
        sup["brake_bond_type"]: "brake force 6e4 stroke 1.0 stiffness 5e6 family brake",
        ups["bond_type"]: f"wire diameter {ups['diameter']!r} curve {SUPPORT_CURVE} family upslope",
        ups["brake_bond_type"]: "brake force 3e4 stroke 0.5 stiffness 3e6 family brake",
        meta["posts"]["bond_type"]: (f"beam section {s['A']!r} {s['Iy']!r} {s['Iz']!r} {s['J']!r} "
                                     f"orient {o[0]} {o[1]} {o[2]} E {meta['posts']['E']!r} "
                                     f"nu {meta['posts']['nu']!r} family post"),
    }
    assert sorted(lines) == list(range(1, 10))
    return "\n".join(f"bond_coeff {t} {lines[t]}" for t in sorted(lines))


@pytest.mark.skipif(not LIGGGHTS.exists(), reason="LIGGGHTS not built")
@pytest.mark.parametrize("args", [[], ["--net", "hex", "--modules", "2", "--spacing", "5", "--height", "3"]])
def test_liggghts_reads_the_fence(tmp_path, args):
    f = Fence(tmp_path, args)
    heads = " ".join(str(i) for i in f.meta["post_heads"])
    bases = " ".join(str(i) for i in f.meta["post_bases"])
    anchors = " ".join(str(a["id"]) for a in f.meta["anchors"])
    deck = "\n".join([lmp.PREAMBLE, "read_data f.data", "bond_style wirenet", coefficients(f.meta),
                      f"group bases id {bases}", f"group heads id {heads}", f"group anchors id {anchors}",
                      "compute bl all wirenet/local", "variable nb equal f_wirenet_bonds",
                      "thermo_style custom step atoms v_nb", "timestep 1e-6", "run 0", ""])
    out = lmp.run_deck(deck, tmp_path)
    assert f"{len(f.atoms)} atoms" in out and f"{len(f.bonds)} bonds" in out
    assert f"{len(f.meta['post_bases'])} atoms in group bases" in out
    assert f"{len(f.meta['anchors'])} atoms in group anchors" in out
    rows = lmp.thermo_rows(out)
    assert rows and rows[-1]["Atoms"] == len(f.atoms) and rows[-1]["nb"] == 0
    # the style took the coefficients of the fence's own types as the JSON describes them
    assert "type 6 brake (brake): force 60000 N" in out and "type 8 brake (brake): force 30000 N" in out
    assert "type 9 beam (post): section A = 0.005383 m^2, Iy = 3.692e-05 m^4, Iz = 1.336e-05 m^4" in out
    assert "orient (1, 0, 0)" in out
