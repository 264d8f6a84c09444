"""The frames' colours: viridis and a diverging map, the particle kinds' plain colours, and the
vorticity a panel is coloured by."""

import numpy as np

# Viridis, sampled at 9 points (matplotlib's data), interpolated linearly.
_VIRIDIS = np.array(
    [
        [0.267, 0.005, 0.329],
        [0.283, 0.141, 0.458],
        [0.254, 0.265, 0.530],
        [0.207, 0.372, 0.553],
        [0.164, 0.471, 0.558],
        [0.128, 0.567, 0.551],
        [0.135, 0.659, 0.518],
        [0.478, 0.821, 0.318],
        [0.993, 0.906, 0.144],
    ]
)
BACKGROUND = (1.0, 1.0, 1.0)
BOUNDARY = (0.55, 0.55, 0.55)
WATER = (0.36, 0.62, 0.90)
SAND = (0.86, 0.70, 0.42)
MODES = ("speed", "phase", "flat", "material", "pressure", "density", "vorticity", "concentration")


def colormap(values):
    """Viridis RGB in [0, 1] for values in [0, 1] (clipped)."""
    v = np.clip(np.asarray(values, float), 0, 1) * (len(_VIRIDIS) - 1)
    i = np.minimum(v.astype(int), len(_VIRIDIS) - 2)
    f = (v - i)[..., None]
    return _VIRIDIS[i] * (1 - f) + _VIRIDIS[i + 1] * f


_DIVERGING = np.array(
    [[0.23, 0.30, 0.75], [0.55, 0.69, 0.99], [0.87, 0.87, 0.87], [0.96, 0.60, 0.48], [0.71, 0.02, 0.15]]
)  # blue - grey - red, for signed fields


def diverging(values):
    """Blue-grey-red RGB for values in [0, 1] (0.5: zero)."""
    v = np.clip(np.asarray(values, float), 0, 1) * (len(_DIVERGING) - 1)
    i = np.minimum(v.astype(int), len(_DIVERGING) - 2)
    f = (v - i)[..., None]
    return _DIVERGING[i] * (1 - f) + _DIVERGING[i + 1] * f


def vorticity(x, v, dx):
    """dv/dx - du/dy at each point, from the velocities binned on a grid of 2 dx."""
    cell = 2.0 * dx
    lo = x.min(0)
    ij = np.floor((x - lo) / cell).astype(int)
    nx, ny = ij.max(0) + 1
    n = np.zeros((nx, ny))
    u = np.zeros((nx, ny))
    w = np.zeros((nx, ny))
    np.add.at(n, (ij[:, 0], ij[:, 1]), 1.0)
    np.add.at(u, (ij[:, 0], ij[:, 1]), v[:, 0])
    np.add.at(w, (ij[:, 0], ij[:, 1]), v[:, 1])
    with np.errstate(invalid="ignore", divide="ignore"):
        u, w = np.where(n > 0, u / n, 0.0), np.where(n > 0, w / n, 0.0)
    if nx < 2 or ny < 2:
        return np.zeros(len(x))
    curl = np.gradient(w, cell, axis=0) - np.gradient(u, cell, axis=1)
    return curl[ij[:, 0], ij[:, 1]]


# a concentration panel spans three decades below its top: suspended sand falls off exponentially
# with height (Rouse), so a linear scale shows only the bed's layer
DECADES = 3


def field_values(field, st, speed, fluid, dx):
    """Each particle's value of the drawn field (the fluid's vorticity; 0 elsewhere)."""
    if field == "vorticity":
        vals = np.zeros(len(st["kind"]))
        if fluid.any():
            vals[fluid] = vorticity(st["x"][fluid], st["v"][fluid], dx)
        return vals
    return {
        "speed": speed,
        "pressure": st["p"],
        "density": st["rho"],
        "concentration": 100.0 * st["c"] if "c" in st else np.zeros(len(st["kind"])),
    }.get(field)


def colour_range(field, values, vrange, speed_scale, pressure_scale, dx):
    """(lo, hi) of a field's colour bar: vrange as given (pressure in kPa), else the scene's top
    speed, the held pressure scale, a vorticity from the top speed over 10 dx, DECADES of
    concentration, or the values' percentiles."""
    if vrange:  # in the unit the colour bar shows: kPa for pressure
        lo, hi = vrange
        if field == "concentration" and lo <= 0:  # a log scale: DECADES below the top
            return hi * 10.0**-DECADES, hi
        return (1000.0 * lo, 1000.0 * hi) if field == "pressure" else vrange
    if field == "speed":
        hi = speed_scale if speed_scale > 0 else float(np.percentile(values, 99)) if len(values) else 1.0
        return 0.0, max(hi, 1e-6)
    if field == "pressure":  # the water's, not the walls' (whose pressure can be several times it)
        return 0.0, max(pressure_scale or 1.0, 1e-6)
    if field == "vorticity":
        if speed_scale > 0:  # one range for the movie: the colour bar's top speed over 10 dx
            return -speed_scale / (10.0 * dx), speed_scale / (10.0 * dx)
        w = float(np.percentile(np.abs(values), 98)) if len(values) else 1.0
        return -max(w, 1e-6), max(w, 1e-6)
    if field == "concentration":
        hi = max(float(np.percentile(values, 99.5)) if len(values) else 0.0, 1e-6)
        return hi * 10.0**-DECADES, hi
    lo, hi = np.percentile(values, [1, 99]) if len(values) else (0.0, 1.0)
    return float(lo), float(max(hi, lo + 1e-6))
