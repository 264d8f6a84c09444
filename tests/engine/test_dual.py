"""Dual time stepping (tisph/physics/dual.py): the viscous and diffusive terms at the advection
criterion, held over the acoustic steps between their evaluations."""

import os

import numpy as np
import pytest

from tisph import runtime
from tisph.engine.solver import Solver
from tisph.runner import Log, build_case, resolve
from tisph.scenes import dam_break, tank


def _solver(scene, ov, **params):
    runtime.init("cpu", "f32")
    cfg = resolve(scene, overrides=dict(ov, **{"output.quiet": True}))
    case = build_case(scene, cfg, Log(os.devnull, True))
    return Solver(case.physics, case.particles, case.materials, case.domain, dict(case.params, **params))


def _schedule(s, steps):
    """Whether each step evaluated the advection terms (the flag the step read), after the zero-length
    step at t = 0 that gives the first forces (it evaluates them)."""
    if not s._primed:
        s.prime()
    out = []
    for _ in range(steps):
        out.append(s.prm[None].full > 0.5)
        s.step()
    return out


def test_one_acoustic_step_a_time_is_the_single_step_to_rounding():
    # the dam break: walls, the impact guard, the sheets' alpha and the renormalised diffusion
    ov = {"numerics.dx": 0.06}
    single = _solver(dam_break, dict(ov, **{"numerics.time_stepping": "single"}))
    dual = _solver(dam_break, dict(ov, **{"numerics.time_stepping": "dual"}), acoustic_steps=1.0)
    assert single.dual is None and dual.dual is not None
    assert all(_schedule(dual, 150))
    for _ in range(150):
        single.step()
    a, b = single.state(("x", "v", "rho")), dual.state(("x", "v", "rho"))
    assert not np.array_equal(a["v"], b["v"])  # the two sums added apart, then together
    assert np.abs(a["x"] - b["x"]).max() < 1e-5
    assert np.abs(a["v"] - b["v"]).max() < 1e-3
    assert np.abs(a["rho"] / b["rho"] - 1.0).max() < 1e-5


def test_still_water_evaluates_every_third_step_a_fast_flow_or_a_viscous_one_sooner():
    s = _solver(tank, {"numerics.dx": 0.04})
    assert s.dual is not None and s.param_values["acoustic_steps"] == 3.0  # the default scheme's
    assert _schedule(s, 12) == [False, False, True] * 4  # held twice after the first forces, then again
    # the advection criterion: the fastest particle may move advection_cfl h between evaluations
    fast = _solver(tank, {"numerics.dx": 0.04}, advection_cfl=1e-6)
    fast.step_ahead(20)
    assert all(_schedule(fast, 10))
    # a Bingham sand's effective viscosity sets a step near its explicit limit: held for two
    # steps its viscous term would pass that limit, so every step evaluates it
    sand = _solver(tank, {"numerics.dx": 0.04, "geometry.sediment_depth": 0.2})
    assert all(_schedule(sand, 20)[1:])


def test_held_terms_keep_the_tank_at_rest_and_its_pressure():
    # 2 s of still water: the held diffusion and viscosity neither drive nor leak it
    runs = {}
    for ts in ("single", "dual"):
        s = _solver(tank, {"numerics.dx": 0.04, "numerics.time_stepping": ts})
        while s.time < 1.0:
            s.step_ahead(32)
        st = s.state(("v", "rho", "kind"))
        f = st["kind"] == 0
        runs[ts] = (np.abs(st["v"][f]).max(), st["rho"][f].mean())
    assert runs["dual"][0] < 1.5 * runs["single"][0] + 1e-3
    assert runs["dual"][1] == pytest.approx(runs["single"][1], rel=2e-4)


def _pipe(ts, **params):
    from tisph.scenes import pipeline_scour

    ov = {
        "numerics.dx": 0.0125,
        "sediment.morph_start": 0.0,
        "numerics.turbulence": "k_equation",
        "numerics.time_stepping": ts,
    }
    return _solver(pipeline_scour, ov, **params)


def test_the_turbulence_is_held_with_the_viscosity_and_steps_k_every_step():
    # the velocity gradient, the k equation and the SPS stress change at the flow's pace: held
    single, one = _pipe("single"), _pipe("dual", acoustic_steps=1.0)
    held = [m.name for m in one.slow["pair"]]
    assert {"velocity_gradient", "tke", "sps", "laminar_viscosity"} <= set(held)
    assert [m.name for m in one.slow["hold"]] == ["tke", "sps"]
    assert single.dual is None and all(_schedule(one, 60))
    for _ in range(60):
        single.step()
    a, b = single.state(("v", "kt")), one.state(("v", "kt"))
    assert np.abs(a["v"] - b["v"]).max() < 1e-4
    assert np.abs(a["kt"] - b["kt"]).max() < 1e-6 + 1e-4 * np.abs(a["kt"]).max()
    # three acoustic steps to an evaluation: k steps on between with the held production and
    # diffusion (not frozen, not made without them), and lands near every term every step
    three = _pipe("dual")
    _schedule(three, 0)
    k0 = three.state(("kt",))["kt"].copy()
    sched = _schedule(three, 2)
    assert sched == [False, False]
    k2 = three.state(("kt",))["kt"]
    assert not np.array_equal(k0, k2)
    for _ in range(58):
        three.step()
    c = three.state(("kt", "kind"))
    f = c["kind"] == 0
    assert abs(c["kt"][f].mean() / a["kt"][f].mean() - 1.0) < 0.05


def test_a_rheology_keeps_the_gradient_every_step():
    # a Bingham sand's viscosity reads the gradient each step (it bounds the step): not held
    s = _solver(tank, {"numerics.dx": 0.04, "geometry.sediment_depth": 0.2})
    assert s.dual is not None
    assert "velocity_gradient" not in [m.name for m in s.slow["pair"]]
