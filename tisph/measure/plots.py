"""Figures without a display, saved whole or not at all (atomic rename)."""

from ..io import atomic_path


def pyplot():
    """matplotlib.pyplot on the Agg backend (no window, no display needed)."""
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


def save(fig, path, dpi=110, tight=True):
    """Lay out, write to a temporary name and rename, close."""
    import matplotlib.pyplot as plt

    if tight:
        fig.tight_layout()
    with atomic_path(path) as tmp:
        fig.savefig(tmp, dpi=dpi, format="png", bbox_inches="tight", pad_inches=0.08)  # titles never clipped
    plt.close(fig)


def gauge_panels(shown, c, metrics, path, title=""):
    """gauges.png: a panel each gauge of `shown` (tisph.measure.gauge_sets.GaugeSet.plot), the gauges
    of a type on one vertical scale; a load gauge's low-passed record over its raw one."""
    import numpy as np

    plt = pyplot()
    fig, axes = plt.subplots(len(shown), 1, figsize=(7.5, 1.15 * len(shown) + 0.8), sharex=True, squeeze=False)
    t = np.asarray(c["t"])
    rec = [g.panel[1] * np.asarray(c[g.columns[0]], float) for g in shown]  # in the panel's unit
    low = [None if (y := g.filtered(c)) is None else g.panel[1] * y for g in shown]
    span = {}
    for g, v, y in zip(shown, rec, low):  # one range a type, the low-passed record's inside it
        v = np.concatenate([v[np.isfinite(v)], [] if y is None else y])
        if v.size:
            lo, hi = span.get(type(g), (np.inf, -np.inf))
            span[type(g)] = (min(lo, v.min()), max(hi, v.max()))
    for ax, g, v, y in zip(axes[:, 0], shown, rec, low):
        ax.plot(t, v, lw=0.8, color="C0")
        if not np.isfinite(v).any():
            ax.text(
                0.5,
                0.5,
                "dry throughout: no water within its kernel",
                transform=ax.transAxes,
                fontsize=7,
                ha="center",
                va="center",
                color="0.4",
            )
        if y is not None:
            ax.plot(t, y, lw=0.9, color="C3", label=f"low-passed at {g.cutoff:.3g} Hz")
            ax.legend(loc="upper right", fontsize=6, frameon=False)
        lo, hi = span.get(type(g), (-1.0, 1.0))
        pad = 0.08 * max(hi - lo, 1e-12)
        ax.set_ylim(lo - pad, hi + pad)
        ax.set_ylabel(g.panel[0], fontsize=7)
        ax.tick_params(labelsize=7)
        ax.text(
            0.005,
            0.95,
            g.describe(metrics),
            transform=ax.transAxes,
            fontsize=7,
            va="top",
            bbox=dict(facecolor="white", edgecolor="none", alpha=0.8, pad=1.5),
        )
    axes[-1, 0].set_xlabel("t (s)", fontsize=8)
    if title:
        fig.suptitle(title, fontsize=9)
    save(fig, path)
