"""Current-induced scour beneath a marine pipeline (paper 002, section 4.2; Mao 1986).

A pipe of diameter D lies on a sand bed in a current; the flow through the gap under the pipe
scours a tunnel (tunnel erosion), then a lee-wake hole forms. The current is periodic in x,
starts from the log law (eq. 32, kappa = 0.42), is held at its mean velocity by a driving
pressure gradient with feedback, and an inflow zone at the seam relaxes the water back to the log
law (the periodic seam would feed the pipe its own wake). The pipe is a ring of boundary
particles with the no-slip ghost velocity of eq. 39. The water is Newtonian with the SPS closure
of eq. 10.

sediment.model = "bedload" (the default; tisph/scenes/pipeline_scour/bedload.py): the sand is a bed
below particle scale (Shields threshold, bed load, Exner, avalanching; tisph/sediment) with its
shear from the near-bed flow through the log law, as grid models of this experiment do (Liang,
Cheng & Li 2005). scenes/pipeline_scour_mao.toml: Mao's D = 5 cm live-bed case against his
measured S/D(t) and profiles (tisph/validation/mao.py).

sediment.model = "particles" (scenes/pipeline_scour_two_phase.toml): paper 002's two-phase model,
sand particles with Cross rheology (eqs. 29-30), DEM contacts (eqs. 17-28) and fluid-sediment
drag (eq. 16); that file says why its contact diameter is 0.7 dx. It reaches S/D 0.19 in 20 s
from a dip of 0.10: the onset of scour, not tunnel erosion (1 cm particles of yield-stress sand
either do not move or creep as a layer).

Defaults: paper 002's theta = 0.065 case, D = 0.1 m, water 0.35 m deep, 0.4 m/s, d50 = 0.36 mm, a
periodic domain 10 D long, dx = D/10, an initial gap of 0.3 D over a sinusoidal dip 0.1 D deep
(the paper opens one "for numerical requirements"; a gap of one spacing holds no jet).
scenes/pipeline_scour_theta098.toml: 0.5 m/s (Shields 0.098). scenes/pipe_on_rigid_bed.toml:
D = 5 cm on a rigid bed, U = 0.197 m/s (Oner et al. 2008).
"""

from functools import partial

import numpy as np

from ...case import Scene, make_case, resolves
from ...constants import G
from ...particles import FLUID, WALL, ParticleSet, block, density_from_pressure, layered_pressure, tait_B
from ...runner import common_params, run_scene, sound_speed
from ...sediment import keys as sediment_keys
from ...settings.config import ConfigError, physics_from_config
from ...settings.schema import NON_NEGATIVE, POSITIVE, K, with_defaults
from ...settings.schemes import numerics
from ...settings.shared_keys import TURBULENCE
from ...validation import mao
from ...viz.render import SAND
from .bedload import bed_stations, build_bedload, far_field
from .common import NAME, add_pipe, friction_velocity, geometry, has_bedload, initial_bed, log_law, profile_time, ring  # noqa: F401
from .record import ScourRecord, streamlines_event


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
        ps.add(xs, FLUID, 1, density_from_pressure(pressure(xs[:, 1], initial_bed(g, xs[:, 0])), rs, c0), rs * dx * dx)
    floor = block(0.0, -L * dx, g.Lx, 0.0, dx)
    ps.add(
        floor,
        WALL,
        0,
        density_from_pressure(pressure(floor[:, 1], hs), rw, c0),
        rw * dx * dx,
        normal=(0.0, 1.0),
        wall_dist=-floor[:, 1],
    )
    add_pipe(ps, g, lambda y: density_from_pressure(pressure(y, 0.0), rw, c0))
    return ps


class PipelineScour(Scene):
    """Current-induced scour beneath a marine pipeline (paper 002, section 4.2; Mao 1986)."""

    NAME = NAME

    SCHEMA = {
        "run": {
            "end_time": K(
                40.0,
                "40 s of flow with morfac 10: the bed moves as in 6.7 min (the paper's Fig. 10 ends at 6.5 min)",
                "s",
            )
        },
        # Wendland kernel (paper 002 eq. 6), laminar viscosity + SPS (eq. 10), Shepard every 200 steps
        # is an option (shepard_every = 200); density diffusion is the default
        # c0 = 18 m/s: Table 3's c_0m
        "numerics": dict(TURBULENCE, **numerics("paper002", dx=0.01, c0=18.0)),
        "geometry": {
            "pipe_diameter": K(0.1, "D", "m", range=POSITIVE),
            "water_depth": K(0.35, "above the undisturbed bed", "m", range=POSITIVE),
            "sand_depth": K(0.15, "0: the pipe lies on a rigid bed (flow-only validation)", range=NON_NEGATIVE),
            "length": K(1.0, "periodic length, 10 D", range=POSITIVE),
            "gap": K(0.03, "initial gap under the pipe", "m", range=NON_NEGATIVE),
            "perturbation": K(0.01, "depth of the sinusoidal bed dip under the pipe", "m", range=NON_NEGATIVE),
            "mean_velocity": K(0.4, "held by the body-force feedback", "m/s", range=POSITIVE),
            "shields": K(
                0.065,
                "Shields number of the current (Mao's 0.065): sets u* = sqrt(theta (s-1) g d50), and the log law's z0 follows from the mean velocity (1.5e-6 m: a hydraulically smooth bed). 0: z0 = 2.5 d50 / 30 (Nikuradse) instead, and u* from the mean velocity.",
                range=NON_NEGATIVE,
            ),
            "grain_diameter": K(0.00036, "d50", "m", range=POSITIVE),
            "porosity": K(
                0.4, "the sand particles' porosity (the two-phase model's drag)", range=(0.0, 1.0, True, False)
            ),
            "drag_coefficient": K(0.4, "Table 3", range=NON_NEGATIVE),
            "sps": K(True, "SPS turbulence (paper 002 eq. 10)"),
            "inflow_length": K(
                0.2,
                "The periodic seam recirculates the pipe's wake; at dx = D/10 the SPS closure mixes far too little to rebuild the near-bed flow in 10 D, and the water under the pipe's level stalls within seconds (measured: near-bed velocity 0.19 -> 0 m/s by t = 5 s). A zone this long (m) at x = 0 relaxes the water to the log law, as the paper's inlet does.",
                range=NON_NEGATIVE,
            ),
            "inflow_rate": K(
                20.0, "the inflow zone's relaxation rate (1/s); a particle crosses it in ~0.5 s", range=NON_NEGATIVE
            ),
            "profile_offsets": K([-2.0, 0.0, 2.0], "velocity profiles at x = x_pipe + offset * D"),
            "reference": K(
                "none", "mao: compare with Mao's S/D(t) and profiles (bedload; D = 5 cm)", choices=("none", "mao")
            ),
            "initial_profile": K(
                "none",
                "none: the flat bed with its dip | mao_11s, mao_18s, mao_25s: the bed starts as Mao's measured profile at that time (scaled to the pipe's D; in place of the dip), and his clock starts there; held still (sediment.morph_start beyond the run), it asks whether the flow erodes his bed where his did (python -m tisph.bench --mao-held)",
                choices=("none", "mao_11s", "mao_18s", "mao_25s"),
            ),
        },
        # DEM contacts between sand particles, paper 002 Table 3 (its eta_s unit "N/m" is N s/m)
        "dem": {
            "enabled": K(True, "DEM contacts between sand particles (the two-phase model)"),
            "kn": K(1000000.0, "normal spring stiffness (N/m)", range=POSITIVE),
            "ks": K(100000.0, "tangential spring stiffness (N/m)", range=POSITIVE),
            "eta_n": K(20.0, "normal damping (N s/m)", range=NON_NEGATIVE),
            "eta_s": K(40.0, "tangential damping (N s/m)", range=NON_NEGATIVE),
            "friction": K(0.57, "Coulomb friction coefficient", range=POSITIVE),
            "contact_diameter": K(
                0.7,
                "in particle spacings; see the module docstring for why 0.7 and not 1",
                range=(0.0, 1.5, False, True),
            ),
        },
        # sediment.model = "bedload": the bed below particle scale (tisph/sediment); its shear by the
        # log law through the near-bed velocity 3 dx above the bed (1.5 dx sits in the wall's no-slip
        # layer) with the current's own z0, scaled to rho u*^2 in the far field (BedCoupler says why);
        # the gap jet's sand settles out 3 D on: deposition_length 3 D (scenes/pipeline_scour_mao.toml);
        # the slope enters once, through the threshold (gravity_coefficient 0: in Mao's case the
        # downslope term on top held the hole at 0.33 D, measured; scenes/pipeline_scour_mao.toml)
        "sediment": with_defaults(
            sediment_keys.SEDIMENT,
            model="bedload",
            grain_density=2650.0,
            shear="log_far_field",
            reference_height=3.0,
            filter_time=0.1,
            update_every=10,
            deposition_length=0.3,
            morph_start=0.5,
            morfac=10.0,
            gravity_coefficient=0.0,
        ),
        "materials": {
            "water": {"rho0": 1000.0, "viscosity": 1.0e-3},
            "sand": {
                "rho0": 1950.0,
                "viscosity": 0.07,
                "rheology": K(
                    "cross",
                    "Cross (paper 002 eqs. 29-30): mu_inf = 0.07 Pa s, tau_B = 25 Pa read as "
                    "mu0 = 1000 mu_inf, K = mu0 / tau_B",
                ),
                "mu0": 70.0,  # Cross: the viscosity at rest (Pa s)
                "K": 2.8,  # Cross: the time constant (s) of mu = mu_inf + (mu0 - mu_inf) / (1 + (K gamma)^m1)
                "m1": 1.0,  # Cross: the exponent m1
                "mu_max": 0.0,
            },
        },
        "output": {"frame_interval": 0.05, "probe_interval": 0.05, "width": 960},
    }

    def check(self, cfg):
        g, dx = cfg.geometry, cfg.numerics.dx
        D = g.pipe_diameter
        resolves(D, 8, "the pipe", dx)
        if g.length < 5 * D:
            raise ConfigError("geometry.length", g.length, f"at least 5 pipe diameters ({5 * D:g} m)")
        if g.water_depth < D + g.gap + 4 * dx:
            raise ConfigError(
                "geometry.water_depth",
                g.water_depth,
                f"at least pipe_diameter + gap + 4 dx ({D + g.gap + 4 * dx:.3g} m)",
            )
        if g.inflow_length > 0.5 * g.length - 2 * D:
            raise ConfigError(
                "geometry.inflow_length",
                g.inflow_length,
                f"at most half the length minus 2 D ({0.5 * g.length - 2 * D:.3g} m): the zone must end 2 D before the pipe",
            )
        if cfg.sediment.suspended and not has_bedload(cfg):
            raise ConfigError(
                "sediment.suspended",
                True,
                "false unless sediment.model = \"bedload\" over sand "
                "(geometry.sand_depth > 0): the suspension is exchanged with the bed-load bed",
            )
        if has_bedload(cfg):
            gm = geometry(cfg)
            far_field(gm, bed_stations(gm), g.inflow_length)
        if 0 < g.sand_depth < 4 * dx:
            raise ConfigError("geometry.sand_depth", g.sand_depth, f"0 (rigid bed) or at least 4 dx ({4 * dx:g} m)")
        if g.initial_profile != "none":
            tp = profile_time(g)
            deepest = -float(mao.profile_bed(tp, mao.PROFILES[tp][:, 0] * D / mao.D, D).min())  # below the bed
            need = deepest + 4 * dx
            if g.sand_depth < need:
                raise ConfigError(
                    "geometry.initial_profile",
                    g.initial_profile,
                    f"'none' unless geometry.sand_depth "
                    f"is at least {need:.4g} m (the profile's deepest point and 4 dx under it; here "
                    f"{g.sand_depth:g} m)",
                )
        if g.perturbation > 0.5 * g.sand_depth:
            raise ConfigError("geometry.perturbation", g.perturbation, "at most half the sand depth")

    def build(self, cfg):
        if has_bedload(cfg):
            return build_bedload(cfg)
        geo = cfg.geometry
        g = geometry(cfg)
        dx, hs, L, mats = g.dx, g.hs, g.L, cfg.materials
        c0, u_max = sound_speed(cfg, 2.5 * g.U)  # the gap jet runs at up to about twice U
        ps = _particles(g, c0)
        dem = cfg.dem
        use_dem = dem.enabled and hs > 0
        materials = [
            dict(dict(mats[n]), name=n, B=tait_B(mats[n]["rho0"], c0), dem=(n == "sand" and use_dem))
            for n in ("water", "sand")
        ]
        params = common_params(cfg, c0, G, depth=g.ytop)
        if use_dem:  # the contact step (eq. 27) is the DEM module's default
            params.update(
                kn=dem.kn, ks=dem.ks, eta_n=dem.eta_n, eta_s=dem.eta_s, mu_c=dem.friction, dc=dem.contact_diameter * dx
            )
        params["drag_K"] = 0.75 * (1 - geo.porosity) * g.rw * geo.drag_coefficient / g.d50
        pad = 4 * g.h
        domain = ((0.0, -L * dx - pad), (g.Lx, 2.0 * g.ytop + pad))
        used = ["water"] + (["sand"] if hs > 0 else [])
        physics = physics_from_config(
            cfg,
            periodic_x=True,
            noslip=True,
            materials_used=used,
            sps=geo.sps,
            drag=hs > 0 and geo.drag_coefficient > 0,
            dem=use_dem,
            inflow=(0.0, geo.inflow_length, geo.inflow_rate, 0, max(hs, 0.0), g.ustar, g.z0)
            if geo.inflow_length > 0 and geo.inflow_rate > 0
            else (),
        )
        rec = ScourRecord(cfg, g)
        params["held_current"] = rec  # the drive's feedback: the device's on a GPU (engine/drive.py)
        t_end = cfg.run.end_time
        events = [(t, rec.on_profile_sample) for t in np.arange(0.5 * t_end, t_end + 1e-9, 0.05)]
        stills_at = (0.0, 0.5 * t_end, t_end)
        if cfg.output.render:
            events += [(t, streamlines_event(g)) for t in stills_at]
        return make_case(
            name=self.NAME,
            particles=ps,
            materials=materials,
            domain=domain,
            params=params,
            physics=physics,
            view=((0.0, -L * dx), (g.Lx, g.ytop + 2 * dx)),
            u_max=u_max,
            probe_columns=("scour_depth_over_D", "transport_rate_phi", "max_bed_shear", "u_mean", "body_force"),
            probe=rec.probe,
            metrics=rec.metrics,
            finalize=rec.finalize,
            events=sorted(events, key=lambda e: e[0]),
            stills=stills_at,
            container=(-1e9, -0.5 * dx, 1e9, float("inf")),
            render_modes=("phase", "pressure"),
            mat_colors=(None, SAND),
            control=rec.update,
            persist=(rec,),
            pressure_scale=g.rw * G * g.ytop + (g.rs - g.rw) * G * hs,
        )


SCENE = PipelineScour()
main = partial(run_scene, SCENE)
