"""Offscreen rendering: NumPy draws particles from arrays into an image, the water's field
interpolated by the kernel (tisph/viz/interpolate.py), the rest as discs (no window, no GPU; the
live run and tisph.view share it); PIL adds the labels and colour bars; tisph/viz/files.py writes
the PNG frames and the MP4."""

import dataclasses

import numpy as np

from ..io import OPTIONAL
from ..particles import BED, FLUID, WALL
from .colours import BACKGROUND, BOUNDARY, MODES, SAND, WATER, colormap, colour_range, diverging, field_values
from .interpolate import kernel_image
from .style import Style, style_of
from .ticks import draw_axes, nice_ticks  # noqa: F401 (re-exported)

FIELDS = ("speed", "pressure", "density", "material", "vorticity", "concentration")  # output.field
UNITS = {
    "speed": "|u| (m/s)",
    "pressure": "p (kPa)",
    "density": "rho (kg/m3)",
    "vorticity": "curl u (1/s)",
    "concentration": "sand (%, log)",
}
STATE = ("x", "v", "p", "rho", "kind", "mat")  # what a frame reads (and io.OPTIONAL where a case has it)


class Renderer:
    """Draws particles from arrays (a solver's state or a snapshot's), so the live run and
    tisph.view make the same picture: grey boundaries, BED particles sand, fluid in one or more
    stacked panels. Panels: "speed" colours every fluid by speed; "phase" draws materials that
    have a colour (sediment) in it, darker where they move, and water by speed; "flat" (or
    "material") gives every material its plain colour; "pressure", "density" and "vorticity"
    colour every fluid by that field. A header strip carries the title and time, a side strip
    the colour bar with its title; text scales with the width and never covers particles.

    How it draws is its Style (viz/style.py). The colour bars: the style's vrange, or speed from
    speed_scale, pressure from pressure_scale or the first frame's (held for the movie), vorticity
    from speed_scale over 10 dx, density from robust percentiles of each frame."""

    def __init__(self, view, style=None):
        s = style or Style()
        dx, modes = s.dx, s.modes
        (x0, y0), (x1, y1) = view
        self.exaggeration = E = float(s.exaggeration)
        aspect = (x1 - x0) / (E * (y1 - y0))  # as drawn, before any air is added
        W = max(16, int(s.width) // 16 * 16)
        self.scale = W / (x1 - x0)
        self.yscale = E * self.scale  # px a metre of height
        H = max(16, int(round((y1 - y0) * self.yscale / 16)) * 16)
        if s.min_height > H:
            H = int(np.ceil(s.min_height / 16)) * 16
            y1 = y0 + H / self.yscale
        self.view = ((float(x0), float(y0)), (float(x1), float(y1)))
        self.W, self.H = W, H
        self.radius = max(1.0, 0.9 * dx * self.scale)
        self.dx = dx
        self.speed_scale = float(s.speed_scale)
        self.title = s.title
        for m in modes:
            if m not in MODES:
                raise ValueError(f"render mode {m!r}: expected one of {sorted(MODES)}")
        self.modes = tuple(modes)
        self.vrange = tuple(s.vrange) if s.vrange else None
        self.pressure_scale = float(s.pressure_scale)  # 0: from the water in view in the first frame
        self.mat_colors = list(s.mat_colors or [])
        self.bed_panel, self.bed_label, self.bed_surface = s.bed_panel, s.bed_label, s.bed_surface
        self._live = (None, None)  # this frame's bed surface and bed change (live_inputs)
        # the solids filled as drawn, not their wall particles (a slope's are stairs a spacing high)
        self.solid_region, self._solid_px, self._walls = s.solid_region, None, None
        # m: the bed panel's half-height: the step that holds bed_range, fixed for the movie; or, with
        # none given, the step that holds the bed so far, only ever growing
        self.bed_fixed = s.bed_range > 0
        self.bed_range = (
            next((r for r in self.BED_RANGE if s.bed_range <= r), self.BED_RANGE[-1]) if self.bed_fixed else 0.0
        )
        self.font_px = max(11, W // 85)
        self.BAR = int(np.ceil(7 * self.font_px / 16)) * 16  # strips in multiples of 16 px (the MP4's blocks)
        self.strip = int(np.ceil(1.8 * self.font_px / 16)) * 16
        r, ry = int(np.ceil(self.radius)), int(np.ceil(self.radius * E))
        oy, ox = np.mgrid[-ry : ry + 1, -r : r + 1]
        keep = ox**2 + (oy / E) ** 2 <= self.radius**2  # a disc drawn E times as tall
        self.offsets = np.column_stack([ox[keep], oy[keep]])
        self.bars = []  # (title, lo, hi, cmap) of each panel's colour bar, None: none
        self._speed_hi = max(self.speed_scale, 1e-6)
        # metre axes: a strip left of the panels for z, one under each particle panel for x
        self.LEFT = int(np.ceil(4.2 * self.font_px / 16)) * 16 if s.axes else 0
        self.AXIS = self.strip if s.axes else 0
        # a window at true scale under the rest (the beach's ripples), its own colour field
        self.zoom = None
        if s.zoom is not None:
            self.zoom = Renderer(
                s.zoom,
                Style(
                    width=W,
                    dx=dx,
                    speed_scale=s.speed_scale,
                    modes=(s.zoom_field,),
                    axes=False,
                    bed_surface=s.bed_surface,
                    solid_region=s.solid_region,
                ),
            )
        self.panels = []  # (top row, height, view, bar) of each panel of the last frame
        self.marks, self.zones = tuple(s.marks), tuple(s.zones)
        # a long view (a flume) in rows, each a stretch of it at a readable scale, where it is the
        # frame's one panel (no second field, bed panel or zoom window along the whole length)
        self.rows = []
        n = int(np.ceil(np.sqrt(aspect / self.ROW_ASPECT)))
        if n > 1 and s.rows and s.bed_panel is None and s.zoom is None and len(modes) == 1:
            n = min(n, self.MAX_ROWS)
            step = (x1 - x0) / n
            y1 = view[1][1]
            part = dataclasses.replace(s, title="", rows=False)
            self.rows = [Renderer(((x0 + i * step, y0), (x0 + (i + 1) * step, y1)), part) for i in range(n)]

    @property
    def left(self):
        """Columns left of the panels (the z axis)."""
        return self.LEFT

    @property
    def panel_top(self):
        """The first panel's top row in a frame (below the title strip)."""
        return self.strip

    def _colour_range(self, field, values):
        if field == "pressure" and not self.vrange and not self.pressure_scale and len(values):
            self.pressure_scale = max(float(np.percentile(values, 99.5)), 1e-6)  # the first frame's, then held
        return colour_range(field, values, self.vrange, self.speed_scale, self.pressure_scale, self.dx)

    def _colours(self, mode, st):
        """Each particle's colour, and the field drawn continuous: (which particles, their value
        in 0-1 of the colour bar, the colour map), or None."""
        field_image = None
        kind, mat = st["kind"], st["mat"]
        fl = kind == FLUID
        col = np.tile(np.array(BOUNDARY), (len(kind), 1))
        col[kind == BED] = SAND
        field = {"phase": "speed", "flat": None, "material": None}.get(mode, mode)
        speed = np.hypot(st["v"][:, 0], st["v"][:, 1])
        if field is not None:
            vals = field_values(field, st, speed, fl, self.dx)
            (x0, y0), (x1, y1) = self.view  # the range from what the panel shows
            seen = fl & (st["x"][:, 0] >= x0) & (st["x"][:, 0] <= x1) & (st["x"][:, 1] >= y0) & (st["x"][:, 1] <= y1)
            lo, hi = self._colour_range(field, vals[seen if seen.any() else fl])
            if field == "concentration":
                s01 = np.log10(np.maximum(vals[fl], lo) / lo) / np.log10(hi / lo)
            else:
                s01 = (vals[fl] - lo) / (hi - lo)
            cmap = diverging if field == "vorticity" else colormap
            col[fl] = cmap(s01)
            # drawn continuous: every fluid in a field panel, the water (no colour of its own) in phase
            smooth = fl.copy()
            if mode == "phase":
                own = [k for k in range(len(self.mat_colors)) if self.mat_colors[k] is not None]
                smooth &= ~np.isin(mat, own)
            vals01 = np.zeros(len(kind))
            vals01[fl] = s01
            field_image = (smooth, vals01, cmap)
            unit = UNITS[field]
            if field == "pressure":
                lo, hi = lo / 1000.0, hi / 1000.0
            self.bars.append((unit, lo, hi, cmap))
            if field == "speed":
                self._speed_hi = hi
        else:
            self.bars.append(None)
        flat = field is None or mode == "phase"
        for k in np.unique(mat[fl]) if flat else ():
            c = self.mat_colors[k] if k < len(self.mat_colors) else None
            sel = fl & (mat == k)
            if mode == "phase" and c is None:
                continue  # water keeps its speed colour
            base = np.array(c if c is not None else (WATER if k == 0 else SAND))
            shade = 1.0 - 0.45 * np.minimum(speed[sel] / self._speed_hi, 1.0) if mode == "phase" else 1.0
            col[sel] = base * (shade[:, None] if mode == "phase" else 1.0)
        return col, field_image

    ROW_ASPECT, MAX_ROWS = 6.0, 3  # a view longer than ROW_ASPECT heights is drawn in rows (at most MAX_ROWS)

    def _splat(self, st, col, field_image=None):
        """The panel: sand under a bed surface, the field's fluid interpolated by the kernel onto
        the pixels (Shepard-normalised, cut where the water ends), every other particle a disc."""
        img = np.full((self.H, self.W, 3), (np.array(BACKGROUND) * 255).astype(np.uint8), np.uint8)
        (x0, y0), _ = self.view
        if self.bed_surface is not None:  # a bed below particle scale: sand under its surface
            zb = self._live[0]
            top = np.clip(np.floor((zb - y0) * self.yscale).astype(int), 0, self.H)
            rows = np.arange(self.H)[:, None]
            img[(self.H - 1 - rows) < top[None, :]] = (np.array(SAND) * 255).astype(np.uint8)
        smooth = np.zeros(len(st["kind"]), bool)
        if field_image is not None and field_image[0].any():
            smooth, s01, cmap = field_image
            val, inside = kernel_image(
                st["x"][smooth], s01[smooth], (x0, y0), self.scale, self.dx, self.W, self.H, self.exaggeration
            )
            lut = (np.clip(cmap(np.linspace(0.0, 1.0, 256)), 0, 1) * 255).astype(np.uint8)
            img[inside] = lut[(np.clip(val[inside], 0.0, 1.0) * 255 + 0.5).astype(np.uint8)]
        hidden = np.zeros(len(st["kind"]), bool)
        if self.solid_region is not None:  # over the water's field, which the kernel spreads into it
            img[self._solid_pixels()] = (np.array(BOUNDARY) * 255).astype(np.uint8)
            hidden = self._hidden_walls(st)
        cx = np.floor((st["x"][:, 0] - x0) * self.scale).astype(int)
        cy = np.floor((st["x"][:, 1] - y0) * self.yscale).astype(int)
        order = np.argsort(st["kind"] == FLUID, kind="stable")  # boundaries first, fluid on top
        order = order[~(smooth | hidden)[order]]
        inview = (
            (cx[order] > -self.radius - 2)
            & (cx[order] < self.W + self.radius + 2)
            & (cy[order] > -self.radius * self.exaggeration - 2)
            & (cy[order] < self.H + self.radius * self.exaggeration + 2)
        )
        order = order[inview]
        c8 = (np.clip(col[order], 0, 1) * 255).astype(np.uint8)
        for ox, oy in self.offsets:
            px, py = cx[order] + ox, cy[order] + oy
            ok = (px >= 0) & (px < self.W) & (py >= 0) & (py < self.H)
            img[self.H - 1 - py[ok], px[ok]] = c8[ok]
        return img

    def _hidden_walls(self, st):
        """The wall particles inside the solids, worked out again only when the walls moved."""
        walls = st["kind"] == WALL
        xw = st["x"][walls]
        if self._walls is None or not np.array_equal(self._walls[0], xw):
            hidden = walls.copy()
            hidden[walls] = self.solid_region(xw)
            self._walls = (xw.copy(), hidden)
        return self._walls[1]

    def _solid_pixels(self):
        """The pixels (rows top to bottom) inside the solids, worked out once: they do not move."""
        if self._solid_px is None:
            (x0, y0), _ = self.view
            X, Y = np.meshgrid(
                x0 + (np.arange(self.W) + 0.5) / self.scale, y0 + (np.arange(self.H) + 0.5) / self.yscale
            )
            inside = self.solid_region(np.column_stack([X.ravel(), Y.ravel()]))
            self._solid_px = inside.reshape(self.H, self.W)[::-1]
        return self._solid_px

    def panel_renderers(self):
        """This renderer, its rows and its zoom window: each draws a panel at its own scales."""
        return [self, *self.rows] + ([self.zoom] if self.zoom is not None else [])

    def live_inputs(self):
        """What a frame reads from the running case besides its particles: the bed below particle
        scale (its surface at each panel's pixel columns, its change along the view). Read where
        the case runs, so another process can draw the frame (runner/frames.py)."""
        out = []
        for r in self.panel_renderers():
            (x0, _), (x1, _) = r.view
            z = r.bed_surface(x0 + (np.arange(r.W) + 0.5) / r.scale) if r.bed_surface is not None else None
            out.append((z, r.bed_panel(x0, x1, r.W) if r.bed_panel is not None else None))
        return out

    def frame(self, st, t, live=None):
        """RGB uint8 image (rows top to bottom) of the state st (arrays x, v, p, rho, kind, mat);
        live: live_inputs() as read with st (read now where not given)."""
        for r, v in zip(self.panel_renderers(), live if live is not None else self.live_inputs()):
            r._live = v
        self.bars = []
        st = {k: np.asarray(v) for k, v in st.items() if k in STATE or k in OPTIONAL}
        st["x"] = st["x"][:, :2]
        st["v"] = st["v"][:, :2]
        W = self.W

        def strip(h):
            return np.full((h, W, 3), 255, np.uint8)

        blocks, self.panels, row = [strip(self.strip)], [], self.strip
        for m in self.modes:
            col, field_image = self._colours(m, st)
            for k, r in enumerate(self.rows or [self]):  # the colours from the whole view, one bar
                img = r._splat(st, col, field_image)
                if self.zoom is not None:
                    self._outline(img, self.zoom.view)
                for x, _ in self.marks:  # gauges: a dotted line across the panel
                    i = int(round((x - r.view[0][0]) * r.scale))
                    if 0 <= i < W:
                        img[::4, i] = 30
                self.panels.append((row, r.H, r.view, self.bars[-1] if k == 0 else None))
                blocks += [img, strip(self.AXIS)]
                row += r.H + self.AXIS
        self.bed_row = None
        if self.bed_panel is not None:
            bed = self._bed_image()
            self.bed_row = row
            blocks += [bed, strip(self.strip)]
            row += bed.shape[0] + self.strip
        self.zoom_row = None
        if self.zoom is not None:
            z = self.zoom
            z.bars = []
            img = z._splat(st, *z._colours(z.modes[0], st))
            self.zoom_row = row
            self.panels.append((row + self.strip, z.H, z.view, z.bars[-1]))
            blocks += [strip(self.strip), img, strip(self.AXIS)]
        body = np.concatenate(blocks, axis=0)
        left = np.full((body.shape[0], self.LEFT, 3), 255, np.uint8)
        side = np.full((body.shape[0], self.BAR, 3), 255, np.uint8)
        img = np.ascontiguousarray(np.concatenate([left, body, side], axis=1))
        return self._annotate(img, t)

    def _outline(self, img, view):
        """A dark rectangle round the part of a panel that `view` shows (the zoom window)."""
        (x0, y0), _ = self.view
        (a, b), (c, d) = view
        i0, i1 = (int(np.clip((v - x0) * self.scale, 0, self.W - 1)) for v in (a, c))
        j0, j1 = (int(np.clip(self.H - 1 - (v - y0) * self.yscale, 0, self.H - 1)) for v in (d, b))
        img[j0 : j1 + 1, [i0, i1]] = 40
        img[[j0, j1], i0 : i1 + 1] = 40

    BED_RANGE = (0.005, 0.01, 0.02, 0.04, 0.08, 0.16)  # m: the bed panel's half-height steps

    def _bed_image(self):
        """The bed change along the view as a sand profile about a zero line, vertically
        exaggerated: the range grows in steps so the scale holds still while the bed changes."""
        dz = np.asarray(self._live[1][1], float)  # bed_panel(x0, x1, W): (x, change)
        peak = float(np.nanmax(np.abs(dz))) if np.isfinite(dz).any() else 0.0
        if not self.bed_fixed:
            rng = next((r for r in self.BED_RANGE if peak <= 0.9 * r), self.BED_RANGE[-1])
            self.bed_range = max(self.bed_range, rng)
        Hp = max(48, self.W // 8) // 16 * 16
        img = np.full((Hp, self.W, 3), 255, np.uint8)
        rows = np.arange(Hp)[:, None]  # 0 at the top
        level = 0.5 * Hp * (1.0 - np.nan_to_num(dz) / self.bed_range)
        level = np.clip(level, 0, Hp - 1)  # a fixed scale clips what exceeds it
        sand = (rows >= level[None, :]) & np.isfinite(dz)[None, :]
        img[sand] = (np.array(SAND) * 255).astype(np.uint8)
        img[Hp // 2, :] = (110, 110, 110)
        self.bed_exaggeration = (0.5 * Hp / self.bed_range) / self.scale  # against the lengths' scale
        self._bed_h = Hp
        return img

    def title_line(self, t):
        """The header: the title, a vertical exaggeration where there is one, the time."""
        label = f"t = {t:.3f} s"
        if self.exaggeration != 1.0:
            label = f"heights x{self.exaggeration:g}   {label}"
        return f"{self.title}   {label}" if self.title else label

    def _annotate(self, img, t):
        from PIL import Image, ImageDraw, ImageFont

        im = Image.fromarray(img)
        d = ImageDraw.Draw(im)
        fp = self.font_px
        try:
            font = ImageFont.load_default(size=fp)
        except TypeError:  # Pillow < 10.1
            font = ImageFont.load_default()
        L = self.LEFT
        label = self.title_line(t)
        d.text((L + 6, int(0.35 * fp)), label, fill=(0, 0, 0), font=font)
        for top, H, view, bar in self.panels:  # one colour bar per coloured panel, beside it
            if self.LEFT:
                draw_axes(self, d, font, top, H, view)
            if bar is None:
                continue
            title, lo, hi, cmap = bar
            y0, y1 = top + int(1.4 * fp), top + H - int(0.6 * fp)
            xb = L + self.W
            if y1 - y0 > 4:
                ramp = cmap(np.linspace(1, 0, y1 - y0))
                img_bar = (ramp[:, None, :] * 255).astype(np.uint8).repeat(int(0.9 * fp), axis=1)
                im.paste(Image.fromarray(np.ascontiguousarray(img_bar)), (xb + int(0.4 * fp), y0))
            d.text((xb + int(0.3 * fp), top + int(0.15 * fp)), title, fill=(0, 0, 0), font=font)
            d.text((xb + int(1.6 * fp), y0 - int(0.2 * fp)), f"{hi:.3g}", fill=(0, 0, 0), font=font)
            d.text((xb + int(1.6 * fp), y1 - fp), f"{lo:.3g}", fill=(0, 0, 0), font=font)
        if self.bed_panel is not None:
            d.text(
                (L + 6, self.bed_row + self._bed_h + int(0.2 * fp)),
                f"bed change above, vertical x{self.bed_exaggeration:.0f} (+-{100 * self.bed_range:g} cm)"
                f"{self.bed_label}",
                fill=(0, 0, 0),
                font=font,
            )
        if self.zoom is not None:
            (a, b), (c, e) = self.zoom.view
            d.text(
                (L + 6, self.zoom_row + int(0.35 * fp)),
                f"x = {a:g} to {c:g} m at true scale (the box above), coloured by {self.zoom.modes[0]}",
                fill=(0, 0, 0),
                font=font,
            )
        return np.asarray(im)


def make_renderer(pic, outc, dx, title, speed_scale):
    """The Renderer for a scene's Picture and the [output] table (view, field, range, width)."""
    return Renderer(*style_of(pic, outc, dx, title, speed_scale))
