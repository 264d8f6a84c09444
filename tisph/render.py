"""Offscreen rendering: a Taichi kernel splats particles into an image (no window, no Vulkan);
PIL adds the time label and colour bar; imageio writes PNG frames and an MP4 (imageio-ffmpeg)."""
import os
import warnings

import numpy as np
import taichi as ti

from .io import atomic_path, OutputError
from .particles import BED, FLUID

# Viridis, sampled at 9 points (matplotlib's data), interpolated linearly.
_VIRIDIS = np.array([
    [0.267, 0.005, 0.329], [0.283, 0.141, 0.458], [0.254, 0.265, 0.530], [0.207, 0.372, 0.553],
    [0.164, 0.471, 0.558], [0.128, 0.567, 0.551], [0.135, 0.659, 0.518], [0.478, 0.821, 0.318],
    [0.993, 0.906, 0.144]])
BACKGROUND = (1.0, 1.0, 1.0)
BOUNDARY = (0.55, 0.55, 0.55)
WATER = (0.36, 0.62, 0.90)
SAND = (0.86, 0.70, 0.42)
MODES = {"speed": 0, "phase": 1, "flat": 2, "pressure": 3}


def colormap(values):
    """Viridis RGB in [0, 1] for values in [0, 1] (clipped)."""
    v = np.clip(np.asarray(values, float), 0, 1) * (len(_VIRIDIS) - 1)
    i = np.minimum(v.astype(int), len(_VIRIDIS) - 2)
    f = (v - i)[..., None]
    return _VIRIDIS[i] * (1 - f) + _VIRIDIS[i + 1] * f


@ti.data_oriented
class Renderer:
    """Draws a solver's particles, grey boundaries, fluid in one or more stacked panels:
    "speed" colours every fluid by speed; "phase" draws materials that have a colour (sediment)
    in it, darker where they move, and the rest (water) by speed; "flat" gives every material
    its plain colour (water blue, sediment sand); "pressure" colours every fluid by its pressure
    (0 to pressure_scale)."""

    BAR = 96  # colour-bar strip width in pixels

    def __init__(self, solver, view, width=640, speed_scale=1.0, title="", modes=("speed",),
                 mat_colors=None, pressure_scale=0.0):
        (x0, y0), (x1, y1) = view
        self.solver = solver
        self.view = ((float(x0), float(y0)), (float(x1), float(y1)))
        W = max(16, int(width) // 16 * 16)
        H = max(16, int(round(W * (y1 - y0) / (x1 - x0) / 16)) * 16)
        self.W, self.H = W, H
        self.scale = W / (x1 - x0)
        self.radius = max(1.0, 0.8 * solver.dx * self.scale)
        self.speed_scale = float(speed_scale)
        self.title = title
        self.img = ti.Vector.field(3, ti.f32, shape=(W, H))
        self.lut = ti.Vector.field(3, ti.f32, shape=256)
        self.lut.from_numpy(colormap(np.linspace(0, 1, 256)).astype(np.float32))
        for m in modes:
            if m not in MODES:
                raise ValueError(f"render mode {m!r}: expected one of {sorted(MODES)}")
        self.modes = tuple(modes)
        self.pressure_scale = float(pressure_scale) if pressure_scale > 0 else 1000.0 * 9.81 * (y1 - y0)
        nmat = len(solver.materials)
        cols = list(mat_colors or [None] * nmat)
        self.mcol = ti.Vector.field(3, ti.f32, shape=nmat)
        self.has_col = ti.field(ti.i32, shape=nmat)
        for k in range(nmat):
            c = cols[k] if k < len(cols) else None
            self.has_col[k] = int(c is not None)
            self.mcol[k] = c if c is not None else (WATER if k == 0 else SAND)

    @ti.kernel
    def _draw(self, vmax: ti.f32, mode: ti.i32, pmax: ti.f32):
        for I in ti.grouped(self.img):
            self.img[I] = ti.Vector(BACKGROUND)
        p = self.solver.p
        for i in range(self.solver.n):
            k = p.kind[i]
            if k >= 0:
                col = ti.Vector(BOUNDARY)
                if k == BED:
                    col = ti.Vector(SAND)
                if k == FLUID:
                    s = ti.min(p.v[i].norm() / vmax, 1.0)
                    col = self.lut[ti.cast(s * 255.0, ti.i32)]
                    mt = p.mat[i]
                    if mode == 2:
                        col = self.mcol[mt]
                    elif mode == 3:
                        sp = ti.min(ti.max(p.p[i] / pmax, 0.0), 1.0)
                        col = self.lut[ti.cast(sp * 255.0, ti.i32)]
                    elif mode == 1 and self.has_col[mt] == 1:
                        col = self.mcol[mt] * (1.0 - 0.45 * s)
                cx = (p.x[i][0] - self.view[0][0]) * self.scale
                cy = (p.x[i][1] - self.view[0][1]) * self.scale
                r = self.radius
                for px in range(ti.cast(ti.floor(cx - r), ti.i32), ti.cast(ti.ceil(cx + r), ti.i32) + 1):
                    for py in range(ti.cast(ti.floor(cy - r), ti.i32), ti.cast(ti.ceil(cy + r), ti.i32) + 1):
                        if 0 <= px < self.W and 0 <= py < self.H:
                            ddx = px + 0.5 - cx
                            ddy = py + 0.5 - cy
                            if ddx * ddx + ddy * ddy <= r * r:
                                self.img[px, py] = col

    def frame(self, t):
        """RGB uint8 image (rows top to bottom) of the current state, annotated."""
        panels = []
        for m in self.modes:
            self._draw(self.speed_scale, MODES[m], self.pressure_scale)
            core = (np.clip(self.img.to_numpy(), 0, 1) * 255).astype(np.uint8)
            panels.append(np.flipud(core.transpose(1, 0, 2)))
        core = np.ascontiguousarray(np.concatenate(panels, axis=0))
        Ht = core.shape[0]
        bar = np.full((Ht, self.BAR, 3), 255, np.uint8)
        top, bot = int(0.15 * Ht), int(0.85 * Ht)
        if bot - top > 4:
            ramp = colormap(np.linspace(1, 0, bot - top))
            bar[top:bot, 12:32] = (ramp[:, None, :] * 255).astype(np.uint8)
        img = np.concatenate([core, bar], axis=1)
        return self._annotate(img, t, top, bot)

    def _annotate(self, img, t, top, bot):
        from PIL import Image, ImageDraw, ImageFont
        im = Image.fromarray(img)
        d = ImageDraw.Draw(im)
        try:
            font = ImageFont.load_default(size=max(10, self.H // 40))
        except TypeError:  # Pillow < 10.1
            font = ImageFont.load_default()
        label = f"t = {t:.3f} s"
        if self.title:
            label = f"{self.title}   {label}"
        d.text((8, 6), label, fill=(0, 0, 0), font=font)
        bx = self.W + 36
        d.text((bx, top - 4), f"{self.speed_scale:.2g}", fill=(0, 0, 0), font=font)
        d.text((bx, bot - 10), "0", fill=(0, 0, 0), font=font)
        d.text((self.W + 6, top - 26), "|u| m/s", fill=(0, 0, 0), font=font)
        if "pressure" in self.modes:   # the same bar reads 0 to pressure_scale in the pressure panel
            d.text((self.W + 6, bot + 8), f"p: 0-{self.pressure_scale / 1000:.2g} kPa", fill=(0, 0, 0), font=font)
        return np.asarray(im)


def write_png(path, img):
    import imageio.v2 as imageio
    try:
        with atomic_path(path) as tmp:
            imageio.imwrite(tmp, img, format="PNG")
    except OSError as e:
        raise OutputError(f"cannot write {path!r}: {e}") from None


class MovieWriter:
    """MP4 through imageio-ffmpeg, written under a temporary name and renamed on close."""

    def __init__(self, path, fps):
        import imageio.v2 as imageio
        self.path = path
        d = os.path.dirname(os.path.abspath(path))
        self.tmp = os.path.join(d, "." + os.path.basename(path) + ".part.mp4")
        self.writer = None
        try:
            self.writer = imageio.get_writer(self.tmp, format="FFMPEG", fps=fps, codec="libx264",
                                             pixelformat="yuv420p", macro_block_size=16,
                                             ffmpeg_log_level="error", quality=7)
        except Exception as e:  # no ffmpeg binary: frames are still written
            warnings.warn(f"MP4 disabled: {e}")

    def append(self, img):
        if self.writer is not None:
            self.writer.append_data(img)

    def close(self):
        if self.writer is not None:
            self.writer.close()
            self.writer = None
            os.replace(self.tmp, self.path)

    def abort(self):
        if self.writer is not None:
            try:
                self.writer.close()
            finally:
                self.writer = None
                if os.path.exists(self.tmp):
                    os.unlink(self.tmp)
