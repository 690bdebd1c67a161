"""The edge supports of a panel, rendered into the deck include the decks read as ${supports}.

Each of the four edges (left x = -W/2, right x = +W/2, bottom y = -H/2, top y = +H/2) is
pinned (held in x, y, z), sliding (held across its edge line and along z: the paper's support)
or free. A corner node is held in every component that either of its two edges holds. Each held
edge (without its corners) has a `fix wirenet/hold` of its own, so that the load on each edge is
an output (a design load: the vector sum of all supports cancels the pulls of opposite edges);
the corners that hold the same components share one (`corners`, one per distinct set). Every
held node is in exactly one fix (a fix keeps a list of its own atoms: no pass over all atoms per
step), a support reaction is the sum of the fixes' reactions. Each fix also keeps the mean of
its reaction over the deck's output window (`mean ${every}`), summed on each rank and reduced
once per output row: v_rx_mean etc. and the edges' v_rx_left_mean etc. need no collective at
every step (doc/fix_wirenet_hold.md). The unfix file (render_unfix) makes the supports
re-includable. inputs/include/hold.in and unfix_supports.in are this renderer's output for four
sliding edges (tests/python/test_case_files.py keeps them equal).
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


# the parts whose reactions the deck reports apart: the four edges and their corners together
PARTS = EDGES + ("corners",)
# unions that edges.in already defines (no group of our own needed)
_UNIONS = {frozenset(("corner_lb", "corner_rb", "corner_lt", "corner_rt")): "corner"}


def fixes(supports):
    """[(fix ID, group, held values X Y Z, held components, member groups, part)]: a hold fix per
    held edge, one per distinct set of held components of the corners, none for free nodes."""
    sides, corners = [], {}
    for group, edges in _GROUPS:
        hold = set("".join(held(e, supports[e]) for e in edges))
        if not hold:
            continue
        values = " ".join("0" if c in hold else "NULL" for c in "xyz")
        if len(edges) == 1:
            sides.append((f"hold_{group}", group, values, hold, [group], group))
        else:
            corners.setdefault(values, (hold, []))[1].append(group)
    out = list(sides)
    for k, (values, (hold, members)) in enumerate(corners.items(), 1):
        fix = "hold_corners" if len(corners) == 1 else f"hold_corners_{k}"
        group = members[0] if len(members) == 1 else _UNIONS.get(frozenset(members), fix)
        out.append((fix, group, values, hold, members, "corners"))
    return out


def render(supports):
    """Deck text of the supports {edge: kind} (every edge named): the fixes, the total reaction
    v_rx v_ry v_rz (now) and v_rx_mean .. (window means), and each part's window mean
    v_rx_PART_mean .. (PART: left, right, bottom, top, corners; 0 where nothing is held)."""
    lines = ["# WireNet deck include, rendered by runner/supports.py: the edge supports "
             + ", ".join(f"{e} {supports[e]}" for e in EDGES) + ".",
             "# A wirenet/hold fix per held edge and per set of held components of the corners (free",
             "# nodes: none); a fix's vector is its support reaction, at this step (1-3) and as its mean",
             "# over the deck's output window of every steps (4-6). Needs the groups of edges.in and the",
             "# variable every; re-include after its unfix file (render_unfix)."]
    terms = {c: [] for c in "xyz"}
    parts = {(p, c): [] for p in PARTS for c in "xyz"}
    for fix, group, values, hold, members, part in fixes(supports):
        if group == fix:
            lines.append(f"group           {fix} union {' '.join(members)}")
        lines.append(f"fix             {fix} {group} wirenet/hold {values} mean ${{every}}")
        for k, c in enumerate("xyz", 1):
            if c in hold:
                terms[c].append((f"f_{fix}[{k}]", f"f_{fix}[{k + 3}]"))
                parts[part, c].append(f"f_{fix}[{k + 3}]")
    for c in "xyz":
        now = "+".join(t for t, _ in terms[c]) or "0"
        mean = "+".join(m for _, m in terms[c]) or "0"
        lines.append(f"variable        r{c} equal {now}")
        lines.append(f"variable        r{c}_mean equal {mean}")
    for p in PARTS:
        for c in "xyz":
            lines.append(f"variable        r{c}_{p}_mean equal {'+'.join(parts[p, c]) or '0'}")
    return "\n".join(lines) + "\n"


def render_unfix(supports):
    """Deck text that removes the fixes of render(supports), so that it can be included again
    after fixes that must act first (inputs/include/damping_then_supports.in)."""
    lines = ["# WireNet deck include, rendered by runner/supports.py: remove the support fixes of "
             + ", ".join(f"{e} {supports[e]}" for e in EDGES) + "."]
    lines += [f"unfix           {fix}" for fix, *_ in fixes(supports)]
    return "\n".join(lines) + "\n"


PAPER = {e: "sliding" for e in EDGES}
