"""Sub-particle-scale (SPS) turbulence, paper 002 eq. 10 (Gotoh et al. 2001; Dalrymple & Rogers 2006).

Smagorinsky eddy viscosity nu_t = (C_s dl)^2 |S|, |S| = sqrt(2 S:S), and the SPS stress
    tau / rho = 2 nu_t S - (2/3) k delta - (2/3) C_I dl^2 |S|^2 delta,
with C_s = 0.12, C_I = 0.0066 and dl the particle spacing. With a mixing length l_m given,
nu_t = l_m^2 |S| instead (Prandtl's mixing-length model with a constant l_m; the SPS's C_s dl is
one at dl = l_m / C_s): at dx = D/20 the Smagorinsky C_s dx is 0.015 D, too small to mix a
pipe's wake, which then stays a dead zone downstream. The SPS kinetic energy k is not
transported; as in Dalrymple & Rogers (2006) it enters through the trace, so the first two terms
are the deviatoric part 2 nu_t (S - tr(S)/3 delta). Its divergence is taken in the symmetric
SPH form sum_j m_j (tau_i/rho_i^2 + tau_j/rho_j^2) . grad W_ij, which conserves momentum.
The stress is evaluated from the velocity gradient of the previous force pass (one dt behind).
"""

import taichi as ti

CS, CI = 0.12, 0.0066


@ti.func
def strain2(gv):
    """|S|^2 = 2 S:S of the velocity gradient gv[a, b] = du_a/dx_b (2D)."""
    sxy = 0.5 * (gv[0, 1] + gv[1, 0])
    return 2.0 * (gv[0, 0] * gv[0, 0] + gv[1, 1] * gv[1, 1] + 2.0 * sxy * sxy)


@ti.func
def eddy_stress(gv, nut, iso):
    """(tau_xx, tau_xy, tau_yy) / rho = 2 nu_t (S - tr(S)/3 delta) - iso delta."""
    sxx = gv[0, 0]
    syy = gv[1, 1]
    sxy = 0.5 * (gv[0, 1] + gv[1, 0])
    tr3 = (sxx + syy) / 3.0
    return ti.Vector([2.0 * nut * (sxx - tr3) - iso, 2.0 * nut * sxy, 2.0 * nut * (syy - tr3) - iso])


@ti.func
def sps_stress(gv, dl, lm=0.0):
    """(tau_xx, tau_xy, tau_yy) / rho and nu_t from the velocity gradient gv[a, b] = du_a/dx_b;
    lm > 0: the mixing length instead of C_s dl."""
    s2 = strain2(gv)
    ls = CS * dl
    if lm > 0.0:
        ls = lm
    nut = ls * ls * ti.sqrt(s2)
    return eddy_stress(gv, nut, (2.0 / 3.0) * CI * dl * dl * s2), nut


@ti.func
def sps_accel(m_j, t_i, ir_i, t_j, ir_j, gw):
    """m_j (tau_i/rho_i^2 + tau_j/rho_j^2) . grad W with t = tau/rho (kinematic) and ir = 1/rho."""
    t = t_i * ir_i + t_j * ir_j
    return m_j * ti.Vector([t[0] * gw[0] + t[1] * gw[1], t[1] * gw[0] + t[2] * gw[1]])
