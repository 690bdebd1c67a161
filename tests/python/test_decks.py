"""The decks share their common parts through inputs/include/ instead of copies: no run of six or
more identical command lines (comments and blank lines aside) stands in two deck files."""

import numpy as np

import lmp

DECKS = sorted((lmp.ROOT / "inputs").rglob("*.in"))
MIN_RUN = 6


def commands(path):
    """(line number, text) of the command lines of a deck, white space folded."""
    out = []
    for k, line in enumerate(path.read_text().splitlines(), 1):
        text = " ".join(line.split("#", 1)[0].split())
        if text:
            out.append((k, text))
    return out


def shared_runs(a, b):
    """Runs of >= MIN_RUN consecutive command lines of a that also stand consecutively in b."""
    lines_a, lines_b = commands(a), commands(b)
    texts_b = [t for _, t in lines_b]
    windows = {tuple(texts_b[i:i + MIN_RUN]) for i in range(len(texts_b) - MIN_RUN + 1)}
    runs = []
    for i in range(len(lines_a) - MIN_RUN + 1):
        if tuple(t for _, t in lines_a[i:i + MIN_RUN]) in windows:
            runs.append(lines_a[i][0])
    return runs


def test_the_decks_are_found():
    names = {p.name for p in DECKS}
    assert {"punch.in", "impact.in", "cantilever.in", "net.in", "contacts.in"} <= names


def test_no_six_lines_repeated_between_decks():
    repeated = []
    for i, a in enumerate(DECKS):
        for b in DECKS[i + 1:]:
            runs = shared_runs(a, b)
            if runs:
                repeated.append(f"{a.relative_to(lmp.ROOT)}:{runs[0]} ~ {b.relative_to(lmp.ROOT)}")
    assert not repeated, "blocks repeated between decks (move them to inputs/include/): " + \
        "; ".join(repeated)


def test_the_check_finds_a_copied_block(tmp_path):
    """The check itself bites: a deck that copies seven lines of net.in is caught."""
    net = lmp.ROOT / "inputs" / "include" / "net.in"
    copy = tmp_path / "copy.in"
    copy.write_text("# a copy\nvariable x index 1\n" + "\n".join(
        t for _, t in commands(net)[:7]) + "\n")
    assert shared_runs(copy, net)


def _stretched_tensions(tmp_path, name, extra_vars):
    """Bond tensions of a wirenet-gen panel read through the decks' own includes (materials.in,
    net.in) after a uniform stretch of 0.05 % in x and y (every bond on its law's first branch)."""
    import subprocess
    work = tmp_path / name
    work.mkdir()
    subprocess.run([str(lmp.GEN), "hex", "--width", "0.6", "--height", "0.6", "--margin-x", "0.1",
                    "--out", str(work / "net")], check=True, stdout=subprocess.DEVNULL)
    sets = "".join(f"variable {k} index {v}\n" for k, v in extra_vars.items())
    deck = f"""{sets}variable inc string {lmp.ROOT / 'inputs' / 'include'}
variable data string {work / 'net.data'}
variable types string {work / 'net.types.in'}
include ${{inc}}/materials.in
include ${{inc}}/net.in
run 0
displace_atoms all ramp x -0.00015 0.00015 x -0.3 0.3 units box
displace_atoms all ramp y -0.00015 0.00015 y -0.3 0.3 units box
compute bl all wirenet/local
dump d all local 1 bonds.dump c_bl[1] c_bl[2] c_bl[3] c_bl[5] c_bl[6]
dump_modify d format "%.0f %.0f %.0f %.17g %.17g"
run 0
"""
    lmp.run_deck(deck, work)
    rows = [line.split() for line in (work / "bonds.dump").read_text().splitlines()
            if len(line.split()) == 5 and not line.startswith("ITEM")]
    return {(int(a), int(b)): (int(t), float(e), float(f)) for a, b, t, e, f in rows}


def _types(path):
    """{NAME: number} of a generator's PREFIX.types.in (variable NAME index N lines)."""
    out = {}
    for line in path.read_text().splitlines():
        words = line.split()
        if words[:1] == ["variable"] and words[2:3] == ["index"]:
            out[words[1]] = int(words[3])
    return out


def test_case_slack_keys_reach_every_wire_bond(tmp_path):
    """materials.slack_u/slack_f/slack_seed (case keys -> materials.in -> net.in) give every wire
    bond the slack of doc/bond_wirenet.md: with seed -1 (dl = lambda_u l0) and lambda_f = 1 the
    first loading branch is k* = F_1 / (dl + e_1 l0'), l0' = l0 + dl, so a bond stretched within
    it carries k*/k_u = e_1 / (lambda_u + (1 + lambda_u) e_1) of its slack-free tension (the
    double twist keeps the single wire's first point: `derived` scales the strains from the
    second on); the default slack_u 0 is exactly no slack."""
    from runner.materials import SW_CURVE
    plain = _stretched_tensions(tmp_path, "plain", {})
    slack = _stretched_tensions(tmp_path, "slack", {"slack_u": 0.2, "slack_seed": -1})
    types = _types(tmp_path / "plain" / "net.types.in")      # the wire bonds' types by name
    first = {types[f"bond_{n}"]: SW_CURVE[0][0] for n in ("DT", "SW", "selvedge")}
    ratios = {t: [] for t in first}
    for pair, (btype, strain, force) in plain.items():
        assert strain < first[btype]                  # the first, linear branch of both laws
        if force > 1.0:
            ratios[btype].append(slack[pair][2] / force)
    for btype, values in ratios.items():
        e1 = first[btype]
        assert len(values) > 10, f"bond type {btype}: {len(values)} stretched bonds"
        assert np.allclose(values, e1 / (0.2 + 1.2 * e1), rtol=1e-9), (btype, min(values), max(values))


def test_no_six_lines_repeated_between_runner_modules():
    """The same rule for the Python modules of the runner (runner/*.py and the kinds,
    runner/kinds/*.py): a set-up shared by two kinds of case lives in one function, not in two
    copies."""
    modules = sorted((lmp.ROOT / "runner").rglob("*.py"))
    assert len(modules) >= 8 and any(m.parent.name == "kinds" for m in modules)
    repeated = []
    for i, a in enumerate(modules):
        for b in modules[i + 1:]:
            ra, rb = a.relative_to(lmp.ROOT), b.relative_to(lmp.ROOT)
            repeated += [f"{ra}:{line} also in {rb}" for line in shared_runs(a, b)]
    assert not repeated, repeated


def _contact_tables(n):
    """{fix id: (property, [values])} of include/contact_tables_N.in (continuation lines
    joined)."""
    text = (lmp.ROOT / "inputs" / "include" / f"contact_tables_{n}.in").read_text()
    joined = text.replace("&\n", " ")
    tables = {}
    for line in joined.splitlines():
        words = line.split()
        if words[:1] == ["fix"]:
            assert words[3:6] == ["property/global", words[4], "peratomtypepair"] and \
                int(words[6]) == n, line[:80]
            tables[words[1]] = (words[4], words[7:])
    return tables


def test_contact_tables_agree():
    """The fence's 14-type contact tables hold the same properties, each with one value for all
    of its n^2 type pairs, as the panels' 8-type tables (LIGGGHTS wants exactly n^2 values; a
    table edited in one file only would give a fence other contacts than a panel)."""
    eight, fourteen = _contact_tables(8), _contact_tables(14)
    assert eight.keys() == fourteen.keys() and len(eight) == 5
    for fix, (prop, values) in eight.items():
        prop14, values14 = fourteen[fix]
        assert prop14 == prop
        assert len(values) == 8 * 8 and len(values14) == 14 * 14, fix
        assert len(set(values)) == 1 and set(values14) == set(values), fix
