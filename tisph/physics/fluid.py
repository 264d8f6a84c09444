"""The WCSPH fluid terms as modules: continuity, pressure, viscosity, density diffusion, XSPH.

Each pair hook adds neighbour j's contribution to fluid particle i; `nb` is how i sees j
(its density, pressure, volume, relative velocity, kernel gradient), `acc` i's sums.
"""

import taichi as ti

from ..hooks.module import Module, Param
from ..particles import FLUID
from ..settings.engine_keys import KEYED
from ..terms.continuity import continuity
from ..terms.diffusion import (
    density_diffusion,
    hydrostatic_density_difference,
    renormalisation_sums,
    renormalised_correction,
)
from ..terms.order import from_bits, to_bits
from ..terms.pressure import pressure_accel
from ..terms.rheology import harmonic_pair
from ..terms.viscosity import artificial_viscosity, laminar_viscosity, monaghan_mu
from ..terms.xsph import xsph
from .lanes import lane_volume

# DualSPHysics' 2D free-surface threshold on the position divergence -sum_j V_j r_ij . grad W_ij
# (2 inside a fluid): the surface alpha and the shifting both read it
SURFACE_DIV = 1.5


def viscous_step(h, materials):
    """The explicit viscous limit 0.125 h^2 / nu of the most viscous material (1e30: inviscid)."""
    nu_max = max((m.get("viscosity", 0.0) / m["rho0"] for m in materials), default=0.0)
    return 0.125 * h**2 / nu_max if nu_max > 0 else 1e30


@ti.data_oriented
class Continuity(Module):
    """Continuity equation, paper 000 eq. 8 / paper 002 eq. 8: d rho_i/dt = rho_i sum V_j v_ij . grad W."""

    name = "continuity"
    pair_once = {}  # a and drho only (engine/pairs.py)
    lanes = True

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        acc.drho += continuity(acc.rhoi, nb.vol_j, nb.v_ij, nb.gw)

    @ti.func
    def pair2(self, S, i, j, r, r2, nb, acc: ti.template(), sj: ti.template()):
        """Both fluid particles' terms (engine/pairs.py), each from the one term function with the
        roles swapped: v_ji . grad W_ji = v_ij . grad W_ij, bit for bit."""
        acc.drho += continuity(acc.rhoi, nb.vol_j, nb.v_ij, nb.gw)
        sj.drho += continuity(nb.rho_j, nb.vol_i, nb.v_ij, nb.gw)


@ti.data_oriented
class Pressure(Module):
    """Momentum equation's pressure term, paper 000 eq. 7 (Tait pressure, eqs. 11-12)."""

    name = "pressure"
    pair_once = {}
    lanes = True

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        acc.a += pressure_accel(nb.m_j, acc.pi, nb.p_j, acc.inv_rhoi, nb.ir_j, nb.gw)

    @ti.func
    def pair2(self, S, i, j, r, r2, nb, acc: ti.template(), sj: ti.template()):
        """Both fluid particles' terms from the one term function: j's with grad W_ji = -grad W_ij."""
        acc.a += pressure_accel(nb.m_j, acc.pi, nb.p_j, acc.inv_rhoi, nb.ir_j, nb.gw)
        sj.a += pressure_accel(nb.m_i, nb.p_j, acc.pi, nb.ir_j, acc.inv_rhoi, -nb.gw)


@ti.data_oriented
class ArtificialViscosity(Module):
    """Monaghan's artificial viscosity, paper 000 eq. 9; its signal speed enters the time step.

    With numerics.artificial_viscosity_surface above alpha, a pair with a particle at the free
    surface (its position divergence -sum_j V_j r_ij . grad W_ij, 2 inside a 2D fluid, under
    numerics.surface_divergence: 1.5, DualSPHysics' threshold, or 1.0 in the default scheme,
    sheets and droplets only; one step behind) takes that alpha instead. A particle with part of
    its support empty has no neighbours to carry an oscillation away as sound: a few particles
    torn off a breaker, or left in the swash, ring as the Tait tension pulls them together and
    apart (density +-20 % at alpha 0.01, docs/waves.md), where a constant alpha large enough to
    damp them damps the waves too."""

    name = "artificial_viscosity"
    pair_once = {"mu": "max"}
    on = {"artificial_viscosity": True}
    params = {
        "alpha": KEYED["numerics.artificial_viscosity"],
        "alpha_s": KEYED["numerics.artificial_viscosity_surface"],
        "div_s": KEYED["numerics.surface_divergence"],
    }
    acc = {"mu": "bits"}  # the largest -mu_ij, as bits (terms/order.py)
    SURFACE_DIV = SURFACE_DIV
    lanes = True

    def __init__(self, S=None):
        self.surface = S is not None and S.physics.surface_viscosity
        if self.surface:
            self.acc = dict(self.acc, fsi="real", dvr="real")
            self.pair_once = dict(self.pair_once, dvr="sum")

    def fields(self, real):
        return {"fs": real} if self.surface else {}  # 1 at the free surface, one step behind

    @ti.func
    def init_acc(self, S, i, acc: ti.template()):
        if ti.static(self.surface):
            acc.fsi = S.tmp.fs[i]

    @ti.func
    def alpha_ij(self, S, j, nb, acc):
        prm = S.prm[None]
        a = prm.alpha
        if ti.static(self.surface):
            fj = ti.select(nb.kj == FLUID, S.tmp.fs[j], 0.0)
            a = ti.select(ti.max(acc.fsi, fj) > 0.5, prm.alpha_s, a)
        return a

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        prm = S.prm[None]
        mu = monaghan_mu(S.h, nb.v_ij, r, nb.ie)
        acc.a += artificial_viscosity(nb.m_j, self.alpha_ij(S, j, nb, acc), prm.c0, mu, acc.inv_rhoi, nb.ir_j, nb.gw)
        acc.mu = ti.max(acc.mu, to_bits(ti.select(nb.q < 2.0, -mu, 0.0), S.bits))  # a lane past the support: 0
        if ti.static(self.surface):
            acc.dvr -= nb.vol_j * r.dot(nb.gw)

    @ti.func
    def pair2(self, S, i, j, r, r2, nb, acc: ti.template(), sj: ti.template()):
        """Both fluid particles' terms: mu_ij and alpha_ij are symmetric, the force equal and opposite."""
        prm = S.prm[None]
        mu = monaghan_mu(S.h, nb.v_ij, r, nb.ie)
        alpha = self.alpha_ij(S, j, nb, acc)
        acc.a += artificial_viscosity(nb.m_j, alpha, prm.c0, mu, acc.inv_rhoi, nb.ir_j, nb.gw)
        sj.a += artificial_viscosity(nb.m_i, alpha, prm.c0, mu, nb.ir_j, acc.inv_rhoi, -nb.gw)
        b = to_bits(-mu, S.bits)
        acc.mu = ti.max(acc.mu, b)
        sj.mu = ti.max(sj.mu, b)
        if ti.static(self.surface):
            rg = r.dot(nb.gw)  # r_ji . grad W_ji is the same
            acc.dvr -= nb.vol_j * rg
            sj.dvr -= nb.vol_i * rg

    @ti.func
    def finish(self, S, i, mi, acc: ti.template(), pt: ti.template()):
        pt.mumax = ti.max(pt.mumax, from_bits(acc.mu, S.real))
        if ti.static(self.surface):
            S.p.fs[i] = 1.0 if acc.dvr < S.prm[None].div_s else 0.0


@ti.data_oriented
class LaminarViscosity(Module):
    """Laminar viscosity, paper 002 eq. 10 (Morris et al. 1997), with the harmonic pair mean."""

    name = "laminar_viscosity"
    rate = "advection"
    pair_once = {}
    lanes = True
    on = {"laminar_viscosity": True}
    params = {
        "dt_visc": Param(
            lambda S, values: viscous_step(S.h, S.materials),
            "s",
            (0.0, None),
            "viscous step 0.125 h^2 / nu_max of the materials",
        )
    }

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        s = S.tmp
        mu_f = 0.0
        if ti.static(S.physics.rheology):
            mu_f = s.mu[j]
        else:
            mu_f = S.mat.mu[ti.cast(s.mat[j], ti.i32)]
        mu_j = ti.select(nb.kj == FLUID, mu_f, acc.mui)  # a wall particle takes the fluid's viscosity
        acc.a += laminar_viscosity(
            nb.m_j, harmonic_pair(acc.mui, mu_j), acc.inv_rhoi, nb.ir_j, nb.v_visc, r, nb.ie, nb.gw
        )

    @ti.func
    def pair2(self, S, i, j, r, r2, nb, acc: ti.template(), sj: ti.template()):
        """Both fluid particles' terms: the harmonic mean and r . grad W are symmetric."""
        mu_j = S.mat.mu[ti.cast(S.tmp.mat[j], ti.i32)]
        mu = harmonic_pair(acc.mui, mu_j)
        acc.a += laminar_viscosity(nb.m_j, mu, acc.inv_rhoi, nb.ir_j, nb.v_visc, r, nb.ie, nb.gw)
        sj.a += laminar_viscosity(nb.m_i, mu, nb.ir_j, acc.inv_rhoi, -nb.v_visc, -r, nb.ie, -nb.gw)


def gradient_held(S):
    """Whether the velocity gradient, and the turbulence it drives (the SPS, the k equation), are
    advection-rate terms under dual time stepping (physics/dual.py): the eddy viscosity changes at
    the flow's pace. Not where a rheology reads the gradient (a Bingham or Cross material's
    effective viscosity bounds the step, so it is evaluated every step) or shifting does."""
    p = S.physics
    return p.time_stepping == "dual" and not (p.rheology or p.shifting)


def rate_of_gradient(m, S):
    """Give module m (the gradient, or a term it drives) the gradient's rate; returns whether it
    is held."""
    held = S is not None and gradient_held(S)
    if held:
        m.rate = "advection"
    return held


@ti.data_oriented
class VelocityGradient(Module):
    """The SPH velocity gradient grad v_i = sum V_j (v_j - v_i) (x) grad W, for the shear rate of
    the rheology (paper 000 eq. 14) and the SPS strain rate (paper 002 eq. 10)."""

    name = "velocity_gradient"
    on = {"sps": True}
    acc = {"gv": "mat2"}
    pair_once = {"gv": "sum"}
    lanes = True

    def __init__(self, S=None):
        rate_of_gradient(self, S)

    @staticmethod
    def enabled(S):
        return S.physics.rheology or S.physics.sps or S.physics.shifting

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        acc.gv += nb.vol_j * (-nb.v_visc).outer_product(nb.gw)

    @ti.func
    def pair2(self, S, i, j, r, r2, nb, acc: ti.template(), sj: ti.template()):
        """Both: v_ij and grad W change sign together, so j's term is i's with V_i for V_j."""
        g = (-nb.v_visc).outer_product(nb.gw)
        acc.gv += nb.vol_j * g
        sj.gv += nb.vol_i * g


@ti.data_oriented
class DensityDiffusion(Module):
    """Density diffusion within a material (numerics.density_diffusion): Molteni & Colagrossi
    (2009); Fourtakas et al. (2019), with the hydrostatic part removed; or Antuono et al. (2010,
    Comput. Phys. Commun. 181:532), delta-SPH's diffusive term with the renormalised density
    gradients, psi_ji = 2 (rho_j - rho_i) r_ji / r^2 - (<grad rho>^L_i + <grad rho>^L_j), which
    vanishes for any linear density field, the dynamic pressure of a wave under a free surface
    included, where the others diffuse it across the kernel's truncated support.

    The renormalised gradient <grad rho>^L_i = L_i^-1 sum_j V_j (rho_j - rho_i) grad W_ij, with
    L_i = sum_j V_j r_ji (x) grad W_ij (Randles & Libersky 1996), comes from the same neighbour
    pass one step behind (a second pass a step would double the cost); where L is near singular
    (a droplet) the gradient is 0, Molteni's term."""

    name = "density_diffusion"
    rate = "advection"
    pair_once = {}  # rho0_c02 is set per particle (init_acc)
    lanes = True
    on = {"density_diffusion": "molteni"}
    params = {"delta": KEYED["numerics.delta"]}
    acc = {"rho0_c02": "real"}
    DET_MIN = 0.05  # det L: 1 in a full support; a droplet's few neighbours fall under this

    @staticmethod
    def enabled(S):
        return S.physics.density_diffusion != "none"

    def __init__(self, S=None):
        self.renormalised = S is not None and S.physics.density_diffusion == "antuono"
        if self.renormalised:
            # L is symmetric (grad W is along r): xx, xy, yy
            self.acc = dict(self.acc, gr="vec2", lm="vec3", gi="vec2")
            # the gather pass: each pair once would add five sums to j's (the flume's step took
            # 18.4 s a 3,000 steps against 16.4 gathering, two threads, back to back)
            self.pair_once = None

    def fields(self, real):
        # the renormalised density gradient, one step behind: the pass reads the sorted copy
        # (S.tmp) and finish writes the next one (S.p), so no read meets a write
        return {"grho": ti.types.vector(2, real)} if self.renormalised else {}

    @ti.func
    def finish(self, S, i, mi, acc: ti.template(), pt: ti.template()):
        if ti.static(self.renormalised):
            g = ti.Vector([0.0, 0.0])
            a, b, c = acc.lm[0], acc.lm[1], acc.lm[2]
            d = a * c - b * b
            if d > self.DET_MIN:
                g = ti.Vector([c * acc.gr[0] - b * acc.gr[1], a * acc.gr[1] - b * acc.gr[0]]) / d
            S.p.grho[i] = g

    @ti.func
    def init_acc(self, S, i, acc: ti.template()):
        prm = S.prm[None]
        acc.rho0_c02 = S.mat.rho0[acc.mat] / (prm.c0 * prm.c0)
        if ti.static(self.renormalised):
            acc.gi = S.tmp.grho[i]

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        prm = S.prm[None]
        # within the material only: the lanes zero the others' volume, the branch form skips them
        mj = ti.cast(S.tmp.mat[j], ti.i32)
        if ti.static(S.lanes) or (nb.kj == FLUID and mj == acc.mat):
            vol = lane_volume(nb, mj, acc.mat)
            hyd = 0.0
            if ti.static(S.physics.density_diffusion == "fourtakas"):
                hyd = hydrostatic_density_difference(acc.rho0_c02, prm.g, r)
            acc.drho += density_diffusion(prm.delta, S.h, prm.c0, vol, acc.rhoi, nb.rho_j, hyd, r, nb.ie, nb.gw)
            if ti.static(self.renormalised):
                gr, lm = renormalisation_sums(acc.rhoi, nb.rho_j, r, nb.gw)
                acc.drho -= vol * renormalised_correction(prm.delta, S.h, prm.c0, acc.gi, S.tmp.grho[j], nb.gw)
                acc.gr += vol * gr
                acc.lm += vol * lm

    @ti.func
    def pair2(self, S, i, j, r, r2, nb, acc: ti.template(), sj: ti.template()):
        """Both fluid particles' terms from the one term function: within one material rho0 / c0^2
        is shared, so j's hydrostatic difference is -i's."""
        prm = S.prm[None]
        if S.tmp.mat[j] == acc.mat:
            hyd = 0.0
            if ti.static(S.physics.density_diffusion == "fourtakas"):
                hyd = hydrostatic_density_difference(acc.rho0_c02, prm.g, r)
            acc.drho += density_diffusion(prm.delta, S.h, prm.c0, nb.vol_j, acc.rhoi, nb.rho_j, hyd, r, nb.ie, nb.gw)
            sj.drho += density_diffusion(prm.delta, S.h, prm.c0, nb.vol_i, nb.rho_j, acc.rhoi, -hyd, -r, nb.ie, -nb.gw)


@ti.data_oriented
class Shifting(Module):
    """Particle shifting (Lind et al. 2012, J. Comput. Phys. 231:1499, eq. 11; the coefficient as
    Skillen et al. 2013, Comput. Methods Appl. Mech. Engrg. 265:163, eq. 21): particles drift
    down the gradient of their own concentration, dr = -A h |u| dt grad C with
    grad C_i = sum_j V_j grad W_ij over every neighbour (walls too, so no particle is pushed into
    one), which evens out the clumps and voids of a wake. At the free surface (the divergence of
    position, -sum_j V_j r_ij . grad W_ij, under SURFACE_DIV; 2 inside a 2D fluid) the
    concentration falls for want of neighbours, not of order, so such a particle is not
    shifted. Applied as a drift velocity one step behind, as XSPH, with the velocity corrected to
    the shifted position to first order (the Taylor correction of Xu et al. 2009 and Lind et
    al. 2012); the density is not (its
    gradient is not at hand, and the shift is a small fraction of dx a step)."""

    name = "shifting"
    on = {"shifting": True}
    SURFACE_DIV = SURFACE_DIV
    params = {"shifting": KEYED["numerics.shifting"]}
    acc = {"gc": "vec2", "divr": "real"}

    def fields(self, real):
        return {"sh": ti.types.vector(2, real)}  # the shifting velocity, one step behind

    @ti.func
    def drift(self, S, i, u):
        return u + S.p.sh[i]

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        acc.gc += nb.vol_j * nb.gw
        acc.divr -= nb.vol_j * r.dot(nb.gw)

    @ti.func
    def finish(self, S, i, mi, acc: ti.template(), pt: ti.template()):
        w = ti.Vector([0.0, 0.0])
        if acc.divr >= self.SURFACE_DIV:
            w = -S.prm[None].shifting * S.h * ti.sqrt(pt.v.dot(pt.v)) * acc.gc
        S.p.sh[i] = w
        # the velocity where the particle is shifted to, v + (dr . grad) v: without it the shift
        # carries momentum across the flow and mixes it
        S.p.v[i] = pt.v + S.prm[None].dt * (acc.gv @ w)


@ti.data_oriented
class XSPH(Module):
    """XSPH, paper 000 eq. 10: particles drift with v + eps sum m_j / rho_ij (v_j - v_i) W."""

    name = "xsph"
    on = {"xsph": True}
    params = {"eps": KEYED["numerics.xsph"]}
    acc = {"xs": "vec2"}
    lanes = True

    def fields(self, real):
        return {"xs": ti.types.vector(2, real)}  # the correction, one step behind

    @ti.func
    def drift(self, S, i, u):
        return u + S.prm[None].eps * S.p.xs[i]

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        if ti.static(S.lanes) or nb.kj == FLUID:  # the lanes take every j and weigh a wall's zero
            w = ti.select(nb.kj == FLUID, S.w_scale * S.K.shape(nb.q), 0.0)
            acc.xs += xsph(nb.m_j, -nb.v_ij, acc.inv_rhoi, nb.ir_j, w)

    @ti.func
    def finish(self, S, i, mi, acc: ti.template(), pt: ti.template()):
        S.p.xs[i] = acc.xs
