"""Render a run's HDF5 snapshots to PNG or a new MP4, as `pysph view` does for PySPH, with the
renderer the live run uses (tisph/viz/render.py) and the scene's own framing and colours.

    python -m tisph.view OUT [--field F] [--time T | --all] [--view X0 X1 Y0 Y1]
                             [--range LO HI] [--width W] [--mp4] [--fps N] [--live]

OUT is a run's output folder (with snapshots/*.h5) or one snapshot file. Without --time or
--all the last snapshot is drawn. Pictures go to OUT/view/FIELD_tT.png (and OUT/view/FIELD.mp4),
with _viewX0,X1,Y0,Y1 and _rangeLO,HI in the name when those are given (--range is in the unit the
colour bar shows: kPa for pressure; without it pressure spans the water's in view, not the walls').
The scene's framing (view, colour scales, sand colours) comes from rebuilding its case from the
config stored in the snapshot; a bed-load bed's surface comes from its BED particles, but its
bed-change panel is not redrawn (the bed's history is in bed_profile.csv, not in the snapshots).
"""

import argparse
import dataclasses
import os
import sys

import numpy as np

from . import registry as scenes
from .case import Picture
from .io import OPTIONAL, SNAPSHOT_FIELDS, OutputError, ensure_dir, load, load_attrs, snapshot_files
from .particles import BED
from .runner.reading import rebuild
from .settings.config import ConfigError, tomllib
from .viz.files import MovieWriter, write_png
from .viz.live import LiveWindow, display_problem
from .viz.render import FIELDS, STATE, make_renderer

KEYS = {SNAPSHOT_FIELDS[k][0]: k for k in STATE}  # dataset name -> what a frame reads


def state_of(arrays):
    missing = [k for k in KEYS if k not in arrays]
    if missing:
        raise OutputError(f"snapshot lacks {', '.join(missing)}: not a tisph snapshot")
    out = {v: arrays[k] for k, v in KEYS.items()}
    for k in OPTIONAL:
        if SNAPSHOT_FIELDS[k][0] in arrays:
            out[k] = arrays[SNAPSHOT_FIELDS[k][0]]
    return out


def scene_picture(attrs):
    """(picture, dx) from the scene's case rebuilt from the snapshot's config; (None, dx or None)
    if that fails."""
    cfg_text, name = attrs.get("config", ""), attrs.get("scene", "")
    try:
        cfg, case = rebuild(scenes.load(name), cfg_text)
        return case.picture, cfg.numerics.dx
    except Exception:  # an old or foreign snapshot: frame the particles instead
        try:
            return None, float(tomllib.loads(cfg_text)["numerics"]["dx"])
        except Exception:
            return None, None


def bed_surface_of(st, dx):
    """z_b(x) of a bed below particle scale from its BED particles (top layer + dx/2), or None."""
    bed = st["kind"] == BED
    if not bed.any():
        return None
    x = st["x"][bed]
    col = np.floor(x[:, 0] / dx).astype(int)
    cols, inv = np.unique(col, return_inverse=True)
    top = np.full(len(cols), -np.inf)
    np.maximum.at(top, inv, x[:, 1])
    xc, zc = (cols + 0.5) * dx, top + 0.5 * dx
    return lambda xs: np.interp(xs, xc, zc)


def make_parser():
    p = argparse.ArgumentParser(
        prog="python -m tisph.view", description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter
    )
    p.add_argument("out", help="a run's output folder, or one snapshot .h5")
    p.add_argument("--field", choices=FIELDS, default=None, help="colour by this field (default: the scene's panels)")
    g = p.add_mutually_exclusive_group()
    g.add_argument("--time", type=float, default=None, help="the snapshot nearest this time (s)")
    g.add_argument("--all", action="store_true", help="every snapshot")
    p.add_argument("--view", type=float, nargs=4, metavar=("X0", "X1", "Y0", "Y1"), help="region to draw (m)")
    p.add_argument(
        "--range",
        type=float,
        nargs=2,
        metavar=("LO", "HI"),
        help="colour bar range, in the unit the bar shows (m/s, kPa, kg/m3, 1/s)",
    )
    p.add_argument("--width", type=int, default=1280, help="picture width in pixels (default 1280)")
    p.add_argument("--mp4", action="store_true", help="also write the pictures as an MP4")
    p.add_argument("--fps", type=int, default=25)
    p.add_argument("--live", action="store_true", help="show each picture in a window as it is drawn (needs a display)")
    return p


def main(argv=None):
    args = make_parser().parse_args(argv)
    try:
        return view(args)
    except (OutputError, ConfigError) as e:
        print(f"python -m tisph.view: {e}", file=sys.stderr)
        return 2


def check_args(args):
    if args.width < 64 or args.width > 4096:
        raise ConfigError("--width", args.width, "64 to 4096 pixels")
    if args.view and not (args.view[0] < args.view[1] and args.view[2] < args.view[3]):
        raise ConfigError("--view", args.view, "X0 < X1 and Y0 < Y1")
    if args.range and not args.range[0] < args.range[1]:
        raise ConfigError("--range", args.range, "LO < HI")
    if args.live:
        why = display_problem(instead="look at the PNGs (and --mp4) it writes")
        if why:
            raise ConfigError("--live", True, "absent on a machine without a display", why)


def view(args):  # noqa: C901 (one branch an option of tisph view)
    check_args(args)
    files = snapshot_files(args.out)
    if args.time is not None:
        times = np.array([float(load_attrs(f).get("time", 0.0)) for f in files])
        files = [files[int(np.argmin(np.abs(times - args.time)))]]
    elif not args.all:
        files = files[-1:]
    attrs = load_attrs(files[0])
    pic, dx = scene_picture(attrs)
    if pic is None or dx is None:  # frame what the first snapshot holds
        x = state_of(load(files[0])[0])["x"]
        dx = dx or float(np.median(np.abs(np.diff(np.unique(np.round(x[:, 0], 6)))))) or 0.01
        lo, hi = x.min(0) - dx, x.max(0) + dx
        pic = pic or Picture(view=((lo[0], lo[1]), (hi[0], hi[1])), u_max=0.0)
    # the rebuilt case's bed is the initial one: its panel is not redrawn, its sand comes from the BED particles
    pic = dataclasses.replace(pic, bed_panel=None, bed_label="", bed_surface=None)
    outc = dict(
        width=args.width,
        view=list(args.view or []),
        field=args.field or "",
        range=list(args.range or []),
        min_height=160,
    )
    r = make_renderer(pic, outc, dx, attrs.get("scene", ""), pic.speed_scale or pic.u_max)
    src = args.out if os.path.isdir(args.out) else os.path.dirname(os.path.dirname(os.path.abspath(args.out)))
    dest = ensure_dir(os.path.join(src, "view"))
    tag = "+".join(r.modes)  # what makes one picture differ from another of the same time
    if args.view:
        tag += "_view" + ",".join(f"{v:g}" for v in args.view)
    if args.range:
        tag += "_range" + ",".join(f"{v:g}" for v in args.range)
    movie = MovieWriter(os.path.join(dest, f"{tag}.mp4"), args.fps) if args.mp4 else None
    live = None
    if args.live:
        live = LiveWindow(f"tisph.view: {args.out}")
    written = []
    try:
        for f in files:
            arrays, attrs = load(f)
            t = float(attrs.get("time", 0.0))
            st = state_of(arrays)
            if "concentration" in r.modes and "c" not in st:
                raise ConfigError(
                    "--field",
                    "concentration",
                    f"a field {f!r} holds: it has no suspended sand (a run with sediment.suspended = true writes it)",
                )
            r.bed_surface = bed_surface_of(st, dx)  # the sand under a bed-load bed, filled
            if r.zoom is not None:
                r.zoom.bed_surface = r.bed_surface
            img = r.frame(st, t)
            path = os.path.join(dest, f"{tag}_t{t:.3f}.png")
            write_png(path, img)
            written.append(path)
            if movie is not None:
                movie.append(img)
            if live is not None:
                live.show(img)
    except BaseException:
        if movie is not None:
            movie.abort()
        raise
    finally:
        if live is not None:
            live.close()
    if movie is not None:
        movie.close()
        written.append(movie.path)
    for p in written if len(written) <= 3 else written[:1] + ["..."] + written[-2:]:
        print(p)
    return 0


if __name__ == "__main__":
    sys.exit(main())
