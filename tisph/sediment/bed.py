"""The morphodynamic bed: a height field z_b at stations dx apart, moved by bed load.

One update (Bed.step) with the bed shear at each station:
  1. Shields number theta = |tau| / ((rho_s - rho) g d50) against the critical value of
     Soulsby & Whitehouse (1997), corrected for the bed slope along the flow;
  2. equilibrium flux q_b = Phi(theta) sqrt((s - 1) g d50^3) in the direction of tau (Meyer-Peter
     & Mueller, or Nielsen for waves), less a gravity term K_g |q_b| (dz/dx) / tan(phi) that
     pulls sand down slopes;
  3. saturation: l_s dq/dx + q = q_b along the flow (the bed load lags the shear over l_s; this
     lag is what lets a bump grow downstream of its crest); with lee_transit the load a current
     carries beyond the capacity crosses a reversed near-bed zone (saturate_transit);
  4. Exner, (1 - n) dz_b/dt = -dq/dx, in conservative finite volumes (fluxes on the faces
     between stations), times the morphological factor: the sand volume changes only through
     the domain's open ends, so in a closed or periodic bed it is conserved to round-off;
  5. avalanching: a face steeper than the angle of repose gives sand from its high side to its
     low side until it stands at that angle, volume conserved.
"""

import dataclasses
import math

import numpy as np

from ..constants import G
from .transport import FORMULAE, shields_critical, shields_number, slope_factor, transport_scale


@dataclasses.dataclass(frozen=True)
class Sand:
    """The bed's grain and transport law, what a Bed needs beside its stations (the [sediment]
    keys, coupling.sand_of): theta_cr None is Soulsby & Whitehouse's for the grain, a
    saturation_length None one station spacing, a deposition_length None the saturation length."""

    d50: float
    rho_s: float = 2650.0
    rho_w: float = 1000.0
    porosity: float = 0.4
    repose_deg: float = 32.0
    theta_cr: float = None
    formula: str = "mpm"
    saturation_length: float = None
    deposition_length: float = None
    gravity_coefficient: float = 1.0
    morfac: float = 1.0
    lee_transit: bool = False
    settling_delay: bool = False


class Bed:
    def __init__(self, x, z, sand, periodic=True):
        d50, rho_s, rho_w, repose_deg = sand.d50, sand.rho_s, sand.rho_w, sand.repose_deg
        theta_cr, saturation_length, deposition_length = sand.theta_cr, sand.saturation_length, sand.deposition_length
        self.x = np.asarray(x, float)
        self.dx = float(self.x[1] - self.x[0])
        self.z = np.array(z, float)
        self.d50, self.rho_s, self.rho_w = d50, rho_s, rho_w
        self.s = rho_s / rho_w
        self.porosity, self.repose = sand.porosity, repose_deg
        self.tan_repose = math.tan(math.radians(repose_deg))
        self.theta_cr = shields_critical(d50, self.s) if theta_cr is None else theta_cr
        self.phi = FORMULAE[sand.formula]
        self.l_s = self.dx if saturation_length is None else saturation_length
        # where the load exceeds what the flow carries it settles out over its own length (sand
        # thrown up by a jet lands u h / w_s on); picking up stays at l_s
        self.l_d = self.l_s if deposition_length is None else deposition_length
        self.K_g = sand.gravity_coefficient
        self.lee_transit = sand.lee_transit
        self.settling_delay = sand.settling_delay
        self.q_settle = np.zeros_like(self.z)  # settling_delay: the first stage's load
        self.q_up = np.zeros_like(self.z)  # lee_transit: the load along the current, and against it
        self.q_back = np.zeros_like(self.z)
        self.morfac = sand.morfac
        self.periodic = periodic
        self.q = np.zeros_like(self.z)  # the last flux at the stations (m2/s)
        self.theta = np.zeros_like(self.z)
        self.scale = transport_scale(d50, self.s, G)

    # ---------------------------------------------------------------- geometry
    def slope(self):
        """dz_b/dx at the stations (central; one-sided at the ends of a closed bed)."""
        if self.periodic:
            return (np.roll(self.z, -1) - np.roll(self.z, 1)) / (2.0 * self.dx)
        return np.gradient(self.z, self.dx)

    def volume(self):
        """Sand volume above z = 0 per unit width (m2)."""
        return float(np.sum(self.z, dtype=np.float64) * self.dx)

    # ---------------------------------------------------------------- transport
    def equilibrium_flux(self, tau):
        """q_b at the stations (m2/s, signed) for the bed shear tau (Pa, signed)."""
        tau = np.asarray(tau, float)
        dzdx = self.slope()
        self.theta = shields_number(tau, self.d50, self.rho_s, self.rho_w)
        crit = self.theta_cr * slope_factor(dzdx, tau, self.repose)
        qb = self.phi(self.theta, crit) * self.scale * np.sign(tau)
        return qb - self.K_g * np.abs(qb) * dzdx / self.tan_repose

    def saturate(self, qb):
        """Solve l dq/dx + q = q_b along the local flow direction (upwind, Gauss-Seidel sweeps;
        three laps settle a periodic bed to round-off for l of a few dx), l = l_s where the bed
        picks sand up (|q| < |q_b|) and the deposition length where it drops it."""
        a, ad = self.l_s / self.dx, self.l_d / self.dx
        if a <= 0 and ad <= 0:
            return qb.copy()
        if self.lee_transit:
            return self.saturate_transit(qb, a, ad)
        n = len(qb)
        # Python floats in lists: the same double arithmetic as NumPy's scalars, 4x faster to index
        q = self.q.tolist()  # the last flux: the sweeps start from it
        qbl = np.asarray(qb, float).tolist()
        fwd = [i for i in range(n) if qbl[i] >= 0]
        back = [i for i in range(n - 1, -1, -1) if not qbl[i] >= 0]
        for _ in range(3):
            for i in fwd:  # flow to +x: upwind neighbour on the left
                up = q[i - 1] if (i > 0 or self.periodic) else 0.0
                k = a if up <= qbl[i] else ad
                q[i] = (qbl[i] + k * up) / (1.0 + k)
            for i in back:  # flow to -x: upwind neighbour on the right
                up = q[(i + 1) % n] if (i < n - 1 or self.periodic) else 0.0
                k = a if up >= qbl[i] else ad
                q[i] = (qbl[i] + k * up) / (1.0 + k)
        return np.array(q)

    def saturate_transit(self, qb, a, ad):
        """saturate for a current over a separated lee (sediment.lee_transit). The load is split
        into the part that travels with the current (the sign of the net q_b) and the part that
        runs against it under a reversed near-bed flow. Load beyond the local capacity travels
        with the current across the reversed zone and settles out over the deposition length, as
        sand a jet throws up crosses a separation bubble above the bed (van Rijn 1987's
        adaptation of the suspended load, which moves with the outer flow); saturate stops it
        where the near-bed flow turns. The load against the current stops within l_s where the
        flow turns forward. The flux is the sum; with no reversed station it is saturate's.
        settling_delay: the load along the current relaxes in two stages of l_d / 2 (the first to
        the capacity, the second to the first): sand the jet throws up must settle down through the
        water before it lands, so its deposition is a gamma kernel, none where the capacity drops
        and the most l_d / 2 on, mean l_d (the one stage lands the most at once)."""
        n = len(qb)
        sgn = 1.0 if float(np.sum(qb)) >= 0 else -1.0
        along = sgn * qb >= 0  # with the current, or still (below the threshold)
        cap_up = np.where(along, qb, 0.0)
        cap_back = np.where(along, 0.0, qb)
        order = range(n) if sgn > 0 else range(n - 1, -1, -1)
        step = -1 if sgn > 0 else 1  # the upwind neighbour's offset along the current

        def relax(cap, q, kd, sweep, step, settles=None):
            """One upwind sweep of l dq/dx + q = cap: l = kd dx where the load exceeds the
            capacity (and, with settles, only at those stations), else l_s."""
            for i in sweep:
                j = i + step
                up = q[j % n] if (0 <= j < n or self.periodic) else 0.0
                k = kd if (abs(up) > abs(cap[i]) and (settles is None or settles[i])) else a
                q[i] = (cap[i] + k * up) / (1.0 + k)

        up_q, back_q = self.q_up.copy(), self.q_back.copy()
        first = self.q_settle.copy()
        for _ in range(3):
            if self.settling_delay:  # two stages of l_d / 2: first down through the water, then out
                relax(cap_up, first, 0.5 * ad, order, step)
                relax(first, up_q, 0.5 * ad, order, step)
            else:
                relax(cap_up, up_q, ad, order, step)
            relax(cap_back, back_q, ad, reversed(order), -step, settles=~along)
        self.q_up, self.q_back, self.q_settle = up_q, back_q, first
        return up_q + back_q

    def face_fluxes(self, q):
        """Fluxes on the n + 1 faces (face k between stations k - 1 and k); a closed bed's end
        faces carry none, a periodic bed's first and last face are the same face."""
        f = np.empty(len(q) + 1)
        f[1:-1] = 0.5 * (q[:-1] + q[1:])
        if self.periodic:
            f[0] = f[-1] = 0.5 * (q[-1] + q[0])
        else:
            f[0] = f[-1] = 0.0
        return f

    def outflow(self, tau):
        """The bed-load flux leaving each station's cell, right face less left face (m2/s), under
        the shear tau: Exner's -dq/dx times dx. The saturated flux stays in self.q (the next
        sweeps start from it)."""
        self.q = self.saturate(self.equilibrium_flux(tau))
        f = self.face_fluxes(self.q)
        return f[1:] - f[:-1]

    def step(self, tau, dt, deposit=None):
        """Advance the bed by dt (seconds of flow; the bed moves morfac times as far) under the
        shear tau; deposit: sand volume per unit width each station took from the suspension
        over dt (m2; negative where the flow picked more up); returns dz_b."""
        out = self.outflow(tau)
        z_old = self.z.copy()
        self.z -= self.morfac * dt / (1.0 - self.porosity) * out / self.dx
        if deposit is not None:
            self.z += self.morfac / (1.0 - self.porosity) * np.asarray(deposit, float) / self.dx
        self.avalanche()
        return self.z - z_old

    def avalanche(self, max_sweeps=500):
        """Relax every face steeper than the angle of repose to it, giving sand from its high
        side to its low side (half the excess each way: volume conserved), face by face in order
        (Gauss-Seidel). Returns the sweeps. A sweep visits only the faces that were steep when it
        began and the face after each one it relaxed (the only ones that can be steep when
        reached; the periodic bed's last face too, as its far end is z[0]): the same result as
        visiting every face (tests/sediment/test_bedload.py), 6x faster on the Mao case's beds."""
        dx, t = self.dx, self.tan_repose
        n = len(self.z)
        faces = n if self.periodic else n - 1
        for sweep in range(max_sweeps):
            za = self.z
            dz_all = (np.append(za[1:], za[0]) if self.periodic else za[1:]) - za[:faces]
            steep = np.nonzero(np.abs(dz_all) - t * dx > 1e-12 * dx)[0].tolist()
            z = za.tolist()  # the sweep on Python floats (the same arithmetic, faster to index)
            if self.periodic and (not steep or steep[-1] != faces - 1):
                steep.append(faces - 1)
            moved = relaxed = False
            k, i = 0, -1
            while True:
                while k < len(steep) and steep[k] <= i:
                    k += 1
                if not relaxed:
                    if k == len(steep):
                        break
                    i = steep[k]
                else:
                    i += 1
                    if i >= faces:
                        break
                j = (i + 1) % n
                dz = z[j] - z[i]
                excess = abs(dz) - t * dx
                relaxed = excess > 1e-12 * dx
                if relaxed:
                    d = 0.5 * excess * (1.0 if dz > 0 else -1.0)
                    z[j] -= d
                    z[i] += d
                    moved = True
            if not moved:
                return sweep
            self.z[:] = z
        return max_sweeps

    def max_slope_deg(self):
        d = np.diff(np.append(self.z, self.z[0]) if self.periodic else self.z) / self.dx
        return math.degrees(math.atan(float(np.abs(d).max()))) if len(d) else 0.0
