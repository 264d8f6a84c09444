"""Suspended sand carried by the SPH water over the morphodynamic bed (sediment.suspended).

Each fluid particle carries a volume concentration c of sand. Per step, in the neighbour pass:
  dc_i/dt = sum_j V_j (eps_i + eps_j) (c_i - c_j) (r_ij . grad W) / (r^2 + 0.01 h^2)    diffusion
          + 2 w_s sum_j V_j |dW/dy| (c_j [j above i] - c_i [j below i])                settling
The diffusion is Morris et al.'s (1997) Laplacian with the turbulent diffusivity eps (van Rijn's
parabolic-constant profile: kappa u* z (1 - z/H), constant at kappa u* H / 4 above mid-depth;
set per particle at each bed update); the settling is a
donor-cell (upwind) flux at w_s, the first-order form of w_s dc/dy, which for c linear in y gives
exactly w_s dc/dy (sum_j V_j (y_j - y_i) dW/dy_i = 1, half from each side). Both exchange sand
between pairs with equal and opposite rates (V_j the nominal volume m_j / rho0), so the sand in
the water changes only at the bed.

The bed exchange (Suspension.exchange, every bed update) works on the water within
LAYER particle spacings of the bed at each station: the layer's mean concentration c_b settles
out at w_s c_b (deposition) and the bed gives E = w_s c_a (entrainment) with van Rijn's (1984)
reference concentration c_a (tisph/sediment/transport.py), as the grid models of pipeline scour
do (Brors 1999; Liang, Cheng & Li 2005). What the water gains the bed loses (times morfac,
as Delft3D's morphological factor does: (1 - n) V_bed + morfac V_suspended is conserved).
"""

import numpy as np
import taichi as ti

from ..constants import KAPPA
from ..hooks.module import Module, Param
from ..particles import FLUID
from ..runtime import blocks

LAYER = 2.0  # particle spacings above the bed that exchange sand with it


@ti.data_oriented
class Suspension(Module):
    name = "suspension"
    on = {"suspension": True}
    params = {
        "w_s": Param(0.0, "m/s", (0.0, None, True, True), "settling velocity of the suspended sand"),
        "eps_max": Param(0.0, "m2/s", (0.0, None, True, True), "largest sediment diffusivity (time step)"),
    }
    acc = {"dc": "real", "ci": "real", "epsi": "real"}

    def fields(self, real):
        return {
            "c": real,  # volume concentration of suspended sand
            "eps": real,
        }  # its turbulent diffusivity (m2/s)

    def allocate(self, S):
        self.nst = int(S.params.get("bed_stations", 1))  # the bed's stations, dx apart from x = 0
        # a GPU sums the layer by blocks of particles, each into its own row of stations
        # (_layer_sums); the CPU in one serial pass
        self.blk, nb = blocks(S.n)
        self.rows = None if S.cpu else ti.field(ti.f64, (nb, self.nst + 1, 2))

    def setup(self, S):
        """The initial concentration, where the scene gives one (ParticleSet.concentration)."""
        c0 = getattr(S.particles, "concentration", None)
        if c0 is not None and len(c0) == S.n:
            S.p.c.from_numpy(np.asarray(c0, dtype=S.np_real))

    @ti.func
    def init_acc(self, S, i, acc: ti.template()):
        acc.ci = S.tmp.c[i]
        acc.epsi = S.tmp.eps[i]

    @ti.func
    def pair(self, S, i, j, r, r2, nb, acc: ti.template()):
        if nb.kj == FLUID:
            s = S.tmp
            cj = s.c[j]
            vj = nb.m_j / S.mat.rho0[ti.cast(s.mat[j], ti.i32)]
            acc.dc += vj * (acc.epsi + s.eps[j]) * (acc.ci - cj) * r.dot(nb.gw) * nb.ie
            f = 2.0 * S.prm[None].w_s * vj * ti.abs(nb.gw[1])
            if r[1] < 0.0:  # j above i: its sand settles into i
                acc.dc += f * cj
            elif r[1] > 0.0:  # j below i: i's sand settles into j
                acc.dc -= f * acc.ci

    @ti.func
    def finish(self, S, i, mi, acc: ti.template(), pt: ti.template()):
        S.p.c[i] = acc.ci + S.prm[None].dt * acc.dc

    @ti.func
    def dt_limit(self, S, dt_new):
        """The explicit diffusion limit 0.125 h^2 / eps_max, as the viscous one."""
        e = S.prm[None].eps_max
        out = dt_new
        if e > 0.0:
            out = ti.min(dt_new, 0.125 * S.h * S.h / e)
        return out

    # ------------------------------------------------------------------ the bed exchange
    def exchange(self, S, zb, entrain, ustar, top, dt):
        """One exchange with the bed over dt seconds of flow. zb: the bed at the stations;
        entrain: E = w_s c_a per station (m/s); ustar: the friction velocity of the diffusivity
        per station; top: the water surface (m). Returns (the sand volume per unit width each
        station received from the water, m2; the sand volume in the water before it, m2)."""
        n = self.nst
        sums = np.zeros((n + 1, 2), np.float64)
        zb64 = np.ascontiguousarray(zb, np.float64)
        self._layer_sums(S, zb64, sums)
        area, sand = sums[:n, 0], sums[:n, 1]
        ws = float(S.prm[None].w_s)
        ok = area > 0
        frac = np.zeros(n)
        gain = np.zeros(n)
        # the layer loses w_s c_b dt per unit bed (a fraction w_s dt dx / area of its sand) and
        # gains E dt (spread evenly); no water over a station: no exchange
        frac[ok] = np.minimum(ws * dt * S.dx / area[ok], 1.0)
        gain[ok] = np.asarray(entrain, float)[ok] * dt * S.dx / area[ok]
        eps_max = float(KAPPA * np.max(ustar) * np.max(top - zb) / 4.0)
        S.prm[None].eps_max = eps_max
        self._layer_apply(S, zb64, frac, gain, np.ascontiguousarray(ustar, np.float64), float(top))
        to_bed = frac * sand - gain * area
        return to_bed, float(sums[n, 1])

    @ti.func
    def station(self, S, x):
        return ti.max(0, ti.min(self.nst - 1, ti.cast(ti.floor(x / S.dx), ti.i32)))

    @ti.kernel
    def _layer_sums(
        self, S: ti.template(), zb: ti.types.ndarray(dtype=ti.f64, ndim=1), out: ti.types.ndarray(dtype=ti.f64, ndim=2)
    ):
        # one order whatever the threads: restarts bit for bit. On a GPU, where one thread over
        # every particle costs milliseconds, each block of particles into its own row, then each
        # station over the rows in block order
        if ti.static(S.cpu):
            ti.loop_config(serialize=True)
            for i in range(S.n):
                self._layer_add(S, i, zb, out, 0)
        else:
            for b in range(self.rows.shape[0]):
                for k in range(self.nst + 1):
                    self.rows[b, k, 0] = 0.0
                    self.rows[b, k, 1] = 0.0
                for i in range(b * self.blk, ti.min((b + 1) * self.blk, S.n)):
                    self._layer_add(S, i, zb, self.rows, b)
            for k in range(self.nst + 1):
                s0 = ti.f64(0.0)
                s1 = ti.f64(0.0)
                for b in range(self.rows.shape[0]):
                    s0 += self.rows[b, k, 0]
                    s1 += self.rows[b, k, 1]
                out[k, 0] = s0
                out[k, 1] = s1

    @ti.func
    def _layer_add(self, S, i, zb: ti.template(), out: ti.template(), b):
        """Particle i's water volume and sand into its station's near-bed layer, and its sand into
        the water's total (the last station): out[k, ...] on the CPU, out[b, k, ...] on a GPU."""
        if S.p.kind[i] == FLUID:
            v = ti.cast(S.p.m[i] / S.mat.rho0[ti.cast(S.p.mat[i], ti.i32)], ti.f64)
            cv = v * ti.cast(S.p.c[i], ti.f64)
            k = self.station(S, S.p.x[i][0])
            if ti.static(S.cpu):
                if ti.cast(S.p.x[i][1], ti.f64) - zb[k] < LAYER * S.dx:
                    out[k, 0] += v
                    out[k, 1] += cv
                out[self.nst, 1] += cv
            else:
                # a block's own row: plain loads and stores, no atomics
                if ti.cast(S.p.x[i][1], ti.f64) - zb[k] < LAYER * S.dx:
                    out[b, k, 0] = out[b, k, 0] + v
                    out[b, k, 1] = out[b, k, 1] + cv
                out[b, self.nst, 1] = out[b, self.nst, 1] + cv

    @ti.kernel
    def _layer_apply(
        self,
        S: ti.template(),
        zb: ti.types.ndarray(dtype=ti.f64, ndim=1),
        frac: ti.types.ndarray(dtype=ti.f64, ndim=1),
        gain: ti.types.ndarray(dtype=ti.f64, ndim=1),
        ustar: ti.types.ndarray(dtype=ti.f64, ndim=1),
        top: ti.f64,
    ):
        for i in range(S.n):
            if S.p.kind[i] == FLUID:
                k = self.station(S, S.p.x[i][0])
                z = ti.cast(S.p.x[i][1], ti.f64) - zb[k]
                if z < LAYER * S.dx:
                    S.p.c[i] = ti.cast(ti.cast(S.p.c[i], ti.f64) * (1.0 - frac[k]) + gain[k], S.real)
                H = ti.max(top - zb[k], S.dx)
                # van Rijn's (1984) parabolic-constant profile: kappa u* z (1 - z/H) in the lower
                # half, its maximum kappa u* H / 4 above
                zc = ti.min(ti.max(z, 0.5 * S.dx), 0.5 * H)
                S.p.eps[i] = ti.cast(KAPPA * ustar[k] * zc * (1.0 - zc / H), S.real)
