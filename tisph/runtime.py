"""Taichi initialisation, once per process (or again when the arch or precision changes)."""

import atexit
import contextlib
import io
import math
import os

import taichi as ti

_current = None
_finalizer = False


def cache_lock_path():
    """The OS lock file beside Taichi's offline cache (its default folder, or the user's)."""
    folder = os.environ.get("TI_OFFLINE_CACHE_FILE_PATH") or os.path.join(
        os.path.expanduser("~"), ".cache", "taichi", "ticache"
    )
    return os.path.join(folder, "tisph.flock")


@contextlib.contextmanager
def cache_guard():
    """Taichi's offline cache takes a lock file of its own (created exclusively) while it reads
    and writes its index; a process that finds it taken prints "Lock .../ticache.lock failed"
    and goes on without it. tisph's processes hold an OS lock (flock) around Taichi's start and
    its final write, so concurrent runs and sweep workers take turns there and share one warm
    cache. Where flock is not available (Windows) Taichi's own lock is all there is."""
    try:
        import fcntl

        path = cache_lock_path()
        os.makedirs(os.path.dirname(path), exist_ok=True)
        f = open(path, "a")  # noqa: SIM115 (closed by the with below, once the guarded block is done)
    except (ImportError, OSError):
        yield
        return
    with f:
        fcntl.flock(f, fcntl.LOCK_EX)
        clear_stale_lock(os.path.join(os.path.dirname(path), "ticache.lock"))
        try:
            yield
        finally:
            fcntl.flock(f, fcntl.LOCK_UN)


def clear_stale_lock(path, age=60.0):
    """Taichi's own lock left by a process killed while it held it (kill -9 during a cache write):
    every later run would print "Lock ... failed" and never write its cache again. Under the guard
    no tisph process holds it, so one older than `age` seconds is a dead process's."""
    import time

    try:
        if time.time() - os.path.getmtime(path) > age:
            os.remove(path)
    except OSError:
        pass


def _finalize():
    """At exit: Taichi writes its cache index when its program ends; end it under the guard."""
    with cache_guard():
        ti.reset()


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
        key = (
            self.file,
            self.lineno_offset,
            self.indent,
            self.func.func.__name__,
            type(node).__name__,
            node.lineno,
            getattr(node, "end_lineno", None),
            getattr(node, "col_offset", None),
            getattr(node, "end_col_offset", None),
            body[0].lineno if isinstance(body, list) and body else None,
        )
        msg = cache.get(key)
        if msg is None:
            msg = cache[key] = orig(self, node)
        return msg

    get_pos_info.cached = True
    ctx.get_pos_info = get_pos_info


def cuda_driver_present():
    """Whether the CUDA driver library loads. Taichi's CUDA probe prints "libcuda.so lib not
    found" as a warning where it does not; without it CUDA is left out of the arches tried."""
    import ctypes
    import sys

    names = {"win32": ("nvcuda.dll",), "darwin": ()}.get(sys.platform, ("libcuda.so.1", "libcuda.so"))
    for name in names:
        try:
            ctypes.CDLL(name)
            return True
        except OSError:
            continue
    return False


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
    gpus = ([ti.cuda] if cuda_driver_present() else []) + [ti.vulkan, ti.metal]
    a = {"cpu": ti.cpu, "gpu": gpus, "auto": gpus}[arch]
    fp = {"f32": ti.f32, "f64": ti.f64}[precision]
    # auto falls back to the CPU silently; gpu says so (the runner logs it too)
    level = ti.ERROR if arch == "auto" else (ti.WARN if quiet else ti.INFO)
    # fast_math on: the pair loop's sums reassociated into the CPU's vector lanes (engine/grid.py,
    # lanes). The price: LLVM orders float operations by the shape of the traced code, so moving
    # a term into another function can change a result in its last bit (the golden states are
    # re-recorded then). The health check's NaN and infinity tests read the bits (Taichi's
    # isnan, isinf), which no float flag can fold away
    kwargs = dict(default_fp=fp, log_level=level, random_seed=0, fast_math=True)
    threads = os.environ.get("TISPH_THREADS")
    if threads:
        kwargs["cpu_max_num_threads"] = int(threads)
    banner = io.StringIO()
    global _finalizer
    with cache_guard(), contextlib.redirect_stdout(banner):  # "[Taichi] Starting on arch=..." -> run.log
        ti.init(arch=a, **kwargs)
    if not _finalizer:
        atexit.register(_finalize)
        _finalizer = True
    cache_debug_info()
    used = arch_name()
    _current = (key, used)
    return used


def describe():
    """One line for logs: Taichi version and the backend in use."""
    return f"taichi {ti.__version__}, arch {current_arch()}"


def current_arch():
    return _current[1] if _current else None


def blocks(m):
    """A two-level pass over m items on a GPU: (items a block, blocks), about sqrt(m) each, so
    the serial part (one thread over the blocks) and each thread's share stay short: at 1.4e6
    cells (the dam break at 1e6 particles) about 1,180 of each, where one thread over every cell
    would take a GPU tenths of a second a step."""
    b = max(256, int(math.ceil(math.sqrt(max(m, 1)))))
    return b, (m + b - 1) // b
