"""Command line: ``/usr/bin/python3 -m postprocess {zone,vtu,data2vtu,plot,report,calibrate} ...``.

Every user error is printed as one line ``postprocess CMD: error: MESSAGE`` (the message names
the file and line where there is one) and the exit code is 2; outputs are written to temporary
names and renamed only on success.
"""

import argparse
import math
import sys

from .errors import PostprocessError

DESCRIPTION = "WireNet post-processing (see doc/postprocess.md)."


class _Parser(argparse.ArgumentParser):
    """argparse with the package's error rule: one line on stderr, exit code 2 (the usage is
    one --help away, and the line says so)."""

    def error(self, message):
        self.exit(2, f"{self.prog}: error: {message} (see {self.prog} --help)\n")


def _number(kind, low=None, strict=False, name=None):
    """argparse type: a finite number of ``kind`` (float or int), > or >= ``low``."""
    bound = None if low is None else (f"> {low:g}" if strict else f">= {low:g}")
    wanted = (("an integer" if kind is int else "a finite number")
              + (f" {bound}" if bound else ""))

    def convert(text):
        try:
            value = kind(text)
        except ValueError:
            raise argparse.ArgumentTypeError(f"expected {wanted}, got '{text}'") from None
        if not math.isfinite(value) or (low is not None and (value <= low if strict
                                                            else value < low)):
            raise argparse.ArgumentTypeError(f"expected {wanted}, got '{text}'")
        return value
    convert.__name__ = name or wanted
    return convert


FINITE = _number(float)
POSITIVE = _number(float, 0.0, strict=True)
POSITIVE_INT = _number(int, 0, strict=True)


class _Formatter(argparse.ArgumentDefaultsHelpFormatter):
    """Shows '(default: X)' only for options that have a real default."""

    def _get_help_string(self, action):
        if action.default in (None, False, argparse.SUPPRESS) or "default" in (action.help or ""):
            return action.help
        return super()._get_help_string(action)


def _formatter(prog):
    return _Formatter(prog, max_help_position=32)


def _add_zone(sub):
    p = sub.add_parser(
        "zone", formatter_class=_formatter,
        help="tension of the bonds in a circular zone, per output step and family",
        description="Per output step and bond family: total and maximum tensile force and the "
                    "number of bonds whose midpoint lies in a circle of the panel plane. "
                    "Compressive forces count as 0. Writes CSV time,displacement,family,"
                    "total_tension,max_tension,bonds (N, m, s).")
    p.add_argument("bonds", nargs="+", metavar="BONDS.dump",
                   help="bond dump(s) of compute wirenet/local (12 columns, or at least atom1 "
                        "atom2 type ... tension with --nodes); several files are merged by step")
    p.add_argument("--nodes", nargs="+", metavar="NODES.dump",
                   help="node dump(s) (dump custom id type x y z) to compute midpoints when the "
                        "bond dump has no midpoint columns c_ID[8..10]")
    p.add_argument("--dt", type=POSITIVE, required=True, help="time step [s]; time = step x dt")
    p.add_argument("--json", metavar="PREFIX.json",
                   help="generator metadata: zone centre, panel normal, bond_types (families); "
                        "without it: centre 0 0 0, normal 0 0 1, families 1=DT,2=SW,"
                        "3=selvedge,4=rope")
    p.add_argument("--radius", type=POSITIVE, default=1.0, help="zone radius [m]")
    p.add_argument("--centre", "--center", type=FINITE, nargs=3, metavar=("X", "Y", "Z"),
                   help="zone centre [m] (default: 'centre' of --json, else 0 0 0)")
    p.add_argument("--normal", type=FINITE, nargs=3, metavar=("NX", "NY", "NZ"),
                   help="panel normal (default: 'normal' of --json, else 0 0 1)")
    p.add_argument("--families", metavar="T=NAME,...",
                   help="bond type -> family names, overrides --json (e.g. 1=DT,2=SW)")
    p.add_argument("--displacement", metavar="CSV",
                   help="CSV with a time column and a displacement column (e.g. platter.csv) "
                        "interpolated linearly at each output time, clamped outside its range; "
                        "without it the displacement column is 0")
    p.add_argument("--displacement-column", default="displacement",
                   help="column of --displacement to use")
    p.add_argument("--time-column", default="time", help="time column of --displacement")
    p.add_argument("--out", "-o", default="zone_forces.csv", help="output CSV")
    p.set_defaults(run="zone")


def _add_vtu(sub):
    p = sub.add_parser(
        "vtu", formatter_class=_formatter,
        help="ParaView time series: nodes as points, bonds as lines with tension",
        description="One .vtu per bond-dump frame (points = nodes, line cells = bonds with "
                    "cell data tension, strain, family, broken, ...) and a .pvd time series. "
                    "OUT.pvd references the frames in folder OUT/.")
    p.add_argument("--nodes", nargs="+", required=True, metavar="NODES.dump",
                   help="node dump(s): dump custom with id type x y z (other columns become "
                        "point data); needs a frame at every bond-dump step")
    p.add_argument("--bonds", nargs="+", required=True, metavar="BONDS.dump",
                   help="bond dump(s) of compute wirenet/local")
    p.add_argument("--data", metavar="PREFIX.data",
                   help="generator data file: its bonds missing from a frame are added with "
                        "broken=1 (without it the first frame's bonds are the reference)")
    p.add_argument("--dt", type=POSITIVE, default=1.0,
                   help="time step [s] for the .pvd times (time = step x dt)")
    p.add_argument("--ascii", action="store_true", help="write ASCII instead of binary VTU")
    p.add_argument("--out", "-o", default="wirenet.pvd", help="output .pvd (frames in OUT/)")
    p.set_defaults(run="vtu")


def _add_data2vtu(sub):
    p = sub.add_parser(
        "data2vtu", formatter_class=_formatter,
        help="a generator's PREFIX.data as one .vtu (points + bonds)",
        description="Points with id, type, diameter, density, molecule; line cells with "
                    "bond_id and family (= bond type).")
    p.add_argument("data", metavar="PREFIX.data", help="LIGGGHTS data file of wirenet-gen")
    p.add_argument("--ascii", action="store_true", help="write ASCII instead of binary VTU")
    p.add_argument("--out", "-o", help="output .vtu (default: PREFIX.vtu)")
    p.set_defaults(run="data2vtu")


def _add_plot(sub):
    p = sub.add_parser("plot", help="the paper's figures from the study CSVs (PNG and SVG)",
                       description="Figures as PREFIX.png and PREFIX.svg (matplotlib, Agg).")
    kinds = p.add_subparsers(dest="figure", metavar="FIGURE", required=True)
    b = kinds.add_parser("beam", formatter_class=_formatter,
                         help="Figure 1: beam check (beam.csv, optional deflection line)",
                         description="beam.csv: elements,load,tip_deflection,"
                                     "analytic_deflection,nrmse. Optional --line CSV: x,"
                                     "deflection[,analytic_deflection][,elements].")
    b.add_argument("csv", metavar="beam.csv")
    b.add_argument("--line", metavar="CSV", help="deflection line along the beam")
    c = kinds.add_parser("calibration", formatter_class=_formatter,
                         help="Figure 2: force-displacement curves of several platter.csv",
                         description="platter.csv: time,displacement,force.")
    c.add_argument("csv", nargs="+", metavar="platter.csv")
    c.add_argument("--labels", nargs="+", help="one label per file (default: the bending "
                   "fraction of the folder's case.json, else the folder name)")
    z = kinds.add_parser("zone", formatter_class=_formatter,
                         help="Figures 3, 5, 6: max and total tension per family",
                         description="Maximum and total tension of zone_forces.csv files vs "
                                     "displacement or time; several files are overlaid.")
    z.add_argument("csv", nargs="+", metavar="zone_forces.csv")
    z.add_argument("--labels", nargs="+", help="one label per file (default: folder name)")
    z.add_argument("--x", choices=("time", "displacement"), default="time", help="abscissa")
    z.add_argument("--families", nargs="+", help="families to plot (default: all with a "
                   "non-zero force)")
    z.add_argument("--title", help="figure title")
    s = kinds.add_parser("study", formatter_class=_formatter,
                         help="all figures available from the case folders of a study DIR",
                         description="Writes DIR/figures/fig1_beam, fig2_calibration, "
                                     "fig3_punch, fig5_impact_hex, fig6_impact_square "
                                     "(.png, .svg) for the cases present.")
    s.add_argument("dir", metavar="DIR")
    for q in (b, c, z):
        q.add_argument("--out", "-o", required=True, metavar="PREFIX",
                       help="writes PREFIX.png and PREFIX.svg")
    p.set_defaults(run="plot")


def _add_report(sub):
    p = sub.add_parser(
        "report", formatter_class=_formatter,
        help="DIR/report.md and DIR/summary.json from the case folders of DIR",
        description="Reads DIR/CASE/{zone_forces,platter,block,beam}.csv and DIR/CASE/case.json, "
                    "draws the figures (DIR/figures), tabulates peaks per case and family, and "
                    "evaluates the paper's three claims.")
    p.add_argument("dir", metavar="DIR")
    p.add_argument("--no-figures", action="store_true", help="skip the figures")
    p.add_argument("--expect", nargs="+", metavar="CASE",
                   help="cases the study should have (missing ones are reported); default: "
                        "beam punch_hex punch_compound impact_hex impact_square impact_compound "
                        "and at least one calib* case")
    p.set_defaults(run="report")


def _add_calibrate(sub):
    p = sub.add_parser(
        "calibrate", formatter_class=_formatter,
        help="best bending fraction for a measured force-displacement curve",
        description="Interpolates the platter.csv curves of the calibration cases in "
                    "log10(fraction + 1e-3) and finds the fraction (continuous, between the "
                    "smallest and the largest simulated one) that minimises the RMSE against "
                    "the measured curve. Writes PREFIX.json, PREFIX.png and PREFIX.svg.")
    p.add_argument("measured", metavar="MEASURED.csv",
                   help="measured curve with a displacement [m] and a force [N] column")
    p.add_argument("--cases", nargs="+", required=True, metavar="DIR",
                   help="calibration case folders (platter.csv + case.json 'bending')")
    p.add_argument("--out", "-o", default="calibration_fit", metavar="PREFIX",
                   help="output prefix")
    p.add_argument("--displacement-column", default="displacement")
    p.add_argument("--force-column", default="force")
    p.set_defaults(run="calibrate")


def build_parser():
    parser = _Parser(prog="postprocess", description=DESCRIPTION)
    sub = parser.add_subparsers(dest="command", metavar="COMMAND", required=True)
    for add in (_add_zone, _add_vtu, _add_data2vtu, _add_plot, _add_report,
                _add_calibrate):
        add(sub)
    return parser


def _dispatch(args):
    if args.run == "zone":
        from . import zone
        zone.run(args)
    elif args.run == "vtu":
        from . import vtu
        vtu.run(args)
    elif args.run == "data2vtu":
        from . import vtu
        vtu.run_data(args)
    elif args.run == "plot":
        from . import plots
        plots.run(args)
    elif args.run == "report":
        from . import report
        report.run(args)
    elif args.run == "calibrate":
        from . import calibrate
        calibrate.run(args)


def main(argv=None):
    """Run the command line; return the exit code (0, or 2 on a user error)."""
    args = build_parser().parse_args(argv)
    try:
        _dispatch(args)
    except PostprocessError as exc:
        print(f"postprocess {args.command}: error: {_one_line(str(exc))}", file=sys.stderr)
        return 2
    except OSError as exc:
        print(f"postprocess {args.command}: error: {_one_line(_os_error_text(exc))}",
              file=sys.stderr)
        return 2
    return 0


def _one_line(text):
    """The message with control characters (from a damaged input quoted in it) escaped, so that
    the error stays one printable line."""
    return "".join(ch if ch.isprintable() else ascii(ch)[1:-1] for ch in text)


def _os_error_text(exc):
    """One line for an OSError: 'FILE: reason' (the reason alone when no file is known)."""
    reason = exc.strerror or str(exc) or type(exc).__name__
    return f"{exc.filename}: {reason}" if exc.filename else reason


if __name__ == "__main__":
    sys.exit(main())
