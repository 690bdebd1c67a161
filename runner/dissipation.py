"""Where a dynamic case's energy goes (doc/impact.md, "Dissipation"): the physical model every
impact and fence uses by default, and the damping of the phases outside its energy budget.

During the impact nothing damps absolute velocity: the energy goes into the wires' and ropes'
plasticity, the brakes, ruptures, friction (block on net, net on ground, between the net's
layers, shackles on ropes) and a structural damping of the bonds' relative motion, which
conserves momentum. Local (Cundall) damping pushes every node towards rest in absolute space, a
force to ground: it is kept for the static settling before the impact and for the search of the
resting state after it (both outside the budget), and as a user's option (damping.local).
"""

# Structural damping: viscous damping of each bond's relative motion, 5 % of its two-node
# oscillator's critical damping (bond_coeff ... damping 0.05). "A few percent" is the damping
# ratio handbooks give metal structures with joints (3-7 %: Adams and Askenazi, Building Better
# Products with Finite Element Analysis, OnWord Press 1999, table of viscous damping ratios).
# Acting per bond it is stiffness-proportional: a mode of the net at omega gets about
# 0.05 omega / omega_bond of critical, so it damps the bonds' own ringing, not the net's swing
# (the energy it takes is reported with every case, and its sensitivity in doc/impact.md).
STRUCTURAL_ZETA = 0.05
STRUCTURAL_ZETA_SOURCE = ("Adams and Askenazi (1999), the viscous damping ratios of metal "
                          "structures with joints, 3-7 % (as tabulated in SolidWorks' help)")

# Local damping while a net or fence settles under its weight before the load, and while it
# comes to rest after it (PFC's default for static solutions, 0.7): outside the energy budget.
SETTLE_ALPHA = 0.7

# Viscous damping (-C m v on every node, 1/s) while a drapery settles on its slope: local
# damping there holds the mesh short of equilibrium (its nodes chatter in the slope contact and
# the damping, against sign(v), acts as a dry friction: doc/drapery.md, "Settling"). 10 1/s as
# the fence's rest (fence.REST_VISCOUS); measured on the quick drapery, 5 1/s settled slower.
SETTLE_VISCOUS = 10.0


def model(case):
    """'physical' when nothing damps absolute velocity during the load (damping.local 0),
    'local' otherwise (the paper's model and its variants)."""
    return "local" if case["damping.local"] > 0 else "physical"
