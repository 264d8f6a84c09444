"""Regular-wave analysis of gauge records: harmonic amplitudes, incident and reflected waves,
bound and free second harmonics.

Convention: a gauge's complex amplitude C at angular frequency w is the least-squares fit of
eta(t) = Re[C exp(i w t)] over whole periods; a wave travelling towards +x has C(x) = A exp(-i k x).
"""

import math

import numpy as np


def harmonics(t, eta, omega, t0, t1, n=2):
    """Complex amplitudes of eta at omega, 2 omega, ... n omega, fitted with a mean level over
    the whole periods in [t0, t1]; None where fewer than two periods fit."""
    t, eta = np.asarray(t, float), np.asarray(eta, float)
    T = 2 * math.pi / omega
    periods = int((t1 - t0) / T + 1e-9)
    if periods < 2:
        return None
    w = (t >= t0) & (t < t0 + periods * T) & np.isfinite(eta)
    cols = [np.ones(w.sum())]
    for m in range(1, n + 1):
        cols += [np.cos(m * omega * t[w]), np.sin(m * omega * t[w])]
    c = np.linalg.lstsq(np.column_stack(cols), eta[w], rcond=None)[0]
    return np.array([c[2 * m - 1] - 1j * c[2 * m] for m in range(1, n + 1)])


def harmonic_amplitudes(label, t, col, period, t0, n=3):
    """<label>_harmonic_1 .. _n: the amplitudes of the record at the wave maker's frequency and its
    multiples (m, Pa or N/m), least squares over the whole periods from t0 to the end with the
    mean level (harmonics, as the flume's); null under two whole periods. A wave
    over a bar or a breaking wave moves energy into the higher harmonics; a regular load's first
    harmonic is what linear theory gives, where its peaks carry the acoustic noise as well."""
    t, col = np.asarray(t, float), np.asarray(col, float)
    wet = np.isfinite(col) & (t >= t0)
    c = harmonics(t, col, 2.0 * math.pi / period, t0, float(t[-1]), n) if wet.sum() > 4 * n + 2 else None
    return {f"{label}_harmonic_{m + 1}": (float(abs(c[m])) if c is not None else None) for m in range(n)}


def two_waves(xs, amps, k_a, k_b):
    """Least squares (Mansard & Funke 1980, J. Coastal Eng. Proc. 17, for any number of gauges)
    of C(x) = A exp(-i k_a x) + B exp(-i k_b x) through the gauges' complex amplitudes: the
    incident and reflected waves with k_b = -k_a, or the bound and free second harmonics with
    k_a = 2 k and k_b the free wave number at 2 omega. Returns (A, B) complex."""
    xs = np.asarray(xs, float)
    M = np.column_stack([np.exp(-1j * k_a * xs), np.exp(-1j * k_b * xs)])
    (a, b), *_ = np.linalg.lstsq(M, np.asarray(amps, complex), rcond=None)
    return a, b


def reflection(xs, amps, k):
    """(incident amplitude, reflected amplitude, reflection coefficient) of the first harmonic
    from three or more gauges (spaced well away from half a wavelength apart)."""
    a, b = two_waves(xs, amps, k, -k)
    return abs(a), abs(b), abs(b) / abs(a) if abs(a) > 0 else float("nan")


def free_second_harmonic(xs, amps2, k, k2):
    """(bound, free) amplitudes of the second harmonic: the bound wave travels with the first
    harmonic (2 k), the free one a paddle sheds at its own wave number k2 (2 omega)^2 = g k2 tanh."""
    b, f = two_waves(xs, amps2, 2 * k, k2)
    return abs(b), abs(f)


def stokes_bound_ratio(k, depth):
    """Second-order Stokes theory's bound second harmonic over the first, per unit first-harmonic
    amplitude a: a2 = a^2 k cosh(kh) (2 + cosh 2kh) / (4 sinh^3 kh)."""
    kh = k * depth
    return k * math.cosh(kh) * (2 + math.cosh(2 * kh)) / (4 * math.sinh(kh) ** 3)


def welch(t, eta, t0, t1, segment):
    """One-sided spectral density (m2/Hz) of eta over [t0, t1] by Welch's method: Hann-windowed
    segments of `segment` seconds, half overlapping, on the record resampled to its mean step.
    Returns (f, S, number of segments); (None, None, 0) when the window is shorter than a segment."""
    t, eta = np.asarray(t, float), np.asarray(eta, float)
    w = (t >= t0) & (t <= t1) & np.isfinite(eta)
    if w.sum() < 16:
        return None, None, 0
    dt = float(np.median(np.diff(t[w])))
    tt = np.arange(t[w][0], t[w][-1], dt)
    x = np.interp(tt, t[w], eta[w])
    n = int(round(segment / dt))
    if n < 8 or len(x) < n:
        return None, None, 0
    win = np.hanning(n)
    starts = range(0, len(x) - n + 1, n // 2)
    P = np.zeros(n // 2 + 1)
    for s in starts:
        seg = x[s : s + n] - x[s : s + n].mean()
        P += np.abs(np.fft.rfft(seg * win)) ** 2
    P *= 2 * dt / ((win**2).sum() * len(starts))
    P[0] /= 2
    return np.fft.rfftfreq(n, dt), P, len(starts)


def spectral_height_and_peak(f, S, lo, hi):
    """Hm0 = 4 sqrt(m0) over lo <= f <= hi, and the peak period 1 / fp with fp the spectrum's
    centroid weighted by S^4 (the "Delft" peak, steadier than the highest bin)."""
    m = (f >= lo) & (f <= hi)
    df = f[1] - f[0]
    m0 = S[m].sum() * df
    fp = (f[m] * S[m] ** 4).sum() / (S[m] ** 4).sum()
    return 4.0 * math.sqrt(m0), 1.0 / fp
