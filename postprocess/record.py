"""The record of a case folder, DIR/CASE/case.json: written by the study runner (runner/study.py)
when a case starts and ends, read by the report (postprocess/report.py) and by the study's
resume. One class for both sides, so that the writer and the reader agree on every name.

case.json is one JSON object: the fields below, then the facts the case's kind returned
(runner/kinds/, doc/file_formats.md), at the same level.
"""

from dataclasses import dataclass, field

# How a case ended. 'ok' is the only status whose numbers the report uses as results; every
# other status says what happened, and the runner exits non-zero for it (runner/study.py).
RUNNING = "running"          # started, not ended (a crash or a kill leaves it so)
OK = "ok"                    # ran and did what the case says
FAILED = "failed"            # an error stopped it (the record's `error`)
INTERRUPTED = "interrupted"  # Ctrl-C or SIGTERM stopped it; the next run redoes it
# ran to the end but did not do what the case says (`verdict` says what and what to change)
NO_CONTACT = "no-contact"            # the loading body never touched the net
LEFT_BOX = "left-box"                # the body or atoms left the simulation box
BUDGET_OPEN = "budget-open"          # the energy budget did not close to its tolerance
NOT_QUASI_STATIC = "not-quasi-static"    # the quasi-static evidence failed
NOT_SETTLED = "not-settled"          # the structure still moved under its weight at the release
NOT_ENDED = "not-ended"              # the run ended with the block still moving into the structure
STATUSES = (RUNNING, OK, FAILED, INTERRUPTED, NO_CONTACT, LEFT_BOX, BUDGET_OPEN,
            NOT_QUASI_STATIC, NOT_SETTLED, NOT_ENDED)
UNSOUND = (NO_CONTACT, LEFT_BOX, BUDGET_OPEN, NOT_QUASI_STATIC, NOT_SETTLED, NOT_ENDED)

# the fields of the record itself; every other key of case.json is a fact of the kind
FIELDS = ("kind", "status", "quick", "mode", "np", "case_file", "case_fingerprint", "title",
          "wall_time", "cpu_time", "started", "finished", "error", "verdict")


@dataclass
class CaseRecord:
    kind: str                      # the kind's record kind (beam, calibration, punch, ...)
    status: str = RUNNING
    quick: bool = False
    np: int = 1                    # MPI ranks it ran on
    case_file: str = ""
    case_fingerprint: str = ""     # sha256 of the checked case values (resume)
    title: str = ""
    wall_time: float = None
    cpu_time: float = None         # CPU seconds of its LIGGGHTS processes
    started: float = None          # Unix times
    finished: float = None
    error: str = None              # status failed: the error line
    verdict: str = None            # an unsound status: what happened and what to change
    facts: dict = field(default_factory=dict)

    @property
    def mode(self):
        return "quick" if self.quick else "full"

    def to_json(self):
        out = {name: getattr(self, name) for name in FIELDS}
        out = {k: v for k, v in out.items() if v is not None or k in ("kind", "status")}
        out.update(self.facts)
        return out

    @classmethod
    def from_json(cls, meta):
        """The record of a case.json object (a dict, as read); facts are the other keys."""
        facts = {k: v for k, v in meta.items() if k not in FIELDS}
        known = {k: meta[k] for k in FIELDS if k in meta and k != "mode"}
        known.setdefault("kind", "")
        return cls(**known, facts=facts)
