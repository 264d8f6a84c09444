"""Suspended sand (tisph/physics/suspension.py): it settles at w_s, diffuses at its diffusivity,
is conserved by both; the formulae it is exchanged with the bed by; the pipeline with it keeps its
sand between the bed and the water."""

import dataclasses
import json

import numpy as np
import pytest

from tisph.engine.solver import Solver
from tisph.particles import FLUID
from tisph.runner import Log, build_case, resolve, run_scene
from tisph.scenes import pipeline_scour, tank
from tisph.sediment.transport import reference_concentration, settling_velocity, shields_critical


def test_settling_velocity_and_reference_concentration():
    # Soulsby (1997) for quartz in water at 20 C: about 2.6 cm/s at 0.2 mm, 5.4 cm/s at 0.36 mm
    assert settling_velocity(0.0002, 2.65) == pytest.approx(0.0262, rel=0.01)
    assert settling_velocity(0.00036, 2.65) == pytest.approx(0.0544, rel=0.01)
    # van Rijn (1984): zero at the threshold, 0.015 (d50 / a) T^1.5 / D*^0.3 above it
    tc = shields_critical(0.00036, 2.65)
    assert reference_concentration(tc, tc, 0.00036, 2.65, 0.0025) == 0.0
    D = 0.00036 * (1.65 * 9.81 / 1e-12) ** (1 / 3)
    want = 0.015 * 0.00036 / 0.0025 * 8.0**1.5 / D**0.3
    assert reference_concentration(9 * tc, tc, 0.00036, 2.65, 0.0025) == pytest.approx(want, rel=1e-9)
    assert reference_concentration(1e6 * tc, tc, 0.00036, 2.65, 0.0025) == 0.6  # the bed's own


def still_column(tmp_path):
    """A still water column 0.3 m deep in a tank, with the suspension compiled in."""
    # the cubic set at h = 1.3 dx with alpha 0.1 (tests/engine/test_hydrostatic.py): still water to 0.1 %
    cfg = resolve(
        tank,
        overrides={
            "numerics.dx": 0.01,
            "geometry.width": 0.2,
            "geometry.depth": 0.3,
            "geometry.tank_height": 0.35,
            "numerics.scheme": "paper000",
            "numerics.h_factor": 1.3,
            "numerics.artificial_viscosity": 0.1,
            "numerics.xsph": 0.0,
        },
    )
    case = build_case(tank, cfg, Log(str(tmp_path / "log"), True))
    physics = dataclasses.replace(case.physics, suspension=True)
    s = Solver(physics, case.particles, case.materials, case.domain, case.params)
    fl = case.particles.kind == FLUID
    return s, case.particles.x, fl


def moments(s):
    st = s.state(("x", "c", "kind"))
    f = st["kind"] == FLUID
    c, y = st["c"][f].astype(float), st["x"][f, 1].astype(float)
    total = c.sum()
    mean = (c * y).sum() / total
    return total, mean, (c * (y - mean) ** 2).sum() / total


@pytest.mark.slow
def test_sand_settles_at_w_s_and_diffuses_at_eps(tmp_path):
    s, x, fl = still_column(tmp_path)
    band = fl & (x[:, 1] > 0.12) & (x[:, 1] < 0.2)  # well clear of the floor and the surface
    n = s.n
    # settling alone: the band's centroid falls at w_s, the sand is conserved
    s.p.c.from_numpy(np.where(band[s.p.id.to_numpy()], 0.01, 0.0).astype(s.np_real))  # fields in sorted order
    s.prm[None].w_s = 0.02
    s.prime()
    tot0, y0, var0 = moments(s)
    t0 = s.time
    while s.time - t0 < 0.5:
        s.step()
    tot1, y1, var1 = moments(s)
    assert tot1 == pytest.approx(tot0, rel=1e-5)
    speed = (y0 - y1) / (s.time - t0)
    assert speed == pytest.approx(0.02, rel=0.05), speed
    # diffusion alone: the band's variance grows at 2 eps, the sand is conserved
    ids = s.p.id.to_numpy()
    s.p.c.from_numpy(np.where(band[ids], 0.01, 0.0).astype(s.np_real))
    s.p.eps.from_numpy(np.where(s.p.kind.to_numpy() == FLUID, 1e-4, 0.0).astype(s.np_real))
    s.prm[None].w_s = 0.0
    s.prm[None].eps_max = 1e-4
    tot0, y0, var0 = moments(s)
    t0 = s.time
    while s.time - t0 < 0.5:
        s.step()
    tot1, y1, var1 = moments(s)
    assert n == s.n and tot1 == pytest.approx(tot0, rel=1e-5)
    rate = (var1 - var0) / (s.time - t0)
    assert rate == pytest.approx(2e-4, rel=0.1), rate
    assert abs(y1 - y0) < 0.002  # no drift without settling


@pytest.mark.slow
def test_pipeline_with_suspended_load_keeps_its_sand(tmp_path):
    """The bed-load pipeline with suspended load a few hundred steps: the gap flow picks sand up,
    the sand in the bed and in the water together is conserved."""
    out = tmp_path / "susp"
    cfg = tmp_path / "susp.toml"
    cfg.write_text("[sediment]\nsuspended = true\nmorph_start = 0.0\n")
    code = run_scene(
        pipeline_scour,
        ["--config", str(cfg), "--dx", "0.0125", "--end-time", "0.3", "--out", str(out), "--quiet", "--no-render"],
    )
    assert code == 0
    s = json.load(open(out / "summary.json"))
    assert s["status"] == "ok" and s["physics"]["suspension"]
    m = s["metrics"]
    assert m["suspended_sand"] > 0
    assert m["sand_volume_error"] < 1e-6  # the water started with its equilibrium load: counted too
    assert m["scour_depth_over_D"] > m["initial_scour_depth_over_D"] + 1e-4, m


def test_concentration_panel_and_snapshot_field():
    """Frames colour water by its suspended sand (output.field = "concentration"); snapshots carry
    it as "concentration" and tisph.view reads it back."""
    from tisph import view
    from tisph.io import SNAPSHOT_FIELDS
    from tisph.viz.render import Renderer
    from tisph.viz.style import Style

    g = (np.arange(40) + 0.5) * 0.025
    x = np.array([(a, b) for a in g for b in g[:20]])
    n = len(x)
    st = dict(
        x=x,
        v=np.zeros((n, 2)),
        p=np.zeros(n),
        rho=np.full(n, 1000.0),
        kind=np.full(n, FLUID),
        mat=np.zeros(n, int),
        c=np.where(x[:, 0] > 0.5, 0.002, 0.0),
    )
    r = Renderer(((0.0, 0.0), (1.0, 0.5)), Style(width=320, dx=0.025, modes=("concentration",)))
    img = r.frame(st, 0.0).astype(int)
    unit, lo, hi, _ = r.bars[0]
    assert unit == "sand (%, log)" and hi == pytest.approx(0.2) and lo == pytest.approx(2e-4)  # three decades
    mid = r.strip + img.shape[0] // 4  # a row inside the particles
    left, right = img[mid, r.left + 40], img[mid, r.left + 280]
    assert np.abs(left - right).sum() > 100  # clear water and loaded water differ
    arrays = {SNAPSHOT_FIELDS[k][0]: st[k] for k in ("x", "v", "p", "rho", "kind", "mat", "c")}
    assert np.array_equal(view.state_of(arrays)["c"], st["c"])
    del arrays["concentration"]
    assert "c" not in view.state_of(arrays)


def test_layer_sums_by_blocks_on_a_gpu_equal_the_serial_pass(tmp_path, monkeypatch):
    """A GPU sums the near-bed layer by blocks of particles, each into its own row of stations,
    then each station over the rows (one thread over every particle would take it milliseconds):
    the same sums as the CPU's serial pass, to rounding."""
    from tisph.engine import grid, state

    def sums():
        cfg = resolve(tank, overrides={"numerics.dx": 0.01, "geometry.width": 0.2, "geometry.depth": 0.3})
        case = build_case(tank, cfg, Log(str(tmp_path / "log"), True))
        physics = dataclasses.replace(case.physics, suspension=True)
        s = Solver(physics, case.particles, case.materials, case.domain, dict(case.params, bed_stations=20))
        ids = s.p.id.to_numpy()
        s.p.c.from_numpy((1e-3 * (1.0 + np.sin(ids))).astype(s.np_real))
        m = s.module("suspension")
        out = np.zeros((m.nst + 1, 2))
        m._layer_sums(s, np.linspace(0.02, 0.08, m.nst), out)
        return s, m, out

    cpu, m_cpu, a = sums()
    monkeypatch.setattr(state, "on_cpu", lambda: False)
    monkeypatch.setattr(grid, "on_cpu", lambda: False)
    gpu, m_gpu, b = sums()
    assert not gpu.cpu and m_cpu.rows is None and m_gpu.rows.shape[0] >= 2  # blocks joined
    assert (a[:-1, 0] > 0).sum() >= 15 and a[-1, 1] > 0  # most stations' layers hold water
    assert np.allclose(a, b, rtol=1e-12, atol=0.0)
