"""Sediment and turbulence modules: rheology (Bingham, Cross), SPS turbulence, fluid-sediment
drag and DEM contacts between sediment particles."""
import taichi as ti

from ..engine.module import MatParam, Module, Param
from ..particles import FLUID
from ..terms.dem import contact_force, critical_step
from ..terms.drag import drag_accel
from ..terms.rheology import BINGHAM, CROSS, RHEOLOGY_CODES, bingham, cross, shear_rate
from ..terms.sps import sps_accel, sps_stress
from ..terms.tke import (CMU14, K_FLOOR, SIGMA_K, SIGMA_W, eddy_viscosity, length_of_omega, omega_update, strain2,
                         tke_stress, tke_update)

DEM_SLOTS = 8   # contacts remembered per particle (a packed 2D lattice has at most 6 within dx)


def mu_cap(mat, h, c0, cfl):
    """The effective-viscosity cap of a material: its mu_max, or with mu_max = 0 ("auto") the
    viscosity whose explicit viscous step 0.125 h^2 rho / mu equals the acoustic step
    cfl h / c0, so a plastic material costs no extra time steps. Below yield such a material
    creeps at about (stress / mu_cap); a larger mu_max makes it stiffer and the run slower in
    proportion."""
    mm = mat.get("mu_max", 0.0)
    if mm > 0:
        return mm
    return 0.125 * h * mat["rho0"] * c0 / cfl


def mu_at_rest(mat, h, c0, cfl):
    r = mat.get("rheology", "newtonian")
    mu = mat.get("viscosity", 0.0)
    if r == "bingham":
        mu = mu + mat.get("yield_stress", 0.0) * mat.get("regularisation", 1000.0)
    elif r == "cross":
        mu = mat.get("mu0", mu)
    return min(mu, mu_cap(mat, h, c0, cfl)) if r != "newtonian" else mu


@ti.data_oriented
class Rheology(Module):
    """Effective viscosity of non-Newtonian materials: Bingham (paper 000 eq. 13, Papanastasiou
    regularised) and Cross (paper 002 eqs. 29-30), lagged by one step; optionally an unyielded
    Bingham material held at rest as a rigid plug."""
    name = "rheology"
    on = {"rheology": True, "laminar_viscosity": True}
    material = {
        "rheology": MatParam("newtonian", "-", "newtonian | bingham | cross", "int",
                             lambda v, mat, S: RHEOLOGY_CODES[v], "rheo"),
        "yield_stress": MatParam(0.0, "Pa", "Bingham yield stress tau_B", field="tau"),
        "regularisation": MatParam(1000.0, "s", "Papanastasiou exponent m", field="m"),
        "mu_max": MatParam(0.0, "Pa s", "cap on the effective viscosity (0: from the acoustic step)",
                           convert=lambda v, mat, S: mu_cap(mat, S.h, S.c0, S.cfl), field="mumax"),
        "mu0": MatParam(None, "Pa s", "Cross zero-shear viscosity (default: the viscosity)",
                        convert=lambda v, mat, S: mat.get("viscosity", 0.0) if v is None else v),
        "K": MatParam(0.0, "s", "Cross time constant"),
        "m1": MatParam(1.0, "-", "Cross exponent"),
        "unyielded": MatParam("creep", "-", "creep | rest: an unyielded Bingham material creeps or rests",
                              "int", lambda v, mat, S: int(v == "rest"), "rest"),
    }
    stats = {"numax": "real"}

    @staticmethod
    def enabled(S):
        return S.physics.rheology

    def fields(self, real):
        return {"mu": real}    # effective viscosity

    def setup(self, S):
        import numpy as np
        S.p.mu.from_numpy(np.array([mu_at_rest(S.materials[k], S.h, S.c0, S.cfl) for k in S.particles.mat],
                                   dtype=S.np_real))

    @ti.func
    def init_acc(self, S, i, acc: ti.template()):
        acc.mui = S.tmp.mu[i]

    @ti.func
    def finish(self, S, i, mi, acc: ti.template(), pt: ti.template()):
        gdot = shear_rate(acc.gv)
        mu_new = S.mat_mu[mi]
        rh = S.mat_rheo[mi]
        if rh == BINGHAM:
            mu_new = bingham(S.mat_mu[mi], S.mat_tau[mi], S.mat_m[mi], S.mat_mumax[mi], gdot)
            if S.mat_rest[mi] == 1 and S.mat_mumax[mi] * gdot < S.mat_tau[mi]:
                # unyielded: the stress the capped viscosity carries is below the yield stress,
                # so Bingham says the material moves as a rigid body; a bed on a fixed floor
                # rests. Without this it creeps at stress / mu_max.
                pt.v = ti.Vector([0.0, 0.0])
                S.p.v[i] = pt.v
        elif rh == CROSS:
            mu_new = cross(S.mat_mu0[mi], S.mat_mu[mi], S.mat_K[mi], S.mat_m1[mi], S.mat_mumax[mi], gdot)
        S.p.mu[i] = mu_new
        ti.atomic_max(S.stats[None].numax, mu_new / pt.rho)


@ti.data_oriented
class SPS(Module):
    """Sub-particle-scale (Smagorinsky) turbulence in Newtonian materials, paper 002 eq. 10; the
    stress is one step behind the velocity gradient it comes from."""
    name = "sps"
    on = {"sps": True}
    stats = {"numax": "real"}
    params = {"mixing_length": Param(0.0, "m", (0.0, None, True, True),
                                     "the SPS's length C_s dl as a mixing length l_m (nu_t = l_m^2 |S|); "
                                     "0: C_s dx", key="numerics.mixing_length")}

    def fields(self, real):
        return {"sps": ti.types.vector(3, real)}    # SPS stress / rho (xx, xy, yy)

    acc = {"sps_i": "vec3"}

    @ti.func
    def init_acc(self, S, i, acc: ti.template()):
        acc.sps_i = S.tmp.sps[i]

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        t_j = acc.sps_i                      # a wall particle mirrors i's SPS stress
        if nb.kj == FLUID:
            t_j = S.tmp.sps[j]
        acc.a += sps_accel(nb.m_j, acc.sps_i, acc.inv_rhoi, t_j, nb.ir_j, nb.gw)

    @ti.func
    def finish(self, S, i, mi, acc: ti.template(), pt: ti.template()):
        tau = ti.Vector([0.0, 0.0, 0.0])
        nut = 0.0
        newtonian = True
        if ti.static(S.physics.rheology):
            newtonian = S.mat_rheo[mi] == 0
        if newtonian:
            if ti.static(S.physics.turbulence == "k_equation"):
                nut = S.p.nut[i]          # TKE.finish, just before, from this step's k
                tau = tke_stress(acc.gv, nut, S.p.kt[i])
            else:
                tau, nut = sps_stress(acc.gv, S.dx, S.prm[None].mixing_length)
        S.p.sps[i] = tau
        ti.atomic_max(S.stats[None].numax, nut + S.mat_mu[mi] / pt.rho)


@ti.data_oriented
class Omega(Module):
    """The k equation's length from a transported specific dissipation omega (Wilcox 2006;
    tisph/terms/tke.py omega_update), bounded by the prescribed length (numerics.length_scale =
    "omega"): it moves with the particles, diffuses between them as k does and steps after TKE,
    which takes its length sqrt(k) / (C_mu^(1/4) omega) from the old omega."""
    name = "omega"
    on = {"sps": True, "turbulence": "k_equation", "tke_length": "omega"}
    acc = {"wi": "real", "dw": "real"}

    def fields(self, real):
        return {"wt": real}    # specific dissipation omega (1/s)

    def setup(self, S):
        """omega from the scene's k and l (the wall layer's equilibrium): omega = sqrt(k) / (C_mu^(1/4) l)."""
        import numpy as np
        k, l = S.p.kt.to_numpy().astype(float), S.p.lt.to_numpy().astype(float)
        S.p.wt.from_numpy((np.sqrt(k) / (CMU14 * np.maximum(l, 1e-12))).astype(S.np_real))

    @ti.func
    def init_acc(self, S, i, acc: ti.template()):
        acc.wi = S.tmp.wt[i]

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        s = S.tmp
        if nb.kj == FLUID and s.mat[j] == acc.mat:
            acc.dw += nb.vol_j * SIGMA_W * (acc.nuti + s.nut[j]) * (acc.wi - s.wt[j]) * r.dot(nb.gw) * nb.ie

    @ti.func
    def finish(self, S, i, mi, acc: ti.template(), pt: ti.template()):
        k = ti.max(acc.ki, K_FLOOR)     # TKE's acc: this particle's k and nu_t before the step
        S.p.wt[i] = omega_update(acc.wi, k, S.tmp.lt[i], strain2(acc.gv), acc.dw, S.prm[None].dt,
                                 S.prm[None].stress_limiter)


@ti.data_oriented
class TKE(Module):
    """A transported turbulent kinetic energy k for the SPS's eddy viscosity (the k-l model,
    tisph/terms/tke.py): k moves with the particles, diffuses between them and is made and
    dissipated per particle; the length l is per particle (the scene sets it; else
    numerics.mixing_length)."""
    name = "tke"
    on = {"sps": True, "turbulence": "k_equation"}
    acc = {"ki": "real", "nuti": "real", "dk": "real"}
    params = {"stress_limiter": Param(0.0, "-", (0.0, None, True, True),
                                      "Wilcox's (2006) stress limiter C_lim on the k equation's eddy viscosity "
                                      "(7/8 in k-omega 2006); 0: off", key="numerics.stress_limiter")}

    def fields(self, real):
        return {"kt": real,    # turbulent kinetic energy k (m2/s2)
                "lt": real,    # its length scale l (m)
                "nut": real}   # eddy viscosity C_mu^(1/4) sqrt(k) l (m2/s)

    def setup(self, S):
        """k and l where the scene gives them (ParticleSet.tke, .turbulence_length), else the
        floor and numerics.mixing_length."""
        import numpy as np
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
        if nb.kj == FLUID and s.mat[j] == acc.mat:
            acc.dk += nb.vol_j * (acc.nuti + s.nut[j]) * (acc.ki - s.kt[j]) * r.dot(nb.gw) * nb.ie / SIGMA_K

    @ti.func
    def finish(self, S, i, mi, acc: ti.template(), pt: ti.template()):
        l = S.tmp.lt[i]
        if ti.static(S.physics.tke_length == "omega"):      # k and omega both step from the old state
            l = ti.min(l, length_of_omega(acc.ki, S.tmp.wt[i]))
        s2 = strain2(acc.gv)
        clim = S.prm[None].stress_limiter
        k = tke_update(acc.ki, l, s2, acc.dk, S.prm[None].dt, clim)
        if ti.static(S.physics.rheology):
            if S.mat_rheo[mi] != 0:     # the SPS is the Newtonian materials' only
                k = K_FLOOR
        S.p.kt[i] = k
        S.p.nut[i] = eddy_viscosity(k, l, s2, clim)


@ti.data_oriented
class Drag(Module):
    """Drag between particles of different materials within a kernel of each other, paper 002
    eq. 16 made dimensionally consistent, equal and opposite pair by pair."""
    name = "drag"
    on = {"drag": True}
    params = {"drag_K": Param(0.0, "1/m", (0.0, None), "drag coefficient K of eq. 16")}

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        s = S.tmp
        if nb.kj == FLUID and s.mat[j] != acc.mat:
            w = S.w_scale * S.K.shape(nb.q)
            acc.a += drag_accel(S.prm[None].drag_K, acc.inv_rhoi, nb.vol_j, w, acc.vi, s.ve[j])


@ti.data_oriented
class DEM(Module):
    """Spring-dashpot contacts between sediment particles, paper 002 eqs. 17-28, with a
    per-particle contact history that moves with the re-sort. The eq. 27 step is taken only
    while grains touch or are about to."""
    name = "dem"
    on = {"dem": True}
    material = {"dem": MatParam(False, "-", "the material's particles touch as DEM grains", "int",
                                lambda v, mat, S: int(bool(v)))}
    params = {"kn": Param(0.0, "N/m", (0.0, None), "normal spring stiffness"),
              "ks": Param(0.0, "N/m", (0.0, None), "tangential spring stiffness"),
              "eta_n": Param(0.0, "N s/m", (0.0, None), "normal damping"),
              "eta_s": Param(0.0, "N s/m", (0.0, None), "tangential damping"),
              "mu_c": Param(0.0, "-", (0.0, None), "Coulomb friction coefficient"),
              "dc": Param("dx", "m", (0.0, None), "contact diameter"),
              "dt_dem": Param(lambda S, values: DEM.default_dt(S.materials, S.dx, values.get("kn", 0.0)), "s",
                              (0.0, None), "contact time step (default: eq. 27's critical step / 20)")}
    acc = {"cid_old": ti.types.vector(DEM_SLOTS, ti.i32), "es_old": "vec%d" % DEM_SLOTS,
           "cid_new": ti.types.vector(DEM_SLOTS, ti.i32), "es_new": "vec%d" % DEM_SLOTS,
           "nc": "int", "dem": "int", "mi": "real", "near": "int"}
    stats = {"dem_near": "int"}

    @staticmethod
    def default_dt(materials, dx, kn):
        """eq. 27's critical step of a grain of mass rho0 dx^2, over 20."""
        if kn <= 0:
            return 1e30
        rs = next((m["rho0"] for m in materials if m.get("dem")), materials[-1]["rho0"])
        return critical_step(rs * dx * dx, kn) / 20.0

    def fields(self, real):
        return {"cid": ti.types.vector(DEM_SLOTS, ti.i32),    # contact partners (ids; -1 free)
                "ces": ti.types.vector(DEM_SLOTS, real)}      # their tangential spring forces

    def setup(self, S):
        import numpy as np
        S.p.cid.from_numpy(np.full((S.n, DEM_SLOTS), -1, np.int32))

    @ti.func
    def init_acc(self, S, i, acc: ti.template()):
        acc.cid_old = S.tmp.cid[i]
        acc.es_old = S.tmp.ces[i]
        acc.cid_new = ti.Vector([-1] * DEM_SLOTS)
        acc.dem = S.mat_dem[acc.mat]
        acc.mi = S.tmp.m[i]

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        s = S.tmp
        prm = S.prm[None]
        if nb.kj == FLUID and s.mat[j] == acc.mat and acc.dem == 1 and r2 > 0.0:   # a grain, not itself
            # about to touch: within dc plus a margin no grain closes in one acoustic step
            # (h / c0 bounds it); the next step then honours the eq. 27 limit
            reach = prm.dc + 0.05 * S.dx + 2.0 * nb.v_ij.norm() * S.h / prm.c0
            if r2 < reach * reach:
                acc.near = 1
            if r2 < prm.dc * prm.dc:
                idj = s.id[j]
                es_old = 0.0
                for k in range(DEM_SLOTS):      # this pair's spring from the last step, if any
                    if acc.cid_old[k] == idj:
                        es_old = acc.es_old[k]
                f, es, on = contact_force(prm.kn, prm.ks, prm.eta_n, prm.eta_s, prm.mu_c, prm.dc, r,
                                          nb.v_ij, es_old, prm.dt)
                if on:
                    acc.a += f / acc.mi
                    if acc.nc < DEM_SLOTS:
                        acc.cid_new[acc.nc] = idj
                        acc.es_new[acc.nc] = es
                        acc.nc += 1

    @ti.func
    def finish(self, S, i, mi, acc: ti.template(), pt: ti.template()):
        # the contacts of this step, with their springs, replace the old list
        S.p.cid[i] = acc.cid_new
        S.p.ces[i] = acc.es_new
        if acc.near == 1:
            ti.atomic_max(S.stats[None].dem_near, 1)

    @ti.func
    def dt_limit(self, S, dt_new):
        # DEM springs are far stiffer than the fluid; their step (eq. 27) is needed only while
        # some grains touch, and otherwise would triple the step count for nothing
        if S.stats[None].dem_near == 1:
            dt_new = ti.min(dt_new, S.prm[None].dt_dem)
        S.stats[None].dem_near = 0
        return dt_new
