"""The beach's waves against linear shoaling: a line of surface gauges from the flat part to the
shoreline, the wave height along it against energy-flux shoaling from the flat part's mean, the
near-bed orbital amplitude against the same theory, and where the waves break.

Linear shoaling (energy flux conserved, no reflection, no loss): H(x) = H_0 sqrt(Cg_0 / Cg(x)),
Cg = (omega / 2k)(1 + 2kh / sinh 2kh), and the near-bed orbital amplitude A = H / (2 sinh kh).
The breaking point is where the measured height is largest; its H_b / h_b is set beside Weggel's
(1972) breaker index for a plane slope m: gamma_b = b - a H_b / (g T^2), a = 43.8 (1 - e^(-19 m)),
b = 1.56 / (1 + e^(-19.5 m)) (Shore Protection Manual 1984, eq. 2-92).
"""

import math

import numpy as np

from ...constants import G
from ...measure.gauge_sets import WaveGauges
from ...measure.records import arrival_time, wave_height
from ...particles import FLUID
from ...waves.theory import group_velocity, hunt_run_up, wavenumber

STEP = 0.25  # m between the gauges of the line


def crest_height(geo):
    """The beach's crest (its slope at the end wall) above the still water."""
    return (geo.length - geo.toe_x) / geo.slope - geo.depth


def warn_run_up(geo, H, omega, k):
    """A warning where Hunt's run-up of the paddle's linear wave (H at the flat bed's depth)
    reaches above the crest: the swash would run against the end wall and reflect from it. Returns
    Hunt's run-up (m above still water)."""
    import warnings

    R = hunt_run_up(H, omega, k, geo.depth, geo.slope)
    top = crest_height(geo)
    if top < R:
        warnings.warn(
            f"geometry.length = {geo.length:g} m leaves the beach's crest {top:.3g} m above still water, "
            f"under Hunt's run-up of this wave ({R:.3g} m): the swash will run against the end wall "
            f"and reflect from it; geometry.length at least {geo.toe_x + (geo.depth + R) * geo.slope:.3g} m "
            "puts the crest above it"
        )
    return R


def run_up(st, stations, zb, shore, still, dx):
    """The swash's reach now: the bed's height above still water at the furthest point up the
    slope (past the still shoreline `shore`) where water lies on the bed (within 2 dx of it); 0
    where none is past the shoreline. A droplet in the air is not the swash."""
    fl = (st["kind"] == FLUID) & (st["mat"] == 0)
    p = st["x"][fl]
    up = p[:, 0] > shore
    if not up.any():
        return 0.0
    z = np.interp(p[up, 0], stations, zb)
    wet = p[up, 1] < z + 2.0 * dx
    return float(z[wet].max() - still) if wet.any() else 0.0


def weggel_index(slope_m, Hb, period, g=G):
    a = 43.8 * (1 - math.exp(-19 * slope_m))
    b = 1.56 / (1 + math.exp(-19.5 * slope_m))
    return b - a * Hb / (g * period * period)


def linear_shoaling(H0, h0, h, omega, g=G):
    """Heights and near-bed orbital amplitudes along depths h from H0 at depth h0."""
    k0 = wavenumber(omega, h0, g)
    cg0 = group_velocity(omega, k0, h0)
    H, A = [], []
    for d in h:
        k = wavenumber(omega, d, g)
        H.append(H0 * math.sqrt(cg0 / group_velocity(omega, k, d)))
        A.append(H[-1] / (2 * math.sinh(k * d)))
    return np.array(H), np.array(A)


def shuto_shoaling(H0, h0, h, omega, g=G):
    """Nonlinear shoaling (Shuto 1974, Coastal Eng. in Japan 17:1; as Goda 2010, Random Seas and
    Design of Maritime Structures, sec. 3.5, writes it) with the Ursell number U = g H T^2 / h^2:
    linear shoaling while U < 30, then H h^(2/7) constant while U < 50, then
    H h^(5/2) (sqrt(U) - 2 sqrt(3)) constant, each constant taken where the regime starts. h
    runs shallower from h0 (along a slope); heights at each h."""
    T2 = (2 * math.pi / omega) ** 2
    ursell = lambda H, d: g * H * T2 / (d * d)
    third = lambda H, d: H * d**2.5 * (math.sqrt(ursell(H, d)) - 2 * math.sqrt(3.0))
    out, H_prev, d_prev, regime, const = [], H0, h0, 0, None
    for d in h:
        d = float(d)
        if regime == 0:
            H = float(linear_shoaling(H0, h0, [d], omega, g)[0][0])
            if ursell(H, d) >= 30:
                regime = 1 if ursell(H_prev, d_prev) < 50 else 2
                const = H_prev * d_prev ** (2 / 7) if regime == 1 else third(H_prev, d_prev)
        if regime == 1:
            H = const * d ** (-2 / 7)
            if ursell(H, d) >= 50:
                regime, const = 2, third(H_prev, d_prev)
        if regime == 2:
            lo, hi = 1e-9, 10.0 * d  # third() grows with H past U = 12: bisect
            lo = max(lo, 12.0 * d * d / (g * T2))
            for _ in range(100):
                mid = 0.5 * (lo + hi)
                lo, hi = (mid, hi) if third(mid, d) < const else (lo, mid)
            H = 0.5 * (lo + hi)
        out.append(H)
        H_prev, d_prev = H, d
    return np.array(out)


class Shoaling:
    def __init__(self, geo, depth_at, level, dx, h, columns_from=1.0):
        """geo: the beach's geometry table; depth_at(x): still-water depth; level: still-water
        level. Gauges every STEP m from columns_from to where the still water is 4 dx deep
        (beyond, a gauge reads the swash, wet and dry)."""
        last = geo["toe_x"] + (geo["depth"] - 4 * dx) * geo["slope"]
        self.xs = list(np.arange(columns_from, last + 1e-9, STEP))
        self.flat = [x <= geo["toe_x"] for x in self.xs]
        self.depth = np.array([depth_at(x) for x in self.xs])
        self.gauges = WaveGauges(self.xs, dx, h, level, tuple(f"x{x:.2f}" for x in self.xs))
        self.slope_m = 1.0 / geo["slope"]
        self.rows = []

    def read(self, st):
        self.rows.append((st["t"],) + self.gauges.read(st))

    def measure(self, p, cg, omega, amplitude_at):
        """The metrics: heights along the line, the theory from the first gauge, the error up to
        the breaking point, the breaking point, and the near-bed amplitude against theory."""
        if len(self.rows) < 4:
            return {}
        arr = np.array(self.rows)
        t = arr[:, 0]
        H = np.array(
            [
                wave_height(t, arr[:, i + 1], arrival_time(p, x, cg), t[-1], p["period"])[0]
                for i, x in enumerate(self.xs)
            ]
        )
        flat = np.array(self.flat) & np.isfinite(H)
        if not flat.any():
            return {}
        # the reference: the mean over the flat part (a wave partly reflected by the beach makes
        # the height there vary along x)
        Hth, Ath = linear_shoaling(float(H[flat].mean()), self.depth[0], self.depth, omega)
        Hnl = shuto_shoaling(float(H[flat].mean()), self.depth[0], self.depth, omega)
        ok = np.isfinite(H)
        ib = int(np.nanargmax(np.where(ok, H, np.nan)))
        err = np.abs(H[: ib + 1] / Hth[: ib + 1] - 1)
        nerr = np.abs(H[: ib + 1] / Hnl[: ib + 1] - 1)
        A = np.array([amplitude_at(x) for x in self.xs])
        aerr = np.abs(A[: ib + 1] / Ath[: ib + 1] - 1)
        Hb, hb = float(H[ib]), float(self.depth[ib])
        self.result = dict(x=self.xs, H=H, Hth=Hth, Hnl=Hnl, A=A, Ath=Ath, ib=ib)
        return dict(
            shoaling_x=[float(x) for x in self.xs],
            shoaling_height=[float(v) for v in H],
            shoaling_theory=[float(v) for v in Hth],
            shoaling_error=float(np.nanmax(err)) if ib > 0 else float("nan"),
            shoaling_nonlinear=[float(v) for v in Hnl],
            shoaling_error_nonlinear=float(np.nanmax(nerr)) if ib > 0 else float("nan"),
            orbital_amplitude_error=float(np.nanmax(aerr)) if ib > 0 else float("nan"),
            breaking_x=float(self.xs[ib]),
            breaking_height=Hb,
            breaking_depth=hb,
            breaker_index=Hb / hb,
            weggel_breaker_index=weggel_index(self.slope_m, Hb, p["period"]),
        )

    def plot(self, path, pyplot, save):
        r = getattr(self, "result", None)
        if r is None:
            return
        plt = pyplot()
        fig, (a1, a2) = plt.subplots(2, 1, figsize=(8, 5.2), sharex=True)
        a1.plot(r["x"], 100 * r["H"], "o-", ms=3, lw=0.9, label="measured (trough to crest)")
        a1.plot(r["x"], 100 * r["Hth"], "k--", lw=0.9, label="linear shoaling from the flat part's mean")
        a1.plot(r["x"], 100 * r["Hnl"], "k-.", lw=0.9, label="nonlinear shoaling (Shuto 1974) from the same")
        a1.axvline(r["x"][r["ib"]], color="0.5", lw=0.8, ls=":", label="breaking (largest H)")
        a1.set_ylabel("wave height (cm)")
        top = lambda v: 130 * np.nanmax(v) if np.isfinite(v).any() else None  # the theories run on past the break
        a1.set_ylim(0, top(r["H"]))
        a1.legend(fontsize=7)
        a2.plot(r["x"], 100 * r["A"], "o-", ms=3, lw=0.9, label="measured near-bed orbital amplitude")
        a2.plot(r["x"], 100 * r["Ath"], "k--", lw=0.9, label="linear theory, H / (2 sinh kh)")
        a2.axvline(r["x"][r["ib"]], color="0.5", lw=0.8, ls=":")
        a2.set_ylabel("orbital amplitude (cm)")
        a2.set_ylim(0, top(r["A"]))
        a2.set_xlabel("x from the paddle (m)")
        a2.legend(fontsize=7)
        fig.suptitle("beach: waves against linear and nonlinear shoaling", fontsize=10)
        save(fig, path)
