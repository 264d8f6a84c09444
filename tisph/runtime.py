"""Taichi initialisation, once per process (or again when the arch or precision changes)."""
import contextlib
import io
import os

import taichi as ti

_current = None
_slot = None       # the open lock file of this process's offline-cache folder (held until exit)
CACHE_SLOTS = 16


def cache_folder():
    """This process's own Taichi offline-cache folder: the first of CACHE_SLOTS folders under
    ~/.cache/tisph/ticache that no other process holds, held with an OS lock (flock) until the
    process ends. Taichi's cache takes a lock file of its own while it writes its index; two runs
    that shared one folder could miss it and print "Lock ... ticache.lock failed". With a folder
    each they never share one, and each folder stays warm for the next run that takes it. None
    (Taichi's default folder) where TI_OFFLINE_CACHE_FILE_PATH is set or flock is not available."""
    global _slot
    if os.environ.get("TI_OFFLINE_CACHE_FILE_PATH"):
        return None
    if _slot is not None:
        return _slot[1]
    try:
        import fcntl
    except ImportError:          # Windows: Taichi's default folder
        return None
    base = os.path.join(os.environ.get("XDG_CACHE_HOME") or os.path.join(os.path.expanduser("~"), ".cache"),
                        "tisph", "ticache")
    try:
        os.makedirs(base, exist_ok=True)
        for k in range(CACHE_SLOTS):
            f = open(os.path.join(base, f"slot{k}.lock"), "a")
            try:
                fcntl.flock(f, fcntl.LOCK_EX | fcntl.LOCK_NB)
            except OSError:
                f.close()
                continue
            folder = os.path.join(base, f"slot{k}")
            os.makedirs(folder, exist_ok=True)
            stale = os.path.join(folder, "ticache.lock")     # left by a run killed while it wrote
            if os.path.exists(stale):
                os.remove(stale)
            _slot = (f, folder)
            return folder
    except OSError:              # a read-only home: Taichi's default folder
        return None
    return None                  # every slot busy: Taichi's default folder


def cache_debug_info():
    """Taichi 1.7 formats a caret-marked source excerpt (a TextWrapper per call) as debug info for
    every name it transforms, again at each inlining of a ti.func: 0.4 s of a 1.0 s warm start of
    the dam break (cProfile). The text depends only on the function and the node's position, so
    it is kept per position; Taichi's messages are unchanged (taichi pinned to 1.7)."""
    from taichi.lang.ast import ast_transformer_utils as u
    ctx = u.ASTTransformerContext
    if getattr(ctx.get_pos_info, "cached", False):
        return
    orig, cache = ctx.get_pos_info, {}

    def get_pos_info(self, node):
        body = getattr(node, "body", None)
        key = (self.file, self.lineno_offset, self.indent, self.func.func.__name__, type(node).__name__,
               node.lineno, getattr(node, "end_lineno", None), getattr(node, "col_offset", None),
               getattr(node, "end_col_offset", None), body[0].lineno if isinstance(body, list) and body else None)
        msg = cache.get(key)
        if msg is None:
            msg = cache[key] = orig(self, node)
        return msg

    get_pos_info.cached = True
    ctx.get_pos_info = get_pos_info


def arch_name():
    """The arch Taichi runs on: x64, arm64, cuda, vulkan or metal."""
    return str(ti.lang.impl.current_cfg().arch).split(".")[-1]


def init(arch="cpu", precision="f32", quiet=True):
    """Initialise Taichi; returns the name of the arch actually used.

    arch: cpu | gpu (CUDA, Vulkan or Metal, whichever Taichi finds; CPU if none) | auto.
    """
    global _current
    key = (arch, precision)
    if _current is not None and _current[0] == key:
        return _current[1]
    # Not ti.gpu: that list includes OpenGL/GLES, whose probe segfaults on a headless machine.
    gpus = [ti.cuda, ti.vulkan, ti.metal]
    a = {"cpu": ti.cpu, "gpu": gpus, "auto": gpus}[arch]
    fp = {"f32": ti.f32, "f64": ti.f64}[precision]
    # auto falls back to the CPU silently; gpu says so (the runner logs it too)
    level = ti.ERROR if arch == "auto" else (ti.WARN if quiet else ti.INFO)
    # fast_math off: with it LLVM contracts and reorders float operations according to the shape
    # of the traced code, so moving a term into another function changed results in the last
    # bit; without it a refactor that keeps the order of the terms keeps every bit, and the
    # dam break at dx 0.03 ran as fast (2.83e6 against 2.54e6 particle-steps/s, back to back)
    kwargs = dict(default_fp=fp, log_level=level, random_seed=0, fast_math=False)
    folder = cache_folder()
    if folder:
        kwargs["offline_cache_file_path"] = folder
    threads = os.environ.get("TISPH_THREADS")
    if threads:
        kwargs["cpu_max_num_threads"] = int(threads)
    banner = io.StringIO()
    with contextlib.redirect_stdout(banner):  # "[Taichi] Starting on arch=..." -> run.log
        ti.init(arch=a, **kwargs)
    cache_debug_info()
    used = arch_name()
    _current = (key, used)
    return used


def describe():
    """One line for logs: Taichi version and the backend in use."""
    return f"taichi {ti.__version__}, arch {current_arch()}"


def current_arch():
    return _current[1] if _current else None
