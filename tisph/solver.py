"""The WCSPH solver: particle fields, cell grid, and one fused kernel per time step.

One time step is one Taichi kernel (a handful of parallel loops), because on the CPU each kernel
launch costs ~40 us and each parallel loop ~15 us: separate kernels for binning, sorting,
forces and integration would cost more than the physics at a few thousand particles.

Time integration is velocity Verlet (kick-drift-kick) with one force evaluation per step:
    x^{n+1} = x^n + dt v^n + dt^2/2 a^n (+ dt * XSPH^n)
    v^{n+1/2} = v^n + dt/2 a^n,  rho^{n+1/2} = rho^n + dt/2 drho^n
    forces at x^{n+1} with the predicted v^n + dt a^n and rho^n + dt drho^n
    v^{n+1} = v^{n+1/2} + dt/2 a^{n+1},  rho^{n+1} = rho^{n+1/2} + dt/2 drho^{n+1}
Second order, symplectic for the conservative part, half the force passes of predictor-corrector.
"""

import math

import numpy as np
import taichi as ti

from .config import Physics
from .kernels import get_kernel
from .particles import FLUID, MOVING, OUT, OUTFLOW
from .terms.continuity import continuity
from .terms.pressure import tait, pressure_accel
from .terms.viscosity import monaghan_mu, artificial_viscosity, laminar_viscosity
from .terms.diffusion import density_diffusion, hydrostatic_density_difference
from .terms.xsph import xsph
from .terms.repulsive import lennard_jones
from .terms.sps import sps_stress, sps_accel
from .terms.drag import drag_accel
from .terms.dem import contact_force
from .terms.rheology import shear_rate, bingham, cross, harmonic_pair, BINGHAM, CROSS, RHEOLOGY_CODES

KAPPA = 0.42    # von Karman's constant of the log law, paper 002 eq. 32
DEM_SLOTS = 8   # contacts remembered per particle (a packed 2D lattice has at most 6 within dx)

# Codes of the instability detector, most severe last.
BAD_NONE, BAD_DENSITY, BAD_SPEED, BAD_SPILL, BAD_WALL, BAD_LEAK, BAD_DT, BAD_NAN = 0, 1, 2, 3, 4, 5, 6, 7
BAD_TEXT = {
    BAD_SPILL: ("a fluid particle went over a side wall and out of the tank",
                "a jet or splash overtopped the walls: raise the walls, or the sound speed is too low "
                "and the run-up too violent"),
    BAD_WALL: ("a fluid particle crossed a wall",
               "particles penetrated the wall: wall force too weak (numerics.wall_strength), walls too "
               "thin (numerics.wall_layers), sound speed too low for the impact, or time step too large"),
    BAD_LEAK: ("a fluid particle left the simulation domain",
               "particles penetrated the wall or were thrown out of the domain"),
    BAD_DENSITY: ("density left the allowed band around rest density",
                  "particles compressed against a wall or torn apart: time step too large for this "
                  "sound speed, or sound speed too low for the flow"),
    BAD_SPEED: ("speed exceeded the sound speed",
                "the flow is faster than the equation of state allows: raise c0 or check forces"),
    BAD_DT: ("time step collapsed below its floor",
             "a force blew up (particles penetrated the wall, or two particles overlap)"),
    BAD_NAN: ("NaN or Inf in acceleration or density",
              "dt too large for this sound speed, or particles penetrated the wall"),
}


@ti.data_oriented
class ParticleFields:
    """Struct of arrays: one Taichi field per particle property.

    Separate fields rather than one ti.Struct field: the neighbour scan reads positions from a
    compact array, which measured 1.75x faster than an SOA struct field and 1.3x than AOS here.
    """

    def __init__(self, members, n):
        self.names = tuple(members)
        for k, dt in members.items():
            setattr(self, k, ti.field(dt, n) if not hasattr(dt, "n") else ti.Vector.field(dt.n, dt.dtype, n))


@ti.data_oriented
class Solver:
    def __init__(self, physics: Physics, particles, materials, domain, params: dict, outflow=(),
                 container=None):
        """particles: ParticleSet; materials: list of dicts (name, rho0, viscosity, B);
        domain: ((xlo, ylo), (xhi, yhi)); params: dx, h, c0, alpha, xsph, delta, g, wall_D,
        wall_r0, cfl, dt_max, density_band."""
        self.physics = physics
        # open boundaries: boxes (x0, y0, x1, y1); fluid entering one leaves the simulation
        self.outflow = tuple(tuple(float(v) for v in z) for z in outflow)
        # The box the walls enclose, (x0, y0, x1, y1[, side-wall top]): fluid outside it (below
        # the top of the side walls, above which it may overtop) crossed a wall, and the run stops.
        # It counts as crossed once past the first row of wall particles, dx/2 behind the surface.
        self.container = None
        if container is not None:
            x0, y0, x1, y1, *top = (float(v) for v in container)
            tol = 0.5 * float(params["dx"])
            big = 1e30   # float32-safe stand-in for an open side
            self.container = (max(x0 - tol, -big), max(y0 - tol, -big), min(x1 + tol, big),
                              min(y1 + tol, big), min(top[0] if top else big, big))
        self.has_container = self.container is not None
        self.K = get_kernel(physics.kernel)
        self.n = len(particles)
        if self.n == 0:
            raise ValueError("no particles to simulate")
        self.dx = float(params["dx"])
        self.h = float(params["h"])
        self.c0 = float(params["c0"])
        self.params_cfl = float(params.get("cfl", 0.4))
        self.materials = materials
        real = ti.lang.impl.get_runtime().default_fp
        self.real = real
        vec2 = ti.types.vector(2, real)

        members = dict(x=vec2, v=vec2, a=vec2, rho=real, drho=real, m=real,
                       kind=ti.i32, mat=ti.i32, id=ti.i32, ve=vec2, rhoe=real, p=real, ir=real)
        # ir = 1 / rhoe, set once per particle so the pair loop divides by no density
        if physics.xsph:
            members["xs"] = vec2          # XSPH correction, only when the term is on
        if physics.rheology:
            members["mu"] = real          # effective viscosity, only with a non-Newtonian material
        if physics.sps:
            members["sps"] = ti.types.vector(3, real)   # SPS stress / rho (xx, xy, yy), one dt behind
        if physics.dem:
            members["cid"] = ti.types.vector(DEM_SLOTS, ti.i32)   # contact partners (ids; -1 free)
            members["ces"] = ti.types.vector(DEM_SLOTS, real)     # their tangential spring forces
        if physics.paddle != "none":
            members["x0"] = vec2          # a paddle particle's position at zero displacement
        if physics.noslip:
            members["wn"] = vec2          # wall normal (into the fluid) and distance behind the
            members["wd"] = real          # wall surface, for the no-slip ghost velocity
        self.members = tuple(members)
        self._member_types = dict(members)
        self.bak = None
        self.p = ParticleFields(members, self.n)
        self.tmp = ParticleFields(members, self.n)
        # (source, sorted copy) pairs: the reorder copies every member in one compile-time loop
        self.pairs = [(getattr(self.p, k), getattr(self.tmp, k)) for k in members]

        # Cell grid: cell size = kernel support, so neighbours lie in the 3 x 3 block of cells.
        lo, hi = np.asarray(domain[0], float), np.asarray(domain[1], float)
        self.support = self.K.support * self.h
        # Cells of half the support and a 5 x 5 stencil: 25 h^2 of candidates instead of 36 h^2.
        self.cdiv = 2
        self.cell = self.support / self.cdiv
        self.cell_y = self.cell
        self.ny = max(1, int(math.ceil((hi[1] - lo[1]) / self.cell)))
        if physics.periodic_x:
            # the domain's x extent is one period; cells tile it exactly (slightly wider than needed)
            self.period = float(hi[0] - lo[0])
            self.nx = int(math.floor(self.period / self.cell))
            if self.nx < 2 * self.cdiv + 1:
                raise ValueError(f"periodic length {self.period:g} m is shorter than {2 * self.cdiv + 1} cells "
                                 f"of {self.cell:g} m: lengthen the domain or reduce h")
            self.cell_x = self.period / self.nx
        else:
            self.period = 0.0
            self.nx = max(1, int(math.ceil((hi[0] - lo[0]) / self.cell)))
            self.cell_x = self.cell
        self.ncells = self.nx * self.ny
        self.lo = (float(lo[0]), float(lo[1]))
        self.hi = (float(lo[0] + self.nx * self.cell_x), float(lo[1] + self.ny * self.cell_y))
        self.domain = (tuple(lo), tuple(hi))
        self.key = ti.field(ti.i32, self.n)
        self.order = ti.field(ti.i32, self.n)
        self.cnt = ti.field(ti.i32, self.ncells + 2)
        self.fcnt = ti.field(ti.i32, self.ncells + 2)  # fluid particles per cell
        self.start = ti.field(ti.i32, self.ncells + 2)

        nmat = len(materials)
        self.mat_rho0 = ti.field(real, nmat)
        self.mat_B = ti.field(real, nmat)
        self.mat_mu = ti.field(real, nmat)       # Newtonian mu, Bingham mu_B, Cross mu_inf
        if physics.rheology:
            self.mat_rheo = ti.field(ti.i32, nmat)
            self.mat_tau = ti.field(real, nmat)      # Bingham yield stress
            self.mat_m = ti.field(real, nmat)        # Papanastasiou regularisation (s)
            self.mat_mumax = ti.field(real, nmat)    # cap on the effective viscosity
            self.mat_mu0 = ti.field(real, nmat)      # Cross zero-shear viscosity
            self.mat_K = ti.field(real, nmat)        # Cross time constant (s)
            self.mat_m1 = ti.field(real, nmat)       # Cross exponent
            self.mat_rest = ti.field(ti.i32, nmat)   # 1: unyielded Bingham material is held at rest
        if physics.periodic_x:
            # a pressure gradient -rho_0 drive pushes each material by rho_0 / rho of it: the pore
            # water carries it through a sediment layer, which does not feel it at its own density
            self.mat_drive = ti.field(real, nmat)
            for k, mat in enumerate(materials):
                self.mat_drive[k] = materials[0]["rho0"] / mat["rho0"]
        if physics.dem:
            self.mat_dem = ti.field(ti.i32, nmat)    # 1: the material's particles touch as DEM grains
        for k, mat in enumerate(materials):
            if physics.dem:
                self.mat_dem[k] = int(bool(mat.get("dem", False)))
            self.mat_rho0[k] = mat["rho0"]
            self.mat_B[k] = mat["B"]
            self.mat_mu[k] = mat.get("viscosity", 0.0)
            if physics.rheology:
                self.mat_rheo[k] = RHEOLOGY_CODES[mat.get("rheology", "newtonian")]
                self.mat_tau[k] = mat.get("yield_stress", 0.0)
                self.mat_m[k] = mat.get("regularisation", 1000.0)
                self.mat_mumax[k] = self.mu_cap(mat)
                self.mat_mu0[k] = mat.get("mu0", mat.get("viscosity", 0.0))
                self.mat_K[k] = mat.get("K", 0.0)
                self.mat_m1[k] = mat.get("m1", 1.0)
                self.mat_rest[k] = int(mat.get("unyielded", "creep") == "rest")

        # Runtime parameters: read by kernels from a field, so changing them needs no recompile.
        prm = dict(c0=real, alpha=real, eps=real, delta=real, g=vec2, wall_D=real, wall_r0=real,
                   cfl=real, dt_max=real, dt_visc=real, band=real, dt=real, dt_floor=real,
                   pd=real, pv=real, pivot=vec2,   # paddle: displacement (m or rad) and its rate
                   drive=vec2,     # a driving pressure gradient / rho of material 0 (periodic current)
                   drag_K=real, kn=real, ks=real, eta_n=real, eta_s=real, mu_c=real, dc=real,
                   dt_dem=real)     # eq. 27 step, taken only while DEM grains touch or are about to
        self.prm = ti.types.struct(**prm).field(shape=())
        nu_max = max((m.get("viscosity", 0.0) / m["rho0"] for m in materials), default=0.0)
        dt_visc = 0.125 * self.h ** 2 / nu_max if (physics.laminar_viscosity and nu_max > 0) else 1e30
        self.params = dict(c0=self.c0, alpha=params.get("alpha", 0.0), eps=params.get("xsph", 0.0),
                           delta=params.get("delta", 0.0), g=tuple(params.get("g", (0.0, -9.81))),
                           wall_D=params.get("wall_D", 0.0), wall_r0=params.get("wall_r0", self.dx),
                           cfl=params.get("cfl", 0.2), dt_max=params.get("dt_max", 1e-3),
                           dt_visc=dt_visc, band=params.get("density_band", 0.1), dt=0.0,
                           dt_floor=params.get("dt_floor", 1e-9), pd=0.0, pv=0.0,
                           pivot=tuple(params.get("pivot", (0.0, 0.0))), drive=(0.0, 0.0), drag_K=params.get("drag_K", 0.0),
                           kn=params.get("kn", 0.0), ks=params.get("ks", 0.0), eta_n=params.get("eta_n", 0.0),
                           eta_s=params.get("eta_s", 0.0), mu_c=params.get("mu_c", 0.0),
                           dc=params.get("dc", self.dx), dt_dem=params.get("dt_dem", 1e30))
        self.motion = params.get("motion")   # motion(t) -> (displacement, rate), for the paddle
        for k, v in self.params.items():
            setattr(self.prm[None], k, v)

        S = ti.types.struct(amax2=real, mumax=real, bad_code=ti.i32, bad_idx=ti.i32,
                            leaked=ti.i32, rhodev=real, numax=real, dem_near=ti.i32)
        self.stats = S.field(shape=())

        # Initial state.
        self.p.x.from_numpy(particles.x.astype(np.float64 if real == ti.f64 else np.float32))
        self.p.v.from_numpy(particles.v.astype(np.float64 if real == ti.f64 else np.float32))
        self.p.rho.from_numpy(particles.rho.astype(np.float64 if real == ti.f64 else np.float32))
        self.p.m.from_numpy(particles.m.astype(np.float64 if real == ti.f64 else np.float32))
        self.p.kind.from_numpy(particles.kind.astype(np.int32))
        self.p.mat.from_numpy(particles.mat.astype(np.int32))
        self.p.id.from_numpy(np.arange(self.n, dtype=np.int32))
        if physics.dem:
            self.p.cid.from_numpy(np.full((self.n, DEM_SLOTS), -1, np.int32))
        if physics.paddle != "none":
            self.p.x0.from_numpy(particles.x.astype(np.float64 if real == ti.f64 else np.float32))
        if physics.noslip:
            fp = np.float64 if real == ti.f64 else np.float32
            self.p.wn.from_numpy(particles.wall_normal.astype(fp))
            self.p.wd.from_numpy(particles.wall_dist.astype(fp))
        if physics.rheology:  # at rest: each material's zero-shear viscosity
            self.p.mu.from_numpy(np.array([self._mu_at_rest(materials[k]) for k in particles.mat],
                                          dtype=np.float64 if real == ti.f64 else np.float32))
        self._reset_stats()
        self.shepard_every = int(params.get("shepard_every", 0))
        self.steps = 0
        self.time = 0.0
        self._primed = False

        # Compile-time constants baked into the kernels.
        self.inv_h = 1.0 / self.h
        self.w_scale = self.K.sigma / self.h ** 2
        self.g_scale = self.K.sigma / self.h ** 4
        self.eta2 = 0.01 * self.h * self.h
        self.is_dbc = physics.wall == "dynamic"

    # ------------------------------------------------------------------ helpers
    def mu_cap(self, mat):
        """The effective-viscosity cap of a material: its mu_max, or with mu_max = 0 ("auto") the
        viscosity whose explicit viscous step 0.125 h^2 rho / mu equals the acoustic step
        cfl h / c0, so a plastic material costs no extra time steps. Below yield such a material
        creeps at about (stress / mu_cap); a larger mu_max makes it stiffer and the run slower in
        proportion."""
        mm = mat.get("mu_max", 0.0)
        if mm > 0:
            return mm
        return 0.125 * self.h * mat["rho0"] * self.c0 / self.params_cfl

    def _mu_at_rest(self, mat):
        r = mat.get("rheology", "newtonian")
        mu = mat.get("viscosity", 0.0)
        if r == "bingham":
            mu = mu + mat.get("yield_stress", 0.0) * mat.get("regularisation", 1000.0)
        elif r == "cross":
            mu = mat.get("mu0", mu)
        return min(mu, self.mu_cap(mat)) if r != "newtonian" else mu

    def _reset_stats(self):
        s = self.stats[None]
        s.amax2 = 0.0
        s.mumax = 0.0
        s.bad_code = 0
        s.bad_idx = 2**31 - 1
        s.rhodev = 0.0

    @ti.func
    def cell_of(self, x):
        c = ti.floor((x - ti.Vector(self.lo)) / ti.Vector([self.cell_x, self.cell_y]), ti.i32)
        return ti.Vector([ti.max(0, ti.min(self.nx - 1, c[0])), ti.max(0, ti.min(self.ny - 1, c[1]))])

    @ti.func
    def inside(self, x):
        return self.lo[0] <= x[0] < self.hi[0] and self.lo[1] <= x[1] < self.hi[1]

    @ti.func
    def wrap(self, x):
        """Periodic in x: back into [lo, lo + period)."""
        y = x
        if ti.static(self.physics.periodic_x):
            y[0] = x[0] - self.period * ti.floor((x[0] - self.lo[0]) / self.period)
            # in float32 a particle a hair left of lo wraps to exactly lo + period (measured: a
            # sand grain at x = -1e-8 became x = 1.0 and counted as leaving the domain)
            if y[0] >= self.lo[0] + self.period:
                y[0] = self.lo[0]
        return y

    @ti.func
    def for_neighbours(self, src: ti.template(), i, xi, task: ti.template(), acc: ti.template()):
        """Visit every j of `src` within the kernel support of xi: task(i, j, r, r2, acc).

        j = i is visited too: a `j != i` test in this loop measured 2.7x slower, and every
        gradient term vanishes at r = 0 anyway; a task that must skip itself tests r2 > 0.

        Cells are numbered row by row, so the cells of a stencil row form one contiguous range of
        the sorted particles: one range per row instead of one per cell.
        """
        c = self.cell_of(xi)
        if ti.static(not self.physics.periodic_x):
            x0 = ti.max(c[0] - self.cdiv, 0)
            x1 = ti.min(c[0] + self.cdiv, self.nx - 1)
            for dy in range(-self.cdiv, self.cdiv + 1):  # runtime: one copy of the pair tasks (compiles 4x faster)
                cy = c[1] + dy
                if 0 <= cy < self.ny:
                    row = cy * self.nx
                    for j in range(self.start[row + x0], self.start[row + x1 + 1]):
                        r = xi - src.x[j]
                        r2 = r.dot(r)
                        if r2 < self.support * self.support:
                            task(i, j, r, r2, acc)
        else:
            # periodic in x: cells wrap, so a row is no longer one range; r is the nearest image
            for dy in range(-self.cdiv, self.cdiv + 1):
                cy = c[1] + dy
                if 0 <= cy < self.ny:
                    row = cy * self.nx
                    # a runtime loop: unrolled, the 25 copies of every pair task took ~45 s to compile
                    for dxo in range(-self.cdiv, self.cdiv + 1):
                        cx = (c[0] + dxo + self.nx) % self.nx
                        for j in range(self.start[row + cx], self.start[row + cx + 1]):
                            r = xi - src.x[j]
                            r[0] -= self.period * ti.round(r[0] / self.period)
                            r2 = r.dot(r)
                            if r2 < self.support * self.support:
                                task(i, j, r, r2, acc)

    @ti.func
    def fluid_near(self, xi):
        """Whether any fluid particle lies in the cells around xi (from this step's counts)."""
        c = self.cell_of(xi)
        found = False
        for dy in ti.static(range(-self.cdiv, self.cdiv + 1)):
            cy = c[1] + dy
            if 0 <= cy < self.ny:
                for dxo in range(-self.cdiv, self.cdiv + 1):
                    cx = c[0] + dxo
                    if ti.static(self.physics.periodic_x):
                        cx = (cx + self.nx) % self.nx
                    if 0 <= cx < self.nx:
                        if self.fcnt[cy * self.nx + cx] > 0:
                            found = True
        return found

    # ------------------------------------------------------------------ pair tasks
    @ti.func
    def fluid_pair(self, i, j, r, r2, acc: ti.template()):
        """All enabled terms for fluid particle i from neighbour j, unrolled at compile time."""
        s = self.tmp
        kj = s.kind[j]
        prm = self.prm[None]
        rho_j = s.rhoe[j]
        ir_j = s.ir[j]
        p_j = s.p[j]
        if ti.static(self.physics.wall == "repulsive"):
            if kj != FLUID:
                # paper 000 eq. 6 stops penetration; in the SPH sums the inert wall particle
                # mirrors i's pressure plus the hydrostatic difference, completing the kernel
                acc.a += lennard_jones(prm.wall_D, prm.wall_r0, r, r2)
                rho_j = acc.rhoi
                ir_j = acc.inv_rhoi
                p_j = acc.pi - acc.rhoi * prm.g.dot(r)
        rn = ti.sqrt(r2)
        q = rn * self.inv_h
        gw = self.g_scale * self.K.fshape(q) * r
        m_j = s.m[j]
        vol_j = m_j * ir_j
        v_ij = acc.vi - s.ve[j]
        acc.drho += continuity(acc.rhoi, vol_j, v_ij, gw)
        acc.a += pressure_accel(m_j, acc.pi, p_j, acc.inv_rhoi, ir_j, gw)
        if ti.static(self.physics.artificial_viscosity):
            mu = monaghan_mu(self.h, v_ij, r, r2)
            acc.a += artificial_viscosity(m_j, prm.alpha, prm.c0, mu, acc.inv_rhoi, ir_j, gw)
            acc.mu = ti.max(acc.mu, -mu)
        v_visc = v_ij
        if ti.static(self.physics.noslip):
            if kj != FLUID:
                # Morris et al. (1997), paper 002 eq. 39: the wall particle carries the ghost
                # velocity u_B = -(d_B/d_A) u_A (relative to the wall), so the no-slip sits on
                # the wall surface; d_B/d_A capped at 1.5 as Morris does for close approach
                d_i = r.dot(s.wn[j]) - s.wd[j]
                ratio = ti.min(s.wd[j] / ti.max(d_i, 1e-6 * self.h), 1.5)
                v_visc = (1.0 + ratio) * v_ij
        if ti.static(self.physics.laminar_viscosity):
            mu_j = acc.mui                      # a wall particle takes the fluid's viscosity
            if kj == FLUID:
                if ti.static(self.physics.rheology):
                    mu_j = s.mu[j]
                else:
                    mu_j = self.mat_mu[s.mat[j]]
            acc.a += laminar_viscosity(m_j, harmonic_pair(acc.mui, mu_j), acc.inv_rhoi, ir_j,
                                       v_visc, r, r2, gw, self.eta2)
        if ti.static(self.physics.rheology or self.physics.sps):
            acc.gv += vol_j * (-v_visc).outer_product(gw)  # velocity gradient: shear rate, SPS stress
        if ti.static(self.physics.sps):
            t_j = acc.sps_i                      # a wall particle mirrors i's SPS stress
            if kj == FLUID:
                t_j = s.sps[j]
            acc.a += sps_accel(m_j, acc.sps_i, acc.inv_rhoi, t_j, ir_j, gw)
        if ti.static(self.physics.dem):
            if kj == FLUID and s.mat[j] == acc.mat and acc.dem == 1 and r2 > 0.0:   # a grain, not itself
                # about to touch: within dc plus a margin no grain closes in one acoustic step
                # (h / c0 bounds it); the next step then honours the eq. 27 limit
                reach = prm.dc + 0.05 * self.dx + 2.0 * v_ij.norm() * self.h / prm.c0
                if r2 < reach * reach:
                    acc.near = 1
                if r2 < prm.dc * prm.dc:
                    idj = s.id[j]
                    es_old = 0.0
                    for k in range(DEM_SLOTS):      # this pair's spring from the last step, if any
                        if acc.cid_old[k] == idj:
                            es_old = acc.es_old[k]
                    f, es, on = contact_force(prm.kn, prm.ks, prm.eta_n, prm.eta_s, prm.mu_c, prm.dc, r,
                                              v_ij, es_old, prm.dt)
                    if on:
                        acc.a += f / acc.mi
                        if acc.nc < DEM_SLOTS:
                            acc.cid_new[acc.nc] = idj
                            acc.es_new[acc.nc] = es
                            acc.nc += 1
        if ti.static(self.physics.drag):
            if kj == FLUID and s.mat[j] != acc.mat:
                w = self.w_scale * self.K.shape(q)
                acc.a += drag_accel(prm.drag_K, acc.inv_rhoi, vol_j, w, acc.vi, s.ve[j])
        if ti.static(self.physics.density_diffusion != "none"):
            if kj == FLUID and s.mat[j] == acc.mat:
                hyd = 0.0
                if ti.static(self.physics.density_diffusion == "fourtakas"):
                    hyd = hydrostatic_density_difference(acc.rho0_c02, prm.g, r)
                acc.drho += density_diffusion(prm.delta, self.h, prm.c0, vol_j, acc.rhoi,
                                              rho_j, hyd, r, r2, gw)
        if ti.static(self.physics.xsph):
            if kj == FLUID:
                w = self.w_scale * self.K.shape(q)
                acc.xs += xsph(m_j, -v_ij, acc.inv_rhoi, ir_j, w)

    @ti.func
    def boundary_pair(self, i, j, r, r2, acc: ti.template()):
        """Dynamic boundary particle i: continuity only, from the fluid around it (DBC)."""
        s = self.tmp
        if s.kind[j] == FLUID:
            gw = self.g_scale * self.K.fshape(ti.sqrt(r2) * self.inv_h) * r
            acc.drho += continuity(acc.rhoi, s.m[j] * s.ir[j], acc.vi - s.ve[j], gw)

    # ------------------------------------------------------------------ the step
    @ti.func
    def is_bad(self, x):
        return ti.math.isnan(x) or ti.math.isinf(x)

    @ti.kernel
    def _step(self) -> ti.f32:
        prm = self.prm[None]
        dt = prm.dt
        ncell = self.ncells
        # 1. drift and half kick, leak check, cell keys and counts
        for i in range(self.n):
            k = self.p.kind[i]
            key = ncell
            if k >= 0:
                if k == FLUID:
                    drift = self.p.v[i]
                    if ti.static(self.physics.xsph):
                        drift += prm.eps * self.p.xs[i]
                    self.p.x[i] = self.wrap(self.p.x[i] + dt * drift + 0.5 * dt * dt * self.p.a[i])
                    self.p.v[i] += 0.5 * dt * self.p.a[i]
                    self.p.rho[i] += 0.5 * dt * self.p.drho[i]
                else:
                    if k == MOVING:
                        if ti.static(self.physics.paddle == "piston"):
                            # prescribed: x = x0 + X(t_new), v = X'(t_new)
                            self.p.x[i] = self.p.x0[i] + ti.Vector([prm.pd, 0.0])
                            self.p.v[i] = ti.Vector([prm.pv, 0.0])
                        elif ti.static(self.physics.paddle == "flap"):
                            # rotation by theta(t_new) about the hinge; v = omega x (x - hinge)
                            rel = self.p.x0[i] - prm.pivot
                            cs, sn = ti.cos(prm.pd), ti.sin(prm.pd)
                            rr = ti.Vector([cs * rel[0] + sn * rel[1], -sn * rel[0] + cs * rel[1]])
                            self.p.x[i] = prm.pivot + rr
                            self.p.v[i] = prm.pv * ti.Vector([rr[1], -rr[0]])
                        else:
                            self.p.x[i] = self.wrap(self.p.x[i] + dt * self.p.v[i])
                    if ti.static(self.is_dbc):
                        self.p.rho[i] += 0.5 * dt * self.p.drho[i]
                gone = False
                if ti.static(len(self.outflow) > 0):
                    if k == FLUID:
                        for z in ti.static(self.outflow):
                            xx = self.p.x[i]
                            if z[0] <= xx[0] <= z[2] and z[1] <= xx[1] <= z[3]:
                                gone = True
                if ti.static(self.has_container):
                    if k == FLUID and not gone:
                        xx = self.p.x[i]
                        b = self.container
                        if xx[1] < b[1] or xx[1] > b[3] or (xx[1] < b[4] and (xx[0] < b[0] or xx[0] > b[2])):
                            code = BAD_WALL
                            # checked every step, a particle pushed through a side wall is caught
                            # within dx of it; one found further out came over the top
                            if xx[1] >= b[1] and (xx[0] < b[0] - self.dx or xx[0] > b[2] + self.dx):
                                code = BAD_SPILL
                            ti.atomic_max(self.stats[None].bad_code, code)
                            ti.atomic_min(self.stats[None].bad_idx, self.p.id[i])
                if gone:
                    self.p.kind[i] = OUTFLOW
                elif self.inside(self.p.x[i]):
                    c = self.cell_of(self.p.x[i])
                    key = c[1] * self.nx + c[0]
                    if self.p.kind[i] == FLUID:
                        ti.atomic_add(self.fcnt[key], 1)
                else:
                    if k == FLUID:
                        ti.atomic_max(self.stats[None].bad_code, BAD_LEAK)
                        ti.atomic_min(self.stats[None].bad_idx, self.p.id[i])
                    self.p.kind[i] = OUT
                    ti.atomic_add(self.stats[None].leaked, 1)
            self.key[i] = key
            ti.atomic_add(self.cnt[key], 1)
        # 2. prefix sum (serial: cells are few next to particles); cnt becomes a write cursor
        ti.loop_config(serialize=True)
        for c in range(ncell + 1):
            if c == 0:
                self.start[0] = 0
            self.start[c + 1] = self.start[c] + self.cnt[c]
            self.cnt[c] = self.start[c]
        # 3. scatter indices into their cells
        for i in range(self.n):
            slot = ti.atomic_add(self.cnt[self.key[i]], 1)
            self.order[slot] = i
        # 4. per cell: order by id (deterministic sums), gather the struct, prepare evaluation state
        for c in range(ncell + 1):
            s0 = self.start[c]
            s1 = self.start[c + 1]
            self.cnt[c] = 0
            if c < ncell:
                for a in range(s0 + 1, s1):
                    v = self.order[a]
                    vid = self.p.id[v]
                    b = a - 1
                    while b >= s0 and self.p.id[self.order[b]] > vid:
                        self.order[b + 1] = self.order[b]
                        b -= 1
                    self.order[b + 1] = v
            for a in range(s0, s1):
                src = self.order[a]
                for fp, ft in ti.static(self.pairs):
                    ft[a] = fp[src]
                k = self.tmp.kind[a]
                if k == FLUID:
                    self.tmp.ve[a] = self.tmp.v[a] + 0.5 * dt * self.tmp.a[a]
                    self.tmp.rhoe[a] = self.tmp.rho[a] + 0.5 * dt * self.tmp.drho[a]
                elif k >= 0:
                    self.tmp.ve[a] = self.tmp.v[a]
                    re = self.tmp.rho[a]
                    if ti.static(self.is_dbc):
                        re = ti.max(re + 0.5 * dt * self.tmp.drho[a], self.mat_rho0[self.tmp.mat[a]])
                    self.tmp.rhoe[a] = re
                mt = self.tmp.mat[a]
                self.tmp.p[a] = tait(self.tmp.rhoe[a], self.mat_rho0[mt], self.mat_B[mt])
                self.tmp.ir[a] = 1.0 / self.tmp.rhoe[a]
        # 5. forces at the new positions, and the closing half kick
        for i in range(self.n):
            for fp, ft in ti.static(self.pairs):
                fp[i] = ft[i]
            k = self.tmp.kind[i]
            if k == FLUID:
                mi = self.tmp.mat[i]
                mui = self.mat_mu[mi]
                if ti.static(self.physics.rheology):
                    mui = self.tmp.mu[i]
                acc = ti.Struct(a=ti.Vector([0.0, 0.0]), drho=0.0, xs=ti.Vector([0.0, 0.0]), mu=0.0,
                                vi=self.tmp.ve[i], rhoi=self.tmp.rhoe[i], pi=self.tmp.p[i],
                                inv_rhoi=self.tmp.ir[i], mui=mui, mat=mi,
                                rho0_c02=self.mat_rho0[mi] / (prm.c0 * prm.c0),
                                gv=ti.Matrix([[0.0, 0.0], [0.0, 0.0]]), sps_i=ti.Vector([0.0, 0.0, 0.0]),
                                cid_old=ti.Vector([-1] * DEM_SLOTS), es_old=ti.Vector([0.0] * DEM_SLOTS),
                                cid_new=ti.Vector([-1] * DEM_SLOTS), es_new=ti.Vector([0.0] * DEM_SLOTS),
                                nc=0, dem=0, mi=1.0, near=0)   # DEM members: unused and compiled away when DEM is off
                if ti.static(self.physics.sps):
                    acc.sps_i = self.tmp.sps[i]
                if ti.static(self.physics.dem):
                    acc.cid_old = self.tmp.cid[i]
                    acc.es_old = self.tmp.ces[i]
                    acc.dem = self.mat_dem[mi]
                    acc.mi = self.tmp.m[i]
                self.for_neighbours(self.tmp, i, self.tmp.x[i], self.fluid_pair, acc)
                a = acc.a + prm.g
                if ti.static(self.physics.periodic_x):
                    a += prm.drive * self.mat_drive[mi]
                v = self.tmp.v[i] + 0.5 * dt * a
                if ti.static(len(self.physics.damping) == 3):
                    # absorbing zone: implicit relaxation of the velocity, ramped in quadratically
                    zd = self.physics.damping
                    s = ti.min(ti.max((self.tmp.x[i][0] - zd[0]) / (zd[1] - zd[0]), 0.0), 1.0)
                    v = v / (1.0 + dt * zd[2] * s * s)
                if ti.static(len(self.physics.inflow) == 7):
                    # inflow zone of a periodic current: the recirculated wake is relaxed back to
                    # the log law u = (u*/kappa) ln(z/z0) (paper 002 eq. 32), as an inlet would
                    # feed it; ramped in and out as sin^2 so no front forms
                    zi = ti.static(self.physics.inflow)
                    xr = (self.tmp.x[i][0] - zi[0]) / (zi[1] - zi[0])
                    if mi == ti.static(int(zi[3])) and 0.0 < xr < 1.0:
                        s = ti.sin(math.pi * xr) ** 2
                        z = ti.max(self.tmp.x[i][1] - zi[4], zi[6])
                        ut = ti.Vector([zi[5] / KAPPA * ti.log(z / zi[6]), 0.0])
                        v = (v + dt * zi[2] * s * ut) / (1.0 + dt * zi[2] * s)
                rho = self.tmp.rho[i] + 0.5 * dt * acc.drho
                self.p.a[i] = a
                self.p.drho[i] = acc.drho
                self.p.v[i] = v
                self.p.rho[i] = rho
                if ti.static(self.physics.xsph):
                    self.p.xs[i] = acc.xs
                if ti.static(self.physics.dem):
                    # the contacts of this step, with their springs, replace the old list
                    self.p.cid[i] = acc.cid_new
                    self.p.ces[i] = acc.es_new
                    if acc.near == 1:
                        ti.atomic_max(self.stats[None].dem_near, 1)
                if ti.static(self.physics.sps):
                    # SPS stress for the next step, Newtonian materials only (the fluid phase)
                    tau = ti.Vector([0.0, 0.0, 0.0])
                    nut = 0.0
                    newtonian = True
                    if ti.static(self.physics.rheology):
                        newtonian = self.mat_rheo[mi] == 0
                    if newtonian:
                        tau, nut = sps_stress(acc.gv, self.dx)
                    self.p.sps[i] = tau
                    ti.atomic_max(self.stats[None].numax, nut + self.mat_mu[mi] / rho)
                if ti.static(self.physics.rheology):
                    # effective viscosity for the next step (lagged by one dt, ~1e-4 s)
                    gdot = shear_rate(acc.gv)
                    mu_new = self.mat_mu[mi]
                    rh = self.mat_rheo[mi]
                    if rh == BINGHAM:
                        mu_new = bingham(self.mat_mu[mi], self.mat_tau[mi], self.mat_m[mi], self.mat_mumax[mi], gdot)
                        if self.mat_rest[mi] == 1 and self.mat_mumax[mi] * gdot < self.mat_tau[mi]:
                            # unyielded: the stress the capped viscosity carries is below the yield
                            # stress, so Bingham says the material moves as a rigid body; a bed on
                            # a fixed floor rests. Without this it creeps at stress / mu_max.
                            v = ti.Vector([0.0, 0.0])
                            self.p.v[i] = v
                    elif rh == CROSS:
                        mu_new = cross(self.mat_mu0[mi], self.mat_mu[mi], self.mat_K[mi], self.mat_m1[mi],
                                       self.mat_mumax[mi], gdot)
                    self.p.mu[i] = mu_new
                    ti.atomic_max(self.stats[None].numax, mu_new / rho)
                ti.atomic_max(self.stats[None].amax2, a.dot(a))
                ti.atomic_max(self.stats[None].mumax, acc.mu)
                v2 = v.dot(v)
                dev = ti.abs(rho / self.mat_rho0[mi] - 1.0)
                ti.atomic_max(self.stats[None].rhodev, dev)
                code = BAD_NONE
                if self.is_bad(a.dot(a)) or self.is_bad(rho):
                    code = BAD_NAN
                elif v2 > prm.c0 * prm.c0:
                    code = BAD_SPEED
                elif dev > prm.band:
                    code = BAD_DENSITY
                if code != BAD_NONE:
                    ti.atomic_max(self.stats[None].bad_code, code)
                    # the particle's id, not its slot: slots change at every re-sort, and the
                    # runner reads this up to 10 steps later
                    ti.atomic_min(self.stats[None].bad_idx, self.tmp.id[i])
            elif k >= 0:
                if ti.static(self.is_dbc):
                    acc = ti.Struct(drho=0.0, vi=self.tmp.ve[i], rhoi=self.tmp.rhoe[i])
                    if self.fluid_near(self.tmp.x[i]):  # most wall particles have no fluid near
                        self.for_neighbours(self.tmp, i, self.tmp.x[i], self.boundary_pair, acc)
                    self.p.drho[i] = acc.drho
                    self.p.rho[i] = ti.max(self.tmp.rho[i] + 0.5 * dt * acc.drho,
                                           self.mat_rho0[self.tmp.mat[i]])
        # 6. next time step: CFL with the viscous signal, force and viscous limits, user cap
        for c in range(ncell + 2):
            self.fcnt[c] = 0
        for _ in range(1):
            st = self.stats[None]
            amax = ti.sqrt(st.amax2)
            dt_f = 1e30
            if amax > 0.0:
                dt_f = ti.sqrt(self.h / amax)
            dt_cv = self.h / (prm.c0 + st.mumax)
            dt_v = prm.dt_visc
            if ti.static(self.physics.rheology or self.physics.sps):
                # the viscous limit from the (effective, eddy) viscosity actually applied this step
                if st.numax > 0.0:
                    dt_v = ti.min(dt_v, 0.125 * self.h * self.h / st.numax)
                self.stats[None].numax = 0.0
            dt_new = ti.min(prm.cfl * ti.min(dt_f, dt_cv), dt_v, prm.dt_max)
            if ti.static(self.physics.dem):
                # DEM springs are far stiffer than the fluid; their step (eq. 27) is needed only
                # while some grains touch, and otherwise would triple the step count for nothing
                if st.dem_near == 1:
                    dt_new = ti.min(dt_new, prm.dt_dem)
                self.stats[None].dem_near = 0
            if dt_new < prm.dt_floor:
                ti.atomic_max(self.stats[None].bad_code, BAD_DT)
            self.prm[None].dt = dt_new
            self.stats[None].amax2 = 0.0
            self.stats[None].mumax = 0.0
        return dt

    @ti.kernel
    def _shepard(self):
        """Shepard density filter (paper 002 eq. 14): rho_i = sum m_j W / sum V_j W, fluid only."""
        for i in range(self.n):
            if self.p.kind[i] == FLUID:
                acc = ti.Struct(num=0.0, den=0.0)  # the self term comes with the neighbours
                self.for_neighbours(self.p, i, self.p.x[i], self.shepard_pair, acc)
                self.tmp.rho[i] = acc.num / acc.den
        for i in range(self.n):
            if self.p.kind[i] == FLUID:
                self.p.rho[i] = self.tmp.rho[i]

    @ti.func
    def shepard_pair(self, i, j, r, r2, acc: ti.template()):
        if self.p.kind[j] == FLUID:
            w = self.w_scale * self.K.shape(ti.sqrt(r2) * self.inv_h)
            acc.num += self.p.m[j] * w
            acc.den += self.p.m[j] / self.p.rho[j] * w

    @ti.kernel
    def _neighbour_stats(self, cnt: ti.types.ndarray(), idsum: ti.types.ndarray()):
        for i in range(self.n):
            if self.p.kind[i] >= 0:
                acc = ti.Struct(n=0, ids=0)
                self.for_neighbours(self.p, i, self.p.x[i], self.count_pair, acc)
                cnt[self.p.id[i]] = acc.n
                idsum[self.p.id[i]] = acc.ids

    @ti.func
    def count_pair(self, i, j, r, r2, acc: ti.template()):
        if j != i:
            acc.n += 1
            acc.ids += self.p.id[j]

    def neighbour_stats(self):
        """Per particle id: how many neighbours the cell grid finds, and the sum of their ids."""
        if not self._primed:
            self.prime()
        cnt = np.zeros(self.n, np.int32)
        ids = np.zeros(self.n, np.int32)
        self._neighbour_stats(cnt, ids)
        return cnt, ids

    # ------------------------------------------------------------------ checkpoints and backup
    def raw_state(self):
        """Everything needed to continue bit for bit: every member in the current sorted order."""
        d = {k: getattr(self.p, k).to_numpy() for k in self.members}
        st = self.stats[None]
        scal = dict(time=self.time, steps=self.steps, dt=float(self.prm[None].dt), leaked=int(st.leaked),
                    n=self.n, primed=int(self._primed), rhodev=float(st.rhodev))
        return d, scal

    def load_raw_state(self, arrays, scalars):
        if int(scalars["n"]) != self.n:
            raise ValueError(f"checkpoint holds {int(scalars['n'])} particles, this case builds {self.n}")
        missing = [k for k in self.members if k not in arrays]
        if missing:
            raise ValueError(f"checkpoint lacks particle fields {missing} (built with other physics?)")
        for k in self.members:
            getattr(self.p, k).from_numpy(arrays[k])
        self.time = float(scalars["time"])
        self.steps = int(scalars["steps"])
        self.prm[None].dt = float(scalars["dt"])
        self.stats[None].leaked = int(scalars["leaked"])
        self.stats[None].rhodev = float(scalars.get("rhodev", 0.0))
        self._primed = bool(int(scalars["primed"]))

    def enable_backup(self):
        """Keep a device-side copy of the last healthy state (for the final snapshot of a run
        that goes unstable); costs one copy of the particle fields per backup() call."""
        if self.bak is None:
            self.bak = ParticleFields(self._member_types, self.n)
            self.bak_pairs = [(getattr(self.p, k), getattr(self.bak, k)) for k in self.members]
            self.bak_time, self.bak_steps = self.time, self.steps

    @ti.kernel
    def _backup(self):
        for i in range(self.n):
            for fp, fb in ti.static(self.bak_pairs):
                fb[i] = fp[i]

    def backup(self):
        self._backup()
        self.bak_time, self.bak_steps = self.time, self.steps

    def backup_state(self, names):
        """The backed-up state, ordered by particle id."""
        inv = np.argsort(self.bak.id.to_numpy())
        return {k: getattr(self.bak, k).to_numpy()[inv] for k in names}

    # ------------------------------------------------------------------ Python API
    def prime(self):
        """Bin the particles and evaluate forces at t = 0 (a zero-length step) to get a^0, dt^0."""
        self.prm[None].dt = 0.0
        self._step()
        self._primed = True

    def set_paddle(self, t):
        """Paddle displacement and rate at time t, into the kernel's parameters."""
        d, r = self.motion(t)
        self.prm[None].pd = d
        self.prm[None].pv = r

    def step(self):
        """Advance one time step; returns the dt taken."""
        if not self._primed:
            self.prime()
        if self.motion is not None:
            self.set_paddle(self.time + self.dt)  # the kernel moves the paddle to t + dt
        dt = float(self._step())
        self.steps += 1
        self.time += dt
        if self.physics.shepard and self.steps % self.shepard_every == 0:
            self._shepard()
        return dt

    @property
    def dt(self):
        return float(self.prm[None].dt)

    def check(self):
        """None if the state is healthy, else (code, id of the first particle that went bad)."""
        st = self.stats[None]
        if st.bad_code != BAD_NONE:
            return int(st.bad_code), int(st.bad_idx)
        return None

    @property
    def max_density_error(self):
        """Largest |rho/rho0 - 1| of any fluid particle at any step so far."""
        return float(self.stats[None].rhodev)

    @property
    def leaked(self):
        return int(self.stats[None].leaked)

    snapshot_members = ("x", "v", "rho", "p", "m", "kind", "mat", "id")

    def field_bytes(self):
        """Bytes the particle and grid fields take on the device (from their shapes and types)."""
        per = 0
        for k, t in self._member_types.items():
            n = getattr(t, "n", 1)
            dt = getattr(t, "dtype", t)
            per += n * (8 if dt in (ti.f64, ti.i64) else 4)
        copies = 2 + (self.bak is not None)          # particles, the sorted copy, the backup
        grid = 3 * (self.ncells + 2) * 4 + 2 * self.n * 4   # counts/starts, keys/order
        return per * self.n * copies + grid

    def state(self, names=("x", "v", "rho", "p", "kind", "mat", "m")):
        """Particle arrays ordered by particle id (the order the scene built them in)."""
        ids = self.p.id.to_numpy()
        inv = np.argsort(ids)
        return {k: getattr(self.p, k).to_numpy()[inv] for k in names}
