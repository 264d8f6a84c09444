"""A transported turbulent kinetic energy k (numerics.turbulence = "k_equation"): the one-equation
(k-l) model of Prandtl (1945) and Kolmogorov in the form of Launder & Spalding (1972, Lectures in
Mathematical Models of Turbulence, ch. 4) and Rodi (1993, Turbulence Models and their Application
in Hydraulics, sec. 2.3.3):

    nu_t = C_mu^(1/4) sqrt(k) l                          (eddy viscosity)
    dk/dt = nu_t |S|^2 - C_mu^(3/4) k^(3/2) / l + div((nu_t / sigma_k) grad k)

with C_mu = 0.09, sigma_k = 1, |S|^2 = 2 S:S and l a length given per particle (the pipeline:
Prandtl's min(kappa d, 0.09 H) from the nearest wall). In local equilibrium (production =
dissipation) it is Prandtl's mixing length, nu_t = l^2 |S|; away from it k is carried with the
water: the turbulence made in the shear layers of a pipe's gap jet and its separation drifts
into the wake, where a local closure (Smagorinsky, a mixing length) sees only the wake's weak
mean shear. The particles carry k (the material derivative is the particle's own), so only the
diffusion needs the neighbours: Morris et al.'s (1997) Laplacian, as the suspended sand's. The
dissipation is implicit (k^(3/2) = k sqrt(k_old)), so k stays positive at any step. The SPS
stress then has nu_t from k and k itself in its trace: tau / rho = 2 nu_t S_dev - (2/3) k delta.

Wilcox's (2006, AIAA J. 46:2823) omega equation (numerics.length_scale = "omega") replaces the
prescribed l where the flow makes its own, smaller scale: dw/dt = alpha (w / k) P - beta w^2 +
div(sigma nu_t grad w), with l = sqrt(k) / (C_mu^(1/4) w) (then the k equation above is k-omega's,
its dissipation beta* k w and nu_t = k / w) and w never below the wall's, sqrt(k) / (C_mu^(1/4)
l_wall), so the prescribed length stays the upper bound (the log layer, 0.09 H). The separated
shear layers and the near wake of a cylinder, whose eddies are smaller than the wall distance,
then carry less eddy viscosity. Not included: the cross-diffusion sigma_d / w grad k . grad w
(k-omega 1998 has none) and sigma* = 0.6 in the k diffusion (sigma_k = 1 here).

Wilcox's (2006, AIAA J. 46:2823; Turbulence Modeling for CFD, 3rd ed., eq. 4.36) stress limiter,
numerics.stress_limiter = C_lim (7/8 in k-omega 2006; 0 = off), caps nu_t at sqrt(C_mu) k /
(C_lim |S|), i.e. omega >= C_lim |S| / sqrt(beta*): it acts only where production exceeds
dissipation by more than 1 / C_lim^2 (1.31), as in the shear layers that leave a cylinder, and
never in an equilibrium wall layer (there nu_t = l^2 |S| = C_lim times the cap). SedFoam carries
k-epsilon and Wilcox's k-omega 2006, which Mathieu et al. (2019, Water 11:1727) compare on Mao's
pipeline; here omega with the limiter is what let Mao's pipe shed over a fixed bed (docs/sediment.md).
"""

import taichi as ti

from ..constants import SQRT_CMU
from .sps import eddy_stress, strain2  # noqa: F401  (strain2: |S|^2, shared with the SPS)

CMU14 = 0.5477226  # C_mu^(1/4)
CMU34 = 0.1643168  # C_mu^(3/4)
SIGMA_K = 1.0
K_FLOOR = 1e-10  # m2/s2: k = 0 is a fixed point of the equation (no nu_t, no production)


@ti.func
def eddy_viscosity(k, l, s2, clim):
    """C_mu^(1/4) sqrt(k) l, capped by Wilcox's stress limiter where clim > 0."""
    nut = CMU14 * ti.sqrt(k) * l
    if clim > 0.0:
        nut = ti.min(nut, SQRT_CMU * k / (clim * ti.sqrt(s2) + 1e-30))
    return nut


@ti.func
def tke_update(k, l, s2, diff, dt, clim):
    """k one step on: production nu_t |S|^2 (nu_t limited) and diffusion explicit, dissipation
    implicit."""
    sk = ti.sqrt(k)
    knew = (k + dt * (eddy_viscosity(k, l, s2, clim) * s2 + diff)) / (1.0 + dt * CMU34 * sk / ti.max(l, 1e-12))
    return ti.max(knew, K_FLOOR)


# Wilcox (2006) k-omega: omega's production alpha (omega / k) P, destruction beta omega^2 (beta_0,
# f_beta = 1 in 2D), diffusion sigma nu_t
ALPHA_W = 0.52
BETA_W = 0.0708
SIGMA_W = 0.5


@ti.func
def omega_of_length(k, l):
    """The omega whose length sqrt(k) / (C_mu^(1/4) omega) is l: k-omega's dissipation beta* k
    omega is then the k-l model's C_mu^(3/4) k^(3/2) / l, and nu_t = k / omega."""
    return ti.sqrt(k) / (CMU14 * ti.max(l, 1e-12))


@ti.func
def length_of_omega(k, w):
    """The length sqrt(k) / (C_mu^(1/4) omega) of an omega (omega_of_length's inverse)."""
    return ti.sqrt(k) / (CMU14 * w)


@ti.func
def omega_update(w, k, l_wall, s2, diff, dt, clim):
    """omega one step on (numerics.length_scale = "omega"): production alpha (omega / k) nu_t |S|^2
    and diffusion explicit, destruction beta omega^2 implicit; never below the wall's
    sqrt(k) / (C_mu^(1/4) l_wall) (the log layer's omega = u* / (sqrt(beta*) kappa d), and
    0.09 H's under the surface), so a wall layer keeps Prandtl's length."""
    w_wall = omega_of_length(k, l_wall)
    we = ti.max(w, w_wall)
    nut = eddy_viscosity(k, length_of_omega(k, we), s2, clim)
    wnew = (w + dt * (ALPHA_W * we / k * nut * s2 + diff)) / (1.0 + dt * BETA_W * we)
    return ti.max(wnew, w_wall)


@ti.func
def tke_stress(gv, nut, k):
    """(tau_xx, tau_xy, tau_yy) / rho = 2 nu_t S_dev - (2/3) k delta."""
    return eddy_stress(gv, nut, (2.0 / 3.0) * k)
