"""Current-induced scour beneath a marine pipeline (paper 002, section 4.2; Mao 1986).

A pipe of diameter D lies on a sand bed in a current; the flow through the gap under the pipe
scours a tunnel (tunnel erosion), then a lee-wake hole forms. Two phases: water (Newtonian, with
the SPS turbulence closure of paper 002 eq. 10) and sand (Cross rheology, eqs. 29-30, with the
paper's mu_inf = 0.07 Pa s, tau_B = 25 Pa read as mu0 = 1000 mu_inf, K = mu0 / tau_B), coupled by
pressure, viscosity and a drag term (eq. 16, made dimensionally consistent; see tisph/terms/drag.py).
The pipe is a ring of boundary particles with the no-slip ghost velocity of eq. 39. The current
is periodic in x, starts from the log law (eq. 32, kappa = 0.42) and is held at its mean
velocity by a body force with feedback.

Defaults: D = 0.1 m, water 0.35 m deep above the bed, mean velocity 0.4 m/s with Mao's Shields
number 0.065, sand d50 = 0.36 mm, a domain 10 D long (periodic) with a sand layer 1.5 D deep,
dx = D/10, and an initial gap of 0.3 D under the pipe over a sinusoidal dip 0.1 D deep, as the
paper does to start tunnel erosion (a smaller gap holds no jet at this dx; see DEFAULTS).
scenes/pipeline_scour_theta098.toml: 0.5 m/s (Shields 0.098). scenes/pipe_on_rigid_bed.toml:
D = 5 cm on a rigid bed, U = 0.197 m/s (Oner et al. 2008).

The periodic seam would feed the pipe its own wake; an inflow zone relaxes the water back to the
log law there, as the paper's log-law inlet does. The body force that holds the mean velocity
stands for a pressure gradient, so sand feels it at rho_w / rho_s of its weight (tisph/solver.py).

Sand particles also touch as DEM grains (paper 002 eqs. 17-28, Table 3 constants). Eq. 28 puts
the contact at the grain diameter d_s, which two SPH particles a spacing apart never reach; with
the contact at one spacing every resting neighbour is a frictional contact and the bed is a
granular solid of 1 cm grains, whose Shields number under this current is 0.002: it did not move
in 4 s (0.0075 D of scour). Resting sand particles here are never closer than 0.84 dx (measured
over a 5 s run), so a contact diameter of 0.7 dx makes DEM what the paper says it is for, the
collisions of grains thrown together during scouring, and leaves the resting bed to the Cross
rheology. The DEM step limit dt_c/20 (eq. 27) is a third of the acoustic step at the default dx;
the solver takes it only while some grains touch or are about to (tisph/solver.py), which in the
default run is rare.
The paper ran 6.5 min of flow at dt = 1e-5 s; the default here is 20 s (9 to 15 minutes on two
cores), in which the hole under the pipe deepens from 0.10 D (the imposed dip) to about 0.19 D.
"""
import math
import types
import os
import sys

import numpy as np

from ..constants import G
from ..config import ConfigError, physics_from_config
from ..io import write_csv
from ..particles import ParticleSet, block, density_from_pressure, layered_pressure, tait_B, FLUID, WALL
from ..render import SAND
from ..case import make_case
from ..run import common_params, run_scene, sound_speed
from ..profiles import streamlines_png
from ..constants import KAPPA
from ..probes.control import PIDrive
from ..probes.gauges import surface_heights
from ..probes.plots import pyplot, save

NAME = "pipeline_scour"


DEFAULTS = {
    "run": {"end_time": 20.0},   # 9 to 15 minutes here; the paper ran 6.5 min of flow
    # Wendland kernel (paper 002 eq. 6), laminar viscosity + SPS (eq. 10), Shepard every 200 steps
    # is an option (shepard_every = 200); density diffusion is the default
    # c0 = 18 m/s: Table 3's c_0m
    "numerics": {"dx": 0.01, "h_factor": 1.3, "kernel": "wendland", "artificial_viscosity": 0.0,
                 "laminar_viscosity": True, "density_diffusion": "fourtakas", "delta": 0.1, "c0": 18.0},
    "geometry": {
        "pipe_diameter": 0.1,       # D (m)
        "water_depth": 0.35,        # above the undisturbed bed (m)
        "sand_depth": 0.15,         # 0: the pipe lies on a rigid bed (flow-only validation)
        "length": 1.0,              # periodic length, 10 D
        # Mao's pipe lies on the bed; the paper opens a small gap and a sinusoidal dip under it "for
        # numerical requirements". At dx = D/10 a gap of one spacing holds a single row of water
        # that the no-slip pipe and the bed hold still (measured: 0.01-0.04 m/s under the pipe),
        # so no jet forms; 3 spacings let the gap jet through (0.3-0.45 m/s).
        "gap": 0.03,                # initial gap under the pipe (m)
        "perturbation": 0.01,       # depth of the sinusoidal bed dip under the pipe (m)
        "mean_velocity": 0.4,       # held by the body-force feedback (m/s)
        # Shields number of the current (Mao's 0.065): sets u* = sqrt(theta (s-1) g d50), and the
        # log law's z0 follows from the mean velocity (1.5e-6 m: a hydraulically smooth bed).
        # 0: z0 = 2.5 d50 / 30 (Nikuradse) instead, and u* from the mean velocity.
        "shields": 0.065,
        "grain_diameter": 0.00036,  # d50 (m)
        "porosity": 0.4,
        "drag_coefficient": 0.4,    # Table 3
        "sps": True,
        # The periodic seam recirculates the pipe's wake; at dx = D/10 the SPS closure mixes far
        # too little to rebuild the near-bed flow in 10 D, and the water under the pipe's level
        # stalls within seconds (measured: near-bed velocity 0.19 -> 0 m/s by t = 5 s). A zone
        # this long (m) at x = 0 relaxes the water to the log law, as the paper's inlet does.
        "inflow_length": 0.2,
        "inflow_rate": 20.0,        # its relaxation rate (1/s); a particle crosses it in ~0.5 s
        "profile_offsets": [-2.0, 0.0, 2.0],   # velocity profiles at x = x_pipe + offset * D
    },
    # DEM contacts between sand particles, paper 002 Table 3 (its eta_s unit "N/m" is N s/m)
    "dem": {"enabled": True, "kn": 1.0e6, "ks": 1.0e5, "eta_n": 20.0, "eta_s": 40.0, "friction": 0.57,
            # in particle spacings; see the module docstring for why 0.7 and not 1
            "contact_diameter": 0.7},
    "materials": {
        "water": {"rho0": 1000.0, "viscosity": 1.0e-3},
        # Cross: mu_inf = 0.07 Pa s, tau_B = 25 Pa read as mu0 = 1000 mu_inf, K = mu0 / tau_B
        "sand": {"rho0": 1950.0, "viscosity": 0.07, "rheology": "cross", "mu0": 70.0, "K": 2.8, "m1": 1.0,
                 "mu_max": 0.0},
    },
    "output": {"frame_interval": 0.05, "probe_interval": 0.05, "width": 960},
}
RANGES = {f"geometry.{k}": (0.0, None, k in ("sand_depth", "gap", "perturbation", "drag_coefficient",
                                                              "inflow_length", "inflow_rate", "shields"), True)
          for k in ("pipe_diameter", "water_depth", "sand_depth", "length", "gap", "perturbation",
                    "mean_velocity", "grain_diameter", "drag_coefficient", "inflow_length", "inflow_rate",
                    "shields")}
RANGES["geometry.porosity"] = (0.0, 1.0, True, False)
RANGES.update({f"dem.{k}": (0.0, None, k.startswith("eta"), True) for k in ("kn", "ks", "eta_n", "eta_s", "friction")})
RANGES["dem.contact_diameter"] = (0.0, 1.5, False, True)


def check(cfg):
    g, dx = cfg["geometry"], cfg["numerics"]["dx"]
    D = g["pipe_diameter"]
    if D / dx < 8:
        raise ConfigError("numerics.dx", dx, f"at most {D / 8:.4g} m (8 particles across the pipe)")
    if g["length"] < 5 * D:
        raise ConfigError("geometry.length", g["length"], f"at least 5 pipe diameters ({5 * D:g} m)")
    if g["water_depth"] < D + g["gap"] + 4 * dx:
        raise ConfigError("geometry.water_depth", g["water_depth"],
                          f"at least pipe_diameter + gap + 4 dx ({D + g['gap'] + 4 * dx:.3g} m)")
    if g["inflow_length"] > 0.5 * g["length"] - 2 * D:
        raise ConfigError("geometry.inflow_length", g["inflow_length"],
                          f"at most half the length minus 2 D ({0.5 * g['length'] - 2 * D:.3g} m): the zone must end 2 D before the pipe")
    if 0 < g["sand_depth"] < 4 * dx:
        raise ConfigError("geometry.sand_depth", g["sand_depth"], f"0 (rigid bed) or at least 4 dx ({4 * dx:g} m)")
    if g["perturbation"] > 0.5 * g["sand_depth"]:
        raise ConfigError("geometry.perturbation", g["perturbation"], "at most half the sand depth")


def log_law(z, ustar, z0):
    """u(z) = (u*/kappa) ln(z/z0) above the bed (paper 002 eq. 32, kappa = 0.42), 0 below z0."""
    z = np.maximum(np.asarray(z, float), z0)
    return ustar / KAPPA * np.log(z / z0)


def friction_velocity(U, depth, z0):
    """u* whose log-law profile has depth-mean U: U = (u*/kappa) (ln(h/z0) - 1)."""
    return KAPPA * U / (math.log(depth / z0) - 1.0)


def ring(cx, cy, radius, dx):
    n = max(8, int(round(2 * math.pi * radius / dx)))
    a = np.arange(n) * 2 * math.pi / n
    return np.column_stack([cx + radius * np.cos(a), cy + radius * np.sin(a)]), np.column_stack([np.cos(a), np.sin(a)])


def geometry(cfg):
    """The case's derived quantities: pipe centre, water top, friction velocity and roughness."""
    geo, num = cfg["geometry"], cfg["numerics"]
    g = types.SimpleNamespace(dx=num["dx"], D=geo["pipe_diameter"], hw=geo["water_depth"], hs=geo["sand_depth"],
                              Lx=geo["length"], U=geo["mean_velocity"], d50=geo["grain_diameter"],
                              L=num["wall_layers"], h=num["h_factor"] * num["dx"], geo=geo)
    mats = cfg["materials"]
    g.rw, g.rs = mats["water"]["rho0"], mats["sand"]["rho0"]
    g.R = 0.5 * g.D
    g.xc = 0.5 * g.Lx
    g.yc = g.hs + geo["gap"] + g.R
    g.ytop = g.hs + g.hw
    if geo["shields"] > 0:
        g.ustar = math.sqrt(geo["shields"] * (g.rs / g.rw - 1) * G * g.d50)
        g.z0 = g.hw * math.exp(-(KAPPA * g.U / g.ustar + 1.0))
    else:
        g.z0 = 2.5 * g.d50 / 30.0                 # Nikuradse roughness 2.5 d50
        g.ustar = friction_velocity(g.U, g.hw, g.z0)
    return g


def build(cfg):
    geo = cfg["geometry"]
    g = geometry(cfg)
    dx, hs, L, mats = g.dx, g.hs, g.L, cfg["materials"]
    c0, u_max = sound_speed(cfg, 2.5 * g.U)      # the gap jet runs at up to about twice U
    ps = _particles(g, c0)
    dem = cfg["dem"]
    use_dem = dem["enabled"] and hs > 0
    materials = [dict(dict(mats[n]), name=n, B=tait_B(mats[n]["rho0"], c0), dem=(n == "sand" and use_dem))
                 for n in ("water", "sand")]
    params = common_params(cfg, c0, G, depth=g.ytop)
    if use_dem:   # the contact step (eq. 27) is the DEM module's default
        params.update(kn=dem["kn"], ks=dem["ks"], eta_n=dem["eta_n"], eta_s=dem["eta_s"], mu_c=dem["friction"],
                      dc=dem["contact_diameter"] * dx)
    params["drag_K"] = 0.75 * (1 - geo["porosity"]) * g.rw * geo["drag_coefficient"] / g.d50
    pad = 4 * g.h
    domain = ((0.0, -L * dx - pad), (g.Lx, 2.0 * g.ytop + pad))
    used = ["water"] + (["sand"] if hs > 0 else [])
    physics = physics_from_config(cfg, periodic_x=True, noslip=True, materials_used=used, sps=geo["sps"],
                                  drag=hs > 0 and geo["drag_coefficient"] > 0, dem=use_dem,
                                  inflow=(0.0, geo["inflow_length"], geo["inflow_rate"], 0, max(hs, 0.0), g.ustar, g.z0)
                                  if geo["inflow_length"] > 0 and geo["inflow_rate"] > 0 else ())
    rec = ScourRecord(cfg, g)
    t_end = cfg["run"]["end_time"]
    events = [(t, rec.on_profile_sample) for t in np.arange(0.5 * t_end, t_end + 1e-9, 0.05)]
    stills_at = (0.0, 0.5 * t_end, t_end)
    if cfg["output"]["render"]:
        events += [(t, _streamlines(g.Lx, g.ytop, dx, g.xc, g.yc, g.R)) for t in stills_at]
    return make_case(name=NAME, particles=ps, materials=materials, domain=domain, params=params, physics=physics,
                     view=((0.0, -L * dx), (g.Lx, g.ytop + 2 * dx)), u_max=u_max,
                     probe_columns=("scour_depth_over_D", "transport_rate_phi", "max_bed_shear", "u_mean",
                                    "body_force"),
                     probe=rec.probe, metrics=rec.metrics, finalize=rec.finalize,
                     events=sorted(events, key=lambda e: e[0]), stills=stills_at,
                     container=(-1e9, -0.5 * dx, 1e9, float("inf")),
                     render_modes=("phase", "pressure"), mat_colors=(None, SAND), control=rec.control, persist=(rec,),
                     pressure_scale=g.rw * G * g.ytop + (g.rs - g.rw) * G * hs)


def initial_bed(g, x):
    """The initial sand surface: flat, with a small dip under the pipe."""
    x = np.asarray(x, float)
    D, xc = g.D, g.xc
    dip = g.geo["perturbation"] * np.where(np.abs(x - xc) < D, 0.5 * (1 + np.cos(np.pi * (x - xc) / D)), 0.0)
    return g.hs - dip


def _particles(g, c0):
    """Water in the log law over the sand, the no-slip floor, and the pipe as rings of wall
    particles inside its surface (normals outward); hydrostatic densities."""
    dx, hs, L, rw, rs = g.dx, g.hs, g.L, g.rw, g.rs
    ps = ParticleSet()
    lattice = block(0.0, 0.0, g.Lx, g.ytop, dx)
    inside_pipe = np.hypot(lattice[:, 0] - g.xc, lattice[:, 1] - g.yc) < g.R + 0.5 * dx
    y_bed = initial_bed(g, lattice[:, 0]) if hs > 0 else np.zeros(len(lattice))
    sand = (lattice[:, 1] < y_bed) & ~inside_pipe
    water = (lattice[:, 1] >= y_bed) & ~inside_pipe
    xs, xw = lattice[sand], lattice[water]

    def pressure(y, yb):
        return layered_pressure(y, yb, g.ytop, rw, rs, G)

    yb_w = initial_bed(g, xw[:, 0]) if hs > 0 else 0.0
    vw = np.column_stack([log_law(xw[:, 1] - yb_w, g.ustar, g.z0), np.zeros(len(xw))])
    ps.add(xw, FLUID, 0, density_from_pressure(pressure(xw[:, 1], yb_w), rw, c0), rw * dx * dx, v=vw)
    if hs > 0:
        ps.add(xs, FLUID, 1, density_from_pressure(pressure(xs[:, 1], initial_bed(g, xs[:, 0])), rs, c0),
               rs * dx * dx)
    floor = block(0.0, -L * dx, g.Lx, 0.0, dx)
    ps.add(floor, WALL, 0, density_from_pressure(pressure(floor[:, 1], hs), rw, c0), rw * dx * dx,
           normal=(0.0, 1.0), wall_dist=-floor[:, 1])
    for k in range(L):
        r_k = g.R - (k + 0.5) * dx
        if r_k <= 0:
            break
        pts, nrm = ring(g.xc, g.yc, r_k, dx)
        ps.add(pts, WALL, 0, density_from_pressure(pressure(pts[:, 1], 0.0), rw, c0), rw * dx * dx,
               normal=nrm, wall_dist=g.R - r_k)
    return ps


class ScourRecord:
    """The drive's control, the bed under and around the pipe, the transport through the
    section under it, the bed shear, and the velocity profiles of the second half of the run."""

    def __init__(self, cfg, g):
        self.cfg, self.g = cfg, g
        # driving: a body force g_x = u*^2 / h (uniform channel flow) plus feedback on the mean velocity
        self.g0 = g.ustar ** 2 / g.hw
        self.ctl = PIDrive(0.5, start=self.g0)
        self.stations = np.arange(0.5 * g.dx, g.Lx, g.dx)
        self.under = np.abs(self.stations - g.xc) < 0.5 * g.D
        self.rows, self.bed0 = [], None
        self.offsets = cfg["geometry"]["profile_offsets"]
        self.prof = {o: [] for o in self.offsets}

    def control(self, s):
        st = s.state(("v", "kind", "mat"))
        w = (st["kind"] == FLUID) & (st["mat"] == 0)
        e = self.g.U - float(st["v"][w, 0].mean())
        self.ctl.update(s, e, self.g0)

    def probe(self, st):
        g, dx, stations = self.g, self.g.dx, self.stations
        fl = st["kind"] == FLUID
        sedm = fl & (st["mat"] == 1)
        wat = fl & (st["mat"] == 0)
        u_mean = float(st["v"][wat, 0].mean())
        if g.hs <= 0:
            return float("nan"), float("nan"), float("nan"), u_mean, self.ctl.value
        b = surface_heights(st, stations, dx, g.h, mat=1)
        if self.bed0 is None:
            self.bed0 = b
        self.rows.append((st["t"],) + tuple(b))
        # scour depth: below the undisturbed bed as first measured (the median level, away from the dip)
        depth = float(np.median(self.bed0) - b[self.under].min()) / g.D
        # sediment flux through the section under the pipe: sum of V u_x over a band dx wide
        band = sedm & (np.abs(st["x"][:, 0] - g.xc) < 0.5 * dx)
        q = float((st["m"][band] / st["rho"][band] * st["v"][band, 0]).sum() / dx)
        phi = q / math.sqrt((g.rs / g.rw - 1) * G * g.d50 ** 3)
        # bed shear stress from the log law through the water velocity 1.5 dx above the bed
        tau = 0.0
        xw_, vw_ = st["x"][wat], st["v"][wat]
        col = np.clip(((xw_[:, 0]) / dx).astype(int), 0, len(stations) - 1)
        zrel = xw_[:, 1] - b[col]
        near = (zrel > dx) & (zrel < 2 * dx)
        if near.any():
            z = zrel[near]
            u = np.abs(vw_[near, 0])
            tau = float((g.rw * (KAPPA * u / np.log(z / g.z0)) ** 2).max())
        return depth, phi, tau, u_mean, self.ctl.value

    def on_profile_sample(self, st, t):
        g = self.g
        wat = (st["kind"] == FLUID) & (st["mat"] == 0)
        for o in self.offsets:
            xo = (g.xc + o * g.D) % g.Lx
            m = wat & (np.abs(st["x"][:, 0] - xo) < g.dx)
            self.prof[o].append((st["x"][m, 1], st["v"][m, 0]))

    def metrics(self, c):
        g = self.g
        out = dict(friction_velocity=g.ustar, shields_parameter=g.ustar ** 2 / ((g.rs / g.rw - 1) * G * g.d50),
                   mean_velocity_end=float(c["u_mean"][-1]), body_force_end=float(c["body_force"][-1]),
                   pipe_reynolds=g.U * g.D / 1e-6)
        if g.hs > 0:
            d = c["scour_depth_over_D"]
            out["scour_depth_over_D"] = float(d[-1])
            # the scour the flow added to the initial dip: S/D, smoothed over 0.5 s (a particle
            # row is 0.1 D and the bed gauge flickers by about half of that)
            t = c["t"]
            w = max(1, int(round(0.5 / max(t[1] - t[0], 1e-9)))) if len(t) > 1 else 1
            if len(d) < w:   # a run shorter than the window: no smoothing
                w = 1
            ds = np.convolve(d, np.ones(w) / w, mode="valid")
            out["initial_scour_depth_over_D"] = float(d[0])
            out["scour_depth_over_D_smoothed"] = float(ds[-1])
            grown = ds[-1] - d[0]
            k = np.nonzero(ds - d[0] >= 0.5 * grown)[0]
            # time (end of the 0.5 s window) when half the added depth was first reached
            out["time_to_half_depth"] = float(t[k[0] + w - 1]) if grown > 0 and len(k) else float("nan")
            out["max_transport_rate_phi"] = float(np.nanmax(c["transport_rate_phi"]))
            out["max_bed_shear_end"] = float(c["max_bed_shear"][-1])
        return out

    def finalize(self, out, metrics):
        if self.rows:
            write_csv(os.path.join(out, "scour_profile.csv"), ("t",) + tuple(f"x{x:.3f}" for x in self.stations),
                      self.rows)
            self.plot_scour(os.path.join(out, "scour_profile.png"))
        if any(self.prof.values()):
            self.velocity_profiles(out)

    def plot_scour(self, path):
        g, plt = self.g, pyplot()
        arr = np.array(self.rows)
        fig, ax = plt.subplots(figsize=(8, 3))
        for t in np.linspace(arr[0, 0], arr[-1, 0], 5):
            r = arr[np.argmin(np.abs(arr[:, 0] - t))]
            ax.plot((self.stations - g.xc) / g.D, (r[1:] - g.hs) / g.D, lw=0.9, label=f"t = {r[0]:.1f} s")
        ax.add_patch(plt.Circle((0, (g.yc - g.hs) / g.D), 0.5, color="0.5"))
        ax.set_aspect("equal")
        ax.set_xlabel("x / D")
        ax.set_ylabel("bed / D")
        ax.legend(fontsize=7)
        save(fig, path)

    def velocity_profiles(self, out):
        g, plt, offsets = self.g, pyplot(), self.offsets
        rows = []
        fig, axes = plt.subplots(1, len(offsets), figsize=(3 * len(offsets), 3.5), sharey=True, squeeze=False)
        for ax, o in zip(axes[0], offsets):
            ys = np.concatenate([p[0] for p in self.prof[o]])
            us = np.concatenate([p[1] for p in self.prof[o]])
            edges = np.arange(0.0, g.ytop + g.dx, g.dx)
            n, _ = np.histogram(ys, edges)
            su, _ = np.histogram(ys, edges, weights=us)
            with np.errstate(invalid="ignore"):
                um = su / n
            yc_ = 0.5 * (edges[1:] + edges[:-1])
            for y, u in zip(yc_, um):
                rows.append((o, y, u))
            ax.plot(um / g.U, (yc_ - (g.hs if g.hs > 0 else 0.0)) / g.D, "o-", ms=2)
            ax.set_title(f"x - x_pipe = {o:g} D", fontsize=9)
            ax.set_xlabel("time-averaged u / U")
        axes[0, 0].set_ylabel("y / D above the bed")
        save(fig, os.path.join(out, "velocity_profiles.png"))
        write_csv(os.path.join(out, "velocity_profiles.csv"), ("x_offset_over_D", "y", "u_mean"), rows)


def _streamlines(Lx, ytop, dx, xc, yc, R):
    def cb(st, t):
        d = os.path.join(st["out"], "stills")
        os.makedirs(d, exist_ok=True)
        streamlines_png(os.path.join(d, f"streamlines_t{t:.3f}.png"), st, (0.0, Lx), (0.0, ytop), dx,
                        f"streamlines of the water velocity, t = {t:.2f} s", (8, 8 * ytop / Lx + 0.6),
                        circle=(xc, yc, R))
    return cb


def main(argv=None):
    return run_scene(sys.modules[__name__], argv)


if __name__ == "__main__":
    sys.exit(main())
