"""The compile-time physics switches of a case (config.Physics): which terms the engine compiles
in, from the config and what the scene uses."""

from collections.abc import Mapping
from dataclasses import asdict, dataclass


@dataclass(frozen=True)
class Physics:
    """Which terms exist. Read with ti.static: a term that is off is never compiled."""

    kernel: str = "cubic"
    wall: str = "dynamic"
    artificial_viscosity: bool = True
    laminar_viscosity: bool = False
    xsph: bool = False
    shifting: bool = False  # particle shifting (Lind et al. 2012; physics/fluid.py Shifting)
    surface_viscosity: bool = False  # a larger alpha at the free surface (physics/fluid.py ArtificialViscosity)
    density_diffusion: str = "none"
    shepard: bool = False
    rheology: bool = False  # some material is Bingham or Cross: effective-viscosity field
    periodic_x: bool = False
    noslip: bool = False  # Morris no-slip walls in the viscous terms (paper 002 eq. 39)
    paddle: str = "none"  # none | piston | flap: MOVING particles follow a prescribed motion
    damping: tuple = ()  # (x0, x1, rate 1/s): absorbing zone, damping grows as ((x-x0)/(x1-x0))^2
    inflow: tuple = ()  # (x0, x1, rate 1/s, material, y_bed, u*, z0): a zone relaxing that
    # material's velocity to the log law (paper 002 eq. 32)
    sps: bool = False  # SPS (Smagorinsky) turbulence in Newtonian materials (paper 002 eq. 10)
    turbulence: str = "smagorinsky"  # with sps: smagorinsky | k_equation (the eddy viscosity from a transported k)
    tke_length: str = (
        "prescribed"  # with k_equation: prescribed (the scene's l) | omega (transported omega, l its bound)
    )
    drag: bool = False  # fluid-sediment drag between different materials (paper 002 eq. 16)
    dem: bool = False  # DEM spring-dashpot contacts between sediment particles (paper 002 eqs. 17-28)
    moving_bed: bool = False  # BED particles follow a morphodynamic bed z_b(x) (tisph/sediment)
    suspension: bool = False  # the water carries suspended sand exchanged with that bed (physics/suspension.py)
    time_stepping: str = "single"  # dual: the advection-rate terms held over acoustic steps (physics/dual.py)
    spray: bool = False  # fluid leaving the density band is removed as spray, up to numerics.spray_limit (zones.Spray)

    def as_dict(self):
        return asdict(self)


def physics_from_config(
    cfg: dict,
    periodic_x=False,
    noslip=False,
    materials_used=None,
    paddle="none",
    damping=(),
    sps=False,
    drag=False,
    dem=False,
    inflow=(),
    moving_bed=False,
    suspension=False,
) -> Physics:
    """The switches of a case. materials_used: names of the materials its particles carry (all
    configured materials if None); rheology is compiled only if one of them is non-Newtonian."""
    n = cfg.numerics
    mats = cfg.get("materials", {})
    used = mats.keys() if materials_used is None else materials_used
    turb = n.get("turbulence", "smagorinsky") if sps else "smagorinsky"
    rheo = any(isinstance(mats[k], Mapping) and mats[k].get("rheology", "newtonian") != "newtonian" for k in used)
    return Physics(
        rheology=rheo,
        periodic_x=periodic_x,
        noslip=noslip,
        paddle=paddle,
        damping=tuple(float(v) for v in damping),
        inflow=tuple(float(v) for v in inflow),
        sps=sps,
        turbulence=turb,
        tke_length=n.get("length_scale", "prescribed") if turb == "k_equation" else "prescribed",
        drag=drag,
        dem=dem,
        moving_bed=moving_bed,
        suspension=suspension,
        kernel=n.kernel,
        wall=n.wall,
        artificial_viscosity=n.artificial_viscosity > 0.0 or n.artificial_viscosity_surface > 0.0,
        laminar_viscosity=bool(n.laminar_viscosity) or rheo,
        xsph=n.xsph > 0.0,
        shifting=n.shifting > 0.0,
        surface_viscosity=n.artificial_viscosity_surface > n.artificial_viscosity,
        density_diffusion=n.density_diffusion,
        shepard=n.shepard_every > 0,
        spray=n.spray_limit > 0.0,
        time_stepping=n.get("time_stepping", "single"),
    )
