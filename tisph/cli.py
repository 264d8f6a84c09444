"""Flags every scene shares. Each maps onto one config key, so a flag and a TOML key never disagree."""

import argparse

# flag dest -> config path
FLAG_KEYS = {
    "dx": "numerics.dx",
    "end_time": "run.end_time",
    "max_steps": "run.max_steps",
    "out": "output.dir",
    "arch": "run.arch",
    "fps": "output.fps",
    "frame_interval": "output.frame_interval",
    "snapshot_every": "output.snapshot_every",
    "checkpoint_every": "output.checkpoint_every",
}


class _Parser(argparse.ArgumentParser):
    def error(self, message):  # exit code 2 with a one-line message, as argparse does, plus usage
        self.print_usage()
        self.exit(2, f"{self.prog}: error: {message}\n")


def make_parser(scene, description="", prog=None):
    p = _Parser(
        prog=prog or f"python -m tisph.scenes.{scene}",
        description=description,
        formatter_class=argparse.RawDescriptionHelpFormatter,
    )
    p.add_argument("--config", metavar="FILE", help="TOML case file (see scenes/*.toml); flags override it")
    p.add_argument("--dx", type=float, help="initial particle spacing in m")
    p.add_argument("--end-time", type=float, help="simulated time to stop at, in s")
    p.add_argument("--max-steps", type=int, help="stop after this many time steps (0: no limit)")
    p.add_argument("--out", metavar="DIR", help=f"output folder (default renders/{scene}/)")
    p.add_argument(
        "--arch", choices=("cpu", "gpu", "auto"), help="Taichi backend: cpu, gpu (CUDA, Vulkan or Metal), auto"
    )
    p.add_argument("--no-render", action="store_true", help="write no PNG frames and no MP4")
    p.add_argument("--fps", type=int, help="movie playback frames per second")
    p.add_argument("--frame-interval", type=float, help="simulated seconds between frames")
    p.add_argument(
        "--snapshot-every",
        type=float,
        metavar="S",
        help="simulated seconds between HDF5 snapshots (default: the frame interval; 0: off)",
    )
    p.add_argument(
        "--checkpoint-every",
        type=float,
        metavar="S",
        help="simulated seconds between checkpoints (SIGINT/SIGTERM always write one)",
    )
    p.add_argument("--restart", metavar="PATH", help="continue from a checkpoint.h5")
    p.add_argument("--force", action="store_true", help="allow --restart with a changed config")
    p.add_argument("--quiet", action="store_true", help="no progress bar and no messages but errors")
    p.add_argument(
        "--live",
        action="store_true",
        help="show each frame in a window as it is rendered (needs a display; the files are written all the same)",
    )
    p.add_argument(
        "--convergence",
        action="store_true",
        help="also run the case at 1.5 and 2.25 times its dx: each metric's observed order, Richardson "
        "estimate and GCI (convergence/ in the run folder, `convergence` in summary.json)",
    )
    p.add_argument(
        "--seeds",
        type=int,
        metavar="N",
        help="run the case with N random seeds of its initial bed (sediment.seed and the next N - 1): each "
        "metric's mean, standard deviation and standard error (seeds/ in the run folder, `ensemble` in "
        "summary.json)",
    )
    p.add_argument(
        "--describe",
        action="store_true",
        help="print every config key with its default, what is allowed and what it means, and exit",
    )
    return p


def overrides_from_args(args):
    """Config overrides (dotted path -> value) for the flags that were given."""
    ov = {}
    for dest, path in FLAG_KEYS.items():
        v = getattr(args, dest, None)
        if v is not None:
            ov[path] = v
    if getattr(args, "no_render", False):
        ov["output.render"] = False
    if getattr(args, "quiet", False):
        ov["output.quiet"] = True
    if getattr(args, "live", False):
        ov["output.live"] = True
    return ov
