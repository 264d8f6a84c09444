"""The oscillating tunnel's bed figures: the bed at five times against the predicted ripple, and
the ripples' length and steepness against bed periods with Wiberg & Harris's bands."""

import numpy as np

from ..ripples import ORBITAL_BAND, STEEPNESS_BAND
from .plots import pyplot, save


def plot_bed(path, arr, stations, geo, dx, lam_wh, eta_wh, level=None):
    """The bed change at five times (level: the bed itself above that level, from the start),
    with the predicted equilibrium ripple for scale."""
    Lx, Tp = geo["length"], geo["period"]
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 3))
    times = np.linspace(arr[0, 0], arr[-1, 0], 5)
    for tt in times if level is not None else times[1:]:
        r = arr[np.argmin(np.abs(arr[:, 0] - tt))]
        base = level if level is not None else arr[0, 1:]
        ax.plot(stations, 1e3 * (r[1:] - base), lw=0.9, label=f"t = {r[0]:.1f} s")
    # the predicted equilibrium ripple, for scale
    xr = np.linspace(0.0, min(Lx, 2 * lam_wh), 100)
    ax.plot(
        xr,
        1e3 * 0.5 * eta_wh * np.sin(2 * np.pi * xr / lam_wh),
        "k--",
        lw=0.8,
        label=f"Wiberg & Harris: {100 * lam_wh:.1f} cm x {100 * eta_wh:.1f} cm",
    )
    ax.axhspan(-0.5e3 * dx, 0.5e3 * dx, color="0.93")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("bed change (mm)" if level is None else "bed level (mm)")
    ax.set_title(f"oscillating tunnel, d0 = {geo['orbital_diameter']:g} m, T = {Tp:g} s (grey: +-dx/2)", fontsize=9)
    ax.legend(fontsize=7, ncol=2)
    save(fig, path)


def plot_growth(path, c, geo, morfac):
    """Ripple length / d0 and steepness (the probe columns c) against bed periods (t morfac / T),
    with the bands of Wiberg & Harris and van der A (0.5-0.75 d0, steepness 0.10-0.20)."""
    d0, Tp = geo["orbital_diameter"], geo["period"]
    lm, hr = np.asarray(c["ripple_length"], float), np.asarray(c["ripple_height"], float)
    per = np.asarray(c["t"], float) * morfac / Tp
    lam = lm / d0
    with np.errstate(invalid="ignore", divide="ignore"):
        st = np.where(lm > 0, hr / lm, np.nan)
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(2, 1, figsize=(7, 4.5), sharex=True)
    a1.plot(per, lam, lw=1.0)
    a1.axhspan(*ORBITAL_BAND, color="0.9", label="{:g}-{:g} d0".format(*ORBITAL_BAND))
    a1.set_ylabel("ripple length / d0")
    a1.legend(fontsize=7, loc="upper left")
    a2.plot(per, st, lw=1.0)
    a2.axhspan(*STEEPNESS_BAND, color="0.9", label="{:.2f}-{:.2f}".format(*STEEPNESS_BAND))
    a2.set_ylabel("steepness")
    a2.set_xlabel(f"bed periods (t x morfac {morfac:g} / T)")
    a2.legend(fontsize=7, loc="upper left")
    fig.suptitle(f"ripple growth, d0 = {d0:g} m, T = {Tp:g} s", fontsize=10)
    save(fig, path)
