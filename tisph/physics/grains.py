"""The granular modules: rheology (Bingham, Cross), fluid-sediment drag and DEM contacts between
sediment particles. The turbulence closures are in physics/turbulence.py."""

import numpy as np
import taichi as ti

from ..hooks.module import MatParam, Module, Param
from ..particles import FLUID
from ..terms.dem import contact_force, critical_step
from ..terms.drag import drag_accel
from ..terms.rheology import BINGHAM, CROSS, RHEOLOGY_CODES, bingham, cross, shear_rate

DEM_SLOTS = 8  # contacts remembered per particle (a packed 2D lattice has at most 6 within dx)


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
        "rheology": MatParam(
            "newtonian", "-", "newtonian | bingham | cross", "int", lambda v, mat, S: RHEOLOGY_CODES[v], "rheo"
        ),
        "yield_stress": MatParam(0.0, "Pa", "Bingham yield stress tau_B", field="tau"),
        "regularisation": MatParam(1000.0, "s", "Papanastasiou exponent m", field="m"),
        "mu_max": MatParam(
            0.0,
            "Pa s",
            "cap on the effective viscosity (0: from the acoustic step)",
            convert=lambda v, mat, S: mu_cap(mat, S.h, S.c0, S.cfl),
            field="mumax",
        ),
        "mu0": MatParam(
            None,
            "Pa s",
            "Cross zero-shear viscosity (default: the viscosity)",
            convert=lambda v, mat, S: mat.get("viscosity", 0.0) if v is None else v,
        ),
        "K": MatParam(0.0, "s", "Cross time constant"),
        "m1": MatParam(1.0, "-", "Cross exponent"),
        "unyielded": MatParam(
            "creep",
            "-",
            "creep | rest: an unyielded Bingham material creeps or rests",
            "int",
            lambda v, mat, S: int(v == "rest"),
            "rest",
        ),
    }
    maxima = {"numax": "real"}

    @staticmethod
    def enabled(S):
        return S.physics.rheology

    def fields(self, real):
        return {"mu": real}  # effective viscosity

    def setup(self, S):
        S.p.mu.from_numpy(
            np.array([mu_at_rest(S.materials[k], S.h, S.c0, S.cfl) for k in S.particles.mat], dtype=S.np_real)
        )

    @ti.func
    def init_acc(self, S, i, acc: ti.template()):
        acc.mui = S.tmp.mu[i]

    @ti.func
    def finish(self, S, i, mi, acc: ti.template(), pt: ti.template()):
        gdot = shear_rate(acc.gv)
        mu_new = S.mat.mu[mi]
        rh = S.mat.rheo[mi]
        if rh == BINGHAM:
            mu_new = bingham(S.mat.mu[mi], S.mat.tau[mi], S.mat.m[mi], S.mat.mumax[mi], gdot)
            if S.mat.rest[mi] == 1 and S.mat.mumax[mi] * gdot < S.mat.tau[mi]:
                # unyielded: the stress the capped viscosity carries is below the yield stress,
                # so Bingham says the material moves as a rigid body; a bed on a fixed floor
                # rests. Without this it creeps at stress / mu_max.
                pt.v = ti.Vector([0.0, 0.0])
                S.p.v[i] = pt.v
        elif rh == CROSS:
            mu_new = cross(S.mat.mu0[mi], S.mat.mu[mi], S.mat.K[mi], S.mat.m1[mi], S.mat.mumax[mi], gdot)
        S.p.mu[i] = mu_new
        pt.numax = ti.max(pt.numax, mu_new / pt.rho)


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
    material = {
        "dem": MatParam(
            False, "-", "the material's particles touch as DEM grains", "int", lambda v, mat, S: int(bool(v))
        )
    }
    params = {
        "kn": Param(0.0, "N/m", (0.0, None), "normal spring stiffness"),
        "ks": Param(0.0, "N/m", (0.0, None), "tangential spring stiffness"),
        "eta_n": Param(0.0, "N s/m", (0.0, None), "normal damping"),
        "eta_s": Param(0.0, "N s/m", (0.0, None), "tangential damping"),
        "mu_c": Param(0.0, "-", (0.0, None), "Coulomb friction coefficient"),
        "dc": Param("dx", "m", (0.0, None), "contact diameter"),
        "dt_dem": Param(
            lambda S, values: DEM.default_dt(S.materials, S.dx, values.get("kn", 0.0)),
            "s",
            (0.0, None),
            "contact time step (default: eq. 27's critical step / 20)",
        ),
    }
    acc = {
        "cid_old": ti.types.vector(DEM_SLOTS, ti.i32),
        "es_old": f"vec{DEM_SLOTS}",
        "cid_new": ti.types.vector(DEM_SLOTS, ti.i32),
        "es_new": f"vec{DEM_SLOTS}",
        "nc": "int",
        "dem": "int",
        "mi": "real",
        "near": "int",
    }
    maxima = {"dem_near": "int"}

    @staticmethod
    def default_dt(materials, dx, kn):
        """eq. 27's critical step of a grain of mass rho0 dx^2, over 20."""
        if kn <= 0:
            return 1e30
        rs = next((m["rho0"] for m in materials if m.get("dem")), materials[-1]["rho0"])
        return critical_step(rs * dx * dx, kn) / 20.0

    def fields(self, real):
        return {
            "cid": ti.types.vector(DEM_SLOTS, ti.i32),  # contact partners (ids; -1 free)
            "ces": ti.types.vector(DEM_SLOTS, real),
        }  # their tangential spring forces

    def setup(self, S):
        S.p.cid.from_numpy(np.full((S.n, DEM_SLOTS), -1, np.int32))

    @ti.func
    def init_acc(self, S, i, acc: ti.template()):
        acc.cid_old = S.tmp.cid[i]
        acc.es_old = S.tmp.ces[i]
        acc.cid_new = ti.Vector([-1] * DEM_SLOTS)
        acc.dem = S.mat.dem[acc.mat]
        acc.mi = S.tmp.m[i]

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        s = S.tmp
        prm = S.prm[None]
        if nb.kj == FLUID and s.mat[j] == acc.mat and acc.dem == 1 and r2 > 0.0:  # a grain, not itself
            # about to touch: within dc plus a margin no grain closes in one acoustic step
            # (h / c0 bounds it); the next step then honours the eq. 27 limit
            reach = prm.dc + 0.05 * S.dx + 2.0 * nb.v_ij.norm() * S.h / prm.c0
            if r2 < reach * reach:
                acc.near = 1
            if r2 < prm.dc * prm.dc:
                idj = s.id[j]
                es_old = 0.0
                for k in range(DEM_SLOTS):  # this pair's spring from the last step, if any
                    if acc.cid_old[k] == idj:
                        es_old = acc.es_old[k]
                f, es, on = contact_force(
                    prm.kn, prm.ks, prm.eta_n, prm.eta_s, prm.mu_c, prm.dc, r, nb.v_ij, es_old, prm.dt
                )
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
        pt.dem_near = ti.max(pt.dem_near, acc.near)

    @ti.func
    def dt_limit(self, S, dt_new):
        # DEM springs are far stiffer than the fluid; their step (eq. 27) is needed only while
        # some grains touch, and otherwise would triple the step count for nothing
        if S.stats[None].dem_near == 1:
            dt_new = ti.min(dt_new, S.prm[None].dt_dem)
        S.stats[None].dem_near = 0
        return dt_new
