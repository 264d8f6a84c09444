"""The runtime parameters that a config key sets, declared once here without Taichi, so that
tisph.settings.config reads their defaults and ranges without importing the engine. Each module takes its
Param from this table (KEYED[key]); the key is the config key. A key the numerics scheme sets
takes the default scheme's value (tisph/settings/schemes.py), its one default."""

from .schema import Param
from .schemes import DEFAULT, SCHEMES

_S = SCHEMES[DEFAULT]

KEYED = {
    p.key: p
    for p in (
        # measured: dam-break front and density error unchanged from 0.2 to 0.4 (0.5: +40 % density error)
        Param(0.4, "-", (0.0, 1.0, False, True), "CFL number of the acoustic and force limits", key="numerics.cfl"),
        Param(1e-3, "s", (0.0, None, False, True), "user cap on the time step", key="numerics.dt_max"),
        Param(
            0.25,
            "-",
            (0.0, 1.0, False, True),
            "with time_stepping dual: the viscous and diffusive terms are evaluated when the fastest particle "
            "has moved this fraction of h since they last were (Zhang et al. 2020: 0.25)",
            key="numerics.advection_cfl",
        ),
        # measured: the sloshing tank at delta 0.1 ran at 4 and blew up at 5 (the held density
        # diffusion is explicit over the held interval); 3 leaves a margin
        Param(
            3.0,
            "-",
            (1.0, 64.0, True, True),
            "with time_stepping dual: at most this many acoustic steps to one evaluation of the viscous and "
            "diffusive terms",
            key="numerics.acoustic_steps",
        ),
        Param(
            0.3,
            "-",
            (0.0, 1.0, False, True),
            "stop when |rho/rho0 - 1| exceeds this (instability)",
            key="numerics.density_band",
        ),
        Param(
            0.0,
            "-",
            (0.0, 0.1, True, True),
            "the fraction of the water that may leave density_band as spray: such a particle (a droplet torn "
            "off a breaker) is removed and counted, as DualSPHysics removes particles outside RhopOutMin/Max; "
            "more stops the run; 0: any particle leaving the band stops it",
            key="numerics.spray_limit",
        ),
        Param(
            _S["artificial_viscosity"],
            "-",
            (0.0, 2.0, True, True),
            "Monaghan alpha; 0 compiles the term out",
            key="numerics.artificial_viscosity",
        ),
        Param(
            _S["artificial_viscosity_surface"],
            "-",
            (0.0, 2.0, True, True),
            "above artificial_viscosity: the alpha of a pair with a particle at the free surface (its position "
            "divergence under surface_divergence), where droplets and the swash ring (with artificial_viscosity 0 "
            "too); 0: alpha everywhere",
            key="numerics.artificial_viscosity_surface",
        ),
        Param(
            _S["surface_divergence"],
            "-",
            (0.0, 2.0, False, True),
            "the position divergence -sum_j V_j r_ij . grad W_ij under which artificial_viscosity_surface acts (2 "
            "inside the water; a flat surface's top row 1.15 with Wendland h = 2.5 dx, 1.28 with the cubic at 1.3 "
            "dx; a sheet two rows thick 0.64 and 1.16; a lone particle 0)",
            key="numerics.surface_divergence",
        ),
        Param(_S["delta"], "-", (0.0, 1.0, True, True), "density diffusion coefficient", key="numerics.delta"),
        Param(
            _S["shifting"],
            "-",
            (0.0, 10.0, True, True),
            "particle shifting coefficient A (Skillen et al. 2013: 2); 0 compiles it out",
            key="numerics.shifting",
        ),
        Param(
            _S["xsph"],
            "-",
            (0.0, 0.5, True, True),
            "XSPH epsilon (paper 000 eq. 10); 0 compiles it out",
            key="numerics.xsph",
        ),
        Param(
            0.0,
            "m",
            (0.0, None, True, True),
            "the SPS's length C_s dl as a mixing length l_m (nu_t = l_m^2 |S|); 0: C_s dx",
            key="numerics.mixing_length",
        ),
        Param(
            0.0,
            "-",
            (0.0, None, True, True),
            "Wilcox's (2006) stress limiter C_lim on the k equation's eddy viscosity (7/8 in k-omega 2006); 0: off",
            key="numerics.stress_limiter",
        ),
    )
}
