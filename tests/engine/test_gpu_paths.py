"""The engine's GPU paths, run on the CPU: with the CPU-only choices turned off (byte-sized
flags, block maxima without atomics, serialised light loops, each pair once, the vector lanes)
a step gives the CPU's gather pass's state to rounding (and each pair once gives it to rounding,
tests/engine/test_pair_once.py), so a GPU build differs from the CPU build only in rounding.
Rounding, not bits: under fast math (runtime.py) LLVM orders a sum by the shape of the code
around it, and the two builds' code differs."""

import os

import numpy as np

from tisph import runtime
from tisph import runtime as rt
from tisph.engine import grid, state
from tisph.engine.solver import Solver
from tisph.particles import FLUID
from tisph.runner import Log, build_case, resolve
from tisph.scenes import dam_break


def _run(steps, **params):
    cfg = resolve(dam_break, overrides={"numerics.dx": 0.04, "output.quiet": True})
    case = build_case(dam_break, cfg, Log(os.devnull, True))
    s = Solver(case.physics, case.particles, case.materials, case.domain, dict(case.params, **params))
    for _ in range(steps):
        s.step()
    return s, s.state(("x", "v", "rho", "kind"))


def test_gpu_layout_and_atomic_maxima_give_the_cpu_state(monkeypatch):
    runtime.init("cpu", "f32")
    cpu, a = _run(60, pair_once=False, lanes=False)  # a GPU's threads are its lanes: the branch form
    assert cpu.cpu and cpu.stepper.nblk >= min(cpu.n, 1024)  # 1,024 blocks or more: every thread takes a share
    monkeypatch.setattr(state, "on_cpu", lambda: False)
    monkeypatch.setattr(grid, "on_cpu", lambda: False)
    gpu, b = _run(60)
    assert not gpu.cpu and gpu.stepper.blk == 1 and gpu.pair_once is None and gpu.grid.fdtype != cpu.grid.fdtype
    assert gpu.p.kind.dtype != cpu.p.kind.dtype
    assert gpu.steps == cpu.steps and not gpu.lanes
    # 3-10x the differences measured after 60 steps (time 1.6e-5, positions 1.3e-3 dx, densities
    # 3.9e-3 kg/m3, velocities 4.8e-3 of the top speed); a term missing moves them by order one
    assert abs(gpu.time - cpu.time) < 1e-4 * cpu.time
    assert np.abs(a["x"] - b["x"]).max() < 1e-2 * 0.04
    assert np.abs(a["rho"] - b["rho"]).max() < 2e-2
    assert np.abs(a["v"] - b["v"]).max() < 2e-2 * np.abs(a["v"]).max()
    assert np.array_equal(a["kind"].astype(int), b["kind"].astype(int))


def test_gpu_prefix_sum_and_mean_velocity_go_by_blocks_and_agree_with_the_cpus(monkeypatch):
    """A GPU sums the cells' counts in three passes over blocks of cells, and the drive's mean
    velocity over blocks of particles (one GPU thread over every cell or particle would take it
    milliseconds): the cells' starts are the same integers as the CPU's serial pass, and the mean
    agrees with NumPy's to rounding."""
    runtime.init("cpu", "f32")
    cpu, _ = _run(20, pair_once=False)
    monkeypatch.setattr(state, "on_cpu", lambda: False)
    monkeypatch.setattr(grid, "on_cpu", lambda: False)
    gpu, _ = _run(20)
    assert gpu.grid.nscan > 4 and gpu.usum.shape[0] > 4  # several blocks each, so the passes join blocks
    assert cpu.grid.bsum is None and cpu.usum is None
    assert np.array_equal(cpu.grid.start.to_numpy(), gpu.grid.start.to_numpy())
    for s in (cpu, gpu):
        st = s.state(("x", "v", "kind"))
        fluid = (st["kind"] == FLUID) & (st["x"][:, 1] > 0.3)
        want = np.mean(st["v"][fluid, 0].astype(np.float64))
        assert abs(s.mean_velocity(0, 0.3) - want) <= 1e-12 * np.abs(st["v"][:, 0]).max()
    assert rt.blocks(1_387_729) == (1179, 1178) and rt.blocks(10) == (256, 1)
