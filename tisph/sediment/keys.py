"""The [sediment] table: its keys, defaults, ranges and choices; the one set of bed parameters
for sand under waves (WAVE_RIPPLES); the refusal of bed-load keys where the sand is particles.
The bed they drive is coupling.py's."""

from ..settings.config import ConfigError, raise_collected
from ..settings.schema import K, choices, ranges, values

SEDIMENT = {
    "model": K(
        "particles",
        "particles: the paper's Bingham/Cross sand | bedload: a bed below particle scale",
        choices=('particles', 'bedload'),
    ),
    "porosity": K(0.4, "n in Exner's (1 - n) dz_b/dt = -dq/dx", range=(0.0, 0.9, True, True)),
    "repose_angle": K(
        32.0, 'angle of repose (degrees): avalanching, slope-corrected threshold', range=(5.0, 60.0, True, True)
    ),
    "shields_critical": K(
        0.0, 'critical Shields number; 0: Soulsby & Whitehouse (1997) for d50', range=(0.0, 1.0, True, True)
    ),
    "formula": K("mpm", 'mpm: Meyer-Peter & Mueller | nielsen: Nielsen (1992), for waves', choices=('mpm', 'nielsen')),
    "saturation_length": K(0.0, 'l_s of l_s dq/dx + q = q_b (m); 0: one dx', range=(0.0, None, True, True)),
    "deposition_length": K(
        0.0, 'l_s where the load settles out (q > q_b), m; 0: saturation_length', range=(0.0, None, True, True)
    ),
    "lee_transit": K(
        False,
        "a current's load beyond the capacity crosses a reversed near-bed zone (a separation bubble) with the outer flow and settles over the deposition length, instead of stopping where the near-bed flow turns (Bed.saturate_transit); the pipeline's lee",
    ),
    "settling_delay": K(
        False,
        'with lee_transit: that load first settles down through the water, then out onto the bed: two stages of l_d / 2 each (deposition peaks l_d / 2 downstream of where it starts, not there)',
    ),
    "gravity_coefficient": K(
        1.0,
        "K_g of the downslope term K_g |q_b| (dz/dx) / tan(phi) (Bailard 1981; 1/tan(phi) = CMS's 1.6); 0: the slope acts through the threshold alone (REEF3D's bedload_MPM, CMS's Dey option)",
        range=(0.0, 10.0, True, True),
    ),
    "morfac": K(1.0, 'morphological acceleration: the bed moves morfac times as fast', range=(1.0, 1000.0, True, True)),
    "shear": K(
        "waves",
        "waves: Swart's friction factor | log: the log law (currents) | log_far_field: the log law scaled so the far field's median shear is the current's rho u*^2 (scenes that set it) | wall_function: Launder & Spalding's, from the k equation's k as well, scaled the same way",
        choices=('waves', 'log', 'log_far_field', 'wall_function'),
    ),
    "reference_height": K(1.5, 'z_r / dx: where the near-bed velocity is read', range=(0.5, 5.0, True, True)),
    "outer_height": K(
        6.0,
        'shear = "waves": the near-bed velocity scaled so its amplitude, averaged along the bed over d0, is the amplitude outer_height dx up (above the SPH\'s near-wall layer: the tunnel\'s bed read 0.70 U_m at 1.5 dx, 0.65 at dx / 1.5; scaled from 6 dx, 0.95 and 0.93); 0: not scaled',
        range=(0.0, 10.0, True, True),
    ),
    "filter_time": K(0.05, "time constant of the near-bed velocity's filter", 's', range=(0.0, None, True, True)),
    "update_every": K(10, 'steps between bed updates', range=(1, 1000, True, True)),
    "morph_start": K(
        0.0,
        "the bed stays put until then while the flow spins up (Delft3D's MorStt)",
        's',
        range=(0.0, None, True, True),
    ),
    "lee_vortex": K(
        0.0,
        "shear in a separated lee reversed to this fraction of the crest's (0: off; beach, tunnel: 0.5)",
        range=(0.0, 1.0, True, True),
    ),
    "separation_length": K(
        6.0,
        "the lee zone's length in crest heights (flow reattaches about 6 step heights on)",
        range=(0.0, 50.0, True, True),
    ),
    "separation_slope": K(10.0, 'a lee steeper than this separates', 'degrees', range=(0.0, 60.0, True, True)),
    "separation_excursion": K(
        0.0,
        'the lee zone at most this many orbital amplitudes A = d0/2 long (0: no cap)',
        range=(0.0, 10.0, True, True),
    ),
    "vortex_throw": K(
        0.0,
        "the sand a separated lee's vortex throws back over its crest as the flow turns, times the crest's bed load (lee.vortex_throw; 0: off)",
        range=(0.0, 10.0, True, True),
    ),
    "throw_distance": K(
        1.0, 'where that sand lands: orbital amplitudes upstream of the crest', range=(0.0, 10.0, True, True)
    ),
    "suspended": K(
        False,
        "suspended load: the water carries sand the bed gives up (van Rijn's pick-up) and lets it settle back (tisph/physics/suspension.py); the pipeline only",
    ),
    "settling_velocity": K(0.0, 'm/s; 0: Soulsby (1997) for d50', range=(0.0, None, True, True)),
    "seed_rms": K(
        0.0, 'RMS of a random initial bed perturbation (smoothed over 2 dx)', 'm', range=(0.0, None, True, True)
    ),
    "seed": K(1, 'the random seed of that initial perturbation', range=(0, None, True, True)),
    "grain_density": K(
        2650.0, "the grains' own density (kg/m3; quartz), not the saturated bed's", range=(1000.0, None, False, True)
    ),
}
DEFAULTS = values(SEDIMENT)
RANGES = ranges(SEDIMENT, "sediment")
CHOICES = choices(SEDIMENT, "sediment")
# One set of bed parameters for sand under waves, the tunnel's and the beach's (docs/sediment.md: which are
# empirical, chosen on what); a scene adds only physical inputs (morfac, seed_rms). The pipeline's differ.
WAVE_RIPPLES = dict(
    model="bedload",
    grain_density=2650.0,
    shear="waves",
    reference_height=1.5,
    outer_height=6.0,
    lee_vortex=0.5,
    separation_length=6.0,
    separation_slope=10.0,
    separation_excursion=0.6,
    gravity_coefficient=1.8,
    vortex_throw=1.0,
    throw_distance=1.0,
)


def refuse_unused_sediment_keys(cfg, scene_defaults):
    """With sediment.model = "particles" the sand is SPH particles and the [sediment] keys, which
    drive the bed-load bed, do nothing: a key set away from its default is refused, all at once."""
    sed = cfg.get("sediment")
    if not sed or sed.get("model") != "particles":
        return
    base = scene_defaults.get("sediment", {})
    raise_collected(
        [
            ConfigError(
                f"sediment.{k}",
                v,
                f"its default ({base[k]!r}) with sediment.model = \"particles\"",
                "the sand is SPH particles; the [sediment] keys set the bed-load bed (sediment.model = \"bedload\")",
            )
            for k, v in sed.items()
            if k != "model" and k in base and v != base[k]
        ]
    )
