"""Golden-state cases: every scene's default and every case file in scenes/, at coarse dx, for a
fixed number of steps. A refactor of the engine must reproduce each final state bit for bit.

`python -m tests.golden.cases --write` (from the repo root) records the hashes in states.json;
tests/engine/test_golden.py compares. Re-record only in a commit that says which case changed and why.
"""

import hashlib
import importlib
import json
import os
import sys
import tempfile

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
STATES = os.path.join(os.path.dirname(os.path.abspath(__file__)), "states.json")
STEPS = 120
FAST = {"output.render": False, "output.quiet": True, "output.snapshot_every": 0.0, "run.end_time": 100.0}

# (case id, scene module, case file or None, overrides)
CASES = [
    ("dam_break", "tisph.scenes.dam_break", None, {"numerics.dx": 0.06}),
    (
        "dam_break_repulsive",
        "tisph.scenes.dam_break",
        "scenes/dam_break.toml",
        {"numerics.dx": 0.06, "numerics.wall": "repulsive", "numerics.xsph": 0.5},
    ),
    ("dam_break_shifting", "tisph.scenes.dam_break", None, {"numerics.dx": 0.06, "numerics.shifting": 2.0}),
    ("dam_break_alpha0", "tisph.scenes.dam_break", "scenes/dam_break_alpha0.toml", {"numerics.dx": 0.025}),
    ("dam_break_alpha01", "tisph.scenes.dam_break", "scenes/dam_break_alpha01.toml", {"numerics.dx": 0.0125}),
    ("dam_break_alpha04", "tisph.scenes.dam_break", "scenes/dam_break_alpha04.toml", {"numerics.dx": 0.025}),
    ("hatch", "tisph.scenes.hatch", "scenes/hatch.toml", {"numerics.dx": 0.0085}),
    ("orifice", "tisph.scenes.hatch", "scenes/orifice.toml", {"numerics.dx": 0.01}),
    ("tank", "tisph.scenes.tank", None, {"numerics.dx": 0.04}),
    ("tank_sediment", "tisph.scenes.tank", None, {"numerics.dx": 0.04, "geometry.sediment_depth": 0.2}),
    (
        "flume",
        "tisph.scenes.flume",
        "scenes/flume_piston.toml",
        {
            "numerics.dx": 0.025,
            "geometry.length": 2.0,
            "geometry.damping_length": 0.6,
            "geometry.gauges_wavelengths": [0.5, 1.0],
        },
    ),
    (
        "flume_flap",
        "tisph.scenes.flume",
        None,
        {
            "numerics.dx": 0.025,
            "geometry.length": 2.0,
            "geometry.damping_length": 0.6,
            "geometry.gauges_wavelengths": [0.5, 1.0],
            "paddle.type": "flap",
        },
    ),
    ("beach", "tisph.scenes.beach", "scenes/beach_bingham_tau200.toml", {}),
    (
        "flume_second_order",
        "tisph.scenes.flume",
        "scenes/flume_second_order.toml",
        {
            "numerics.dx": 0.025,
            "geometry.length": 3.0,
            "geometry.damping_length": 1.0,
            "geometry.gauges_wavelengths": [0.5],
            "geometry.array_gauges": 0,
        },
    ),
    (
        "flume_jonswap",
        "tisph.scenes.flume",
        "scenes/flume_jonswap.toml",
        {"numerics.dx": 0.015, "geometry.length": 3.5, "geometry.damping_length": 1.0},
    ),
    ("beach_tau1000", "tisph.scenes.beach", "scenes/beach_bingham_tau1000.toml", {}),
    ("beach_bedload", "tisph.scenes.beach", None, {"numerics.dx": 0.03}),
    ("tunnel", "tisph.scenes.tunnel", "scenes/tunnel_bingham.toml", {"numerics.dx": 0.02}),
    ("tunnel_bedload", "tisph.scenes.tunnel", "scenes/tunnel.toml", {"numerics.dx": 0.02}),
    ("erodible_bed", "tisph.scenes.erodible_bed", None, {"numerics.dx": 0.02}),
    ("erodible_bed_deep", "tisph.scenes.erodible_bed", "scenes/erodible_bed_deep.toml", {"numerics.dx": 0.025}),
    # the two-phase model, now a case file (its state bit-identical to the scene's former default)
    ("pipeline_scour", "tisph.scenes.pipeline_scour", "scenes/pipeline_scour_two_phase.toml", {}),
    (
        "pipeline_scour_theta098",
        "tisph.scenes.pipeline_scour",
        "scenes/pipeline_scour_theta098.toml",
        {"sediment.model": "particles"},
    ),
    ("pipeline_bedload", "tisph.scenes.pipeline_scour", None, {"numerics.dx": 0.0125, "sediment.morph_start": 0.0}),
    (
        "pipeline_suspended",
        "tisph.scenes.pipeline_scour",
        None,
        {"numerics.dx": 0.0125, "sediment.morph_start": 0.0, "sediment.suspended": True},
    ),
    (
        "pipeline_k_equation",
        "tisph.scenes.pipeline_scour",
        None,
        {"numerics.dx": 0.0125, "sediment.morph_start": 0.0, "numerics.turbulence": "k_equation"},
    ),
    (
        "pipeline_k_omega",
        "tisph.scenes.pipeline_scour",
        None,
        {
            "numerics.dx": 0.0125,
            "sediment.morph_start": 0.0,
            "numerics.turbulence": "k_equation",
            "numerics.length_scale": "omega",
            "numerics.stress_limiter": 0.875,
            "sediment.shear": "wall_function",
        },
    ),
    ("pipe_on_rigid_bed", "tisph.scenes.pipeline_scour", "scenes/pipe_on_rigid_bed.toml", {}),
    ("poiseuille_bingham", "tisph.validation.poiseuille", None, {"numerics.dx": 0.005}),
    ("dam_break_custom", "tisph.scenes.custom", "scenes/dam_break_custom.toml", {"numerics.dx": 0.06}),
    ("breakwater", "tisph.scenes.custom", "scenes/breakwater.toml", {"numerics.dx": 0.03}),
    ("seawall", "tisph.scenes.custom", "scenes/seawall.toml", {"numerics.dx": 0.03}),
    ("surveyed_beach", "tisph.scenes.custom", "scenes/surveyed_beach.toml", {"numerics.dx": 0.03}),
]


def run(case_id, steps=STEPS, arch="cpu", arrays=False):
    """Final state digest of one case: a hash of x, v, rho (by particle id) and of probes.csv.
    arch: the Taichi backend ("gpu": Vulkan, CUDA or Metal; tests/engine/test_vulkan.py); arrays:
    also return the final x, v, rho and kind by particle id under "arrays", the arch under "arch"."""
    import numpy as np

    from tisph import runtime
    from tisph.runner import Log, Run, build_case, resolve

    _, modname, cfile, ov = next(c for c in CASES if c[0] == case_id)
    scene = importlib.import_module(modname).SCENE
    overrides = dict(FAST, **ov)
    overrides["run.max_steps"] = steps
    # the gather pass, as the records were made: each pair once (run.pair_once) is held to it to
    # rounding by tests/engine/test_pair_once.py, and a 120-step case would pay its longer compile
    overrides["run.pair_once"] = "off"
    with tempfile.TemporaryDirectory() as out:
        overrides["output.dir"] = out
        cfg = resolve(scene, os.path.join(ROOT, cfile) if cfile else None, overrides)
        used = runtime.init(arch, cfg["run"]["precision"])
        log = Log(os.path.join(out, "run.log"), True)
        case = build_case(scene, cfg, log)
        r = Run(case, cfg, out, log, scene.NAME)
        r.arch = runtime.current_arch()
        summary = r.execute()
        st = r.solver.state(("x", "v", "rho", "kind"))
        with open(os.path.join(out, "probes.csv"), "rb") as f:
            probes = f.read()
    h = hashlib.sha256()
    for k in ("x", "v", "rho"):
        h.update(np.ascontiguousarray(st[k]).tobytes())
    out = dict(
        state=h.hexdigest()[:20],
        probes=hashlib.sha256(probes).hexdigest()[:20],
        steps=int(summary["steps"]),
        particles=int(summary["particles"]),
        modules=summary.get("modules", []),
        x_sum=float(np.sum(st["x"], dtype=np.float64)),
        status=summary["status"],
        fields={k: fingerprint(st[k]) for k in ("x", "v", "rho")},
        probe_columns=probe_fingerprint(probes),
    )
    if arrays:
        out["arrays"], out["arch"] = st, used
    return out


def fingerprint(a):
    """Mean, RMS, min and max of a field (every component together), in float64: beside the
    hash, they say how far a field moved when the hash changes."""
    import numpy as np

    a = np.asarray(a, np.float64)
    return [float(a.mean()), float(np.sqrt(np.mean(a * a))), float(a.min()), float(a.max())]


def probe_fingerprint(text):
    """{column: fingerprint} of probes.csv's numeric columns."""
    import csv
    import io

    import numpy as np

    rows = list(csv.reader(io.StringIO(text.decode())))
    out = {}
    for k, name in enumerate(rows[0]):
        try:
            col = np.array([float(r[k]) for r in rows[1:]])
        except ValueError:
            continue
        col = col[np.isfinite(col)]
        if len(col):
            out[name] = fingerprint(col)
    return out


def moved(want, got):
    """Lines naming each field and probe column whose mean, RMS, min or max moved, with the
    largest relative change: round-off moves them by 1e-7 or less in f32, a broken term by far more."""

    def rel(a, b):
        scale = max(abs(a), abs(b), 1e-30)
        return abs(a - b) / scale

    lines = []
    for group, label in (("fields", "field"), ("probe_columns", "probe")):
        w, g = want.get(group, {}), got.get(group, {})
        for k in sorted(set(w) | set(g)):
            if k not in w or k not in g:
                lines.append(f"{label} {k}: {'new' if k not in w else 'gone'}")
                continue
            r = max(rel(a, b) for a, b in zip(w[k], g[k]))
            if r > 0:
                lines.append(f"{label} {k}: largest relative change of its mean, RMS, min or max {r:.2g}")
    return lines or ["(no field statistic moved: the change is below their resolution)"]


def main(argv):
    ids = [a for a in argv if not a.startswith("--")] or [c[0] for c in CASES]
    old = json.load(open(STATES)) if os.path.exists(STATES) else {}
    new = dict(old)
    bad = 0
    for cid in ids:
        d = run(cid)
        same = old.get(cid, {}).get("state") == d["state"] and old.get(cid, {}).get("probes") == d["probes"]
        bad += not same
        print(
            f"{cid:26s} {d['particles']:6d} particles {d['steps']:4d} steps  state {d['state']} "
            f"probes {d['probes']}  {'same' if same else 'DIFFERENT'}",
            flush=True,
        )
        new[cid] = d
    if "--write" in argv:
        with open(STATES, "w") as f:
            json.dump(new, f, indent=1, sort_keys=True)
            f.write("\n")
    return 1 if bad and "--write" not in argv else 0


if __name__ == "__main__":
    sys.path.insert(0, ROOT)
    sys.exit(main(sys.argv[1:]))
