"""Reading a case: the scene's keys from its defaults, the case file and the flags, checked, then
the resolving steps and one final check, frozen (tisph/settings/resolved.py)."""

import os
import warnings

from ..case import as_scene
from ..sediment.keys import refuse_unused_sediment_keys
from ..settings.config import (
    ConfigError,
    ConfigErrors,
    build_config,
    flatten,
    raise_collected,
    read_toml,
    tomllib,
    validate,
)
from ..settings.plausible import check_materials
from ..settings.resolved import freeze, thaw
from ..settings.schemes import apply_scheme


def given_keys(config, overrides):
    """The dotted keys the user set, in the case file and as overrides (flags, the API)."""
    keys = set(overrides or {})
    if config:
        keys |= set(flatten(config if isinstance(config, dict) else read_toml(config)))
    return keys


def resolve(scene, config=None, overrides=None):
    """The resolved case of a scene (tisph/settings/resolved.py): defaults <- TOML <- overrides, checked;
    then the resolving steps, each a pure function of the case so far that returns the values it
    chooses and run.log's line on each (the scheme a case file named, what the scene derives for a
    key the user left at its default: the tunnel's dx and morfac, the paddle's stroke for a wave
    height); then one final check of the whole (the rules and the scene's check) and frozen."""
    scene, errors = as_scene(scene), []
    raw = build_config(scene.DEFAULTS, config, overrides or {}, scene.RANGES, scene.CHOICES, errors=errors)
    if not errors:
        return _checked(scene, raw, config, overrides)
    # the scene's checks on the rest (each bad key at its default), so every error shows at once;
    # what they find about a key already reported, or a check the defaults cannot pass, is left out
    bad = {e.field for e in errors}
    try:
        _checked(scene, raw, config, overrides)
    except ConfigErrors as e:
        errors += [x for x in e.errors if x.field not in bad]
    except ConfigError as e:
        errors += [e] if e.field not in bad else []
    except Exception:  # noqa: BLE001  (a check that cannot run on what is left stands aside)
        pass
    raise_collected(errors)


def _checked(scene, raw, config, overrides):
    if isinstance(config, str) and raw.get("domain", {}).get("base_dir") == "":
        raw["domain"]["base_dir"] = os.path.dirname(os.path.abspath(config))  # a case's files sit beside it
    cfg, notes = freeze(raw), []
    refuse_unused_sediment_keys(cfg, scene.DEFAULTS)
    check_materials(cfg)
    given = given_keys(config, overrides)
    for step in (apply_scheme, scene.derive):
        changes, said = step(cfg, given)
        cfg, notes = cfg.replace(changes), notes + list(said)
    if notes:  # what the steps chose is held to the rules the user's values were
        validate(thaw(cfg), scene.RANGES, scene.CHOICES)
    scene.check(cfg)
    return freeze(thaw(cfg), notes=notes, case_file=config if isinstance(config, str) else "")


def resolved_notes(scene):
    """The notes of resolving a scene's defaults (--describe prints them); none where the defaults
    are not a whole case (a case of one's own needs its geometry)."""
    try:
        return list(resolve(scene).notes)
    except ConfigError:
        return []


def rebuild(scene, cfg_text):
    """(resolved config, case) of a run again from the resolved config it stored (a snapshot's
    attrs, the head of run.log): its particles laid, nothing compiled, its warnings not said
    again (the run said them)."""
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        cfg = resolve(scene, None, flatten(tomllib.loads(cfg_text)))
        return cfg, as_scene(scene).build(cfg)
