"""The frames' metre axes: round tick values, and the ticks and labels drawn."""

import numpy as np


def nice_ticks(lo, hi, n):
    """About n round values (1, 2 or 5 times a power of ten apart) inside [lo, hi]."""
    span = hi - lo
    if not (span > 0) or n < 1:
        return []
    raw = span / n
    p = 10.0 ** np.floor(np.log10(raw))
    step = next(m * p for m in (1, 2, 5, 10) if m * p >= raw)
    first = np.ceil(lo / step - 1e-9) * step
    vals = np.arange(first, hi + 1e-9 * span, step)
    return [float(round(v, 10)) + 0.0 for v in vals]


def draw_axes(r, d, font, top, H, view):
    """Renderer r's metre ticks: z on the left of a panel, x in the strip under it; the gauges'
    labels at the panel's top and the zones as a bar along its foot."""
    (x0, y0), (x1, y1) = view
    fp = r.font_px
    L = r.LEFT
    q = next(p for p in r.panel_renderers() if p.view == view)  # the panel's own: its scales
    scale, yscale = q.scale, q.yscale
    if q is not r.zoom:
        for x, label in r.marks:
            px = int(round((x - x0) * scale))
            if 0 <= px < r.W - 2 * fp:  # its dotted line drawn, and room for the label
                d.text((L + px + 2, top + 2), label, fill=(0, 0, 0), font=font)
        for a, b, label in r.zones:
            pa, pb = (L + int(round((min(max(v, x0), x1) - x0) * scale)) for v in (a, b))
            if pb > pa:
                d.rectangle([pa, top + H - 4, pb, top + H - 1], fill=(200, 60, 60))
                d.text((pa + 2, top + H - 4 - int(1.2 * fp)), label, fill=(150, 30, 30), font=font)
    for v in nice_ticks(x0, x1, max(2, r.W // (6 * fp))):
        px = L + int(round((v - x0) * scale))
        if px > L + r.W - int(3.0 * fp):
            continue  # room for the axis's unit
        d.line([(px, top + H), (px, top + H + int(0.3 * fp))], fill=(0, 0, 0))
        d.text((px - int(0.6 * fp), top + H + int(0.3 * fp)), f"{v:g}", fill=(0, 0, 0), font=font)
    for v in nice_ticks(y0, y1, max(2, H // (3 * fp))):
        py = top + H - 1 - int(round((v - y0) * yscale))
        if py < top + int(1.6 * fp):
            continue
        d.line([(L - int(0.3 * fp), py), (L - 1, py)], fill=(0, 0, 0))
        d.text((int(0.2 * fp), py - int(0.5 * fp)), f"{v:g}", fill=(0, 0, 0), font=font)
    d.text((L + r.W - int(1.6 * fp), top + H + int(0.3 * fp)), "x (m)", fill=(0, 0, 0), font=font)
    d.text((int(0.2 * fp), top + int(0.1 * fp)), "z (m)", fill=(0, 0, 0), font=font)
