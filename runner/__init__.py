"""WireNet's case runner. One way through it:

    case file (casefile.py, checked against schema.py)
      -> kind (kinds/: one module per kind of case, on kinds/base.py)
      -> deck (inputs/*.in, -var values from the kind; the net from generator.py)
      -> engine (engine.py: LIGGGHTS under mpirun, process groups, progress, interrupts)
      -> outputs (the deck's tables read by name: tables.py)
      -> record (postprocess/record.py: case.json, written by study.py)
      -> report (postprocess/report.py)

Physics every kind shares has a module of its own: the time step (timestep.py), the quasi-static
evidence (quasistatic.py), energy and momentum budgets (budget.py). doc/architecture.md draws the
flow and says where each thing lives. The analysis of dumps and the report live in the package
`postprocess`, which this package calls and which never calls back.
"""

from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
INPUTS = ROOT / "inputs"
