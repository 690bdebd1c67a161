"""Outputs every net case writes the same way from its deck's dumps: the zone forces, the
ruptures, the ParaView series of the net and the loading body (doc/file_formats.md)."""

import os

import numpy as np

from postprocess import bodyframes, dumps, vtu, zone
from postprocess.csvio import write_csv
from postprocess.errors import PostprocessError, at
from postprocess.meta import PanelInfo

# fix wirenet/bonds' local columns, 1-based as f_wirenet_bonds[k] (doc/fix_wirenet_bonds.md)
RUPTURE_COLUMNS = ("step", "atom1", "atom2", "type", "x", "y", "z", "elongation")


def read_rupture_dump(path):
    """{column: values} of the rupture dump (include/ruptures.in writes fix wirenet/bonds'
    local rows), by the fix's column names, sorted by step."""
    out = {name: np.zeros(0) for name in RUPTURE_COLUMNS}
    if not os.path.isfile(path):
        return out
    frames = list(dumps.iter_frames(path))
    if not frames or not len(frames[-1].data):
        return out
    frame = frames[-1]
    for k, name in enumerate(frame.names):
        index = int(name.rsplit("[", 1)[1].rstrip("]")) if name.endswith("]") else 0
        if 1 <= index <= len(RUPTURE_COLUMNS):
            out[RUPTURE_COLUMNS[index - 1]] = frame.data[:, k]
    order = np.argsort(out["step"], kind="stable")
    return {name: values[order] for name, values in out.items()}


def ruptures(path, dt, families):
    """Every broken bond of a run as a dict (time, step, atoms, type, family, midpoint,
    elongation)."""
    cols = read_rupture_dump(path)
    out = []
    for step, a1, a2, btype, x, y, z, elong in zip(*(cols[c] for c in RUPTURE_COLUMNS)):
        out.append(dict(time=float(step) * dt, step=int(step), atom1=int(a1), atom2=int(a2),
                        type=int(btype), family=families.get(int(btype), f"type{int(btype)}"),
                        x=float(x), y=float(y), z=float(z), elongation=float(elong)))
    return out


def write_ruptures(path, rows):
    write_csv(path, ("time", "atom1", "atom2", "type", "family", "x", "y", "z", "elongation"),
              [(r["time"], r["atom1"], r["atom2"], r["type"], r["family"], r["x"], r["y"],
                r["z"], r["elongation"]) for r in rows])


def rupture_facts(r):
    """A rupture as case.json's first_rupture object."""
    return dict(time=r["time"], step=r["step"], position=[r["x"], r["y"], r["z"]],
                bond=dict(atom1=r["atom1"], atom2=r["atom2"], type=r["type"], family=r["family"]))


def write_zones(case_dir, workdir, json_path, zones, dt, displacement):
    """zone_forces.csv for the first zone and zone_forces_NAME.csv for every other one: zones
    are (name, (x, y) offset from the panel centre, radius). ``displacement(times)`` gives the
    load's travel at the dump times. Returns the panel's families."""
    panel = PanelInfo(json_path)
    for k, (name, offset, radius) in enumerate(zones):
        centre = panel.centre + np.r_[np.asarray(offset, float), 0.0]
        info = PanelInfo(json_path, centre=centre)
        times, names, totals, maxima, counts = zone.compute(
            [os.path.join(workdir, "bonds.dump")], info, radius, dt)
        file = "zone_forces.csv" if k == 0 else f"zone_forces_{name}.csv"
        write_csv(os.path.join(case_dir, file), zone.HEADER,
                  zone.rows(times, displacement(times), names, totals, maxima, counts))
    return panel.families


def write_series(case_dir, workdir, data_path, body_stl, dt):
    """The ParaView series CASE/CASE.pvd (net) and CASE/CASE_body.pvd (the loading body: with
    the analytic body, its STL moved to the poses the deck wrote)."""
    bodyframes.write_body_frames(workdir, body_stl)
    vtu.write_case_series(case_dir, workdir, data_path, dt)


def read_vector_rows(path, ncols):
    """A fix ave/time mode vector file ('step rows' lines, each followed by that many 'index
    values' rows): (steps, values[row, index, ncols])."""
    try:
        lines = [l.split() for l in open(path) if l.strip() and not l.startswith("#")]
    except OSError as exc:
        raise PostprocessError(f"{path}: {exc.strerror or exc}") from None
    steps, blocks, k = [], [], 0
    while k < len(lines):
        head = lines[k]
        try:
            step, n = int(head[0]), int(head[1])
            if len(head) != 2:
                raise ValueError
            block = np.array([[float(v) for v in row[1:]] for row in lines[k + 1:k + 1 + n]])
        except (ValueError, IndexError):
            raise at(path, k + 1, "expected a 'step rows' line and its rows of numbers") from None
        if block.shape != (n, ncols) or not np.all(np.isfinite(block)):
            raise at(path, k + 1, f"expected {n} rows of {ncols} finite values")
        steps.append(step)
        blocks.append(block)
        k += n + 1
    if not blocks:
        raise PostprocessError(f"{path}: no rows")
    return np.array(steps), np.array(blocks)


def read_support_rows(path):
    """anchors.txt / bases.txt (fix ave/time mode vector of fix wirenet/hold ... each: id and
    the window-mean reaction): (steps, ids, forces[row, atom, xyz]) [N]."""
    steps, rows = read_vector_rows(path, 4)
    return steps, rows[0, :, 0].astype(int), rows[:, :, 1:]


def last_frame(path, up_to=None):
    """The last frame of a custom dump, or the last one at or before step up_to."""
    frame = None
    for candidate in dumps.iter_frames(path):
        if up_to is not None and candidate.step > up_to:
            break
        frame = candidate
    if frame is None:
        raise PostprocessError(f"{path}: no frames" +
                               (f" up to step {up_to}" if up_to is not None else ""))
    return frame


def last_nodes(path, up_to=None):
    """(ids, positions) of the last frame of a custom dump (id type x y z), or of the last one
    at or before step up_to (the frames go on through the rest after the impact)."""
    frame = last_frame(path, up_to)
    return frame.integers(frame.names.index("id")), np.column_stack(
        [frame.column(c) for c in ("x", "y", "z")])
