"""Outputs every net case writes the same way from its deck's dumps: the zone forces, the
ruptures, the ParaView series of the net and the loading body (doc/file_formats.md)."""

import os

import numpy as np

from postprocess import bodyframes, vtu, zone
from postprocess.csvio import write_csv
from postprocess.meta import PanelInfo

RUPTURE_COLUMNS = ("step", "atom1", "atom2", "type", "x", "y", "z", "elongation")


def read_rupture_dump(path):
    """Rows of the rupture dump (include/ruptures.in: RUPTURE_COLUMNS), sorted by step."""
    if not os.path.isfile(path):
        return np.zeros((0, len(RUPTURE_COLUMNS)))
    rows, body = [], False
    with open(path) as fh:
        for line in fh:
            if line.startswith("ITEM: ENTRIES"):
                body = True
                continue
            if line.startswith("ITEM:"):
                body = False
                continue
            if body and line.strip():
                rows.append([float(v) for v in line.split()[:len(RUPTURE_COLUMNS)]])
    rows = np.array(rows, float).reshape(-1, len(RUPTURE_COLUMNS))
    return rows[np.argsort(rows[:, 0], kind="stable")]


def ruptures(path, dt, families):
    """Every broken bond of a run as a dict (time, step, atoms, type, family, midpoint,
    elongation)."""
    out = []
    for step, a1, a2, btype, x, y, z, elong in read_rupture_dump(path):
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
