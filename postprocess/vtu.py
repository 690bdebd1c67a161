"""VTU output: nodes as points, bonds as line cells (one .vtu per frame plus a .pvd series).

Cell data of every bond: tension [N], strain [-], family (the bond type number), broken (1 for a
bond of the reference set that is missing from the frame, else 0), and length0, length, shear,
moment when the dump has them. Point data: id, type and any other node-dump column.
"""

import os
import re
from xml.sax.saxutils import quoteattr

import numpy as np

from . import dumps
from .datafile import ATOM_FIELDS, read_data
from .errors import PostprocessError
from .output import Outputs, atomic_path

OPTIONAL_BOND_DATA = ("length0", "length", "shear", "moment")


def bond_keys(first, second):
    """Order-independent int64 key of the atom pairs."""
    first = np.asarray(first, dtype=np.int64)
    second = np.asarray(second, dtype=np.int64)
    return (np.minimum(first, second) << 32) | np.maximum(first, second)


def write_mesh(path, points, cells, point_data, cell_data, binary=True, label=None):
    """Write one .vtu atomically with meshio (cells: (n, 2) point indices of line cells);
    ``label``: the name errors give (the final path of a frame written in a temporary folder)."""
    import meshio
    mesh = meshio.Mesh(points=np.asarray(points, dtype=float),
                       cells=[("line", np.asarray(cells, dtype=np.int64).reshape(-1, 2))],
                       point_data=point_data,
                       cell_data={name: [value] for name, value in cell_data.items()})
    with atomic_path(path, ".vtu", label) as tmp:
        meshio.write(tmp, mesh, file_format="vtu", binary=binary)


def pvd_text(entries):
    """The .pvd collection (ParaView time series) of (time, relative file) pairs."""
    lines = ['<?xml version="1.0"?>',
             '<VTKFile type="Collection" version="0.1" byte_order="LittleEndian">',
             "  <Collection>"]
    for time, name in entries:
        lines.append(f'    <DataSet timestep="{time!r}" group="" part="0" '
                     f"file={quoteattr(name)}/>")
    lines += ["  </Collection>", "</VTKFile>", ""]
    return "\n".join(lines)


class Reference:
    """The bonds every frame is compared with to flag broken ones (data file or first frame)."""

    def __init__(self, keys, first, second, types):
        order = np.argsort(keys, kind="stable")
        self.keys, self.first, self.second = keys[order], first[order], second[order]
        self.types = types[order]

    @classmethod
    def from_data(cls, data):
        first, second = data.bonds[:, 2], data.bonds[:, 3]
        return cls(bond_keys(first, second), first, second, data.bonds[:, 1])

    @classmethod
    def from_frame(cls, frame, mapping):
        first = frame.integers(mapping["atom1"])
        second = frame.integers(mapping["atom2"])
        types = frame.integers(mapping["type"])
        return cls(bond_keys(first, second), first, second, types)

    def missing(self, keys):
        """Mask of the reference bonds absent from ``keys``."""
        return ~np.isin(self.keys, keys)


def frame_arrays(frame, mapping, nodes, reference):
    """Points, cells, point data and cell data of one frame."""
    data = frame.data
    first = frame.integers(mapping["atom1"])
    second = frame.integers(mapping["atom2"])
    types = frame.integers(mapping["type"])
    cell_data = {"tension": data[:, mapping["tension"]],
                 "strain": data[:, mapping["strain"]] if "strain" in mapping
                 else np.full(len(data), np.nan)}
    for name in OPTIONAL_BOND_DATA:
        if name in mapping:
            cell_data[name] = data[:, mapping[name]]
    broken = np.zeros(len(data), dtype=np.int32)
    if reference is not None:
        gone = reference.missing(bond_keys(first, second))
        count = int(gone.sum())
        first = np.r_[first, reference.first[gone]]
        second = np.r_[second, reference.second[gone]]
        types = np.r_[types, reference.types[gone]]
        broken = np.r_[broken, np.ones(count, dtype=np.int32)]
        cell_data = {k: np.r_[v, np.zeros(count)] for k, v in cell_data.items()}
    cell_data["family"] = types.astype(np.int32)
    cell_data["broken"] = broken
    cells = np.column_stack([nodes.index_of(first, frame.path, frame.header_line),
                             nodes.index_of(second, frame.path, frame.header_line)])
    point_data = {"id": nodes.ids.astype(np.int64), "type": nodes.types.astype(np.int32)}
    point_data.update({name: np.asarray(v, dtype=float) for name, v in nodes.extra.items()})
    return nodes.xyz, cells, point_data, cell_data


def series_paths(out):
    """OUT.pvd and the folder OUT/ that holds the frames."""
    out = str(out)
    pvd = out if out.endswith(".pvd") else out + ".pvd"
    folder = pvd[:-4]
    if out.endswith(("/", os.sep)) or not os.path.basename(folder):
        raise PostprocessError(f"--out: expected the series file name (e.g. DIR/wirenet.pvd), "
                               f"got '{out}'")
    return pvd, folder


def frame_name_pattern(stem):
    """The names of the frames of series ``stem`` in its folder (anything else there is not
    ours, and the folder is then not replaced)."""
    return re.compile(re.escape(stem) + r"_\d{10}\.vtu")


def run(args):
    """The ``vtu`` subcommand.

    The frames folder and the .pvd are committed together once every frame is written: on any
    error neither is created or changed.
    """
    if not args.dt > 0:
        raise PostprocessError(f"--dt must be positive, got {args.dt}")
    pvd, folder = series_paths(args.out)
    stem = os.path.basename(folder)
    ours = frame_name_pattern(stem)
    nodes = dumps.NodeSeries(args.nodes)
    reference = Reference.from_data(read_data(args.data)) if args.data else None
    entries = {}
    with Outputs() as outputs:
        tmp = outputs.directory(folder, replaceable=lambda name: ours.fullmatch(name))
        pvd_tmp = outputs.file(pvd)
        for frame in dumps.iter_files(args.bonds):
            mapping = dumps.bond_column_map(frame)
            dumps.require_columns(frame, mapping, ("atom1", "atom2", "type", "tension"),
                                  "needed by vtu")
            if reference is None and not args.data:
                reference = Reference.from_frame(frame, mapping)
            at_step = nodes.at_step(frame.step, frame.path, frame.header_line)
            arrays = frame_arrays(frame, mapping, at_step, reference)
            name = f"{stem}_{frame.step:010d}.vtu"
            write_mesh(os.path.join(tmp, name), *arrays, binary=not args.ascii,
                       label=os.path.join(folder, name))
            entries[frame.step] = f"{stem}/{name}"
        series = [(step * args.dt, entries[step]) for step in sorted(entries)]
        with open(pvd_tmp, "w", encoding="utf-8") as handle:
            handle.write(pvd_text(series))
    print(f"wrote {pvd}: {len(series)} frames in {folder}/")


def run_data(args):
    """The ``data2vtu`` subcommand: a generated panel (points + bonds) as one .vtu."""
    data = read_data(args.data)
    out = args.out or os.path.splitext(args.data)[0] + ".vtu"
    ids = data.atom_ids
    bonds = data.bonds
    pos = np.searchsorted(ids, bonds[:, 2:4].ravel()).clip(0, max(len(ids) - 1, 0))
    if len(bonds) and not np.all(ids[pos] == bonds[:, 2:4].ravel()):
        bad = bonds[:, 2:4].ravel()[ids[pos] != bonds[:, 2:4].ravel()][0]
        raise PostprocessError(f"{args.data}: bond refers to unknown atom {bad}")
    point_data = {name: data.atoms[:, i] for i, name in enumerate(ATOM_FIELDS)
                  if name not in ("x", "y", "z")}
    for name in ("id", "type", "molecule"):
        point_data[name] = point_data[name].astype(np.int32 if name != "id" else np.int64)
    cell_data = {"bond_id": bonds[:, 0], "family": bonds[:, 1].astype(np.int32)}
    write_mesh(out, data.atoms[:, 2:5], pos.reshape(-1, 2), point_data, cell_data,
               binary=not args.ascii)
    print(f"wrote {out}: {len(ids)} points, {len(bonds)} bonds")
