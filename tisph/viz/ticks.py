"""Round tick values for the frames' metre axes."""
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
