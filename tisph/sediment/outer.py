"""The outer scaling of the near-bed velocity under waves (sediment.outer_height, applied by
coupling.BedCoupler): Swart's friction factor relates the bed shear to the orbital velocity outside
the wave boundary layer, which the SPH resolves only above its own near-wall layer of a few dx
(measured in the tunnel: the velocity 1.5 dx up read 0.70 of U_m at dx = 1 cm and 0.65 at dx / 1.5;
scaled from 6 dx up, 0.95 and 0.93; docs/sediment.md, "What the bed reads of the waves")."""

import numpy as np


def running_mean(v, w, periodic):
    """v averaged over w (odd) neighbouring stations: periodic, or over the stations there are at
    the ends of a closed bed."""
    v = np.asarray(v, float)
    k = np.ones(w)
    if periodic:
        pad = np.concatenate([v[-(w // 2) :], v, v[: w // 2]])
        return np.convolve(pad, k / w, mode="valid")
    return np.convolve(v, k, mode="same") / np.convolve(np.ones_like(v), k, mode="same")


def outer_heights(sed, dx, z, still_level=None):
    """The outer reading's height above the bed z: outer_height dx, at most half the still water
    over the bed (on a beach's upper slope the reading must stay in the water through a wave's
    trough); NaN where that is no higher than z_r + dx / 2 (the factor stays 1 there)."""
    zo = np.full(len(z), sed["outer_height"] * dx)
    if still_level is not None:
        zo = np.minimum(zo, 0.5 * (still_level - np.asarray(z, float)))
    return np.where(zo > (sed["reference_height"] + 0.5) * dx, zo, np.nan)


class Window:
    """The rows (t, u at z_r, u outer) of the last wave period, in preallocated arrays: the
    window's rows are one contiguous slice, so its extremes are one reduction (a deque of
    per-update arrays had to be stacked again at every update)."""

    def __init__(self, n):
        self.n = n
        self.t = np.empty(0)
        self.u = np.empty((0, n))
        self.uo = np.empty((0, n))
        self.a = self.b = 0  # the live rows: [a, b)

    def append(self, t, u, uo):
        if self.b == len(self.t):  # full: the live rows to the front of a larger buffer
            live = self.b - self.a
            cap = max(64, 2 * live)
            t_, u_, uo_ = np.empty(cap), np.empty((cap, self.n)), np.empty((cap, self.n))
            t_[:live], u_[:live], uo_[:live] = (
                self.t[self.a : self.b],
                self.u[self.a : self.b],
                self.uo[self.a : self.b],
            )
            self.t, self.u, self.uo, self.a, self.b = t_, u_, uo_, 0, live
        self.t[self.b], self.u[self.b], self.uo[self.b] = t, u, uo
        self.b += 1

    def drop_before(self, t0):
        """Forget the rows older than t0 (the newest row always stays)."""
        self.a += int(np.searchsorted(self.t[self.a : self.b - 1], t0, side="left"))

    @property
    def first(self):
        return float(self.t[self.a])

    @property
    def near(self):
        return self.u[self.a : self.b]

    @property
    def outer(self):
        return self.uo[self.a : self.b]


def outer_scale(window, amplitude, dx, periodic, heights):
    """The factor on the near-bed velocity at each station: the amplitude at the outer height over
    the amplitude at z_r, each over the wave period the Window holds and
    averaged along the bed over one orbital diameter 2 A (amplitude: A at each station) among the
    stations that read both: a ripple's crest speed-up and lee slow-down stay in the near-bed
    velocity, the near-wall layer's loss, uniform over that length, goes. Where the water is too
    shallow to read, the nearest reading station's factor."""
    ur, uo = window.near, window.outer
    ar = 0.5 * (ur.max(0) - ur.min(0))
    ao = 0.5 * (uo.max(0) - uo.min(0))
    amp = np.broadcast_to(np.asarray(amplitude, float), ar.shape)
    d0 = 2.0 * float(np.median(amp[amp > 0])) if np.any(amp > 0) else 0.0
    w = max(3, int(round(d0 / dx)) | 1)
    valid = np.isfinite(heights) & (ao > 0)
    ar_s, ao_s = (running_mean(np.where(valid, v, 0.0), w, periodic) for v in (ar, ao))
    ok = valid & (ar_s > 1e-12)
    if not ok.any():
        return np.ones(len(ar))
    factor = np.where(ok, ao_s / np.where(ok, ar_s, 1.0), 1.0)
    # where the water is too shallow for an outer reading the near-wall layer is still there (it
    # is the numerics', not the depth's): those stations take the nearest reading station's factor
    i = np.arange(len(ar))
    return np.interp(i, i[ok], factor[ok])
