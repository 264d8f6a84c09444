"""Zones as modules: open outflow boxes, the container check, the absorbing (damping) zone, the
inflow zone of a periodic current, and the periodic current's driving pressure gradient."""

import math

import taichi as ti

from ..constants import KAPPA
from ..hooks.health import BAD_SPILL, BAD_SPRAY, BAD_WALL, report
from ..hooks.module import MatParam, Module, Param
from ..particles import FLUID, SPRAY
from ..settings.engine_keys import KEYED


@ti.data_oriented
class Outflow(Module):
    """Open boundaries: fluid entering one of the boxes (x0, y0, x1, y1) leaves the simulation."""

    name = "outflow"
    on = {"outflow": ((0.05, -1.0, 1.0, 1.0),)}

    @ti.func
    def remove(self, S, i):
        gone = False
        for z in ti.static(S.outflow):
            xx = S.p.x[i]
            if z[0] <= xx[0] <= z[2] and z[1] <= xx[1] <= z[3]:
                gone = True
        return gone


@ti.data_oriented
class Spray(Module):
    """Spray torn off a breaker: a droplet of two or three particles whose continuity sum drifts
    as they fly apart (or clump) leaves the density band; such a particle is removed as SPRAY and
    counted, as DualSPHysics removes particles outside RhopOutMin/Max, instead of stopping the
    run. More than spray_limit of the water is the flow coming apart, not spray: the run stops."""

    name = "spray"
    on = {"spray": True}
    kind_out = SPRAY
    params = {
        "spray_limit": KEYED["numerics.spray_limit"],
        "spray_cap": Param(
            lambda S, v: max(1, int(v.get("spray_limit", 0.0) * S.particles.count(FLUID))),
            "particles",
            (1, None, True, True),
            "spray particles beyond which the run stops",
        ),
    }
    stats = {"spray": "int"}

    @ti.func
    def remove(self, S, i):
        gone = False
        if ti.abs(S.p.rho[i] / S.mat.rho0[ti.cast(S.p.mat[i], ti.i32)] - 1.0) > S.prm[None].band:
            gone = True
            if ti.atomic_add(S.stats[None].spray, 1) >= S.prm[None].spray_cap:
                report(S.stats, BAD_SPRAY, S.p.id[i])
        return gone


@ti.data_oriented
class Container(Module):
    """The box the walls enclose, (x0, y0, x1, y1, side-wall top), widened by dx/2: fluid outside
    it (below the top of the side walls, above which it may overtop) crossed a wall, and the run
    stops. It counts as crossed once past the first row of wall particles."""

    name = "container"
    on = {"container": (0.0, 0.0, 0.07, 1.0)}

    @ti.func
    def position_check(self, S, i):
        xx = S.p.x[i]
        b = ti.static(S.container)
        if xx[1] < b[1] or xx[1] > b[3] or (xx[1] < b[4] and (xx[0] < b[0] or xx[0] > b[2])):
            code = BAD_WALL
            # checked every step, a particle pushed through a side wall is caught within dx of
            # it; one found further out came over the top
            if xx[1] >= b[1] and (xx[0] < b[0] - S.dx or xx[0] > b[2] + S.dx):
                code = BAD_SPILL
            report(S.stats, code, S.p.id[i])


@ti.data_oriented
class Damping(Module):
    """Absorbing zone (x0, x1, rate 1/s): an implicit relaxation of the velocity, ramped in
    quadratically, so waves leave the flume without reflecting."""

    name = "damping"
    on = {"damping": (0.03, 0.07, 5.0)}

    @ti.func
    def relax(self, S, i, mi, v, dt):
        zd = ti.static(S.physics.damping)
        s = ti.min(ti.max((S.tmp.x[i][0] - zd[0]) / (zd[1] - zd[0]), 0.0), 1.0)
        return v / (1.0 + dt * zd[2] * s * s)


@ti.data_oriented
class Inflow(Module):
    """Inflow zone of a periodic current (x0, x1, rate, material, y_bed, u*, z0): the recirculated
    wake is relaxed back to the log law u = (u*/kappa) ln(z/z0) (paper 002 eq. 32), as an inlet
    would feed it; ramped in and out as sin^2 so no front forms."""

    name = "inflow"
    on = {"inflow": (0.0, 0.02, 5.0, 0, 0.0, 0.01, 1e-4), "periodic_x": True}

    @ti.func
    def relax(self, S, i, mi, v, dt):
        zi = ti.static(S.physics.inflow)
        xr = (S.tmp.x[i][0] - zi[0]) / (zi[1] - zi[0])
        out = v
        if mi == ti.static(int(zi[3])) and 0.0 < xr < 1.0:
            s = ti.sin(math.pi * xr) ** 2
            z = ti.max(S.tmp.x[i][1] - zi[4], zi[6])
            ut = ti.Vector([zi[5] / KAPPA * ti.log(z / zi[6]), 0.0])
            out = (v + dt * zi[2] * s * ut) / (1.0 + dt * zi[2] * s)
        return out


@ti.data_oriented
class Drive(Module):
    """The driving pressure gradient of a periodic current, -grad p / rho of material 0. It
    pushes each material by rho_0 / rho of it: the pore water carries it through a sediment
    layer, which does not feel it at its own density. Set with solver.set_drive()."""

    name = "drive"
    on = {"periodic_x": True}
    params = {"drive": Param((0.0, 0.0), "m/s2", (None, None), "driving pressure gradient / rho_water", vector=True)}
    material = {
        "drive": MatParam(
            None,
            "-",
            "the drive's factor rho_0 / rho (set by the solver)",
            convert=lambda v, mat, S: S.materials[0]["rho0"] / mat["rho0"],
        )
    }

    @ti.func
    def body_force(self, S, i, mi, a):
        return a + S.prm[None].drive * S.mat.drive[mi]
