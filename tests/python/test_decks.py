"""The decks share their common parts through inputs/include/ instead of copies: no run of six or
more identical command lines (comments and blank lines aside) stands in two deck files."""

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
