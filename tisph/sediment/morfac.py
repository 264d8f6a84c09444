"""How fast the bed may move: the morphological factor's rule (Roelvink 2006: morfac assumes the
bed all but still through a wave period).

The ripple model was chosen on one case, the calibration tunnel below (the oscillating tunnel's
defaults): there the bed load moves one predicted ripple's sand in 6.8 wave periods at morfac 10.
A case whose bed turns over faster per period (the tunnel at another d0, the beach at its toe) is
outside what the model was chosen on: it is warned, with the morfac that keeps it as slow. At
mobility 145 (d0 = 0.4 m, T = 1.5 s, 2.9 periods a ripple at morfac 10) the ripples coarsened to
1.0 d0 at morfac 10 and kept 0.58-0.67 d0 at 3 (docs/sediment.md).
"""

import functools
import math
import warnings

from ..ripples import wiberg_harris
from ..settings.materials import WATER
from . import keys
from .transport import ripple_turnover_periods

# the calibration tunnel: orbital diameter d0 (m), period T (s), grain diameter d50 (m) and morfac,
# over the wave-ripple bed (keys.WAVE_RIPPLES); tisph.scenes.tunnel's defaults are these
CALIBRATION = {"orbital_diameter": 0.3, "period": 2.0, "grain_diameter": 0.0003, "morfac": 10.0}


def bed_turnover(d0, T, d50, s, sed):
    """Wave periods the bed load takes to move one predicted ripple's sand at sed's morfac (s:
    the grains' specific gravity)."""
    lam, eta, _ = wiberg_harris(d0, d50)
    return ripple_turnover_periods(d0, T, d50, s, lam, eta, sed["porosity"], sed["formula"]) / sed["morfac"]


@functools.lru_cache(maxsize=1)
def reference_turnover():
    """bed_turnover of the calibration tunnel (6.8 wave periods)."""
    sed = dict(keys.DEFAULTS, **keys.WAVE_RIPPLES, morfac=CALIBRATION["morfac"])
    c = CALIBRATION
    return bed_turnover(
        c["orbital_diameter"], c["period"], c["grain_diameter"], sed["grain_density"] / WATER["rho0"], sed
    )


def morfac_limit(sed, turnover):
    """The largest morfac at which the bed turns over no faster, in wave periods, than in the
    calibration tunnel; turnover: the periods a ripple's sand takes at sed's morfac."""
    return sed["morfac"] * turnover / reference_turnover()


def warn_fast_bed(sed, turnover, where):
    """Warn where the bed at sed's morfac turns over faster than in the calibration tunnel;
    returns the largest morfac that keeps it as slow."""
    limit = morfac_limit(sed, turnover)
    if sed["morfac"] > limit:
        warnings.warn(
            f"sediment.morfac = {sed['morfac']:g} moves the bed faster in each wave period than in the "
            f"default tunnel, where the ripple model was chosen ({where} the bed load moves a "
            f"ripple's sand in {turnover:.2g} periods at this morfac, against "
            f"{reference_turnover():.2g}): ripples may coarsen past their length (docs/sediment.md); "
            f"sediment.morfac = {math.floor(limit * 10) / 10:g} keeps it as slow"
        )
    return limit
