"""Figure 4: the deformed net of a punch, impact or tensile case at its peak, in 3D.

Drawn from the case's ParaView series (CASE/CASE.pvd and CASE/CASE_body.pvd, written by
vtu.write_case_series at the end of every punch and impact case), so the figure and the VTU show
the same frame:

- the frame: punch (and calibration) cases, the frame nearest the peak platter force before the
  first rupture (platter.csv, case.json ``first_rupture``; frames after the first rupture are
  not used unless there is no other), else the end; impact cases, the frame nearest the block's
  lowest point (block.csv), a tensile case's peak clamp force (tensile.csv); without those
  tables, the frame with the largest bond tension;
- intact bonds in tension coloured by their tension (colour bar in N, from 0 to the largest
  tension of the frame), compressive or slack bonds thin grey, broken bonds (in the data file,
  missing from the frame) a red cross at their midpoint;
- the loading body (platter or block) of the same time, translucent grey;
- equal scaling on the three axes; the title names the case, the time, the platter travel or
  block travel, the load at that frame and the peak values.
"""

import os

import numpy as np

from . import vtu
from .errors import PostprocessError

CMAP = "viridis"
SERIES_KINDS = ("punch", "calibration", "impact", "tensile")


def _read_vtu(path):
    import meshio
    try:
        return meshio.read(path)
    except PostprocessError:
        raise
    except Exception as exc:          # meshio raises many kinds on a damaged file
        raise PostprocessError(f"{path}: cannot read the frame: {exc}") from None


def _cell_array(mesh, name, cell_type="line"):
    data = mesh.cell_data_dict.get(name, {})
    if cell_type not in data:
        raise PostprocessError(f"frame without cell data '{name}'")
    return np.asarray(data[cell_type])


def _nearest(times, target, allowed=None):
    times = np.asarray(times, float)
    candidates = np.arange(len(times)) if allowed is None else np.flatnonzero(allowed)
    if not candidates.size:
        candidates = np.arange(len(times))
    return int(candidates[np.argmin(np.abs(times[candidates] - target))])


def select_frame(case, times):
    """Index of the Figure 4 frame among the series' ``times`` and the facts of that choice:
    dict(reason, target_time, ...)."""
    tables, meta = case.tables, case.meta
    kind = case.kind
    if kind in ("punch", "calibration") and "platter" in tables:
        table = tables["platter"]
        rows = np.ones(len(table["force"]), bool)
        rupture = meta.get("first_rupture")
        rupture_time = None
        if isinstance(rupture, dict) and isinstance(rupture.get("displacement"), (int, float)):
            rows = table["displacement"] <= rupture["displacement"]
            step, dt = rupture.get("step"), meta.get("dt")
            if isinstance(step, (int, float)) and isinstance(dt, (int, float)):
                rupture_time = float(step) * float(dt)
        if not rows.any():
            rows[:] = True
        k = int(np.argmax(np.where(rows, table["force"], -np.inf)))
        allowed = None if rupture_time is None else np.asarray(times) <= rupture_time
        return _nearest(times, table["time"][k], allowed), dict(
            reason="peak platter force" + (" before the first rupture" if rupture else ""),
            target_time=float(table["time"][k]), peak_force=float(table["force"][k]),
            peak_displacement=float(table["displacement"][k]))
    if kind == "impact" and "block" in tables:
        table = tables["block"]
        k = int(np.argmin(table["z"]))
        return _nearest(times, table["time"][k]), dict(
            reason="lowest point of the block", target_time=float(table["time"][k]),
            max_travel=float(table["z"][0] - table["z"][k]),
            peak_force=float(np.max(np.abs(table["force"]))))
    if kind == "tensile" and "tensile" in tables:
        table = tables["tensile"]
        k = int(np.argmax(table["force"]))
        return _nearest(times, table["time"][k]), dict(
            reason="peak clamp force", target_time=float(table["time"][k]),
            peak_force=float(table["force"][k]), peak_displacement=float(table["displacement"][k]))
    return None, dict(reason="largest bond tension")


def load(case):
    """Everything Figure 4 draws for a casefolders.Case with a series: dict(points, cells, tension,
    broken, body_points, body_triangles, time, frame, ...)."""
    net_pvd, body_pvd = vtu.case_series_paths(case.path)
    if not os.path.isfile(net_pvd):
        raise PostprocessError(f"{net_pvd}: no ParaView series (the case wrote no frames)")
    entries = vtu.read_pvd(net_pvd)
    if not entries:
        raise PostprocessError(f"{net_pvd}: the series has no frame")
    times = [t for t, _ in entries]
    index, choice = select_frame(case, times)
    if index is None:       # no table to choose by: the frame with the largest tension
        peaks = [float(np.max(_cell_array(_read_vtu(p), "tension"), initial=0.0))
                 for _, p in entries]
        index = int(np.argmax(peaks))
    time, path = entries[index]
    mesh = _read_vtu(path)
    cells = mesh.cells_dict.get("line")
    if cells is None:
        raise PostprocessError(f"{path}: the frame has no line cells (bonds)")
    data = dict(name=case.name, kind=case.kind, time=float(time), frame=path, index=index,
                frames=len(entries), points=np.asarray(mesh.points, float),
                cells=np.asarray(cells, np.int64),
                tension=_cell_array(mesh, "tension").astype(float),
                broken=_cell_array(mesh, "broken").astype(bool), choice=choice,
                body_points=None, body_triangles=None)
    if os.path.isfile(body_pvd):
        body = vtu.read_pvd(body_pvd)
        if body:
            k = int(np.argmin([abs(t - time) for t, _ in body]))
            body_mesh = _read_vtu(body[k][1])
            data["body_points"] = np.asarray(body_mesh.points, float)
            data["body_triangles"] = body_mesh.cells_dict.get("triangle")
    data["title"] = _title(case, data)
    return data


def _title(case, data):
    t = data["time"]
    tension = data["tension"][~data["broken"]]
    peak = float(np.max(tension, initial=0.0))
    nbroken = int(np.count_nonzero(data["broken"]))
    choice = data["choice"]
    first = f"Figure 4: {case.name} at t = {t:.4g} s"
    if case.kind in ("punch", "calibration") and "platter" in case.tables:
        table = case.tables["platter"]
        d = float(np.interp(t, table["time"], table["displacement"]))
        f = float(np.interp(t, table["time"], table["force"]))
        first += f": platter travel {d:.4g} m, platter force {f:.4g} N"
        second = (f"{choice['reason']}: {choice['peak_force']:.4g} N at "
                  f"{choice['peak_displacement']:.4g} m")
    elif case.kind == "impact" and "block" in case.tables:
        table = case.tables["block"]
        z = float(np.interp(t, table["time"], table["z"]))
        f = float(np.interp(t, table["time"], table["force"]))
        first += f": block travel {table['z'][0] - z:.4g} m, block force {f:.4g} N"
        second = (f"{choice['reason']}: travel {choice['max_travel']:.4g} m at "
                  f"{choice['target_time']:.4g} s, peak block force {choice['peak_force']:.4g} N")
    else:
        second = choice["reason"]
    return (f"{first}\n{second}\nlargest bond tension {peak:.4g} N, {nbroken} broken "
            f"bond{'s' if nbroken != 1 else ''}")


def body_far_from_net(points, body):
    """The distance between the boxes around the net and the body when it exceeds half the net's
    largest extent (the view then keeps to the net), else None."""
    low, high = points.min(axis=0), points.max(axis=0)
    gap = np.maximum(np.maximum(body.min(axis=0) - high, low - body.max(axis=0)), 0.0)
    distance = float(np.linalg.norm(gap))
    return distance if distance > 0.5 * float(np.max(high - low)) else None


def draw(data):
    """The matplotlib figure of ``data`` (from load) and its artists: dict(axes, tension
    (Line3DCollection of the bonds in tension), slack, broken (the red crosses, or None),
    colorbar, body)."""
    from matplotlib import cm, colors
    from mpl_toolkits.mplot3d.art3d import Line3DCollection, Poly3DCollection
    from .canvas import pyplot
    plt = pyplot()
    points, cells = data["points"], data["cells"]
    broken, tension = data["broken"], data["tension"]
    segments = points[cells]
    pulled = ~broken & (tension > 0)
    slack = ~broken & ~pulled
    top = float(np.max(tension[pulled], initial=0.0))
    norm = colors.Normalize(vmin=0.0, vmax=top if top > 0 else 1.0)
    fig = plt.figure(figsize=(9, 7), layout="constrained")
    ax = fig.add_subplot(projection="3d")
    artists = dict(axes=ax, body=None, broken=None)
    slack_lines = Line3DCollection(segments[slack], colors="0.65", linewidths=0.4)
    ax.add_collection3d(slack_lines)
    lines = Line3DCollection(segments[pulled], cmap=CMAP, norm=norm, linewidths=1.3)
    lines.set_array(tension[pulled])
    ax.add_collection3d(lines)
    artists.update(tension=lines, slack=slack_lines)
    if broken.any():
        mid = segments[broken].mean(axis=1)
        artists["broken"] = ax.scatter(mid[:, 0], mid[:, 1], mid[:, 2], marker="x", color="red",
                                       s=40, linewidths=1.5, depthshade=False,
                                       label=f"broken bonds ({int(broken.sum())})")
        ax.legend(loc="upper left")
    everything = [points]
    body, triangles = data.get("body_points"), data.get("body_triangles")
    if body is not None and triangles is not None and len(triangles):
        far = body_far_from_net(points, body)
        if far is None:
            artists["body"] = Poly3DCollection(body[triangles], facecolors=(0.5, 0.5, 0.5, 0.25),
                                               edgecolors="none")
            ax.add_collection3d(artists["body"])
            everything.append(body)
        else:      # a block that went through: drawn to scale, the net would be a speck
            ax.text2D(0.02, 0.02, f"the body is out of view, {far:.3g} m from the net",
                      transform=ax.transAxes, fontsize="small")
    every = np.vstack(everything)
    low, high = every.min(axis=0), every.max(axis=0)
    span = np.maximum(high - low, 1e-3 * float(np.max(high - low, initial=1.0)) + 1e-12)
    centre = (low + high) / 2
    ax.set_xlim(centre[0] - span[0] / 2, centre[0] + span[0] / 2)
    ax.set_ylim(centre[1] - span[1] / 2, centre[1] + span[1] / 2)
    ax.set_zlim(centre[2] - span[2] / 2, centre[2] + span[2] / 2)
    ax.set_box_aspect(tuple(span))          # equal scaling: 1 m is as long on every axis
    from matplotlib.ticker import MaxNLocator
    ax.zaxis.set_major_locator(MaxNLocator(max(2, min(6, int(8 * span[2] / span.max())))))
    ax.view_init(elev=25, azim=-60)
    ax.set_xlabel("x [m]")
    ax.set_ylabel("y [m]")
    ax.set_zlabel("z [m]")
    mappable = cm.ScalarMappable(norm=norm, cmap=CMAP)
    mappable.set_array(tension[pulled])
    artists["colorbar"] = fig.colorbar(mappable, ax=ax, shrink=0.6,
                                       label="bond tension [N] (grey: slack or compressed)")
    ax.set_title(data["title"], fontsize="medium")
    return fig, artists


def figure_case(case, prefix, outputs=None):
    """Figure 4 of a casefolders.Case into PREFIX.png and PREFIX.svg; returns the paths."""
    from .canvas import save
    fig, _ = draw(load(case))
    return save(fig, prefix, outputs)


def has_series(case):
    """True for a punch, calibration or impact case folder holding CASE/CASE.pvd."""
    return case.kind in SERIES_KINDS and os.path.isfile(vtu.case_series_paths(case.path)[0])
