"""What the tunnel's two beds share: the drive that holds the free stream, and the bed's sizes and
rate (the random bed's roughness, the seeded ripples, the turnover against the calibration tunnel)."""

import math

from ...measure.control import HeldCurrent, PIDrive
from ...particles import FLUID
from ...sediment import initial, morfac
from ...sediment.morfac import bed_turnover

BED_PERIODS = 200
CREST_SPEED = 2.0  # the fastest water over grown ripples / U_m, for c0 (1.95 measured at mobility 145)


class TunnelDrive(HeldCurrent):
    """The drive is dU/dt plus PI feedback on the free stream (the water above the lower half of
    the layer), as a tunnel's piston holds the flow: friction on the bed drains momentum during
    the ramp, and without feedback a mean current of 7 % of U_m was left (measured at dx 0.02)."""

    def __init__(self, geo):
        self.period = geo["period"]
        self.omega = 2.0 * math.pi / self.period
        self.Um = 0.5 * geo["orbital_diameter"] * self.omega
        self.above = geo["sand_depth"] + 0.5 * geo["water_depth"]  # the free stream's water
        self.breaks = (self.period,)  # the ramp's end
        self.ctl = PIDrive(0.1 * self.period)

    def u_free(self, st):
        """Mean velocity of the water above the lower half of the layer (out of the boundary layer)
        in a state read (the probes); the drive reads the same on the device."""
        free = (st["kind"] == FLUID) & (st["mat"] == 0) & (st["x"][:, 1] > self.above)
        return float(st["v"][free, 0].mean())

    def target(self, t):
        return free_stream(t, self.Um, self.omega, self.period)[0]

    def law(self, t):
        """The free stream's U(t) and its dU/dt, the feedforward."""
        return free_stream(t, self.Um, self.omega, self.period)


def turnover_periods(cfg):
    """bed_turnover for the tunnel's d0, T and sand."""
    g, sed = cfg.geometry, cfg.sediment
    return bed_turnover(
        g.orbital_diameter, g.period, g.grain_diameter, sed.grain_density / cfg.materials.water.rho0, sed
    )


def morfac_limit(cfg):
    """The largest morfac at which this tunnel's bed turns over no faster than the calibration
    tunnel's (tisph/sediment/morfac.py)."""
    return morfac.morfac_limit(cfg.sediment, turnover_periods(cfg))


def seed_rms(cfg):
    """The random bed's RMS (m): initial.random_bed_rms for the tunnel's d0."""
    return initial.random_bed_rms(cfg.sediment, cfg.geometry.roughness, cfg.geometry.orbital_diameter)


def seed_count(geo, lam_wh):
    """How many seeded ripples fit the periodic length: of seed_ripple_length, or the predicted."""
    lam = geo["seed_ripple_length"] or lam_wh
    return max(1, int(round(geo["length"] / lam))) if lam > 0 else 1


def free_stream(t, Um, omega, period):
    """U(t) = U_m r(t) sin(omega t), r = sin^2(pi t / 2T) over the first period, then 1; and its
    time derivative, the drive."""
    if t < period:
        r = math.sin(0.5 * math.pi * t / period) ** 2
        dr = 0.5 * math.pi / period * math.sin(math.pi * t / period)
    else:
        r, dr = 1.0, 0.0
    return Um * r * math.sin(omega * t), Um * (dr * math.sin(omega * t) + r * omega * math.cos(omega * t))
