"""Bingham and Cross effective viscosity, Poiseuille flow against the exact solution, and a
sediment layer under water that stays put."""

import math

import numpy as np
import pytest
import taichi as ti

from tisph.runner import simulate
from tisph.scenes import tank
from tisph.terms.rheology import bingham, bingham_np, cross, cross_np
from tisph.validation import poiseuille


def test_bingham_formula_and_regularised_limit():
    mu_b, tau, m, cap = 0.1, 200.0, 100.0, 1e9
    g = np.array([1e-9, 1e-6, 1e-3, 0.1, 1.0, 10.0, 1e3])
    mu = bingham_np(mu_b, tau, m, cap, g)
    # Papanastasiou: finite at rest, mu_B + tau m
    assert mu[0] == pytest.approx(mu_b + tau * m, rel=1e-6)
    # at high shear rate it is paper 000 eq. 13, mu_B + tau / gamma_dot
    assert mu[-1] == pytest.approx(mu_b + tau / 1e3, rel=1e-9)
    assert mu[4] == pytest.approx(mu_b + tau * (1 - math.exp(-100.0)) / 1.0, rel=1e-12)
    assert np.all(np.diff(mu) <= 0) and np.all(np.diff(mu[1:]) < 0)  # shear thinning throughout
    assert bingham_np(mu_b, tau, m, 50.0, 1e-6) == 50.0  # the cap


def test_cross_limits():
    # the paper-002 reading: mu_inf = mu_B = 0.07, mu0 = 1000 mu_B, K = mu0 / tau_B, m1 = 1
    mu_inf, tau = 0.07, 25.0
    mu0 = 1000 * mu_inf
    K = mu0 / tau
    assert cross_np(mu0, mu_inf, K, 1.0, 1e9, 0.0) == pytest.approx(mu0)
    assert cross_np(mu0, mu_inf, K, 1.0, 1e9, 1e9) == pytest.approx(mu_inf, rel=1e-6)
    # for K gamma_dot >> 1 it is Bingham with tau_B = mu0 / K
    g = 50.0
    assert cross_np(mu0, mu_inf, K, 1.0, 1e9, g) == pytest.approx(mu_inf + tau / g, rel=0.01)


def test_taichi_rheology_matches_numpy():
    g = np.array([0.0, 1e-5, 0.01, 0.5, 3.0, 200.0], dtype=np.float32)
    gf, ob, oc = (ti.field(ti.f32, len(g)) for _ in range(3))
    gf.from_numpy(g)

    @ti.kernel
    def ev():
        for i in gf:
            ob[i] = bingham(0.1, 200.0, 100.0, 5000.0, gf[i])
            oc[i] = cross(70.0, 0.07, 2.8, 1.0, 1e6, gf[i])

    ev()
    assert np.allclose(ob.to_numpy(), bingham_np(0.1, 200.0, 100.0, 5000.0, g), rtol=1e-4)
    assert np.allclose(oc.to_numpy(), cross_np(70.0, 0.07, 2.8, 1.0, 1e6, g), rtol=1e-4)


def test_exact_poiseuille_profiles():
    y = np.linspace(-0.05, 0.05, 101)
    u = poiseuille.exact(y, 1000.0, 0.05, 1.0, 10.0)
    assert u.max() == pytest.approx(1000.0 * 0.04**2 / 2.0)  # plug velocity
    assert np.allclose(u[np.abs(y) <= 0.01], u.max(), rtol=1e-12) and u[0] == pytest.approx(0.0, abs=1e-12)
    assert poiseuille.fit_plug(y, u, 1000.0, 0.05, 1.0) == pytest.approx(0.01, abs=1e-4)


@pytest.mark.slow
@pytest.mark.parametrize("tau_y, l2_bound", [(0.0, 0.06), (10.0, 0.06)])
def test_poiseuille_against_exact(tau_y, l2_bound, tmp_path):
    # dx = b / 10. Measured L2 errors 3.6 % (Newtonian) and 2.8 % (Bingham); the bound leaves
    # room for the 0.7 % unsteadiness left at t = 5 decay times, not for a wrong wall or viscosity
    # (DBC walls without the no-slip ghost velocity gave 17 %).
    ov = {"materials.fluid.yield_stress": tau_y, "output.quiet": True}
    s = simulate(poiseuille, ov, out=str(tmp_path))
    m = s["metrics"]
    assert s["status"] == "ok" and s["leaked_particles"] == 0
    assert m["velocity_l2_error"] < l2_bound
    assert m["plug_width_error"] < 0.05  # plug half-width within 5 % of b (one dx = 10 %)
    assert (tmp_path / "profile.png").exists() and (tmp_path / "profile.csv").exists()


@pytest.mark.slow
def test_sediment_layer_under_water_stays_put(tmp_path):
    # the cubic set at h = 1.3 dx with alpha 0.1 (tests/engine/test_hydrostatic.py): the interface's test
    s = simulate(
        tank,
        {
            "geometry.sediment_depth": 0.2,
            "run.end_time": 2.0,
            "output.quiet": True,
            "numerics.scheme": "paper000",
            "numerics.h_factor": 1.3,
            "numerics.artificial_viscosity": 0.1,
            "numerics.xsph": 0.0,
        },
        out=str(tmp_path),
    )
    m = s["metrics"]
    assert s["status"] == "ok" and s["leaked_particles"] == 0 and m["crossed_wall"] == 0
    assert s["physics"]["rheology"] is True
    assert m["interface_displacement_over_dx"] < 1.0  # the interface moved less than dx
    assert m["speed_ratio"] < 0.01  # peak speed < 1 % sqrt(g H)
    assert m["interface_pressure_jump_error"] < 0.05  # pressure continuous across it
    assert m["pressure_error"] < 0.03


def test_newtonian_tank_compiles_no_rheology(tmp_path):
    s = simulate(tank, {"run.end_time": 0.01, "output.quiet": True}, out=str(tmp_path))
    assert s["physics"]["rheology"] is False


def _heap_case(tau, unyielded="rest"):
    """A block of Bingham material, 0.3 m wide and 0.15 m high, released on a floor in air."""
    from tisph.case import Scene, make_case
    from tisph.particles import FLUID, WALL, ParticleSet, block, box_walls, hydrostatic_density, tait_B
    from tisph.runner import common_params
    from tisph.settings.config import physics_from_config

    defaults = {
        "run": {"end_time": 0.4},
        "numerics": {"dx": 0.01, "artificial_viscosity": 0.1, "density_diffusion": "fourtakas"},
        "materials": {
            "mud": {
                "rho0": 1950.0,
                "viscosity": 0.1,
                "rheology": "bingham",
                "yield_stress": float(tau),
                "regularisation": 100.0,
                "mu_max": 0.0,
                "unyielded": unyielded,
            }
        },
        "output": {"render": False, "snapshot_every": 0.0, "quiet": True},
    }

    def build(cfg):
        dx, W, H = cfg["numerics"]["dx"], 0.3, 0.15
        c0 = 10 * math.sqrt(2 * 9.81 * H)
        mat = cfg["materials"]["mud"]
        ps = ParticleSet()
        heap = block(0.0, 0.0, W, H, dx)
        ps.add(heap, FLUID, 0, hydrostatic_density(H - heap[:, 1], mat["rho0"], c0, 9.81), mat["rho0"] * dx * dx)
        walls = box_walls(0.0, 0.0, 1.0, 0.4, dx, 3)
        ps.add(walls, WALL, 0, mat["rho0"], mat["rho0"] * dx * dx)
        mats = [dict(mat, name="mud", B=tait_B(mat["rho0"], c0))]
        return make_case(
            name="heap",
            particles=ps,
            materials=mats,
            domain=((-0.1, -0.1), (1.1, 0.9)),
            params=common_params(cfg, c0, 9.81, H),
            physics=physics_from_config(cfg),
            view=((-0.05, -0.05), (1.05, 0.45)),
            u_max=c0 / 10,
            probe_columns=("runout",),
            probe=lambda st: (st["x"][st["kind"] == FLUID, 0].max() + 0.005,),
            container=(0.0, 0.0, 1.0, float("inf")),
        )

    return type("Heap", (Scene,), {"NAME": "heap", "SCHEMA": defaults, "build": lambda self, cfg: build(cfg)})()


@pytest.mark.slow
def test_bingham_heap_large_yield_stays_small_yield_slumps(tmp_path):
    """A heap 0.15 m high presses on its base with about rho g H / 2 = 1.4 kPa of shear: with
    tau_B = 5 Pa it slumps, with tau_B = 3000 Pa it stays put (paper 000's premise that sand
    below its yield stress does not deform)."""
    runout = {}
    for tau in (5.0, 3000.0):
        s = simulate(_heap_case(tau), out=str(tmp_path / f"tau{tau:g}"))
        assert s["status"] == "ok", s["message"]
        runout[tau] = s["metrics"].get("runout", None) or float(
            open(tmp_path / f"tau{tau:g}" / "probes.csv").read().splitlines()[-1].split(",")[1]
        )
    dx = 0.01
    assert runout[5.0] > 0.3 + 5 * dx, runout  # slumped: the toe moved over 5 particles
    assert runout[3000.0] < 0.3 + 1 * dx, runout  # held: the toe moved under one particle


@pytest.mark.slow
def test_erodible_bed_command_runs_a_few_steps(tmp_path):
    from tisph.runner import run_scene
    from tisph.scenes import erodible_bed

    out = tmp_path / "eb"
    code = run_scene(erodible_bed, ["--max-steps", "30", "--out", str(out), "--quiet", "--frame-interval", "0.002"])
    assert code == 0
    import json

    s = json.load(open(out / "summary.json"))
    assert s["steps"] == 30 and s["leaked_particles"] == 0
    assert (out / "frames" / "00000.png").exists()
    assert (out / "probes.csv").read_text().splitlines()[0] == "t,front_x,eroded_area"
    # two panels stacked: phase colours above, speed below
    import imageio.v2 as imageio

    img = imageio.imread(out / "frames" / "00000.png")
    assert img.shape[0] > 0.5 * img.shape[1] * 0.44 / 2.52
