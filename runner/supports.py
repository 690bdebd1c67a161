"""The edge supports of a panel, rendered into the deck include the decks read as ${supports}.

Each of the four edges (left x = -W/2, right x = +W/2, bottom y = -H/2, top y = +H/2) is
pinned (held in x, y, z), sliding (held across its edge line and along z: the paper's support)
or free. A corner node is held in every component that either of its two edges holds. The
eight groups of edge nodes (four edges without their corners, four corners) that hold the same
components share one `fix wirenet/hold` (each fix is a pass over every atom: the paper's four
sliding edges need three, four pinned edges one), so every held node is in exactly one fix and a
support reaction is the sum of the fixes' reactions. Each fix also keeps the mean of its
reaction over the deck's output window (`mean ${every}`), summed on each rank and reduced once
per output row: v_rx_mean etc. need no collective at every step (doc/fix_wirenet_hold.md).
The unfix file (render_unfix) makes
the supports re-includable. inputs/include/hold.in and unfix_supports.in are this renderer's
output for four sliding edges (tests/python/test_case_files.py keeps them equal).
"""

EDGES = ("left", "right", "bottom", "top")
KINDS = ("pinned", "sliding", "free")
# components held by a sliding edge: across the edge line and out of the plane
_SLIDING = {"left": "xz", "right": "xz", "bottom": "yz", "top": "yz"}
# the eight node groups of edges.in and the edges each lies on
_GROUPS = (("left", ("left",)), ("right", ("right",)), ("bottom", ("bottom",)), ("top", ("top",)),
           ("corner_lb", ("left", "bottom")), ("corner_rb", ("right", "bottom")),
           ("corner_lt", ("left", "top")), ("corner_rt", ("right", "top")))


def held(edge, kind):
    """Components ('x', 'y', 'z') an edge of this kind holds."""
    return {"pinned": "xyz", "sliding": _SLIDING[edge], "free": ""}[kind]


# unions that edges.in already defines (no group of our own needed)
_UNIONS = {frozenset(("left", "right")): "xedge", frozenset(("bottom", "top")): "yedge",
           frozenset(("corner_lb", "corner_rb", "corner_lt", "corner_rt")): "corner",
           frozenset(g for g, _ in _GROUPS): "edge"}


def fixes(supports):
    """[(fix ID, group, held values X Y Z, held components, member groups)]: one hold fix per
    distinct set of held components (a pass over the atoms per fix), none for free nodes."""
    by_values = {}
    for group, edges in _GROUPS:
        hold = set("".join(held(e, supports[e]) for e in edges))
        if hold:
            values = " ".join("0" if c in hold else "NULL" for c in "xyz")
            by_values.setdefault(values, (hold, []))[1].append(group)
    out = []
    for k, (values, (hold, members)) in enumerate(by_values.items(), 1):
        fix = f"hold_{k}"
        group = members[0] if len(members) == 1 else _UNIONS.get(frozenset(members), fix)
        out.append((fix, group, values, hold, members))
    return out


def render(supports):
    """Deck text of the supports {edge: kind} (every edge named)."""
    lines = ["# WireNet deck include, rendered by runner/supports.py: the edge supports "
             + ", ".join(f"{e} {supports[e]}" for e in EDGES) + ".",
             "# One wirenet/hold fix per distinct set of held components (free nodes: none); a fix's",
             "# vector is its support reaction, at this step (1-3) and as its mean over the deck's",
             "# output window of every steps (4-6). Needs the groups of edges.in and the variable every;",
             "# re-include after its unfix file (render_unfix)."]
    terms = {c: [] for c in "xyz"}
    for fix, group, values, hold, members in fixes(supports):
        if group == fix:
            lines.append(f"group           {fix} union {' '.join(members)}")
        lines.append(f"fix             {fix} {group} wirenet/hold {values} mean ${{every}}")
        for k, c in enumerate("xyz", 1):
            if c in hold:
                terms[c].append((f"f_{fix}[{k}]", f"f_{fix}[{k + 3}]"))
    for c in "xyz":
        now = "+".join(t for t, _ in terms[c]) or "0"
        mean = "+".join(m for _, m in terms[c]) or "0"
        lines.append(f"variable        r{c} equal {now}")
        lines.append(f"variable        r{c}_mean equal {mean}")
    return "\n".join(lines) + "\n"


def render_unfix(supports):
    """Deck text that removes the fixes of render(supports), so that it can be included again
    after fixes that must act first (inputs/include/damping_then_supports.in)."""
    lines = ["# WireNet deck include, rendered by runner/supports.py: remove the support fixes of "
             + ", ".join(f"{e} {supports[e]}" for e in EDGES) + "."]
    lines += [f"unfix           {fix}" for fix, *_ in fixes(supports)]
    return "\n".join(lines) + "\n"


PAPER = {e: "sliding" for e in EDGES}
