"""The edge supports of a panel, rendered into the deck include the decks read as ${supports}.

Each of the four edges (left x = -W/2, right x = +W/2, bottom y = -H/2, top y = +H/2) is
pinned (held in x, y, z), sliding (held across its edge line and along z: the paper's support)
or free. A corner node is held in every component that either of its two edges holds. Every
node is in exactly one of eight setforce fixes (four edges without their corners, four corners),
so a support reaction is the sum of the components those fixes remove where they hold, and the
file stays re-includable after inputs/include/unfix_supports.in. inputs/include/hold.in is this
renderer's output for four sliding edges (tests/python/test_case_files.py keeps them equal).
"""

EDGES = ("left", "right", "bottom", "top")
KINDS = ("pinned", "sliding", "free")
# components held by a sliding edge: across the edge line and out of the plane
_SLIDING = {"left": "xz", "right": "xz", "bottom": "yz", "top": "yz"}
_FIXES = (("hold_l", "left", ("left",)), ("hold_r", "right", ("right",)),
          ("hold_b", "bottom", ("bottom",)), ("hold_t", "top", ("top",)),
          ("hold_lb", "corner_lb", ("left", "bottom")), ("hold_rb", "corner_rb", ("right", "bottom")),
          ("hold_lt", "corner_lt", ("left", "top")), ("hold_rt", "corner_rt", ("right", "top")))


def held(edge, kind):
    """Components ('x', 'y', 'z') an edge of this kind holds."""
    return {"pinned": "xyz", "sliding": _SLIDING[edge], "free": ""}[kind]


def render(supports):
    """Deck text of the supports {edge: kind} (every edge named)."""
    lines = ["# WireNet deck include, rendered by runner/supports.py: the edge supports "
             + ", ".join(f"{e} {supports[e]}" for e in EDGES) + ".",
             "# Every edge node is in one setforce fix (edges without corners, then corners); a fix's",
             "# vector is the force it removed, so minus its held components is the support reaction.",
             "# Needs the groups of edges.in; re-include after unfix_supports.in."]
    terms = {c: [] for c in "xyz"}
    for fix, group, edges in _FIXES:
        hold = set("".join(held(e, supports[e]) for e in edges))
        values = " ".join("0" if c in hold else "NULL" for c in "xyz")
        lines.append(f"fix             {fix} {group} setforce {values}")
        for k, c in enumerate("xyz", 1):
            if c in hold:
                terms[c].append(f"f_{fix}[{k}]")
    for c in "xyz":
        expr = f"-({'+'.join(terms[c])})" if terms[c] else "0"
        lines.append(f"variable        r{c} equal {expr}")
    return "\n".join(lines) + "\n"


PAPER = {e: "sliding" for e in EDGES}
