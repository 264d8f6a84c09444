"""Wave flume: a piston or flap paddle at the left makes regular waves over a flat bed; an
absorbing zone at the far end takes them out. Wave gauges record the free surface, and the wave
height at one, two and three wavelengths from the paddle is checked against Biesel's linear
wave-maker theory (tisph.waves): piston H/S = 2 (cosh 2kh - 1)/(sinh 2kh + 2kh). An array of
gauges in front of the absorbing zone separates the incident and reflected waves (the absorber's
reflection coefficient) and the second harmonic's bound and free parts (paddle.order = 2 adds
the second-order stroke that cancels the free one, for a piston or a flap).

Default (scenes/flume_piston.toml is the same case, spelled out): depth 0.25 m, period 0.8 s
(kh = 1.68, wavelength 0.93 m), piston stroke 4 cm, so Biesel gives H = 6.1 cm (H/L = 0.065:
mild, linear theory applies within a few per cent). A gauge's window starts when the fully
ramped waves have reached it at the group velocity and runs to the end; the reflection's starts
when the wave reflected from the far end is back over the array.

The numerics are chosen for waves (what each does to the height: docs/waves.md): walls
whose pressure is extrapolated from the water (Adami et al. 2012), where the dynamic wall's
density ratchets up under the paddle's foot and the wave comes out low; no artificial viscosity
(density diffusion keeps the pressure smooth; the water's own viscosity stays); density diffusion
with renormalised gradients (Antuono et al. 2010), which leaves a wave's dynamic pressure under the
free surface alone; a Wendland kernel with h = 2.5 dx, whose wider support carries the wave with
less loss.
"""

import math
import sys
from functools import partial

import numpy as np

from ...case import Scene, make_case, resolves
from ...constants import G
from ...measure import records
from ...particles import FLUID, MOVING, WALL, ParticleSet, block, hydrostatic_density, tait_B, wall_density
from ...runner import common_params, run_scene, sound_speed
from ...settings.config import ConfigError, physics_from_config
from ...settings.plausible import warn_waves, warn_window
from ...settings.schema import NON_NEGATIVE, POSITIVE, K
from ...settings.schemes import numerics
from ...waves import theory
from ...waves.absorb import with_control
from ...waves.irregular import IRREGULAR
from ...waves.paddle import PADDLE, check_paddle, paddle, stroke_step
from ...waves.theory import linear_wave
from .record import FlumeRecord


def gauge_positions(geo, wavelength):
    """Gauge x (m): geometry.gauges_x, or gauges_wavelengths times the wavelength; each in front
    of the absorbing zone."""
    key = "gauges_x" if geo["gauges_x"] else "gauges_wavelengths"
    xg = [float(w) for w in geo["gauges_x"]] or [w * wavelength for w in geo["gauges_wavelengths"]]
    end = geo["length"] - geo["damping_length"]
    for x in xg:
        if x >= end:
            raise ConfigError(
                f"geometry.{key}",
                geo[key],
                f"gauges in front of the absorbing zone (x < {end:g} m; one wavelength is {wavelength:.3g} m)",
            )
    return xg


def array_positions(geo, wavelength):
    """The analysis array (reflection, bound and free second harmonics): geometry.array_gauges
    gauges a tenth of a wavelength apart, the last half a wavelength in front of the absorbing
    zone; [] when the flume is too short for it or array_gauges = 0."""
    n = geo["array_gauges"]
    end = geo["length"] - geo["damping_length"] - 0.5 * wavelength
    xs = [end - 0.1 * wavelength * (n - 1 - i) for i in range(n)]
    return xs if n and xs[0] > 0.5 * wavelength else []


def _particles(cfg, c0):
    """Still water on a flat floor, the end wall and the paddle, hydrostatic densities."""
    geo, num = cfg.geometry, cfg.numerics
    dx, Lf, d, Hw = num.dx, geo.length, geo.depth, geo.wall_height
    rho0 = cfg.materials.water.rho0
    T = num.wall_layers * dx
    h = num.h_factor * dx
    ps = ParticleSet()
    # whole columns up to the end wall: a length that is not a whole number of spacings would round
    # the last column into the wall (3.23 m at dx 0.02 did, and stopped at once)
    water = block(0.0, 0.0, dx * math.floor(Lf / dx + 1e-9), d, dx)
    ps.add(water, FLUID, 0, hydrostatic_density(d - water[:, 1], rho0, c0, G), rho0 * dx * dx)
    pad_pts, motion, extra, reach = paddle(cfg, d, Hw)
    x_left = -reach - 2 * T
    walls = np.vstack([block(x_left, -T, Lf + T, 0.0, dx), block(Lf, 0.0, Lf + T, Hw, dx)])
    ps.add(walls, WALL, 0, wall_density(walls, water, dx, h, rho0, c0, G), rho0 * dx * dx)
    ps.add(pad_pts, MOVING, 0, wall_density(pad_pts, water, dx, h, rho0, c0, G), rho0 * dx * dx)
    return ps, extra, reach, x_left


class Flume(Scene):
    """Wave flume: a piston or flap paddle makes waves over a flat bed, measured against Biesel."""

    NAME = "flume"

    SCHEMA = {
        "run": {
            "end_time": K(
                16.0, "long enough for the wave reflected from the far end to be back over the array (reflection)", "s"
            )
        },
        "numerics": numerics("default", dx=0.0125),
        "geometry": {
            "length": K(4.5, "paddle (x = 0) to the end wall", "m", range=POSITIVE),
            "depth": K(0.25, "still water", "m", range=POSITIVE),
            "wall_height": K(0.45, "the walls' height", "m", range=POSITIVE),
            "damping_length": K(1.2, "absorbing zone at the far end (m); 0: none", range=NON_NEGATIVE),
            "damping_rate": K(
                10.0, "the absorbing zone's strongest velocity relaxation rate", "1/s", range=NON_NEGATIVE
            ),
            "gauges_x": K([], "gauge positions (m from the paddle's mean position)"),
            "gauges_wavelengths": K(
                [1.0, 2.0, 3.0], "gauge positions in wavelengths from the paddle, when gauges_x is empty"
            ),
            "array_gauges": K(6, "gauges of the reflection and second-harmonic array", range=(0, 12, True, True)),
        },
        "paddle": dict(PADDLE, **IRREGULAR),
        "materials": {"water": {"rho0": 1000.0, "viscosity": 1.0e-3}},
        "output": {"frame_interval": 0.04, "probe_interval": 0.01},
    }

    def derive(self, cfg, given):
        """The stroke a wave height asks for (a resolving step: the values and run.log's line)."""
        return stroke_step(cfg, cfg.geometry.depth, self.DEFAULTS["paddle"]["stroke"])

    def check(self, cfg):
        g, dx = cfg.geometry, cfg.numerics.dx
        resolves(g.depth, 8, "the depth", dx)
        if g.depth >= g.wall_height:
            raise ConfigError("geometry.depth", g.depth, f"below geometry.wall_height = {g.wall_height}")
        if g.damping_length >= 0.8 * g.length:
            raise ConfigError(
                "geometry.damping_length", g.damping_length, f"under 80 % of the flume length ({0.8 * g.length:g} m)"
            )
        for key, unit in (("gauges_x", "m"), ("gauges_wavelengths", "wavelengths")):
            if not isinstance(g[key], list) or any(not isinstance(v, (int, float)) or v <= 0 for v in g[key]):
                raise ConfigError(f"geometry.{key}", g[key], f"a list of positive numbers ({unit} from the paddle)")
        if 0 < g.array_gauges < 3:
            raise ConfigError(
                "geometry.array_gauges",
                g.array_gauges,
                "0 (no array) or 3 to 12 (two waves are fitted at each frequency)",
            )
        check_paddle(cfg, g.depth, g.length, default_stroke=self.DEFAULTS["paddle"]["stroke"])

    def build(self, cfg):
        geo, num, p = cfg.geometry, cfg.numerics, cfg.paddle
        dx, Lf, d, Hw = num.dx, geo.length, geo.depth, geo.wall_height
        rho0 = cfg.materials.water.rho0
        omega, k, wavelength, cg, hs_ratio = linear_wave(cfg, d)
        H_biesel = hs_ratio * p.stroke
        c0, u_max = sound_speed(cfg, math.sqrt(G * d))  # shallow-water speed bounds the orbital speeds
        L = num.wall_layers
        T = L * dx
        h = num.h_factor * dx
        ps, extra, reach, x_left = _particles(cfg, c0)
        pad = 3 * T + 4 * h
        domain = ((x_left - pad, -pad), (Lf + pad, 2 * Hw + pad))
        params = common_params(cfg, c0, G, depth=d)
        params.update(extra)
        damping = ()
        if geo.damping_length > 0:
            damping = (Lf - geo.damping_length, Lf, geo.damping_rate)
        xg = gauge_positions(geo, wavelength)
        xa = array_positions(geo, wavelength)
        k2 = theory.wavenumber(2 * omega, d, G)
        cg2 = theory.group_velocity(2 * omega, k2, d)
        if not p.spectrum and not p.series:
            warn_waves(cfg, H_biesel, k, d)
            warn_window(p, xg, cg, cfg.run.end_time, p.period, records.arrival_time)
            if p.order == 2 and xa:  # the free second harmonic is fitted once it is over the array
                warn_window(
                    p,
                    xa[-1:],
                    cg2,
                    cfg.run.end_time,
                    p.period,
                    records.arrival_time,
                    "the free second harmonic (at its group velocity) would",
                )
        rec = FlumeRecord(cfg, (omega, k, wavelength, cg, hs_ratio, k2, cg2), xg, xa)
        margin = T + dx
        return make_case(
            name=self.NAME,
            particles=ps,
            materials=[dict(name="water", rho0=rho0, viscosity=cfg.materials.water.viscosity, B=tait_B(rho0, c0))],
            domain=domain,
            params=params,
            physics=physics_from_config(cfg, paddle=p.type, damping=damping),
            marks=[(x, f"g{i + 1}") for i, x in enumerate(xg)],
            zones=[(damping[0], damping[1], "absorber")] if damping else [],
            # the frame: the paddle to half a wavelength past the last gauge (a long flume drawn
            # whole is a strip); output.view draws another region
            view=(
                (x_left - margin, -margin),
                (min(Lf + margin, max(xg, default=Lf) + 0.5 * wavelength), min(Hw, 1.6 * d) + margin),
            ),
            u_max=u_max,
            # colour top: twice the linear surface orbital speed, not the sound-speed bound
            speed_scale=2.0 * 0.5 * (p.hs if p.spectrum else H_biesel) * omega / math.tanh(k * d),
            probe_columns=rec.cols + rec.acols,
            probe=rec.gauges.read,
            metrics=rec.metrics,
            finalize=rec.finalize,
            container=(-reach - dx, 0.0, Lf, float("inf"), Hw),
            control=with_control(extra["motion"]),
            persist=(rec.gauges,) + ((extra["motion"],) if p.absorb else ()),
        )


SCENE = Flume()
main = partial(run_scene, SCENE)


if __name__ == "__main__":
    sys.exit(main())
