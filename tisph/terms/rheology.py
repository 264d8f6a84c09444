"""Non-Newtonian effective viscosity: Bingham (paper 000 eq. 13) and Cross (paper 002 eqs. 29-30).

Shear rate from the SPH velocity gradient, gamma_dot = sqrt(2 D:D) with D the strain-rate tensor:
    gamma_dot^2 = 2 (du/dx)^2 + 2 (dv/dy)^2 + (du/dy + dv/dx)^2.
Paper 000 eq. 14 prints the last term as (du/dx + dv/dy)^2 and paper 002 eq. 31 adds a factor 2;
both are typos for the second invariant above, which this uses.
"""

import numpy as np
import taichi as ti

NEWTONIAN, BINGHAM, CROSS = 0, 1, 2
RHEOLOGY_CODES = {"newtonian": NEWTONIAN, "bingham": BINGHAM, "cross": CROSS}


@ti.func
def shear_rate(gv):
    """gamma_dot from the velocity gradient gv[a, b] = d u_a / d x_b."""
    s01 = gv[0, 1] + gv[1, 0]
    return ti.sqrt(2.0 * gv[0, 0] * gv[0, 0] + 2.0 * gv[1, 1] * gv[1, 1] + s01 * s01)


@ti.func
def bingham(mu_b, tau_y, m, mu_max, gdot):
    """Bingham, paper 000 eq. 13, mu = mu_B + tau_B / gamma_dot, regularised (Papanastasiou 1987):
    mu = mu_B + tau_B (1 - exp(-m gamma_dot)) / gamma_dot, which tends to mu_B + tau_B m at rest,
    and capped at mu_max (a material setting: it bounds the viscous time step)."""
    mu = mu_b + tau_y * m
    if gdot * m > 1e-4:
        mu = mu_b + tau_y * (1.0 - ti.exp(-m * gdot)) / gdot
    return ti.min(mu, mu_max)


@ti.func
def cross(mu0, mu_inf, K, m1, mu_max, gdot):
    """Cross model, paper 002 eqs. 29-30: (mu0 - mu)/(mu - mu_inf) = (K gamma_dot)^m1, i.e.
    mu = mu_inf + (mu0 - mu_inf) / (1 + (K gamma_dot)^m1); for K gamma_dot >> 1 and m1 = 1 it is
    Bingham with mu_B = mu_inf and tau_B = mu0 / K."""
    return ti.min(mu_inf + (mu0 - mu_inf) / (1.0 + ti.pow(K * gdot, m1)), mu_max)


def bingham_np(mu_b, tau_y, m, mu_max, gdot):
    g = np.asarray(gdot, float)
    with np.errstate(divide="ignore", invalid="ignore"):
        mu = np.where(g * m > 1e-4, mu_b + tau_y * (1 - np.exp(-m * g)) / np.where(g > 0, g, 1), mu_b + tau_y * m)
    return np.minimum(mu, mu_max)


def cross_np(mu0, mu_inf, K, m1, mu_max, gdot):
    return np.minimum(mu_inf + (mu0 - mu_inf) / (1 + (K * np.asarray(gdot, float)) ** m1), mu_max)


@ti.func
def harmonic_pair(mu_i, mu_j):
    """mu_i + mu_j replaced by twice their harmonic mean, 4 mu_i mu_j / (mu_i + mu_j).

    Harmonic, not arithmetic: across a water/sediment interface the shear stress is continuous,
    so the layers act in series and the smaller viscosity governs, as for resistors in series.
    An arithmetic mean would make water next to a plastic bed feel the bed's huge effective
    viscosity. For equal viscosities the two means agree."""
    s = mu_i + mu_j
    out = 0.0
    if s > 0.0:
        out = 4.0 * mu_i * mu_j / s
    return out
