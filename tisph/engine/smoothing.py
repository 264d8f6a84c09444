"""The smoothing kernels as Taichi functions, for the pair loop: shape(q) and fshape(q) of
tisph/kernels.py's kernels (the constants and the NumPy twins are there)."""

import taichi as ti

from .. import kernels as shapes


class CubicSpline2D(shapes.CubicSpline2D):
    """The cubic spline (paper 000 eq. 5) in the pair loop."""

    @staticmethod
    @ti.func
    def shape(q):
        w = 0.0
        if q < 1.0:
            w = 1.0 - 1.5 * q * q + 0.75 * q * q * q
        elif q < 2.0:
            w = 0.25 * (2.0 - q) ** 3
        return w

    @staticmethod
    @ti.func
    def fshape(q):
        f = 0.0
        if q < 1.0:
            f = -3.0 + 2.25 * q
        elif q < 2.0:
            # the max: in the CPU's vector lanes both pieces are computed for every candidate,
            # and 1 / q at i's own q = 0 is infinite, which is poison to LLVM under fast math
            # (it assumes no infinities), select or not; q >= 1 here, so the max changes nothing
            f = -0.75 * (2.0 - q) ** 2 / ti.max(q, 0.5)
        return f


class WendlandC2_2D(shapes.WendlandC2_2D):
    """The Wendland C2 kernel (paper 002 eq. 6) in the pair loop."""

    @staticmethod
    @ti.func
    def shape(q):
        w = 0.0
        if q < 2.0:
            t = 1.0 - 0.5 * q
            w = t * t * t * t * (2.0 * q + 1.0)
        return w

    @staticmethod
    @ti.func
    def fshape(q):
        f = 0.0
        if q < 2.0:
            t = 1.0 - 0.5 * q
            f = -5.0 * t * t * t
        return f


KERNELS = {"cubic": CubicSpline2D, "wendland": WendlandC2_2D}


def get_kernel(name):
    return KERNELS[name]
