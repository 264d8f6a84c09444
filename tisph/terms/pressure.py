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


@ti.func
def riemann_wall_pressure(rho_i, c0, v_ij, n_w):
    """The approach's share of the interface pressure of a linearised Riemann solver between
    fluid i and a wall that mirrors it (Zhang, Hu & Adams 2017, J. Comput. Phys. 335:605,
    eqs. 19-22, with the mirrored normal velocity U_L - U_R = 2 u_n): rho_i c0 beta u_n, with
    beta = min(3 (U_L - U_R) / c0, 1) = min(6 u_n / c0, 1) the
    dissipation limiter and u_n = -v_ij . n_w > 0 the speed closing on
    the wall along its unit normal n_w (into the water); 0 when the particle moves away. As a pressure p_j beside p_i + p_j it is 2 p*'s
    extra term."""
    un = -v_ij.dot(n_w)
    p = 0.0
    if un > 0.0:
        p = 2.0 * rho_i * un * ti.min(6.0 * un, c0)
    return p
