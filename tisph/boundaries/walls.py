"""Wall treatments as modules."""

import taichi as ti

from ..hooks.module import Module, Param
from ..particles import FLUID
from ..terms.continuity import continuity
from ..terms.pressure import pressure_accel, riemann_wall_pressure
from ..terms.repulsive import lennard_jones


@ti.data_oriented
class DynamicWall(Module):
    """Dynamic boundary particles (Crespo et al. 2007): wall particles obey continuity from the
    fluid around them, never below rest density, and push back through the pressure term."""

    name = "dynamic_wall"
    on = {"wall": "dynamic"}
    lanes = True

    @ti.func
    def boundary_kick(self, S, i, dt):
        S.p.rho[i] += 0.5 * dt * S.p.drho[i]

    @ti.func
    def prepare(self, S, a, re, dt):
        return ti.max(re + 0.5 * dt * S.tmp.drho[a], S.mat.rho0[ti.cast(S.tmp.mat[a], ti.i32)])

    @ti.func
    def boundary_pass(self, S, i, dt):
        acc = ti.Struct(drho=0.0, vi=S.tmp.ve[i], rhoi=S.tmp.rhoe[i])
        if S.grid.fluid_near(S.tmp.x[i]):  # most wall particles have no fluid near
            S.grid.for_neighbours(S.tmp, i, S.tmp.x[i], self.boundary_pair, acc, S.lanes)
        S.p.drho[i] = acc.drho
        S.p.rho[i] = ti.max(S.tmp.rho[i] + 0.5 * dt * acc.drho, S.mat.rho0[ti.cast(S.tmp.mat[i], ti.i32)])

    @ti.func
    def boundary_pair(self, i, j, r, r2, acc: ti.template()):
        """Continuity only, from the fluid around the wall particle."""
        S = self.S
        s = S.tmp
        fluid = s.kind[j] == FLUID
        if ti.static(S.lanes) or fluid:  # the lanes take every j and zero a wall's volume
            gw = S.g_scale * S.K.fshape(ti.sqrt(r2) * S.inv_h) * r
            acc.drho += continuity(acc.rhoi, ti.select(fluid, s.m[j] * s.ir[j], 0.0), acc.vi - s.ve[j], gw)

    def setup(self, S):
        self.S = S


@ti.data_oriented
class ExtrapolatedWall(Module):
    """Wall particles whose pressure is extrapolated from the fluid around them (Adami, Hu &
    Adams 2012, J. Comput. Phys. 231:7057, eq. 27):
    p_w = (sum_f p_f W_wf + (g - a_w) . sum_f rho_f r_wf W_wf) / sum_f W_wf,
    and their density the Tait density of p_w, never below rest density (as the dynamic wall's).
    Unlike the dynamic wall's continuity, it has no memory: a floor particle a paddle sweeps over
    cannot ratchet up in density cycle after cycle. a_w is the wall's acceleration (the paddle's)."""

    name = "extrapolated_wall"
    on = {"wall": "adami"}
    lanes = True

    def fields(self, real):
        vec2 = ti.types.vector(2, real)
        return {
            "vw": vec2,  # the wall's velocity a step ago: its acceleration
            "nw": vec2,
        }  # the wall's unit normal, out of the wall (the impact guard's)

    @ti.func
    def boundary_pass(self, S, i, dt):
        acc = ti.Struct(sw=0.0, sp=0.0, sr=ti.Vector([0.0, 0.0]), sn=ti.Vector([0.0, 0.0]))
        if S.grid.fluid_near(S.tmp.x[i]):
            S.grid.for_neighbours(S.tmp, i, S.tmp.x[i], self.boundary_pair, acc, S.lanes)
        if acc.sw > 0.0:
            mi = ti.cast(S.tmp.mat[i], ti.i32)
            rho0, B = S.mat.rho0[mi], S.mat.B[mi]
            aw = (S.tmp.v[i] - S.tmp.vw[i]) / dt  # a static wall's is zero
            pw = (acc.sp + (S.prm[None].g - aw).dot(acc.sr)) / acc.sw
            S.p.rho[i] = rho0 * ti.pow(ti.max(pw, 0.0) / B + 1.0, 1.0 / 7.0)
            n2 = acc.sn.dot(acc.sn)
            if n2 > 0.0:
                S.p.nw[i] = acc.sn / ti.sqrt(n2)
        S.p.drho[i] = 0.0
        S.p.vw[i] = S.tmp.v[i]

    @ti.func
    def boundary_pair(self, i, j, r, r2, acc: ti.template()):
        S = self.S
        s = S.tmp
        w = S.K.shape(ti.sqrt(r2) * S.inv_h)
        k = s.kind[j]
        wf = ti.select(k == FLUID, w, 0.0)  # selects, not branches: the loop stays in lanes
        acc.sw += wf
        acc.sp += s.p[j] * wf
        acc.sr += s.rhoe[j] * r * wf
        acc.sn += r * ti.select(k >= 0 and k != FLUID, w, 0.0)  # away from the wall's own particles: the wall's normal

    def setup(self, S):
        self.S = S


WALL_D = Param(0.0, "m2/s2", (0.0, None), "wall strength D of eq. 6 (numerics.wall_strength)")


@ti.data_oriented
class WallImpact(Module):
    """The extrapolated wall's guard against penetration. A fluid particle closing on a wall
    particle sees, beside the wall's extrapolated pressure, the acoustic pressure of the approach
    as the linearised Riemann solver of Zhang, Hu & Adams (2017, J. Comput. Phys. 335:605,
    eqs. 19-22) gives it for a wall whose state mirrors the fluid's: 2 rho_i c0 beta u_n beside
    p_i + p_j, with beta = min(6 u_n / c0, 1) and u_n the speed closing on the wall along its
    normal (SPHinXsys takes the wall's normal too: water sliding along a wall, or rising and
    falling beside it, sees none of it). The limiter keeps it to 12 rho u_n^2 at a wave's speeds
    and lets it grow to twice the water hammer's rho c0 u_n under an impact, where Adami's
    extrapolation alone holds a thin film at its low pressure and lets it through the wall.

    The normal points away from the wall's own particles around the wall particle (sum_k r_wk
    W_wk over the boundary particles k), from the extrapolation's pass a step behind: it follows
    a moving paddle or bed and needs no geometry. (The direction to the water instead tilts at
    the dry floor ahead of a surge front and held the front back.)

    Behind it, a last guard: paper 000's eq. 6 (Lennard-Jones, D = numerics.wall_strength,
    5 g H by default) with r0 = 0.75 dx. On the lattice no water particle sits closer to a wall
    particle than dx, so it acts only on one getting through: a film under tension, whose
    negative pressure the wall's (clamped at zero) does not balance, is drawn into the wall
    particles, and inside them nothing extrapolated pushes it out (a breakwater's run-up on a
    1:2 staircase slope did so at t = 5.7 s without it)."""

    name = "wall_impact"
    on = {"wall": "adami"}
    pair_once = {}
    lanes = True
    params = {
        "wall_D": WALL_D,
        "guard_r0": Param(
            lambda S, values: 0.75 * S.dx,
            "m",
            (0.0, None),
            "the guard's cut-off, under the closest a water and a wall particle sit",
        ),
    }

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        # a wall j only: the lanes take every j and select, the branch form skips a fluid j's work
        if ti.static(S.lanes) or nb.kj != FLUID:
            prm = S.prm[None]
            pj = riemann_wall_pressure(acc.rhoi, prm.c0, nb.v_ij, S.tmp.nw[j])
            f = pressure_accel(nb.m_j, 0.0, pj, acc.inv_rhoi, nb.ir_j, nb.gw) + lennard_jones(
                prm.wall_D, prm.guard_r0, r, r2
            )
            acc.a += ti.select(nb.kj != FLUID, f, ti.Vector([0.0, 0.0]))

    @ti.func
    def pair2(self, S, i, j, r, r2, nb, acc: ti.template(), sj: ti.template()):
        pass  # fluid pairs: nothing


@ti.data_oriented
class RepulsiveWall(Module):
    """Repulsive wall particles, paper 000 eq. 6 (Lennard-Jones type); in the SPH sums the inert
    wall particle mirrors the fluid particle's pressure plus the hydrostatic difference."""

    name = "repulsive_wall"
    on = {"wall": "repulsive"}
    params = {"wall_D": WALL_D, "wall_r0": Param("dx", "m", (0.0, None), "cut-off distance r0 of eq. 6")}

    @ti.func
    def view(self, S, i, j, r, r2, nb: ti.template(), acc: ti.template()):
        prm = S.prm[None]
        if nb.kj != FLUID:
            acc.a += lennard_jones(prm.wall_D, prm.wall_r0, r, r2)
            nb.rho_j = acc.rhoi
            nb.ir_j = acc.inv_rhoi
            nb.p_j = acc.pi - acc.rhoi * prm.g.dot(r)


@ti.data_oriented
class NoSlip(Module):
    """No-slip walls in the viscous terms, Morris et al. (1997), paper 002 eq. 39: the wall
    particle carries the ghost velocity u_B = -(d_B/d_A) u_A (relative to the wall), so the
    no-slip sits on the wall surface; d_B/d_A capped at 1.5 as Morris does for close approach."""

    name = "noslip"
    on = {"noslip": True}
    pair_once = {}  # a wall pair's ghost velocity only (engine/pairs.py gives those pairs the pair hooks)
    lanes = True

    def fields(self, real):
        vec2 = ti.types.vector(2, real)
        return {
            "wn": vec2,  # wall normal (into the fluid) and distance behind the wall surface
            "wd": real,
        }

    def setup(self, S):
        S.p.wn.from_numpy(S.particles.wall_normal.astype(S.np_real))
        S.p.wd.from_numpy(S.particles.wall_dist.astype(S.np_real))

    @ti.func
    def pair(self, S, i, j, r, r2, nb: ti.template(), acc: ti.template()):
        s = S.tmp
        wall = nb.kj != FLUID
        if ti.static(S.lanes) or wall:  # the lanes take every j (a fluid's wd is 0: ratio 0)
            d_i = r.dot(s.wn[j]) - s.wd[j]
            ratio = ti.min(s.wd[j] / ti.max(d_i, 1e-6 * S.h), 1.5)
            nb.v_visc = ti.select(wall, (1.0 + ratio) * nb.v_ij, nb.v_visc)

    @ti.func
    def pair2(self, S, i, j, r, r2, nb: ti.template(), acc: ti.template(), sj: ti.template()):
        """Two fluid particles: no wall between them, nothing to change."""
        pass
