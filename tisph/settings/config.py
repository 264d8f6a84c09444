"""Case configuration: defaults, TOML loading, validation, and the compile-time Physics switches.

A scene's defaults (a nested dict) are the schema: a TOML file or a CLI flag may only set keys
that exist there, with a value of the same type, inside the range a rule allows. Everything is
checked in Python before Taichi compiles anything, so a typo is a one-line message, not a
traceback.
"""

from __future__ import annotations

import copy
import difflib
import math
import os
import sys
from collections.abc import Mapping

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - exercised on 3.9/3.10 only
    import tomli as tomllib

from ..errors import ConfigError, ConfigErrors, raise_collected  # noqa: F401  (re-exported: every check raises them)
from . import schema
from .resolved import thaw
from .shared_keys import MATERIAL, SHARED, TURBULENCE
from .switches import Physics, physics_from_config  # noqa: F401  (re-exported: scenes import them here)

# The keys every scene shares, the turbulence closure's and every material's, as Keys
# (tisph/settings/shared_keys.py); a scene's SCHEMA lays its own on them. These are read from there.
SHARED_DEFAULTS = schema.values(SHARED)
RANGES = dict(schema.ranges(SHARED), **schema.ranges(TURBULENCE, "numerics"))
CHOICES = dict(schema.choices(SHARED), **schema.choices(TURBULENCE, "numerics"))
MATERIAL_RANGES = schema.ranges(MATERIAL)
MATERIAL_CHOICES = schema.choices(MATERIAL)


def describe_range(lo, hi, lo_inc, hi_inc):
    parts = []
    if lo is not None:
        parts.append(f"{'>=' if lo_inc else '>'} {lo}")
    if hi is not None:
        parts.append(f"{'<=' if hi_inc else '<'} {hi}")
    return "a number " + " and ".join(parts)


def _check_range(path, value, rng):
    lo, hi, lo_inc, hi_inc = rng
    bad = isinstance(value, float) and not math.isfinite(value)
    if lo is not None and (value < lo or (value == lo and not lo_inc)):
        bad = True
    if hi is not None and (value > hi or (value == hi and not hi_inc)):
        bad = True
    if bad:
        raise ConfigError(path, value, describe_range(*rng))


def _type_name(v):
    return {
        bool: "true or false",
        int: "an integer",
        float: "a number",
        str: "a string",
        list: "a list",
        dict: "a table",
    }.get(type(v), type(v).__name__)


def _coerce(path, default, value):
    """Value of the same type as the default (an int is accepted where a float is expected)."""
    if isinstance(default, bool):
        if not isinstance(value, bool):
            raise ConfigError(path, value, "true or false")
        return value
    if isinstance(default, int):
        if isinstance(value, bool) or not isinstance(value, int):
            if isinstance(value, float) and value.is_integer():
                return int(value)
            raise ConfigError(path, value, "an integer")
        return value
    if isinstance(default, float):
        if isinstance(value, bool) or not isinstance(value, (int, float)):
            raise ConfigError(path, value, "a number")
        return float(value)
    if isinstance(default, str):
        if not isinstance(value, str):
            raise ConfigError(path, value, "a string")
        return value
    if isinstance(default, list):
        if not isinstance(value, list):
            raise ConfigError(path, value, "a list")
        return value
    raise ConfigError(path, value, _type_name(default))


def merge(base: dict, override: dict, prefix: str = "", errors=None) -> dict:
    """Return base updated by override; unknown keys are refused with the closest valid name.
    Every bad key is reported (errors: the list a caller collects them in; None: raise them)."""
    top = errors is None
    errors = [] if top else errors
    out = thaw(base)
    for key, value in override.items():
        path = f"{prefix}{key}"
        try:
            if key not in base:
                close = difflib.get_close_matches(key, list(base.keys()), n=1, cutoff=0.5)
                hint = f"did you mean '{prefix}{close[0]}'?" if close else ""
                if prefix == "numerics." and key in TURBULENCE:
                    hint = "a turbulence key: this scene has no SPS turbulence (the pipeline has)"
                raise ConfigError(
                    path, value, "one of: " + ", ".join(sorted(f"{prefix}{k}" for k in base)), hint or "unknown key"
                )
            if isinstance(base[key], Mapping):
                if not isinstance(value, dict):
                    raise ConfigError(path, value, "a table")
                out[key] = merge(base[key], value, path + ".", errors)
            else:
                out[key] = _coerce(path, base[key], value)
        except ConfigError as e:
            errors.append(e)
    if top:
        raise_collected(errors)
    return out


def validate(cfg: dict, extra_ranges: dict | None = None, extra_choices: dict | None = None) -> dict:
    """Check choices and ranges of every key that has a rule."""
    ranges = dict(RANGES, **(extra_ranges or {}))
    choices = dict(CHOICES, **(extra_choices or {}))

    errors = []

    def check(path, prefix, k, v):
        if path in choices and v not in choices[path]:
            raise ConfigError(path, v, "one of " + ", ".join(repr(c) for c in choices[path]))
        if path in ranges:
            _check_range(path, v, ranges[path])
        if prefix.startswith("materials.") and k in MATERIAL_RANGES:
            _check_range(path, v, MATERIAL_RANGES[k])
        if prefix.startswith("materials.") and k in MATERIAL_CHOICES and v not in MATERIAL_CHOICES[k]:
            raise ConfigError(path, v, "one of " + ", ".join(repr(c) for c in MATERIAL_CHOICES[k]))

    def walk(d, prefix):
        for k, v in d.items():
            path = f"{prefix}{k}"
            if isinstance(v, dict):
                walk(v, path + ".")
                continue
            try:
                check(path, prefix, k, v)
            except ConfigError as e:
                errors.append(e)

    walk(cfg, "")
    out = cfg.get("output", {})
    box = "[x0, x1, y0, y1] in m with x0 < x1 and y0 < y1"
    for key, what in (("view", box), ("zoom", box), ("range", "[lo, hi] with lo < hi")):
        v, n = out.get(key), 2 if key == "range" else 4
        if v and (
            len(v) != n
            or not all(isinstance(a, (int, float)) and not isinstance(a, bool) and math.isfinite(a) for a in v)
            or any(v[k] >= v[k + 1] for k in range(0, n, 2))
        ):
            errors.append(ConfigError(f"output.{key}", v, f"{what}, or [] for the default"))
    raise_collected(errors)
    return cfg


def check_file(key, path, what):
    """A path-valued key or flag must name an existing file, not a folder."""
    if os.path.isdir(path):
        raise ConfigError(key, str(path), f"a {what}", "it is a folder")
    if not os.path.exists(path):
        raise ConfigError(key, str(path), f"an existing {what}", "no such file")


def read_toml(path) -> dict:
    check_file("--config", path, "TOML file")
    try:
        with open(path, "rb") as f:
            raw = f.read()
    except OSError as e:
        raise ConfigError("--config", str(path), "a readable TOML file", str(e)) from None
    # a UTF-8 byte-order mark (what several Windows editors write) is not TOML: drop it
    if raw.startswith(b"\xef\xbb\xbf"):
        raw = raw[3:]
    try:
        return tomllib.loads(raw.decode("utf-8"))
    except UnicodeDecodeError as e:
        raise ConfigError("--config", str(path), "a TOML file in UTF-8", str(e)) from None
    except tomllib.TOMLDecodeError as e:
        raise ConfigError("--config", str(path), "valid TOML", str(e)) from None


def set_path(d: dict, path: str, value):
    keys = path.split(".")
    for k in keys[:-1]:
        d = d.setdefault(k, {})
    d[keys[-1]] = value


def flatten(d: dict, prefix: str = "") -> dict:
    """{dotted path: value} of a nested config (the inverse of set_path)."""
    out = {}
    for k, v in d.items():
        if isinstance(v, Mapping):
            out.update(flatten(v, f"{prefix}{k}."))
        else:
            out[f"{prefix}{k}"] = v
    return out


def get_path(d: dict, path: str):
    for k in path.split("."):
        d = d[k]
    return d


def build_config(
    scene_defaults: dict,
    toml_path=None,
    overrides: dict | None = None,
    extra_ranges=None,
    extra_choices=None,
    errors=None,
) -> dict:
    """Defaults <- TOML file (or its tables as a dict) <- CLI overrides (dotted paths), validated.
    errors: a list to collect the bad input in instead of raising it; each bad key then keeps its
    default, so that the scene's own checks can run on the rest and report theirs with it."""
    base = merge(SHARED_DEFAULTS, {}) if not scene_defaults else _deep_union(SHARED_DEFAULTS, scene_defaults)
    top = errors is None
    cfg, errors = base, ([] if top else errors)
    n0 = len(errors)
    if toml_path:
        cfg = merge(cfg, toml_path if isinstance(toml_path, dict) else read_toml(toml_path), errors=errors)
    if overrides:
        ov: dict = {}
        for path, value in overrides.items():
            set_path(ov, path, value)
        cfg = merge(cfg, ov, errors=errors)
    try:
        validate(cfg, extra_ranges, extra_choices)
    except ConfigErrors as e:
        errors += e.errors
    except ConfigError as e:
        errors.append(e)
    if top:
        raise_collected(errors)
    for e in errors[n0:]:
        try:
            set_path(cfg, e.field, copy.deepcopy(get_path(base, e.field)))
        except (KeyError, TypeError):
            pass  # an unknown key: never merged
    return cfg


def _deep_union(a: dict, b: dict) -> dict:
    """Scene defaults extend and override the shared ones (no strictness here: we wrote both)."""
    out = copy.deepcopy(a)
    for k, v in b.items():
        if isinstance(v, dict) and isinstance(out.get(k), dict):
            out[k] = _deep_union(out[k], v)
        else:
            out[k] = copy.deepcopy(v)
    return out


def dump_toml(d: dict, notes=None) -> str:
    """The resolved config as TOML text; notes: {dotted key: text} written as a comment beside it."""
    notes = notes or {}
    lines: list[str] = []

    def fmt(v):
        if isinstance(v, bool):
            return "true" if v else "false"
        if isinstance(v, (int, float)):
            return repr(v)
        if isinstance(v, str):
            return '"' + v.replace("\\", "\\\\").replace('"', '\\"') + '"'
        if isinstance(v, (list, Mapping)):  # a table: an entry of a list of tables ([[solid]]), inline
            return (
                "{" + ", ".join(f"{k} = {fmt(x)}" for k, x in v.items() if x is not None) + "}"
                if isinstance(v, Mapping)
                else "[" + ", ".join(fmt(x) for x in v) + "]"
            )
        raise TypeError(type(v))

    def table(prefix, t):
        scalars = {k: v for k, v in t.items() if not isinstance(v, Mapping)}
        if scalars and prefix:
            lines.append(f"[{prefix}]")
        for k, v in scalars.items():
            note = notes.get(f"{prefix}.{k}" if prefix else k)
            lines.append(f"{k} = {fmt(v)}" + (f"    # {note}" if note else ""))
        if scalars:
            lines.append("")
        for k, v in t.items():
            if isinstance(v, Mapping):
                table(f"{prefix}.{k}" if prefix else k, v)

    table("", d)
    return "\n".join(lines)
