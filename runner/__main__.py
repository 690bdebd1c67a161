"""Command line behind ./wirenet run and ./wirenet new:

    /usr/bin/python3 -m runner run [STUDY|CASE|FILE.toml] [--quick] [--np N] [--partitions M]
                                   [--out DIR] [--set KEY=VALUE ...]
    /usr/bin/python3 -m runner run datasheet FILE.toml [...]   the data sheet of the file's net
    /usr/bin/python3 -m runner new KIND               a commented case file on stdout
    /usr/bin/python3 -m runner keys                  the key tables of doc/case_files.md

User errors are one line and exit code 2.
"""

import argparse
import sys

from . import kinds, templates


class _Parser(argparse.ArgumentParser):
    def error(self, message):
        self.exit(2, f"wirenet {self.prog.split()[-1]}: error: {message} (see ./wirenet help)\n")


def _ranks(text):
    try:
        value = int(text)
    except ValueError:
        value = 0
    if value < 1:
        raise argparse.ArgumentTypeError(f"expected an integer > 0, got '{text}'")
    return value


def build_parser():
    parser = _Parser(prog="runner")
    sub = parser.add_subparsers(dest="command", required=True, parser_class=_Parser)
    run = sub.add_parser("run", help="run a study, a case or a case file")
    run.add_argument("target", nargs="?", metavar="STUDY|CASE|FILE.toml",
                     help="a study of inputs/studies/ (default compound: the paper), a case of "
                          "inputs/cases/, or a case or study file; datasheet FILE.toml: the "
                          "data sheet of the file's net (doc/tensile.md)")
    run.add_argument("file", nargs="?", metavar="FILE.toml",
                     help="after datasheet: the case file whose net the data sheet is of")
    run.add_argument("--quick", action="store_true", help="coarse, short versions of the cases")
    run.add_argument("--np", type=_ranks, default=None, metavar="N",
                     help="cores to use (default: WIRENET_NP, else the machine's cores as nproc "
                          "counts them): one case runs on N MPI ranks (a punch's run and its 4x "
                          "slower twin side by side on N/2 each, an odd one more for the run); "
                          "a study runs its cases side by side, one rank each (two for a punch "
                          "and its twin)")
    run.add_argument("--partitions", type=_ranks, default=None, metavar="M",
                     help="run M cases (an ensemble's members) at a time as the partitions of "
                          "one LIGGGHTS multi-partition job (mpirun -np N liggghts -partition "
                          "MxK, K = N / M ranks each; doc/ensembles.md)")
    run.add_argument("--out", metavar="DIR", help="output folder (default: out/NAME)")
    run.add_argument("--set", action="append", metavar="KEY=VALUE",
                     help="override a case-file key (TOML value; repeatable), e.g. "
                          "--set punch.speed=0.02 --set 'supports.left=\"pinned\"'")
    new = sub.add_parser("new", help="print a commented case-file template")
    new.add_argument("kind", choices=[k for k in kinds.NAMES if k != "cantilever"])
    sub.add_parser("keys", help="print the key tables of doc/case_files.md")
    return parser


def main(argv=None):
    args = build_parser().parse_args(argv)
    if args.command == "run":
        from postprocess.errors import PostprocessError
        from . import study
        from .errors import RunError
        if args.file and args.target != "datasheet":
            print(f"wirenet run: error: one target only (got {args.target} and {args.file}; "
                  "a second argument follows datasheet)", file=sys.stderr)
            return 2
        try:
            if args.target == "datasheet":
                from . import datasheet
                datasheet.run(args)
            else:
                study.run(args)
        except (RunError, PostprocessError) as exc:   # a case failed: its folder and the error
            print(f"wirenet run: error: {exc}", file=sys.stderr, flush=True)
            return 2
    elif args.command == "new":
        sys.stdout.write(templates.template(args.kind))
    else:
        sys.stdout.write(templates.key_tables())
    return 0


if __name__ == "__main__":
    sys.exit(main())
