"""The flume's record: the wave gauges' heights, harmonics and periods against Biesel's transfer
and linear theory, the reflection array's incident and reflected waves, an irregular sea's
spectra, and the metrics and figures the flume writes from them."""

import math
import os

import numpy as np

from ...io import write_csv
from ...measure import harmonics, records
from ...measure.gauge_sets import WaveGauges
from ...measure.plots import pyplot, save
from ...waves.irregular import spectrum


def irregular_metrics(c, p, xg, cols, cg, keep):
    """Hm0 and Tp at each gauge from its spectrum (Welch, segments of 16 peak periods) once the
    ramped waves have arrived at the peak's group velocity, against the target; the spectra are
    kept in `keep` for spectra.csv."""
    t_end = float(c["t"][-1])
    fp = 1.0 / p["tp"]
    lo, hi = (b * fp for b in p["band"])
    out = dict(hm0_at_gauges=[], tp_at_gauges=[], waves_measured=[])
    for x, col in zip(xg, cols):
        t0 = records.arrival_time(p, x, cg)
        f, S, n = harmonics.welch(c["t"], c[col], t0, t_end, 16 * p["tp"])
        if n == 0:
            out["hm0_at_gauges"].append(float("nan"))
            out["tp_at_gauges"].append(float("nan"))
            out["waves_measured"].append(0)
            continue
        hm0, tp = harmonics.spectral_height_and_peak(f, S, lo, hi)
        out["hm0_at_gauges"].append(hm0)
        out["tp_at_gauges"].append(tp)
        out["waves_measured"].append(int((t_end - t0) / p["tp"]))
        keep[x] = (f, S)
    if math.isfinite(out["hm0_at_gauges"][0]):
        out["hm0_error"] = abs(out["hm0_at_gauges"][0] / p["hs"] - 1)
        out["tp_error"] = abs(out["tp_at_gauges"][0] / p["tp"] - 1)
    return out


def write_spectra(out, spectra, p, xg):
    """spectra.csv (f, the target, each gauge's S) and spectra.png."""
    f = next(iter(spectra.values()))[0]
    fp = 1.0 / p["tp"]
    band = (f >= p["band"][0] * fp) & (f <= p["band"][1] * fp)
    target = np.zeros_like(f)
    target[band] = spectrum(f[band], p["hs"], p["tp"], 1.0 if p["spectrum"] == "pm" else p["gamma"])
    cols = {"f_hz": f, "target_m2_per_hz": target}
    cols.update({f"S_x{x:.2f}": spectra[x][1] for x in xg if x in spectra})
    write_csv(os.path.join(out, "spectra.csv"), list(cols), np.column_stack(list(cols.values())))
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(7.5, 3.2))
    ax.plot(f, target, "k--", lw=1.0, label=f"target {p['spectrum']}, Hm0 {p['hs']:g} m, Tp {p['tp']:g} s")
    for x in xg:
        if x in spectra:
            ax.plot(f, spectra[x][1], lw=0.9, label=f"gauge at {x:.2f} m")
    ax.set_xlim(0, 1.2 * p["band"][1] * fp)
    ax.set_xlabel("f (Hz)")
    ax.set_ylabel("S (m2/Hz)")
    ax.legend(fontsize=8)
    save(fig, os.path.join(out, "spectra.png"))


def worst(errors):
    """The largest error over the gauges the waves have reached (NaN if none has)."""
    e = [v for v in errors if math.isfinite(v)]
    return max(e) if e else float("nan")


class FlumeRecord:
    """The flume's gauges and array, and what their records give: the wave heights, periods and
    harmonics against Biesel at each gauge, the decay, the array's reflection and second
    harmonics, or a spectrum's Hm0 and Tp (metrics, from the probe columns alone); gauges.png and
    spectra.csv (finalize)."""

    def __init__(self, cfg, wave, xg, xa):
        """wave: (omega, k, wavelength, group velocity, Biesel's H/S, the second harmonic's k and
        group velocity); xg, xa: the gauges' and the array's x."""
        self.cfg, self.xg, self.xa = cfg, xg, xa
        self.omega, self.k, self.wavelength, self.cg, self.hs_ratio, self.k2, self.cg2 = wave
        self.H_biesel = self.hs_ratio * cfg.paddle.stroke
        self.cols = tuple(f"eta_{i}" for i in range(len(xg)))
        self.acols = tuple(f"array_{i}" for i in range(len(xa)))
        dx = cfg.numerics.dx
        self.gauges = WaveGauges(xg + xa, dx, cfg.numerics.h_factor * dx, cfg.geometry.depth, self.cols + self.acols)
        self.seen, self.seen_spectra = {}, {}

    def _names(self):
        geo, p = self.cfg.geometry, self.cfg.paddle
        return (
            geo,
            p,
            geo.depth,
            geo.length,
            self.omega,
            self.k,
            self.wavelength,
            self.cg,
            self.hs_ratio,
            self.k2,
            self.cg2,
            self.H_biesel,
            self.xg,
            self.xa,
            self.cols,
            self.acols,
            self.gauges,
        )

    def metrics(self, c):
        geo, p, d, Lf, omega, k, wavelength, cg, hs_ratio, k2, cg2, H_biesel, xg, xa, cols, acols, gauges = (
            self._names()
        )
        seen_spectra = self.seen_spectra
        self.seen.update(c)
        out = dict(
            kh=k * d,
            wavelength=wavelength,
            group_velocity=cg,
            biesel_H_over_S=hs_ratio,
            gauges_x=xg,
            array_x=xa,
            gauge_zero_offset=list(gauges.zero[: len(xg)]),
        )
        if not p.spectrum:
            out["biesel_wave_height"] = H_biesel
        elif xg:
            out.update(irregular_metrics(c, p, xg, cols, cg, seen_spectra))
        if not xg or p.series or p.spectrum:
            return out
        t_end = float(c["t"][-1])
        H, H1, err, err1, Tz, mean_level = [], [], [], [], [], []
        for x, col in zip(xg, cols):
            t0 = records.arrival_time(p, x, cg)
            t1 = t_end
            if geo.damping_length < 0.5 * wavelength:
                # no absorbing zone worth the name: stop before the end wall's reflection is back
                t1 = min(t1, (2 * Lf - x) / cg)
            if p.duration > 0:  # and before the paddle's ramp down has arrived
                t1 = min(t1, p.duration - p.ramp_periods * p.period + x / cg)
            h_pp, n = records.wave_height(c["t"], c[col], t0, t1, p.period)
            per, level = records.crossing_period_and_level(c["t"], c[col], t0, t1)
            Tz.append(per)
            mean_level.append(level)
            a = harmonics.harmonics(c["t"], c[col], omega, t0, t1, 1)
            H.append(h_pp if n else float("nan"))
            H1.append(2 * abs(a[0]) if a is not None else float("nan"))
            err.append(abs(H[-1] - H_biesel) / H_biesel)
            err1.append(abs(H1[-1] - H_biesel) / H_biesel)
        out.update(
            wave_height_at_gauges=H,
            wave_period_at_gauges=Tz,
            mean_level_at_gauges=mean_level,
            first_harmonic_height_at_gauges=H1,
            wave_height_errors=err,
            first_harmonic_errors=err1,
            # the worst gauge: the target is Biesel's height everywhere in the flume
            wave_height_error=worst(err),
            first_harmonic_error=worst(err1),
        )
        if len(xg) > 1:
            # decay per wavelength of the first harmonic, fitted over the gauges
            ok = np.isfinite(H1)
            if ok.sum() > 1:
                slope = np.polyfit(np.asarray(xg)[ok] / wavelength, np.log(np.asarray(H1)[ok]), 1)[0]
                out["decay_per_wavelength"] = float(1 - math.exp(slope))
        if xa:
            out.update(self.array_metrics(c, t_end))
        return out

    def array_metrics(self, c, t_end):
        """The reflection array: the incident and reflected first harmonics once the wave the far end
        reflects is back over it, and the second harmonic's bound and free parts."""
        p, geo, xa, acols = self.cfg.paddle, self.cfg.geometry, self.xa, self.acols
        omega, k, cg, k2, cg2 = self.omega, self.k, self.cg, self.k2, self.cg2
        d, Lf = geo.depth, geo.length
        out = {}
        t0 = records.arrival_time(p, xa[-1], cg)
        t_back = p.ramp_periods * p.period + (2 * Lf - xa[0]) / cg + p.period
        amps = [harmonics.harmonics(c["t"], c[col], omega, max(t0, t_back), t_end, 2) for col in acols]
        if all(a is not None for a in amps):
            ai, ar, kr = harmonics.reflection(xa, [a[0] for a in amps], k)
            out.update(
                reflection_coefficient=kr,
                reflection_window=[max(t0, t_back), t_end],
                incident_height=2 * ai,
                reflected_height=2 * ar,
            )
        # the free second harmonic travels at its own, slower group velocity: fit once it is there
        t0 = records.arrival_time(p, xa[-1], cg2)
        amps = [harmonics.harmonics(c["t"], c[col], omega, t0, t_end, 2) for col in acols]
        if all(a is not None for a in amps):
            out["second_harmonic_window"] = [t0, t_end]
            b, f = harmonics.free_second_harmonic(xa, [a[1] for a in amps], k, k2)
            ai = np.mean([abs(a[0]) for a in amps])
            out.update(
                second_harmonic_bound=b,
                second_harmonic_free=f,
                second_harmonic_bound_stokes=harmonics.stokes_bound_ratio(k, d) * ai * ai,
            )
        return out

    def finalize(self, out, metrics):
        _, p, _, _, _, _, _, cg, _, _, _, H_biesel, xg, _, cols, _, _ = self._names()
        seen, seen_spectra = self.seen, self.seen_spectra
        plt = pyplot()
        data = seen
        if not data or len(data["t"]) < 2:
            return
        fig, axes = plt.subplots(len(xg), 1, figsize=(7.5, 1.8 * len(xg) + 0.6), sharex=True, squeeze=False)
        for i, ax in enumerate(axes[:, 0]):
            ax.plot(data["t"], data[cols[i]], lw=0.8)
            if not p.spectrum:
                ax.axhline(0.5 * H_biesel, color="k", ls="--", lw=0.6)
                ax.axhline(-0.5 * H_biesel, color="k", ls="--", lw=0.6)
            ax.set_ylabel(f"eta (m) at {xg[i]:.2f} m")
            ax.axvspan(
                records.arrival_time(p, xg[i], cg),
                data["t"][-1],
                color="0.9",
                label="measured from here: the fully ramped waves have arrived" if i == 0 else None,
            )
            if i == 0:
                ax.legend(fontsize=7, loc="lower right")
        axes[-1, 0].set_xlabel("t (s)")
        if seen_spectra:
            write_spectra(out, seen_spectra, p, xg)
        fig.suptitle(
            f"{p.type} paddle, {p.spectrum} spectrum Hm0 {p.hs:g} m, Tp {p.tp:g} s"
            if p.spectrum
            else f"{p.type} paddle: gauges against Biesel H = {H_biesel:.3g} m (dashed)",
            fontsize=10,
        )
        save(fig, os.path.join(out, "gauges.png"))
