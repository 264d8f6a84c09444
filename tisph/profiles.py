"""Free-surface and depth profiles from particles, and their plots (matplotlib, no window)."""

import numpy as np

from .io import write_csv
from .measure.plots import pyplot, save
from .particles import FLUID
from .viz.render import SAND


def depth_profile(state, x0, x1, width):
    """Water depth along x from the particles' volumes: sum(m / rho) in a column / column width.

    Counting volume rather than taking the highest particle keeps splashes and overturning jets
    from reading as depth. Returns bin centres and depths.
    """
    fl = state["kind"] == FLUID
    x = state["x"][fl, 0]
    vol = state["m"][fl] / state["rho"][fl]
    edges = np.arange(x0, x1 + 0.5 * width, width)
    v, _ = np.histogram(x, bins=edges, weights=vol)
    return 0.5 * (edges[1:] + edges[:-1]), v / width


def surface_profile(state, x0, x1, width, dx):
    """Highest fluid particle (+ dx/2) per column of the given width; NaN where a column is dry."""
    fl = state["kind"] == FLUID
    x, y = state["x"][fl, 0], state["x"][fl, 1]
    edges = np.arange(x0, x1 + 0.5 * width, width)
    idx = np.digitize(x, edges) - 1
    top = np.full(len(edges) - 1, np.nan)
    for k in range(len(edges) - 1):
        m = idx == k
        if m.any():
            top[k] = y[m].max() + 0.5 * dx
    return 0.5 * (edges[1:] + edges[:-1]), top


def write_profile(path_csv, x, h_sim, h_ref=None, names=("x", "h_sim", "h_exact")):
    cols = [x, h_sim] + ([h_ref] if h_ref is not None else [])
    write_csv(path_csv, names[: len(cols)], list(zip(*[np.asarray(c, float) for c in cols])))


def plot_profiles(path_png, panels, xlabel, ylabel, title=""):
    """panels: list of (label, x, h_sim, x_ref, h_ref). One subplot per panel, SPH as dots."""
    plt = pyplot()
    n = max(1, len(panels))
    fig, axes = plt.subplots(n, 1, figsize=(7.5, 2.2 * n + 0.6), sharex=True, squeeze=False)
    for ax, (label, x, h, xr, hr) in zip(axes[:, 0], panels):
        if xr is not None:
            ax.plot(xr, hr, "k-", lw=1.2, label="exact")
        ax.plot(x, h, "o", ms=2.5, color="#2a6fbb", label="tisph")
        ax.set_ylabel(ylabel)
        ax.set_title(label, fontsize=9, loc="left")
        ax.grid(alpha=0.3)
    axes[0, 0].legend(fontsize=8, loc="upper right")
    axes[-1, 0].set_xlabel(xlabel)
    if title:
        fig.suptitle(title, fontsize=10)
    save(fig, path_png)


def streamlines_png(path, st, xlim, ylim, dx, title, figsize, density=1.6, circle=None):
    """Streamlines of the water velocity (material 0), binned on a grid of 2 dx, over the
    sediment drawn as sand-coloured dots; circle = (x, y, r) draws an obstacle (a pipe)."""
    plt = pyplot()
    fl = st["kind"] == FLUID
    x, v, mat = st["x"][fl], st["v"][fl], st["mat"][fl]
    w = mat == 0
    cell = 2 * dx
    xe = np.arange(xlim[0], xlim[1] + cell, cell)
    ye = np.arange(ylim[0], ylim[1] + cell, cell)
    n, _, _ = np.histogram2d(x[w, 0], x[w, 1], bins=(xe, ye))
    u, _, _ = np.histogram2d(x[w, 0], x[w, 1], bins=(xe, ye), weights=v[w, 0])
    vv, _, _ = np.histogram2d(x[w, 0], x[w, 1], bins=(xe, ye), weights=v[w, 1])
    with np.errstate(invalid="ignore", divide="ignore"):
        u, vv = np.where(n > 0, u / n, 0.0), np.where(n > 0, vv / n, 0.0)
    xm, ym = 0.5 * (xe[1:] + xe[:-1]), 0.5 * (ye[1:] + ye[:-1])
    fig, ax = plt.subplots(figsize=figsize)
    ax.scatter(x[~w, 0], x[~w, 1], s=1.5, color=SAND, lw=0)
    speed = np.hypot(u, vv)
    if speed.max() > 0:
        sp = ax.streamplot(
            xm, ym, u.T, vv.T, color=speed.T, cmap="viridis", density=density, linewidth=0.6, arrowsize=0.6
        )
        wide = (xlim[1] - xlim[0]) > 3 * (ylim[1] - ylim[0])  # a strip: the bar goes under it
        fig.colorbar(
            sp.lines,
            ax=ax,
            label="speed (m/s)",
            orientation="horizontal" if wide else "vertical",
            fraction=0.08 if wide else 0.03,
            pad=0.3 if wide else 0.01,
            aspect=50 if wide else 20,
        )
    if circle is not None:
        ax.add_patch(plt.Circle(circle[:2], circle[2], color="0.5"))
    ax.set_xlim(*xlim)
    ax.set_ylim(*ylim)
    ax.set_aspect("equal")
    ax.set_xlabel("x (m)")
    ax.set_ylabel("y (m)")
    ax.set_title(title, fontsize=9)
    save(fig, path, dpi=100)
