"""The ripple sweep's report (`python -m tisph.bench --ripples`, ripple_sweep.py): which cases
land in Wiberg & Harris's band, the table, and the figures of length against d0 and of growth."""

import os

import numpy as np

from ..io import read_csv
from ..measure.plots import pyplot, save
from ..ripples import ORBITAL_BAND as BAND
from ..ripples import STEEPNESS_BAND as STEEP_BAND
from .common import table

SHEET_STEEPNESS = 0.03  # above mobility 240 a bed this flat has no ripples


def growth(path):
    """(t, ripple length) of a case's probes.csv (empty arrays if missing)."""
    try:
        _, cols = read_csv(path)
    except OSError:
        return np.array([]), np.array([])
    return np.array(cols["t"]), np.array(cols["ripple_length"])


def in_band(row):
    if row["kind"] == "sheet":
        return bool(np.isfinite(row["steepness"]) and row["steepness"] < SHEET_STEEPNESS) or row["count"] == 0
    return (BAND[0] <= row["lam_d0"] <= BAND[1]) and (STEEP_BAND[0] <= row["steepness"] <= STEEP_BAND[1])


def plot(rows, path_fig, path_growth):
    plt = pyplot()
    fig, (a1, a2) = plt.subplots(1, 2, figsize=(10, 4))
    marks = {
        "check": ("o", "C0", "checks"),
        "sheet": ("x", "C2", "sheet flow (mobility > 240)"),
        "seeded": ("s", "C1", "seeded at 0.3 / 1.5 d0"),
        "resolution": ("^", "C4", "twice the length, dx and dx / 1.5"),
        "calibration": ("*", "C3", "calibration case"),
    }  # drawn last: on top of a check at its d0
    for kind, (m, c, lab) in marks.items():
        rr = [r for r in rows if r["kind"] == kind]
        if not rr:
            continue
        if kind != "sheet":  # a flat bed has no ripple length to show
            a1.plot([r["d0"] for r in rr], [r["lam_d0"] for r in rr], m, color=c, label=lab, ms=8)
        a2.plot([r["d0"] for r in rr], [r["steepness"] for r in rr], m, color=c, label=lab, ms=8)
    for ax, band, ref, name in ((a1, BAND, 0.62, "ripple length / d0"), (a2, STEEP_BAND, 0.17, "steepness")):
        ax.axhspan(*band, color="0.9", label="Wiberg & Harris band")
        ax.axhline(ref, color="k", lw=1, label="Wiberg & Harris")
        ax.set_xlabel("orbital diameter d0 (m)")
        ax.set_ylabel(name)
        ax.grid(alpha=0.3)
    a2.legend(fontsize=7, loc="lower left")  # the empty corner under the band
    a1.set_title("ripple length at the end, every case at the defaults")
    a2.set_title("steepness (height / length)")
    save(fig, path_fig)
    fig, ax = plt.subplots(figsize=(8, 4.5))
    shown = [r for r in rows if r["kind"] != "sheet"]  # a flat bed's count is noise
    for k, r in enumerate(shown):
        t, lam = growth(os.path.join(r["dir"], "probes.csv"))
        if len(t):
            ax.plot(
                t / r["T"] * r["morfac"],
                lam / r["d0"],
                color=f"C{k % 10}",
                lw=1.2,
                ls="-" if k < 10 else "--",
                label=f"{r['label']} ({r['kind']})",
            )
    ax.axhspan(*BAND, color="0.9")
    ax.set_xlabel("bed periods (wave periods x morfac)")
    ax.set_ylabel("mean ripple length / d0")
    ax.set_ylim(0, 2)
    ax.grid(alpha=0.3)
    ax.legend(fontsize=6, ncol=2)
    save(fig, path_growth)


def report(rows, wall):
    head = (
        "case",
        "kind",
        "d0 m",
        "T s",
        "mobility",
        "dx m",
        "morfac",
        "ripples",
        "length / d0",
        "steepness",
        "in band",
        "held in the band (bed periods)",
        "density error max / mean",
        "near-bed at z_r / U_m",
        "particles",
        "steps",
        "wall s",
    )
    body = [
        (
            r["label"],
            r["kind"],
            f"{r['d0']:g}",
            f"{r['T']:g}",
            f"{r['psi']:.0f}",
            f"{r['dx']:g}",
            f"{r['morfac']:g}",
            r["count"],
            f"{r['lam_d0']:.2f}",
            f"{r['steepness']:.3f}",
            "yes" if r["in_band"] else "**no**",
            f"{r['held']:.0f}",
            f"{r['rho_max']:.1%} / {r['rho_mean']:.2%}",
            f"{r['near_bed']:.2f}",
            r["particles"],
            r["steps"],
            f"{r['wall']:.0f}",
        )
        for r in rows
    ]
    ok = sum(r["in_band"] for r in rows)
    rip = [r for r in rows if r["kind"] != "sheet"]
    n_len = sum(BAND[0] <= r["lam_d0"] <= BAND[1] for r in rip)
    n_st = sum(STEEP_BAND[0] <= r["steepness"] <= STEEP_BAND[1] for r in rip)
    cost = sum(r["wall"] for r in rows if np.isfinite(r["wall"]))
    pair = [r for r in rows if r["kind"] == "resolution"]
    res = (
        f"At twice the length, dx / 1.5 against dx: {pair[1]['count']} against {pair[0]['count']} ripples, "
        f"lengths {abs(pair[1]['lam_d0'] / pair[0]['lam_d0'] - 1):.0%} apart."
        if len(pair) == 2
        else ""
    )
    return "\n".join(
        [
            "# Ripples against the orbital diameter",
            "",
            f"{len(rows)} tunnel cases, {ok} in the band (length 0.5-0.75 d0 and steepness 0.10-0.20; "
            f"sheet flow: steepness under {SHEET_STEEPNESS}). Of the {len(rip)} with ripples, {n_len} have "
            f"their length in the band and {n_st} their steepness. The cases' wall times add up to "
            f"{cost:.0f} s ({wall:.0f} s of wall time for this call, on the sweep's workers).",
            "",
            table(head, body),
            "",
            res,
            "",
            "![length and steepness against d0](ripples.png)",
            "",
            "![growth](growth.png)",
            "",
        ]
    )
