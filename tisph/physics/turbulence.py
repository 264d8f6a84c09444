"""Turbulence closures of the water: the Smagorinsky SPS (paper 002 eq. 10), the k equation
(the k-l model of Launder & Spalding 1972 and Rodi 1993) and its transported omega length
(Wilcox 2006)."""

import numpy as np
import taichi as ti

from ..hooks.module import Module
from ..particles import FLUID
from ..settings.engine_keys import KEYED
from ..terms.sps import sps_accel, sps_stress
from ..terms.tke import (
    CMU14,
    K_FLOOR,
    SIGMA_K,
    SIGMA_W,
    eddy_viscosity,
    length_of_omega,
    omega_update,
    strain2,
    tke_stress,
    tke_update,
)
from .fluid import rate_of_gradient
from .lanes import lane_volume


@ti.data_oriented
class SPS(Module):
    """Sub-particle-scale (Smagorinsky) turbulence in Newtonian materials, paper 002 eq. 10; the
    stress is one step behind the velocity gradient it comes from."""

    name = "sps"
    on = {"sps": True}
    maxima = {"numax": "real"}
    params = {"mixing_length": KEYED["numerics.mixing_length"]}
    pair_once = {}  # into a (engine/pairs.py)
    lanes = True

    def __init__(self, S=None):
        # a held Smagorinsky nu_t still bounds the step between its evaluations (the k equation's
        # is in its own field)
        self.held_nu = rate_of_gradient(self, S) and S.physics.turbulence != "k_equation"

    def fields(self, real):
        f = {"sps": ti.types.vector(3, real)}  # SPS stress / rho (xx, xy, yy)
        if self.held_nu:
            f["nus"] = real  # nu_t of the last evaluation (dual time stepping)
        return f

    acc = {"sps_i": "vec3"}

    @ti.func
    def init_acc(self, S, i, acc: ti.template()):
        acc.sps_i = S.tmp.sps[i]

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        t_j = acc.sps_i  # a wall particle mirrors i's SPS stress
        if ti.static(S.lanes):
            t_j = ti.select(nb.kj == FLUID, S.tmp.sps[j], acc.sps_i)
        elif nb.kj == FLUID:
            t_j = S.tmp.sps[j]
        acc.a += sps_accel(nb.m_j, acc.sps_i, acc.inv_rhoi, t_j, nb.ir_j, nb.gw)

    @ti.func
    def pair2(self, S, i, j, r, r2, nb, acc: ti.template(), sj: ti.template()):
        """Both fluid particles: the symmetric stress sum is the same from either side, grad W
        changes sign."""
        w = sps_accel(1.0, acc.sps_i, acc.inv_rhoi, S.tmp.sps[j], nb.ir_j, nb.gw)
        acc.a += nb.m_j * w
        sj.a -= nb.m_i * w

    @ti.func
    def finish(self, S, i, mi, acc: ti.template(), pt: ti.template()):
        tau = ti.Vector([0.0, 0.0, 0.0])
        nut = 0.0
        newtonian = True
        if ti.static(S.physics.rheology):
            newtonian = S.mat.rheo[mi] == 0
        if newtonian:
            if ti.static(S.physics.turbulence == "k_equation"):
                nut = S.p.nut[i]  # TKE.finish, just before, from this step's k
                tau = tke_stress(acc.gv, nut, S.p.kt[i])
            else:
                tau, nut = sps_stress(acc.gv, S.dx, S.prm[None].mixing_length)
        S.p.sps[i] = tau
        if ti.static(self.held_nu):
            S.p.nus[i] = nut
        pt.numax = ti.max(pt.numax, nut + S.mat.mu[mi] / pt.rho)

    @ti.func
    def hold(self, S, i, mi, pt: ti.template()):
        """A step that holds the stress: its eddy viscosity still bounds the step."""
        nut = 0.0
        if ti.static(S.physics.turbulence == "k_equation"):
            nut = S.p.nut[i]  # TKE.hold, just before, from this step's k
        else:
            nut = S.tmp.nus[i]
        pt.numax = ti.max(pt.numax, nut + S.mat.mu[mi] / pt.rho)


@ti.data_oriented
class Omega(Module):
    """The k equation's length from a transported specific dissipation omega (Wilcox 2006;
    tisph/terms/tke.py omega_update), bounded by the prescribed length (numerics.length_scale =
    "omega"): it moves with the particles, diffuses between them as k does and steps after TKE,
    which takes its length sqrt(k) / (C_mu^(1/4) omega) from the old omega."""

    name = "omega"
    on = {"sps": True, "turbulence": "k_equation", "tke_length": "omega"}
    acc = {"wi": "real", "dw": "real"}
    pair_once = {"dw": "sum"}
    lanes = True

    def __init__(self, S=None):
        self.held = rate_of_gradient(self, S)

    def fields(self, real):
        f = {"wt": real}  # specific dissipation omega (1/s)
        if self.held:
            f["kdw"] = real  # omega's diffusion rate of the last evaluation (dual time stepping)
        return f

    def setup(self, S):
        """omega from the scene's k and l (the wall layer's equilibrium): omega = sqrt(k) / (C_mu^(1/4) l)."""
        k, l = S.p.kt.to_numpy().astype(float), S.p.lt.to_numpy().astype(float)
        S.p.wt.from_numpy((np.sqrt(k) / (CMU14 * np.maximum(l, 1e-12))).astype(S.np_real))

    @ti.func
    def init_acc(self, S, i, acc: ti.template()):
        acc.wi = S.tmp.wt[i]

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        s = S.tmp
        mj = ti.cast(s.mat[j], ti.i32)
        if ti.static(S.lanes) or (nb.kj == FLUID and mj == acc.mat):  # the lanes: every j, the others' volume 0
            acc.dw += (
                lane_volume(nb, mj, acc.mat)
                * SIGMA_W
                * (acc.nuti + s.nut[j])
                * (acc.wi - s.wt[j])
                * r.dot(nb.gw)
                * nb.ie
            )

    @ti.func
    def pair2(self, S, i, j, r, r2, nb, acc: ti.template(), sj: ti.template()):
        """Both: the flux is antisymmetric."""
        s = S.tmp
        if s.mat[j] == acc.mat:
            f = SIGMA_W * (acc.nuti + s.nut[j]) * (acc.wi - s.wt[j]) * r.dot(nb.gw) * nb.ie
            acc.dw += nb.vol_j * f
            sj.dw -= nb.vol_i * f

    @ti.func
    def finish(self, S, i, mi, acc: ti.template(), pt: ti.template()):
        if ti.static(self.held):
            S.p.kdw[i] = acc.dw
        self.step(S, i, acc.wi, acc.ki, strain2(acc.gv), acc.dw)  # TKE's acc: k before the step

    @ti.func
    def hold(self, S, i, mi, pt: ti.template()):
        """A step that holds the sums: omega steps on with the held strain and diffusion."""
        t = S.tmp
        self.step(S, i, t.wt[i], t.kt[i], t.ks2[i], t.kdw[i])

    @ti.func
    def step(self, S, i, w, k, s2, dw):
        S.p.wt[i] = omega_update(w, ti.max(k, K_FLOOR), S.tmp.lt[i], s2, dw, S.prm[None].dt, S.prm[None].stress_limiter)


@ti.data_oriented
class TKE(Module):
    """A transported turbulent kinetic energy k for the SPS's eddy viscosity (the k-l model,
    tisph/terms/tke.py): k moves with the particles, diffuses between them and is made and
    dissipated per particle; the length l is per particle (the scene sets it; else
    numerics.mixing_length)."""

    name = "tke"
    on = {"sps": True, "turbulence": "k_equation"}
    acc = {"ki": "real", "nuti": "real", "dk": "real"}
    pair_once = {"dk": "sum"}
    lanes = True
    params = {"stress_limiter": KEYED["numerics.stress_limiter"]}

    def __init__(self, S=None):
        self.held = rate_of_gradient(self, S)

    def fields(self, real):
        f = {
            "kt": real,  # turbulent kinetic energy k (m2/s2)
            "lt": real,  # its length scale l (m)
            "nut": real,
        }  # eddy viscosity C_mu^(1/4) sqrt(k) l (m2/s)
        if self.held:  # dual time stepping: the last evaluation's |S|^2 and diffusion of k
            f.update(ks2=real, kdk=real)
        return f

    def setup(self, S):
        """k and l where the scene gives them (ParticleSet.tke, .turbulence_length), else the
        floor and numerics.mixing_length."""
        k0 = getattr(S.particles, "tke", None)
        k = np.full(S.n, K_FLOOR) if k0 is None else np.maximum(np.asarray(k0, float), K_FLOOR)
        l0 = getattr(S.particles, "turbulence_length", None)
        l = np.full(S.n, float(S.prm[None].mixing_length)) if l0 is None else np.asarray(l0, float)
        S.p.kt.from_numpy(k.astype(S.np_real))
        S.p.lt.from_numpy(l.astype(S.np_real))
        S.p.nut.from_numpy((CMU14 * np.sqrt(k) * l).astype(S.np_real))

    @ti.func
    def init_acc(self, S, i, acc: ti.template()):
        acc.ki = S.tmp.kt[i]
        acc.nuti = S.tmp.nut[i]

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        s = S.tmp
        # no flux through walls (k at a wall is the near-wall balance's) or into another material
        mj = ti.cast(s.mat[j], ti.i32)
        if ti.static(S.lanes) or (nb.kj == FLUID and mj == acc.mat):  # as Omega's
            acc.dk += (
                lane_volume(nb, mj, acc.mat)
                * (acc.nuti + s.nut[j])
                * (acc.ki - s.kt[j])
                * r.dot(nb.gw)
                * nb.ie
                / SIGMA_K
            )

    @ti.func
    def pair2(self, S, i, j, r, r2, nb, acc: ti.template(), sj: ti.template()):
        """Both: the flux is antisymmetric."""
        s = S.tmp
        if s.mat[j] == acc.mat:
            f = (acc.nuti + s.nut[j]) * (acc.ki - s.kt[j]) * r.dot(nb.gw) * nb.ie / SIGMA_K
            acc.dk += nb.vol_j * f
            sj.dk -= nb.vol_i * f

    @ti.func
    def finish(self, S, i, mi, acc: ti.template(), pt: ti.template()):
        s2 = strain2(acc.gv)
        if ti.static(self.held):
            S.p.ks2[i] = s2
            S.p.kdk[i] = acc.dk
        self.step(S, i, mi, acc.ki, s2, acc.dk)

    @ti.func
    def hold(self, S, i, mi, pt: ti.template()):
        """A step that holds the sums (dual time stepping): k steps on with the last evaluation's
        production strain and diffusion, and its own dissipation."""
        t = S.tmp
        self.step(S, i, mi, t.kt[i], t.ks2[i], t.kdk[i])

    @ti.func
    def step(self, S, i, mi, k0, s2, dk):
        l = S.tmp.lt[i]
        if ti.static(S.physics.tke_length == "omega"):  # k and omega both step from the old state
            l = ti.min(l, length_of_omega(k0, S.tmp.wt[i]))
        clim = S.prm[None].stress_limiter
        k = tke_update(k0, l, s2, dk, S.prm[None].dt, clim)
        if ti.static(S.physics.rheology):
            if S.mat.rheo[mi] != 0:  # the SPS is the Newtonian materials' only
                k = K_FLOOR
        S.p.kt[i] = k
        S.p.nut[i] = eddy_viscosity(k, l, s2, clim)
