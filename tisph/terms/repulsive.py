import taichi as ti


@ti.func
def lennard_jones(D, r0, r, r2):
    """Repulsive wall force per unit mass (paper 000 eq. 6, Monaghan 1994), n1 = 12, n2 = 6:
    F = D ((r0/r)^12 - (r0/r)^6) r_ij / r^2 for r < r0, else 0."""
    f = ti.Vector([0.0, 0.0])
    if r2 < r0 * r0:
        # the floor: in the CPU's vector lanes a particle's own r = 0 is computed too, and an
        # infinity there is poison to LLVM under fast math (which assumes none), select or not
        d2 = ti.max(r2, 1e-6 * r0 * r0)
        s2 = r0 * r0 / d2
        s6 = s2 * s2 * s2
        f = D * (s6 * s6 - s6) / d2 * r
    return f
