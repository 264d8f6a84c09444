"""The resolved case: a scene's settings after every resolving step (the case file and flags on
the defaults, the scheme, the values the scene derives, the paddle's stroke) and one final check,
frozen. Everything below the reader takes this, and reads it by attribute: cfg.numerics.dx.

Each table is a frozen dataclass made from the validated table (its fields' types are the
schema's, which the checks already held the values to), not a hand-written one: the schema
(tisph/settings/schema.py) stays the one place a key and its default are written, and a hand-written
dataclass would be a second. A table is also a read-only Mapping, so the dumps (run.log, the
checkpoint, --describe) walk it as they walk the case file's tables. A table whose names are data,
not keys (materials: {name: material}), is a frozen mapping of its entries, read as
cfg.materials["water"] or cfg.materials.water.
"""

from __future__ import annotations

import dataclasses
import keyword
from collections.abc import Mapping


class Section(Mapping):
    """A resolved table: read by attribute; frozen; a Mapping of its keys for the dumps."""

    def _data(self) -> dict:
        return {f.name: getattr(self, f.name) for f in dataclasses.fields(self)}

    def __getitem__(self, key):
        if key not in self.__dataclass_fields__:  # a field by name, no dict of them all built
            raise KeyError(key)
        return getattr(self, key)

    def __iter__(self):
        return iter(self._data())

    def __len__(self):
        return len(self._data())

    def __reduce__(self):  # generated classes are not importable by name: rebuild from the values
        return freeze, (thaw(self), self.__class__.__name__)

    def __deepcopy__(self, memo):  # frozen: a copy is itself
        return self

    def __repr__(self):
        return f"{type(self).__name__}({', '.join(f'{k}={v!r}' for k, v in self.items())})"

    def replace(self, changes: dict) -> Section:
        """A copy with {dotted key: value} changed (a resolving step's result); notes kept."""
        d = thaw(self)
        for path, value in changes.items():
            t = d
            *head, last = path.split(".")
            for k in head:
                t = t[k]
            if last not in t:
                raise KeyError(f"{path}: not a key of this case")
            t[last] = value
        return freeze(d, type(self).__name__, getattr(self, "notes", ()), getattr(self, "case_file", ""))


class Table(Section):
    """A frozen mapping whose keys are names the user chose (materials), read either way."""

    __slots__ = ("_d",)

    def __init__(self, d):
        object.__setattr__(self, "_d", dict(d))

    def _data(self):
        return self._d

    def __getitem__(self, key):
        return self._d[key]

    def __getattr__(self, key):
        try:
            return object.__getattribute__(self, "_d")[key]
        except KeyError:
            raise AttributeError(key) from None

    def __setattr__(self, key, value):
        raise dataclasses.FrozenInstanceError(f"cannot assign to {key!r}: the resolved case is frozen")


class Resolved(Section):
    """The whole resolved case; notes: run.log's and --describe's lines on each value a resolving
    step chose (the scheme's, a scene's derived dx, the paddle's stroke); case_file: the case
    file it was read from ("" for a scene's defaults and flags)."""

    notes: tuple = ()
    case_file: str = ""


_CLASSES: dict = {}


def _is_field(name) -> bool:
    return (
        isinstance(name, str)
        and name.isidentifier()
        and not keyword.iskeyword(name)
        and not name.startswith("_")
        and not hasattr(Section, name)
    )


def freeze(d, name="Resolved", notes=(), case_file="") -> Section:
    """The frozen form of a validated config table (nested dicts) named `name`."""
    values = {k: freeze(v, _camel(k)) if isinstance(v, Mapping) else v for k, v in d.items()}
    top = name == "Resolved" or name.startswith("Resolved")
    if not all(_is_field(k) for k in values) or (name == "Materials" and not top):
        return Table(values)
    sig = (name, tuple((k, type(v)) for k, v in values.items()))
    cls = _CLASSES.get(sig)
    if cls is None:
        cls = _CLASSES[sig] = dataclasses.make_dataclass(
            name,
            [(k, type(v)) for k, v in values.items()],
            bases=(Resolved if top else Section,),
            frozen=True,
            eq=False,
            repr=False,
        )
    out = cls(**values)
    if top:
        object.__setattr__(out, "notes", tuple(notes))
        object.__setattr__(out, "case_file", str(case_file))
    return out


def thaw(x):
    """The plain nested dicts (and lists) of a resolved table."""
    if isinstance(x, Mapping):
        return {k: thaw(v) for k, v in x.items()}
    if isinstance(x, list):
        return [thaw(v) for v in x]
    return x


def _camel(key: str) -> str:
    return "".join(p.capitalize() for p in str(key).split("_")) or "Table"
