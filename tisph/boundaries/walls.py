"""Wall treatments as modules."""
import taichi as ti

from ..hooks.module import Module, Param
from ..particles import FLUID
from ..terms.continuity import continuity
from ..terms.repulsive import lennard_jones


@ti.data_oriented
class DynamicWall(Module):
    """Dynamic boundary particles (Crespo et al. 2007): wall particles obey continuity from the
    fluid around them, never below rest density, and push back through the pressure term."""
    name = "dynamic_wall"
    on = {"wall": "dynamic"}

    @ti.func
    def boundary_kick(self, S, i, dt):
        S.p.rho[i] += 0.5 * dt * S.p.drho[i]

    @ti.func
    def prepare(self, S, a, re, dt):
        return ti.max(re + 0.5 * dt * S.tmp.drho[a], S.mat_rho0[ti.cast(S.tmp.mat[a], ti.i32)])

    @ti.func
    def boundary_pass(self, S, i, dt):
        acc = ti.Struct(drho=0.0, vi=S.tmp.ve[i], rhoi=S.tmp.rhoe[i])
        if S.grid.fluid_near(S.tmp.x[i]):  # most wall particles have no fluid near
            S.grid.for_neighbours(S.tmp, i, S.tmp.x[i], self.boundary_pair, acc)
        S.p.drho[i] = acc.drho
        S.p.rho[i] = ti.max(S.tmp.rho[i] + 0.5 * dt * acc.drho, S.mat_rho0[ti.cast(S.tmp.mat[i], ti.i32)])

    @ti.func
    def boundary_pair(self, i, j, r, r2, acc: ti.template()):
        """Continuity only, from the fluid around the wall particle."""
        S = self.S
        s = S.tmp
        if s.kind[j] == FLUID:
            gw = S.g_scale * S.K.fshape(ti.sqrt(r2) * S.inv_h) * r
            acc.drho += continuity(acc.rhoi, s.m[j] * s.ir[j], acc.vi - s.ve[j], gw)

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

    def fields(self, real):
        return {"vw": ti.types.vector(2, real)}   # the wall's velocity a step ago: its acceleration

    @ti.func
    def boundary_pass(self, S, i, dt):
        acc = ti.Struct(sw=0.0, sp=0.0, sr=ti.Vector([0.0, 0.0]))
        if S.grid.fluid_near(S.tmp.x[i]):
            S.grid.for_neighbours(S.tmp, i, S.tmp.x[i], self.boundary_pair, acc)
        if acc.sw > 0.0:
            mi = ti.cast(S.tmp.mat[i], ti.i32)
            rho0, B = S.mat_rho0[mi], S.mat_B[mi]
            aw = (S.tmp.v[i] - S.tmp.vw[i]) / dt     # a static wall's is zero
            pw = (acc.sp + (S.prm[None].g - aw).dot(acc.sr)) / acc.sw
            S.p.rho[i] = rho0 * ti.pow(ti.max(pw, 0.0) / B + 1.0, 1.0 / 7.0)
        S.p.drho[i] = 0.0
        S.p.vw[i] = S.tmp.v[i]

    @ti.func
    def boundary_pair(self, i, j, r, r2, acc: ti.template()):
        S = self.S
        s = S.tmp
        if s.kind[j] == FLUID:
            w = S.K.shape(ti.sqrt(r2) * S.inv_h)
            acc.sw += w
            acc.sp += s.p[j] * w
            acc.sr += s.rhoe[j] * r * w

    def setup(self, S):
        self.S = S


@ti.data_oriented
class RepulsiveWall(Module):
    """Repulsive wall particles, paper 000 eq. 6 (Lennard-Jones type); in the SPH sums the inert
    wall particle mirrors the fluid particle's pressure plus the hydrostatic difference."""
    name = "repulsive_wall"
    on = {"wall": "repulsive"}
    params = {"wall_D": Param(0.0, "m2/s2", (0.0, None), "wall strength D of eq. 6 (numerics.wall_strength)"),
              "wall_r0": Param("dx", "m", (0.0, None), "cut-off distance r0 of eq. 6")}

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

    def fields(self, real):
        vec2 = ti.types.vector(2, real)
        return {"wn": vec2,   # wall normal (into the fluid) and distance behind the wall surface
                "wd": real}

    def setup(self, S):
        S.p.wn.from_numpy(S.particles.wall_normal.astype(S.np_real))
        S.p.wd.from_numpy(S.particles.wall_dist.astype(S.np_real))

    @ti.func
    def pair(self, S, i, j, r, r2, nb: ti.template(), acc: ti.template()):
        s = S.tmp
        if nb.kj != FLUID:
            d_i = r.dot(s.wn[j]) - s.wd[j]
            ratio = ti.min(s.wd[j] / ti.max(d_i, 1e-6 * S.h), 1.5)
            nb.v_visc = (1.0 + ratio) * nb.v_ij
