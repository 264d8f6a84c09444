"""Steps in batches with no read of the device between them (access.py, step_ahead): the batch's
size, how its log is read, and a smooth function of time (the paddle's motion, a held current's
law) as a Chebyshev series over a batch, fitted on the host (series_fit) and evaluated by the
device (series_at)."""

import numpy as np
import taichi as ti

# the most steps the host launches between two reads of the device: on a GPU, where the steps
# after an output park (stepper.py), enough for the steps between two outputs; on the CPU the
# most it takes between two looks at a signal or the progress bar
BATCH = 512
BATCH_CPU = 64
# a batch given a time to reach stops its f32 sum this much short (step_ahead)
STOP_SHORT = 1.0 - 1e-4
# on the CPU a batch of up to this many steps reads its log element by element (5 us each); a
# longer one, and any on a GPU (where each read waits for the device), in one to_numpy (about
# 100 us on the CPU)
READ_ELEMENTS = 16
# the degree of the Chebyshev series over a batch
CHEB = 8


# the device's copy of a fit: the first piece's two series and where it ends, then the second
# piece's and the batch's span
PFIT = 4 * CHEB + 6


def series_fit(motion, t0, span, breaks=None):
    """Chebyshev series of motion(t) = two values (the paddle's displacement and rate; a held
    current's target and feedforward) over [t0, t0 + span], for the device to evaluate at each
    step's time, in two pieces where one of its kinks (breaks, else motion.breaks: the ramp's end,
    the ramp down's) falls inside: the PFIT values of a fit, or None where two kinks do, or a
    piece misses the motion by more than 3e-8 of its largest value at 4 points between each pair
    of nodes (fit_steps then tries fewer steps)."""
    breaks = getattr(motion, "breaks", ()) if breaks is None else breaks
    inside = [b - t0 for b in breaks if t0 < b < t0 + span]
    if len(inside) > 1:
        return None
    split = inside[0] if inside else span
    first = _series(motion, t0, split)
    second = _series(motion, t0 + split, span - split) if inside else first
    if first is None or second is None:
        return None
    return first + (split,) + second + (span,)


def _series(motion, t0, span):
    """The displacement's and the rate's series over [t0, t0 + span] (2 (CHEB + 1) values), or None."""
    cheb = np.polynomial.chebyshev
    nodes = np.cos(np.pi * (np.arange(CHEB + 1) + 0.5) / (CHEB + 1))
    at = lambda x: np.array([motion(t0 + 0.5 * span * (u + 1.0)) for u in x], np.float64)
    fits = [cheb.chebfit(nodes, col, CHEB) for col in at(nodes).T]
    check = np.linspace(-1.0, 1.0, 4 * CHEB + 1)
    for c, col in zip(fits, at(check).T):
        if np.max(np.abs(cheb.chebval(check, c) - col)) > 3e-8 * np.max(np.abs(col)) + 1e-30:
            return None
    return tuple(fits[0]) + tuple(fits[1])


def fit_steps(motion, t0, n, step_bound, breaks=None):
    """(steps, fit): the most steps, n or n halved until its series holds (series_fit, over the
    longest those steps can take, step_bound each), and that series; (1, None) where none holds
    over two steps (then the step goes alone, its value from the host)."""
    while n > 1:
        fit = series_fit(motion, t0, n * step_bound, breaks)
        if fit is not None:
            return n, fit
        n //= 2
    return 1, None


def constant_fit(values, span):
    """A fit (as series_fit's) that holds the two values over the whole span."""
    piece = (values[0],) + (0.0,) * CHEB + (values[1],) + (0.0,) * CHEB
    return piece + (span,) + piece + (span,)


@ti.func
def series_at(c: ti.template(), tau):
    """A fit's two values tau seconds into its span (series_fit): the first piece to its end,
    then the second."""
    split = c[2 * CHEB + 2]
    at, t0, span = 0, 0.0 * split, split
    if tau > split:
        at, t0, span = 2 * CHEB + 3, split, c[PFIT - 1] - split
    x = 2.0 * (tau - t0) / span - 1.0
    return ti.Vector([chebyshev(c, at, x), chebyshev(c, at + CHEB + 1, x)])


@ti.func
def chebyshev(c: ti.template(), at, x):
    """sum_j c[at + j] T_j(x), j = 0 .. CHEB, by Clenshaw's recurrence."""
    b1 = 0.0 * x
    b2 = 0.0 * x
    for j in ti.static(range(CHEB, 0, -1)):
        b1, b2 = 2.0 * x * b1 - b2 + c[at + j], b1
    return x * b1 - b2 + c[at]
