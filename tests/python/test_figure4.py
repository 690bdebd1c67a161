"""The ParaView series of a punch / impact case (CASE/CASE.pvd, CASE/CASE_body.pvd) and Figure 4
(the deformed net at the peak, bonds coloured by tension, broken bonds marked).

Unit part on a synthetic case folder (a 3 x 3 node net, four frames, one bond breaking in the
last, a tetrahedron as the loading body): the series read back with meshio frame by frame, the
frame Figure 4 chooses, its colour bar, its broken-bond crosses and its pixels. Integration part:
the quick square impact through LIGGGHTS writes the series without any extra command.
"""

import os
import sys
import xml.etree.ElementTree as ET
from pathlib import Path

import meshio
import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))

from postprocess import casefolders, figure4, plots, synthetic, vtu  # noqa: E402
from runner import api  # noqa: E402

DT = 1e-3
STEPS = (0, 100, 200, 300)
BROKEN = (5, 6)                # the bond that breaks at step 300


def grid_nodes(sag):
    """3 x 3 nodes 0.5 m apart, ids 1..9, the centre (id 5) lowest: z = -sag (1 - r^2 / 2)."""
    rows = []
    for k in range(9):
        x, y = 0.5 * (k % 3) - 0.5, 0.5 * (k // 3) - 0.5
        rows.append((k + 1, 1 if k != 4 else 2, x, y, -sag * (1 - (x * x + y * y) / 0.5 * 0.5)))
    return rows


def grid_bonds():
    """(atom1, atom2, type): rows and columns of the grid; types 1, 2 and 4."""
    bonds = []
    for r in range(3):
        for c in range(2):
            bonds.append((3 * r + c + 1, 3 * r + c + 2, 1 if r != 1 else 4))
            bonds.append((3 * c + r + 1, 3 * c + r + 4, 2))
    return bonds


def tensions(step, bonds):
    """Tension of each bond at ``step``: grows with the step, one bond compressive."""
    scale = step / 100.0
    return [(-5.0 if (a, b) == (1, 2) else 100.0 * scale * (i + 1)) for i, (a, b, _) in
            enumerate(bonds)]


def tetra_stl(dz):
    vertices = np.array([[0, 0, 0.3], [0.2, 0, 0.5], [0, 0.2, 0.5], [-0.2, -0.2, 0.5]]) + \
        [0, 0, -dz]
    faces = ((0, 1, 2), (0, 1, 3), (0, 2, 3), (1, 2, 3))
    lines = ["solid LIGGGHTS_STL_EXPORT"]
    for face in faces:
        lines += ["  facet normal 0 0 1", "    outer loop"]
        lines += [f"      vertex {v[0]:g} {v[1]:g} {v[2]:g}" for v in vertices[list(face)]]
        lines += ["    endloop", "  endfacet"]
    return "\n".join(lines + ["endsolid LIGGGHTS_STL_EXPORT", ""])


def make_case(root, name, kind="impact"):
    """A case folder as a punch / impact run leaves it before the series is written:
    setup/panel.data, run/frames/{nodes,bonds}.dump and body_STEP.stl, and block.csv or
    platter.csv (+ case.json)."""
    case = Path(root) / name
    frames = case / "run" / "frames"
    frames.mkdir(parents=True)
    bonds = grid_bonds()
    atoms = [(i, t, x, y, z, 0.01, 7850, 1) for i, t, x, y, z in grid_nodes(0.0)]
    (case / "setup").mkdir()
    (case / "setup" / "panel.data").write_text(synthetic.data_file_text(
        atoms, [(k + 1, t, a, b) for k, (a, b, t) in enumerate(bonds)]))
    node_frames, bond_frames = [], []
    for step in STEPS:
        node_frames.append((step, grid_nodes(0.001 * step)))
        rows = [synthetic.bond_row(a, b, t, f, (0, 0, 0), strain=f * 1e-6)
                for (a, b, t), f in zip(bonds, tensions(step, bonds))
                if not (step == STEPS[-1] and (a, b) == BROKEN)]
        bond_frames.append((step, rows))
        (frames / f"body_{step}.stl").write_text(tetra_stl(0.001 * step))
    (frames / "nodes.dump").write_text(synthetic.node_dump_text(node_frames))
    (frames / "bonds.dump").write_text(synthetic.bond_dump_text(bond_frames))
    times = np.linspace(0.0, STEPS[-1] * DT, 13)
    if kind == "impact":
        # the block is lowest at t = 0.3 s (the last frame, where the bond has broken)
        z = 0.5 - times
        (case / "block.csv").write_text("time,x,y,z,vx,vy,vz,force\n" + "".join(
            f"{t!r},0,0,{zz!r},0,0,-1,{1000 * t!r}\n" for t, zz in zip(times, z)))
    elif kind == "tensile":
        # the clamp force peaks at t = 0.1 s; the bonds' largest tension is in the last frame
        force = 1000.0 * np.minimum(times, 0.2 - times)
        (case / "tensile.csv").write_text("time,displacement,force\n" + "".join(
            f"{t!r},{0.01 * t!r},{f!r}\n" for t, f in zip(times, force)))
        (case / "case.json").write_text('{"status": "ok", "kind": "tensile", "dt": %r}' % DT)
    else:
        # the platter force peaks at t = 0.2 s; the first rupture comes after it
        force = 1000.0 * np.minimum(times, 0.4 - times)
        (case / "platter.csv").write_text("time,displacement,force\n" + "".join(
            f"{t!r},{0.01 * t!r},{f!r}\n" for t, f in zip(times, force)))
        (case / "case.json").write_text('{"status": "ok", "dt": %r, "first_rupture": '
                                        '{"displacement": 0.0029, "force": 50, "step": 290, '
                                        '"bond": {"atom1": 5, "atom2": 6, "family": "DT"}}}'
                                        % DT)
    return case


def write_series(case):
    return vtu.write_case_series(str(case), str(case / "run"),
                                 str(case / "setup" / "panel.data"), DT)


def read_pvd(path):
    root = ET.parse(path).getroot()
    assert root.get("type") == "Collection"
    return [(float(d.get("timestep")), Path(path).parent / d.get("file"))
            for d in root.iter("DataSet")]


def midpoint(mesh, a, b):
    ids = list(mesh.point_data["id"])
    return (mesh.points[ids.index(a)] + mesh.points[ids.index(b)]) / 2


def png_pixels(path):
    from matplotlib import image
    pixels = image.imread(str(path))[..., :3]
    return pixels


# ---------------------------------------------------------------------------------------------
# the series

def test_case_series_reads_back_with_meshio(tmp_path):
    case = make_case(tmp_path, "impact_grid")
    net, body = write_series(case)
    assert (net, body) == (str(case / "impact_grid.pvd"), str(case / "impact_grid_body.pvd"))
    series = read_pvd(net)
    times = [t for t, _ in series]
    assert times == pytest.approx([s * DT for s in STEPS]) and np.all(np.diff(times) > 0)
    bonds = grid_bonds()
    for k, (_, path) in enumerate(series):
        assert path.parent == case / "impact_grid"
        mesh = meshio.read(path)
        np.testing.assert_array_equal(mesh.point_data["id"], np.arange(1, 10))
        np.testing.assert_allclose(mesh.points, np.array(grid_nodes(0.001 * STEPS[k]))[:, 2:5])
        np.testing.assert_allclose(mesh.point_data["displacement"][:, 2],
                                   np.array(grid_nodes(0.001 * STEPS[k]))[:, 4])
        lines = mesh.cells_dict["line"]
        assert len(lines) == len(bonds)              # every bond of the data file, intact or not
        ids = mesh.point_data["id"][lines]
        pairs = {tuple(sorted(p)) for p in ids.tolist()}
        assert pairs == {tuple(sorted(b[:2])) for b in bonds}
        data = {n: mesh.cell_data_dict[n]["line"] for n in ("tension", "strain", "family",
                                                            "broken")}
        by_pair = {tuple(sorted(p)): i for i, p in enumerate(ids.tolist())}
        expected = dict(zip([b[:2] for b in bonds], tensions(STEPS[k], bonds)))
        for (a, b, btype) in bonds:
            i = by_pair[(a, b)]
            assert data["family"][i] == btype
            gone = k == len(STEPS) - 1 and (a, b) == BROKEN
            assert data["broken"][i] == int(gone)
            assert data["tension"][i] == pytest.approx(0.0 if gone else expected[(a, b)])
            assert data["strain"][i] == pytest.approx(0.0 if gone else expected[(a, b)] * 1e-6)
    bodies = read_pvd(body)
    assert [t for t, _ in bodies] == pytest.approx(times)
    lowest = []
    for _, path in bodies:
        mesh = meshio.read(path)
        assert mesh.cells_dict["triangle"].shape == (4, 3) and len(mesh.points) == 4
        lowest.append(mesh.points[:, 2].min())
    assert lowest == pytest.approx([0.3 - 0.001 * s for s in STEPS])


def test_series_is_replaced_on_rerun_and_left_alone_on_error(tmp_path):
    case = make_case(tmp_path, "impact_grid")
    write_series(case)
    first = sorted(os.listdir(case / "impact_grid"))
    write_series(case)                                   # a rerun replaces the frames
    assert sorted(os.listdir(case / "impact_grid")) == first
    before = (case / "impact_grid.pvd").read_text()
    (case / "run" / "frames" / "nodes.dump").write_text("ITEM: TIMESTEP\n0\n")     # truncated
    with pytest.raises(Exception):
        write_series(case)
    assert (case / "impact_grid.pvd").read_text() == before
    assert sorted(os.listdir(case / "impact_grid")) == first


# ---------------------------------------------------------------------------------------------
# Figure 4

def test_figure4_impact_frame_colour_bar_and_broken_bond(tmp_path):
    case_dir = make_case(tmp_path, "impact_grid")
    write_series(case_dir)
    case = casefolders.load_case(str(case_dir))
    assert figure4.has_series(case)
    data = figure4.load(case)
    assert data["time"] == pytest.approx(STEPS[-1] * DT)        # the block's lowest point
    assert "impact_grid" in data["title"] and "1 broken bond" in data["title"]
    fig, artists = figure4.draw(data)
    # the colour bar spans the tension of the frame's intact bonds, from 0 to the largest
    frame = meshio.read(data["frame"])
    tension = frame.cell_data_dict["tension"]["line"]
    broken = frame.cell_data_dict["broken"]["line"].astype(bool)
    assert artists["colorbar"].mappable.get_clim() == pytest.approx(
        (0.0, tension[~broken].max()))
    assert artists["tension"].get_clim() == pytest.approx((0.0, tension[~broken].max()))
    np.testing.assert_allclose(np.sort(artists["tension"].get_array()),
                               np.sort(tension[~broken & (tension > 0)]))
    assert len(artists["slack"]._segments3d) == int(np.sum(~broken & (tension <= 0)))
    # the broken bond: flagged in the VTU, a red cross at its midpoint in the figure
    lines = frame.point_data["id"][frame.cells_dict["line"]]
    assert sorted(lines[broken][0].tolist()) == list(BROKEN) and broken.sum() == 1
    crosses = np.column_stack(artists["broken"]._offsets3d)
    np.testing.assert_allclose(crosses, [midpoint(frame, *BROKEN)])
    assert artists["body"] is not None
    paths = plots.save(fig, str(tmp_path / "fig4"))
    pixels = png_pixels(paths[0])
    assert pixels.std() > 0.05                                 # not a blank page
    assert np.mean(pixels.min(axis=2) < 0.9) > 0.02            # enough ink
    red = (pixels[..., 0] > 0.8) & (pixels[..., 1] < 0.3) & (pixels[..., 2] < 0.3)
    assert red.sum() > 20                                      # the red cross is drawn


def test_figure4_keeps_to_the_net_when_the_body_is_far_away(tmp_path):
    """A block that went through the net and fell 40 m (issue #42): the view keeps to the net
    and says where the block is, instead of drawing a speck of net beside it."""
    case_dir = make_case(tmp_path, "impact_grid")
    write_series(case_dir)
    data = figure4.load(casefolders.load_case(str(case_dir)))
    near = figure4.draw(data)[1]
    assert near["body"] is not None
    data["body_points"] = data["body_points"] + np.array([0.0, 0.0, -40.0])
    fig, artists = figure4.draw(data)
    assert artists["body"] is None
    ax = artists["axes"]
    span = np.ptp(data["points"], axis=0)
    assert ax.get_zlim()[1] - ax.get_zlim()[0] < 2 * span.max()
    assert any("out of view" in t.get_text() for t in ax.texts)


def test_figure4_punch_uses_the_peak_before_the_first_rupture(tmp_path):
    case_dir = make_case(tmp_path, "punch_grid", kind="punch")
    write_series(case_dir)
    case = casefolders.load_case(str(case_dir))
    assert case.kind == "punch"
    data = figure4.load(case)
    assert data["time"] == pytest.approx(0.2)                  # peak force, before the rupture
    assert not data["broken"].any()
    assert "peak platter force before the first rupture" in data["title"]
    fig, artists = figure4.draw(data)
    assert artists["broken"] is None
    assert artists["colorbar"].mappable.get_clim() == pytest.approx(
        (0.0, data["tension"].max()))
    from postprocess import canvas
    canvas.pyplot().close(fig)


def test_figure4_tensile_uses_the_peak_clamp_force(tmp_path):
    """A tensile case's frame is the one nearest its peak clamp force (tensile.csv), not the one
    with the largest bond tension (the last frame here, as after the peak of a real strip whose
    clamps have moved on)."""
    case_dir = make_case(tmp_path, "tensile_grid", kind="tensile")
    write_series(case_dir)
    case = casefolders.load_case(str(case_dir))
    assert case.kind == "tensile"
    data = figure4.load(case)
    assert data["time"] == pytest.approx(0.1)
    assert "peak clamp force" in data["title"]


def test_study_figures_draw_figure4_for_every_case_with_a_series(tmp_path):
    for name, kind in (("impact_grid", "impact"), ("punch_grid", "punch")):
        write_series(make_case(tmp_path, name, kind))
    written = plots.study_figures(str(tmp_path))
    assert {"fig4_impact_grid", "fig4_punch_grid"} <= set(written)
    for name in ("fig4_impact_grid", "fig4_punch_grid"):
        png = tmp_path / "figures" / f"{name}.png"
        assert png_pixels(png).std() > 0.05
        assert "<svg" in (tmp_path / "figures" / f"{name}.svg").read_text()[:2000]


# ---------------------------------------------------------------------------------------------
# through LIGGGHTS

def _built():
    return (Path(__file__).resolve().parents[2] / "build" / "bin" / "liggghts").is_file()


@pytest.mark.skipif(not _built(), reason="build/bin/liggghts not built")
def test_quick_impact_writes_the_series_and_figure4(tmp_path):
    case_dir = tmp_path / "impact_square"
    api.run(api.load('kind = "impact"\n[panel]\nnet = "square"\n', quick=True), str(case_dir))
    data_file = case_dir / "setup" / "panel.data"
    from postprocess.datafile import read_data
    panel = read_data(str(data_file))
    series = read_pvd(case_dir / "impact_square.pvd")
    assert len(series) >= 15
    times = np.array([t for t, _ in series])
    assert times[0] == 0.0 and np.all(np.diff(times) > 0)
    zmin = []
    for _, path in series:
        mesh = meshio.read(path)
        np.testing.assert_array_equal(mesh.point_data["id"], panel.atom_ids)
        assert len(mesh.cells_dict["line"]) == len(panel.bonds)
        for name in ("tension", "strain", "family", "broken"):
            assert len(mesh.cell_data_dict[name]["line"]) == len(panel.bonds)
        assert set(np.unique(mesh.cell_data_dict["family"]["line"])) <= {1, 2, 3, 4}
        zmin.append(mesh.points[:, 2].min())
    assert min(zmin) < zmin[0] - 0.02                        # the net is pushed down
    bodies = read_pvd(case_dir / "impact_square_body.pvd")
    assert [t for t, _ in bodies] == pytest.approx(times)
    low = [meshio.read(p).points[:, 2].min() for _, p in bodies]
    assert min(low) < low[0] - 0.02                          # the block moves down
    data = figure4.load(casefolders.load_case(str(case_dir)))
    table = casefolders.load_case(str(case_dir)).tables["block"]
    lowest = table["time"][np.argmin(table["z"])]
    assert abs(data["time"] - lowest) <= np.max(np.diff(times)) / 2 + 1e-12
    fig, artists = figure4.draw(data)
    assert artists["colorbar"].mappable.get_clim()[1] == pytest.approx(
        data["tension"][~data["broken"]].max())
    paths = plots.save(fig, str(tmp_path / "fig4"))
    assert png_pixels(paths[0]).std() > 0.05
