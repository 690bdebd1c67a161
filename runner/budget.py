"""Energy and momentum budgets of a dynamic case (impact, fence). Each term is measured in
LIGGGHTS by its own mechanism (a fix's tally, a compute); this module only adds them up, from
the deck's table read by column name.

A kind declares its budget as a tuple of Terms: what each is, which columns hold it, and
whether it is stored energy (counted as it stands: kinetic, elastic) or an amount since the
first row (potential energies as changes, dissipations as positive amounts). The sum of the
terms must stay at its first value; the closure error is the departure relative to it.
"""

from dataclasses import dataclass

import numpy as np


@dataclass(frozen=True)
class Term:
    name: str            # energy.csv column
    columns: tuple       # the deck table's columns whose sum it is
    meaning: str         # what it is, for the docs and the report
    sign: float = 1.0    # -1 for the work of a force on the system (minus it is dissipated)
    stored: bool = False # counted as it stands (else as its change since the first row)
    dissipative: bool = True   # a mechanism that takes energy out for good (the report's split)
    # stored energies of the same mechanism, taken off (a contact's work is the energy its
    # springs hold now plus what its friction dissipated: the term is the dissipated part)
    less: tuple = ()
    mechanism: str = ""  # the report's group: the name of the mechanism it belongs to


# The terms every block-on-net case shares (impact, fence, drapery): ruptures, the two
# dampings and the block's contact with the net
RUPTURE_DAMPING_CONTACT_TERMS = (
    Term("e_released", ("e_released",), "elastic energy released at ruptures",
         mechanism="ruptures"),
    Term("damping", ("w_damping",), "work of the local damping", sign=-1,
         mechanism="local damping (to ground)"),
    Term("bond_damping", ("w_bond_damping",), "energy dissipated by bond damping",
         mechanism="structural damping (bonds)"),
    Term("e_contact", ("e_contact_block",), "energy stored in the block's contact springs",
         stored=True, dissipative=False),
    Term("friction_block", ("w_contact_block", "w_contact_net"), "dissipated by the block's "
         "contacts with the net: friction and normal damping", sign=-1,
         less=("e_contact_block",), mechanism="friction: block on net"),
)


# The ground's terms (a fence's level ground, a drapery's slope): the nodes' contacts with it
# (fix wirenet/body plane) and the block's (its floor)
GROUND_TERMS = (
    Term("e_ground", ("e_ground",), "energy stored in the ground's contact springs",
         stored=True, dissipative=False),
    Term("friction_ground", ("w_ground",), "dissipated by the ground's contacts with the nodes: "
         "friction and normal damping", sign=-1, less=("e_ground",),
         mechanism="friction: net on ground"),
    Term("e_floor", ("e_floor_block",), "energy stored in the contacts of the block with the "
         "ground", stored=True, dissipative=False),
    Term("friction_block_ground", ("w_floor_block",), "dissipated by the block's contacts with "
         "the ground: friction and normal damping", mechanism="friction: block on ground"),
)


def terms_of(table, terms):
    """{term name: series} of a budget."""
    out = {}
    for term in terms:
        series = None
        for column in term.columns:
            value = table[column] if term.stored else table[column] - table[column][0]
            series = value if series is None else series + value
        series = -series if term.sign < 0 else series
        for column in term.less:
            series = series - table[column]
        out[term.name] = series
    return out


def energy_budget(table, terms, relative_to_largest=False):
    """Per row: every term (terms_of), their sum, the initial energy E0 (the sum at the first
    row) and the closure error (sum - E0) / E0. relative_to_largest: the error relative to the
    largest energy any term reaches instead (a load released at rest starts with next to no
    energy, and gravity gives it all: E0 is then no scale)."""
    values = terms_of(table, terms)
    total = sum(values[t.name] for t in terms)
    e0 = float(total[0])
    scale = reference_energy(values, terms, e0) if relative_to_largest else e0
    return values, total, e0, (total - e0) / scale


def reference_energy(values, terms, e0):
    """The larger of |E0| and the largest energy any term reaches (J)."""
    return max(abs(e0), *(float(np.max(np.abs(values[t.name]))) for t in terms))


def mechanisms(values, terms, row=-1):
    """{mechanism: energy it dissipated by ``row``} over the dissipative terms (J): the
    report's energy by mechanism."""
    out = {}
    for term in terms:
        if term.dissipative and term.mechanism:
            out[term.mechanism] = out.get(term.mechanism, 0.0) + float(values[term.name][row])
    return out


def momentum_gap(dp, *impulses):
    """The change of momentum minus the sum of the impulses of the forces from outside (rows x
    3)."""
    return dp - sum(impulses)


def cumulative(means, window):
    """The impulse of a force given as window means (rows x 3) over windows of ``window`` s."""
    return np.cumsum(means * window[:, None], axis=0)
