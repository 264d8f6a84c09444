"""The next time step: CFL with the viscous signal, the force limit, the viscous limits, the
modules' limits (DEM contacts) and the user's cap."""

import taichi as ti

from ..hooks.health import BAD_DT


@ti.func
def next_dt(S):
    """Run once per step after the force pass (a one-iteration loop in the step kernel)."""
    prm = S.prm[None]
    st = S.stats[None]
    amax = ti.sqrt(st.amax2)
    dt_f = 1e30
    if amax > 0.0:
        dt_f = ti.sqrt(S.h / amax)  # force limit, sqrt(h / |a|_max)
    dt_cv = S.h / (prm.c0 + st.mumax)  # acoustic, with the viscous signal
    dt_v = 1e30
    if ti.static(S.physics.laminar_viscosity):
        dt_v = prm.dt_visc  # 0.125 h^2 / nu of the materials
    if ti.static(S.has_stat("numax")):
        # the viscous limit from the (effective, eddy) viscosity actually applied this step
        if st.numax > 0.0:
            dt_v = ti.min(dt_v, 0.125 * S.h * S.h / st.numax)
        S.stats[None].numax = 0.0
    if ti.static(bool(S.dual)):
        S.prm[None].dt_vis = dt_v  # a held viscous term's bound (physics/dual.py)
    dt_new = ti.min(prm.cfl * ti.min(dt_f, dt_cv), dt_v, prm.dt_max)
    for m in ti.static(S.hooks["dt_limit"]):
        dt_new = m.dt_limit(S, dt_new)
    if dt_new < prm.dt_floor:
        ti.atomic_max(S.stats[None].bad_code, BAD_DT)
    S.prm[None].dt = dt_new
    S.stats[None].amax2 = 0.0
    S.stats[None].mumax = 0.0
