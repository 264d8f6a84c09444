"""`python -m tisph.scenes.NAME --describe`: every config key of a scene with its default, what is
allowed and what it means, generated from the code (the defaults, the range and choice tables,
the engine modules' Params, and the comment written beside each default), so it cannot go stale.
"""
import importlib
import inspect
import io
import os
import sys
import tokenize

from . import config
from .registry import modules as scene_modules
from .config import CHOICES, MATERIAL_CHOICES, MATERIAL_RANGES, RANGES, describe_range



def comments(module, table=""):
    """{dotted key: the comment written beside its default} from a module's source: a comment on
    the key's own line, or else the comment lines right above it. A key inside a nested table
    ("geometry": {...}, "sediment": dict(...)) is named with it, and `table` prefixes every key
    (the table the module's defaults fill: "sediment" for coupling), so geometry.width and
    output.width, or sediment.seed and paddle.seed, keep their own words."""
    out = {}
    try:
        src = inspect.getsource(module)
    except (OSError, TypeError):
        return out
    toks = list(tokenize.generate_tokens(io.StringIO(src).readline))
    notes, keys, code_lines = {}, {}, set()
    stack, pending = [], None          # open brackets, each with the table it opens (or None)
    for k, tok in enumerate(toks):
        if tok.type == tokenize.COMMENT and (tok.start[1] > 0 or tok.line[:tok.start[1]].strip()):
            # indented or after code: a key's note (a comment at column 0 heads a section)
            notes[tok.start[0]] = tok.string.lstrip("#").strip()
        elif tok.type not in (tokenize.NL, tokenize.NEWLINE, tokenize.INDENT, tokenize.DEDENT):
            code_lines.add(tok.start[0])
            nxt = toks[k + 1] if k + 1 < len(toks) else None
            if tok.type == tokenize.OP and tok.string in "{([":
                stack.append(pending)
                pending = None
            elif tok.type == tokenize.OP and tok.string in "})]":
                if stack:
                    stack.pop()
            elif tok.type == tokenize.STRING and nxt is not None and nxt.string == ":":
                name = tok.string.strip("\"'")
                path = ".".join([t for t in [table] + stack if t] + [name])
                keys[tok.start[0]] = path           # the last key on a line owns its comment
                after = toks[k + 2] if k + 2 < len(toks) else None
                pending = name if after is not None and after.string in ("{", "dict") else None
                continue
            if not (tok.type == tokenize.NAME and tok.string == "dict"):
                pending = pending if tok.type == tokenize.OP and tok.string == ":" else None if tok.string not in "{(" else pending
    for line, key in keys.items():
        text = notes.get(line)
        if text is None:                       # a block of comment lines right above
            above, n = [], line - 1
            while n in notes and n not in code_lines:
                above.insert(0, notes[n])
                n -= 1
            text = " ".join(above) or None
        if text:
            out.setdefault(key, text)
    return out


def lookup(docs, key):
    """The description of a dotted key: its own, else that of its longest dotted tail
    (materials.water.rho0 -> rho0 from the materials module)."""
    parts = key.split(".")
    for i in range(len(parts)):
        text = docs.get(".".join(parts[i:]))
        if text:
            return text
    return ""


def _module_docs():
    docs = {}
    for p in config._module_keys():
        docs[p.key] = f"{p.doc} ({p.unit})" if p.unit not in ("", "-") else p.doc
    return docs


def rows(scene):
    """(key, default, allowed, meaning) of every key the scene's config has."""
    cfg = config.build_config(scene.DEFAULTS, None, {}, getattr(scene, "RANGES", None), getattr(scene, "CHOICES", None))
    ranges = dict(RANGES, **getattr(scene, "RANGES", {}))
    choices = dict(CHOICES, **getattr(scene, "CHOICES", {}))
    from . import materials
    from .waves import irregular, paddle
    from .sediment import coupling
    docs = {}
    extra = tuple((importlib.import_module(n), t) for n, t in getattr(scene, "DESCRIBED", ()))
    for m, table in ((materials, ""), (paddle, "paddle"), (irregular, "paddle"), (coupling, "sediment"),
                     (config, "")) + extra + (
            (scene, ""),):   # the scene's own words win
        docs.update(comments(m, table))
    mod_docs = _module_docs()
    out = []
    for key, v in config.flatten(cfg).items():
        if key in getattr(scene, "ELEMENTS", {}):
            continue                             # a list of tables: element_rows has its keys
        leaf = key.split(".")[-1]
        if key in choices:
            allowed = "one of " + ", ".join(repr(c) for c in choices[key])
        elif key in ranges:
            allowed = describe_range(*ranges[key])
        elif key.startswith("materials.") and leaf in MATERIAL_CHOICES:
            allowed = "one of " + ", ".join(repr(c) for c in MATERIAL_CHOICES[leaf])
        elif key.startswith("materials.") and leaf in MATERIAL_RANGES:
            allowed = describe_range(*MATERIAL_RANGES[leaf])
        else:
            allowed = config._type_name(v)
        out.append((key, repr(v) if isinstance(v, str) else str(v).lower() if isinstance(v, bool) else str(v),
                    allowed, mod_docs.get(key) or lookup(docs, key)))
    return out


def element_rows(scene):
    """(list, key, default, meaning) of the keys of each entry of a scene's lists of tables
    ([[solid]], [[water]], [[gauge]] of a custom case)."""
    elements = getattr(scene, "ELEMENTS", {})
    if not elements:
        return []
    docs = comments(sys.modules[scene.ELEMENTS_MODULE])
    return [(table, k, "(not given)" if v is None else repr(v) if isinstance(v, str) else str(v),
             docs.get(f"{table}.{k}", "")) for table, spec in elements.items() for k, v in spec.items()]


def describe(scene):
    """The table as text, one key per line, grouped by table."""
    lines = [f"Config keys of {scene.NAME} (defaults; set them in a case file with --config, "
             f"see scenes/*.toml):", ""]
    last = None
    for key, default, allowed, meaning in rows(scene):
        table = key.rsplit(".", 1)[0]
        if table != last:
            lines.append(f"[{table}]")
            last = table
        lines.append(f"  {key.rsplit('.', 1)[1]} = {default}    ({allowed}){'  ' + meaning if meaning else ''}")
    for table, key, default, meaning in element_rows(scene):
        if table != last:
            lines.append(f"[[{table}]]  (as many as the case needs; each entry's keys)")
            last = table
        lines.append(f"  {key} = {default}  {meaning}")
    return "\n".join(lines)


def as_toml(scene):
    """A case file that sets every key to its default, each with what is allowed and what it
    means beside it: scenes/defaults/NAME.toml (python -m tisph.describe --write scenes/defaults)."""
    cfg = config.build_config(scene.DEFAULTS, None, {}, getattr(scene, "RANGES", None), getattr(scene, "CHOICES", None))
    notes = {key: f"{allowed}" + (f"; {meaning}" if meaning else "") for key, _, allowed, meaning in rows(scene)}
    head = [f"# Every key of `python -m {scene.__name__}` at its default, with what is allowed and",
            "# what it means: generated from the code by `python -m tisph.describe --write scenes/defaults`",
            "# (tests/test_cli.py checks it is current). Copy the keys you change into a case file;",
            f"#   python -m {scene.__name__} --config scenes/defaults/{scene.NAME}.toml",
            "# runs the defaults." if not getattr(scene, "ELEMENTS", None) else
            "# needs its own domain.box, [[solid]] and [[water]] (scenes/breakwater.toml is a whole case).", ""]
    tail, last = [], None
    for table, key, default, meaning in element_rows(scene):
        if table != last:
            tail += ["", f"# [[{table}]]    (as many entries as the case needs; the keys of each)"]
            last = table
        tail.append(f"# {key} = {default}    # {meaning}")
    return "\n".join(head) + config.dump_toml(cfg, notes) + "\n" + ("\n".join(tail) + "\n" if tail else "")


def scenes():
    """Every registered scene module (tisph.registry.REGISTRY)."""
    return scene_modules()


def main(argv=None):
    argv = sys.argv[1:] if argv is None else argv
    if len(argv) != 2 or argv[0] != "--write":
        print("usage: python -m tisph.describe --write DIR   (writes DIR/NAME.toml for every scene)", file=sys.stderr)
        return 2
    from .io import ensure_dir, write_text
    ensure_dir(argv[1])
    for sc in scenes():
        write_text(os.path.join(argv[1], f"{sc.NAME}.toml"), as_toml(sc))
        print(f"wrote {os.path.join(argv[1], sc.NAME + '.toml')}")
    return 0


if __name__ == "__main__":
    sys.exit(main())
