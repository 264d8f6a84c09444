import taichi as ti


@ti.func
def xsph(m_j, v_ji, inv_rho_i, inv_rho_j, w):
    """XSPH velocity correction term m_j v_ji / rho_bar_ij W_ij (paper 000 eq. 10), times epsilon;
    1 / rho_bar as the mean of the inverse densities (equal to O(drho^2) for one fluid)."""
    return m_j * v_ji * (0.5 * (inv_rho_i + inv_rho_j)) * w
