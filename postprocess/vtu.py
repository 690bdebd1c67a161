"""VTU output: nodes as points, bonds as line cells (one .vtu per frame plus a .pvd series).

Cell data of every bond: tension [N], strain [-], family (the bond type number), broken (1 for a
bond of the reference set that is missing from the frame, else 0), and length0, length, shear,
moment when the dump has them. Point data: id, type, any other node-dump column, and with the
data file the displacement (x - x of the data file, a vector for ParaView's Warp By Vector).

Every punch and impact case writes two series at its end (``write_case_series``, from the frames
of inputs/include/frames.in): CASE/CASE.pvd (the net, frames in CASE/CASE/) and CASE/CASE_body.pvd
(the loading body as triangles, frames in CASE/CASE_body/).
"""

import contextlib
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


CELL_WIDTH = {"line": 2, "triangle": 3}


def write_mesh(path, points, cells, point_data, cell_data, binary=True, label=None,
               cell_type="line"):
    """Write one .vtu atomically with meshio (cells: (n, 2) point indices of line cells, or
    (n, 3) of triangles with ``cell_type="triangle"``); ``label``: the name errors give (the
    final path of a frame written in a temporary folder)."""
    import meshio
    width = CELL_WIDTH[cell_type]
    mesh = meshio.Mesh(points=np.asarray(points, dtype=float),
                       cells=[(cell_type, np.asarray(cells, dtype=np.int64).reshape(-1, width))],
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
        first, second = data.bond("atom1"), data.bond("atom2")
        return cls(bond_keys(first, second), first, second, data.bond("type"))

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


def write_series(pvd, bond_paths, node_paths, dt, data=None, binary=True, outputs=None):
    """The series PVD (.pvd) with its frames folder from bond and node dumps: one .vtu per bond
    frame, time = step x dt. ``data``: a read_data() result (broken bonds and displacements are
    taken against it), else the first frame's bonds are the reference. The folder and the .pvd
    are committed with ``outputs`` (output.Outputs), or at once; on any error neither is created
    or changed. Returns [(time, relative frame path)]."""
    if not dt > 0:
        raise PostprocessError(f"--dt must be positive, got {dt}")
    pvd, folder = series_paths(pvd)
    stem = os.path.basename(folder)
    ours = frame_name_pattern(stem)
    nodes = dumps.NodeSeries(node_paths)
    reference = Reference.from_data(data) if data is not None else None
    origin = None
    if data is not None:
        order = np.argsort(data.atom_ids, kind="stable")
        origin = (data.atom_ids[order], data.positions[order])
    entries = {}
    with Outputs() if outputs is None else contextlib.nullcontext(outputs) as out:
        tmp = out.directory(folder, replaceable=lambda name: ours.fullmatch(name))
        pvd_tmp = out.file(pvd)
        for frame in dumps.iter_files(bond_paths):
            mapping = dumps.bond_column_map(frame)
            dumps.require_columns(frame, mapping, ("atom1", "atom2", "type", "tension"),
                                  "needed by vtu")
            if reference is None:
                reference = Reference.from_frame(frame, mapping)
            at_step = nodes.at_step(frame.step, frame.path, frame.header_line)
            points, cells, point_data, cell_data = frame_arrays(frame, mapping, at_step,
                                                                reference)
            if origin is not None and np.array_equal(origin[0], at_step.ids):
                point_data["displacement"] = points - origin[1]
            name = f"{stem}_{frame.step:010d}.vtu"
            write_mesh(os.path.join(tmp, name), points, cells, point_data, cell_data,
                       binary=binary, label=os.path.join(folder, name))
            entries[frame.step] = f"{stem}/{name}"
        series = [(step * dt, entries[step]) for step in sorted(entries)]
        with open(pvd_tmp, "w", encoding="utf-8") as handle:
            handle.write(pvd_text(series))
    return series


_STL_STEP = re.compile(r"(\d+)\.stl$")


def read_stl(path):
    """Points (unique) and triangles of an ASCII STL (e.g. one frame of dump mesh/stl)."""
    vertices = []
    try:
        with open(path, encoding="utf-8", errors="replace") as handle:
            for number, line in enumerate(handle, 1):
                fields = line.split()
                if fields and fields[0] == "vertex":
                    try:
                        vertices.append([float(v) for v in fields[1:4]])
                    except ValueError:
                        raise PostprocessError(f"{path}:{number}: expected a vertex x y z, got "
                                               f"'{line.strip()}'") from None
    except OSError as exc:
        raise PostprocessError(f"{path}: cannot read: {exc.strerror or exc}") from None
    vertices = np.asarray(vertices, float).reshape(-1, 3)
    if len(vertices) % 3 or not np.all(np.isfinite(vertices)):
        raise PostprocessError(f"{path}: not a complete ASCII STL of finite numbers")
    points, inverse = np.unique(vertices, axis=0, return_inverse=True)
    return points, inverse.reshape(-1, 3)


def write_body_series(pvd, stl_paths, dt, binary=True, outputs=None):
    """The loading body's series from per-step STL files (NAME_STEP.stl of dump mesh/stl):
    triangles, point data id; time = step x dt. Returns [(time, relative frame path)]."""
    pvd, folder = series_paths(pvd)
    stem = os.path.basename(folder)
    ours = frame_name_pattern(stem)
    steps = {}
    for path in stl_paths:
        match = _STL_STEP.search(os.path.basename(path))
        if not match:
            raise PostprocessError(f"{path}: expected a file name ending in _STEP.stl")
        steps[int(match.group(1))] = path
    entries = {}
    with Outputs() if outputs is None else contextlib.nullcontext(outputs) as out:
        tmp = out.directory(folder, replaceable=lambda name: ours.fullmatch(name))
        pvd_tmp = out.file(pvd)
        for step in sorted(steps):
            points, triangles = read_stl(steps[step])
            name = f"{stem}_{step:010d}.vtu"
            write_mesh(os.path.join(tmp, name), points, triangles, {}, {}, binary=binary,
                       label=os.path.join(folder, name), cell_type="triangle")
            entries[step] = f"{stem}/{name}"
        series = [(step * dt, entries[step]) for step in sorted(entries)]
        with open(pvd_tmp, "w", encoding="utf-8") as handle:
            handle.write(pvd_text(series))
    return series


def case_series_paths(case_dir):
    """CASE/CASE.pvd (the net) and CASE/CASE_body.pvd (the loading body) of a case folder."""
    case_dir = os.path.normpath(str(case_dir))
    name = os.path.basename(case_dir)
    return os.path.join(case_dir, f"{name}.pvd"), os.path.join(case_dir, f"{name}_body.pvd")


def write_case_series(case_dir, workdir, data_path, dt):
    """The ParaView series of a punch or impact case from its run's frames (WORKDIR/frames/ of
    inputs/include/frames.in), both or neither: CASE/CASE.pvd + CASE/CASE/ (the net) and
    CASE/CASE_body.pvd + CASE/CASE_body/ (the platter or block). Returns the two .pvd paths."""
    frames = os.path.join(workdir, "frames")
    net_pvd, body_pvd = case_series_paths(case_dir)
    stls = [os.path.join(frames, n) for n in os.listdir(frames) if _STL_STEP.search(n)] \
        if os.path.isdir(frames) else []
    with Outputs() as outputs:
        write_series(net_pvd, [os.path.join(frames, "bonds.dump")],
                     [os.path.join(frames, "nodes.dump")], dt, read_data(data_path),
                     outputs=outputs)
        written = [net_pvd]
        if stls:
            write_body_series(body_pvd, stls, dt, outputs=outputs)
            written.append(body_pvd)
    return written


def read_pvd(path):
    """[(time, absolute .vtu path)] of a .pvd collection, in file order."""
    import xml.etree.ElementTree as ElementTree
    try:
        root = ElementTree.parse(path).getroot()
    except (OSError, ElementTree.ParseError) as exc:
        raise PostprocessError(f"{path}: cannot read the series: {exc}") from None
    folder = os.path.dirname(os.path.abspath(path))
    return [(float(d.get("timestep")), os.path.join(folder, d.get("file")))
            for d in root.iter("DataSet")]


def run(args):
    """The ``vtu`` subcommand.

    The frames folder and the .pvd are committed together once every frame is written: on any
    error neither is created or changed.
    """
    if not args.dt > 0:
        raise PostprocessError(f"--dt must be positive, got {args.dt}")
    pvd, folder = series_paths(args.out)
    data = read_data(args.data) if args.data else None
    series = write_series(pvd, args.bonds, args.nodes, args.dt, data, binary=not args.ascii)
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
    write_mesh(out, data.positions, pos.reshape(-1, 2), point_data, cell_data,
               binary=not args.ascii)
    print(f"wrote {out}: {len(ids)} points, {len(bonds)} bonds")
