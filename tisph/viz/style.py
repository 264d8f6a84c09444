"""How a frame is drawn: everything a Renderer needs beside the view it shows, in one value a
scene's Picture and the [output] table make (render.make_renderer)."""

import dataclasses
from typing import Callable


@dataclasses.dataclass(frozen=True)
class Style:
    """width: px of a panel; dx: the particle spacing (a disc's size, the kernel image's h);
    speed_scale: the top of the speed bar (the scene's expected peak speed; 0: each frame's 99th
    percentile); modes: the stacked panels' fields (render.MODES); mat_colors: per material an RGB
    colour (sediment) or None (by the field); pressure_scale: the pressure bar's top (0: the first
    frame's); vrange: (lo, hi) of the colour bar, overriding the scales; min_height: a panel
    shorter than this (px) gets more room above the view (air); bed_panel, bed_label, bed_range:
    the bed change's panel under the frame; bed_surface(x): sand filled under it; zoom: a window
    ((x0, y0), (x1, y1)) at true scale under the frame, coloured by zoom_field; axes: metre axes;
    marks: (x, label) of gauges; zones: (x0, x1, label) bars; rows: a long view drawn in rows;
    solid_region(points): the solids filled as drawn, their wall particles left out; exaggeration:
    heights drawn this many times the lengths' scale (stated in the title; the zoom stays true)."""

    width: int = 640
    dx: float = 0.01
    speed_scale: float = 0.0
    title: str = ""
    modes: tuple = ("speed",)
    mat_colors: tuple = None
    pressure_scale: float = 0.0
    vrange: tuple = None
    min_height: int = 0
    bed_panel: Callable = None
    bed_label: str = ""
    bed_range: float = 0.0
    bed_surface: Callable = None
    zoom: tuple = None
    zoom_field: str = "vorticity"
    axes: bool = True
    marks: tuple = ()
    zones: tuple = ()
    rows: bool = True
    solid_region: Callable = None
    exaggeration: float = 1.0


def style_of(pic, outc, dx, title, speed_scale):
    """(view, Style) of a scene's Picture and the [output] table (view, field, range, width, zoom)."""
    view = pic.view
    if outc.get("view"):
        x0, x1, y0, y1 = outc["view"]
        view = ((x0, y0), (x1, y1))
    modes = (outc["field"],) if outc.get("field") else pic.render_modes
    zoom = pic.zoom
    if outc.get("zoom"):
        x0, x1, y0, y1 = outc["zoom"]
        zoom = ((x0, y0), (x1, y1))
    return view, Style(
        width=outc["width"],
        dx=dx,
        speed_scale=speed_scale,
        title=title,
        modes=modes,
        mat_colors=pic.mat_colors,
        pressure_scale=pic.pressure_scale,
        bed_panel=pic.bed_panel,
        bed_label=pic.bed_label,
        vrange=outc.get("range") or None,
        min_height=outc.get("min_height", 0),
        bed_surface=pic.bed_surface,
        zoom=zoom,
        marks=pic.marks,
        zones=pic.zones,
        bed_range=pic.bed_range,
        solid_region=pic.solid_region,
        exaggeration=outc.get("exaggeration", 1.0),
    )
