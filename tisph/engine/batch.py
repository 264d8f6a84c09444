"""Steps in batches with no read of the device between them (access.py, step_ahead): the batch's
size, how its log is read, and the paddle's motion as a Chebyshev series over a batch, fitted on
the host (paddle_fit) and evaluated by the step kernel (chebyshev)."""

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
# the degree of the paddle's Chebyshev series over a batch
CHEB = 8


# the device's copy of a fit (pfit): the first piece's displacement and rate series and where it
# ends, then the second piece's and the batch's span
PFIT = 4 * CHEB + 6


def paddle_fit(motion, t0, span):
    """Chebyshev series of motion(t) = (displacement, rate) over [t0, t0 + span], for the device to
    evaluate at each step's time, in two pieces where one of the motion's kinks (motion.breaks:
    the ramp's end, the ramp down's) falls inside: the values for pfit (PFIT of them), or None
    where two kinks do, or a piece misses the motion by more than 3e-8 of its largest value at 4
    points between each pair of nodes (then the steps go one at a time)."""
    inside = [b - t0 for b in getattr(motion, "breaks", ()) if t0 < b < t0 + span]
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


@ti.func
def chebyshev(c: ti.template(), at, x):
    """sum_j c[at + j] T_j(x), j = 0 .. CHEB, by Clenshaw's recurrence."""
    b1 = 0.0 * x
    b2 = 0.0 * x
    for j in ti.static(range(CHEB, 0, -1)):
        b1, b2 = 2.0 * x * b1 - b2 + c[at + j], b1
    return x * b1 - b2 + c[at]
