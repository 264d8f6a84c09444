"""--live: a window that shows each frame as it is rendered (Taichi's ti.GUI), for every scene and
for `python -m tisph.view --all`. Off by default; without a display it is refused up front."""

import ctypes
import ctypes.util
import os
import sys

import numpy as np

RUN_FILES = "look at OUT/frames/ and OUT/<scene>.mp4, or render the snapshots again with python -m tisph.view OUT --all"


def display_problem(instead=RUN_FILES):
    """None where a window can open; otherwise why not, and where the pictures are `instead`. On
    Linux the X display is opened and closed again (a set DISPLAY that no server answers is no
    display)."""
    if sys.platform in ("darwin", "win32"):
        return None
    name = os.environ.get("DISPLAY", "")
    hint = (
        "--live needs a display to open a window; this machine has {} The frames are written all the same: " + instead
    ).format
    if not name:
        return hint("none (no DISPLAY).")
    lib = ctypes.util.find_library("X11")
    if lib is None:
        return None  # cannot check here; Taichi's GUI reports it if the display fails
    x11 = ctypes.CDLL(lib)
    x11.XOpenDisplay.restype = ctypes.c_void_p
    x11.XOpenDisplay.argtypes = [ctypes.c_char_p]
    x11.XCloseDisplay.argtypes = [ctypes.c_void_p]
    d = x11.XOpenDisplay(name.encode())
    if not d:
        return hint(f"none (DISPLAY={name} does not answer).")
    x11.XCloseDisplay(d)
    return None


class LiveWindow:
    """One window for a run's frames, opened at the first frame at its size. Closing the window
    stops showing frames; the run goes on and writes every file."""

    def __init__(self, title):
        self.title, self.gui, self.closed = title, None, False

    def show(self, img):
        if self.closed:
            return
        import taichi as ti

        h, w = img.shape[:2]
        if self.gui is None:
            self.gui = ti.GUI(self.title, res=(w, h), show_gui=True, fast_gui=False)
        if not self.gui.running:
            self.closed = True
            self.gui.close()
            return
        # ti.GUI indexes [x, y] from the lower left; a picture is [row, column] from the top
        self.gui.set_image(np.ascontiguousarray(img[::-1, :, :3].transpose(1, 0, 2)).astype(np.float32) / 255.0)
        self.gui.show()

    def close(self):
        if self.gui is not None and not self.closed:
            self.gui.close()
        self.closed = True
