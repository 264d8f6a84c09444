"""The GPU path run on a GPU backend: golden cases stepped 60 steps with `--arch gpu` (Vulkan; in CI
Mesa's software Vulkan, llvmpipe) end within a stated f32 tolerance of the CPU's states; a run
whose drive's feedback the device runs restarts bit for bit.

The set: the golden cases that together compile every module, and for each registered scene
without one of them, its cheapest golden case; so every scene builds and steps on the GPU, and
every module's GPU form (32-bit kind and material, per-particle atomic maxima, the gather pass
in place of each pair once, the serial loops as one GPU thread, the pipeline's drive feedback
on the device against the CPU's host control) runs there.

Why a tolerance and not bit for bit: the GPU's pow (SPIR-V's, exp2 of log2) rounds differently
from the CPU's in about a quarter of its results, and the extrapolated wall's density is
rho0 (p / B + 1)^(1/7); the impact guard then grows the difference about tenfold every 30 steps
in a dam break. The CPU adds the pair terms in its vector lanes' order (engine/grid.py), which
moves a wall particle whose few fluid neighbours barely reach it most (its extrapolated
pressure a ratio of small sums). The bounds below are 3-10x the largest differences measured on
llvmpipe after these 60 steps (docs/performance.md); a term missing on the GPU moves the state
by order one.

Where no GPU backend can be had the tests skip, saying so; TISPH_REQUIRE_GPU=1 (set by .ci/run,
which installs Mesa's Vulkan driver) makes that a failure."""

import json
import os
import subprocess
import sys

import numpy as np
import pytest

from tests.golden.cases import CASES, STATES

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))
GOLDEN = json.load(open(STATES))

# f32 tolerance of a GPU state against the CPU's (set from the differences after the 60 steps below): positions in units
# of the case's spacing, velocities of its largest speed (at least 0.01 m/s), densities relative
TOL = {"x_rms": 5e-3, "x_max": 0.1, "v_rms": 5e-3, "v_max": 0.1, "rho_rms": 5e-4, "rho_max": 1e-2}
GPU_ARCHES = ("vulkan", "cuda", "metal")


def gpu_set():
    """The covering golden cases, then each registered scene's cheapest case where none covers it."""
    from tests.engine.test_golden import QUICK
    from tisph import registry

    chosen = list(QUICK)
    scene_of = {c[0]: c[1] for c in CASES}
    for module in registry.REGISTRY.values():
        if not any(scene_of[c] == module for c in chosen):
            mine = [c[0] for c in CASES if c[1] == module]
            chosen.append(min(mine, key=lambda c: GOLDEN[c]["particles"]))
    return chosen


def halves():
    s = sorted(gpu_set(), key=lambda c: -GOLDEN[c]["particles"])
    return [s[0::2], s[1::2]]  # about equal work in each of the two test processes


def spacing(case_id):
    """The case's dx: its override, else the case file's or scene's (via resolve)."""
    _, modname, cfile, ov = next(c for c in CASES if c[0] == case_id)
    if "numerics.dx" in ov:
        return ov["numerics.dx"]
    import importlib

    from tisph.runner import resolve

    cfg = resolve(importlib.import_module(modname), os.path.join(ROOT, cfile) if cfile else None, {})
    return cfg["numerics"]["dx"]


# steps a case runs on each backend: half the golden 120 (compiling is most of the test's time;
# the differences grow with the steps)
STEPS = 60


def dump(arch, cases, folder):
    out = os.path.join(folder, f"{arch}.npz")
    cmd = [sys.executable, "-m", "tests.golden.dump", "--arch", arch, "--steps", str(STEPS), "--out", out, *cases]
    return subprocess.Popen(cmd, cwd=ROOT, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True), out


def differences(a, b, dx):
    """The measures TOL bounds, of state b against state a."""
    dxp = np.linalg.norm(a["x"] - b["x"], axis=1) / dx
    u = max(float(np.linalg.norm(a["v"], axis=1).max()), 0.01)
    dv = np.linalg.norm(a["v"] - b["v"], axis=1) / u
    dr = np.abs(a["rho"] - b["rho"]) / np.abs(a["rho"])
    rms = lambda d: float(np.sqrt(np.mean(d * d)))
    return {
        "x_rms": rms(dxp),
        "x_max": float(dxp.max()),
        "v_rms": rms(dv),
        "v_max": float(dv.max()),
        "rho_rms": rms(dr),
        "rho_max": float(dr.max()),
    }


@pytest.mark.parametrize("part", [0, 1])
def test_gpu_states_match_the_cpu(part, tmp_path):
    cases = halves()[part]
    gpu, gpu_out = dump("gpu", cases, tmp_path)
    cpu, cpu_out = dump("cpu", cases, tmp_path)
    gpu_log, cpu_log = gpu.communicate(timeout=900)[0], cpu.communicate(timeout=900)[0]
    assert cpu.returncode == 0, cpu_log[-3000:]
    assert gpu.returncode == 0, gpu_log[-3000:]
    meta = {a: json.load(open(os.path.splitext(p)[0] + ".json")) for a, p in (("gpu", gpu_out), ("cpu", cpu_out))}
    arch = {m["arch"] for m in meta["gpu"].values()}
    if not arch <= set(GPU_ARCHES):
        msg = f"no GPU backend here (--arch gpu ran on {sorted(arch)}): apt-get install mesa-vulkan-drivers"
        if os.environ.get("TISPH_REQUIRE_GPU") == "1":
            pytest.fail(msg)
        pytest.skip(msg)
    states = {a: np.load(p) for a, p in (("gpu", gpu_out), ("cpu", cpu_out))}
    bad = []
    for c in cases:
        g, k = meta["gpu"][c], meta["cpu"][c]
        assert g["status"] == "ok", (c, g)
        assert (g["steps"], g["particles"]) == (k["steps"], k["particles"]) == (STEPS, GOLDEN[c]["particles"])
        assert sorted(g["modules"]) == sorted(GOLDEN[c]["modules"]), c
        a, b = ({f: s[f"{c}/{f}"] for f in ("x", "v", "rho", "kind")} for s in (states["cpu"], states["gpu"]))
        assert np.array_equal(a["kind"], b["kind"]), f"{c}: a particle's kind differs (removed or leaked on one)"
        for f in ("x", "v", "rho"):
            assert np.all(np.isfinite(b[f])), f"{c}: non-finite {f} on the GPU"
        d = differences(a, b, spacing(c))
        over = {k: v for k, v in d.items() if v > TOL[k]}
        if over:
            bad.append(f"{c}: {', '.join(f'{k} {v:.2g} (bound {TOL[k]:g})' for k, v in over.items())}")
    assert not bad, "GPU states off the CPU's:\n  " + "\n  ".join(bad)


def test_the_gpu_set_covers_every_scene_and_module():
    from tisph import registry

    chosen = gpu_set()
    scenes = {c[1] for c in CASES if c[0] in chosen}
    assert scenes == set(registry.REGISTRY.values())
    every = {m for v in GOLDEN.values() for m in v["modules"]}
    assert every == {m for c in chosen for m in GOLDEN[c]["modules"]}


def test_a_gpu_run_with_its_drive_on_the_device_restarts_bit_for_bit(tmp_path):
    """The tunnel's particle bed on the GPU, its drive's feedback run by the device (engine/drive.py):
    stopped at a checkpoint and restarted, it writes the probes of the run that was not stopped,
    byte for byte (the controller's state saved with the checkpoint and loaded back)."""
    args = [
        sys.executable,
        "-m",
        "tisph.scenes.tunnel",
        "--config",
        os.path.join(ROOT, "scenes", "tunnel_bingham.toml"),
    ]
    args += ["--dx", "0.02", "--arch", "gpu", "--no-render", "--quiet"]
    whole, part = tmp_path / "whole", tmp_path / "part"
    for extra in (
        ["--end-time", "0.4", "--out", str(whole)],
        ["--end-time", "0.2", "--checkpoint-every", "0.2", "--out", str(part)],
        ["--end-time", "0.4", "--out", str(part), "--restart", str(part / "checkpoint.h5")],
    ):
        r = subprocess.run(args + extra, cwd=ROOT, capture_output=True, text=True, timeout=600)
        assert r.returncode == 0, (r.stdout + r.stderr)[-3000:]
    log = (part / "run.log").read_text()
    if not any(f"arch {a}" in log for a in GPU_ARCHES):
        msg = "no GPU backend here: apt-get install mesa-vulkan-drivers"
        if os.environ.get("TISPH_REQUIRE_GPU") == "1":
            pytest.fail(msg)
        pytest.skip(msg)
    assert "restarted from" in log
    assert (whole / "probes.csv").read_bytes() == (part / "probes.csv").read_bytes()
