"""Does the flow erode Mao's bed where his current did? The pipeline case over Mao's measured beds
held still:

    python -m tisph.bench --mao-held [--times 11 18 25] [--end-time 2.5] [--dx DX] [--config F] [--quick] [--out renders/bench]

For each published time the case file (scenes/pipeline_scour_mao.toml) runs with its bed set to
Mao's measured profile (geometry.initial_profile) and held still (sediment.morph_start beyond the
run). After 1 s of flow (shedding.average_from; D / U = 0.14 s) the coupler's bed shear
(bed_shear.csv, every probe) is averaged, and each sample is put through the case's own bed
model (coupling.make_bed, Bed.outflow: threshold, transport, the lee transit and settling delay,
Exner; no avalanching, which acts only on faces steeper than the repose angle) for the rate
dz_b/dt the bed would start to change at, on the experiment's clock.
Mao's own rate is his next profile less this one over the 7 s between them, and under the pipe
his series' deepening. A model that reproduces the experiment must erode where his bed went down.
Beside it, whether the wake sheds over his hole (the fixed-bed benchmark's spectrum test,
tisph/bench/shedding.py, on snapshots every 0.05 s over the same averaging window).
Writes OUT/mao_held.md, OUT/mao_held.csv and OUT/mao_held.png; a benchmark, not a test (about
13,700 steps of 48,000 particles per time at 2.5 s).
"""

import os
import shutil
import time

import numpy as np

from ..io import ensure_dir, read_station_rows, write_csv, write_text
from ..measure.plots import pyplot, save
from ..sediment import coupling
from ..validation import mao
from .common import ROOT, table
from .shedding import SAMPLE, average_from, judge, run_pipeline, wake_series

BINS = np.arange(-2.0, 6.01, 0.5)  # x / D from the pipe's centre: the CSV's bins' centres, D/2 wide
REGIONS = (("upstream", -2.0, -0.5), ("hole", -0.5, 1.0), ("lee", 1.0, 3.0), ("dune", 3.0, 6.0))


def exner_rate(sed, stations, z, taus, d50, rho_s, rho_w):
    """Mean dz_b/dt (m per second of bed time) the case's bed model gives bed z under each shear
    row in turn (its saturation sweeps start from the last row's flux, as in a run)."""
    bed = coupling.make_bed(sed, stations, z, d50, rho_s, rho_w, periodic=True, morfac=1.0)
    out = np.zeros(len(stations))
    for tau in taus:
        out -= bed.outflow(tau) / bed.dx / (1.0 - bed.porosity)
    return out / max(len(taus), 1)


def _mean(a, m):
    """Mean of a over the mask m, NaN where it has no finite value (Mao's rate after his last profile)."""
    return float(np.nanmean(a[m])) if np.isfinite(a[m]).any() else float("nan")


def mao_rate(tp, x_rel, D):
    """Mao's dz_b/dt (m/s) after his profile at tp: the next profile less it over the time
    between (NaN after the last); and his series' rate under the pipe there, -dS/dt (m/s)."""
    times = sorted(mao.PROFILES)
    k = times.index(tp)
    if k + 1 < len(times):
        t1 = times[k + 1]
        rate = (mao.profile_bed(t1, x_rel, D) - mao.profile_bed(tp, x_rel, D)) / (t1 - tp)
    else:
        rate = np.full(len(x_rel), np.nan)
    under = -(mao.depth_at(tp + 2.0) - mao.depth_at(tp - 2.0)) / 4.0 * D
    return rate, float(under)


def run_time(tp, end_time, out, cfg_file, dx=None):
    """One run over Mao's bed at tp held still; the shear and rates along the bed."""
    ov = {
        "geometry.initial_profile": f"mao_{tp:g}s",
        "sediment.morph_start": 10.0 * end_time,
        "run.end_time": end_time,
        "output.render": False,
        "output.quiet": True,
        "output.snapshot_every": SAMPLE,
    }
    run_dir = os.path.join(out, "runs", f"mao_held_{tp:g}s")
    cfg, s, wall, g = run_pipeline(cfg_file, ov, dx, run_dir)
    # does the wake shed over his hole? (the fixed-bed benchmark's test, over the averaging window)
    t, v = wake_series(run_dir, g.xc, g.yc, g.D, average_from(end_time))
    shutil.rmtree(os.path.join(run_dir, "snapshots"), ignore_errors=True)
    std, freq, _, best, sheds = judge(t, v, g)
    info = dict(
        particles=s["particles"],
        steps=s["steps"],
        wall_time_s=round(wall, 1),
        sheds=sheds,
        strouhal=float(freq[best] * g.D / g.U),
        v_std=float(np.max(std)),
    )
    return analyse(tp, run_dir, cfg, g, info)


def analyse(tp, run_dir, cfg, g, info):
    """The held run in run_dir (its config cfg, geometry g): the shear and rates along the bed."""
    t, st, taus = read_station_rows(os.path.join(run_dir, "bed_shear.csv"))
    _, _, beds = read_station_rows(os.path.join(run_dir, "scour_profile.csv"))
    keep = t >= average_from(cfg.run.end_time)
    tau_inf = g.rw * g.ustar**2
    x_rel = (st - g.xc) / g.D
    rate = exner_rate(cfg.sediment, st, beds[0], taus[keep], g.d50, g.rs, g.rw)
    m_rate, m_under = mao_rate(tp, st - g.xc, g.D)
    under = np.abs(x_rel) < 1.0
    return dict(
        info,
        time=tp,
        x=x_rel,
        bed=(beds[0] - g.hs) / g.D,
        tau=taus[keep].mean(axis=0) / tau_inf,
        rate=rate / g.D,
        mao_rate=m_rate / g.D,
        under_model=float(rate[under].min() / g.D),
        under_mao=m_under / g.D,
    )


def region_means(r):
    """(name, model rate, Mao's rate, mean shear / tau_inf) over each region, in D/s."""
    out = []
    for name, lo, hi in REGIONS:
        m = (r["x"] >= lo) & (r["x"] < hi)
        out.append((name, float(r["rate"][m].mean()), _mean(r["mao_rate"], m), float(r["tau"][m].mean())))
    return out


def plot(rows, path):
    plt = pyplot()
    # the bed panel's height is about what its equal aspect over 10 D by 2.3 D leaves it
    fig, axes = plt.subplots(
        3,
        len(rows),
        figsize=(4.2 * len(rows), 5.6),
        sharex=True,
        squeeze=False,
        gridspec_kw=dict(height_ratios=(0.5, 1, 1.2)),
    )
    for c, r in enumerate(rows):
        a0, a1, a2 = axes[:, c]
        a0.fill_between(r["x"], r["bed"], -1.2, color="tan")
        a0.add_patch(plt.Circle((0, 0.5), 0.5, color="0.6"))
        a0.set_ylim(-1.2, 1.1)
        a0.set_aspect("equal")
        a0.set_title(f"Mao's bed at {r['time']:g} s, held still", fontsize=10)
        a1.axhline(1.0, color="0.6", lw=0.8)
        a1.plot(r["x"], r["tau"], color="C0", lw=1)
        # signed: water running back at the bed (a separation bubble) reads below zero
        a1.set_ylim(min(0.0, float(np.nanmin(r["tau"])) * 1.1), max(2.5, float(np.nanmax(r["tau"])) * 1.1))
        a2.axhline(0.0, color="0.6", lw=0.8)
        a2.plot(r["x"], r["rate"], color="C0", lw=1, label="tisph's bed model")
        if np.isfinite(r["mao_rate"]).any():
            a2.plot(r["x"], r["mao_rate"], color="k", lw=1, ls="--", label="Mao, to his next profile")
        a2.plot([0.0], [r["under_mao"]], "ko", ms=4, label="Mao's series under the pipe")
        a2.set_ylim(-0.08, 0.05)
        a2.set_xlim(-3, 7)
        a2.set_xlabel("x / D from the pipe's centre (flow to the right)")
        if c == 0:
            a0.set_ylabel("bed / D")
            a1.set_ylabel("bed shear / far field's")
            a2.set_ylabel("dz_b/dt (D per s)")
            a2.legend(fontsize=7, loc="lower left")
    save(fig, path)


def main(a):
    cfg_file = a.config or os.path.join(ROOT, "scenes", "pipeline_scour_mao.toml")
    times = a.times or ([18.0] if a.quick else [11.0, 18.0, 25.0])
    end = a.end_time or (1.5 if a.quick else 2.5)
    rows = []
    for tp in times:
        r = run_time(tp, end, a.out, cfg_file, a.dx)
        reg = region_means(r)
        print(
            f"Mao's bed at {tp:g} s held: {r['particles']} particles, {r['steps']} steps, {r['wall_time_s']:.0f} s; "
            + "; ".join(f"{n} {m:+.4f} D/s (Mao {o:+.4f}), shear {s:.2f}" for n, m, o, s in reg),
            flush=True,
        )
        rows.append(r)
    return write_report(rows, a.out, cfg_file, end)


def write_report(rows, out, cfg_file, end):
    """OUT/mao_held.csv, .png and .md from the held runs' rows (run_time / analyse)."""
    ensure_dir(out)
    csv = []
    for r in rows:
        for xb in BINS:
            m = (r["x"] >= xb - 0.25) & (r["x"] < xb + 0.25)
            csv.append(
                (
                    r["time"],
                    xb,
                    float(r["bed"][m].mean()),
                    float(r["tau"][m].mean()),
                    float(r["rate"][m].mean()),
                    _mean(r["mao_rate"], m),
                )
            )
    write_csv(
        os.path.join(out, "mao_held.csv"),
        ("t_mao", "x_over_D", "bed_over_D", "shear_over_far_field", "rate_D_per_s", "mao_rate_D_per_s"),
        csv,
    )
    plot(rows, os.path.join(out, "mao_held.png"))
    md = [
        "# Mao's measured beds held still under the case file's flow",
        "",
        f"{time.strftime('%Y-%m-%d %H:%M')}; `{os.path.relpath(cfg_file)}` with `geometry.initial_profile`, "
        f"the bed held still for {end:g} s of flow; the bed shear averaged from {average_from(end):g} s on and put "
        "through the case's bed model for the rate the bed would start to change at (D per second on Mao's clock; "
        "negative: it goes down). Mao's rate is his next profile less this one over the 7 s between them; "
        "under the pipe, his series' deepening.",
        "",
        table(
            (
                "Mao's bed",
                "particles",
                "steps",
                "wall s",
                "fastest rate within 1 D of the pipe (D/s)",
                "Mao's series under the pipe (D/s)",
                "wake sheds (St; v std m/s)",
            ),
            [
                (
                    f"{r['time']:g} s",
                    r["particles"],
                    r["steps"],
                    f"{r['wall_time_s']:.0f}",
                    f"{r['under_model']:+.4f}",
                    f"{r['under_mao']:+.4f}",
                    f"{'yes' if r['sheds'] else 'no'} ({r['strouhal']:.2f}; {r['v_std']:.3f})",
                )
                for r in rows
            ],
        ),
        "",
        table(
            ("Mao's bed", "region (x / D)", "shear / far field", "rate (D/s)", "Mao's rate (D/s)"),
            [
                (
                    f"{r['time']:g} s",
                    f"{n} ({lo:g} to {hi:g})",
                    f"{s:.2f}",
                    f"{m:+.4f}",
                    "-" if not np.isfinite(o) else f"{o:+.4f}",
                )
                for r in rows
                for (n, m, o, s), (_, lo, hi) in zip(region_means(r), REGIONS)
            ],
        ),
    ]
    write_text(os.path.join(out, "mao_held.md"), "\n".join(md) + "\n")
    print("\n".join(md))
    return 0
