"""Physical plausibility of a case, checked before anything compiles: values that are impossible
are refused (exit 2) with the physical reason and, where the lengths look like centimetres or
millimetres, that guess; values the model does not resolve are warned about at the start of the
run (warnings captured into summary.json).

Lengths in tisph are metres. A laboratory case (the scenes here) has a water depth of centimetres
to metres and a dx of millimetres to centimetres; a case written in centimetres has its depth in
tens and its dx in whole numbers, in millimetres both a thousand times too large.
"""

import math
import warnings

from .config import ConfigError

# the water's rest density must be near 1000 kg/m3 (fresh to sea water, with room for brines)
WATER_DENSITY = (900.0, 1300.0)
# Miche's breaking limit on wave steepness: H / L <= 0.142 tanh(kh)
MICHE = 0.142
# the wave heights tisph's flume measurements resolve: at H = 4.8 dx the height at three
# wavelengths was 7 % low (docs/waves.md), at 2.4 dx 20 %
MIN_HEIGHT_DX = 3.0
# a wavelength shorter than this many smoothing lengths is not a wave the kernel can carry
MIN_WAVELENGTH_H = 10.0
# linear (Biesel) generation holds for Ursell numbers H L^2 / h^3 below about 26 (cnoidal above)
URSELL_LINEAR = 26.0


def unit_guess(cfg):
    """' (the lengths look like centimetres: ...)' or millimetres, or '' when they look like metres:
    from the depth and dx a scene has."""
    g, dx = cfg.get("geometry", {}), cfg.numerics.dx
    depth = next((g[k] for k in ("depth", "water_depth", "column_height", "height") if k in g), None)
    if depth is None:
        return ""
    seen = f"depth = {depth:g}, dx = {dx:g}"
    if depth > 200 or dx > 20:
        return f" (these lengths look like millimetres: {seen}; tisph reads metres)"
    if depth > 8 or dx >= 0.5:
        return f" (these lengths look like centimetres: {seen}; tisph reads metres)"
    return ""


def height_guess(height, depth):
    """' (... looks like centimetres ...)' for a wave height no water of this depth holds (over 0.8
    of it) that would be a wave in centimetres or millimetres; '' otherwise."""
    if height <= 0.8 * depth:
        return ""
    for unit, f in (("centimetres", 100.0), ("millimetres", 1000.0)):
        if height / f <= 0.8 * depth:
            return (
                f" ({height:g} looks like {unit}: tisph reads metres, so {height / f:g} m here; the still "
                f"water is {depth:g} m deep)"
            )
    return ""


def check_materials(cfg):
    """The water's rest density near water's."""
    water = cfg.get("materials", {}).get("water")
    if not water:
        return
    rho = water["rho0"]
    lo, hi = WATER_DENSITY
    if not lo <= rho <= hi:
        hint = " (a value near 1 looks like g/cm3; tisph reads kg/m3)" if 0.5 <= rho <= 1.5 else ""
        raise ConfigError("materials.water.rho0", rho, f"a water density between {lo:g} and {hi:g} kg/m3{hint}")


def check_regular_waves(cfg, key, H, k, depth):
    """Refuse waves no water can carry: steeper than Miche's breaking limit, or shorter than the
    kernel resolves. key: the paddle key that set the height (stroke or wave_height)."""
    L = 2.0 * math.pi / k
    h = cfg.numerics.h_factor * cfg.numerics.dx
    limit = MICHE * math.tanh(k * depth)
    guess = unit_guess(cfg)
    if limit < H / L:
        raise ConfigError(
            key,
            cfg.paddle[key.split(".")[1]],
            f"a wave no steeper than Miche's breaking limit 0.142 tanh(kh) = {limit:.3g}: this one is "
            f"H / L = {H:.3g} / {L:.3g} m = {H / L:.3g} (kh = {k * depth:.3g}){guess}",
        )
    if MIN_WAVELENGTH_H * h > L:
        raise ConfigError(
            "numerics.dx",
            cfg.numerics.dx,
            f"a dx whose smoothing length h = {h:.3g} m is at most a tenth of the wavelength, "
            f"{L:.3g} m ({L / h:.3g} h){guess}",
        )


def warn_waves(cfg, H, k, depth, linear_metric=True):
    """Warnings for waves the run carries but does not resolve well: a height under MIN_HEIGHT_DX
    spacings, and (where a Biesel height is the result) an Ursell number beyond linear theory."""
    dx = cfg.numerics.dx
    L = 2.0 * math.pi / k
    if MIN_HEIGHT_DX * dx > H:
        warnings.warn(
            f"the wave height {H:.3g} m is {H / dx:.2g} dx: under {MIN_HEIGHT_DX:g} dx the waves lose "
            f"height as they run (measured: 20 % at three wavelengths at 2.4 dx); numerics.dx at most "
            f"{H / MIN_HEIGHT_DX:.3g} m resolves it"
        )
    ur = H * L * L / depth**3
    if linear_metric and ur > URSELL_LINEAR:
        warnings.warn(
            f"the Ursell number H L^2 / h^3 = {ur:.3g} is above {URSELL_LINEAR:g}: the waves are "
            "nonlinear (cnoidal), and Biesel's linear height is not what a gauge should read"
        )


def warn_window(p, xs, cg, end_time, period, arrival, what="the waves"):
    """A warning when the run ends before MIN_PERIODS wave periods have passed a gauge after the
    ramped waves reached it, with the end time that gives them."""
    if not xs:
        return None
    x = max(xs)
    need = arrival(p, x, cg) + 3.0 * period
    if end_time < need:
        warnings.warn(
            f"run.end_time = {end_time:g} s leaves {math.floor(10.0 * max(0.0, (end_time - arrival(p, x, cg)) / period)) / 10.0:g} "
            f"wave periods at the gauge at x = {x:g} m after {what} reach it: its height needs at "
            f"least 3; run.end_time = {math.ceil(need):g} s gives them"
        )
    return need


def warn_gauges(cfg, gauges, depth_at):
    """The warnings a case's [[gauge]] tables earn at the start: a surface gauge with no water under
    it (dry land: its wave height means nothing), a window that starts at or after the end, and a
    run too short for any gauge to record two readings. depth_at(x): the still water's depth there
    (NaN or <= 0 where dry)."""
    end, dt = cfg.run.end_time, cfg.output.probe_interval
    dry = [q for q in gauges if q["type"] == "surface" and not depth_at(q["x"]) > 0]
    if dry:
        warnings.warn(
            "surface gauges " + ", ".join(f"{q['label']} (x = {q['x']:g} m)" for q in dry) + " stand on "
            "dry land at the start: no water under them, so their wave heights read nothing"
        )
    late = [q for q in gauges if q["from_time"] >= end]
    if late:
        warnings.warn(
            "gauges "
            + ", ".join(f"{q['label']} (from_time = {q['from_time']:g} s)" for q in late)
            + f" start their statistics at or after run.end_time = {end:g} s: they report none"
        )
    if gauges and all(end - q["from_time"] < 2 * dt for q in gauges):
        warnings.warn(
            f"run.end_time = {end:g} s leaves no gauge two readings (one every output.probe_interval = "
            f"{dt:g} s after its from_time): summary.json will have no gauge metrics"
        )


def warn_case_waves(cfg, H, k, depth, xs, cg, period, arrival):
    """A case's regular waves: warn_waves for the height, and warn_window for the surface gauges at
    xs (m in front of the paddle)."""
    warn_waves(cfg, H, k, depth)
    warn_window(cfg.paddle, [x for x in xs if x > 0], cg, cfg.run.end_time, period, arrival)
