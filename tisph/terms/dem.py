"""Soft-contact DEM between sediment particles, paper 002 eqs. 17-28 (Cundall & Strack 1979).

A linear spring-dashpot in the normal and tangential directions of each contact:
    f_n = e_n + d_n,  e_n = k_n * overlap (eq. 20 summed over the steps), d_n = eta_n * (relative
    normal velocity, eq. 21); no tension: f_n = f_s = 0 if e_n < 0 (eq. 24);
    f_s = e_s + d_s,  e_s(t) = e_s(t - dt) + k_s * (tangential slip in dt) (eq. 22), d_s = eta_s *
    (tangential relative velocity) (eq. 23); Coulomb: |e_s| <= mu e_n, e_s = mu SIGN(e_n, e_s) (eq. 25).
The contact is on when the centres are closer than the contact diameter (eq. 28). Eq. 28 writes
the grain diameter d_s = 0.36 mm, which no two SPH particles a spacing apart ever reach; the
scene chooses the contact diameter dc in spacings (pipeline_scour: 0.7 dx, so only grains thrown
closer than a resting bed packs touch; its docstring says why). The tangential spring e_s is
history: it lives in a per-particle list of contact partners (by particle id) that moves with the
particle through every re-sort.
Time step (eq. 27): dt <= dt_c / 20, dt_c = 2 pi sqrt(m_s / (2 k_n)).
"""

import math

import taichi as ti


@ti.func
def contact_force(kn, ks, eta_n, eta_s, mu, dc, r, v_ij, es_old, dt):
    """Force on i from the contact with j (r = x_i - x_j, v_ij = v_i - v_j) and the updated
    tangential spring force. Returns (force vector, e_s new, in contact)."""
    rn = r.norm()
    f = ti.Vector([0.0, 0.0])
    es = 0.0
    on = False
    if 0.0 < rn < dc:
        n = r / rn  # from j to i
        t = ti.Vector([-n[1], n[0]])
        overlap = dc - rn
        vn = v_ij.dot(n)  # > 0: separating
        vt = v_ij.dot(t)
        en = kn * overlap
        fn = en - eta_n * vn  # repulsive when positive
        es = es_old - ks * vt * dt  # the spring resists the slip
        if en < 0.0:
            fn = 0.0
            es = 0.0
        # Coulomb: the spring force cannot exceed mu times the normal spring force (eq. 25)
        lim = mu * en
        if ti.abs(es) > lim:
            es = lim if es >= 0.0 else -lim
        fs = es - eta_s * vt
        if ti.abs(fs) > lim:  # the slider caps the dashpot too
            fs = lim if fs >= 0.0 else -lim
        f = ti.max(fn, 0.0) * n + fs * t
        on = True
    return f, es, on


def critical_step(m_s, kn):
    """dt_c = 2 pi sqrt(m_s / (2 k_n)) (eq. 27); the step is dt_c / 20."""
    return 2 * math.pi * math.sqrt(m_s / (2 * kn))


def restitution(m_eff, kn, eta_n):
    """Coefficient of restitution of a linear spring-dashpot head-on contact."""
    zeta = eta_n / (2 * math.sqrt(kn * m_eff))
    return math.exp(-math.pi * zeta / math.sqrt(1 - zeta * zeta)) if zeta < 1 else 0.0
