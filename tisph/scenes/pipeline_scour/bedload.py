"""The pipeline over the morphodynamic bed (sediment.model = "bedload", the default): SPH water
around a no-slip pipe over a height field z_b(x) whose boundary particles follow it
(tisph/sediment), in a periodic current.

The bed shear is the log law through the filtered near-bed velocity reference_height dx above
the bed, with the current's own roughness z0 (the one its log-law inflow profile has), scaled so
that its median over the approach flow is the current's rho u*^2 (sediment.shear =
"log_far_field"; coupling.BedCoupler says why): the undisturbed bed feels the current's u* and
the gap under the pipe, where the flow accelerates, feels more. With the k equation the bed can
feel its k too (sediment.shear = "wall_function": Launder & Spalding's wall function, each of its
two factors scaled the same way; Mao's case file). Sand the gap jet throws up
settles out over sediment.deposition_length; with sediment.lee_transit it crosses the still or
reversed water behind the pipe with the current instead of stopping where the jet dies, and with
sediment.settling_delay it lands the most half a deposition length on. The bed
slope acts through the threshold alone (sediment.gravity_coefficient = 0): with Bailard's downslope term on top the sand could not climb
out of the hole and it stopped at a third of Mao's depth (scenes/pipeline_scour_mao.toml). Tunnel erosion needs water under the pipe: the
initial dip (geometry.perturbation) and gap (geometry.gap) give it, as the paper and the grid
models of this experiment open one.
With sediment.suspended the water also carries sand in suspension (tisph/physics/suspension.py),
starting from the current's equilibrium (Rouse) profile. With geometry.reference = "mao" the run is compared with Mao's measured S/D(t) and bed profiles
(tisph/validation/mao.py) on the experiment's clock: the run starts where Mao's hole was as deep
as the initial dip, and the bed's time runs morfac times the flow's. With
geometry.initial_profile the bed starts as Mao's measured bed instead, and his clock at its time.
The bed shear at every probe goes to bed_shear.csv.
"""

import os

import numpy as np

from ...case import make_case
from ...constants import KAPPA, SQRT_CMU, G
from ...io import write_csv, write_station_rows
from ...measure.plots import pyplot, save
from ...particles import FLUID, ParticleSet, block, density_from_pressure, tait_B
from ...runner import common_params, sound_speed
from ...sediment import coupling, initial
from ...sediment.transport import rouse_profile, transport_scale
from ...settings.config import ConfigError, physics_from_config
from ...validation import mao
from .common import NAME, add_pipe, geometry, initial_bed, log_law, profile_time
from .record import ScourRecord, streamlines_event, water_velocity

APPROACH = 2.0  # the far field: the approach flow from the inflow zone's end to this many D before the pipe


def bed_stations(g):
    """The bed's stations: dx apart over the periodic length, from x = dx/2."""
    return (np.arange(int(round(g.Lx / g.dx))) + 0.5) * g.dx


def far_field(g, stations, inflow_length):
    """The undisturbed bed's stations: upstream of the pipe, out of the inflow zone and APPROACH D
    clear of the pipe. Not downstream: in a periodic domain 10-15 D long the wake and the dune
    reach the seam (measured: with the downstream stations in it the far field's median shear fell
    with the wake's and the scaled shear under the pipe ran to 150 Pa)."""
    m = (stations > inflow_length + g.dx) & (stations < g.xc - APPROACH * g.D)
    if m.sum() < 3:
        raise ConfigError(
            "geometry.inflow_length",
            inflow_length,
            f"at most {g.xc - APPROACH * g.D - 4 * g.dx:.4g} m with the bed-load bed: the far-field shear "
            f"is read on the approach flow between the inflow zone and {APPROACH:g} D before the pipe",
        )
    return m


def build_bedload(cfg):
    geo, sed = cfg.geometry, cfg.sediment
    g = geometry(cfg)
    dx, L, h, rw = g.dx, g.L, g.h, g.rw
    c0, u_max = sound_speed(cfg, 2.5 * g.U)  # the gap jet runs at up to about twice U
    stations = bed_stations(g)
    z = initial.initial_bed(stations, initial_bed(g, stations), sed, dx, periodic=True, top=g.ytop)
    ps = _particles(g, stations, z, c0)
    params = common_params(cfg, c0, G, depth=g.ytop)
    params["bed_stations"] = len(stations)
    pad = 4 * h
    floor = -(L + 2) * dx - 0.5 * g.hs  # room for the bed's columns as the hole deepens
    domain = ((0.0, floor - pad), (g.Lx, 2.0 * g.ytop + pad))
    inflow = (
        (0.0, geo.inflow_length, geo.inflow_rate, 0, g.hs, g.ustar, g.z0)
        if geo.inflow_length > 0 and geo.inflow_rate > 0
        else ()
    )
    physics = physics_from_config(
        cfg,
        periodic_x=True,
        noslip=True,
        materials_used=["water"],
        sps=geo.sps,
        moving_bed=True,
        inflow=inflow,
        suspension=sed.suspended,
    )
    if sed.shear == "wall_function" and physics.turbulence != "k_equation":
        raise ConfigError(
            "sediment.shear",
            sed.shear,
            "'log_far_field' unless numerics.turbulence = "
            f"'k_equation' (the wall function reads its k; here '{physics.turbulence}')",
        )
    far = far_field(g, stations, geo.inflow_length)
    bed = coupling.BedCoupler(
        sed,
        coupling.sand_of(sed, g.d50, g.rs, rw),
        coupling.Stations(stations, z, dx, h),
        coupling.Drive(z0=g.z0, far_field=(far, rw * g.ustar**2), surface=g.ytop),
    )
    params["w_s"] = bed.w_s
    if sed.suspended:
        ps.concentration = equilibrium_suspension(g, bed, ps)
        bed.carrying(float(np.sum(ps.concentration * ps.m)) / rw)
    if physics.turbulence == "k_equation":
        ps.tke, ps.turbulence_length = equilibrium_turbulence(g, bed, ps)
    rec = BedScourRecord(cfg, g, bed)
    t_end = cfg.run.end_time
    events = [(t, rec.on_profile_sample) for t in np.arange(0.5 * t_end, t_end + 1e-9, 0.05)]
    stills_at = (0.0, 0.5 * t_end, t_end)
    if cfg.output.render:
        events += [(t, streamlines_event(g)) for t in stills_at]
    # frames: the pipe and its hole, 4 D upstream to 8 D downstream, to the surface
    x0, x1 = max(0.0, g.xc - 4 * g.D), min(g.Lx, g.xc + 8 * g.D)
    return make_case(
        name=NAME,
        particles=ps,
        materials=[dict(cfg.materials.water, name="water", B=tait_B(rw, c0))],
        domain=domain,
        params=params,
        physics=physics,
        view=((x0, g.hs - 1.2 * g.D), (x1, g.ytop + 2 * dx)),
        u_max=u_max,
        probe_columns=("scour_depth_over_D", "transport_rate_phi", "max_bed_shear", "u_mean", "body_force"),
        probe=rec.probe,
        metrics=rec.metrics,
        finalize=rec.finalize,
        events=sorted(events, key=lambda e: e[0]),
        stills=stills_at,
        container=(-1e9, floor, 1e9, float("inf")),
        control=rec.control,
        render_modes=("speed", "concentration") if sed.suspended else ("speed",),
        control_every=sed.update_every,
        persist=(rec, bed),
        **bed.picture(),
    )


def _particles(g, stations, z, c0):
    """Water in the log law above the bed z (at least dx/2 clear of it) and outside the pipe;
    the bed's BED columns; the pipe's rings. Hydrostatic densities."""
    dx, rw = g.dx, g.rw

    def density(y):
        return density_from_pressure(rw * G * np.maximum(g.ytop - y, 0.0), rw, c0)

    lattice = block(0.0, float(z.min()), g.Lx, g.ytop, dx)
    above, col = initial.above_bed(lattice, stations, z, dx)
    keep = above & ~(np.hypot(lattice[:, 0] - g.xc, lattice[:, 1] - g.yc) < g.R + 0.5 * dx)
    xw = lattice[keep]
    vw = np.column_stack([log_law(xw[:, 1] - z[col[keep]], g.ustar, g.z0), np.zeros(len(xw))])
    ps = ParticleSet()
    ps.add(xw, FLUID, 0, density(xw[:, 1]), rw * dx * dx, v=vw)
    initial.add_bed_particles(ps, stations, z, dx, g.L, rw, density)
    add_pipe(ps, g, density)
    return ps


def equilibrium_suspension(g, bed, ps):
    """The live bed's current arrives carrying its equilibrium load: the Rouse profile of the
    far field's u* over the bed at each water particle, with van Rijn's c_a at one dx (where the
    bed exchange reads it); 0 elsewhere. Without it the clear water of the start takes sand from
    the whole bed at first (measured: 0.016 D of bed in the first 0.9 s of Mao's case)."""
    ca = float(bed.pickup_concentration(g.rw * g.ustar**2))
    z = bed.bed.z
    fl = ps.kind == FLUID
    _, col = initial.above_bed(ps.x, bed.stations, z, g.dx)
    above = ps.x[:, 1] - z[col]
    c = np.zeros(len(ps))
    c[fl] = rouse_profile(above[fl], g.ytop - z[col[fl]], g.dx, ca, bed.w_s, g.ustar)
    return c


def turbulence_length(g, x, z):
    """Prandtl's length l = min(kappa d, 0.09 H) (Rodi 1993, sec. 2.3.3; the 0.09 H of open
    channels) at points x over the bed heights z under them (BedCoupler.surface): d the distance to the
    nearer of the bed and the pipe (at least dx/2), H the local depth."""
    d_bed = x[:, 1] - z
    d_pipe = np.hypot(x[:, 0] - g.xc, x[:, 1] - g.yc) - g.R
    d = np.maximum(np.minimum(d_bed, d_pipe), 0.5 * g.dx)
    return np.minimum(KAPPA * d, 0.09 * np.maximum(g.ytop - z, g.dx))


def equilibrium_turbulence(g, bed, ps):
    """The current's k and l at each particle: k = u*^2 / sqrt(C_mu) (1 - z/H), the equilibrium
    of a wall layer's production and dissipation falling to 0 at the surface (Nezu & Nakagawa
    1993 measure 4.78 u*^2 exp(-2 z/H); the two agree to 30 % over the depth's lower half)."""
    z = bed.surface(ps.x[:, 0])
    H = np.maximum(g.ytop - z, g.dx)
    k = g.ustar**2 / SQRT_CMU * np.clip(1.0 - (ps.x[:, 1] - z) / H, 0.0, 1.0)
    return np.where(ps.kind == FLUID, k, 0.0), turbulence_length(g, ps.x, z)


def equilibrium_fit(tb, s):
    """Fit S(t) = S0 + (S_eq - S0)(1 - exp(-t / T)) to the scour depth against the bed's time
    (Sumer & Fredsoe's exponential approach to equilibrium); returns (S_eq, T), NaN when the run
    is too short to tell (under 5 samples, or the best T beyond 10 times the run)."""
    tb, s = np.asarray(tb, float), np.asarray(s, float)
    m = (tb > 0) & np.isfinite(s)
    if m.sum() < 5:
        return float("nan"), float("nan")
    t, y, s0 = tb[m], s[m] - s[0], s[0]
    best = (np.inf, np.nan, np.nan)
    for T in np.geomspace(0.05 * t[-1], 10 * t[-1], 200):
        f = 1.0 - np.exp(-t / T)
        a = float(f @ y / (f @ f))
        err = float(np.sum((a * f - y) ** 2))
        if err < best[0]:
            best = (err, s0 + a, T)
    if best[2] >= 9.9 * t[-1]:
        return float("nan"), float("nan")
    return float(best[1]), float(best[2])


class BedScourRecord(ScourRecord):
    """ScourRecord over the morphodynamic bed: the bed is z_b, the transport its flux under the
    pipe; with geometry.reference = "mao", Mao's S/D(t) and profiles beside the run's."""

    def __init__(self, cfg, g, bed):
        super().__init__(cfg, g)
        self.bed = bed
        self.under = np.abs(self.stations - g.xc) < g.D  # Mao's deepest point lies just downstream
        self.k_pipe = int(np.argmin(np.abs(self.stations - g.xc)))
        self.scale = transport_scale(g.d50, g.rs / g.rw, G)
        self.morfac = cfg.sediment.morfac
        self.mao = cfg.geometry.reference == "mao"
        # Mao's profiles are from his pipe's centre, D/2 above the undisturbed bed; a gap raises
        # ours, so the comparison is made from where his centre was
        self.y_ref = g.hs + g.R
        self.shear_rows = []  # (t, the bed shear at each station), at the probes' times
        # the experiment's clock starts where Mao's hole was as deep as the initial dip, or at the
        # time of his bed the run starts from
        start = profile_time(cfg.geometry)
        self.t0_mao = mao.time_of_depth(float(self.depth(bed.z0))) if start is None else start

    def depth(self, z):
        """S/D below the undisturbed bed under the pipe, of a bed z (or of each row of beds)."""
        z = np.asarray(z, float)
        return (self.g.hs - z[..., self.under].min(axis=-1)) / self.g.D

    def bed_time(self, t):
        """The bed's time at the run's time t: morfac times the flow's once it moves (morph_start)."""
        return self.morfac * np.maximum(np.asarray(t, float) - self.bed.sed["morph_start"], 0.0)

    def experiment_time(self, t):
        """The experiment's clock at the run's time t."""
        return self.t0_mao + self.bed_time(t)

    def control(self, s):
        self.update(s)  # the drive's feedback on the host, at the bed's cadence
        self.bed.update(s)
        if "lt" in s.members:  # the k-equation's length follows the bed
            x = s.p.x.to_numpy()
            s.p.lt.from_numpy(turbulence_length(self.g, x, self.bed.surface(x[:, 0])).astype(s.np_real))

    def probe(self, st):
        zb = self.bed.bed.z
        self.rows.append((st["t"],) + tuple(zb))
        self.shear_rows.append((st["t"],) + tuple(self.bed.tau))
        phi = float(self.bed.bed.q[self.k_pipe]) / self.scale
        return float(self.depth(zb)), phi, float(np.abs(self.bed.tau).max()), water_velocity(st), self.ctl.value

    def metrics(self, c):
        out = super().metrics(c)
        b = self.bed
        far = self.bed.far_field[0]
        tau_far = float(np.median(np.abs(b.tau[far])))  # far_field() holds 3 stations or more
        out.update(
            sediment_model="bedload",
            morfac=self.morfac,
            theta_cr=b.bed.theta_cr,
            sand_volume_error=b.volume_error(),
            suspended_sand=b.suspended,  # m2 of grains per unit width in the water at the end
            shields_far_field=float(np.median(b.bed.theta[far])),
            # the gap flow's shear against the undisturbed bed's, at the end
            gap_shear_over_far_field=float(np.abs(b.tau[self.under]).max()) / tau_far if tau_far > 0 else float("nan"),
        )
        s_eq, T = equilibrium_fit(self.bed_time(c["t"]), c["scour_depth_over_D"])
        s0 = float(c["scour_depth_over_D"][0])
        out["equilibrium_depth_fit_over_D"], out["scour_time_scale_fit"] = s_eq, T
        # the bed's time to half the fitted equilibrium depth (0: the initial dip was deeper)
        if not np.isfinite(s_eq):
            half = float("nan")
        elif 0.5 * s_eq > s0:  # then also s_eq > s0
            half = float(-T * np.log(1.0 - (0.5 * s_eq - s0) / (s_eq - s0)))
        else:
            half = 0.0
        out["time_to_half_equilibrium"] = half
        if self.mao:
            te = self.experiment_time(c["t"])
            out["mao_time_offset"] = float(te[0])
            out["mao_depth_max_error_15s"], out["mao_depth_rms_error_15s"] = mao.depth_error(
                te, c["scour_depth_over_D"], 15.0
            )
            for tp in mao.PROFILES:
                out[f"scour_profile_error_{tp:g}s"] = self.profile_error(tp)
        return out

    def row_at(self, arr, te, tp):
        """The bed row (t, z...) of arr nearest Mao's time tp on the clock te, or None if the run
        did not reach it (within a quarter of a bed-second per flow-second)."""
        if te[-1] < tp - 0.25 * self.morfac:
            return None
        return arr[int(np.argmin(np.abs(te - tp)))]

    def profile_error(self, tp):
        """scour_profile_error at Mao's time tp from the bed row nearest it (NaN: not reached)."""
        arr = np.array(self.rows)
        r = self.row_at(arr, self.experiment_time(arr[:, 0]), tp) if len(arr) else None
        if r is None:
            return float("nan")
        return mao.scour_profile_error(tp, self.stations - self.g.xc, r[1:] - self.y_ref, self.g.D)

    def finalize(self, out, metrics):
        super().finalize(out, metrics)
        if self.shear_rows:
            write_station_rows(os.path.join(out, "bed_shear.csv"), self.stations, self.shear_rows)
        if self.mao and self.rows:
            self.plot_mao(out)

    def plot_mao(self, out):
        g, plt = self.g, pyplot()
        arr = np.array(self.rows)
        te = self.experiment_time(arr[:, 0])
        s = self.depth(arr[:, 1:])
        write_csv(
            os.path.join(out, "scour_depth_mao.csv"),
            ("t_experiment", "S_over_D", "S_over_D_mao"),
            list(zip(te, s, mao.depth_at(te))),
        )
        fig, (a1, a2) = plt.subplots(1, 2, figsize=(11, 3.6), gridspec_kw=dict(width_ratios=(1, 1.6)))
        a1.plot(mao.DEPTH[:, 0], mao.DEPTH[:, 1], "o", ms=3, color="k", label="Mao (1986)")
        a1.plot(te, s, "-", color="C0", label=f"tisph, morfac {self.morfac:g}")
        a1.set_xlabel("t (s, the experiment's clock)")
        a1.set_ylabel("S / D")
        a1.set_xlim(0, max(30.0, float(te[-1])))
        a1.legend(fontsize=8)
        for k, tp in enumerate(mao.PROFILES):
            ref = mao.PROFILES[tp]
            a2.plot(ref[:, 0] / g.D, ref[:, 1] / g.D, "o", ms=2.5, color=f"C{k}", label=f"Mao {tp:g} s")
            r = self.row_at(arr, te, tp)
            if r is not None:
                a2.plot(
                    (self.stations - g.xc) / g.D,
                    (r[1:] - self.y_ref) / g.D,
                    "-",
                    color=f"C{k}",
                    lw=1,
                    label=f"tisph {tp:g} s",
                )
        lift = (g.yc - self.y_ref) / g.D  # the run's pipe stands the initial gap above Mao's
        a2.add_patch(
            plt.Circle((0, lift), 0.5, color="0.6", label=f"pipe, {lift:.2g} D above Mao's" if lift > 1e-6 else "pipe")
        )
        a2.set_xlim(-3, 7)
        a2.set_aspect("equal")
        a2.set_xlabel("x / D from the pipe's centre (flow to the right)")
        a2.set_ylabel("bed / D from Mao's pipe centre")
        # below the panel (its equal aspect leaves the room), where it hides no profile
        a2.legend(fontsize=8, ncol=4, loc="upper center", bbox_to_anchor=(0.5, -0.32), frameon=False)
        save(fig, os.path.join(out, "scour_mao.png"))
