"""The morphodynamic bed under the SPH water: the bed's boundary particles, and the update that carries the near-bed flow to the bed and the bed to the solver.

Each update (every sediment.update_every steps):
  1. the water velocity tangential to the bed at z_r = reference_height * dx above it, SPH
     interpolated at every station, filtered in time over filter_time (an exponential average);
  2. the bed shear from it through a wall law with grain roughness k_s = 2.5 d50: for waves
     (shear = "waves") tau = 0.5 rho f_w |u| u with Swart's f_w for the orbital amplitude; for a
     current (shear = "log") the rough-wall log law through u at z_r; with the k equation
     (shear = "wall_function") Launder & Spalding's (1974, Comput. Methods Appl. Mech. Eng. 3:269)
     wall function tau = rho C_mu^(1/4) sqrt(k) kappa u / ln(z_r / z0), k filtered as u is: the
     geometric mean of the log law's shear and rho sqrt(C_mu) k, each scaled to the far field;
  3. Bed.step (tisph/sediment/bed.py) over the elapsed time; the solver's bed particles move
     with the new z_b (solver.set_bed).
"""

import dataclasses

import numpy as np

from ..constants import SQRT_CMU, G
from ..errors import SimulationError, unstable
from ..settings.config import ConfigError
from .bed import Bed, Sand
from .lee import lee_vortex_shear, lee_zones, vortex_throw
from .outer import Window, outer_heights, outer_scale
from .transport import reference_concentration, settling_velocity, shear_log_law, shear_waves, shields_number

# the fastest the bed may move, in units of the sound speed (BedCoupler.check_speed)
BED_MACH = 0.2
# the shears scaled to the far field (the pipeline's undisturbed bed and its current's u*)
FAR_FIELD_SHEARS = ("log_far_field", "wall_function")


def sand_of(sed, d50, rho_s, rho_w=1000.0, morfac=None):
    """The Sand the [sediment] table sed describes (morfac: its own unless given)."""
    return Sand(
        d50,
        rho_s,
        rho_w,
        porosity=sed["porosity"],
        repose_deg=sed["repose_angle"],
        theta_cr=sed["shields_critical"] or None,
        formula=sed["formula"],
        saturation_length=sed["saturation_length"] or None,
        deposition_length=sed["deposition_length"] or None,
        gravity_coefficient=sed["gravity_coefficient"],
        morfac=sed["morfac"] if morfac is None else morfac,
        lee_transit=sed["lee_transit"],
        settling_delay=sed["settling_delay"],
    )


def make_bed(sed, stations, z, d50, rho_s, rho_w=1000.0, periodic=True, morfac=None):
    """The Bed the [sediment] table sed describes (morfac: its own unless given)."""
    return Bed(stations, z, sand_of(sed, d50, rho_s, rho_w, morfac), periodic)


@dataclasses.dataclass(frozen=True)
class Stations:
    """Where a coupled bed lies: its stations' x and initial heights z, their spacing dx (the
    particles'), the kernel's h, and whether the bed closes round (a periodic domain)."""

    x: object
    z: object
    dx: float
    h: float
    periodic: bool = True


@dataclasses.dataclass(frozen=True)
class Drive:
    """What the bed's shear needs of the flow over it. amplitude: the near-bed orbital amplitude A
    (Swart's f_w, the lee zone's cap), a number; None: measured at each station from the
    filtered near-bed velocity over the last wave period 2 pi / omega, A = (u_max - u_min) /
    (2 omega): Wiberg & Harris's d0 = U_m T / pi with U_m the peak orbital velocity (a beach,
    where A varies and the waves are not sines). z0: the log law's roughness for shear = "log"
    (None: the grains', 2.5 d50 / 30). far_field: (mask of stations, tau_inf) for shear =
    "log_far_field": the log-law shear is scaled so its median over those stations is tau_inf.
    An SPH current over a wall at dx = D/20 does not keep a rough-wall log profile near the bed
    (measured in the pipeline's Mao case: the log law through the SPH velocity 3 dx up gave 2.5
    times the current's rho u*^2 on the undisturbed bed), so the current's u* is taken as given
    and the SPH supplies the shear's amplification around the structure, tau / tau_inf = (u /
    u_far)^2. surface: the water surface's height (m), for the suspended load's diffusivity; a
    scene without it refuses sediment.suspended. still_level: the still water's level, which
    caps the outer reading's height."""

    amplitude: object = 0.0
    omega: float = 0.0
    z0: float = None
    far_field: tuple = None
    surface: float = None
    still_level: float = None


class BedCoupler:
    def __init__(self, sed, sand, where, drive):
        """The bed-load bed the [sediment] table sed describes, of sand (Sand), at the stations
        `where` (Stations), under the flow `drive` describes (Drive)."""
        stations, z, dx, h, periodic = where.x, where.z, where.dx, where.h, where.periodic
        amplitude, omega, surface = drive.amplitude, drive.omega, drive.surface
        d50, rho_w = sand.d50, sand.rho_w
        self.sed, self.dx, self.h, self.rho_w = sed, dx, h, rho_w
        self.stations = np.asarray(stations, float)
        self.bed = Bed(stations, z, sand, periodic)
        self.z0 = self.bed.z.copy()
        self.v0 = self.bed.volume()
        self.d50, self.omega, self.z0_log, self.far_field = d50, omega, drive.z0, drive.far_field
        self.measured = amplitude is None
        self.amplitude = np.zeros(len(stations)) if self.measured else amplitude
        self.history = Window(len(stations))  # (t, filtered u, u outer) over the last wave period
        if sed["shear"] in FAR_FIELD_SHEARS and drive.far_field is None:
            raise ConfigError(
                "sediment.shear",
                sed["shear"],
                "'waves' or 'log' in this scene: the far-field "
                "scaling needs the undisturbed bed and the current's u*, which the pipeline sets",
            )
        if sed["suspended"] and surface is None:
            raise ConfigError(
                "sediment.suspended",
                True,
                "false in this scene: suspended load is built for the "
                "pipeline over the bed-load bed (its periodic current has one water surface)",
            )
        if sed["lee_transit"] and sed["shear"] == "waves":
            raise ConfigError(
                "sediment.lee_transit",
                True,
                "false with sediment.shear = 'waves': the load crosses "
                "a separated lee in the direction of a current (the net flux's), which waves turn "
                "every half period",
            )
        if sed["settling_delay"] and not sed["lee_transit"]:
            raise ConfigError(
                "sediment.settling_delay",
                True,
                "false unless sediment.lee_transit = true: the "
                "delay is a stage of the load that crosses the lee with the current",
            )
        self.water_top = surface
        self.still_level = drive.still_level
        self.w_s = sed["settling_velocity"] or settling_velocity(d50, self.bed.s)
        self.suspended = 0.0  # sand volume in the water per unit width (m2)
        self.u = np.zeros(len(stations))
        # the outer scaling (shear = "waves", outer_height > 0): the filtered velocity at the outer
        # height, the (t, u, u_outer) history over the last wave period, and the scale it gives
        self.outer = sed["shear"] == "waves" and sed["outer_height"] > 0 and omega > 0
        self.u_outer = np.zeros(len(stations))
        self.u_outer_now = None
        self.outer_factor = np.ones(len(stations))
        self.u_eff = np.zeros(len(stations))
        self.k = np.zeros(len(stations))  # the filtered k at z_r (shear = "wall_function")
        self.tau = np.zeros(len(stations))
        self.zones = []  # the separated lees of the last shear (lee.lee_zones)
        self.t = 0.0

    def near_bed_flow(self, s):
        """(Tangential water velocity, k or None) at z_r above the bed at each station (NaN: no
        water there), sampled on the solver's own cells (Solver.sample_velocity); k, in the same
        pass, for the wall function only."""
        z = self.bed.z
        heights = [z + self.sed["reference_height"] * self.dx]
        if self.outer:
            self.zo = self.outer_heights()  # outer_scale reads the same heights this update
            heights.append(z + np.nan_to_num(self.zo, nan=self.sed["reference_height"] * self.dx))
        pts = np.vstack([np.column_stack([self.stations, zz]) for zz in heights])
        k = None
        if self.sed["shear"] == "wall_function":
            u, k = s.sample_velocity(pts, tke=True)
        else:
            u = s.sample_velocity(pts)
        dzdx = np.tile(self.bed.slope(), len(heights))
        ut = (u[:, 0] + u[:, 1] * dzdx) / np.sqrt(1.0 + dzdx * dzdx)
        n = len(self.stations)
        if self.outer:
            self.u_outer_now = ut[n:]
        return ut[:n], k

    def shear(self, u):
        kind = self.sed["shear"]
        if kind == "waves":
            tau = shear_waves(u, self.amplitude, self.d50, self.rho_w)
        else:
            tau = shear_log_law(u, self.sed["reference_height"] * self.dx, self.d50, self.rho_w, self.z0_log)
            if kind in FAR_FIELD_SHEARS:
                tau = self.to_far_field(tau)
            if kind == "wall_function":
                tau_k = self.to_far_field(self.rho_w * SQRT_CMU * self.k)
                tau = np.sign(u) * np.sqrt(np.abs(tau) * tau_k)
        self.zones = []
        if self.sed["lee_vortex"] > 0:
            self.zones = lee_zones(self.bed.z, self.dx, u, self.sed, self.bed.periodic, self.amplitude, self.mobility())
            tau = lee_vortex_shear(tau, self.bed.z, self.dx, u, self.sed, zones=self.zones)
        return tau

    def outer_heights(self):
        """The outer reading's height above the bed at each station (outer.outer_heights)."""
        return outer_heights(self.sed, self.dx, self.bed.z, self.still_level)

    def outer_scale(self, full_period):
        """The factor on the near-bed velocity at each station (outer.outer_scale); 1 until a
        whole wave period has been seen."""
        if not full_period:
            return np.ones(len(self.stations))
        return outer_scale(self.history, self.amplitude, self.dx, self.bed.periodic, self.zo)

    def to_far_field(self, tau):
        """tau scaled so that its median magnitude over the far field's stations is tau_inf."""
        mask, tau_inf = self.far_field
        ref = float(np.median(np.abs(tau[mask])))
        return tau * (tau_inf / ref) if ref > 0 else tau

    def mobility(self):
        """Mobility number psi = (A omega)^2 / ((s - 1) g d50) at the stations (0: no omega)."""
        if not self.omega:
            return np.zeros(len(self.stations))
        U = np.broadcast_to(np.asarray(self.amplitude, float), (len(self.stations),)) * self.omega
        return U * U / ((self.bed.s - 1.0) * G * self.d50)

    def update(self, s):
        """One bed update from the solver's state: shear, bed step, the bed particles moved."""
        dt = s.time - self.t
        if dt <= 0:
            return
        self.t = s.time
        u, k = self.near_bed_flow(s)
        u = np.where(np.isfinite(u), u, 0.0)
        tf = self.sed["filter_time"]
        a = dt / (tf + dt) if tf > 0 else 1.0
        self.u += a * (u - self.u)
        if k is not None:
            self.k += a * (np.where(np.isfinite(k), k, 0.0) - self.k)
        if self.outer:
            uo = self.u_outer_now
            self.u_outer += a * (np.where(np.isfinite(uo), uo, self.u_outer) - self.u_outer)
        if self.measured or self.outer:
            period = 2.0 * np.pi / self.omega
            self.history.append(s.time, self.u, self.u_outer)
            self.history.drop_before(s.time - period)
            if self.outer:
                self.outer_factor = self.outer_scale(s.time - self.history.first >= 0.95 * period)
            self.u_eff = self.u * self.outer_factor
            if self.measured:
                us = self.history.near * self.outer_factor
                self.amplitude = 0.5 * (us.max(0) - us.min(0)) / self.omega
        else:
            self.u_eff = self.u
        self.tau = self.shear(self.u_eff)
        moving = s.time > self.sed["morph_start"]
        dt = min(dt, s.time - self.sed["morph_start"]) if moving else 0.0
        deposit = self.exchange(s, dt) if self.sed["suspended"] else None
        if not moving:
            return
        if self.sed["vortex_throw"] > 0 and self.zones:  # from the last update's bed load (self.bed.q)
            thrown = vortex_throw(self.zones, self.bed.q, self.dx, self.sed, self.bed.periodic, self.amplitude) * dt
            deposit = thrown if deposit is None else deposit + thrown
        w = self.bed.step(self.tau, dt, deposit) / dt
        self.check_speed(s, w)
        s.set_bed(self.bed.z - self.z0, w)

    def check_speed(self, s, w):
        """Stop the run when the bed moves faster than BED_MACH c0: its particles would push the
        water faster than the equation of state allows (the c0 = 10 u rule's Mach 0.1, with room for
        a moment's burst), and the water would blow up a few steps later with a message about its
        sound speed. Measured: Mao's case at D/20 peaks at 0.08 c0 as its hole opens; at D/30 the
        gap's shear at the same opening is about 4x as high and the bed moved at 0.47 c0."""
        i = int(np.argmax(np.abs(w)))
        if abs(w[i]) <= BED_MACH * s.c0:
            return
        k = int(np.argmax(np.abs(self.tau)))
        raise SimulationError(
            unstable(
                s,
                f"the bed moved faster than {BED_MACH:g} c0",
                f"station x = {self.stations[i]:.4g} m, dz_b/dt = {w[i]:.4g} m/s (c0 = {s.c0:.4g} m/s); the bed's "
                f"highest shear {abs(self.tau[k]):.4g} Pa (Shields {self.bed.theta[k]:.3g}) at x = "
                f"{self.stations[k]:.4g} m",
                "a local shear far above the far field's, which the transport formula turns into erosion faster "
                "than the water can follow (a jet through a gap a few dx high): lower sediment.morfac, or open "
                "the gap wider",
            )
        )

    def carrying(self, volume):
        """The water starts with this much sand in it (m2 per unit width): it counts in the
        conserved sand as the bed volume it stands for."""
        self.v0 += self.sed["morfac"] * (volume - self.suspended) / (1.0 - self.bed.porosity)
        self.suspended = volume

    def pickup_concentration(self, tau):
        """van Rijn's c_a at one dx above the bed (the exchange layer's mid-height) under the
        shear tau, his transport stage against the flat bed's threshold: his c_a has no slope, and
        the slope-reduced threshold falls to 0 on a face at the angle of repose (c_a unbounded)."""
        b = self.bed
        theta = shields_number(tau, b.d50, b.rho_s, b.rho_w)
        return reference_concentration(theta, b.theta_cr, b.d50, b.s, self.dx, b.porosity)

    def exchange(self, s, dt):
        """The suspension's exchange with the bed over dt (0: only the diffusivity is set):
        pick-up E = w_s c_a with van Rijn's c_a at the layer's mid-height (one dx), the
        friction velocity of the diffusivity the local one, at least the far field's (a wake is
        no less turbulent than the flow that makes it). Returns the sand each station received."""
        b = self.bed
        ca = self.pickup_concentration(self.tau)
        ustar = np.sqrt(np.abs(self.tau) / self.rho_w)
        if self.far_field is not None:
            ustar = np.maximum(ustar, np.sqrt(self.far_field[1] / self.rho_w))
        to_bed, before = s.module("suspension").exchange(s, b.z, self.w_s * ca, ustar, self.water_top, dt)
        self.suspended = before - float(np.sum(to_bed))
        return to_bed

    def surface(self, x, left=None):
        """z_b at x: periodic over the bed, or `left` (the rigid floor's level) before its first station."""
        if self.bed.periodic:
            return np.interp(x, self.stations, self.bed.z, period=len(self.stations) * self.dx)
        return np.interp(x, self.stations, self.bed.z, left=left)

    def change(self, x0, x1, n):
        """(x, z_b - z_b0) at n points over [x0, x1]: the movie's bed panel (NaN off a closed bed)."""
        xs = np.linspace(x0, x1, n)
        dz = self.bed.z - self.z0
        if self.bed.periodic:
            return xs, np.interp(xs, self.stations, dz, period=len(self.stations) * self.dx)
        return xs, np.interp(xs, self.stations, dz, left=np.nan, right=np.nan)

    def picture(self, left=None, ripple_height=0.0):
        """The make_case parts that draw this bed: sand under z_b, the bed-change panel (one scale
        for the whole movie where the predicted ripple's height gives it), morfac."""
        m = self.sed["morfac"]
        return dict(
            bed_surface=lambda x: self.surface(x, left),
            bed_panel=self.change,
            bed_range=ripple_height,
            bed_label=f", morfac {m:g}: the bed moves {m:g}x as fast",
        )

    def volume_error(self):
        """Relative change of the sand: the bed's volume and, with suspended load, the sand in
        the water as the bed volume it came from ((1 - n) V_bed + morfac V_water is conserved)."""
        v = self.bed.volume() + self.sed["morfac"] * self.suspended / (1.0 - self.bed.porosity)
        return abs(v - self.v0) / abs(self.v0) if self.v0 else 0.0
