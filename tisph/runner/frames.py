"""The run's frames, stills and movie, drawn and written in a process of their own.

Drawing a frame (the kernel interpolation, the discs, the labels), its PNG and the movie's
pipe take about 0.15 s for the beach (10,839 particles): about 60 s of its 6-minute run when the
stepping waits for them. The stepping uses 1.2 of two cores, so a second process draws while
the solver steps (docs/performance.md, "Frames beside the stepping"). The run reads
the particles and the bed (Renderer.live_inputs) at the frame's time and hands them over; the
drawer, forked with the Renderer as built, keeps its state (the held pressure range, the bed
panel's range) from frame to frame as one renderer does. Where fork is not had (not Linux) or a
window shows the frames (--live), they are drawn in the run's process (Inline)."""

import multiprocessing
import os
import queue
import signal
import sys
import warnings

from ..io import OutputError
from ..viz.files import MovieWriter, write_png
from .pool import die_with_parent

AHEAD = 2  # frames handed over and not yet drawn: the run waits for the drawer past this


class Inline:
    """Frames drawn in the run's process, shown in the live window where there is one."""

    def __init__(self, renderer, movie_path, fps, rebuild=(), live=None):
        self.renderer, self.live = renderer, live
        self.movie = MovieWriter(movie_path, fps)
        _rebuild(self.movie, rebuild)

    def draw(self, path, st, t, movie=True):
        img = _draw(self.renderer, self.movie, path, st, t, None, movie)
        if movie and self.live is not None:
            self.live.show(img)

    def sync(self):
        pass

    def close(self):
        self.movie.close()
        if self.live is not None:
            self.live.close()

    def abort(self):
        self.movie.abort()


def _draw(renderer, movie, path, st, t, live, to_movie):
    """One frame drawn, written as PNG and (to_movie) appended to the movie; returns it."""
    img = renderer.frame(st, t, live)
    write_png(path, img)
    if to_movie:
        movie.append(img)
    return img


def _rebuild(movie, frames):
    """A restart's movie: the frames already on disk first."""
    if frames:
        import imageio.v2 as imageio

        for f in frames:
            if os.path.exists(f):
                movie.append(imageio.imread(f))


def _drawer(renderer, movie_path, fps, rebuild, inbox, outbox, parent):
    # the run's process stops this one (close, abort); a Ctrl-C or SIGTERM sent to the group
    # must not cut a frame or the movie short
    signal.signal(signal.SIGINT, signal.SIG_IGN)
    signal.signal(signal.SIGTERM, signal.SIG_IGN)
    die_with_parent(signal.SIGKILL, parent)
    movie = None
    try:
        movie = MovieWriter(movie_path, fps)
        _rebuild(movie, rebuild)
        while True:
            msg = inbox.get()
            if msg is None:
                movie.close()
                outbox.put(("closed", ""))
                return
            if msg == "sync":
                outbox.put(("synced", ""))
                continue
            _draw(renderer, movie, *msg)
    except BaseException as e:  # told to the run, which stops with it
        if movie is not None:
            movie.abort()
        outbox.put(("error", str(e) if isinstance(e, OutputError) else f"{type(e).__name__}: {e}"))


class Background:
    """Frames drawn in a forked process while the run steps (Inline's interface)."""

    def __init__(self, renderer, movie_path, fps, rebuild=()):
        ctx = multiprocessing.get_context("fork")
        self.renderer = renderer
        self.inbox, self.outbox = ctx.Queue(AHEAD), ctx.Queue()
        self.proc = ctx.Process(
            target=_drawer,
            args=(renderer, movie_path, fps, list(rebuild), self.inbox, self.outbox, os.getpid()),
            daemon=True,
        )
        with warnings.catch_warnings():
            # Python 3.12 warns of fork beside threads (Taichi's); the drawer touches none of
            # their state (NumPy, PIL and ffmpeg only)
            warnings.filterwarnings("ignore", ".*fork", DeprecationWarning)
            self.proc.start()
        self.movie_tmp = MovieWriter.tmp_path(movie_path)

    def _put(self, msg):
        while True:
            self._check()
            try:
                self.inbox.put(msg, timeout=0.5)
                return
            except queue.Full:
                continue

    def _check(self, block=False):
        """The drawer's word ("synced", "closed"; None: none yet), waiting for one where block;
        raises its error, or that it died without a word."""
        while True:
            alive = self.proc.is_alive()
            try:  # a dead drawer's last word may still be on the way: a second for it
                kind, text = self.outbox.get(timeout=1.0) if block or not alive else self.outbox.get_nowait()
                break
            except queue.Empty:
                if not alive:
                    raise OutputError(f"the frames' process stopped (exit code {self.proc.exitcode})") from None
                if not block:
                    return None
        if kind == "error":
            raise OutputError(f"drawing the frames: {text}")
        return kind

    def draw(self, path, st, t, movie=True):
        self._put((path, st, t, self.renderer.live_inputs(), movie))

    def sync(self):
        """Back when every frame handed over is on disk (before a checkpoint names them)."""
        self._put("sync")
        while self._check(block=True) != "synced":
            pass

    def close(self):
        self._put(None)
        while self._check(block=True) != "closed":
            pass
        self.proc.join()

    def abort(self):
        if self.proc.is_alive():
            self.proc.kill()
        self.proc.join()
        if os.path.exists(self.movie_tmp):
            os.unlink(self.movie_tmp)


def open_frames(renderer, movie_path, fps, rebuild=(), live=None):
    """Background where the platform forks and no window shows the frames, else Inline."""
    if live is None and sys.platform.startswith("linux") and os.environ.get("TISPH_INLINE_FRAMES") != "1":
        return Background(renderer, movie_path, fps, rebuild)
    return Inline(renderer, movie_path, fps, rebuild, live)
