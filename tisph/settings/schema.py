"""The configuration's one key type: every key of every scene, the engine's included, is a Key
with its default, unit, range or choices and words. A scene's SCHEMA is a tree of them (nested
dicts; a plain value at a leaf sets the default of a key declared in the shared tables); its
DEFAULTS, RANGES and CHOICES, --describe, scenes/defaults/*.toml and the checks are read from it.

Our own dataclass, not pydantic or attrs: a case is checked before anything compiles, every error
at once, each naming the key, the value and what is allowed, with a "did you mean" and a units
guess (tisph/settings/config.py); a library's messages would need the same rewriting, and its types would
be one more dependency for 40 lines.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Iterable, Iterator

POSITIVE = (0.0, None, False, True)  # > 0
NON_NEGATIVE = (0.0, None, True, True)  # >= 0


@dataclasses.dataclass(frozen=True)
class Key:
    """A config key: its one default, unit ("" or "-": none), allowed range (lo, hi,
    lo_inclusive, hi_inclusive; None open) or choices, and what it means."""

    default: object
    unit: str = ""
    range: tuple | None = None
    doc: str = ""
    choices: tuple | None = None


def K(
    default: object, doc: str = "", unit: str = "", range: tuple | None = None, choices: Iterable | None = None
) -> Key:
    """A Key, written words first: K(0.5, "the tank's inside width", "m", POSITIVE)."""
    return Key(default, unit, range, doc, tuple(choices) if choices is not None else None)


def walk(tree: dict, prefix: str = "") -> Iterator[tuple[str, object]]:
    """(dotted key, leaf) of every leaf of a schema tree, in order."""
    for name, v in tree.items():
        path = f"{prefix}.{name}" if prefix else name
        if isinstance(v, dict):
            yield from walk(v, path)
        else:
            yield path, v


def values(tree: dict) -> dict:
    """The tree's defaults as plain nested dicts (a Key by its default)."""
    return {k: values(v) if isinstance(v, dict) else (v.default if isinstance(v, Key) else v) for k, v in tree.items()}


def ranges(tree: dict, prefix: str = "") -> dict[str, tuple]:
    """{dotted key: range} of the tree's Keys that have one."""
    return {p: tuple(v.range) for p, v in walk(tree, prefix) if isinstance(v, Key) and v.range is not None}


def choices(tree: dict, prefix: str = "") -> dict[str, tuple]:
    """{dotted key: choices} of the tree's Keys that have them."""
    return {p: tuple(v.choices) for p, v in walk(tree, prefix) if isinstance(v, Key) and v.choices is not None}


def words(k: Key) -> str:
    """What a Key means, with its unit."""
    return f"{k.doc} ({k.unit})" if k.doc and k.unit not in ("", "-") else k.doc


def docs(tree: dict, prefix: str = "") -> dict[str, str]:
    """{dotted key: words} of the tree's Keys that have words."""
    return {p: words(v) for p, v in walk(tree, prefix) if isinstance(v, Key) and v.doc}


def with_defaults(tree: dict, **defaults: object) -> dict:
    """A copy of a table whose named keys take new defaults, keeping their words and rules (a
    scene's own values for a shared table: dict(sediment/keys.py's SEDIMENT) with its morfac)."""
    unknown = set(defaults) - set(tree)
    if unknown:
        raise KeyError(f"not keys of the table: {sorted(unknown)}")

    def new(v, d):
        if isinstance(d, Key):  # a whole new key in its place
            return d
        return dataclasses.replace(v, default=d) if isinstance(v, Key) else d

    return {k: new(v, defaults[k]) if k in defaults else v for k, v in tree.items()}


@dataclasses.dataclass(frozen=True)
class Param(Key):
    """A runtime parameter: a config Key (the one default, its unit and allowed range) the solver holds in a Taichi struct. A default may be 'dx' (the particle spacing) or a
    function (S, values) -> value. `key`: the config key that sets it; config.py takes that
    key's default, range and words from here, so they are written once."""

    unit: str = "-"
    range: tuple = (None, None, True, True)
    vector: bool = False
    key: str = ""
