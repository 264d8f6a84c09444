"""Engine speed: particle-steps/s of the dam break and the tank over a range of sizes, cold and
warm compile, and the same cases on another git revision, run back to back.

    python -m tisph.bench --speed [--against REV] [--repeats N] [--threads N] [--quick]
                                  [--peer pysph,dualsphysics] [--arch gpu] [--out renders/bench]
                                  [--sizes 1e4 1e5 1e6]
    python -m tisph.bench --speed --peer-ladder [--peer pysph,dualsphysics]

--sizes: the dam break and the flume at about these particle counts (the GPU check of
docs/performance.md: `--speed --arch gpu --sizes 1e4 1e5 1e6 --repeats 1`).

Each measurement runs in its own process (Taichi compiles once per process): build the case,
prime, one warm-up step, then a fixed number of steps timed with a field read at the end (it
waits for the last kernel). With --against, every case is run on this tree and on REV (checked
out into a temporary git worktree) alternately, every other pair REV first, --repeats times, and
the ratio is the median of the pairs: these machines are shared and drift, so only ratios from
one run mean anything. With --peer, PySPH's and DualSPHysics' dam breaks beside ours
(tisph/bench/peers/dambreak_codes.py). Writes OUT/speed.md and OUT/speed.csv.
"""

import json
import math
import os
import statistics
import subprocess
import sys
import tempfile
import time

from ..io import ensure_dir, write_csv, write_text
from .common import PEERS, ROOT, peers

# (name, scene, overrides, steps): sizes from 3.4e3 to 6.5e5 particles, and the flume's paddle
CASES = [
    ("dam break dx 0.03", "dam_break", {"numerics.dx": 0.03}, 1000),
    ("dam break dx 0.015", "dam_break", {"numerics.dx": 0.015}, 400),
    # a paddle: the Python side of a step (its motion is set every step)
    ("flume dx 0.0125 (paddle)", "flume", {}, 600),
    # periodic in x with the bed-load bed and SPS: Mao's pipeline case (an older revision that
    # cannot read its case file is reported as not measured)
    # at 15 D (2.9e4 particles) with the Smagorinsky SPS and the log-law shear, so that older
    # revisions, which cannot read the case file's later keys, run the same case
    (
        "pipeline Mao D/20 (periodic)",
        "pipeline_scour",
        {
            "--config": "scenes/pipeline_scour_mao.toml",
            "geometry.length": 0.75,
            "numerics.turbulence": "smagorinsky",
            "sediment.shear": "log_far_field",
        },
        150,
    ),
    (
        "tank 4.4e4",
        "tank",
        {"numerics.dx": 0.01, "geometry.width": 2.1, "geometry.depth": 2.1, "geometry.tank_height": 2.2},
        150,
    ),
    (
        "tank 1.8e5",
        "tank",
        {"numerics.dx": 0.005, "geometry.width": 2.1, "geometry.depth": 2.1, "geometry.tank_height": 2.2},
        50,
    ),
    (
        "tank 6.5e5",
        "tank",
        {"numerics.dx": 0.0025, "geometry.width": 2.0, "geometry.depth": 2.0, "geometry.tank_height": 2.1},
        20,
    ),
]
QUICK = 4  # --quick: the first four
# the bed-load scenes as a user runs them, the Python side of the bed coupling included: steps
# timed by the runner (its step_time_s, without the outputs), from the start of the run past
# the first wave period (the bed's outer scaling and its amplitude start once it has seen one)
SCENES = [
    # the 1:20 beach (scenes/beach_1to20.toml) by its keys, which older trees have too
    (
        "beach (1:20, dx 0.015)",
        "beach",
        {
            "geometry.length": 8.0,
            "geometry.toe_x": 1.5,
            "geometry.slope": 20.0,
            "geometry.gauges_x": [1.0, 3.0, 4.5, 5.5, 6.5],
            "paddle.stroke": 0.26,
            "numerics.dx": 0.015,
            "sediment.morfac": 22.0,
        },
        8000,
    ),
    ("tunnel (default)", "tunnel", {}, 8000),
]
# --arch gpu: the tank ladder, the case whose size a GPU is for
GPU_CASES = [c for c in CASES if c[1] == "tank"]

# Runs in the tree under test (this one or REV's): only APIs every revision since the engine
# refactor has (resolve, build_case, Log, the Solver from tisph.engine.solver or the older shim).
CHILD = r"""
import json, os, sys, time, importlib, resource
t0 = time.perf_counter()
from tisph import runtime
from tisph.runner import build_case, Log, resolve
try:
    from tisph.engine.solver import Solver
except ImportError:
    from tisph.engine.solver import Solver
arch = runtime.init(sys.argv[4] if len(sys.argv) > 4 else "cpu", "f32")
scene = importlib.import_module("tisph.scenes." + sys.argv[1]).SCENE
ov = json.loads(sys.argv[2]); ov["output.quiet"] = True
steps = int(sys.argv[3])
cfg = resolve(scene, config=ov.pop("--config", None), overrides=ov)
case = build_case(scene, cfg, Log(os.devnull, True))
s = Solver(case.physics, case.particles, case.materials, case.domain, case.params)
t1 = time.perf_counter()
s.prime(); s.step(); s.dt
t2 = time.perf_counter()
batch = getattr(s, "steps_ahead_allowed", False)
left = steps
while left > 0:   # as the runner steps: in batches with one read each, where no paddle needs the host
    n = min(left, getattr(s, "batch", 64)) if batch else 1
    s.step_ahead(n) if batch else s.step()
    left -= n
s.dt
el = time.perf_counter() - t2
fb = s.field_bytes() / s.n if hasattr(s, "field_bytes") else float("nan")
rss = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024.0
print(json.dumps(dict(particles=s.n, steps=steps, seconds=el, pps=s.n * steps / el, setup=t1 - t0,
                      compile=t2 - t1, field_bytes=fb, peak_rss_mb=rss, arch=arch)))
"""

# A scene run as the runner runs it, to a number of steps (run.max_steps), no pictures or snapshots.
CHILD_SCENE = r"""
import json, sys, tempfile, importlib
try:
    from tisph.runner import simulate
except ImportError:
    from tisph.run.entry import simulate
scene = importlib.import_module("tisph.scenes." + sys.argv[1]).SCENE
ov = json.loads(sys.argv[2])
ov.update({"output.quiet": True, "output.render": False, "output.snapshot_every": 0.0})
try:   # each pair once as the scene's whole run would take it (run.pair_once = auto), where known
    import os
    from tisph.runner import Log, build_case, resolve
    case = build_case(scene, resolve(scene, overrides=dict(ov)), Log(os.devnull, True))
    ov["run.pair_once"] = "on" if case.params["pair_once"] else "off"
except (ImportError, KeyError):
    pass
ov.update({"run.max_steps": int(sys.argv[3]), "run.end_time": 1e6})
with tempfile.TemporaryDirectory() as d:
    s = simulate(scene, ov, out=d)
print(json.dumps(dict(particles=s["particles"], steps=s["steps"], seconds=s["step_time_s"],
                      pps=s["particle_steps_per_s"], compile=s["compile_time_s"], field_bytes=float("nan"),
                      arch=s.get("arch", "x64"))))
"""


def measure(tree, scene, overrides, steps, cache=None, arch="cpu", whole=False, threads=None):
    """One measurement in a fresh process on the tree at `tree`; cache: Taichi's offline cache
    folder (a new empty one for a cold compile); whole: the scene as the runner runs it."""
    env = dict(os.environ, PYTHONPATH=tree)
    if threads:
        env["TISPH_THREADS"] = str(threads)
    if "--config" in overrides:  # this tree's case file, whichever tree runs it
        overrides = dict(overrides, **{"--config": os.path.join(ROOT, overrides["--config"])})
    if cache:
        env["TI_OFFLINE_CACHE_FILE_PATH"] = cache
    r = subprocess.run(
        [sys.executable, "-c", CHILD_SCENE if whole else CHILD, scene, json.dumps(overrides), str(steps), arch],
        cwd=tree,
        capture_output=True,
        text=True,
        env=env,
        timeout=3600,
    )
    if r.returncode != 0:
        raise RuntimeError(f"{scene} {overrides} on {tree} failed: {r.stderr[-1500:]}")
    return json.loads(r.stdout.strip().splitlines()[-1])


def worktree(rev, base):
    """REV checked out (detached) under base; returns its path."""
    path = os.path.join(base, "rev")
    r = subprocess.run(["git", "-C", ROOT, "worktree", "add", "--detach", path, rev], capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(
            f"python -m tisph.bench --speed: --against {rev!r}: not a revision of {ROOT} ({r.stderr.strip()})"
        )
    return path


def remove_worktree(path):
    """Undo worktree(): the checkout and git's record of it."""
    subprocess.run(["git", "-C", ROOT, "worktree", "remove", "--force", path], capture_output=True)


def _measure_old(tree, rev, name, scene, ov, steps, log, arch, whole, threads):
    try:
        return measure(tree, scene, ov, steps, arch=arch, whole=whole, threads=threads)["pps"]
    except RuntimeError as e:  # a case newer than REV
        log(f"{name}: not measured on {rev}: {str(e).splitlines()[-1]}")
        return float("nan")


# --sizes: the scenes a GPU user scales up, each at the dx that gives about the particles asked
SIZED = ("dam_break", "flume")


def dx_for(scene_name, n):
    """The dx at which a scene's default case has about n particles (the count scales as dx^-2;
    two corrections from the particles built, nothing compiled)."""
    import importlib

    from ..runner import Log, build_case, resolve

    scene = importlib.import_module("tisph.scenes." + scene_name).SCENE
    dx = resolve(scene, overrides={"output.quiet": True}).numerics.dx
    for _ in range(2):
        cfg = resolve(scene, overrides={"output.quiet": True, "numerics.dx": dx})
        have = len(build_case(scene, cfg, Log(os.devnull, True)).particles)
        dx *= math.sqrt(have / n)
    return float(f"{dx:.4g}")


def sized_cases(a):
    """--sizes: the dam break and the flume at each size, steps from about 3e8 particle-steps
    (at least 50, at most 1000; --quick: 10)."""
    out = []
    for scene in SIZED:
        for n in a.sizes:
            steps = 10 if a.quick else int(max(50, min(1000, 3e8 / n)))
            out.append((f"{scene.replace('_', ' ')} {n:.0e}", scene, {"numerics.dx": dx_for(scene, n)}, steps, False))
    return out


def cases_for(a):
    """(name, scene, overrides, steps, whole) of the run a asks for."""
    arch = getattr(a, "arch", "cpu") or "cpu"
    if getattr(a, "sizes", None):
        return sized_cases(a)
    if arch == "gpu":  # --quick: the smallest tank, a few steps (the fallback's test)
        return [GPU_CASES[0][:3] + (20, False)] if a.quick else [c + (False,) for c in GPU_CASES]
    if a.quick:
        return [c + (False,) for c in CASES[:QUICK]]
    out = [c + (False,) for c in CASES] + [c + (True,) for c in SCENES]
    only = getattr(a, "only", None)
    return [c for c in out if any(w.lower() in c[0].lower() for w in only)] if only else out


def run(a, log):
    arch = getattr(a, "arch", "cpu") or "cpu"
    threads = getattr(a, "threads", None)  # Taichi's CPU threads in every run (None: all cores)
    cases = cases_for(a)
    rows = []
    with tempfile.TemporaryDirectory() as tmp:
        old = worktree(a.against, tmp) if a.against else None
        try:
            # compile, cold (an empty offline cache) then warm (the same cache again)
            cache = os.path.join(tmp, "cache")
            cold = measure(ROOT, *CASES[0][1:3], 5, cache, arch=arch)
            warm = measure(ROOT, *CASES[0][1:3], 5, cache, arch=arch)["compile"]
            if arch == "gpu" and cold.get("arch") in ("x64", "arm64"):
                log(
                    "warning: --arch gpu: Taichi found no GPU (CUDA, Vulkan or Metal) here; the cases run on the "
                    "CPU, and the table says so"
                )
            used = cold.get("arch", "x64")
            cold = cold["compile"]
            for name, scene, ov, steps, whole in cases:
                new_pps, old_pps = [], []
                for k in range(a.repeats):
                    # every other pair REV first: the one run second measured 8-10 % faster on
                    # these VMs whichever tree it was (cases the change could not touch, 3 pairs)
                    if old and k % 2:
                        old_pps.append(_measure_old(old, a.against, name, scene, ov, steps, log, arch, whole, threads))
                    m = measure(ROOT, scene, ov, steps, arch=arch, whole=whole, threads=threads)
                    new_pps.append(m["pps"])
                    if old and not k % 2:
                        old_pps.append(_measure_old(old, a.against, name, scene, ov, steps, log, arch, whole, threads))
                    log(
                        f"{name}: {m['particles']} particles, {new_pps[-1]:.3g} particle-steps/s"
                        + (f", {a.against}: {old_pps[-1]:.3g}" if old else "")
                    )
                row = dict(
                    case=name,
                    particles=m["particles"],
                    steps=m.get("steps", steps),
                    pps=statistics.median(new_pps),
                    field_bytes=round(m["field_bytes"], 1),
                    arch=used,
                )
                if old:
                    row["pps_against"] = statistics.median(old_pps)
                    row["ratio"] = (
                        float("nan")
                        if any(math.isnan(o) for o in old_pps)
                        else statistics.median(n / o for n, o in zip(new_pps, old_pps))
                    )
                rows.append(row)
        finally:
            if old:
                remove_worktree(old)
    return rows, cold, warm


def report(a, rows, cold, warm):
    hdr = "| case | particles | steps | particle-steps/s | field bytes/particle |"
    sep = "|---|---|---|---|---|"
    if a.against:
        hdr += f" {a.against} particle-steps/s | ratio (median of {a.repeats} pairs) |"
        sep += "---|---|"
    lines = [
        "# tisph engine speed",
        "",
        f"{time.strftime('%Y-%m-%d %H:%M')}, Taichi arch {rows[0]['arch']}, f32, "
        f"{getattr(a, 'threads', None) or os.cpu_count()} threads; "
        "each figure the "
        f"median of {a.repeats} runs, each in a fresh process"
        + (f", alternating with {a.against} back to back" if a.against else "")
        + ".",
        "",
        hdr,
        sep,
    ]
    for r in rows:
        line = f"| {r['case']} | {r['particles']} | {r['steps']} | {r['pps']:.3g} | {r['field_bytes']} |"
        if a.against:
            line += f" {r['pps_against']:.3g} | {r['ratio']:.2f} |"
        lines.append(line)
    lines += [
        "",
        f"Compile (dam break dx 0.03, set-up excluded): cold {cold:.2f} s (empty offline cache), "
        f"warm {warm:.2f} s (Taichi's offline kernel cache).",
        "",
    ]
    return lines


def main(a):
    log = lambda m: print(m, file=sys.stderr, flush=True)
    ensure_dir(a.out)
    if getattr(a, "peer_ladder", False):
        return peer_ladder(a, log)
    rows, cold, warm = run(a, log)
    lines = report(a, rows, cold, warm)
    if getattr(a, "peer", ()):
        lines += peers("dambreak_codes").compare(
            a.out, log, a.peer, getattr(a, "peer_venv", None), getattr(a, "dualsphysics", None)
        )
    write_text(os.path.join(a.out, "speed.md"), "\n".join(lines) + "\n")
    write_csv(os.path.join(a.out, "speed.csv"), tuple(rows[0]), [tuple(r.values()) for r in rows])
    print("\n".join(lines))
    return 0


def peer_ladder(a, log):
    """--peer-ladder: the three codes' dam breaks over five spacings only (OUT/dambreak_codes.md)."""
    codes = peers("dambreak_codes")
    lines = [f"# tisph and its peers on the dam break, {time.strftime('%Y-%m-%d %H:%M')}", ""]
    lines += codes.compare(a.out, log, a.peer or PEERS, a.peer_venv, a.dualsphysics, codes.LADDER)
    write_text(os.path.join(a.out, "dambreak_codes.md"), "\n".join(lines) + "\n")
    print("\n".join(lines))
    return 0
