"""WireNet benchmarks (run by `./wirenet bench`; not a test).

1. The bond loop: the default 3 m x 3 m hexagonal net of `wirenet-gen hex`, stretched by 0.08 %,
   edges held, interior nodes integrated with fix nve/sphere for N steps after a small random
   displacement of every node, once with
   bond_style wirenet (wire laws, elastic range) and once with bond_style harmonic on the same
   bonds (one harmonic type per distinct bond length, so every bond starts at rest). The time is
   LIGGGHTS' own "Bond time" of the run's timing breakdown; the best of a few repeats is kept
   (the machine may be shared). Reported: ns per bond and step, and the ratio wirenet/harmonic.
   The same for the beam law on a strand-rope mesh (0.1 m cells) against bond_style harmonic.
2. `wirenet-gen hex --width 10 --height 10` (wall time).
3. `/usr/bin/python3 -m postprocess.benchmark` (its own timing line).

Prints a table and writes docs/PERFORMANCE.md (the part between the bench markers; notes outside
them are kept).

    /usr/bin/python3 tests/bench/run_bench.py [--steps 5000] [--repeats 3] [--out DIR] [--no-doc]
"""

import argparse
import json
import os
import platform
import re
import shutil
import subprocess
import sys
import time
from pathlib import Path

import bench_body   # tests/bench/bench_body.py: the timed punch, LIGGGHTS' loop times
from bench_body import loop_times
from postprocess import report   # the study elapsed time, as the report counts it

ROOT = Path(__file__).resolve().parents[2]
BUILD = Path(os.environ.get("WIRENET_BUILD", ROOT / "build"))
LIGGGHTS = BUILD / "bin" / "liggghts"
GEN = BUILD / "bin" / "wirenet-gen"
DOC = ROOT / "docs" / "PERFORMANCE.md"
BEGIN, END = "<!-- bench:begin (written by tests/bench/run_bench.py) -->", "<!-- bench:end -->"

SW = ("0.0019230769 2.5e8 0.0192 3.2195e8 0.05 3.8292e8 0.15 5.1219e8 "
      "0.25 5.5854e8 0.30 5.6585e8 0.35 5.6585e8")
WIRE_COEFFS = f"""bond_style wirenet
bond_coeff 1 wire diameter 0.0027 curve {SW} family DT derived lambda_eps 0.4 lambda_k 0.66 nu 0.3
bond_coeff 2 wire diameter 0.0027 curve {SW} family SW
bond_coeff 3 wire diameter 0.0034 curve {SW} family selvedge
bond_coeff 4 wire diameter 0.0027 curve {SW} family unused
"""
DT = 1e-6            # s; the shortest, stiffest bonds of the panel need about 1e-5
PRESTRAIN = 8e-4     # uniform in-plane stretch of the net (elastic limit of the wires: 1.9e-3)
PERTURB = 3e-6       # m, uniform in [-PERTURB, PERTURB] per coordinate
SEED = 15485863     # LIGGGHTS wants a prime > 10000


def deck(data, coeffs, steps):
    """The net at rest (the wire bonds take their initial lengths at `run 0`), then stretched by
    PRESTRAIN in x and y, every node displaced at random by up to PERTURB, edge nodes held, the
    interior nodes integrated: every bond is loaded, in the elastic range, and vibrates."""
    h = 1.5 * PRESTRAIN  # displacement at x, y = +-1.5 m
    return f"""units si
atom_style hybrid granular molecular
atom_modify map array sort 0 0
boundary f f f
newton off on
read_data {data}
{coeffs}
group interior type 1 5
fix integrate interior nve/sphere
timestep {DT!r}
thermo 1000
run 0
displace_atoms all ramp x {-h!r} {h!r} x -1.5 1.5 units box
displace_atoms all ramp y {-h!r} {h!r} y -1.5 1.5 units box
displace_atoms all random {PERTURB!r} {PERTURB!r} {PERTURB!r} {SEED} units box
run {steps}
"""


def read_data(path):
    """Header lines, atoms section text, list of bonds (id, type, a, b), atom positions."""
    text = Path(path).read_text().splitlines()
    a0 = text.index("Atoms")
    b0 = text.index("Bonds")
    pos = {}
    for line in text[a0 + 1:b0]:
        w = line.split()
        if len(w) >= 5:
            pos[int(w[0])] = tuple(float(v) for v in w[2:5])
    bonds = [tuple(int(v) for v in line.split()) for line in text[b0 + 1:] if line.split()]
    return text, a0, b0, pos, bonds


def harmonic_data(src, dst):
    """Copy of the net with one bond type per distinct length (to 0.1 um); returns the
    bond_coeff block: harmonic K (F = 2 K dr) with 2 K = the wire's initial stiffness
    sigma_1 A / (eps_1 l0) at that length, r0 = the length."""
    text, a0, b0, pos, bonds = read_data(src)
    lengths = {}
    out_bonds = []
    for bid, btype, i, j in bonds:
        d = sum((p - q) ** 2 for p, q in zip(pos[i], pos[j])) ** 0.5
        key = (btype, round(d, 7))
        if key not in lengths:
            lengths[key] = len(lengths) + 1
        out_bonds.append(f"{bid} {lengths[key]} {i} {j}")
    header = [re.sub(r"^\s*\d+ bond types", f"{len(lengths)} bond types", l) for l in text[:a0]]
    Path(dst).write_text("\n".join(header + text[a0:b0 + 1] + [""] + out_bonds) + "\n")
    coeffs = ["bond_style harmonic"]
    for (btype, d), t in sorted(lengths.items(), key=lambda kv: kv[1]):
        diameter = 0.0034 if btype == 3 else 0.0027
        area = 3.141592653589793 * diameter ** 2 / 4
        k = 2.5e8 * area / (0.0019230769 * d)
        coeffs.append(f"bond_coeff {t} {0.5 * k!r} {d!r}")
    return "\n".join(coeffs) + "\n", len(lengths)


def bond_time(output):
    """(Bond time, loop time, steps, bonds) of the last run in a LIGGGHTS output."""
    loops = re.findall(r"Loop time of ([0-9.eE+-]+) on \d+ procs for (\d+) steps", output)
    bonds = re.findall(r"^Bond\s+time \(%\) = ([0-9.eE+-]+)", output, re.M)
    if not loops or not bonds:
        raise RuntimeError("no timing breakdown in the LIGGGHTS output:\n" + output[-2000:])
    return float(bonds[-1]), float(loops[-1][0]), int(loops[-1][1])


def run_liggghts(text, workdir, name):
    (workdir / name).write_text(text)
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    p = subprocess.run([str(LIGGGHTS), "-in", name, "-log", "none", "-echo", "none"], cwd=workdir,
                       env=env, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    if p.returncode != 0 or "ERROR" in p.stdout:
        raise RuntimeError(f"{name} failed:\n" + p.stdout[-3000:])
    return p.stdout


def machine_facts():
    model = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                model = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    load = os.getloadavg() if hasattr(os, "getloadavg") else (float("nan"),) * 3
    return {"nproc": os.cpu_count(), "cpu": model, "kernel": platform.release(),
            "python": platform.python_version(), "load_average": [round(v, 2) for v in load]}


def bench_bonds(out, steps, repeats):
    subprocess.run([str(GEN), "hex", "--out", str(out / "net3x3")], check=True, stdout=subprocess.DEVNULL)
    meta = json.loads((out / "net3x3.json").read_text())
    natoms, nbonds = meta["counts"]["atoms"], meta["counts"]["bonds"]
    hcoeffs, ntypes = harmonic_data(out / "net3x3.data", out / "net3x3_harmonic.data")
    # the tensions are dumped at the first and the last step only (output time is not Bond time)
    wire = WIRE_COEFFS + f"compute bl all wirenet/local\ndump bd all local {steps} tension.dump c_bl[6] c_bl[5]\n"
    decks = {"wirenet": deck("net3x3.data", wire, steps),
             "harmonic": deck("net3x3_harmonic.data", hcoeffs, steps)}
    best = {k: None for k in decks}
    for r in range(repeats):
        for name, text in decks.items():   # alternate, so both see the same machine load
            res = bond_time(run_liggghts(text, out, f"in.{name}"))
            if best[name] is None or res[0] < best[name][0]:
                best[name] = res
    rows = {}
    for name, (tb, tl, n) in best.items():
        rows[name] = {"bond_time_s": tb, "loop_time_s": tl, "steps": n,
                      "ns_per_bond_step": tb / (n * nbonds) * 1e9}
    return {"atoms": natoms, "bonds": nbonds, "harmonic_types": ntypes, "steps": steps,
            "repeats": repeats, "dt": DT, "perturbation_m": PERTURB, "runs": rows,
            "ratio": rows["wirenet"]["bond_time_s"] / rows["harmonic"]["bond_time_s"]}


BEAM_COEFFS = """bond_style wirenet
bond_coeff 1*3 wire diameter 0.0027 curve 0.0019230769 2.5e8 0.35 5.6585e8
bond_coeff 4 beam diameter 0.01 E 6e10 nu 0.3 bending 0.05 family rope
"""


def bench_beam(out, steps, repeats):
    """The beam law on a strand-rope mesh (0.1 m cells, 3 elements a side) against bond_style
    harmonic on the same bonds: the rope bonds carry axial, shear, bending and twist terms."""
    subprocess.run([str(GEN), "square", "--cell", "0.1", "--out", str(out / "rope3x3")], check=True,
                   stdout=subprocess.DEVNULL)
    meta = json.loads((out / "rope3x3.json").read_text())
    nbonds = meta["counts"]["bonds"]
    hcoeffs, _ = harmonic_data(out / "rope3x3.data", out / "rope3x3_harmonic.data")
    decks = {"wirenet": deck("rope3x3.data", BEAM_COEFFS, steps),
             "harmonic": deck("rope3x3_harmonic.data", hcoeffs, steps)}
    best = {k: None for k in decks}
    for _ in range(repeats):
        for name, text in decks.items():
            res = bond_time(run_liggghts(text, out, f"in.beam_{name}"))
            if best[name] is None or res[0] < best[name][0]:
                best[name] = res
    rows = {name: {"bond_time_s": tb, "steps": n, "ns_per_bond_step": tb / (n * nbonds) * 1e9}
            for name, (tb, tl, n) in best.items()}
    return {"bonds": nbonds, "runs": rows,
            "ratio": rows["wirenet"]["bond_time_s"] / rows["harmonic"]["bond_time_s"]}


def tension_share(out):
    """(Fraction of wire bonds carrying tension, largest strain) in the last frame of the wirenet
    run's bond dump (a slack wire skips the force update, which a harmonic bond never does)."""
    lines = (out / "tension.dump").read_text().splitlines()
    start = max(k for k, l in enumerate(lines) if l.startswith("ITEM: ENTRIES")) + 1
    rows = [[float(v) for v in l.split()] for l in lines[start:] if l.strip()]
    loaded = sum(1 for r in rows if r[0] > 0) / max(len(rows), 1)
    return loaded, max(abs(r[1]) for r in rows)


def bench_generator(out, repeats):
    best = None
    for _ in range(repeats):
        t0 = time.perf_counter()
        subprocess.run([str(GEN), "hex", "--width", "10", "--height", "10", "--out", str(out / "net10x10")],
                       check=True, stdout=subprocess.DEVNULL)
        dt = time.perf_counter() - t0
        best = dt if best is None else min(best, dt)
    meta = json.loads((out / "net10x10.json").read_text())
    return {"seconds": best, "atoms": meta["counts"]["atoms"], "bonds": meta["counts"]["bonds"]}


def bench_postprocess():
    t0 = time.perf_counter()
    p = subprocess.run(["/usr/bin/python3", "-m", "postprocess.benchmark"], cwd=ROOT,
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    wall = time.perf_counter() - t0
    line = p.stdout.strip().splitlines()[-1] if p.stdout.strip() else ""
    m = re.search(r"zone: ([0-9.]+) s", line)
    return {"wall_seconds": wall, "zone_seconds": float(m.group(1)) if m else None, "line": line,
            "exit": p.returncode}


RELEASED = "impact: block released"    # the impact deck's line before the timed phase
YADE_CASE = ROOT / "docs" / "examples" / "yade_punch.toml"
YADE_SCRIPT = ROOT / "tests" / "bench" / "yade_punch.py"
ENV = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")


def bench_yade_punch(out, travel):
    """YADE WirePM's punch test in both codes on one core: WireNet runs the case file
    docs/examples/yade_punch.toml (its net is hexaNet's lattice) for `travel` metres of the sphere;
    YADE (tests/bench/yade_punch.py) the same number of steps of the same time step. Per step:
    LIGGGHTS' loop time (everything in the step: bonds, contacts, body, damping, integration,
    outputs) against YADE's wall time of O.run (after a warm-up)."""
    folder = out / "yade_punch"
    shutil.rmtree(folder, ignore_errors=True)     # a finished case would be skipped, not timed
    cmd = [sys.executable, "-P", "-m", "runner", "run", str(YADE_CASE), "--np", "1", "--out",
           str(folder), "--set", f"punch.travel={travel!r}"]
    p = subprocess.run(cmd, cwd=ROOT, env=dict(ENV, PYTHONPATH=str(ROOT)), stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    if p.returncode != 0:
        raise RuntimeError("WireNet yade_punch failed:\n" + p.stdout[-3000:])
    case = folder / "yade_punch"
    meta = json.loads((case / "case.json").read_text())
    steps, seconds = loop_times((case / "run" / "log.lammps").read_text())
    panel = json.loads((case / "setup" / "panel.json").read_text())["counts"]
    res = {"wirenet": {"nodes": panel["atoms"], "bonds": panel["bonds"], "steps": steps,
                       "loop_seconds": seconds, "ms_per_step": 1e3 * seconds / steps,
                       "dt": meta["dt"], "peak_force": meta["peak_force"]}}
    yade = shutil.which("yade")
    if yade is None:
        res["yade"] = None
        res["note"] = "yade is not installed (Debian package yade): no YADE row"
        return res
    result = out / "yade_punch.json"
    p = subprocess.run([yade, "-n", "-x", "-j1", str(YADE_SCRIPT), str(steps), repr(meta["dt"]),
                        str(result)], cwd=out, stdout=subprocess.PIPE, stderr=subprocess.STDOUT,
                       text=True)
    if p.returncode != 0 or not result.exists():
        raise RuntimeError("YADE yade_punch.py failed:\n" + p.stdout[-3000:])
    res["yade"] = json.loads(result.read_text())
    res["ratio"] = res["yade"]["ms_per_step"] / res["wirenet"]["ms_per_step"]
    return res


TENSILE_CASE = ROOT / "docs" / "examples" / "yade_tensile.toml"
TENSILE_SCRIPT = ROOT / "tests" / "bench" / "yade_tensile.py"
TENSILE_REFERENCE = ROOT / "tests" / "reference" / "yade_tensile" / "yade_tensile.json"


def bench_yade_tensile(out, yade_displ=0.045):
    """YADE WirePM's tensile test in both codes (doc/tensile.md): WireNet runs the case file
    docs/examples/yade_tensile.toml on one core, YADE tests/bench/yade_tensile.py to
    `yade_displ` metres of clamp travel (past the peak at 40.8 mm; without the Debian package
    yade the full run kept in tests/reference/yade_tensile/ stands in); returns the comparison
    table of `yade_tensile.py --compare` (force at 10/20/40 mm, peak and its displacement) and
    whether every difference is within 2 %."""
    folder = out / "yade_tensile"
    shutil.rmtree(folder, ignore_errors=True)
    cmd = [sys.executable, "-P", "-m", "runner", "run", str(TENSILE_CASE), "--np", "1", "--out",
           str(folder)]
    p = subprocess.run(cmd, cwd=ROOT, env=dict(ENV, PYTHONPATH=str(ROOT)), stdout=subprocess.PIPE,
                       stderr=subprocess.STDOUT, text=True)
    if p.returncode != 0:
        raise RuntimeError("WireNet yade_tensile failed:\n" + p.stdout[-3000:])
    reference, note = TENSILE_REFERENCE, "YADE: the run kept in tests/reference/yade_tensile/"
    yade = shutil.which("yade")
    if yade is not None:
        prefix = out / "yade_tensile_yade"
        q = subprocess.run([yade, "-n", "-x", "-j1", str(TENSILE_SCRIPT), str(prefix),
                            repr(yade_displ)], cwd=out, stdout=subprocess.PIPE,
                           stderr=subprocess.STDOUT, text=True)
        if q.returncode != 0 or not Path(f"{prefix}.json").exists():
            raise RuntimeError("YADE yade_tensile.py failed:\n" + q.stdout[-3000:])
        reference, note = Path(f"{prefix}.json"), f"YADE run here to {yade_displ} m"
    c = subprocess.run([sys.executable, str(TENSILE_SCRIPT), "--compare",
                        str(folder / "yade_tensile" / "case.json"), str(reference)],
                       stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True)
    return {"table": c.stdout.strip(), "within_target": c.returncode == 0, "reference": note}


def yade_tensile_table(t):
    return "\n".join(["### YADE WirePM tensile test (docs/examples/yade_tensile.toml)", "",
                      f"{t['reference']}; WireNet on one core.", "", t["table"]])


def keep_best(res, np_, n, seconds):
    """res[np_] = the run of n steps in `seconds` if it is the fastest per step so far."""
    best = res.get(np_)
    if best is None or seconds / n < best["seconds"] / best["steps"]:
        res[np_] = {"steps": n, "seconds": seconds}


def speedup(one, two):
    """Time per step of run `one` over that of run `two` ({"steps", "seconds"} each)."""
    return (one["seconds"] / one["steps"]) / (two["seconds"] / two["steps"])


def bench_ranks(out, steps, repeats=3, ranks=(1, 2)):
    """The 3 m compound panel's punch and impact on 1 and 2 MPI ranks: LIGGGHTS' loop time of
    `steps` steps of the load phase (after a short pre-load or settling, which is not timed).
    The set-ups are the study's (runner/kinds/punch.py, runner/kinds/impact.py); the bond dumps
    are off.
    The rank counts alternate, `repeats` times, and the best of each is kept: a single run on a
    shared machine moves by about 5 %, as much as the effects measured here."""
    from runner import INPUTS, api, engine, kinds, materials
    from runner.kinds import impact
    res = {"punch": {}, "impact": {}}

    for _ in range(repeats):
        for np_ in ranks:
            n, seconds = bench_body.run("compound", True, steps, "analytic",
                                        str(out / f"ranks_punch_np{np_}"), np_=np_)
            keep_best(res["punch"], np_, n, seconds)
            folder = out / f"ranks_impact_np{np_}"
            case = api.load('kind = "impact"\n[panel]\nnet = "compound"\n',
                            set=["preload.settle_time=0.002"])
            setup = impact.Setup(kinds.of(case), str(folder / "setup"), case.impacts[0],
                                 materials.bending_of(case, str(folder))[0])
            setup.duration, setup.steps = steps * setup.dt, steps     # the first `steps` of the impact
            variables = setup.variables()
            variables.update(dump_every=10 ** 9, frame_every=10 ** 9)
            engine.run(INPUTS / "impact.in", str(folder / "run"), variables, np=np_,
                       total_steps=steps, dt=setup.dt, phase_marker=RELEASED)
            keep_best(res["impact"], np_, *loop_times((folder / "run" / "log.lammps").read_text(), RELEASED))
    for case in res.values():
        case["speedup"] = speedup(case[ranks[0]], case[ranks[-1]])
    res["repeats"] = repeats
    return res


def bench_fence_ranks(out, steps, repeats=2, ranks=(1, 2)):
    """The default compound fence's impact on 1 and 2 MPI ranks: LIGGGHTS' loop time of the
    first `steps` steps after the release (the block in contact from the first steps). The
    fence settles once, for 0.2 s only (the first run, on the most ranks; the others start from
    its settled state in the bench's own study folder, as a study's cases do; the cost of the
    impact's first steps hardly depends on how still the fence was); the rank counts alternate,
    the best of each kept."""
    from runner import api
    study = out / "fence_ranks"
    dt_guess = 5.2e-6     # the default fence's step (doc/fence.md): about `steps` steps
    case = api.load(str(ROOT / "inputs" / "cases" / "fence_compound.toml"),
                    set=["fence.rest_time=0", "fence.impact_end=0", "output.frames=2",
                         "fence.settle_time=0.2", f"fence.duration={steps * dt_guess!r}"])
    res = {}
    for _ in range(repeats):
        for np_ in sorted(ranks, reverse=True):
            folder = study / f"np{np_}"
            if folder.exists():
                shutil.rmtree(folder)
            api.run(case, str(folder), ranks=np_, study_dir=str(study))
            keep_best(res, np_, *loop_times((folder / "run" / "log.lammps").read_text(), RELEASED))
    res["speedup"] = speedup(res[ranks[0]], res[ranks[-1]])
    res["repeats"] = repeats
    return res


def fence_ranks_table(r):
    one, two = r[1], r[2]
    return "\n".join([
        f"| default compound fence, impact | steps | 1 rank (s) | 2 ranks (s) | speed-up (best of {r['repeats']} alternating runs each) |",
        "|---|---|---|---|---|",
        f"| first steps after the release | {one['steps']} | {one['seconds']:.2f} | {two['seconds']:.2f} | "
        f"**{r['speedup']:.2f}** (target >= 1.8) |"])


def ranks_table(r):
    lines = [f"| 3 m compound panel | steps | 1 rank (s) | 2 ranks (s) | speed-up (best of {r.get('repeats', 1)} alternating runs each) |",
             "|---|---|---|---|---|"]
    for case in ("punch", "impact"):
        c = r[case]
        lines.append(f"| {case} (load phase) | {c[1]['steps']} | {c[1]['seconds']:.2f} | "
                     f"{c[2]['seconds']:.2f} | **{c['speedup']:.2f}** (target >= 1.8) |")
    return "\n".join(lines)


def study_table(folder):
    """Wall time per case of a finished study folder (case.json of each case), or a note."""
    if folder is None or not Path(folder).is_dir():
        return ("Study wall times: no study folder (run `./wirenet run` first, or give "
                "`--study DIR`).")
    rows, total, cpu_total, metas = [], 0.0, 0.0, []
    for meta_path in sorted(Path(folder).glob("*/case.json")):
        meta = json.loads(meta_path.read_text())
        metas.append(meta)
        wall, cpu = meta.get("wall_time"), meta.get("cpu_time")
        timed = isinstance(wall, (int, float))
        total += wall if timed else 0.0
        cpu_total += cpu if isinstance(cpu, (int, float)) else 0.0
        rows.append(f"| {meta_path.parent.name} | {meta.get('mode', '?')} | {meta.get('status', '?')} | "
                    f"{meta.get('np', '?')} | {f'{wall:.0f}' if timed else 'n/a'} | "
                    f"{f'{cpu:.0f}' if isinstance(cpu, (int, float)) else 'n/a'} |")
    span = report.elapsed(metas)
    return "\n".join([f"Study `{shown(folder)}` (each case as its case.json records it, whenever it ran; "
                      "CPU: its LIGGGHTS processes, all ranks):", "",
                      "| case | mode | status | ranks | wall time [s] | CPU [core-s] |",
                      "|---|---|---|---|---|---|",
                      *rows, f"| **total** | | | | **{total:.0f}** ({total / 60:.1f} min) | "
                      f"**{cpu_total:.0f}** |",
                      *([] if span is None else
                        [f"| **elapsed**, first start to last end (cases side by side) | | | | "
                         f"**{span:.0f}** ({span / 60:.1f} min) | {cpu_total / span:.2f} cores "
                         "busy on average |"])])


def yade_table(y):
    w = y["wirenet"]
    lines = ["| YADE WirePM punch test, 1 core | nodes | links/bonds | steps of dt | ms per step |",
             "|---|---|---|---|---|",
             f"| WireNet (`docs/examples/yade_punch.toml`, analytic sphere) | {w['nodes']} | "
             f"{w['bonds']} | {w['steps']} of {w['dt']:.3g} s | {w['ms_per_step']:.3f} |"]
    if y.get("yade"):
        v = y["yade"]
        lines.append(f"| YADE {v['yade']} (`tests/bench/yade_punch.py`, `yade -j1`) | {v['nodes']} | "
                     f"{v['links']} | {v['steps']} of {v['dt']:.3g} s | {v['ms_per_step']:.3f} |")
        lines += ["", f"YADE / WireNet time per step: **{y['ratio']:.1f}** (target >= 10)"]
    else:
        lines += ["", y["note"]]
    return "\n".join(lines)


def table(res):
    b = res["bonds"]
    lines = ["| case | bonds | steps | Bond time (s) | loop time (s) | ns per bond-step |",
             "|---|---|---|---|---|---|"]
    for name in ("wirenet", "harmonic"):
        r = b["runs"][name]
        lines.append(f"| bond_style {name} | {b['bonds']} | {r['steps']} | {r['bond_time_s']:.4f} | "
                     f"{r['loop_time_s']:.4f} | {r['ns_per_bond_step']:.1f} |")
    lines.append("")
    lines.append(f"ratio wirenet / harmonic (Bond time): **{b['ratio']:.2f}** (target <= 1.5); "
                 f"wire bonds in tension at the end: {100 * res['tension_share'][0]:.0f} %, largest strain "
                 f"{res['tension_share'][1]:.2g} (elastic up to 1.9e-3)")
    lines.append("")
    bm = res["beam"]
    lines += ["| beam law (strand-rope mesh) | bonds | ns per bond-step |", "|---|---|---|"]
    for name in ("wirenet", "harmonic"):
        lines.append(f"| bond_style {name} | {bm['bonds']} | {bm['runs'][name]['ns_per_bond_step']:.1f} |")
    lines += ["", f"ratio beam / harmonic (Bond time): **{bm['ratio']:.2f}** (target <= 5; LAMMPS' "
              "bpm/rotational is about 30)", ""]
    g, p = res["generator"], res["postprocess"]
    lines += ["| other | time |", "|---|---|",
              f"| `wirenet-gen hex --width 10 --height 10` ({g['atoms']} atoms, {g['bonds']} bonds) | "
              f"{g['seconds']:.2f} s (best of {res['repeats']}) |",
              f"| `/usr/bin/python3 -m postprocess.benchmark` (zone statistics of 100 frames x 10 000 bonds) | "
              f"zone {p['zone_seconds']} s, whole command {p['wall_seconds']:.1f} s |"]
    return "\n".join(lines)


def shown(path):
    """A path relative to the repository when it lies inside it."""
    try:
        return str(Path(path).resolve().relative_to(ROOT))
    except ValueError:
        return str(path)


def write_doc(res, text):
    m = res["machine"]
    block = "\n".join([
        BEGIN,
        f"Measured {time.strftime('%Y-%m-%d %H:%M %Z')} with `{res['command']}`",
        f"(LIGGGHTS binary `{shown(LIGGGHTS)}`, {res['bonds']['atoms']} atoms, {res['bonds']['bonds']} bonds, "
        f"{res['bonds']['steps']} steps of {DT:g} s; net stretched by {PRESTRAIN:g}, edges held, nodes displaced "
        f"at random by up to {PERTURB * 1e6:g} um; "
        f"best of {res['repeats']} alternating repeats, 1 MPI rank).",
        "",
        f"Machine: {m['nproc']} CPUs (`nproc`), {m['cpu']}, Linux {m['kernel']}, "
        f"load average at the start {m['load_average'][0]} (other jobs may share the CPUs).",
        "",
        text,
        END,
    ])
    if DOC.exists():
        old = DOC.read_text()
        if BEGIN in old and END in old:
            new = old[:old.index(BEGIN)] + block + old[old.index(END) + len(END):]
        else:
            new = old.rstrip() + "\n\n" + block + "\n"
    else:
        new = ("# Performance\n\n`./wirenet bench` (or `WIRENET_BUILD=build /usr/bin/python3 "
               "tests/bench/run_bench.py`) measures the bond loop of bond_style wirenet against "
               "bond_style harmonic, the generator and the post-processing.\n\n" + block + "\n")
    DOC.parent.mkdir(parents=True, exist_ok=True)
    DOC.write_text(new)


def main(argv=None):
    ap = argparse.ArgumentParser(prog="run_bench.py")
    ap.add_argument("--steps", type=int, default=5000)
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--out", type=Path, default=BUILD / "bench")
    ap.add_argument("--yade-travel", type=float, default=0.04,
                    help="sphere travel of the YADE punch comparison [m] (0.04: about 20 000 steps)")
    ap.add_argument("--study", type=Path, default=ROOT / "out" / "compound",
                    help="a finished study folder whose case wall times are tabulated "
                         "(default out/compound, what ./wirenet run writes)")
    ap.add_argument("--rank-steps", type=int, default=4000,
                    help="steps of the 1-vs-2-rank comparison on the compound panel")
    ap.add_argument("--fence-steps", type=int, default=3000,
                    help="steps of the 1-vs-2-rank comparison on the default compound fence's impact")
    ap.add_argument("--only", choices=("yade", "yade-tensile", "ranks", "fence-ranks", "study"),
                    help="run one benchmark only (no doc rewrite)")
    ap.add_argument("--no-doc", action="store_true", help="do not rewrite docs/PERFORMANCE.md")
    opts = ap.parse_args(argv)
    for exe in (LIGGGHTS, GEN):
        if not exe.exists():
            sys.exit(f"run_bench.py: {exe} is missing; build first (./wirenet setup)")
    opts.out.mkdir(parents=True, exist_ok=True)
    res = {"machine": machine_facts(), "repeats": opts.repeats,
           "command": "./wirenet bench" + "".join(f" {a}" for a in (argv or sys.argv[1:]))}
    if opts.only == "study":
        print(study_table(opts.study))
        return 0
    if opts.only == "ranks":
        r = bench_ranks(opts.out, opts.rank_steps, opts.repeats)
        print(ranks_table(r))
        (opts.out / "ranks_results.json").write_text(json.dumps(r, indent=2) + "\n")
        return 0
    if opts.only == "fence-ranks":
        r = bench_fence_ranks(opts.out, opts.fence_steps)
        print(fence_ranks_table(r))
        (opts.out / "fence_ranks_results.json").write_text(json.dumps(r, indent=2) + "\n")
        return 0
    if opts.only == "yade-tensile":
        t = bench_yade_tensile(opts.out)
        print(yade_tensile_table(t))
        (opts.out / "yade_tensile_results.json").write_text(json.dumps(t, indent=2) + "\n")
        return 0 if t["within_target"] else 1
    if opts.only == "yade":
        y = bench_yade_punch(opts.out, opts.yade_travel)
        print(yade_table(y))
        (opts.out / "yade_punch_results.json").write_text(json.dumps(y, indent=2) + "\n")
        return 0
    print(f"[bench] bond loop: 3 m x 3 m hex net, {opts.steps} steps, best of {opts.repeats}", flush=True)
    res["bonds"] = bench_bonds(opts.out, opts.steps, opts.repeats)
    res["tension_share"] = tension_share(opts.out)
    print(f"[bench] beam law: strand-rope mesh, {opts.steps} steps, best of {opts.repeats}", flush=True)
    res["beam"] = bench_beam(opts.out, opts.steps, opts.repeats)
    print("[bench] wirenet-gen hex --width 10 --height 10", flush=True)
    res["generator"] = bench_generator(opts.out, opts.repeats)
    print("[bench] python3 -m postprocess.benchmark", flush=True)
    res["postprocess"] = bench_postprocess()
    print(f"[bench] YADE WirePM punch test: WireNet and YADE, {opts.yade_travel} m of travel, 1 core",
          flush=True)
    res["yade_punch"] = bench_yade_punch(opts.out, opts.yade_travel)
    print("[bench] YADE WirePM tensile test: WireNet and YADE, force at 10/20/40 mm and the peak",
          flush=True)
    res["yade_tensile"] = bench_yade_tensile(opts.out)
    print(f"[bench] 1 vs 2 MPI ranks: 3 m compound punch and impact, {opts.rank_steps} steps", flush=True)
    res["ranks"] = bench_ranks(opts.out, opts.rank_steps, opts.repeats)
    text = "\n\n".join([table(res), yade_table(res["yade_punch"]),
                         yade_tensile_table(res["yade_tensile"]), ranks_table(res["ranks"]),
                         study_table(opts.study)])
    print()
    print(text)
    (opts.out / "results.json").write_text(json.dumps(res, indent=2) + "\n")
    if not opts.no_doc:
        write_doc(res, text)
        print(f"\n[bench] wrote {DOC}")
    return 0


if __name__ == "__main__":
    try:
        sys.exit(main())
    except RuntimeError as exc:    # a benchmark run failed: its message ends with the run's output
        sys.exit(f"run_bench.py: error: {exc}")
