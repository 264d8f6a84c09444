"""Fluid-sediment drag, paper 002 eq. 16 (first term), applied pairwise so momentum is conserved.

Eq. 16 prints the drag on a sediment particle as sum_j W_ij (m_j/rho_f) C_d (pi/4) d_s^2
|u_f - u_s| (u_f - u_s), which is not a force (its units are m^4/s^2: rho_f and the 1/2 of the
drag law are missing, and it counts one grain per SPH particle). Here: the drag per unit volume of
sediment is that of the grains it holds, n_g (1/2) rho_f C_d (pi/4) d_s^2 |du| du with
n_g = (1 - porosity) / (pi d_s^3 / 6) grains per unit volume, i.e.
    f = K |du| du,  K = (3/4) (1 - porosity) rho_f C_d / d_s,
and between a sediment particle i and a water particle j the force is
    F_ij = V_i V_j W_ij K |u_j - u_i| (u_j - u_i) = -F_ji,
so each side adds its own F / m and the pair's momentum is unchanged. Only particles within a
kernel support of the other phase feel it: the interface, and grains lifted into the water.
"""

import taichi as ti


@ti.func
def drag_accel(K, ir_i, vol_j, w, v_i, v_j):
    """Acceleration of particle i from the drag pair (i, j): F_ij / m_i = (V_j / rho_i) W K |du| du."""
    du = v_j - v_i
    return ir_i * vol_j * w * K * du.norm() * du
