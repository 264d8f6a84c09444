"""A bed-load sand bed over a stretch of a solid line in a custom case ([sand], [sediment]): the
beach's bed (tisph/sediment, docs/sediment.md) with the line's surface as its initial level.

Over [x0, x1] the line's wall particles give way to bed particles that follow z_b(x), one station
a spacing; the bed's ends are closed (its sand is conserved). The shear is the waves' (Swart's
friction factor on the near-bed orbital motion measured at each station, as on the beach), so a
sand bed needs the paddle. The bed may erode down to the bottom of domain.box.
"""

import dataclasses
import os

import numpy as np

from ...io import write_station_rows
from ...measure.plots import pyplot, save
from ...particles import density_from_pressure
from ...sediment import coupling, initial
from ...sediment import keys as sediment_keys
from ...settings.config import ConfigError
from ...settings.schema import K, values, with_defaults

SAND = {
    "x": K([], '[x0, x1] m: the stretch of the sand line that is a bed-load bed; []: no sand'),
    "solid": K("", "the label of the [[solid]] line (or csv) whose surface is the bed's initial level"),
    "grain_diameter": K(0.0003, "d50, the bed load's grain", 'm'),
}
SAND_DEFAULTS = values(SAND)


def check(cfg, solids, box, errors):
    """The [sand] table against the solids and the box: the stations and the line's level there."""
    s, dx = cfg.sand, cfg.numerics.dx
    if not s.x:
        base = SEDIMENT_DEFAULTS
        errors += [
            ConfigError(
                f"sediment.{k}",
                v,
                f"its default ({base[k]!r}) without a sand bed",
                "the [sediment] keys set the bed-load bed; give sand.x and sand.solid",
            )
            for k, v in cfg.sediment.items()
            if v != base[k]
        ]
        return None
    x = s.x
    if not (isinstance(x, list) and len(x) == 2 and all(isinstance(v, (int, float)) for v in x) and x[0] < x[1]):
        errors.append(ConfigError("sand.x", x, "[x0, x1] in m with x0 < x1"))
        return None
    if not box[0] <= x[0] < x[1] <= box[1]:
        errors.append(ConfigError("sand.x", x, f"a stretch inside domain.box ({box[0]:g} to {box[1]:g} m)"))
        return None
    if (x[1] - x[0]) < 16 * dx:
        errors.append(ConfigError("sand.x", x, f"a stretch at least 16 dx = {16 * dx:g} m long"))
        return None
    line = next((e for e in solids if e["label"] == s.solid and e.get("shape") == "line"), None)
    if line is None:
        errors.append(
            ConfigError(
                "sand.solid",
                s.solid,
                "the label of a [[solid]] line or csv: "
                + ", ".join(repr(e["label"]) for e in solids if e.get("shape") == "line"),
            )
        )
        return None
    if cfg.paddle.type == "none":
        errors.append(
            ConfigError(
                "sand.x",
                x,
                "[] without a paddle",
                "the bed's shear is the waves' (Swart's "
                "friction factor on the near-bed orbital motion): a sand bed needs [paddle] type",
            )
        )
        return None
    if s.grain_diameter <= 0:
        errors.append(ConfigError("sand.grain_diameter", s.grain_diameter, "a number > 0 (m)"))
        return None
    pts = np.asarray(line["line"])
    cover = (pts[1:, 0] > x[0]) & (pts[:-1, 0] < x[1])
    if (np.diff(pts[:, 0])[cover] <= 0).any():
        errors.append(ConfigError("sand.x", x, f"a stretch where {line['name']} runs from left to right (a bed z(x))"))
        return None
    n = int(round((x[1] - x[0]) / dx))
    stations = x[0] + (np.arange(n) + 0.5) * dx
    z = np.interp(stations, pts[:, 0], pts[:, 1])
    if z.min() - box[2] < 4 * dx:
        errors.append(
            ConfigError(
                "domain.box",
                box,
                f"a bottom at least 4 dx below the sand's lowest point ({z.min():.4g} m): the bed may erode down to it",
            )
        )
        return None
    return stations, z, line


@dataclasses.dataclass(frozen=True)
class Still:
    """The still water over the bed: its level, density, sound speed and gravity (the bed
    particles' hydrostatic density)."""

    level: float
    rho_w: float
    c0: float
    g: float


class SandBed:
    """The bed, its bed particles, probes and outputs."""

    def __init__(self, cfg, site, lay, still, omega, h):
        """site: (stations, their heights, the [[solid]] line it lies on) (sand_site)."""
        stations, z, line = site
        level, rho_w = still.level, still.rho_w
        self.cfg, self.dx = cfg, cfg.numerics.dx
        sed = cfg.sediment
        self.stations = stations
        z0 = initial.initial_bed(stations, z, sed, self.dx, periodic=False)
        x0, x1 = cfg.sand.x
        shape = next(sh for e, sh in lay.shapes if e is line)
        stretch = (lay.pts[:, 0] > x0) & (lay.pts[:, 0] < x1)
        lay.wall &= ~(stretch & shape.band(lay.pts, lay.T))  # the bed particles stand in for them
        zl = np.interp(lay.pts[:, 0], stations, z0)
        lay.water &= ~(stretch & (lay.pts[:, 1] < zl + 0.5 * self.dx))
        over = stretch & lay.water  # its columns down onto the bed (initial.water_columns)
        lay.pts[over, 1] -= initial.drop_onto_bed(lay.pts[over, 1], zl[over], self.dx)
        self.level, self.rho_w, self.c0, self.g = level, rho_w, still.c0, still.g
        sand = coupling.sand_of(sed, cfg.sand.grain_diameter, sed.grain_density, rho_w)
        self.coupler = coupling.BedCoupler(
            sed,
            sand,
            coupling.Stations(stations, z0, self.dx, h, periodic=False),
            coupling.Drive(amplitude=None, omega=omega, still_level=level),
        )
        self.rows = []

    def density(self, y):
        return density_from_pressure(self.rho_w * self.g * np.maximum(self.level - y, 0.0), self.rho_w, self.c0)

    def add_particles(self, ps, layers):
        initial.add_bed_particles(ps, self.stations, self.coupler.bed.z, self.dx, layers, self.rho_w, self.density)

    def picture(self):
        b = self.coupler
        return dict(
            bed_surface=lambda x: np.interp(x, self.stations, b.bed.z, left=-np.inf, right=-np.inf),
            bed_panel=b.change,
            bed_label=b.picture()["bed_label"],
        )

    def probe(self, st):
        zb = self.coupler.bed.z
        self.rows.append((st["t"],) + tuple(zb))
        return (float(np.sqrt(np.mean((zb - self.coupler.z0) ** 2))),)

    def metrics(self, c):
        b = self.coupler
        dz = b.bed.z - b.z0
        out = dict(
            sand_volume_error=b.volume_error(),
            bed_change_rms=float(np.sqrt(np.mean(dz * dz))),
            bed_erosion_max=float(-dz.min()),
            bed_deposition_max=float(dz.max()),
            morfac=self.cfg.sediment.morfac,
        )
        return out

    def finalize(self, out):
        """bed_profile.csv (the bed at every probe) and bed_profile.png (the bed at the start and the
        end, and the change)."""
        if not self.rows:
            return
        write_station_rows(os.path.join(out, "bed_profile.csv"), self.stations, self.rows)
        plt = pyplot()
        b = self.coupler
        fig, (a1, a2) = plt.subplots(2, 1, figsize=(9, 5), sharex=True)
        a1.plot(self.stations, b.z0, "k--", lw=0.8, label="at the start")
        a1.plot(self.stations, b.bed.z, lw=1.0, label=f"at t = {self.rows[-1][0]:.3g} s")
        a1.axhline(self.level, color="tab:blue", lw=0.6, ls=":", label="still water")
        a1.set_ylabel("bed z (m)")
        a1.legend(fontsize=8)
        a2.plot(self.stations, 1e3 * (b.bed.z - b.z0), lw=1.0)
        a2.axhline(0.0, color="k", lw=0.5)
        a2.set_ylabel("bed change (mm)")
        a2.set_xlabel("x (m)")
        fig.suptitle(f"sand bed, morfac {self.cfg.sediment.morfac:g}", fontsize=10)
        save(fig, os.path.join(out, "bed_profile.png"))


# the bed-load bed's keys: the beach's set (keys.WAVE_RIPPLES read unscaled, docs/sediment.md)
SEDIMENT = with_defaults(sediment_keys.SEDIMENT, **dict(sediment_keys.WAVE_RIPPLES, outer_height=0.0))
SEDIMENT_DEFAULTS = values(SEDIMENT)
