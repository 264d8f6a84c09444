"""The case file's lists of tables ([[solid]], [[water]], [[gauge]]): each entry's keys with their
defaults, checked as the scalar tables are (unknown keys with a "did you mean", types, choices),
every error at once, named as solid[2].polygon."""

import difflib
import math
import os

from ...geometry import read_profile
from ...measure.gauges import GAUGE_TYPES
from ...settings.config import ConfigError
from ...settings.schema import K, values

NUM = "a number"

# The keys of each list's entries; None: not given (a number where one is needed).
ELEMENTS = {
    "solid": {
        "label": K("", 'its name in messages and in the picture'),
        "line": K(
            [], '[[x, z], ...] m: an open polyline; the solid is on its right walking along it (the water on its left)'
        ),
        "polygon": K([], '[[x, z], ...] m: a closed polygon; the solid is inside (a breakwater, a seawall)'),
        "box": K([], '[x0, x1, z0, z1] m: a rectangle; the solid is inside'),
        "circle": K([], '[xc, zc, r] m: a circle; the solid is inside (a pipe)'),
        "csv": K(
            "",
            'a CSV of x, z rows (a surveyed profile, relative to the case file): a line from left to right, solid below it',
        ),
    },
    "water": {
        "label": K("", 'its name in messages'),
        "level": K(None, 'fill below this level wherever no solid is (give level or polygon)', 'm'),
        "x": K([], '[x0, x1] m: the stretch the level fills; []: the whole domain'),
        "polygon": K([], '[[x, z], ...] m: fill this closed region instead (it may not overlap a solid)'),
        "velocity": K([0.0, 0.0], "[u, w] m/s at the start; the pressure starts hydrostatic from the region's surface"),
    },
    "gauge": {
        "label": K("", 'its name in probes.csv and summary.json; "": type and number (surface1)'),
        "type": K(
            "surface",
            'surface (free-surface height at x) | velocity (at x, z) | pressure (at x, z) | force (along line) | discharge (through the vertical section at x) | front (the leading water along the floor at z)',
        ),
        "x": K(None, "a surface, velocity, pressure or discharge gauge's position", "m"),
        "z": K(
            None,
            'the point of a velocity or pressure gauge (put it half a smoothing length into the water from a wall)',
            'm',
        ),
        "line": K(
            [],
            "[[x0, z0], [x1, z1]] m: a force gauge's wall face; the pressure is integrated along it (force per metre)",
        ),
        "from_time": K(0.0, "the gauge's statistics start here (wave height, mean discharge)", 's'),
        "crest": K(None, "a discharge gauge's crest level: EurOtop's mean overtopping beside the measured one", 'm'),
        "cot_slope": K(0.0, "the structure's seaward slope (cot alpha) for EurOtop; 0: no EurOtop"),
        "array": K(
            "",
            "surface gauges given one name form an array: the incident and reflected waves at the paddle's frequency from two or more of them (Mansard & Funke 1980, as the flume's), a tenth of a wavelength or so apart",
        ),
        "toe_gauges": K(
            [],
            'the surface gauges in front of the structure whose incident wave height EurOtop reads: one (its wave height, incident and reflected together) or three or more on a flat stretch, a tenth of a wavelength or so apart (the incident first harmonic, separated from the reflected one)',
        ),
    },
}
SHAPES = ("line", "polygon", "box", "circle", "csv")


def _num(v):
    return isinstance(v, (int, float)) and not isinstance(v, bool) and math.isfinite(v)


def points(key, v, closed):
    """[[x, z], ...] as floats, at least 2 (3 closed) distinct points."""
    need = 3 if closed else 2
    ok = (
        isinstance(v, list)
        and len(v) >= need
        and all(isinstance(p, list) and len(p) == 2 and all(_num(c) for c in p) for p in v)
    )
    if not ok:
        raise ConfigError(key, v, f"a list of at least {need} [x, z] points in m")
    return [[float(a), float(b)] for a, b in v]


def numbers(key, v, n, what, increasing=()):
    if not (isinstance(v, list) and len(v) == n and all(_num(c) for c in v)):
        raise ConfigError(key, v, what)
    for i in increasing:
        if v[i] >= v[i + 1]:
            raise ConfigError(key, v, what)
    return [float(c) for c in v]


def entries(cfg, table, base_dir, errors):
    """The entries of list `table`, each with every key (defaults filled in), checked."""
    spec = values(ELEMENTS[table])
    raw = cfg.get(table, [])
    if not isinstance(raw, list) or not all(isinstance(e, dict) for e in raw):
        errors.append(ConfigError(table, raw, f"[[{table}]] tables"))
        return []
    out = []
    for i, e in enumerate(raw):
        name = f"{table}[{i}]"
        item = dict(spec, index=i, name=name)
        for k, v in e.items():
            key = f"{name}.{k}"
            if k not in spec:
                close = difflib.get_close_matches(k, list(spec), n=1, cutoff=0.5)
                errors.append(
                    ConfigError(
                        key,
                        v,
                        "one of: " + ", ".join(sorted(spec)),
                        f"did you mean '{close[0]}'?" if close else "unknown key",
                    )
                )
                continue
            d = spec[k]
            try:
                if d is None or isinstance(d, float):
                    if not _num(v):
                        raise ConfigError(key, v, NUM)
                    v = float(v)
                elif isinstance(d, str) and not isinstance(v, str):
                    raise ConfigError(key, v, "a string")
                elif isinstance(d, list) and not isinstance(v, list):
                    raise ConfigError(key, v, "a list")
                item[k] = v
            except ConfigError as err:
                errors.append(err)
        try:
            CHECKS[table](item, base_dir)
        except ConfigError as err:
            errors.append(err)
        out.append(item)
    return out


def _solid(s, base_dir):
    n = s["name"]
    given = [k for k in SHAPES if s[k] not in ([], "")]
    if len(given) != 1:
        raise ConfigError(n, "+".join(given) or "no shape", "exactly one of " + ", ".join(SHAPES))
    k = given[0]
    key = f"{n}.{k}"
    if k in ("line", "polygon"):
        s[k] = points(key, s[k], k == "polygon")
    elif k == "box":
        s[k] = numbers(key, s[k], 4, "[x0, x1, z0, z1] in m with x0 < x1 and z0 < z1", (0, 2))
    elif k == "circle":
        s[k] = numbers(key, s[k], 3, "[xc, zc, r] in m with r > 0")
        if s[k][2] <= 0:
            raise ConfigError(key, s[k], "[xc, zc, r] in m with r > 0")
    else:
        path = s[k] if os.path.isabs(s[k]) else os.path.join(base_dir, s[k])
        if not os.path.isfile(path):
            raise ConfigError(key, s[k], "an existing CSV file of x, z rows", f"looked for {path}")
        try:
            s["line"] = read_profile(path).tolist()
        except (ValueError, OSError) as e:
            raise ConfigError(key, s[k], "a CSV of x, z rows in m", str(e)) from None
    s["shape"] = "line" if k == "csv" else k


def _water(w, base_dir):
    n = w["name"]
    if (w["level"] is None) == (w["polygon"] == []):
        raise ConfigError(n, "level and polygon" if w["level"] is not None else "neither", "one of level or polygon")
    if w["polygon"]:
        w["polygon"] = points(f"{n}.polygon", w["polygon"], True)
    if w["x"]:
        w["x"] = numbers(f"{n}.x", w["x"], 2, "[x0, x1] in m with x0 < x1, or [] for the whole domain", (0,))
    w["velocity"] = numbers(f"{n}.velocity", w["velocity"], 2, "[u, w] in m/s")


def _gauge(g, base_dir):
    n = g["name"]
    if g["type"] not in GAUGE_TYPES:
        raise ConfigError(f"{n}.type", g["type"], "one of " + ", ".join(repr(t) for t in GAUGE_TYPES))
    t = g["type"]
    for key, what in GAUGE_TYPES[t].needs.items():  # what each type must be given (tisph/measure/gauges.py)
        if key == "line":
            g["line"] = points(f"{n}.line", g["line"], False)
            if len(g["line"]) != 2:
                raise ConfigError(f"{n}.line", g["line"], what)
        elif g[key] is None:
            raise ConfigError(f"{n}.{key}", None, what)
    if g["cot_slope"] < 0:
        raise ConfigError(f"{n}.cot_slope", g["cot_slope"], "a number >= 0")
    if g["cot_slope"] > 0 and (t != "discharge" or g["crest"] is None or not g["toe_gauges"]):
        raise ConfigError(
            f"{n}.cot_slope",
            g["cot_slope"],
            "0 unless the gauge is a discharge gauge with crest and "
            "toe_gauges given (EurOtop needs the freeboard and the wave height at the toe)",
        )
    if g["array"] and t != "surface":
        raise ConfigError(f"{n}.array", g["array"], '"" for a ' + t + " gauge (an array is of surface gauges)")
    if g["toe_gauges"] and len(g["toe_gauges"]) == 2:
        raise ConfigError(
            f"{n}.toe_gauges",
            g["toe_gauges"],
            "one surface gauge's label, or three or more (two waves, incident and reflected, are fitted)",
        )
    g["label"] = g["label"] or f"{t}{g['index'] + 1}"


CHECKS = {"solid": _solid, "water": _water, "gauge": _gauge}
