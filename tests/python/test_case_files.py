"""Case files (doc/case_files.md): the checker's one-line errors, --set, the templates of
`./wirenet new` (they parse and run), the shipped case files, the supports renderer (the
paper's rendering is inputs/include/hold.in; the reactions of pinned edges close the momentum
balance of an oblique impact: test_examples.py), and doc/case_files.md in step with the schema."""

import math
import os
import subprocess

import numpy as np
import pytest

import lmp
from runner import casefile, kinds, materials, schema, supports, templates

DRIVER = lmp.ROOT / "wirenet"
# the kinds as the registry lists them (runner/kinds/__init__.py): the paper's four among them
KIND_NAMES = ", ".join(kinds.NAMES)
assert {"punch", "impact", "cantilever", "fence"} <= set(kinds.NAMES)


def check(text, quick=False):
    return casefile.parse(text, path="case.toml", quick=quick)


def error_of(text):
    with pytest.raises(casefile.CaseFileError) as info:
        check(text)
    return str(info.value)


# --- errors: one line naming the key ---------------------------------------------------------

@pytest.mark.parametrize("text, expected", [
    ('kind = "punch"\n[panle]\nnet = "hex"\n', "panle: unknown key (did you mean 'panel'?)"),
    ('kind = "punch"\n[panel]\nnett = "hex"\n', "panel.nett: unknown key (did you mean 'panel.net'?)"),
    ('kind = "punch"\n[supports]\nfront = "pinned"\n', "supports.front: unknown key"),
    ('kind = "punch"\n[supports]\nleft = "glued"\n', "supports.left: must be one of pinned, sliding, free"),
    ('kind = "punch"\n[panel]\nwidth = "3"\n', "panel.width: must be a number [m], got text '3'"),
    ('kind = "punch"\n[panel]\nwidth = -3.0\n', "panel.width: must be >= 0.1, got -3 [m]"),
    ('kind = "punch"\n[panel]\nwidth = nan\n', "panel.width: must be a finite number, got nan"),
    ('kind = "punch"\n[panel]\nwidth = inf\n', "panel.width: must be a finite number, got inf"),
    ('kind = "punch"\n[damping]\nlocal = 1.5\n', "damping.local: must be <= 0.999, got 1.5"),
    ('kind = "punch"\n[punch]\nposition = [0.0]\n', "punch.position: must be a list of 2 numbers"),
    ('kind = "punch"\n[punch]\nquasi_static_check = 1\n', "punch.quasi_static_check: must be true or false"),
    ('kind = "punch"\n[punch]\nplatter = "spheriod"\n', "did you mean 'spheroid'?"),
    ('kind = "punch"\n[impact]\nmass = 10.0\n', "impact.mass: only for kind 'impact' (this case is 'punch')"),
    ('kind = "impact"\n[punch]\nspeed = 1.0\n', "punch.speed: only for kind 'punch'"),
    ('kind = "impact"\n[impact]\nmas = 10.0\n', "impact.mas: unknown key (did you mean 'mass'?)"),
    ('kind = "impact"\n[impact]\nvelocity = [0.0, 0.0, 0.0]\n', "impact.velocity: must not be zero"),
    ('kind = "impact"\n[impact]\nblock = "stl"\nstl = "nowhere.stl"\nbody = "mesh"\n',
     "impact.stl: no such file"),
    ('kind = "impact"\n[impact]\nblock = "stl"\n', "impact.stl: block 'stl' needs the STL file"),
    ('kind = "impact"\n[preload]\nmode = "sag"\n', "preload.mode: 'sag' is a punch pre-load"),
    ('kind = "punch"\ngravity = 0.0\n', "preload.mode: 'sag' needs gravity > 0"),
    ('kind = "wall"\n', f"kind: must be one of {KIND_NAMES}, got 'wall'"),
    ('kind = "fence"\n[panel]\nwidth = 3.0\n', "panel.width: not used by a fence case"),
    ('kind = "fence"\n[supports]\nleft = "pinned"\n', "supports.left: not used by a fence case"),
    ('kind = "fence"\n[preload]\nmode = "none"\n', "preload.mode: not used by a fence case"),
    ('kind = "fence"\n[[output.zones]]\nname = "a"\n', "output.zones: not used by a fence case"),
    ('kind = "fence"\n[fence]\nmodules = 0\n', "fence.modules: must be >= 1, got 0"),
    ('kind = "fence"\n[output]\ndump_rows = 3\n', "output.dump_rows: not used by a fence case"),
    ('kind = "fence"\n[fence]\nhead_guides = "glued"\n', "fence.head_guides: must be one of clamp, slide"),
    ('kind = "fence"\n[fence]\nspeed = nan\n', "fence.speed: must be a finite number"),
    ('kind = "fence"\n[fence]\npost_tilt = 75.0\n', "fence.post_tilt: must be <= 40"),
    ('kind = "fence"\n[fence]\nimpacts = 3\n', "fence.impacts: must be <= 2"),
    ('kind = "impact"\n[panel]\ncell = 0.0\n', "panel.cell: must be >= 0.02, got 0 [m]"),
    ('kind = "impact"\n[panel]\nrope_elements = 2.5\n', "panel.rope_elements: must be an integer"),
    ('kind = "fence"\n[fence]\nbrakes = -1\n', "fence.brakes: must be >= 0, got -1"),
    ('kind = "fence"\n[fence]\npost_iy = nan\n', "fence.post_iy:"),
    ('kind = "impact"\n[output]\nforce_window = 0.0\n', "output.force_window: must be > 0"),
    ('kind = "fence"\n[fence]\nrest_time = -1.0\n', "fence.rest_time: must be >= 0"),
    ('kind = "fence"\n[impact]\nmass = 10.0\n', "impact.mass: only for kind 'impact'"),
    ('kind = "punch"\n[fence]\nspeed = 10.0\n', "fence.speed: only for kind 'fence'"),
    ('title = "x"\n', "kind: missing"),
    ('kind = "punch"\n[materials]\ncurve = [[0.01, 1e8], [0.005, 2e8]]\n', "materials.curve: strains must be > 0 and increasing"),
    ('kind = "punch"\n[materials]\nbending = "paper"\n', "materials.bending: must be a number >= 0 or 'calibrated'"),
    ('kind = "impact"\n[[impact]]\nmass = 1.0\n[[impact]]\nmass = -1.0\n', "impact[2].mass: must be >= 0.001, got -1 [kg]"),
    ('kind = "punch"\n[[output.zones]]\nname = "a"\n[[output.zones]]\nname = "a"\n', "output.zones: zone names must differ"),
    ('kind = "punch"\n[punch]\ntip_radius = 0.01\n', "punch.tip_radius: only for punch.platter = 'cone'"),
    ('kind = "punch"\n[punch]\nbody = "mesh"\nspeed_max = 2\n', "punch.speed_max: > 1 needs punch.body = 'analytic'"),
    ('kind = "punch"\n[punch]\nspeed_max = 0.5\n', "punch.speed_max: must be >= 1, got 0.5"),
    ('kind = "punch"\n[punch]\nequilibrium_target = 0\n', "punch.equilibrium_target: must be > 0, got 0"),
    ('kind = "punch"\npanel = 3\n', "panel: is a section of keys ([panel] in the file, panel.KEY with --set), not a value"),
    ('kind = "punch"\n[panel\n', "not valid TOML"),
    ('kind = "punch"\n[materials]\nslack_seed = 1.5\n', "materials.slack_seed: must be an integer, got"),
    ('kind = "punch"\n[materials]\nslack_seed = -2\n', "materials.slack_seed: must be >= -1, got -2"),
    ('kind = "punch"\n[materials]\nslack_f = 0.0\n', "materials.slack_f: must be > 0, got 0"),
    ('kind = "punch"\n[materials]\nslack_u = nan\n', "materials.slack_u: must be a finite number"),
    ('kind = "punch"\n[panel]\nselvedge = "yes"\n', "panel.selvedge: must be one of loop, none, sides"),
    ('kind = "punch"\n[output]\ndump_rows = 0\n', "output.dump_rows: must be >= 1, got 0"),
    ('kind = "punch"\n[output]\nrow_time = 1e-3\n', "output.row_time: only for kinds 'drapery', 'impact'"),
    ('kind = "impact"\n[output]\nrow_travel = 1e-3\n', "output.row_travel: only for kind"),
    ('kind = "punch"\n[output]\nframes = true\n', "output.frames: must be an integer, got"),
    ('kind = "fence"\n[fence]\nsettle_kinetic = false\n', "fence.settle_local: 0 with fence.settle_kinetic false"),
    ('kind = "fence"\n[fence]\nsettle_local = 1.0\n', "fence.settle_local: must be <= 0.99, got 1"),
    ('kind = "fence"\n[fence]\nsettle_dt_fraction = 1.5\n', "fence.settle_dt_fraction: must be <= 1, got 1.5"),
    ('kind = "fence"\n[fence]\nsettle_dt_fraction = nan\n', "fence.settle_dt_fraction: must be a finite number"),
    ('kind = "fence"\n[fence]\nduration = 0.001\n', "fence.duration: 0.001 s: shorter than two rows"),
])
def test_bad_case_file_is_one_line_naming_the_key(text, expected):
    message = error_of(text)
    assert expected in message, message
    assert "\n" not in message and message.startswith("/") and "case.toml: " in message


@pytest.mark.parametrize("text, path, kind", [
    ('kind = "impact"\n[output]\nrow_travel = 1e-3\n', "output.row_travel", "impact"),
    ('kind = "punch"\n[output]\nrow_time = 1e-3\n', "output.row_time", "punch"),
    ('kind = "fence"\n[impact]\nmass = 10.0\n', "impact.mass", "fence"),
])
def test_a_key_of_other_kinds_names_every_kind_that_takes_it(text, path, kind):
    takers = schema.takers(schema.BY_PATH[path])
    assert takers and kind not in takers
    expected = f"{path}: only for kind{'s' if len(takers) > 1 else ''} " + \
        ", ".join(f"'{n}'" for n in sorted(takers)) + f" (this case is '{kind}')"
    assert error_of(text).endswith(expected)


def test_defaults_are_the_papers():
    punch = check('kind = "punch"\n')
    assert punch["panel.width"] == 3.0 and punch["supports.left"] == "sliding"
    assert punch["damping.local"] == 0.7 and punch["preload.mode"] == "sag"
    assert punch["materials.wire_d"] == 0.0027 and punch["contact.kn"] == 1e9
    # an impact's default dissipation is the physical model (runner/dissipation.py: no local
    # damping during the impact, the bonds' structural damping); the paper's local damping 0.5
    # is the case impact_*_paper
    from runner import dissipation
    impact = check('kind = "impact"\n')
    assert impact["damping.local"] == 0.0 and impact["preload.mode"] == "settle"
    assert impact["damping.bond"] == dissipation.STRUCTURAL_ZETA == 0.05
    paper = casefile.read(lmp.ROOT / "inputs" / "cases" / "impact_hex_paper.toml")
    assert paper["damping.local"] == 0.5 and paper["damping.bond"] == 0.0
    assert impact.impacts == [dict(block="truncated-cube", stl="", side=0.45, mass=44.5,
                                   velocity=[0.0, 0.0, -10.0], point=[0.0, 0.0],
                                   orientation=[1.0, 0.0, 0.0, 0.0], duration=1.0,
                                   dt_fraction=0.5, body="analytic")]
    assert impact.zones == [dict(name="centre", centre=[0.0, 0.0], radius=1.0)]
    quick = check('kind = "impact"\n', quick=True)
    assert quick["panel.width"] == 1.2 and quick.impacts[0]["duration"] == 0.06
    # a stated size is kept under --quick
    assert check('kind = "punch"\n[panel]\nwidth = 4.0\n', quick=True)["panel.width"] == 4.0


def test_materials_defaults_come_from_materials_in():
    """One source: the schema's material defaults are the values of inputs/include/materials.in,
    and a case at its defaults gives the deck exactly materials.in's numbers (the deck gets every
    key's variable: kinds.of(case).key_variables()); a changed key changes that value only."""
    text = (lmp.ROOT / "inputs" / "include" / "materials.in").read_text()
    assert "variable rope_E        index 6e10" in text
    assert schema.BY_PATH["materials.rope_E"].default == 6e10
    default = kinds.of(check('kind = "punch"\n'))
    values, deck = default.material_values(), default.key_variables()
    shared = [n for n in values if n in materials.MATERIALS and n not in ("bending", "rope_strength")]
    assert {"wire_d", "rope_E", "kn", "ks", "mu", "slack_seed", "curve", "shear"} <= set(shared)
    for name in shared:
        if name == "curve":
            assert [tuple(p) for p in values[name]] == list(materials.SW_CURVE)
            assert [float(v) for v in deck[name].split()] == [v for p in materials.SW_CURVE for v in p]
        elif isinstance(materials.MATERIALS[name], str):
            assert values[name] == deck[name] == materials.MATERIALS[name], name
        else:
            assert values[name] == materials.MATERIALS[name], name
            assert float(deck[name]) == materials.MATERIALS[name], name
    changed = kinds.of(check('kind = "punch"\n[materials]\nrope_E = 1e11\n'
                             '[contact]\nmu = 0.3\n')).material_values()
    assert {n: v for n, v in changed.items() if v != values[n]} == {"rope_E": 1e11, "mu": 0.3}


def test_set_overrides(tmp_path):
    path = tmp_path / "c.toml"
    path.write_text('kind = "impact"\n[[impact]]\nmass = 10.0\n[[impact]]\nmass = 20.0\n')
    case = casefile.read(path, ["panel.width=2.5", "supports.left=pinned", "impact.2.mass=30",
                                "output.zones.radius=0.5"])
    assert case["panel.width"] == 2.5 and case["supports.left"] == "pinned"
    assert [i["mass"] for i in case.impacts] == [10.0, 30.0]
    assert case.zones[0]["radius"] == 0.5
    case = casefile.read(path, ["impact.mass=40"])
    assert [i["mass"] for i in case.impacts] == [40.0, 40.0]
    with pytest.raises(casefile.CaseFileError, match="impact.3.mass: the case file has 2"):
        casefile.read(path, ["impact.3.mass=1"])
    with pytest.raises(casefile.CaseFileError, match=r"panel.width: must be >= 0.1, got -1 \[m\]"):
        casefile.read(path, ["panel.width=-1"])
    with pytest.raises(casefile.CaseFileError, match="expected KEY=VALUE"):
        casefile.read(path, ["panel.width"])


@pytest.mark.parametrize("kind", ["punch", "impact", "fence"])
def test_templates_parse_to_the_defaults(kind):
    template = templates.template(kind)
    assert check(template).values == check(f'kind = "{kind}"\n').values
    for key in schema.KEYS:
        if schema.applies(key, kind) and key.path != "kind" and \
                schema.default_of(key, kind) is not None:
            assert f"{key.name} = " in template, key.path
        elif not schema.applies(key, kind):
            assert f"\n{key.name} = " not in template or key.name in (
                k.name for k in schema.KEYS if schema.applies(k, kind)), key.path


def test_fence_defaults_and_contact(tmp_path, monkeypatch):
    """A fence case: the generator's default fence (compound net, 3 x 10 m x 5 m), the 500 kJ
    block of EAD 340059 (1600 kg at 25 m/s), the fence's soft contact penalty passed to the
    deck (materials.in's 1e9 N/m is the paper's panel contact); --quick shrinks all of it."""
    from runner.kinds import fence
    case = check('kind = "fence"\n')
    assert case["panel.net"] == "compound" and case["fence.modules"] == 3
    assert 0.5 * case["fence.block_mass"] * case["fence.speed"] ** 2 == pytest.approx(500e3)
    kind = kinds.of(case)
    assert kind.material_values()["kn"] == 1e7 and kind.material_values()["ks"] == 1e6
    assert float(kind.key_variables()["kn"]) == 1e7 and float(kind.key_variables()["ks"]) == 1e6
    impact = kinds.of(check('kind = "impact"\n'))
    assert impact.material_values()["kn"] == materials.MATERIALS["kn"] == 1e9
    quick = casefile.parse('kind = "fence"\n', quick=True)
    assert quick["fence.spacing"] == 4.0 and quick["fence.speed"] == 5.0
    # generator options: a fence takes the compound generator's prefixed names for any net
    # (what the fence's Setup hands wirenet-gen, stopped there)
    case = check('kind = "fence"\n[panel]\nnet = "hex"\nhex_node_mass = 0.005\n')
    calls = []

    class Generated(Exception):
        pass

    def generate(what, prefix, *options):
        calls.append((what, options))
        raise Generated

    monkeypatch.setattr(fence, "generate", generate)
    with pytest.raises(Generated):
        fence.Setup(kinds.of(case), str(tmp_path), 0.05)
    what, options = calls[0]
    assert what == "fence" and list(options[-2:]) == ["--hex-node-mass", 0.005]
    assert options[options.index("--net") + 1] == "hex"
    # the fence's make-up (issue #42): only what differs from the defaults goes to the generator
    calls.clear()
    case = check('kind = "fence"\n[panel]\ncell = 0.25\n[fence]\nsupport_rope_d = 0.024\n'
                 'brakes = 2\npost_iy = 5e-5\n')
    with pytest.raises(Generated):
        fence.Setup(kinds.of(case), str(tmp_path), 0.05)
    options = list(calls[0][1])
    tail = options[options.index("--head-guides") + 2:]
    assert tail == ["--cell", 0.25, "--support-rope-diameter", 0.024, "--brakes", 2,
                    "--post-iy", 5e-5]


def test_shipped_case_files_check():
    names = sorted(p.stem for p in (lmp.ROOT / "inputs" / "cases").glob("*.toml"))
    assert {"beam", "punch_hex", "punch_compound", "impact_hex", "impact_square",
            "impact_compound", "calibration_0.05"} <= set(names)
    for name in names:
        case = casefile.read(lmp.ROOT / "inputs" / "cases" / f"{name}.toml")
        assert case.name == name
    for path in (lmp.ROOT / "docs" / "examples").glob("*.toml"):
        casefile.read(path)


def test_calibration_fraction_flows_into_the_cases(tmp_path):
    case = check('kind = "punch"\n')
    assert materials.bending_of(case, tmp_path)[0] == 0.05            # the paper's
    (tmp_path / "calibration.json").write_text('{"best_fraction": 0.031}')
    value, source = materials.bending_of(case, tmp_path)
    assert value == 0.031 and "calibrated" in source
    assert materials.bending_of(check('kind = "punch"\n[materials]\nbending = 0.2\n'), tmp_path)[0] == 0.2


# --- supports ---------------------------------------------------------------------------------

def test_paper_supports_are_hold_in():
    include = lmp.ROOT / "inputs" / "include"
    assert supports.render(supports.PAPER) == (include / "hold.in").read_text()
    assert supports.render_unfix(supports.PAPER) == (include / "unfix_supports.in").read_text()


def test_supports_have_a_fix_per_edge_hold_the_union_at_corners_and_sum_held_components_only():
    text = supports.render(dict(left="pinned", right="free", bottom="sliding", top="free"))
    # a fix per held edge (its load is an output); the corners by what they hold: the pinned
    # left edge's two (pinned + free, pinned + sliding) in one, the sliding bottom's free-side
    # corner in another; the free right and top edges and their common corner in none
    assert "fix             hold_left left wirenet/hold 0 0 0 mean ${every}\n" in text
    assert "fix             hold_bottom bottom wirenet/hold NULL 0 0 mean ${every}\n" in text
    assert "group           hold_corners_1 union corner_lb corner_lt\n" in text
    assert "fix             hold_corners_1 hold_corners_1 wirenet/hold 0 0 0 mean ${every}\n" in text
    assert "fix             hold_corners_2 corner_rb wirenet/hold NULL 0 0 mean ${every}\n" in text
    assert text.count("\nfix ") == 4
    assert "variable        rx equal f_hold_left[1]+f_hold_corners_1[1]\n" in text
    assert "variable        ry_mean equal f_hold_left[5]+f_hold_bottom[5]+f_hold_corners_1[5]+" \
           "f_hold_corners_2[5]\n" in text
    # each part's window mean, 0 for what a part does not hold
    assert "variable        ry_left_mean equal f_hold_left[5]\n" in text
    assert "variable        rx_bottom_mean equal 0\n" in text
    assert "variable        rz_right_mean equal 0\n" in text
    assert "variable        rz_corners_mean equal f_hold_corners_1[6]+f_hold_corners_2[6]\n" in text
    # the corner group edges.in already has is used as it is
    pinned = supports.render({e: "pinned" for e in supports.EDGES})
    assert "fix             hold_corners corner wirenet/hold 0 0 0 mean ${every}\n" in pinned \
        and "group  " not in pinned and pinned.count("\nfix ") == 5
    free = supports.render({e: "free" for e in supports.EDGES})
    assert "\nfix " not in free and "variable        rz equal 0\n" in free \
        and "variable        rz_mean equal 0\n" in free and "variable        rz_top_mean equal 0\n" in free
    assert supports.render_unfix(dict(left="pinned", right="free", bottom="sliding", top="free")) \
        .splitlines()[1:] == ["unfix           hold_left", "unfix           hold_bottom",
                              "unfix           hold_corners_1", "unfix           hold_corners_2"]


def _held(node_edges, chosen):
    return set("".join(supports.held(e, chosen[e]) for e in node_edges))


@pytest.mark.parametrize("chosen", [
    dict(left="pinned", right="sliding", bottom="free", top="sliding"),
    dict(left="pinned", right="free", bottom="sliding", top="free"),
    {e: "pinned" for e in supports.EDGES},
    supports.PAPER,
])
def test_supports_in_liggghts_block_what_they_say(tmp_path, chosen):
    """A 3 x 3 grid of nodes typed as a panel's edges (the hex mesh's atom types, numbered as
    the generator's PREFIX.types.in numbers them) under a uniform force: the rendered supports,
    included, removed by their unfix file and included again, hold exactly the components they
    name, and the reactions v_rx v_ry v_rz balance the applied force on the held nodes (counted
    here from the edges each node lies on)."""
    subprocess.run([str(lmp.GEN), "hex", "--width", "0.3", "--height", "0.3", "--out",
                    str(tmp_path / "gen")], check=True, capture_output=True)
    types = tmp_path / "gen.types.in"
    number = {line.split()[1]: int(line.split()[3]) for line in types.read_text().splitlines()
              if line.startswith("variable")}
    atoms, k, expected = [], 0, {"x": 0.0, "y": 0.0, "z": 0.0}
    push = {"x": 1.0, "y": 2.0, "z": 3.0}
    for j, y in enumerate((-1.0, 0.0, 1.0)):
        for i, x in enumerate((-1.0, 0.0, 1.0)):
            k += 1
            corner, xe, ye = (i != 1 and j != 1), (i != 1 and j == 1), (j != 1 and i == 1)
            t = number["atom_hex_corner" if corner else "atom_hex_edge_x" if xe else
                       "atom_hex_edge_y" if ye else "atom_hex_interior"]
            atoms.append((k, t, x, y, 0.0))
            edges = ([("left", "right")[i // 2]] if i != 1 else []) + \
                    ([("bottom", "top")[j // 2]] if j != 1 else [])
            for c in _held(edges, chosen):
                expected[c] -= push[c]
    (tmp_path / "supports.in").write_text(supports.render(chosen))
    (tmp_path / "unfix.in").write_text(supports.render_unfix(chosen))
    data = tmp_path / "grid.data"
    lines = ["grid", "", "9 atoms",
             f"{max(v for n, v in number.items() if n.startswith('atom_'))} atom types", "", "-2 2 xlo xhi", "-2 2 ylo yhi",
             "-2 2 zlo zhi", "", "Atoms", ""]
    lines += [f"{i} {t} 0.1 1000 {x} {y} {z}" for i, t, x, y, z in atoms]
    data.write_text("\n".join(lines) + "\n")
    deck = f"""units si
atom_style sphere
atom_modify map array sort 0 0
boundary f f f
read_data {data}
variable inc string {lmp.ROOT / 'inputs' / 'include'}
include {types}
include ${{inc}}/edges.in
variable every index 5
fix push all addforce {push['x']} {push['y']} {push['z']}
include {tmp_path / 'supports.in'}
include {tmp_path / 'unfix.in'}
include {tmp_path / 'supports.in'}
fix integ all nve/sphere
timestep 1e-3
thermo_style custom step v_rx v_ry v_rz v_rx_mean v_ry_mean v_rz_mean
thermo_modify format float %.10g
run 10
"""
    out = lmp.run_deck(deck, tmp_path)
    row = lmp.thermo_rows(out)[-1]
    assert (row["rx"], row["ry"], row["rz"]) == pytest.approx(
        (expected["x"], expected["y"], expected["z"]))
    # a constant load: the window means (of the last 5 steps) are the reactions
    assert (row["rx_mean"], row["ry_mean"], row["rz_mean"]) == (row["rx"], row["ry"], row["rz"])
    if chosen == dict(left="pinned", right="sliding", bottom="free", top="sliding"):
        # by hand: x: left 3 (pinned) + right edge node and 2 corners (sliding) = 6; y: left 3 +
        # top edge node + right-top corner = 5 (x 2 N); z: all but the bottom edge node and the
        # centre = 7 (x 3 N)
        assert (row["rx"], row["ry"], row["rz"]) == pytest.approx((-6.0, -10.0, -21.0))


# --- doc ----------------------------------------------------------------------------------------

def test_doc_key_tables_are_the_schemas():
    doc = (lmp.ROOT / "doc" / "case_files.md").read_text()
    assert templates.key_tables() in doc, "doc/case_files.md: regenerate the tables with `PYTHONPATH=. /usr/bin/python3 -P -m runner keys`"


# --- the command line -----------------------------------------------------------------------------

def test_bad_case_file_through_the_driver(tmp_path):
    bad = tmp_path / "bad.toml"
    bad.write_text('kind = "punch"\n[suports]\nleft = "pinned"\n')
    p = subprocess.run([str(DRIVER), "run", str(bad), "--out", str(tmp_path / "out")],
                       capture_output=True, text=True, timeout=60,
                       env=dict(os.environ, WIRENET_SETUP="skip",
                                WIRENET_BUILD=str(lmp.BUILD)))
    assert p.returncode == 2
    assert p.stderr.strip().count("\n") == 0, p.stderr
    assert "suports: unknown key (did you mean 'supports'?)" in p.stderr
    assert not (tmp_path / "out").exists()


def test_new_prints_a_template():
    p = subprocess.run([str(DRIVER), "new", "punch"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0 and p.stdout == templates.template("punch")
    p = subprocess.run([str(DRIVER), "new", "fence"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 0 and p.stdout == templates.template("fence")
    p = subprocess.run([str(DRIVER), "new", "wall"], capture_output=True, text=True, timeout=60)
    assert p.returncode == 2 and "invalid choice" in p.stderr


def test_quaternion_is_normalised():
    case = check('kind = "impact"\n[impact]\norientation = [2.0, 0.0, 0.0, 0.0]\n')
    assert case.impacts[0]["orientation"] == [1.0, 0.0, 0.0, 0.0]
    assert math.isclose(sum(v * v for v in check(
        'kind = "impact"\n[impact]\norientation = [1.0, 1.0, 0.0, 0.0]\n').impacts[0]["orientation"]), 1.0)


# --- studies: every mistake named before a case runs ---------------------------------------------

def test_study_file_errors(tmp_path):
    from runner import study
    bad = tmp_path / "s.toml"
    bad.write_text('cases = "punch_hex"\n')
    with pytest.raises(study.StudyError, match="s.toml: cases: must be a list"):
        study.resolve_target(str(bad))
    bad.write_text('cases = ["punch_hxe"]\n')
    with pytest.raises(study.StudyError, match="unknown case 'punch_hxe'"):
        study.resolve_target(str(bad))
    with pytest.raises(study.StudyError, match="unknown study or case 'compund'"):
        study.resolve_target("compund")
    with pytest.raises(study.StudyError, match="nowhere.toml: no such file"):
        study.resolve_target(str(tmp_path / "nowhere.toml"))
    # two case files of the same name in one study would share a case folder
    (tmp_path / "a").mkdir()
    (tmp_path / "a" / "punch_hex.toml").write_text('kind = "punch"\n')
    bad.write_text('cases = ["punch_hex", "a/punch_hex.toml"]\n')
    name, files = study.resolve_target(str(bad))
    with pytest.raises(study.StudyError, match="share the name punch_hex"):
        study.load_cases(files, True, ())
    # a bad file anywhere in the study stops it before the first case
    (tmp_path / "a" / "broken.toml").write_text('kind = "punch"\n[panel]\nwidth = 0.0\n')
    bad.write_text('cases = ["beam", "a/broken.toml"]\n')
    with pytest.raises(study.StudyError, match="broken.toml: panel.width: must be >= 0.1, got 0 "):
        study.load_cases(study.resolve_target(str(bad))[1], True, ())
    # a study file is told from a case file by its `cases` key
    assert study.resolve_target(str(lmp.ROOT / "inputs" / "studies" / "impact.toml"))[1][0] \
        .endswith("impact_hex.toml")


# --- the block of an STL: mass properties of the uniform solid ------------------------------------

def _box_stl(path, a, b, c, shift):
    """A closed, outward-oriented box a x b x c with its corner at ``shift``."""
    import itertools
    v = {k: (k[0] * a + shift[0], k[1] * b + shift[1], k[2] * c + shift[2])
         for k in itertools.product((0, 1), repeat=3)}
    quads = [((0, 0, 0), (0, 1, 0), (1, 1, 0), (1, 0, 0)), ((0, 0, 1), (1, 0, 1), (1, 1, 1), (0, 1, 1)),
             ((0, 0, 0), (1, 0, 0), (1, 0, 1), (0, 0, 1)), ((0, 1, 0), (0, 1, 1), (1, 1, 1), (1, 1, 0)),
             ((0, 0, 0), (0, 0, 1), (0, 1, 1), (0, 1, 0)), ((1, 0, 0), (1, 1, 0), (1, 1, 1), (1, 0, 1))]
    lines = ["solid box"]
    for q in quads:
        for tri in ((q[0], q[1], q[2]), (q[0], q[2], q[3])):
            lines += ["facet normal 0 0 0", "outer loop", *(f"vertex {v[k][0]} {v[k][1]} {v[k][2]}"
                                                          for k in tri), "endloop", "endfacet"]
    path.write_text("\n".join(lines + ["endsolid box"]) + "\n")


def test_stl_block_mass_properties_and_orientation(tmp_path):
    """A 0.6 x 0.4 x 0.2 m box of 12 kg anywhere in its file: centred, I = m (b^2 + c^2) / 12
    etc.; turned 90 degrees about z its x and y moments swap and its lowest point stays c / 2
    below the centroid."""
    import numpy as np
    from postprocess import vtu
    from runner.block import Block
    _box_stl(tmp_path / "box.stl", 0.6, 0.4, 0.2, (5.0, -3.0, 1.0))
    block = Block(str(tmp_path), 12.0, None, stl=str(tmp_path / "box.stl"))
    expected = np.diag([12 * (0.4 ** 2 + 0.2 ** 2) / 12, 12 * (0.6 ** 2 + 0.2 ** 2) / 12,
                        12 * (0.6 ** 2 + 0.4 ** 2) / 12])
    assert np.allclose(block.inertia, expected, atol=1e-12)
    assert block.half == pytest.approx(0.1)
    points, _ = vtu.read_stl(block.path)
    assert np.allclose(points.mean(axis=0), 0.0, atol=1e-12)    # the written STL is centred
    s = math.sqrt(0.5)
    (tmp_path / "t").mkdir()
    turned = Block(str(tmp_path / "t"), 12.0, None, quat=(s, 0.0, 0.0, s),
                          stl=str(tmp_path / "box.stl"))
    assert np.allclose(np.diag(turned.inertia), np.diag(expected)[[1, 0, 2]], atol=1e-12)
    assert turned.half == pytest.approx(0.1)


def test_missing_previous_net_is_named(tmp_path):
    from runner.errors import RunError
    from runner.kinds import impact
    case = check('kind = "impact"\n', quick=True)
    with pytest.raises(RunError, match="no net from the previous impact"):
        impact.Setup(kinds.of(case), str(tmp_path), case.impacts[0], 0.05,
                     restart=str(tmp_path / "net.restart"))


def test_product_keys_shape_the_generated_net(tmp_path, monkeypatch):
    """The mesh product of a case file (issue #42) reaches wirenet-gen: a compound panel with a
    10x12 hex mesh (axis distance 0.1 m), a 0.25 m square cell of 12 mm ropes in 5 elements:
    its JSON and data file say so (cell, element length, node spheres the rope's diameter, the
    twist rows' pitch); the defaults pass no option at all (the generator's default net)."""
    from runner import panel
    monkeypatch.setenv("WIRENET_BUILD", str(lmp.BUILD))
    assert panel.generator_options(check('kind = "impact"\n[panel]\nnet = "compound"\n'),
                                   "compound") == []
    case = check('kind = "impact"\n[panel]\nnet = "compound"\nwidth = 1.0\nheight = 1.0\n'
                 'axis_distance = 0.1\ntwist_length = 0.05\nrise = 0.045\ncell = 0.25\n'
                 'rope_elements = 5\n[materials]\nrope_d = 0.012\n')
    made = panel.Panel(case, str(tmp_path))
    square = made.meta["cells"]["square"]
    assert square["cell"] == 0.25 and square["elements_per_side"] == 5
    assert square["element_length"] == pytest.approx(0.05)
    hex_ = made.meta["cells"]["hex"]
    assert hex_["axis_distance"] == 0.1 and hex_["twist_length"] == 0.05 and hex_["rise"] == 0.045
    d = made.data.atom("diameter")
    assert np.isclose(d, 0.012).sum() > 0                # the square layer's nodes: the rope's
