"""`python -m tisph.scenes.NAME --describe`: every config key of a scene with its default, what is
allowed and what it means, read from the scene's SCHEMA and the shared keys (tisph/settings/schema.py's
Key: default, unit, range or choices, words), so it cannot go stale.
"""

import os
import sys

from .case import as_scene
from .io import ensure_dir, write_text
from .registry import scenes as registered
from .settings import config, schema
from .settings.config import CHOICES, MATERIAL_CHOICES, MATERIAL_RANGES, RANGES, describe_range
from .settings.shared_keys import MATERIAL, SHARED, TURBULENCE


def words(scene):
    """{dotted key: what it means} of every key the scene declares or shares."""
    scene = as_scene(scene)
    out = dict(schema.docs(SHARED), **schema.docs(TURBULENCE, "numerics"))
    out.update(schema.docs(scene.SCHEMA))  # the scene's own words win
    return out


def rows(scene):
    """(key, default, allowed, meaning) of every key the scene's config has."""
    scene = as_scene(scene)
    cfg = config.build_config(scene.DEFAULTS, None, {}, scene.RANGES, scene.CHOICES)
    ranges = dict(RANGES, **scene.RANGES)
    choices = dict(CHOICES, **scene.CHOICES)
    docs = words(scene)
    out = []
    for key, v in config.flatten(cfg).items():
        if key in scene.ELEMENTS:
            continue  # a list of tables: element_rows has its keys
        leaf = key.split(".")[-1]
        material = key.startswith("materials.") and leaf in MATERIAL
        if key in choices:
            allowed = "one of " + ", ".join(repr(c) for c in choices[key])
        elif key in ranges:
            allowed = describe_range(*ranges[key])
        elif material and leaf in MATERIAL_CHOICES:
            allowed = "one of " + ", ".join(repr(c) for c in MATERIAL_CHOICES[leaf])
        elif material and leaf in MATERIAL_RANGES:
            allowed = describe_range(*MATERIAL_RANGES[leaf])
        else:
            allowed = config._type_name(v)
        meaning = docs.get(key) or (schema.words(MATERIAL[leaf]) if material else "")
        out.append(
            (
                key,
                repr(v) if isinstance(v, str) else str(v).lower() if isinstance(v, bool) else str(v),
                allowed,
                meaning,
            )
        )
    return out


def element_rows(scene):
    """(list, key, default, meaning) of the keys of each entry of a scene's lists of tables
    ([[solid]], [[water]], [[gauge]] of a custom case)."""
    scene = as_scene(scene)
    return [
        (
            table,
            k,
            "(not given)" if v.default is None else repr(v.default) if isinstance(v.default, str) else str(v.default),
            schema.words(v),
        )
        for table, spec in scene.ELEMENTS.items()
        for k, v in spec.items()
    ]


def describe(scene, notes=()):
    """The table as text, one key per line, grouped by table; then notes: what resolving the
    defaults chose (tisph.runner.reading.resolved_notes: the tunnel's dx and morfac)."""
    scene = as_scene(scene)
    lines = [f"Config keys of {scene.NAME} (defaults; set them in a case file with --config, see scenes/*.toml):", ""]
    keyed = list(rows(scene))
    geometry = []
    if scene.ELEMENTS:  # a case of one's own: the domain and its entries first
        geometry = [r for r in keyed if r[0].startswith("domain.")]
        keyed = [r for r in keyed if not r[0].startswith("domain.")]
    last = None

    def keys(rs):
        nonlocal last
        for key, default, allowed, meaning in rs:
            table = key.rsplit(".", 1)[0]
            if table != last:
                lines.append(f"[{table}]")
                last = table
            lines.append(f"  {key.rsplit('.', 1)[1]} = {default}    ({allowed}){'  ' + meaning if meaning else ''}")

    keys(geometry)
    for table, key, default, meaning in element_rows(scene):
        if table != last:
            lines.append(f"[[{table}]]  (as many as the case needs; each entry's keys)")
            last = table
        lines.append(f"  {key} = {default}  {meaning}")
    keys(keyed)
    if notes:
        lines += ["", "Resolved from the defaults (run.log says the same for a run):"] + [f"  {n}" for n in notes]
    return "\n".join(lines)


def as_toml(scene):
    """A case file that sets every key to its default, each with what is allowed and what it
    means beside it: scenes/defaults/NAME.toml (python -m tisph.describe --write scenes/defaults)."""
    scene = as_scene(scene)
    cfg = config.build_config(scene.DEFAULTS, None, {}, scene.RANGES, scene.CHOICES)
    notes = {key: f"{allowed}" + (f"; {meaning}" if meaning else "") for key, _, allowed, meaning in rows(scene)}
    head = [
        f"# Every key of `python -m {scene.module}` at its default, with what is allowed and",
        "# what it means: generated from the code by `python -m tisph.describe --write scenes/defaults`",
        "# (tests/runner/test_cli.py checks it is current). Copy the keys you change into a case file;",
        f"#   python -m {scene.module} --config scenes/defaults/{scene.NAME}.toml",
        "# runs the defaults."
        if not scene.ELEMENTS
        else "# needs its own domain.box, [[solid]] and [[water]] (scenes/breakwater.toml is a whole case).",
        "",
    ]
    tail, last = [], None
    for table, key, default, meaning in element_rows(scene):
        if table != last:
            tail += ["", f"# [[{table}]]    (as many entries as the case needs; the keys of each)"]
            last = table
        tail.append(f"# {key} = {default}    # {meaning}")
    return "\n".join(head) + config.dump_toml(cfg, notes) + "\n" + ("\n".join(tail) + "\n" if tail else "")


def scenes():
    """Every registered Scene (tisph.registry.REGISTRY)."""
    return registered()


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 2 or argv[0] != "--write":
        print("usage: python -m tisph.describe --write DIR   (writes DIR/NAME.toml for every scene)", file=sys.stderr)
        return 2
    ensure_dir(argv[1])
    for sc in scenes():
        write_text(os.path.join(argv[1], f"{sc.NAME}.toml"), as_toml(sc))
        print(f"wrote {os.path.join(argv[1], sc.NAME + '.toml')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
