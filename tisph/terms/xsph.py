import taichi as ti


@ti.func
def xsph(m_j, v_ji, rho_i, rho_j, w):
    """XSPH velocity correction term m_j v_ji / rho_bar_ij W_ij (paper 000 eq. 10), times epsilon."""
    return m_j * v_ji / (0.5 * (rho_i + rho_j)) * w
