"""Second-order wave generation: the stroke at 2 omega a paddle adds to its sine so that it sheds
no free second harmonic (Schaffer 1996, Ocean Eng. 23:47, for regular waves).

The paddle's surface is x = f(z) X(t): f = 1 for a piston, (z + l) / l for a flap hinged l under
the still-water level (z = 0, bed z = -h). At first order X1 = S/2 sin(omega t) makes the
progressive wave and the evanescent modes of linear wave-maker theory (Havelock 1929). At second
order (2 omega) the potential is

- the particular solution of the free-surface condition forced by each pair of first-order modes
  (the progressive wave with itself is Stokes' bound second harmonic; pairs with an evanescent
  mode are local to the paddle), and
- free waves at 2 omega, which the wave-maker condition u2 = dX2/dt - X1 du1/dx + w1 dX1/dz on
  x = 0 sets.

X2 leaves no free progressive wave when the projection of that condition on the free mode
cosh k2 (z + h) vanishes (the modes are orthogonal over the depth). Madsen (1971, J. Geophys.
Res. 76:8672) kept only the progressive first-order mode and projected on a constant; his closed
form for a piston, H^2 / (32 h) (3 cosh kh / sinh^3 kh - 2 / m1), is this with no evanescent
modes and cosh k2 (z + h) taken as flat, which holds in shallow water only.
"""

import math

import numpy as np

from ..constants import G
from .theory import wavenumber


def _roots(omega, depth, n, k):
    """k, then the first n evanescent wave numbers i kappa: omega^2 = -g kappa tan(kappa h), each
    kappa h in ((j - 1/2) pi, j pi), by bisection."""
    out = [complex(k)]
    f = lambda q: omega * omega + G * q / depth * math.tan(q)
    for j in range(1, n + 1):
        a, b = (j - 0.5) * math.pi + 1e-12, j * math.pi - 1e-12
        for _ in range(60):
            m = 0.5 * (a + b)
            a, b = (a, m) if f(m) > 0 else (m, b)
        out.append(1j * 0.5 * (a + b) / depth)
    return np.array(out)


def _int_cosh2(p, q, h):
    """The integral of cosh(p s) cosh(q s) over s in [0, h], for complex p (array) and real q."""

    def sinhc(x):
        small = np.abs(x) < 1e-8
        return np.where(small, h, np.sinh(x * h) / np.where(small, 1, x))

    return 0.5 * (sinhc(p + q) + sinhc(p - q))


def shape(kind, depth, lever=None):
    """(c0, c1): the paddle's displacement profile f = c0 + c1 s over s = z + h (1 at the level)."""
    l = depth if lever is None else lever
    return (1.0, 0.0) if kind == "piston" else ((l - depth) / l, 1.0 / l)


def first_order(kind, stroke, omega, depth, lever=None, modes=100):
    """(K, A): linear wave-maker theory's modes, phi1 = Re sum A_n cosh K_n (z + h) exp(i (K_n x -
    omega t)), K_0 = k and K_n = i kappa_n, for the paddle X1 = S/2 f(z) sin(omega t): A_n from
    its velocity S omega / 2 f projected on cosh K_n (z + h) (the modes are orthogonal)."""
    h, w = depth, omega
    K = _roots(w, h, modes, wavenumber(w, h))
    c0, c1 = shape(kind, h, lever)
    sh, ch = np.sinh(K * h), np.cosh(K * h)
    fproj = c0 * sh / K + c1 * (h * sh / K - (ch - 1) / (K * K))
    return K, 0.5 * stroke * w * fproj / (1j * K * (0.5 * h + np.sinh(2 * K * h) / (4 * K)))


def second_order_stroke(kind, stroke, omega, depth, lever=None, modes=100):
    """(b_sin, b_cos): the second-order stroke b_sin sin(2 omega t) + b_cos cos(2 omega t) (m, at
    the still-water level) for a first-order stroke S sin(omega t) / 2; modes: evanescent modes
    kept at first order (0: Madsen's progressive-only forcing, projected on the free mode)."""
    h, w = depth, omega
    k2 = wavenumber(2 * w, h)
    K, A = first_order(kind, stroke, w, h, lever, modes)
    c0, c1 = shape(kind, h, lever)
    sh, ch = np.sinh(K * h), np.cosh(K * h)
    # the first-order potential and its derivatives at z = 0 (time factor exp(-i omega t))
    p, px, pz = A * ch, 1j * K * A * ch, K * A * sh
    pzz = K * K * p
    # 2 omega amplitude of the second-order free-surface forcing, phi2_tt + g phi2_z = R
    R = (
        0.5j * w * (2 * np.outer(px, px) + np.outer(pz, pz))
        + 1j * w**3 / G * np.outer(p, pz)
        - 0.5j * w * np.outer(p, pzz)
    )
    Q = K[:, None] + K[None, :]
    C = R / (-4 * w * w * np.cosh(Q * h) + G * Q * np.sinh(Q * h))
    forced = (1j * Q * C * _int_cosh2(Q, k2, h)).sum()  # u of the forced potential, projected
    # the wave-maker terms -X1 u1_x + w1 X1_z at 2 omega, projected by quadrature
    q, wq = np.polynomial.legendre.leggauss(max(64, 8 * modes))
    s, wq = 0.5 * h * (q + 1), 0.5 * h * wq
    X1 = 0.5j * stroke
    u1x = -(K[:, None] ** 2 * A[:, None] * np.cosh(np.outer(K, s))).sum(0)
    w1 = (K[:, None] * A[:, None] * np.sinh(np.outer(K, s))).sum(0)
    paddle = 0.5 * X1 * (-(c0 + c1 * s) * u1x + c1 * w1)
    free = np.cosh(k2 * s) * wq
    X2 = ((paddle * free).sum() - forced) / (2j * w * ((c0 + c1 * s) * free).sum())
    return float(X2.imag), float(X2.real)
