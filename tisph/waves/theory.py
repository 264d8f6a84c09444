"""Linear wave theory: the dispersion relation, Biesel's (1951) wave-maker transfer functions for
a piston and a flap, the group velocity, and the linear wave a configured paddle makes. The
bottom of the wave-making package: it imports only the constants and, for a paddle table's
period, the record analysis below it."""

import math

from ..constants import G
from ..measure.records import wave_period


def wavenumber(omega, depth, g=9.81):
    """k from the linear dispersion relation omega^2 = g k tanh(k h) (Newton, from Eckart's guess)."""
    k0 = omega * omega / g
    k = k0 / math.sqrt(math.tanh(k0 * depth)) if k0 * depth > 0 else k0
    for _ in range(50):
        th = math.tanh(k * depth)
        f = g * k * th - omega * omega
        df = g * th + g * k * depth * (1 - th * th)
        dk = f / df
        k -= dk
        if abs(dk) < 1e-12 * k:
            break
    return k


def biesel_piston(kh):
    """Piston wave maker, H/S = 2 (cosh 2kh - 1) / (sinh 2kh + 2kh) (Biesel 1951; Dean & Dalrymple).
    Past kh = 20 the deep-water value 2 to round-off (and no overflow)."""
    kh = min(kh, 20.0)
    return 2 * (math.cosh(2 * kh) - 1) / (math.sinh(2 * kh) + 2 * kh)


def biesel_flap(kh):
    """Flap hinged at the bed, H/S = (4 sinh kh / kh) (kh sinh kh - cosh kh + 1) / (sinh 2kh + 2kh).
    Past kh = 20 its deep-water form 2 (1 - 1/kh) (exact to e^-2kh; no overflow)."""
    if kh > 20.0:
        return 2.0 * (1.0 - 1.0 / kh)
    return 4 * math.sinh(kh) / kh * (kh * math.sinh(kh) - math.cosh(kh) + 1) / (math.sinh(2 * kh) + 2 * kh)


def group_velocity(omega, k, depth):
    c = omega / k
    kh = min(k * depth, 20.0)  # deep water past it (and no overflow)
    return 0.5 * c * (1 + 2 * kh / math.sinh(2 * kh))


def linear_wave(cfg, depth):
    """(omega, k, wavelength, group velocity, Biesel H/S) of the configured paddle (at the peak
    period with a spectrum)."""
    p = cfg.paddle
    omega = 2 * math.pi / wave_period(p)
    k = wavenumber(omega, depth, G)
    hs = biesel_piston(k * depth) if p.type == "piston" else biesel_flap(k * depth)
    return omega, k, 2 * math.pi / k, group_velocity(omega, k, depth), hs


def hunt_run_up(H, omega, k, depth, slope):
    """Hunt's (1959) run-up of regular waves breaking on a plane slope of 1 : slope, R = xi H0
    with the surf similarity xi = tan(beta) / sqrt(H0 / L0) (Battjes 1974); H0 is the deep-water
    height of H at `depth` by linear shoaling (H0 = H / Ks, Ks = sqrt(cg0 / cg)). For xi above
    about 2.3 the waves surge rather than break and R levels off near 2.3 H0 (EurOtop 2018)."""
    cg0 = 0.5 * G / omega
    H0 = H / math.sqrt(cg0 / group_velocity(omega, k, depth))
    L0 = 2.0 * math.pi * G / omega**2
    xi = (1.0 / slope) / math.sqrt(H0 / L0)
    return min(xi, 2.3) * H0
