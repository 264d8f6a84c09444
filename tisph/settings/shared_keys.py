"""The keys every scene shares ([run], [numerics], [output]), the turbulence closure's (only the
pipeline has them), and the keys of any material, whatever its name: each a Key (tisph/settings/schema.py).
A scene's SCHEMA lays its own tables and defaults on these; the engine's runtime parameters
(tisph/settings/engine_keys.py) are Keys of their own, placed here by their config key."""

import math

from ..errors import ConfigError
from .engine_keys import KEYED
from .schema import NON_NEGATIVE, POSITIVE, K
from .schemes import DEFAULT, SCHEMES

_S = SCHEMES[DEFAULT]  # a key the numerics scheme sets: the default scheme's value, its one default

SHARED = {
    "run": {
        "end_time": K(1.0, "the simulated time at which the run ends", "s", POSITIVE),
        "max_steps": K(0, "0: no limit", range=(0, None, True, True)),
        "arch": K("cpu", "the Taichi backend", choices=("cpu", "gpu", "auto")),
        "precision": K("f32", "the fields' floating point", choices=("f32", "f64")),
        "pair_once": K(
            "auto",
            "each pair once on the CPU, where the pair loop does not run in its vector lanes (a support under "
            "2.55 dx): auto (where the run is long enough to repay its compile) | on | off",
            choices=("auto", "on", "off"),
        ),
        "perturbation": K(
            0.0,
            "each fluid particle displaced at the start by up to this fraction of dx, at random (run.seed); "
            "0: none. --seeds N sets 0.001 on a case with no random bed: how far round-off-sized noise moves it",
            range=(0.0, 0.1, True, True),
        ),
        "seed": K(1, "the random seed of run.perturbation", range=(0, None, True, True)),
    },
    "numerics": {
        "dx": K(0.03, "initial particle spacing", "m", POSITIVE),
        "scheme": K(
            DEFAULT,
            "the numerics scheme (tisph/settings/schemes.py): default (waves, sloshing, impacts) | paper000 "
            "(paper 000's Table 2) | paper002 (paper 002) | bed (the sand bed's calibration); named in a "
            "case file, it sets every numerics key the file leaves unset",
            choices=tuple(SCHEMES),
        ),
        "h_factor": K(_S["h_factor"], "smoothing length h = h_factor * dx", range=(1.0, 3.0, True, True)),
        "kernel": K(
            _S["kernel"], "cubic (paper 000 eq. 5) | wendland (paper 002 eq. 6)", choices=("cubic", "wendland")
        ),
        "wall": K(
            _S["wall"],
            "dynamic (DBC) | repulsive (paper 000 eq. 6) | adami (pressure from the water, Adami et al. 2012)",
            choices=("dynamic", "repulsive", "adami"),
        ),
        "wall_layers": K(
            _S["wall_layers"], "layers of wall particles (dynamic and extrapolated walls)", range=(1, 6, True, True)
        ),
        "wall_strength": K(
            0.0,
            "D of the Lennard-Jones force (m^2/s^2): repulsive walls', and the extrapolated "
            "walls' backstop at 0.75 dx; 0: auto = 5 g H (Monaghan 1994)",
            range=NON_NEGATIVE,
        ),
        "c0": K(0.0, "sound speed (m/s); 0: auto = c0_factor * u_max", range=NON_NEGATIVE),
        "c0_factor": K(
            10.0, "c0 = this x max(expected speed, sqrt(g depth)) when c0 = 0", range=(1.0, None, True, True)
        ),
        "u_max": K(0.0, "expected peak flow speed (m/s); 0: the scene's estimate", range=NON_NEGATIVE),
        "laminar_viscosity": K(_S["laminar_viscosity"], "paper 002 eq. 10 with the materials' viscosity"),
        "density_diffusion": K(
            _S["density_diffusion"],
            "none | molteni | fourtakas | antuono (renormalised gradients: waves)",
            choices=("none", "molteni", "fourtakas", "antuono"),
        ),
        "time_stepping": K(
            _S["time_stepping"],
            "single: every term every step | dual: the viscous and diffusive terms at "
            "the advection criterion, held over the acoustic steps inside it (Zhang et al. 2020)",
            choices=("single", "dual"),
        ),
        "shepard_every": K(
            0, "Shepard density filter every N steps (paper 002 eq. 14); 0 off", range=(0, None, True, True)
        ),
        **{
            k.split(".")[1]: p
            for k, p in KEYED.items()
            if k.startswith("numerics.") and k not in ("numerics.mixing_length", "numerics.stress_limiter")
        },
    },
    "output": {
        "dir": K("", '"" -> renders/<scene>'),
        "render": K(True, "PNG frames and the MP4 (false: neither)"),
        "fps": K(25, "movie playback frames per second", range=(1, 240, True, True)),
        "frame_interval": K(0.02, "simulated seconds between frames", range=POSITIVE),
        "probe_interval": K(0.005, "simulated seconds between probe samples", range=POSITIVE),
        "width": K(640, "frame width in pixels (height follows the domain)", range=(64, 4096, True, True)),
        "quiet": K(False, "no progress bar or progress lines"),
        "speed_scale": K(0.0, "colour bar top (m/s); 0: the scene's expected peak speed", range=NON_NEGATIVE),
        "view": K([], "[x0, x1, y0, y1] (m) the frames show; []: the scene's"),
        "field": K(
            "",
            'speed | pressure | density | material | vorticity; "": the scene\'s panels',
            choices=("", "speed", "pressure", "density", "material", "vorticity", "concentration"),
        ),
        "range": K([], "[lo, hi] of the colour bar in its unit (kPa for pressure); []: automatic"),
        "zoom": K([], "[x0, x1, y0, y1] (m): a window at true scale under the frame, by vorticity; []: the scene's"),
        "exaggeration": K(
            1.0,
            "heights drawn this many times the lengths' scale, said in each frame's title "
            "(a long flume's waves; the zoom window stays at true scale)",
            range=(1.0, 100.0, True, True),
        ),
        "min_height": K(160, "a lower panel gets more room above the view (air)", "px", (0, 4096, True, True)),
        "snapshot_every": K(
            -1.0,
            "simulated s between HDF5 snapshots; -1: about 50 per run, on frame times; 0: off",
            range=(-1.0, None, True, True),
        ),
        "checkpoint_every": K(0.0, "simulated s between checkpoints; 0: only on SIGINT/SIGTERM", range=NON_NEGATIVE),
        "live": K(False, "show each frame in a window as it is rendered (--live; needs a display)"),
    },
}


# The turbulence closure's keys: only a scene with SPS turbulence (the pipeline) has them, in its
# SCHEMA's [numerics]; elsewhere they are refused by name.
TURBULENCE = {
    "turbulence": K(
        "smagorinsky",
        "smagorinsky (paper 002 eq. 10) | k_equation (transported k, tisph/terms/tke.py); where SPS is on",
        choices=("smagorinsky", "k_equation"),
    ),
    "length_scale": K(
        "prescribed",
        "the k equation's length: prescribed (the scene's wall distance) | omega (transported, bounded by it)",
        choices=("prescribed", "omega"),
    ),
    "mixing_length": KEYED["numerics.mixing_length"],
    "stress_limiter": KEYED["numerics.stress_limiter"],
}

# The keys of every material, whatever its name (materials.water.rho0, materials.sand.rho0, ...):
# the words, unit and range or choices; the defaults are the scene's.
MATERIAL = {
    "rho0": K(None, "rest density", "kg/m3", POSITIVE),
    "viscosity": K(None, "dynamic viscosity (Pa s; a Bingham material's plastic viscosity mu_B)", range=NON_NEGATIVE),
    "rheology": K(
        None,
        "newtonian | bingham (paper 000 eqs. 13-14) | cross (paper 002 eqs. 29-30)",
        choices=("newtonian", "bingham", "cross"),
    ),
    "yield_stress": K(None, "tau_B", "Pa", NON_NEGATIVE),
    "regularisation": K(
        None, "Papanastasiou exponent m (s): mu = mu_B + tau_B (1 - exp(-m gamma)) / gamma", range=POSITIVE
    ),
    "mu_max": K(
        None,
        "cap on the effective viscosity (Pa s); 0: where its explicit step meets the acoustic one",
        range=NON_NEGATIVE,
    ),
    "unyielded": K(
        None,
        'an unyielded Bingham material: "creep" at stress / mu_max, or "rest" (a rigid plug on a fixed bed)',
        choices=("creep", "rest"),
    ),
    "mu0": K(None, "Cross: the viscosity at rest", "Pa s", NON_NEGATIVE),
    "K": K(
        None, "Cross: the time constant (s) of mu = mu_inf + (mu0 - mu_inf) / (1 + (K gamma)^m1)", range=NON_NEGATIVE
    ),
    "m1": K(None, "Cross: the exponent m1", range=POSITIVE),
}


# ---- rules that join keys, beside them: each a check of the resolved config and the case's
# compiled physics that raises a ConfigError naming the key to change
def _wall_layers_fill_the_support(cfg, physics, particles):
    """Dynamic wall particles must fill the kernel's support (2 h) behind the wall, or a fluid
    particle there sums a truncated kernel (the kernel's rule, not a measured fix: Mao's case at
    1.6 dx gave the same profiles with 3 and 4 layers); repulsive walls (paper 000 eq. 6) are one
    line of particles."""
    num = cfg.numerics
    need = math.ceil(2.0 * num.h_factor - 1e-9)
    if physics.wall in ("dynamic", "adami") and num.wall_layers < need:
        raise ConfigError(
            "numerics.wall_layers",
            num.wall_layers,
            f"at least {need} with numerics.h_factor = {num.h_factor}",
            f"dynamic wall particles must fill the kernel's support 2 h = {2.0 * num.h_factor:g} dx",
        )


def _turbulence_needs_sps(cfg, physics, particles):
    """The SPS's mixing length and the k equation need SPS turbulence on; the k equation needs a
    length, the scene's wall distance or the mixing length."""
    num = cfg.numerics
    lm = num.get("mixing_length", 0.0)
    if lm > 0 and not physics.sps:
        raise ConfigError(
            "numerics.mixing_length",
            lm,
            "0 in a case without SPS turbulence (the mixing length "
            "sets the SPS's eddy viscosity; the pipeline turns SPS on with geometry.sps = true)",
        )
    turb = num.get("turbulence", "smagorinsky")
    if turb == "k_equation":
        if not physics.sps:
            raise ConfigError(
                "numerics.turbulence",
                turb,
                "smagorinsky in a case without SPS turbulence (the "
                "k equation gives the SPS's eddy viscosity; the pipeline turns SPS on with geometry.sps = true)",
            )
        if getattr(particles, "turbulence_length", None) is None and lm <= 0:
            raise ConfigError(
                "numerics.mixing_length",
                lm,
                "> 0 with numerics.turbulence = \"k_equation\" in this "
                "scene: it sets no wall distance, so the k equation's length l is this constant",
            )


def _k_options_need_the_k_equation(cfg, physics, particles):
    """The k equation's own options are off without it."""
    num = cfg.numerics
    for name, off, what in (
        ("length_scale", "prescribed", "omega is the k equation's length"),
        ("stress_limiter", 0.0, "the limiter caps the k equation's eddy viscosity"),
    ):
        if num.get(name, off) != off and physics.turbulence != "k_equation":
            raise ConfigError(
                f"numerics.{name}",
                num[name],
                f"{off!r} without the k equation ({what}; it needs "
                "numerics.turbulence = \"k_equation\" and SPS turbulence on)",
            )


def _concentration_needs_suspension(cfg, physics, particles):
    if cfg.output.field == "concentration" and not physics.suspension:
        raise ConfigError(
            "output.field",
            "concentration",
            "a field this case has: concentration needs suspended "
            "sand (sediment.suspended = true, the pipeline over the bed-load bed)",
        )


RULES = (
    _wall_layers_fill_the_support,
    _turbulence_needs_sps,
    _k_options_need_the_k_equation,
    _concentration_needs_suspension,
)


def check_rules(cfg, physics, particles):
    """Every rule that joins keys, against the resolved config and the case built from it."""
    for rule in RULES:
        rule(cfg, physics, particles)
