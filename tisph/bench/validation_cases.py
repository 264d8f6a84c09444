"""The validation table's cases: each a scene or case file, the metric its error comes from, the
reference it is measured against, and the spacings it runs at (tisph/bench/validate.py runs them)."""

import dataclasses

import numpy as np

from ..constants import G


@dataclasses.dataclass
class Case:
    name: str
    scene: str  # module under tisph
    metric: str  # the summary metric the error comes from
    error: str  # what the error is
    reference: str  # the reference and its source
    ladder: tuple  # dx values, coarse to fine; the last is the reported run
    quick: float  # dx in --quick
    config: str = ""  # a case file under scenes/
    overrides: dict = dataclasses.field(default_factory=dict)
    quick_overrides: dict = dataclasses.field(default_factory=dict)
    figure: str = ""  # a picture the scene writes; "" draws the probes
    probes: tuple = ()  # probes.csv columns drawn when the scene writes no picture
    reference_value: float = None  # the error is metric / reference_value - 1 when set
    also: tuple = ()  # more metrics shown beside the error
    has_reference: bool = True  # False: the metric is shown, no error is computed
    note: str = ""
    seeds: int = 0  # > 1: the reported run with this many seeds (the bed's, or the start's), the metric their mean
    spread: str = ""  # where one run's spread is measured, for a chaotic metric run once here


# a table, one case a row: kept as written
# fmt: off
CASES = [
    Case("Still water in a tank", "scenes.tank", "pressure_error", "pressure against rho g d, below the top two rows",
         "hydrostatics", (0.04, 0.03, 0.02), 0.05, overrides={"run.end_time": 2.0}, quick_overrides={"run.end_time": 0.2},
         probes=("speed_ratio",), also=("density_error",),
         note="The default scheme's kernel reaches 5 dx: the third row from the surface, inside its reach, reads "
              "4.4 % (22 Pa) over rho g d at dx = 0.02 m and the rows below it within 1.5 %; the cubic spline at "
              "h = 1.3 dx read 0.9 %."),
    # the first mode of a closed tank: linear theory's period for L = 0.9 m, d = 0.3 m (the case
    # file's header); the loss a period beside it (linear theory: none)
    Case("Sloshing, first mode (linear theory)", "scenes.custom", "left_period", "period error",
         "linear theory, omega^2 = g k tanh(k d), k = pi / L", (0.0225, 0.015, 0.01), 0.03, config="sloshing.toml",
         quick_overrides={"run.end_time": 1.0}, probes=("eta_left", "eta_right"),
         reference_value=2 * np.pi / np.sqrt(G * np.pi / 0.9 * np.tanh(np.pi / 0.9 * 0.3)),
         also=("left_loss_per_period", "left_loss_stderr", "right_loss_per_period", "right_loss_stderr",
               "max_density_error"),
         note="The amplitude lost a period is the numerics' dissipation (linear theory keeps it); its standard "
              "error is the cycles' scatter about the fit."),
    Case("Poiseuille, Newtonian", "validation.poiseuille", "velocity_l2_error", "L2 velocity error",
         "the exact parabola (periodic plane channel, Morris no-slip walls)", (0.01, 0.005), 0.01,
         overrides={"materials.fluid.yield_stress": 0.0, "geometry.length": 0.08}, quick_overrides={"run.end_time": 0.3},
         figure="profile.png"),
    Case("Poiseuille, Bingham 10 Pa", "validation.poiseuille", "velocity_l2_error", "L2 velocity error",
         "the exact Bingham profile and plug (Bird, Stewart & Lightfoot)", (0.01, 0.005), 0.01,
         overrides={"geometry.length": 0.08}, quick_overrides={"run.end_time": 0.3}, figure="profile.png", also=("plug_half_width",)),
    Case("Dam break (Martin & Moyce)", "scenes.dam_break", "front_rms_error", "front RMS error, x / a, T <= 3.3",
         "Martin & Moyce (1952), measured front", (0.06, 0.04, 0.03), 0.08, quick_overrides={"run.end_time": 0.3},
         probes=("front_x", "column_h")),
    Case("Dam break on a dry bed (Ritter)", "scenes.dam_break", "front_speed_error", "front speed error",
         "Ritter's exact shallow-water solution (paper 000 section 4.2)", (0.025, 0.01875, 0.0125), 0.03,
         config="dam_break_alpha0.toml", quick_overrides={"run.end_time": 1.0, "geometry.profile_times": []},
         figure="profiles/profiles.png", probes=("front_x",), also=("front_speed_resolution_limit",),
         note="The SPH front cannot outrun 2 c0 - 3 sqrt(g dx) (front_speed_resolution_limit). Run on paper 000's "
              "scheme (Table 2, `numerics.scheme = \"paper000\"`): on the default scheme the front's thin tip "
              "runs slower (front speed error 0.39, [engine.md](engine.md))."),
    Case("Dam break on a wet bed, alpha 0.1 (Stoker)", "scenes.dam_break", "bore_speed_error", "bore speed error",
         "Stoker's exact solution (paper 000 section 4.2)", (0.0125,), 0.0125, config="dam_break_alpha01.toml",
         quick_overrides={"run.end_time": 0.6, "geometry.profile_times": []}, figure="profiles/profiles.png",
         probes=("bore_x", "plateau_h"), also=("plateau_depth_error",)),
    Case("Dam break on a wet bed, alpha 0.4 (Stoker)", "scenes.dam_break", "bore_speed_error", "bore speed error",
         "Stoker's exact solution (paper 000 section 4.2)", (0.025, 0.01875, 0.0125), 0.03, config="dam_break_alpha04.toml",
         quick_overrides={"run.end_time": 1.0, "geometry.profile_times": []}, figure="profiles/profiles.png",
         probes=("bore_x", "plateau_h"), also=("plateau_depth_error",)),
    Case("Hatch (paper 000 section 4.1)", "scenes.hatch", "discharge_coefficient",
         "discharge coefficient against pi / (pi + 2)",
         "a sharp-edged slot's contraction, pi / (pi + 2) = 0.611 (Kirchhoff's free streamline)", (0.00875, 0.0075, 0.005),
         0.0075, quick_overrides={"run.end_time": 0.1}, figure="profiles/surface.png", probes=("reservoir_level", "discharge"),
         reference_value=np.pi / (np.pi + 2)),
    Case("Wave flume, piston (Biesel)", "scenes.flume", "wave_height_error", "wave height error, worst of 1, 2, 3 wavelengths out",
         "Biesel's linear wave-maker theory (H / S for the piston and kh)", (0.028125, 0.01875, 0.0125), 0.03,
         quick_overrides={"run.end_time": 3.0}, figure="gauges.png", probes=("eta_0", "eta_1", "eta_2"),
         also=("wave_height_errors", "first_harmonic_error", "decay_per_wavelength", "reflection_coefficient")),
    Case("Oscillating tunnel ripples (Wiberg & Harris)", "scenes.tunnel", "ripple_length_over_prediction",
         "ripple length over the prediction, less 1", "Wiberg & Harris (1994) orbital ripples: 0.5-0.75 d0",
         (0.015, 0.01), 0.02, quick_overrides={"run.end_time": 2.0}, figure="ripple_growth.png", probes=("ripple_length", "ripple_height"),
         seeds=5,
         reference_value=1.0, also=("ripple_length_over_d0", "ripple_steepness", "max_density_error"),
         note="The same tunnel over 12 orbital diameters and periods, seeded short and long, and at two dx "
              "(18 cases): "
              "`python -m tisph.bench --ripples` ([sediment.md](sediment.md))."),
    # the headline beach at its default dx (18 dx the ripple predicted at the toe), over five seeds
    # of its random bed: one bed's ratio moves by 0.07 (standard deviation) from seed to seed
    Case("Beach ripples (Wiberg & Harris)", "scenes.beach", "ripple_length_over_prediction",
         "ripple length over the prediction, less 1", "Wiberg & Harris (1994) for the measured near-bed motion",
         (0.0093,), 0.03, quick_overrides={"run.end_time": 1.0}, seeds=5,
         figure="bed_profile.png", probes=("ripple_length",), reference_value=1.0,
         also=("ripple_count", "ripple_steepness", "run_up_max", "run_up_hunt", "crest_above_still_water",
               "max_density_error", "density_error_p999"),
         note="The headline case as `tisph run beach` runs it, over five seeds of its random bed (the first "
              "seed's bed, run-up and density in the table). The swash's highest reach (run_up_max, m above still "
              "water) against Hunt's run-up for the paddle's wave and the crest's height. Finer, 27 dx a ripple: "
              "`tisph run beach --dx 0.0062 --seeds 5`."),
    Case("Pipeline scour (Mao 1986)", "scenes.pipeline_scour", "mao_depth_max_error_15s",
         "largest S/D error over Mao's first 15 s", "Mao's (1986) measured S/D(t) and profiles, D = 5 cm",
         (0.0025,), 0.00625, config="pipeline_scour_mao.toml",
         quick_overrides={"run.end_time": 0.6, "geometry.length": 0.5, "geometry.inflow_length": 0.1},
         figure="scour_mao.png", probes=("scour_depth_over_D",),
         also=("scour_profile_error_11s", "scour_profile_error_18s", "scour_profile_error_25s"),
         spread="docs/sediment.md, over three perturbed starts (`--seeds 3`: each a 19-minute run, so once here)"),
    Case("Erodible bed (paper 000 section 4.3)", "scenes.erodible_bed", "eroded_area", "no reference value",
         "the paper's figures only (no measured values)", (0.02, 0.01), 0.02, quick_overrides={"run.end_time": 0.2},
         probes=("front_x", "eroded_area"), also=("bed_drop_at_gate",), has_reference=False,
         note="Shown for its cost and its bed change; the paper gives no value to compare with."),
]
# fmt: on


CASES_BY_NAME = {c.name: c for c in CASES}
