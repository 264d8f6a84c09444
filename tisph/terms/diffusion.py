import taichi as ti


@ti.func
def density_diffusion(delta, h, c0, vol_j, rho_i, rho_j, rho_hyd_ji, r, inv_r2e, gw):
    """delta-SPH density diffusion, Brookshaw Laplacian of the density:
    2 delta h c0 sum_j V_j ((rho_i - rho_j) + rho^H_ji) (r_ij . grad W)/(r^2 + 0.01 h^2).

    rho^H_ji = 0 is Molteni & Colagrossi (2009); the hydrostatic difference rho^H_j - rho^H_i
    makes it Fourtakas et al. (2019), which does not diffuse the hydrostatic gradient away.
    inv_r2e = 1 / (r^2 + 0.01 h^2), one division per pair shared by every term.
    """
    return 2.0 * delta * h * c0 * vol_j * ((rho_i - rho_j) + rho_hyd_ji) * r.dot(gw) * inv_r2e


@ti.func
def hydrostatic_density_difference(rho0_over_c02, g, r):
    """rho^H_j - rho^H_i for r = x_i - x_j under gravity g (Fourtakas et al. 2019).

    Linearised: rho0 ((1 + rho0 g dz / B)^(1/7) - 1) = rho0 g dz / c0^2 + O((g dz / c0^2)^2), and
    g dz / c0^2 < 1e-3 over a kernel support, so this saves a pow per pair at no visible cost.
    """
    return rho0_over_c02 * (-g.dot(r))  # -g . r = g . (x_j - x_i) > 0 when j lies deeper


@ti.func
def renormalisation_sums(rho_i, rho_j, r, gw):
    """One neighbour's (rho_j - rho_i) grad W_ij and r_ji (x) grad W_ij, the sums of the
    renormalised density gradient (Randles & Libersky 1996, as Antuono et al. 2010 use it).
    r = x_i - x_j and grad W lies along r, so the matrix is symmetric: (xx, xy, yy)."""
    return (rho_j - rho_i) * gw, -ti.Vector([r[0] * gw[0], r[1] * gw[0], r[1] * gw[1]])


@ti.func
def renormalised_correction(delta, h, c0, grad_i, grad_j, gw):
    """The renormalised gradients' part of Antuono et al.'s (2010) psi_ij . grad W, times
    delta h c0: subtracted from the Molteni term, it cancels that term for a linear field."""
    return delta * h * c0 * (grad_i + grad_j).dot(gw)
