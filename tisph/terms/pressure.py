import taichi as ti


@ti.func
def tait(rho, rho0, B):
    """Tait equation of state, gamma = 7: p = B ((rho/rho0)^7 - 1) (paper 000 eqs. 11-12)."""
    s = rho / rho0
    s2 = s * s
    return B * (s2 * s2 * s2 * s - 1.0)


@ti.func
def pressure_accel(m_j, p_i, p_j, inv_rho_i, inv_rho_j, gw):
    """Symmetric pressure gradient -sum_j m_j (p_i + p_j)/(rho_i rho_j) grad W_ij.

    Paper 000 eq. 8 / paper 002 eq. 10 discretised in the form that conserves momentum pairwise and
    stays stable across a density ratio of about 2 (Colagrossi & Landrini 2003); in one fluid it
    equals the p/rho^2 form to O(delta rho / rho).
    """
    return -m_j * (p_i + p_j) * (inv_rho_i * inv_rho_j) * gw
