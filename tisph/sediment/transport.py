"""Bed shear, threshold and bed-load flux: the formulae of the morphodynamic bed.

Each function takes and returns NumPy arrays (or floats) in SI units and cites its source;
tests/sediment/test_bedload.py checks them against the formulae and their published values.
"""

import math

import numpy as np

from ..constants import KAPPA, G

NU_WATER = 1.0e-6  # kinematic viscosity of water at about 20 C (m2/s)


def grain_roughness(d50):
    """Nikuradse grain roughness k_s = 2.5 d50 and the log law's z0 = k_s / 30 (rough bed)."""
    ks = 2.5 * d50
    return ks, ks / 30.0


def shear_log_law(u_r, z_r, d50, rho=1000.0, z0=None):
    """Bed shear stress (Pa, signed with u_r) from the velocity u_r at height z_r above the bed
    through the rough-wall log law u* = kappa u_r / ln(z_r / z0), tau = rho u*^2; z0: the
    grain roughness's k_s / 30 unless given (a current's own roughness)."""
    if z0 is None:
        _, z0 = grain_roughness(d50)
    ustar = KAPPA * np.abs(u_r) / np.log(np.maximum(z_r, 2.0 * z0) / z0)
    return rho * ustar * ustar * np.sign(u_r)


def swart_friction_factor(amplitude, d50):
    """Wave friction factor, Swart (1974): f_w = exp(5.213 (k_s / A)^0.194 - 5.977), A the
    near-bed orbital amplitude, capped at 0.3 for very rough beds (k_s / A > 0.63)."""
    ks, _ = grain_roughness(d50)
    A = np.maximum(np.asarray(amplitude, float), 1e-9)
    return np.minimum(np.exp(5.213 * (ks / A) ** 0.194 - 5.977), 0.3)


def shear_waves(u, amplitude, d50, rho=1000.0):
    """Instantaneous wave bed shear tau = 0.5 rho f_w |u| u (Pa, signed with u)."""
    u = np.asarray(u, float)
    return 0.5 * rho * swart_friction_factor(amplitude, d50) * np.abs(u) * u


def dimensionless_grain_size(d50, s, nu=NU_WATER, g=G):
    """D* = d50 ((s - 1) g / nu^2)^(1/3)."""
    return d50 * ((s - 1.0) * g / nu**2) ** (1.0 / 3.0)


def shields_critical(d50, s, nu=NU_WATER, g=G):
    """Critical Shields number on a flat bed, Soulsby & Whitehouse (1997):
    theta_cr = 0.30 / (1 + 1.2 D*) + 0.055 (1 - exp(-0.02 D*))."""
    D = dimensionless_grain_size(d50, s, nu, g)
    return 0.30 / (1.0 + 1.2 * D) + 0.055 * (1.0 - math.exp(-0.02 * D))


def shields_number(tau, d50, rho_s, rho=1000.0, g=G):
    """theta = |tau| / ((rho_s - rho) g d50)."""
    return np.abs(tau) / ((rho_s - rho) * g * d50)


def slope_factor(dzdx, direction, repose_deg):
    """Threshold on a slope along the flow, sin(phi + beta) / sin(phi) with beta the bed's angle
    rising in the flow direction (Dey 2003; SPHERA's K_beta): up a slope the grains must be
    lifted, so the threshold grows; down it falls, to 0 at the angle of repose."""
    phi = math.radians(repose_deg)
    beta = np.arctan(np.asarray(dzdx, float) * np.sign(direction))
    return np.maximum(np.sin(phi + beta), 0.0) / math.sin(phi)


def transport_scale(d50, s, g=G):
    """sqrt((s - 1) g d50^3): the bed-load flux of Phi = 1 (m2/s)."""
    return math.sqrt((s - 1.0) * g * d50**3)


def bedload_mpm(theta, theta_cr):
    """Meyer-Peter & Mueller (1948): Phi = 8 (theta - theta_cr)^1.5 above the threshold."""
    return 8.0 * np.maximum(np.asarray(theta, float) - theta_cr, 0.0) ** 1.5


def bedload_nielsen(theta, theta_cr):
    """Nielsen (1992) for waves: Phi = 12 theta^0.5 (theta - theta_cr) above the threshold."""
    theta = np.asarray(theta, float)
    return 12.0 * np.sqrt(theta) * np.maximum(theta - theta_cr, 0.0)


FORMULAE = {"mpm": bedload_mpm, "nielsen": bedload_nielsen}


def settling_velocity(d50, s, nu=NU_WATER, g=G):
    """Settling velocity of a natural sand grain, Soulsby (1997):
    w_s = nu / d50 (sqrt(10.36^2 + 1.049 D*^3) - 10.36)."""
    D = dimensionless_grain_size(d50, s, nu, g)
    return nu / d50 * (math.sqrt(10.36**2 + 1.049 * D**3) - 10.36)


def reference_concentration(theta, theta_cr, d50, s, a, porosity=0.4, nu=NU_WATER, g=G):
    """Equilibrium volume concentration at height a above the bed, van Rijn (1984), Sediment
    transport part II: suspended load transport, J. Hydraul. Eng. 110(11): c_a = 0.015 (d50 / a) T^1.5 / D*^0.3 with the transport stage
    T = (theta - theta_cr) / theta_cr; capped at the bed's own concentration 1 - n."""
    T = np.maximum(np.asarray(theta, float) - theta_cr, 0.0) / theta_cr
    D = dimensionless_grain_size(d50, s, nu, g)
    return np.minimum(0.015 * d50 / a * T**1.5 / D**0.3, 1.0 - porosity)


def rouse_profile(z, depth, a, c_a, w_s, ustar, kappa=KAPPA):
    """Equilibrium suspended concentration at height z above the bed under a current (Rouse
    1937): c = c_a ((H - z) / z * a / (H - a))^(w_s / (kappa u*)) above the reference height a,
    c_a below it; H the water depth."""
    z = np.clip(np.asarray(z, float), a, None)
    H = np.maximum(np.asarray(depth, float), 1.001 * a)
    ratio = np.clip((H - z) / z * a / (H - a), 0.0, None)
    return c_a * ratio ** (w_s / (kappa * ustar))


def ripple_turnover_periods(d0, T, d50, s, ripple_length, ripple_height, porosity=0.4, formula="mpm"):
    """Wave periods the flat bed's bed load takes to move one ripple's sand (its cross-section,
    length x height / 2, at the bed's packing), for a near-bed oscillation U_m sin(omega t) of
    orbital diameter d0 = U_m T / pi: Swart's shear, the threshold of Soulsby & Whitehouse and
    the bed-load formula, averaged over the period. A morphological factor m makes the bed move
    m times as far each period, so a morfac that keeps this over m as long as in a case known to
    work (sediment/morfac.py's calibration tunnel) keeps the bed all but still through a wave period, as the
    factor assumes (Roelvink 2006)."""
    Um = math.pi * d0 / T
    fw = float(swart_friction_factor(0.5 * d0, d50))
    theta = (
        0.5 * fw * Um * Um / ((s - 1.0) * G * d50) * np.sin((np.arange(400) + 0.5) * np.pi / 400) ** 2
    )  # the half period's midpoints
    q = float(np.mean(FORMULAE[formula](theta, shields_critical(d50, s)))) * transport_scale(d50, s)
    return (1.0 - porosity) * 0.5 * ripple_length * ripple_height / (q * T) if q > 0 else float("inf")
