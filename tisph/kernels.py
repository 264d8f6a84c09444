"""Smoothing kernels, normalised in 2D, both with support 2h.

W(r, h) = sigma / h^2 * shape(q) and grad W = sigma / h^4 * fshape(q) * r_vec, q = r / h, where
fshape(q) = (dW/dr) / r in those units. Writing the gradient as a factor times r_vec keeps it
finite at r -> 0 and saves a square root's division in the pair loop.

Here each kernel's constants and its NumPy form (gauges, set-up, tests); the engine's Taichi
functions (tisph/engine/smoothing.py) extend these classes, so reading a case needs no Taichi.
"""

import math

import numpy as np


class CubicSpline2D:
    """Cubic spline (paper 000 eq. 5; Monaghan & Lattanzio 1985), alpha_D = 10 / (7 pi h^2)."""

    name = "cubic"
    support = 2.0
    sigma = 10.0 / (7.0 * math.pi)

    @staticmethod
    def shape_np(q):
        q = np.asarray(q, dtype=float)
        return np.where(q < 1, 1 - 1.5 * q**2 + 0.75 * q**3, np.where(q < 2, 0.25 * (2 - q) ** 3, 0.0))

    @staticmethod
    def fshape_np(q):
        q = np.asarray(q, dtype=float)
        qs = np.maximum(q, 1e-12)
        return np.where(q < 1, -3 + 2.25 * q, np.where(q < 2, -0.75 * (2 - q) ** 2 / qs, 0.0))


class WendlandC2_2D:
    """Wendland C2 (paper 002 eq. 6): W = 7 / (4 pi h^2) (1 - q/2)^4 (2q + 1), q < 2."""

    name = "wendland"
    support = 2.0
    sigma = 7.0 / (4.0 * math.pi)

    @staticmethod
    def shape_np(q):
        q = np.asarray(q, dtype=float)
        t = np.clip(1 - 0.5 * q, 0, None)
        return t**4 * (2 * q + 1)

    @staticmethod
    def fshape_np(q):
        q = np.asarray(q, dtype=float)
        t = np.clip(1 - 0.5 * q, 0, None)
        return -5 * t**3
