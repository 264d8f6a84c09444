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
"""
import taichi as ti

from .sps import eddy_stress, strain2  # noqa: F401  (strain2: |S|^2, shared with the SPS)

SQRT_CMU = 0.3       # C_mu^(1/2), C_mu = 0.09: k = u*^2 / sqrt(C_mu) in a wall layer in equilibrium
CMU14 = 0.5477226    # C_mu^(1/4)
CMU34 = 0.1643168    # C_mu^(3/4)
SIGMA_K = 1.0
K_FLOOR = 1e-10      # m2/s2: k = 0 is a fixed point of the equation (no nu_t, no production)


@ti.func
def eddy_viscosity(k, l):
    return CMU14 * ti.sqrt(k) * l


@ti.func
def tke_update(k, l, s2, diff, dt):
    """k one step on: production nu_t |S|^2 and diffusion explicit, dissipation implicit."""
    sk = ti.sqrt(k)
    knew = (k + dt * (CMU14 * sk * l * s2 + diff)) / (1.0 + dt * CMU34 * sk / ti.max(l, 1e-12))
    return ti.max(knew, K_FLOOR)


@ti.func
def tke_stress(gv, nut, k):
    """(tau_xx, tau_xy, tau_yy) / rho = 2 nu_t S_dev - (2/3) k delta."""
    return eddy_stress(gv, nut, (2.0 / 3.0) * k)
