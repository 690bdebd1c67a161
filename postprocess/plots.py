"""The paper's figures (matplotlib, Agg backend), each saved as PREFIX.png and PREFIX.svg."""

import os
import sys

import numpy as np

from . import casefolders
from .csvio import read_csv
from .output import Outputs
from .summary import case_summary
from .errors import PostprocessError
from .canvas import check_prefix, force_scale, pyplot, save  # noqa: F401 (check_prefix: the CLI's)

FAMILY_COLOURS = {"DT": "tab:blue", "SW": "tab:orange", "selvedge": "tab:green",
                  "rope": "tab:red", "beam": "tab:purple"}
LINESTYLES = ("-", "--", ":", "-.")
# the paper's figures 3, 5 and 6: (the nets compared, families, x axis, title); their cases are
# found by what they are (postprocess/claims.py), not by their names
STUDY_FIGURES = {
    "fig3_punch": (("hex", "compound"), ("DT", "SW"), "displacement",
                   "Figure 3: punch tests, tension in the central zone"),
    "fig5_impact_hex": (("hex", "compound"), ("DT", "SW"), "time",
                        "Figure 5: impact, hexagonal mesh wires"),
    "fig6_impact_square": (("square", "compound"), ("rope",), "time",
                           "Figure 6: impact, strand-rope (square) mesh"),
}


def _figure_cases(name, nets, summaries):
    """The case names a study figure compares: the punch group for Figure 3, the first impact
    group holding both nets (under the first dissipation model) for Figures 5 and 6."""
    from . import claims
    if name == "fig3_punch":
        group = claims.punch_group(summaries)
        return [group[n] for n in nets if n in group]
    for model in claims.models(summaries):
        for group in claims.impact_groups(summaries, model).values():
            if all(n in group for n in nets):
                return [group[n] for n in nets]
    return []


def figure_beam(beam, prefix, line=None, outputs=None):
    """Figure 1: deflection (line, or tip deflection vs load) and NRMSE vs elements."""
    plt = pyplot()
    fig, (left, right) = plt.subplots(1, 2, figsize=(10, 4), layout="constrained")
    elements = beam["elements"]
    if line is not None:
        groups = np.unique(line["elements"]) if "elements" in line else [None]
        for n in groups:
            rows = (line["elements"] == n) if n is not None else slice(None)
            label = f"DEM, {int(n)} elements" if n is not None else "DEM"
            left.plot(line["x"][rows], line["deflection"][rows], "o-", ms=3, label=label)
        for key in ("analytic_deflection", "analytic"):
            if key in line:
                rows = line["elements"] == groups[-1] if groups[0] is not None else slice(None)
                left.plot(line["x"][rows], line[key][rows], "k-", lw=1, label="analytic")
                break
        left.set_xlabel("position along the beam x [m]")
        left.set_ylabel("deflection [m]")
    else:
        for n in np.unique(elements):
            rows = elements == n
            left.plot(beam["load"][rows], beam["tip_deflection"][rows], "o", label=f"DEM, "
                      f"{int(n)} elements")
        order = np.argsort(beam["load"])
        left.plot(beam["load"][order], beam["analytic_deflection"][order], "k-", lw=1,
                  label="analytic")
        left.set_xlabel("tip load [N]")
        left.set_ylabel("tip deflection [m]")
    left.legend()
    left.set_title("(a) deflection")
    right.plot(elements, beam["nrmse"], "s-")
    right.set_xlabel("number of elements [-]")
    right.set_ylabel("NRMSE [-]")
    right.set_title("(b) normalised RMS error")
    fig.suptitle("Figure 1: beam tip-load test")
    return save(fig, prefix, outputs)


def relative_to_first(curves, floor=0.002):
    """[(label, displacement, percent)]: each later curve's force minus the first one's (linear
    interpolation on the first one's displacements), in % of the first one's force, where that
    force is at least FLOOR of its largest |value| (below it the ratio is noise). Empty curves
    are left out."""
    _, x_ref, f_ref = curves[0]
    if not np.size(f_ref):
        return []
    order = np.argsort(x_ref)
    x_ref, f_ref = np.asarray(x_ref)[order], np.asarray(f_ref)[order]
    keep = np.abs(f_ref) >= floor * np.max(np.abs(f_ref))
    result = []
    for label, x, force in curves[1:]:
        if not np.size(x):
            continue
        order = np.argsort(x)
        x, force = np.asarray(x)[order], np.asarray(force)[order]
        inside = keep & (x_ref >= x[0]) & (x_ref <= x[-1])
        other = np.interp(x_ref[inside], x, force)
        result.append((label, x_ref[inside], 100.0 * (other - f_ref[inside]) / f_ref[inside]))
    return result


def figure_calibration(curves, prefix, outputs=None):
    """Figure 2: (a) platter force vs displacement, one curve per (label, displacement, force);
    (b) with several curves, each one's difference to the first in % (they nearly overlap)."""
    plt = pyplot()
    several = len(curves) > 1
    fig, axes = plt.subplots(1, 2 if several else 1, figsize=(11 if several else 6, 4.5),
                             layout="constrained", squeeze=False)
    axis = axes[0][0]
    scale, unit = force_scale([force for _, _, force in curves])
    colours = {label: axis.plot(displacement, force / scale, label=label)[0].get_color()
               for label, displacement, force in curves}
    axis.set_xlabel("platter displacement [m]")
    axis.set_ylabel(f"platter force [{unit}]")
    axis.legend(title="bending stiffness ratio")
    if several:
        axis.set_title("(a) force-displacement curves")
        right = axes[0][1]
        right.axhline(0.0, color=colours[curves[0][0]], lw=1, label=curves[0][0])
        for label, x, percent in relative_to_first(curves):
            right.plot(x, percent, color=colours[label], label=label)
        right.set_xlabel("platter displacement [m]")
        right.set_ylabel(f"force relative to ratio {curves[0][0]} [%]")
        right.set_title(f"(b) difference to ratio {curves[0][0]} (force >= 0.2 % of its peak)")
        right.legend(title="bending stiffness ratio")
        fig.suptitle("Figure 2: square-mesh cone punch, bending-fraction sensitivity")
    else:
        axis.set_title("Figure 2: square-mesh cone punch, bending-fraction sensitivity")
    return save(fig, prefix, outputs)


def _families_to_plot(series, families):
    if families:
        return list(families)
    found = []
    for _, zone in series:
        for name, data in zone.items():
            if name not in found and (np.any(data["total"] != 0) or np.any(data["max"] != 0)):
                found.append(name)
    return found


def figure_zone(series, prefix, x="time", families=None, title=None, ruptures=None,
                outputs=None):
    """Figures 3, 5, 6: (a) maximum and (b) total tension per family of several cases.

    ``series``: list of (label, Case.zone() dict). Colour = family, line style = case.
    ``ruptures``: {label: x of the case's first rupture}, drawn as a grey vertical line in the
    case's line style (where the mesh starts to tear, the curves stop being quasi-static).
    """
    plt = pyplot()
    families = _families_to_plot(series, families)
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), layout="constrained")
    for panel, key, name in ((axes[0], "max", "maximum"), (axes[1], "total", "total")):
        values = [z[f][key] for _, z in series for f in families if f in z]
        scale, unit = force_scale(values)
        for index, (label, zone) in enumerate(series):
            for family in families:
                if family not in zone:
                    continue
                data = zone[family]
                panel.plot(data[x], data[key] / scale, LINESTYLES[index % len(LINESTYLES)],
                           color=FAMILY_COLOURS.get(family), label=f"{label}: {family}")
            at = (ruptures or {}).get(label)
            if at is not None:
                panel.axvline(at, ls=LINESTYLES[index % len(LINESTYLES)], color="0.5", lw=1,
                              label=f"{label}: first rupture")
        panel.set_xlabel("platter displacement [m]" if x == "displacement" else "time [s]")
        panel.set_ylabel(f"{name} tensile force [{unit}]")
        panel.set_title(f"({'a' if key == 'max' else 'b'}) {name} bond tension in the zone")
        if values:
            panel.legend(fontsize="small")
    if title:
        fig.suptitle(title)
    return save(fig, prefix, outputs)


FENCE_ENERGY = (("ke_block", "block kinetic"), ("ke_net", "fence kinetic"),
                ("e_elastic", "bonds elastic"), ("e_shackle", "shackle springs"),
                ("w_plastic", "plastic (wires, brakes)"), ("friction", "shackle friction"),
                ("damping", "local damping"), ("bond_damping", "bond damping"))


def figure_fence(case_dir, prefix, title=None, outputs=None):
    """A fence impact (runner/fence.py): (a) the window-mean reaction of every anchor and post
    base (supports.csv), (b) where the energy went (energy.csv; gravity terms left out)."""
    plt = pyplot()
    supports = read_csv(os.path.join(case_dir, "supports.csv"), required=("time",))
    energy = read_csv(os.path.join(case_dir, "energy.csv"),
                      required=("time",) + tuple(k for k, _ in FENCE_ENERGY))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), layout="constrained")
    names = [k for k in supports if k != "time"]
    scale, unit = force_scale([supports[k] for k in names])
    for name in names:
        axes[0].plot(supports["time"], supports[name] / scale, "--" if "post" in name else "-",
                     label=name)
    axes[0].set_xlabel("time [s]")
    axes[0].set_ylabel(f"|reaction| [{unit}]")
    axes[0].set_title("(a) anchors (solid) and post bases (dashed)")
    axes[0].legend(fontsize="x-small", ncol=2)
    _energy_axes(axes[1], energy, FENCE_ENERGY)
    if title:
        fig.suptitle(title)
    return save(fig, prefix, outputs)


def _energy_axes(ax, energy, terms):
    """(b) of the fence and impact figures: each term of energy.csv that reaches 0.1 % of the
    initial total, in kJ against time."""
    e0 = float(energy["total"][0]) if "total" in energy else 1.0
    for key, label in terms:
        if key in energy and np.max(np.abs(energy[key])) > 1e-3 * abs(e0):
            ax.plot(energy["time"], energy[key] / 1e3, label=label)
    ax.set_xlabel("time [s]")
    ax.set_ylabel("energy [kJ]")
    ax.set_title("(b) energy by component")
    ax.legend(fontsize="small")


IMPACT_ENERGY = (("ke_block", "block kinetic"), ("ke_net", "net kinetic"),
                 ("e_elastic", "bonds elastic"), ("w_plastic", "plastic"),
                 ("e_released", "released at ruptures"), ("damping", "local damping"),
                 ("bond_damping", "bond damping"), ("friction_block", "block friction"),
                 ("contact_layers", "layer contacts"))
EDGE_PARTS = ("left", "right", "bottom", "top", "corners")


def figure_impact(case_dir, prefix, title=None, outputs=None):
    """A panel impact (runner/kinds/impact.py): (a) the block's contact force, the sum of all
    supports and each edge's and the corners' reaction over time (window means; block.csv,
    edges.csv), (b) where the energy went (energy.csv; gravity terms left out)."""
    plt = pyplot()
    block = read_csv(os.path.join(case_dir, "block.csv"), required=("time", "force"))
    edges = read_csv(os.path.join(case_dir, "edges.csv"), required=("time", "force"))
    energy = read_csv(os.path.join(case_dir, "energy.csv"), required=("time",))
    fig, axes = plt.subplots(1, 2, figsize=(11, 4.5), layout="constrained")
    parts = [p for p in EDGE_PARTS if f"{p}_force" in edges and np.any(edges[f"{p}_force"])]
    series = [block["force"], edges["force"]] + [edges[f"{p}_force"] for p in parts]
    scale, unit = force_scale(series)
    axes[0].plot(block["time"], block["force"] / scale, color="k", label="block contact")
    axes[0].plot(edges["time"], edges["force"] / scale, color="tab:red", lw=2,
                 label="all supports (vector sum)")
    for p in parts:
        axes[0].plot(edges["time"], edges[f"{p}_force"] / scale, "--", label=f"{p} edge"
                     if p != "corners" else "corners")
    axes[0].set_xlabel("time [s]")
    axes[0].set_ylabel(f"force [{unit}]")
    axes[0].set_title("(a) block contact and support reactions")
    axes[0].legend(fontsize="x-small")
    _energy_axes(axes[1], energy, IMPACT_ENERGY)
    if title:
        fig.suptitle(title)
    return save(fig, prefix, outputs)


def figure_tensile(case_dir, prefix, title=None, outputs=None):
    """A tensile case (runner/kinds/tensile.py, doc/tensile.md): the force on the moving clamp
    and the fixed clamp's reaction against the clamp's travel (tensile.csv), the peak and the
    first rupture marked."""
    plt = pyplot()
    table = read_csv(os.path.join(case_dir, "tensile.csv"),
                     required=("displacement", "force", "reaction"))
    fig, ax = plt.subplots(figsize=(7, 4.5), layout="constrained")
    scale, unit = force_scale([table["force"], table["reaction"]])
    u = np.r_[0.0, table["displacement"]] * 1e3
    ax.plot(u, np.r_[0.0, table["force"]] / scale, label="force on the moving clamp")
    ax.plot(u, np.r_[0.0, table["reaction"]] / scale, "--", label="fixed clamp's reaction")
    if len(table["force"]):
        k = int(np.argmax(table["force"]))
        ax.plot(table["displacement"][k] * 1e3, table["force"][k] / scale, "o", color="black",
                label=f"peak {table['force'][k] / scale:.4g} {unit} at "
                      f"{table['displacement'][k] * 1e3:.4g} mm")
    meta_path = os.path.join(case_dir, "case.json")
    if os.path.isfile(meta_path):
        import json
        with open(meta_path, encoding="utf-8") as handle:
            first = first_rupture_at(json.load(handle).get("first_rupture"), "displacement")
        if first is not None:
            ax.axvline(first * 1e3, color="red", linestyle=":", label="first rupture")
    ax.set_xlabel("clamp travel [mm]")
    ax.set_ylabel(f"force [{unit}]")
    ax.legend(fontsize="small")
    if title:
        ax.set_title(title, fontsize="medium")
    return save(fig, prefix, outputs)


def first_rupture_at(record, x):
    """Abscissa of a case.json first rupture on a figure plotted against x: the punch records
    {displacement, ...}, the impact a time; None when absent or not on that axis."""
    if isinstance(record, dict):
        value = record.get(x)
    else:
        value = record if x == "time" else None
    return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) \
        else None


def _case_label(path, labels, index):
    if labels:
        return labels[index]
    return os.path.basename(os.path.dirname(os.path.abspath(path))) or path


def study_figures(directory, cases=None, outputs=None, summaries=None):
    """Every figure the case folders allow, in DIR/figures, all or none; returns
    {figure: [paths]}. With ``outputs`` (output.Outputs) the figures are committed with the
    caller's other outputs (e.g. report.md and summary.json)."""
    cases = casefolders.discover(directory) if cases is None else cases
    if summaries is None:
        summaries = {n: case_summary(c) for n, c in cases.items()}
    if outputs is not None:
        return _study_figures(directory, cases, outputs, summaries)
    with Outputs() as own:
        return _study_figures(directory, cases, own, summaries)


def _study_figures(directory, cases, outputs, summaries):
    out = os.path.join(directory, "figures")
    written = {}
    beams = [c for c in cases.values() if c.kind == "beam" and c.usable and "beam" in c.tables]
    if beams:
        line = _optional_line(beams[0].line_path())
        written["fig1_beam"] = figure_beam(beams[0].tables["beam"],
                                           os.path.join(out, "fig1_beam"), line, outputs)
    calibration = casefolders.calibration_cases(cases)
    if calibration:
        curves = [(_format_bending(c), c.tables["platter"]["displacement"],
                   c.tables["platter"]["force"]) for c in calibration]
        written["fig2_calibration"] = figure_calibration(
            curves, os.path.join(out, "fig2_calibration"), outputs)
    for name, (nets, families, x, title) in STUDY_FIGURES.items():
        wanted = _figure_cases(name, nets, summaries)
        series = [(c, cases[c].zone()) for c in wanted
                  if c in cases and cases[c].usable and "zone" in cases[c].tables]
        if series:
            ruptures = {c: first_rupture_at(cases[c].meta.get("first_rupture"), x)
                        for c, _ in series}
            written[name] = figure_zone(series, os.path.join(out, name), x, families, title,
                                        ruptures, outputs)
    # one figure per fence, panel impact and tensile case that wrote its table
    for kind, figure, table, stem in (("fence", figure_fence, None, "fence"),
                                      ("impact", figure_impact, "edges.csv", "history"),
                                      ("tensile", figure_tensile, "tensile.csv", "tensile")):
        for case in cases.values():
            if case.kind != kind or not case.usable or (
                    table and not os.path.isfile(os.path.join(case.path, table))):
                continue
            name = f"{stem}_{case.name}"
            try:
                written[name] = figure(case.path, os.path.join(out, name),
                                       case.meta.get("title") or case.name, outputs)
            except PostprocessError as exc:
                print(f"postprocess: warning: {name} skipped: {exc}", file=sys.stderr)
    # Figure 4: the deformed net at the peak, one per punch / calibration / impact case that
    # wrote its ParaView series (figure4.py)
    from . import figure4
    for case in cases.values():
        if case.usable and figure4.has_series(case):
            name = f"fig4_{case.name}"
            try:
                written[name] = figure4.figure_case(case, os.path.join(out, name), outputs)
            except PostprocessError as exc:
                print(f"postprocess: warning: {name} skipped: {exc}", file=sys.stderr)
    return written


def _optional_line(path):
    """The beam's deflection-line CSV, or None (with a warning when it is unreadable)."""
    if not path:
        return None
    try:
        return read_csv(path, required=("x", "deflection"))
    except PostprocessError as exc:
        print(f"postprocess: warning: deflection line skipped: {exc}", file=sys.stderr)
        return None


def _format_bending(case):
    return f"{case.bending:g}" if case.bending is not None else case.name


def run(args):
    """The ``plot`` subcommand."""
    if args.figure == "study":
        written = study_figures(args.dir)
        for name, paths in written.items():
            print(f"wrote {', '.join(paths)}")
        if not written:
            print(f"no figures: no usable case folders in {args.dir}")
        return
    check_prefix(args.out)
    labels = getattr(args, "labels", None)
    if labels and len(labels) != len(args.csv):
        raise PostprocessError(f"--labels: {len(labels)} labels for {len(args.csv)} files")
    if args.figure == "beam":
        beam = read_csv(args.csv, required=casefolders.TABLES["beam"][1])
        line = read_csv(args.line, required=("x", "deflection")) if args.line else None
        paths = figure_beam(beam, args.out, line)
    elif args.figure == "calibration":
        curves = []
        for index, path in enumerate(args.csv):
            table = read_csv(path, required=casefolders.TABLES["platter"][1])
            label = labels[index] if labels else _format_bending(
                casefolders.load_case(os.path.dirname(os.path.abspath(path))))
            curves.append((label, table["displacement"], table["force"]))
        paths = figure_calibration(curves, args.out)
    else:
        series = []
        for index, path in enumerate(args.csv):
            case = casefolders.Case(_case_label(path, labels, index), os.path.dirname(path))
            case.tables["zone"] = read_csv(path, required=casefolders.TABLES["zone"][1])
            series.append((case.name, case.zone()))
        paths = figure_zone(series, args.out, args.x, args.families, args.title)
    print(f"wrote {', '.join(paths)}")
