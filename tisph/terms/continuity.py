import taichi as ti


@ti.func
def continuity(rho_i, vol_j, v_ij, gw):
    """d rho_i/dt = rho_i sum_j V_j v_ij . grad W_ij: paper 002 eq. 8 written with the
    neighbour's volume V_j = m_j / rho_j (Colagrossi & Landrini 2003), which equals eq. 8 in a
    single fluid and stays consistent across a density jump (water/sediment)."""
    return rho_i * vol_j * v_ij.dot(gw)
