"""The bed shear's correction in a ripple's lee, applied by the coupler (coupling.BedCoupler.shear):
the ripples' parametrised lee vortex (sediment.lee_vortex), with its sheet-flow factor."""

import numpy as np


def sheet_flow_factor(psi):
    """1 for mobility psi <= 190, falling linearly to 0 at 240 and above: the factor n of van der A
    et al. (2013)'s ripple predictor, where ripples wash out into sheet flow."""
    return np.clip((240.0 - np.asarray(psi, float)) / 50.0, 0.0, 1.0)


def lee_zones(z, dx, u, sed, periodic=True, amplitude=0.0, mobility=0.0):
    """The separated lees: [(crest, direction, sheet factor, stations)], one for each crest whose lee
    (downstream along the near-bed flow u at the crest, a number or one per station) is steeper
    than separation_slope somewhere between the crest and its trough. Its zone runs
    separation_length crest heights downstream, and with separation_excursion > 0 at most that many
    orbital amplitudes (amplitude: A, a number or one per station): a vortex shed in a half period
    cannot reach farther than the water travels past the crest, so neighbours beyond it no longer
    feed a crest. sheet factor: sheet_flow_factor(mobility) at the crest, as ripples wash out
    above psi = 240 (imposed from the ripple predictor, not computed: the bed load has no
    suspension); a lee with none does not separate, nor any with lee_vortex = 0."""
    if sed["lee_vortex"] <= 0:
        return []
    n = len(z)
    u = np.broadcast_to(np.asarray(u, float), (n,))
    amp = np.broadcast_to(np.asarray(amplitude, float), (n,))
    sheet = np.broadcast_to(sheet_flow_factor(mobility), (n,))
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
    up_all = np.where(d_all > 0, zl, zr)  # the upstream neighbour (the end's own height)
    down_all = np.where(d_all > 0, zr, zl)
    crests = idx[(d_all != 0) & (z >= up_all) & (z > down_all)].tolist()
    # the walks on Python floats: the same double arithmetic as NumPy's scalars, faster to index
    zs = np.asarray(z, float).tolist()
    dl, sheetl, ampl = d_all.tolist(), sheet.tolist(), amp.tolist()
    zones = []
    for c in crests:
        d = dl[c]
        k, trough, steepest = c, zs[c], 0.0
        while True:  # down the lee to the trough
            j = nxt(k, d)
            if j is None or j == c or zs[j] > zs[k]:
                break
            steepest = max(steepest, (zs[k] - zs[j]) / dx)
            k, trough = j, zs[j]
        if steepest < t_sep or sheetl[c] <= 0:
            continue  # a gentle lee: no separation
        length = sed["separation_length"] * (zs[c] - trough)
        if cap > 0 and ampl[c] > 0:
            length = min(length, cap * ampl[c])
        j, st = c, []
        for _ in range(int(np.ceil(length / dx))):
            j = nxt(j, d)
            if j is None:
                break
            st.append(j)
        zones.append((c, d, sheetl[c], st))
    return zones


def lee_vortex_shear(tau, z, dx, u, sed, periodic=True, amplitude=0.0, mobility=0.0, zones=None):
    """A reduced-complexity lee vortex (after the separation-zone picture of
    Nienhuis et al. 2014): in each separated lee (lee_zones) the flow has separated and its vortex
    drives the bed back towards the crest: tau there is -lee_vortex times the crest's shear (times
    the sheet-flow factor)."""
    if zones is None:
        zones = lee_zones(z, dx, u, sed, periodic, amplitude, mobility)
    taul = np.asarray(tau, float).tolist()
    res = list(taul)  # tau, with the lee zones written over it
    for c, d, sheet, st in zones:
        strength = sed["lee_vortex"] * sheet
        for j in st:
            res[j] = -strength * abs(taul[c]) * d  # towards the crest, against the flow
    return np.array(res)


def vortex_throw(zones, q, dx, sed, periodic=True, amplitude=0.0):
    """The sand each lee vortex throws back over its crest (m2/s of grain volume at each station,
    positive where it lands). The vortex a half period builds in a crest's lee fills with sand from
    that lee; as the flow turns it is thrown up and carried back over the crest, and its sand
    settles out about an orbital amplitude beyond it (the sand clouds over vortex ripples, van der
    Werf et al. 2007). Where the troughs are longer than twice that distance it lands in the trough
    and builds a new crest there: the doubling of ripples that are too long (Hansen et al. 2001).
    Each separated crest throws vortex_throw times its own bed load |q| (times the sheet-flow
    factor), taken evenly from its lee zone and laid down as a Gaussian of standard deviation a
    quarter of the distance, centred throw_distance orbital amplitudes upstream of the crest (where
    the turning flow carries it). Volume is conserved to round-off."""
    n = len(q)
    dep = np.zeros(n)
    amp = np.broadcast_to(np.asarray(amplitude, float), (n,))
    for c, d, sheet, st in zones:
        dist = sed["throw_distance"] * amp[c]
        if not st or dist <= 0:
            continue
        volume = sed["vortex_throw"] * sheet * abs(q[c])
        sigma = 0.25 * dist
        half = int(np.ceil(4.0 * sigma / dx))
        j = c - d * int(round(dist / dx)) + np.arange(-half, half + 1)
        r = (j - (c - d * dist / dx)) * dx
        if periodic:
            j = j % n
        else:
            keep = (j >= 0) & (j < n)
            j, r = j[keep], r[keep]
            if not len(j):
                continue
        g = np.exp(-0.5 * (r / sigma) ** 2)
        np.add.at(dep, j, volume * g / g.sum())
        np.add.at(dep, st, -volume / len(st))
    return dep
