"""Zone forces: tensile force of the bonds whose midpoint lies in a circle of the panel plane.

For every frame of the bond dump and every family: the sum of the tensile forces (compressive
bonds contribute 0), the largest tensile force (0 if none) and the number of bonds whose midpoint
is inside the zone (all of them, whatever the sign of their force).
"""

import numpy as np

from . import dumps
from .csvio import read_csv, write_csv
from .errors import PostprocessError

HEADER = ("time", "displacement", "family", "total_tension", "max_tension", "bonds")


def in_zone(points, centre, normal, radius):
    """Boolean mask: distance of ``points`` to ``centre`` measured in the plane (normal removed)
    is at most ``radius`` (the boundary counts as inside)."""
    offset = points - centre
    offset = offset - np.outer(offset @ normal, normal)
    return np.einsum("ij,ij->i", offset, offset) <= radius * radius


def midpoints(frame, mapping, nodes):
    """Bond midpoints: columns xm ym zm of the dump, else from the node dump (atom1, atom2)."""
    if all(name in mapping for name in ("xm", "ym", "zm")):
        return frame.data[:, [mapping["xm"], mapping["ym"], mapping["zm"]]]
    dumps.require_columns(frame, mapping, ("atom1", "atom2"),
                          "needed with --nodes when the dump has no midpoint columns xm ym zm")
    if nodes is None:
        raise PostprocessError(f"{frame.path}:{frame.header_line}: no midpoint columns "
                               f"(c_ID[8..10]); give the node dump with --nodes")
    if len(frame.data) == 0:
        return np.zeros((0, 3))
    at_step = nodes.at_step(frame.step, frame.path, frame.header_line)
    first = at_step.index_of(frame.integers(mapping["atom1"]), frame.path, frame.header_line)
    second = at_step.index_of(frame.integers(mapping["atom2"]), frame.path, frame.header_line)
    return 0.5 * (at_step.xyz[first] + at_step.xyz[second])


class FamilyIndex:
    """Bond type -> family column; unknown types become families named ``type<T>``."""

    def __init__(self, families):
        self.names = []
        self.by_type = {}
        for btype in sorted(families):
            self._add(btype, families[btype])

    def _add(self, btype, name):
        if name not in self.names:
            self.names.append(name)
        self.by_type[btype] = self.names.index(name)

    def indices(self, types):
        """Family index of each bond type (vectorised through the distinct types)."""
        types = np.asarray(types, dtype=np.int64)
        if len(types) == 0:
            return np.zeros(0, dtype=np.int64)
        distinct, inverse = np.unique(types, return_inverse=True)
        for btype in distinct:
            if int(btype) not in self.by_type:
                self._add(int(btype), f"type{int(btype)}")
        lookup = np.array([self.by_type[int(t)] for t in distinct], dtype=np.int64)
        return lookup[inverse.reshape(-1)]


def frame_forces(frame, panel, radius, family_index, nodes=None):
    """(step, totals, maxima, counts) of one frame, arrays indexed by family."""
    mapping = dumps.bond_column_map(frame)
    dumps.require_columns(frame, mapping, ("type", "tension"), "needed by zone")
    mids = midpoints(frame, mapping, nodes)
    inside = in_zone(mids, panel.centre, panel.normal, radius)
    family = family_index.indices(frame.integers(mapping["type"]))
    tension = frame.data[:, mapping["tension"]]
    tensile = np.where(inside & (tension > 0), tension, 0.0)
    size = len(family_index.names)
    totals = np.bincount(family, weights=tensile, minlength=size)
    counts = np.bincount(family, weights=inside.astype(float), minlength=size)
    maxima = np.zeros(size)
    if len(family):
        order = np.lexsort((tensile, family))          # by family, then by force
        last = np.r_[family[order][1:] != family[order][:-1], True]
        maxima[family[order][last]] = tensile[order][last]
    return frame.step, totals, maxima, counts


def displacement_at(times, path, column="displacement", time_column="time"):
    """Displacement interpolated at ``times`` from a CSV (clamped outside its time range)."""
    if path is None:
        return np.zeros(len(times))
    table = read_csv(path, required=(time_column, column))
    if len(table[time_column]) == 0:
        raise PostprocessError(f"{path}:2: no data rows")
    order = np.argsort(table[time_column], kind="stable")
    return np.interp(times, table[time_column][order], table[column][order])


def compute(bond_paths, panel, radius, dt, node_paths=None):
    """Zone forces of all frames: (times, family names, totals, maxima, counts), sorted by step.

    A step present several times (overlapping restarts) keeps its last frame.
    """
    nodes = dumps.NodeSeries(node_paths) if node_paths else None
    family_index = FamilyIndex(panel.families)
    by_step = {}
    for frame in dumps.iter_files(bond_paths):
        by_step[frame.step] = frame_forces(frame, panel, radius, family_index, nodes)
    steps = sorted(by_step)
    size = len(family_index.names)

    def stack(k):
        return np.array([np.pad(by_step[s][k], (0, size - len(by_step[s][k]))) for s in steps]
                        ).reshape(len(steps), size)

    times = np.array(steps, dtype=float) * dt
    return times, list(family_index.names), stack(1), stack(2), stack(3)


def rows(times, displacement, names, totals, maxima, counts):
    """CSV rows in HEADER order: one per time and family."""
    for i, time in enumerate(times):
        for j, name in enumerate(names):
            yield (float(time), float(displacement[i]), name, float(totals[i, j]),
                   float(maxima[i, j]), float(counts[i, j]))


def run(args):
    """The ``zone`` subcommand."""
    from .meta import PanelInfo, parse_families
    if not args.radius > 0:
        raise PostprocessError(f"--radius must be positive, got {args.radius}")
    if not args.dt > 0:
        raise PostprocessError(f"--dt must be positive, got {args.dt}")
    families = parse_families(args.families) if args.families else None
    panel = PanelInfo(args.json, args.centre, args.normal, families)
    times, names, totals, maxima, counts = compute(args.bonds, panel, args.radius, args.dt,
                                                   args.nodes)
    displacement = displacement_at(times, args.displacement, args.displacement_column,
                                   args.time_column)
    write_csv(args.out, HEADER, rows(times, displacement, names, totals, maxima, counts))
    print(f"wrote {args.out}: {len(times)} steps x {len(names)} families")
