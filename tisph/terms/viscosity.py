import taichi as ti


@ti.func
def monaghan_mu(h, v_ij, r, inv_r2e):
    """mu_ij = h v_ij.r_ij / (r^2 + 0.01 h^2) for approaching pairs, else 0 (Monaghan 1992);
    inv_r2e = 1 / (r^2 + 0.01 h^2), computed once per pair for every term that needs it."""
    vr = v_ij.dot(r)
    mu = 0.0
    if vr < 0.0:
        mu = h * vr * inv_r2e
    return mu


@ti.func
def artificial_viscosity(m_j, alpha, c0, mu, inv_rho_i, inv_rho_j, gw):
    """Monaghan artificial viscosity: -sum_j m_j Pi_ij grad W, Pi_ij = -alpha c0 mu_ij / rho_bar,
    with 1 / rho_bar taken as the mean of 1/rho_i and 1/rho_j (symmetric, and no division)."""
    return m_j * alpha * c0 * mu * 0.5 * (inv_rho_i + inv_rho_j) * gw


@ti.func
def laminar_viscosity(m_j, mu_sum, inv_rho_i, inv_rho_j, v_ij, r, inv_r2e, gw):
    """Laminar viscosity of paper 002 eq. 10 (Lo & Shao / Morris 1997):
    sum_j m_j (mu_i + mu_j)/(rho_i rho_j) (r_ij . grad W)/(r^2 + eta^2) v_ij,
    which is eq. 10's 4 nu / (rho_i + rho_j) term for one fluid. mu_sum stands for mu_i + mu_j;
    the solver passes twice the harmonic mean (terms/rheology.py says why); eta^2 = 0.01 h^2,
    inv_r2e = 1 / (r^2 + eta^2)."""
    return m_j * mu_sum * (inv_rho_i * inv_rho_j) * r.dot(gw) * inv_r2e * v_ij
