"""What a gauge's record says of the waves: the mean height over whole periods, the zero
up-crossing period and the mean level, and the window a regular wave is read in (from the
fully ramped waves' arrival at the group velocity to the end of the run)."""

import numpy as np


def wave_height(t, eta, t0, t1, period):
    """Mean trough-to-crest height over whole periods in [t0, t1]: max - min in each period window."""
    t, eta = np.asarray(t, float), np.asarray(eta, float)
    hs = []
    a = t0
    while a + period <= t1 + 1e-9:
        m = (t >= a) & (t < a + period) & np.isfinite(eta)
        if m.sum() >= 4:
            hs.append(float(eta[m].max() - eta[m].min()))
        a += period
    return (float(np.mean(hs)) if hs else float("nan")), len(hs)


def _crossing_times(t, d, up):
    """The times d crosses zero upwards, interpolated between samples up and up + 1."""
    return t[up] - d[up] * (t[up + 1] - t[up]) / (d[up + 1] - d[up])


def crossing_period_and_level(t, eta, t0, t1):
    """(mean zero up-crossing period about the window's mean, that mean level) of eta over
    [t0, t1]: what a gauge's record says of the waves' period and of the set-up or set-down.
    A crossing counts once the record has dipped a tenth of its range below the mean since the
    last one.
    NaN where the window holds under two up-crossings."""
    t, eta = np.asarray(t, float), np.asarray(eta, float)
    m = (t >= t0) & (t <= t1) & np.isfinite(eta)
    if m.sum() < 4:
        return float("nan"), float("nan")
    tt, e = t[m], eta[m]
    level = float(e.mean())
    d = e - level
    # a crossing counts once the record has been below -b since the last one: a shoaling wave's
    # secondary crests (its harmonics) near the mean are not waves of their own
    b = 0.1 * float(d.max() - d.min())
    up, low = [], False
    for i in range(len(d) - 1):
        low = low or d[i] < -b
        if low and d[i] < 0 <= d[i + 1]:
            up.append(i)
            low = False
    up = np.array(up, int)
    if len(up) < 2:
        return float("nan"), level
    tc = _crossing_times(tt, d, up)
    if len(tc) < 2:
        return float("nan"), level
    whole = (tt >= tc[0]) & (tt < tc[-1])  # the level over whole waves only
    return float(np.mean(np.diff(tc))), float(e[whole].mean())


def free_oscillation(t, eta):
    """(period, fraction of the amplitude lost a period, its standard error, whole cycles) of a free
    oscillation about the record's mean level (sloshing, a seiche): the period is the mean spacing
    of the up-crossings; each cycle between two up-crossings gives an amplitude, half its range, and
    the loss is 1 - exp(slope) of their logarithm against the cycle (Antuono et al. 2011 read an SPH
    standing wave's damping so); the standard error is the slope's, from the scatter of the cycles
    about the line (higher modes beating in a gauge's record). (nan, nan, nan, 0) under three cycles."""
    nothing = float("nan"), float("nan"), float("nan"), 0
    t, e = np.asarray(t, float), np.asarray(eta, float)
    ok = np.isfinite(e)
    t, e = t[ok], e[ok]
    if len(e) < 8:
        return nothing
    e = e - e.mean()
    up = np.nonzero((e[:-1] < 0) & (e[1:] >= 0))[0]
    if len(up) < 4:
        return nothing
    tc = _crossing_times(t, e, up)
    amp = np.array([0.5 * (e[a : b + 1].max() - e[a : b + 1].min()) for a, b in zip(up[:-1], up[1:])])
    k, y = np.arange(len(amp), dtype=float), np.log(amp)
    slope, icept = np.polyfit(k, y, 1)
    res = y - (slope * k + icept)
    se = np.sqrt(np.sum(res**2) / (len(k) - 2) / np.sum((k - k.mean()) ** 2))
    return float(np.mean(np.diff(tc))), float(1.0 - np.exp(slope)), float(np.exp(slope) * se), len(amp)


def wave_period(p):
    """The paddle table's period: the peak period with a spectrum."""
    return p["tp"] if p.get("spectrum") else p["period"]


def arrival_time(p, x, cg):
    """When the fully ramped waves of paddle table p have reached x at group velocity cg, plus
    one period (the peak period with a spectrum): the start of a wave-height window there."""
    T = wave_period(p)
    return p["ramp_periods"] * T + x / cg + T


def height_at(c, column, x, p, cg):
    """(mean wave height, periods) of probe column c[column] at x, from the ramped waves' arrival
    to the end of the run."""
    return wave_height(c["t"], c[column], arrival_time(p, x, cg), float(c["t"][-1]), p["period"])


def low_pass(t, x, cutoff, order=2):
    """x(t) (uniform samples) through a zero-phase Butterworth low-pass of this order at cutoff
    (Hz), as filtfilt applies it: the gain |H(f)|^2 = 1 / (1 + (f / cutoff)^(2 order)) in the
    frequency domain, no phase shift, so a filtered peak stays where the load peaked. Order 2:
    1/125 of the amplitude left at 3.3 cutoff, and a step overshoots 3.4 % (order 4: 6.8 %). The
    record is extended by its odd reflection at both ends (as filtfilt pads), so its ends are
    not wrapped onto each other. None where a sample is missing (a dry point) or the record is
    under 8 samples."""
    x = np.asarray(x, float)
    if len(x) < 8 or not np.isfinite(x).all():
        return None
    dt = float(np.median(np.diff(np.asarray(t, float))))
    pad = min(len(x) - 1, int(np.ceil(4.0 / (cutoff * dt))))
    y = np.concatenate([2 * x[0] - x[pad:0:-1], x, 2 * x[-1] - x[-2 : -pad - 2 : -1]])
    f = np.fft.rfftfreq(len(y), dt)
    gain = 1.0 / (1.0 + (f / cutoff) ** (2 * order))
    return np.fft.irfft(np.fft.rfft(y) * gain, len(y))[pad : pad + len(x)]
