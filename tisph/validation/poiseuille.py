"""Plane Poiseuille flow of a Newtonian or Bingham fluid: an exact check of the viscous and
rheology terms. `python -m tisph.validation.poiseuille [--tau-y PA] [--dx M] [--out DIR]`.

Channel walls at y = +-b, periodic in x, driven by a pressure gradient G (a body force G/rho).
Steady state (Bird, Stewart & Lightfoot; Chhabra & Richardson for the Bingham plug): with
tau_y < G b a plug of half-width y0 = tau_y / G moves at u_p = G (b - y0)^2 / (2 mu_p); outside it
u(y) = G (b^2 - y^2) / (2 mu_p) - tau_y (b - |y|) / mu_p. tau_y = 0 is the Newtonian parabola.
"""

import copy
import os
import sys
from functools import partial

import numpy as np

from ..case import Scene, make_case, resolves
from ..particles import FLUID, WALL, ParticleSet, block, tait_B
from ..profiles import plot_profiles, write_profile
from ..runner import common_params, run_scene, sound_speed
from ..settings.config import ConfigError, physics_from_config
from ..settings.schema import POSITIVE, K
from ..settings.schemes import numerics


def exact(y, G, b, mu_p, tau_y=0.0):
    """Steady velocity u(y) for |y| <= b."""
    y = np.abs(np.asarray(y, float))
    y0 = min(tau_y / G, b) if G > 0 else b
    u = G * (b * b - y * y) / (2 * mu_p) - tau_y * (b - y) / mu_p
    up = G * (b - y0) ** 2 / (2 * mu_p)
    return np.where(y <= y0, up, u)


def fit_plug(y, u, G, b, mu_p):
    """Plug half-width y0 that best fits a measured profile (least squares over y0 in [0, b))."""
    cands = np.linspace(0.0, 0.95 * b, 951)
    err = [np.sum((exact(y, G, b, mu_p, G * y0) - u) ** 2) for y0 in cands]
    return float(cands[int(np.argmin(err))])


def profile_metrics(cols, result, G, b, mu, tau, y0_exact):
    """The last velocity profile against the exact one: its L2 error, the plug's half width and
    the peak speed beside the exact values."""
    y, u = result["y"], result["u"]
    ue = exact(y, G, b, mu, tau)
    l2 = float(np.sqrt(np.nansum((u - ue) ** 2) / np.sum(ue**2)))
    y0 = fit_plug(y, np.nan_to_num(u), G, b, mu)
    return dict(
        velocity_l2_error=l2,
        plug_half_width=y0,
        plug_half_width_exact=y0_exact,
        plug_width_error=abs(y0 - y0_exact) / b,
        u_max=float(np.nanmax(u)),
        u_max_exact=float(exact(0.0, G, b, mu, tau)),
    )


def write_profile_figure(out, metrics, result, G, b, mu, tau, dx):
    """profile.csv and profile.png: the SPH profile over the exact one."""
    y, u = result["y"], result["u"]
    write_profile(os.path.join(out, "profile.csv"), y, u, exact(y, G, b, mu, tau), names=("y", "u_sph", "u_exact"))
    yf = np.linspace(-b, b, 400)
    label = f"tau_y = {tau:g} Pa, dx = {dx:g} m: L2 error {metrics['velocity_l2_error']:.3%}"
    plot_profiles(
        os.path.join(out, "profile.png"),
        [(label, y, u, yf, exact(yf, G, b, mu, tau))],
        "y (m)",
        "u (m/s)",
        "plane Poiseuille flow: tisph against the exact solution",
    )


class Poiseuille(Scene):
    """Plane Poiseuille flow, Newtonian or Bingham: an exact check of the viscous and rheology terms."""

    NAME = "poiseuille"

    # where the scene departs from its scheme (tisph/settings/schemes.py), and why
    DEPARTS = {
        "density_diffusion": "Molteni's term: a periodic channel without gravity has no hydrostatic part to remove"
    }

    SCHEMA = {
        "run": {
            "end_time": K(
                5.0, "five times the slowest viscous decay time 4 b^2 / (pi^2 nu) = 1 s: steady to 0.7 %", "s"
            )
        },
        "numerics": numerics("paper002", dx=0.005, density_diffusion="molteni"),
        "geometry": {
            "half_width": K(0.05, "b, the channel's half width", "m", POSITIVE),
            "length": K(0.04, "periodic length", "m", POSITIVE),
            "pressure_gradient": K(1000.0, "G, the driving pressure gradient", "Pa/m", POSITIVE),
        },
        "materials": {
            "fluid": {
                "rho0": 1000.0,
                "viscosity": 1.0,
                "rheology": "bingham",
                "yield_stress": 10.0,
                "regularisation": 100.0,
                # in the plug the stress is below tau_y, so the shear rate there is <= tau_y / mu_max
                "mu_max": K(
                    25.0,
                    "bounds the plug's viscosity (25 x mu_p) so the viscous time step stays at the CFL "
                    "step (Pa s; > 0 here)",
                    range=POSITIVE,
                ),
            }
        },
        "output": {"frame_interval": 0.25, "probe_interval": 0.05, "render": False, "snapshot_every": 0.0},
    }

    def check(self, cfg):
        g, dx = cfg.geometry, cfg.numerics.dx
        f = cfg.materials.fluid
        resolves(2 * g.half_width, 8, "the channel", dx)
        if f.yield_stress >= g.pressure_gradient * g.half_width:
            raise ConfigError(
                "materials.fluid.yield_stress",
                f.yield_stress,
                f"below G b = {g.pressure_gradient * g.half_width:g} Pa (else nothing flows)",
            )
        h = cfg.numerics.h_factor * dx
        if g.length < 5 * h:
            raise ConfigError(
                "geometry.length", g.length, f"at least 5 h = {5 * h:g} m (five cells of the periodic grid)"
            )

    def build(self, cfg):
        geo, num = cfg.geometry, cfg.numerics
        f = dict(cfg.materials.fluid)
        dx, b, L, G = num.dx, geo.half_width, geo.length, geo.pressure_gradient
        rho0, mu = f["rho0"], f["viscosity"]
        tau = f["yield_stress"] if f["rheology"] == "bingham" else 0.0
        # Cross with the Bingham reading of paper 002: mu_inf = mu_B, mu0 = 1000 mu_B, K = mu0 / tau_B
        if f["rheology"] == "cross":
            f.setdefault("mu0", 1000.0 * mu)
            f.setdefault("K", f["mu0"] / max(f.get("yield_stress", 1e-30), 1e-30))
        u_peak = G * b * b / (2 * mu)
        c0, u_max = sound_speed(cfg, u_peak)
        # an exact period: round the length to whole particle columns
        nxp = max(1, int(round(L / dx)))
        L = nxp * dx
        ps = ParticleSet()
        fluid = block(0.0, 0.0, L, 2 * b, dx)
        ps.add(fluid, FLUID, 0, rho0, rho0 * dx * dx)
        T = num.wall_layers * dx
        low, high = block(0.0, -T, L, 0.0, dx), block(0.0, 2 * b, L, 2 * b + T, dx)
        ps.add(low, WALL, 0, rho0, rho0 * dx * dx, normal=(0.0, 1.0), wall_dist=-low[:, 1])
        ps.add(high, WALL, 0, rho0, rho0 * dx * dx, normal=(0.0, -1.0), wall_dist=high[:, 1] - 2 * b)
        params = common_params(cfg, c0, 0.0, depth=2 * b)
        params["g"] = (G / rho0, 0.0)
        mat = dict(
            name="fluid",
            rho0=rho0,
            viscosity=mu,
            B=tait_B(rho0, c0),
            rheology=f["rheology"],
            yield_stress=f["yield_stress"],
            regularisation=f["regularisation"],
            mu_max=f["mu_max"],
        )
        for k in ("mu0", "K"):
            if k in f:
                mat[k] = f[k]
        domain = ((0.0, -T - 4 * dx), (L, 2 * b + T + 4 * dx))
        y0_exact = tau / G

        def profile(st):
            fl = st["kind"] == FLUID
            y = st["x"][fl, 1] - b
            edges = np.linspace(-b, b, int(round(2 * b / dx)) + 1)
            idx = np.clip(np.digitize(y, edges) - 1, 0, len(edges) - 2)
            u = np.array(
                [st["v"][fl, 0][idx == k].mean() if np.any(idx == k) else np.nan for k in range(len(edges) - 1)]
            )
            return 0.5 * (edges[1:] + edges[:-1]), u

        result = {}

        def probe(st):
            yc, u = profile(st)
            result["y"], result["u"] = yc, u
            return (float(np.nanmax(u)),)

        return make_case(
            name=self.NAME,
            particles=ps,
            materials=[mat],
            domain=domain,
            params=params,
            physics=physics_from_config(cfg, periodic_x=True, noslip=True),
            view=((0, -T), (L, 2 * b + T)),
            u_max=u_max,
            probe_columns=("u_max",),
            probe=probe,
            metrics=partial(profile_metrics, result=result, G=G, b=b, mu=mu, tau=tau, y0_exact=y0_exact),
            finalize=partial(write_profile_figure, result=result, G=G, b=b, mu=mu, tau=tau, dx=dx),
        )


SCENE = Poiseuille()


def main(argv=None):
    """Adds --tau-y (and --rheology) to the shared flags."""
    argv = list(sys.argv[1:] if argv is None else argv)
    extra = []
    for flag, key in (("--tau-y", "yield_stress"), ("--rheology", "rheology")):
        if flag in argv:
            i = argv.index(flag)
            if i + 1 >= len(argv):
                print(f"python -m tisph.validation.poiseuille: error: {flag} needs a value", file=sys.stderr)
                return 2
            extra.append((key, argv[i + 1]))
            del argv[i : i + 2]
    scene = SCENE
    if extra:
        d = copy.deepcopy(SCENE.DEFAULTS)
        for key, val in extra:
            try:
                d["materials"]["fluid"][key] = float(val) if key == "yield_stress" else val
            except ValueError:
                print(f"python -m tisph.validation.poiseuille: error: {key} = {val!r} is not a number", file=sys.stderr)
                return 2
        scene = copy.copy(SCENE)
        scene.DEFAULTS = d  # this run's defaults: the flags' material
    return run_scene(scene, argv)


if __name__ == "__main__":
    sys.exit(main())
