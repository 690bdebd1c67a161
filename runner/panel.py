"""A net panel as the panel kinds (punch, impact) use it: generated from the case's [panel] keys
by wirenet-gen, read back (data file, metadata), its supports rendered into a deck include and
its output zones. Not a kind: the kinds that load a panel share it."""

import math
import os

import numpy as np

from postprocess.datafile import read_data
from postprocess.meta import read_json

from . import supports
from .generator import generate

# case key -> wirenet-gen option for each net (compound prefixes its layers' options)
GENERATOR_OPTIONS = (
    ("panel.placement", {"hex": "--placement", "compound": "--placement"}),
    ("panel.selvedge", {"hex": "--selvedge", "compound": "--selvedge"}),
    ("panel.hex_node_radius", {"hex": "--node-radius", "compound": "--hex-node-radius"}),
    ("panel.hex_node_mass", {"hex": "--node-mass", "compound": "--hex-node-mass"}),
    ("panel.square_node_radius", {"square": "--node-radius", "compound": "--square-node-radius"}),
    ("panel.rope_mass", {"square": "--rope-mass", "compound": "--rope-mass"}),
    ("panel.axis_distance", {"hex": "--axis-distance", "compound": "--axis-distance"}),
    ("panel.twist_length", {"hex": "--twist-length", "compound": "--twist-length"}),
    ("panel.rise", {"hex": "--rise", "compound": "--rise"}),
    ("panel.cell", {"square": "--cell", "compound": "--cell"}),
    ("panel.rope_elements", {"square": "--elements", "compound": "--elements"}),
    # the diameters size the generated net (node spheres, the 'wire' node mass, its metadata) as
    # they size the bonds (materials.in)
    ("materials.wire_d", {"hex": "--wire-diameter", "compound": "--wire-diameter"}),
    ("materials.selvedge_d", {"hex": "--selvedge-diameter", "compound": "--selvedge-diameter"}),
    ("materials.rope_d", {"square": "--rope-diameter", "compound": "--rope-diameter"}),
)


def changed_options(case, pairs):
    """The wirenet-gen options of (case key, option) pairs whose value the case changes from the
    key's default (the generator's own; a node radius's 0 is its 'unset'), so that a case with
    the defaults generates the generator's default net. An option of None: not for this net."""
    options = []
    for path, option in pairs:
        if option and case[path] != case.keys[path].default:
            options += [option, case[path]]
    return options


def generator_options(case, net):
    """wirenet-gen options of the net beyond its kind and size (GENERATOR_OPTIONS)."""
    return changed_options(case, [(path, by_net.get(net)) for path, by_net in GENERATOR_OPTIONS])


# nodes per square metre of the generator's default nets (3 m panels: 2930, 561, 3491 nodes)
NODE_DENSITY = {"hex": 326.0, "square": 62.0, "compound": 388.0}
MAX_NODES = 2_000_000     # a panel beyond this is hours a step-second and gigabytes: refused


def check(case, fail):
    """What makes a panel case meaningless or impossible, from the case file alone (each
    refused with one line naming a key): a panel too large, or held by no edge."""
    w, h = case["panel.width"], case["panel.height"]
    nodes = w * h * NODE_DENSITY[case["panel.net"]]
    if nodes > MAX_NODES:
        fail("panel.width", f"{w:g} m x panel.height {h:g} m is about {nodes:.3g} nodes, more "
                            f"than the {MAX_NODES:.0e} a case may have")
    if all(case[f"supports.{e}"] == "free" for e in supports.EDGES):
        fail("supports", "all four edges are free: nothing holds the net against the load")


def inside(case, offset, reach, fail, key):
    """Refuse a load point (offset from the panel centre) whose load, ``reach`` from it, does
    not lie within the panel."""
    half = (case["panel.width"] / 2, case["panel.height"] / 2)
    for axis, (o, hs) in enumerate(zip(offset, half)):
        if abs(o) + reach >= hs:
            where = "x" if axis == 0 else "y"
            fail(key, f"{list(offset)} puts the load {abs(o) + reach:g} m from the centre in "
                      f"{where}, beyond the panel's half size {hs:g} m (panel.width x "
                      "panel.height)")


def node_masses(data):
    """Masses of the data file's atoms (density x sphere volume)."""
    d = data.atom("diameter")
    return data.atom("density") * math.pi * d ** 3 / 6.0


class Panel:
    """The generated panel of a case: PREFIX.data, PREFIX.json and what the kinds read of them.
    ``extra``: options beyond the case's (an impact raises the box)."""

    def __init__(self, case, setup_dir, extra=()):
        net = case["panel.net"]
        prefix = os.path.join(setup_dir, "panel")
        os.makedirs(setup_dir, exist_ok=True)
        self.net = net
        self.data_path = generate(net, prefix, "--width", case["panel.width"], "--height",
                                  case["panel.height"], *generator_options(case, net), *extra)
        self.json_path = prefix + ".json"
        self.types_path = prefix + ".types.in"    # the type numbers by name (a deck include)
        self.meta = read_json(self.json_path)
        self.data = read_data(self.data_path)
        self.layers = 2 if self.meta.get("kind") == "compound" else 1
        self.masses = node_masses(self.data)

    @property
    def centre(self):
        return np.asarray(self.meta.get("centre", [0.0, 0.0, 0.0]), float)

    def centre_node(self, offset=(0.0, 0.0)):
        """(id, radius) of the node nearest the panel centre (+ offset in x, y) on the loaded
        (topmost) layer."""
        data = self.data
        z = data.atom("z")
        top = z >= z.max() - 1e-9
        centre = self.centre[:2] + np.asarray(offset, float)
        d = np.hypot(data.atom("x") - centre[0], data.atom("y") - centre[1])
        d[~top] = np.inf
        k = int(np.argmin(d))
        return int(data.atom_ids[k]), float(data.atom("diameter")[k] / 2)


def write_supports(case, setup_dir):
    """The deck variables of the case's supports: its rendered include and the matching unfix
    file; none for the paper's (inputs/include/hold.in, unfix_supports.in)."""
    chosen = {e: case[f"supports.{e}"] for e in supports.EDGES}
    if chosen == supports.PAPER:
        return {}
    os.makedirs(setup_dir, exist_ok=True)
    paths = {"supports": os.path.join(setup_dir, "supports.in"),
             "unfix_supports": os.path.join(setup_dir, "unfix_supports.in")}
    for name, text in (("supports", supports.render(chosen)),
                       ("unfix_supports", supports.render_unfix(chosen))):
        with open(paths[name], "w", encoding="utf-8") as handle:
            handle.write(text)
    return paths


def zones_of(case):
    """(name, (x, y) offset from the panel centre, radius) of the case's output zones."""
    return tuple((z["name"], tuple(z["centre"]), z["radius"]) for z in case.zones)
