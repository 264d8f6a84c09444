"""Every module is compiled in only when its switch is on: generated from the module registry,
so a new module is covered by declaring its `on` switches (tisph/hooks/module.py). The solvers
with a module on are built but not compiled: the golden cases and each module's own tests
compile and run them."""

import numpy as np
import pytest

from tisph.engine.enabled import MODULES
from tisph.engine.solver import Solver
from tisph.hooks.module import HOOKS
from tisph.particles import FLUID, MOVING, WALL, ParticleSet
from tisph.scenes import dam_break
from tisph.settings.config import Physics, build_config, physics_from_config
from tisph.settings.resolved import freeze

DX = 0.01
SOLVER_ARGS = ("outflow", "container")  # switches that are solver arguments, not Physics fields


def tiny(on):
    """A patch of water over a wall row (a MOVING column for the paddle), with a Bingham and a
    DEM material, where the switches `on` hold."""
    ps = ParticleSet()
    g = (np.arange(7) + 0.5) * DX
    ps.add(np.array([(a, b) for a in g for b in g]), FLUID, 0, 1000.0, 0.1)
    ps.add(np.column_stack([g, np.full(7, -0.5 * DX)]), WALL, 0, 1000.0, 0.1, normal=(0.0, 1.0), wall_dist=0.5 * DX)
    ps.add(np.column_stack([np.full(3, -0.5 * DX), g[:3]]), MOVING, 0, 1000.0, 0.1)
    ps.add(np.array([(0.035, 0.1)]), FLUID, 1, 1500.0, 0.15)
    mats = [
        dict(name="water", rho0=1000.0, viscosity=1e-3, B=1e5),
        dict(name="sand", rho0=1500.0, viscosity=0.1, B=1.5e5, rheology="bingham", yield_stress=10.0, dem=True),
    ]
    phys = {k: v for k, v in on.items() if k not in SOLVER_ARGS}
    kw = {k: v for k, v in on.items() if k in SOLVER_ARGS}
    params = dict(dx=DX, h=1.3 * DX, c0=20.0, cfl=0.4, kn=1e3, motion=lambda t: (0.0, 0.0))
    return Solver(Physics(**phys), ps, mats, ((-0.03, -0.03), (0.1, 0.15)), params, **kw)


def fields_of(cls):
    import taichi as ti

    return set(cls().fields(ti.f32))


# Every switch off (two builds: the wall kinds exclude each other). Built once for all modules.
ALL_OFF = dict(
    artificial_viscosity=False,
    laminar_viscosity=False,
    xsph=False,
    shifting=False,
    density_diffusion="none",
    shepard=False,
    rheology=False,
    periodic_x=False,
    noslip=False,
    paddle="none",
    damping=(),
    inflow=(),
    sps=False,
    turbulence="smagorinsky",
    tke_length="prescribed",
    drag=False,
    dem=False,
    moving_bed=False,
    suspension=False,
    spray=False,
    surface_viscosity=False,
    time_stepping="single",
)


@pytest.fixture(scope="module")
def off_solvers():
    out = {w: tiny(dict(ALL_OFF, wall=w)) for w in ("dynamic", "repulsive")}
    for s in out.values():
        for _ in range(3):
            s.step()
    return out


def test_all_off_covers_every_switch():
    import dataclasses

    switches = {f.name for f in dataclasses.fields(Physics)} - {"kernel", "wall"}
    assert switches == set(ALL_OFF), "a new Physics switch must be added to ALL_OFF"


@pytest.mark.parametrize("cls", [c for c in MODULES if c.on is not None], ids=lambda c: c.name)
def test_module_only_when_switched_on(cls, off_solvers):
    on = tiny(cls.on)
    off = off_solvers["repulsive" if cls.on.get("wall") == "dynamic" else "dynamic"]
    assert cls.name in [m.name for m in on.modules]
    assert cls.name not in [m.name for m in off.modules]
    for hook in HOOKS:  # not traced: no hook of the module in any list the kernel unrolls
        assert all(type(m) is not cls for m in off.hooks[hook])
    for k in fields_of(cls):
        assert k in on.members and hasattr(on.p, k)
        assert k not in off.members and not hasattr(off.p, k) and not hasattr(off.tmp, k)
    for k, d in cls.material.items():
        assert hasattr(on.mat, d.field or k) and not hasattr(off.mat, d.field or k)
    # that each module compiles and runs is the golden cases' job (every module is on in one)


@pytest.mark.slow
def test_switched_off_terms_change_the_result():
    def make(**ov):
        cfg = freeze(build_config(dam_break.SCENE.DEFAULTS, None, dict({"numerics.dx": 0.06}, **ov)))
        case = dam_break.SCENE.build(cfg)
        return Solver(case.physics, case.particles, case.materials, case.domain, case.params)

    off = make(
        **{
            "numerics.artificial_viscosity": 0.0,
            "numerics.artificial_viscosity_surface": 0.0,
            "numerics.xsph": 0.0,
            "numerics.density_diffusion": "none",
            "numerics.laminar_viscosity": False,
        }
    )
    on = make(
        **{
            "numerics.artificial_viscosity": 0.1,
            "numerics.xsph": 0.3,
            "numerics.density_diffusion": "fourtakas",
            "numerics.laminar_viscosity": True,
        }
    )
    assert {m.name for m in on.modules} - {m.name for m in off.modules} == {
        "artificial_viscosity",
        "xsph",
        "density_diffusion",
        "laminar_viscosity",
    }
    for s in (off, on):
        for _ in range(300):
            s.step()
        assert s.check() is None
    a, b = off.state(), on.state()
    assert np.abs(a["x"] - b["x"]).max() > 1e-5
    assert np.abs(a["rho"] - b["rho"]).max() > 1e-3


def test_physics_follows_config():
    cfg = freeze(
        build_config(
            dam_break.SCENE.DEFAULTS,
            None,
            {"numerics.kernel": "wendland", "numerics.wall": "repulsive", "numerics.shepard_every": 20},
        )
    )
    ph = physics_from_config(cfg)
    assert ph.kernel == "wendland" and ph.wall == "repulsive" and ph.shepard
    # the default scheme: no alpha but in sheets and droplets, renormalised diffusion
    assert ph.artificial_viscosity and ph.surface_viscosity and ph.density_diffusion == "antuono" and not ph.xsph
    # the surface alpha compiles the term in on its own, and only above alpha
    for alpha, surface, want in ((0.0, 0.1, (True, True)), (0.1, 0.05, (True, False)), (0.0, 0.0, (False, False))):
        ph = physics_from_config(
            freeze(
                build_config(
                    dam_break.SCENE.DEFAULTS,
                    None,
                    {"numerics.artificial_viscosity": alpha, "numerics.artificial_viscosity_surface": surface},
                )
            )
        )
        assert (ph.artificial_viscosity, ph.surface_viscosity) == want


def test_shepard_filter_smooths_noise_and_keeps_the_mean():
    """Paper 002 eqs. 13-15: one Shepard pass over a density field with 2 % particle-to-particle
    noise removes most of the noise and keeps the mean (a normalised average). A Wendland dam
    break, filtered every step, the noise added at the start."""
    cfg = freeze(
        build_config(
            dam_break.SCENE.DEFAULTS,
            None,
            {"numerics.dx": 0.06, "numerics.kernel": "wendland", "numerics.shepard_every": 1, "numerics.h_factor": 1.5},
        )
    )
    case = dam_break.SCENE.build(cfg)
    fl = case.particles.kind == FLUID
    rho0 = case.particles.rho.copy()
    noise = 20.0 * np.random.default_rng(3).standard_normal(len(rho0))
    case.particles.rho[fl] += noise[fl]
    s = Solver(case.physics, case.particles, case.materials, case.domain, case.params)
    assert s.module("shepard") is not None
    s.step()
    assert s.check() is None
    rho = s.state()["rho"]
    left = rho[fl] - rho0[fl]
    assert left.std() < 0.35 * noise[fl].std(), (left.std(), noise[fl].std())
    assert abs(rho[fl].mean() / rho0[fl].mean() - 1) < 2e-3
