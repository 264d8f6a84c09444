"""Waves in two codes: the default flume (piston, T = 0.8 s over 0.25 m, Biesel's height, an
absorbing zone at the far end) in tisph and in DualSPHysics 5.0 (CPU), at the same dp, back to
back, each run to the same time: wave height error against Biesel at 1, 2 and 3 wavelengths,
particles, steps and wall time.

    python -m tisph.bench --waves [--quick] [--dx DX] [--peer-finest DP] [--dualsphysics CLONE]

DualSPHysics runs twice at each dp: with the settings of its own 2D wave cases (Wendland with
coefh 1.2, symplectic, CFL 0.2, artificial viscosity 0.01, Fourtakas diffusion 0.1, c0 = 20
sqrt(g h), dynamic boundary particles: examples/others/GaugeSystem/WallRegAwas2.xml), and with
ours where a setting can match (h = 2.5 dp, laminar viscosity, c0 = 10 sqrt(g h)). Its paddle is
its own first-order piston (JWavePaddles) given Biesel's height; its gauges are its own SWL
gauges (JGaugeSystem) at our gauges' x; both records go through one analysis (tisph.measure.records).
"""

import csv
import dataclasses
import math
import os
import sys
import time

import numpy as np

from ...constants import G
from ...io import ensure_dir, write_csv, write_text
from ...measure.plots import pyplot, save
from ...measure.records import arrival_time, wave_height
from ...runner import resolve
from ...scenes import flume
from ...settings.config import ConfigError
from ...waves.theory import linear_wave
from ..common import cache_dir, run_case, table
from ..ladder import CASES
from . import dualsphysics

# the flume as the bench ladder runs it (H / dx = 3, 5, 8, 12, to the end of the window at three
# wavelengths), one case for both benches
FLUME = next(c for c in CASES if c.scene == "scenes.flume")
LADDER = FLUME.ladder
QUICK = (0.025,)
END_TIME = FLUME.overrides["run.end_time"]

OWN = dict(label="DualSPHysics, its settings", coefh=1.2, visco_treatment=1, visco=0.01, c0_factor=20.0)
MATCHED = dict(
    label="DualSPHysics, our settings", coefh=2.5 / math.sqrt(2.0), visco_treatment=2, visco=1e-6, c0_factor=10.0
)


def flume_setup(dx):
    """The default flume's depth, length, wall height, absorber, paddle and gauges at dx."""
    cfg = resolve(flume, overrides={"numerics.dx": dx})
    geo, p = cfg.geometry, cfg.paddle
    d = geo.depth
    omega, k, wavelength, cg, ratio = linear_wave(cfg, d)
    return dict(
        depth=d,
        length=geo.length,
        wall_height=geo.wall_height,
        damping=geo.damping_length,
        period=p.period,
        ramp=p.ramp_periods,
        height=ratio * p.stroke,
        gauges=flume.gauge_positions(geo, wavelength),
        wavelength=wavelength,
        cg=cg,
        paddle=p,
        numerics=cfg.numerics,
    )


def flume_xml(dp, tmax, f, s):
    """DualSPHysics' case definition of the flume f at dp with settings s: a piston of three
    particle columns at x <= 0, the floor and end wall three layers thick, water to f's depth on
    the lattice (rows at multiples of dp, the walls' faces half a spacing out; a fill box's own
    border is not filled, so the box is one spacing larger than the water), its damping zone
    over the absorber, SWL gauges at f's gauges."""
    rows = int(round(f["depth"] / dp))
    depth = rows * dp
    c0 = s["c0_factor"] * math.sqrt(G * depth)
    n = lambda v: f"{v:.6g}"
    x_end = dp * math.floor(f["length"] / dp + 1e-9) + dp  # the end wall's first column
    lo = -dp * math.ceil(0.2 / dp)  # the floor runs on behind the piston
    gauges = "\n".join(
        f'<swl name="g{i}"><pointdp coefdp="0.1" /><point0 x="{n(x + 0.5 * dp)}" y="0" z="0" />'
        f'<point2 x="{n(x + 0.5 * dp)}" y="0" z="{n(f["wall_height"])}" /></swl>'
        for i, x in enumerate(f["gauges"])
    )
    damping = ""
    if f["damping"] > 0:
        damping = (
            f'<damping><dampingzone><limitmin x="{n(x_end - f["damping"])}" y="0" z="0" />'
            f'<limitmax x="{n(x_end)}" y="0" z="0" /><overlimit value="1" /><redumax value="10" />'
            f'</dampingzone></damping>'
        )
    return (
        f"""<?xml version="1.0" encoding="UTF-8" ?>
<case>
  <casedef>
    <constantsdef>
      <gravity x="0" y="0" z="-{G}" />
      <rhop0 value="1000" />
      <hswl value="0" auto="true" />
      <gamma value="7" />
      <speedsystem value="0" auto="true" />
      <coefsound value="20" />
      <speedsound value="{n(c0)}" auto="false" />
      <coefh value="{n(s['coefh'])}" />
      <cflnumber value="0.2" />
    </constantsdef>
    <mkconfig boundcount="240" fluidcount="9" />
    <geometry>
      <definition dp="{n(dp)}">
        <pointmin x="{n(lo - 4 * dp)}" y="0" z="{n(-4 * dp)}" />
        <pointmax x="{n(x_end + 4 * dp)}" y="0" z="{n(f['wall_height'] + 4 * dp)}" />
      </definition>
      <commands>
        <mainlist>
          <setdrawmode mode="full" />
          <setmkbound mk="10" />
          <drawbox><boxfill>solid</boxfill><point x="{n(-2 * dp)}" y="-1" z="{n(dp)}" />
            <size x="{n(2 * dp)}" y="2" z="{n(f['wall_height'] - dp)}" /></drawbox>
          <setmkbound mk="0" />
          <drawbox><boxfill>solid</boxfill><point x="{n(lo)}" y="-1" z="{n(-2 * dp)}" />
            <size x="{n(x_end + 2 * dp - lo)}" y="2" z="{n(2 * dp)}" /></drawbox>
          <drawbox><boxfill>solid</boxfill><point x="{n(x_end)}" y="-1" z="0" />
            <size x="{n(2 * dp)}" y="2" z="{n(f['wall_height'])}" /></drawbox>
          <setmkfluid mk="0" />
          <fillbox x="{n(f['length'] / 2)}" y="0" z="{n(depth / 2)}"><modefill>void</modefill>
            <point x="0" y="-1" z="0" />
            <size x="{n(x_end)}" y="2" z="{n(depth + dp)}" /></fillbox>
        </mainlist>
      </commands>
    </geometry>
    <motion>
      <objreal ref="10"><begin mov="1" start="0" /><mvnull id="1" /></objreal>
    </motion>
  </casedef>
{_execution(f, s, tmax, depth, gauges, damping)}</case>
""",
        dict(depth=depth, c0=c0, h=s["coefh"] * math.sqrt(2.0) * dp),
    )


def _execution(f, s, tmax, depth, gauges, damping):
    """flume_xml's <execution>: the gauges, the piston, the damping zone and the run's parameters."""
    n = lambda v: f"{v:.6g}"
    return f"""  <execution>
    <special>
      <gauges>
        <default><savevtkpart value="false" /><computedt value="0.01" /><output value="true" />
          <outputdt value="0.01" /></default>
        {gauges}
      </gauges>
      <wavepaddles>
        <piston>
          <mkbound value="10" /><start value="0" /><duration value="0" /><depth value="{n(depth)}" />
          <pistondir x="1" y="0" z="0" /><waveorder value="1" /><waveheight value="{n(f['height'])}" />
          <waveperiod value="{n(f['period'])}" /><gainstroke value="1" /><phase value="0" />
          <ramp value="{n(f['ramp'])}" />
        </piston>
      </wavepaddles>
      {damping}
    </special>
    <parameters>
      <parameter key="StepAlgorithm" value="2" />
      <parameter key="Kernel" value="2" />
      <parameter key="ViscoTreatment" value="{s['visco_treatment']}" />
      <parameter key="Visco" value="{n(s['visco'])}" />
      <parameter key="ViscoBoundFactor" value="1" />
      <parameter key="DensityDT" value="2" />
      <parameter key="DensityDTvalue" value="0.1" />
      <parameter key="Shifting" value="0" />
      <parameter key="CoefDtMin" value="0.05" />
      <parameter key="DtIni" value="0" />
      <parameter key="DtMin" value="0" />
      <parameter key="TimeMax" value="{n(tmax)}" />
      <parameter key="TimeOut" value="{n(max(tmax / 10, 0.05))}" />
      <parameter key="PartsOutMax" value="1" />
      <parameter key="RhopOutMin" value="700" />
      <parameter key="RhopOutMax" value="1300" />
      <simulationdomain><posmin x="default" y="default" z="default" />
        <posmax x="default" y="default" z="default + 50%" /></simulationdomain>
    </parameters>
  </execution>
"""


def _swl(out, names):
    """Each SWL gauge's record (t, swlz) from DualSPHysics' GaugesSWL_<name>.csv."""
    recs = []
    for name in names:
        with open(os.path.join(out, f"GaugesSWL_{name}.csv"), newline="") as fh:
            rows = [r for r in csv.reader(fh, delimiter=";") if r]
        head = [h.strip() for h in rows[0]]
        a = np.array([[float(r[head.index("time [s]")]), float(r[head.index("swlz [m]")])] for r in rows[1:]])
        recs.append((a[:, 0], a[:, 1]))
    return recs


def heights(f, records):
    """Trough-to-crest height (mean over whole periods) and its error against Biesel at each gauge,
    over the window the flume scene measures in: from the fully ramped waves' arrival (at the
    group velocity, plus a period) to the end. Each record is zeroed at its first reading."""
    H, err = [], []
    for x, (t, z) in zip(f["gauges"], records):
        h, _ = wave_height(t, z - z[0], arrival_time(f["paddle"], x, f["cg"]), float(t[-1]), f["period"])
        H.append(h)
        err.append(abs(h - f["height"]) / f["height"])
    return H, err


def run_dualsphysics(root, work, dp, tmax, s, threads=2):
    f = flume_setup(dp)
    xml, info = flume_xml(dp, tmax, f, s)
    tag = "own" if s is OWN else "ours"
    r = dualsphysics.run_xml(root, os.path.join(work, f"dualsphysics_flume_{tag}_dp{dp:g}"), "Flume", xml, threads)
    H, err = heights(f, _swl(r["out"], [f"g{i}" for i in range(len(f["gauges"]))]))
    settings = (
        f"Wendland, h = {info['h'] / dp:.2f} dp (coefh {s['coefh']:.3g}), symplectic with CFL 0.2, "
        f"c0 {info['c0']:.1f} m/s, "
        + (
            f"artificial viscosity {s['visco']:g}"
            if s["visco_treatment"] == 1
            else f"laminar viscosity {s['visco']:g} m2/s with its SPS term"
        )
        + ", Fourtakas diffusion 0.1, dynamic boundary particles (3 layers), its first-order piston "
        "(JWavePaddles) and damping zone (redumax 10), SWL gauges"
    )
    return dict(
        code=s["label"],
        dx=dp,
        particles=r["particles"],
        steps=r["steps"],
        wall_s=r["wall_s"],
        loop_s=r["loop_s"],
        H=H,
        errors=err,
        settings=settings,
    )


def run_tisph(work, dx, tmax):
    case = dataclasses.replace(FLUME, overrides=dict(FLUME.overrides, **{"run.end_time": tmax}))
    s, wall = run_case(case, dx, False, os.path.join(work, f"tisph_flume_dx{dx:g}"))
    m, num = s["metrics"], flume_setup(dx)["numerics"]
    return dict(
        code="tisph",
        dx=dx,
        particles=s["particles"],
        steps=s["steps"],
        wall_s=wall,
        loop_s=s["step_time_s"],
        H=m["wave_height_at_gauges"],
        errors=m["wave_height_errors"],
        settings=f"{num.kernel}, h = {s['h'] / dx:.2f} dx, velocity Verlet with CFL {num.cfl:g}, "
        f"c0 {s['c0']:.1f} m/s, artificial viscosity {num.artificial_viscosity:g}, "
        f"{num.density_diffusion} diffusion {num.delta:g}, {num.wall} walls "
        f"({num.wall_layers} layers), its piston and absorbing zone, surface gauges; modules: "
        + ", ".join(s["modules"]),
    )


def plot(rows, f, path):
    """Error against H / dx (1 wavelength solid, 3 dashed) and, at 3 wavelengths, against wall time;
    one colour per code."""
    plt = pyplot()
    from matplotlib.ticker import FixedLocator, NullFormatter, ScalarFormatter

    fig, axes = plt.subplots(1, 2, figsize=(10, 5.2))
    for n, code in enumerate(dict.fromkeys(r["code"] for r in rows)):
        rr = sorted((r for r in rows if r["code"] == code), key=lambda r: -r["dx"])
        c = f"C{n}"
        for i, ls, lab in ((0, "-", "1 wavelength"), (2, "--", "3 wavelengths")):
            axes[0].loglog(
                [f["height"] / r["dx"] for r in rr],
                [max(r["errors"][i], 1e-3) for r in rr],
                "o" + ls,
                color=c,
                label=f"{code}, {lab}",
            )
        axes[1].loglog([r["wall_s"] for r in rr], [max(r["errors"][2], 1e-3) for r in rr], "o--", color=c, label=code)
    axes[0].set_xlabel("particles per wave height, H / dx")
    axes[0].set_ylabel("wave height error against Biesel")
    axes[1].set_xlabel("wall time to the end (s), 2 threads")
    axes[1].set_ylabel("error at 3 wavelengths")
    ticks = ((3, 5, 8, 12), (10, 30, 100, 300, 1000, 3000))
    for ax, xt in zip(axes, ticks):
        ax.grid(alpha=0.3, which="both")
        ax.xaxis.set_major_locator(FixedLocator(xt))
        ax.yaxis.set_major_locator(FixedLocator((0.002, 0.005, 0.01, 0.02, 0.03, 0.05, 0.1, 0.2, 0.3, 0.5)))
        for axis in (ax.xaxis, ax.yaxis):
            axis.set_major_formatter(ScalarFormatter())
            axis.set_minor_formatter(NullFormatter())
        ax.legend(fontsize=7, loc="upper center", bbox_to_anchor=(0.5, -0.16), ncol=2)
    fig.suptitle(
        f"Piston flume, T = {f['period']:g} s over {f['depth']:g} m, Biesel H = {f['height']:.4f} m: "
        "error against resolution and cost",
        fontsize=10,
    )
    save(fig, path)


def main(a):
    log = lambda m: print(m, flush=True)
    from ... import runtime

    runtime.init("cpu", "f32")
    dxs = (a.dx,) if a.dx else QUICK if a.quick else LADDER
    tmax = a.end_time or (8.0 if a.quick else END_TIME)  # 8 s: two periods past the arrival at 3 L
    try:
        for dx in dxs:
            flume_setup(dx)
    except ConfigError as e:  # a --dx the flume refuses: its message, no traceback
        print(f"--dx: {e}", file=sys.stderr)
        return 2
    out = ensure_dir(os.path.join(a.out, "waves"))
    notes = []
    try:
        root = dualsphysics.ensure(cache_dir(), a.dualsphysics, log)
    except dualsphysics.NotAvailable as e:
        root = None
        notes.append(f"DualSPHysics not run: {e}")
    rows = []
    started = time.time()
    for dx in dxs:
        runs = [lambda: run_tisph(out, dx, tmax)]
        if root and dx >= a.peer_finest - 1e-12:
            runs += [lambda s=s: run_dualsphysics(root, out, dx, tmax, s) for s in (OWN, MATCHED)]
        elif root:
            notes.append(f"DualSPHysics not run at dp {dx:g} (finer than --peer-finest {a.peer_finest:g})")
        for fn in runs:
            try:
                r = fn()
            except Exception as e:  # one failed run is a row of the report, not the end of the bench
                notes.append(f"a run at dp {dx:g} failed: {str(e).splitlines()[0][:300]}")
                log(notes[-1])
                continue
            log(
                f"dp {dx:g}, {r['code']}: {r['particles']} particles, {r['steps']} steps, {r['wall_s']:.1f} s, "
                "errors " + ", ".join(f"{e * 100:.1f} %" for e in r["errors"])
            )
            rows.append(r)
    f = flume_setup(dxs[0])
    cols = ("code", "dx", "H_over_dx", "particles", "steps", "wall_s", "loop_s", "error_1L", "error_2L", "error_3L")
    recs = [
        (
            r["code"],
            r["dx"],
            round(f["height"] / r["dx"], 2),
            r["particles"],
            r["steps"],
            round(r["wall_s"], 1),
            round(r["loop_s"], 1),
            *[round(e, 4) for e in r["errors"]],
        )
        for r in rows
    ]
    write_csv(os.path.join(out, "waves.csv"), cols, recs)
    md = [
        "# Waves in two codes: the default flume against Biesel",
        "",
        f"Run {time.strftime('%Y-%m-%d %H:%M')} to t = {tmax:g} s, 2 threads each, back to back "
        f"({(time.time() - started) / 60:.0f} min in all). Biesel H = {f['height']:.4f} m, wavelength "
        f"{f['wavelength']:.3f} m; error = |H - H_Biesel| / H_Biesel, H the mean trough-to-crest height from "
        "the fully ramped waves' arrival to the end.",
        "",
        table(
            ("code", "dx", "H/dx", "particles", "steps", "wall s", "error 1 L", "error 2 L", "error 3 L"),
            [(r[0], f"{r[1]:g}", r[2], r[3], r[4], r[5], *[f"{e * 100:.1f} %" for e in r[7:]]) for r in recs],
        ),
        "",
        "![error against H/dx and wall time](waves.png)",
        "",
    ]
    md += [f"- {code}: {s}." for code, s in {r["code"]: r["settings"] for r in rows}.items()] + [""]
    md += [f"- {n}" for n in notes]
    if rows:
        plot(rows, f, os.path.join(out, "waves.png"))
    write_text(os.path.join(out, "waves.md"), "\n".join(md) + "\n")
    print("\n".join(md))
    return 0
