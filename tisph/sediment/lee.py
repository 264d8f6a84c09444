"""The bed shear's correction in a ripple's lee, applied by the coupler (coupling.BedCoupler.shear):
the ripples' parametrised lee vortex (sediment.lee_vortex), with its sheet-flow factor."""
import numpy as np


def sheet_flow_factor(psi):
    """1 for mobility psi <= 190, falling linearly to 0 at 240 and above: the factor n of van der A
    et al. (2013)'s ripple predictor, where ripples wash out into sheet flow."""
    return np.clip((240.0 - np.asarray(psi, float)) / 50.0, 0.0, 1.0)


def lee_vortex_shear(tau, z, dx, u, sed, periodic=True, amplitude=0.0, mobility=0.0):
    """A reduced-complexity lee vortex (after the separation-zone picture of
    Nienhuis et al. 2014): downstream of each crest whose lee is steeper than separation_slope,
    over separation_length crest heights, the flow has separated and its vortex drives the bed
    back towards the crest: tau there is -lee_vortex times the crest's shear. Downstream is the
    direction of the near-bed flow u at the crest (a number, or one per station). The lee's
    steepest slope between the crest and its trough decides whether the flow separates. With
    separation_excursion > 0 the zone is at most that many orbital amplitudes long (amplitude: A,
    a number or one per station): a vortex shed in a half period cannot reach farther than the
    water travels past the crest, so neighbours beyond it no longer feed a crest. The vortex's
    strength is scaled by sheet_flow_factor(mobility): ripples wash out above psi = 240. That is
    imposed from the ripple predictor, not computed: the bed load has no suspension."""
    n = len(z)
    u = np.broadcast_to(np.asarray(u, float), (n,))
    amp = np.broadcast_to(np.asarray(amplitude, float), (n,))
    strength = sed["lee_vortex"] * np.broadcast_to(sheet_flow_factor(mobility), (n,))
    t_sep = np.tan(np.radians(sed["separation_slope"]))
    cap = sed.get("separation_excursion", 0.0)

    def nxt(k, d):
        j = k + d
        if 0 <= j < n:
            return j
        return j % n if periodic else None

    d_all = np.sign(u).astype(int)
    idx = np.arange(n)
    if periodic:
        zl, zr = np.roll(z, 1), np.roll(z, -1)
    else:
        zl, zr = np.append(z[0], z[:-1]), np.append(z[1:], z[-1])
    up_all = np.where(d_all > 0, zl, zr)          # the upstream neighbour (the end's own height)
    down_all = np.where(d_all > 0, zr, zl)
    crests = idx[(d_all != 0) & (z >= up_all) & (z > down_all)].tolist()
    # the walks on Python floats: the same double arithmetic as NumPy's scalars, faster to index
    zs, taul = np.asarray(z, float).tolist(), np.asarray(tau, float).tolist()
    res = list(taul)                               # tau, with the lee zones written over it
    dl, strl, ampl = d_all.tolist(), strength.tolist(), amp.tolist()
    for c in crests:
        d = dl[c]
        k, trough, steepest = c, zs[c], 0.0
        while True:                                # down the lee to the trough
            j = nxt(k, d)
            if j is None or j == c or zs[j] > zs[k]:
                break
            steepest = max(steepest, (zs[k] - zs[j]) / dx)
            k, trough = j, zs[j]
        if steepest < t_sep or strl[c] <= 0:
            continue                               # a gentle lee: no separation
        length = sed["separation_length"] * (zs[c] - trough)
        if cap > 0 and ampl[c] > 0:
            length = min(length, cap * ampl[c])
        j = c
        for _ in range(int(np.ceil(length / dx))):
            j = nxt(j, d)
            if j is None:
                break
            res[j] = -strl[c] * abs(taul[c]) * d   # towards the crest, against the flow
    return np.array(res)
