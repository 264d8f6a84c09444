"""A standing wave in a closed tank: how much of a wave the numerics take per period, with no
paddle, no absorber and no gauge window in the way.

    python -m tisph.bench --standing [--dx DX] [--end-time PERIODS] [--quick]

The tank is one wavelength of the default flume's wave long (0.93 m, 0.25 m deep, kh = 1.68,
T = 0.80 s); the water starts at rest with its surface a cos(kx), a = 3 cm (the flume's H / 2),
and its pressure hydrostatic from that surface. Linear theory has the mode ring at constant
amplitude (the water's own viscosity takes 1e-4 of it a period); whatever it loses is the
numerics'. Each period's amplitude is the mode's half range over that period, from four surface
gauges projected on cos(kx); the decay is the fitted exponential rate per period after the first
period. It runs the flume's numerics (tisph.scenes.flume) with each density diffusion: the
flume's waves lose c / c_g = 1.6 times as much per wavelength as the mode does per period.
Writes OUT/standing/standing.md and standing.csv.
"""

import functools
import math
import os
import time

import numpy as np

from ..constants import G
from ..io import ensure_dir, write_csv, write_text
from ..runner import resolve
from ..scenes import flume
from ..waves.theory import linear_wave
from .common import table

DEPTH, AMPLITUDE = 0.25, 0.03
KINDS = ("fourtakas", "antuono")


@functools.cache
def mode():
    """Wave number, angular frequency, period, wavelength and group velocity of the tank's mode:
    the flume's wave (solved once: the case, the analysis and the report all ask)."""
    omega, k, wavelength, cg, ratio = linear_wave(resolve(flume), DEPTH)
    return k, omega, 2 * math.pi / omega, wavelength, cg


def case(dx, periods, diffusion):
    import tisph
    from tisph.geometry import Polyline

    k, omega, T, L, cg = mode()
    num = dict(resolve(flume).numerics.items(), dx=dx, density_diffusion=diffusion)
    xs = np.linspace(0.0, L, 241)
    top = [[float(x), DEPTH + AMPLITUDE * math.cos(k * x)] for x in xs]
    tank = Polyline([[0.0, 0.6], [0.0, 0.0], [L, 0.0], [L, 0.6]], label="tank")
    gauges = [{"type": "surface", "x": f * L, "label": f"g{n}"} for n, f in enumerate((0.1, 0.4, 0.6, 0.9))]
    keep = (
        "dx",
        "h_factor",
        "kernel",
        "wall",
        "wall_layers",
        "artificial_viscosity",
        "laminar_viscosity",
        "density_diffusion",
        "delta",
        "cfl",
    )
    # the flume's sound speed, c0_factor sqrt(g h) (a custom case would take its own estimate)
    c0 = num["c0_factor"] * math.sqrt(G * DEPTH)
    return tisph.Case.custom(
        box=[0.0, L, 0.0, 0.6],
        solids=[tank],
        water=[{"polygon": [[0.0, 0.0], [L, 0.0]] + top[::-1]}],
        gauges=gauges,
        numerics=dict({key: num[key] for key in keep}, c0=c0, u_max=AMPLITUDE * omega / math.tanh(k * DEPTH)),
        run={"end_time": periods * T},
        output={"probe_interval": T / 40},
    )


def decay(probes, periods):
    """The mode's amplitude over each period (in units of a) and its decay per period."""
    k, omega, T, L, cg = mode()
    w = np.array([math.cos(k * f * L) for f in (0.1, 0.4, 0.6, 0.9)])
    eta = sum(wi * probes[f"eta_g{n}"] for n, wi in enumerate(w)) / (w @ w)
    t = probes["t"]
    amp = []
    for n in range(periods):
        s = (t >= n * T) & (t < (n + 1) * T)
        if s.sum() > 5:
            amp.append(0.5 * (eta[s].max() - eta[s].min()) / AMPLITUDE)
    amp = np.array(amp)
    rate = -np.polyfit(np.arange(1, len(amp)), np.log(amp[1:]), 1)[0] if len(amp) > 2 else float("nan")
    return amp, rate


def main(a):
    import tisph

    dx = a.dx or 0.0125
    periods = int(a.end_time or (8 if a.quick else 20))
    out = ensure_dir(os.path.join(a.out, "standing"))
    rows = []
    k, omega, T, L, cg = mode()
    for kind in KINDS:
        t0 = time.time()
        r = tisph.run(case(dx, periods, kind), out=os.path.join(out, f"{kind}_dx{dx:g}"), render=False, progress=False)
        wall = time.time() - t0
        amp, rate = decay(r.probes, periods)
        s = r.summary
        rows.append(
            (
                kind,
                dx,
                s["particles"],
                s["steps"],
                round(wall, 1),
                round(float(amp[-1]), 4),
                round(float(rate), 5),
                round(float(rate * L / (T * cg)), 5),
                s["status"],
            )
        )
        print(
            f"{kind}: {s['particles']} particles, {s['steps']} steps, {wall:.1f} s, amplitude after "
            f"{periods} periods {amp[-1]:.3f} a, decay {rate * 100:.2f} % a period",
            flush=True,
        )
    cols = (
        "diffusion",
        "dx",
        "particles",
        "steps",
        "wall_s",
        "last_amplitude",
        "decay_per_period",
        "decay_per_wavelength_progressive",
        "status",
    )
    write_csv(os.path.join(out, "standing.csv"), cols, rows)
    md = [
        "# A standing wave in a closed tank",
        "",
        f"One wavelength ({L:.3f} m) of the default flume's wave (T = {T:.3f} s over {DEPTH} m), a = "
        f"{AMPLITUDE} m, dx = {dx:g} m, {periods} periods; the flume's numerics with each density diffusion.",
        "",
        table(
            (
                "diffusion",
                "particles",
                "steps",
                "wall s",
                f"amplitude after {periods} periods",
                "decay a period",
                "as a progressive wave's a wavelength",
            ),
            [(r[0], r[2], r[3], r[4], f"{r[5]:.3f} a", f"{r[6] * 100:.2f} %", f"{r[7] * 100:.2f} %") for r in rows],
        ),
        "",
    ]
    write_text(os.path.join(out, "standing.md"), "\n".join(md) + "\n")
    print("\n".join(md))
    return 0
