"""The wave-maker paddle: MOVING particles follow a prescribed motion (piston or flap)."""

import taichi as ti

from ..hooks.module import Module, Param


@ti.data_oriented
class Paddle(Module):
    """Piston: x = x0 + X(t), v = X'(t). Flap: rotation by theta(t) about the hinge, v = omega x
    (x - hinge). The solver sets X (or theta) and its rate for t + dt before each step."""

    name = "paddle"
    on = {"paddle": "piston"}
    params = {
        "pd": Param(0.0, "m or rad", (None, None), "paddle displacement (set per step)"),
        "pv": Param(0.0, "m/s or rad/s", (None, None), "paddle rate (set per step)"),
        "pivot": Param((0.0, 0.0), "m", (None, None), "flap hinge", vector=True),
    }

    @staticmethod
    def enabled(S):
        return S.physics.paddle != "none"

    def fields(self, real):
        return {"x0": ti.types.vector(2, real)}  # position at zero displacement

    def setup(self, S):
        S.p.x0.from_numpy(S.particles.x.astype(S.np_real))

    @ti.func
    def move(self, S, i, dt):
        prm = S.prm[None]
        if ti.static(S.physics.paddle == "piston"):
            S.p.x[i] = S.p.x0[i] + ti.Vector([prm.pd, 0.0])
            S.p.v[i] = ti.Vector([prm.pv, 0.0])
        else:
            rel = S.p.x0[i] - prm.pivot
            cs, sn = ti.cos(prm.pd), ti.sin(prm.pd)
            rr = ti.Vector([cs * rel[0] + sn * rel[1], -sn * rel[0] + cs * rel[1]])
            S.p.x[i] = prm.pivot + rr
            S.p.v[i] = prm.pv * ti.Vector([rr[1], -rr[0]])
