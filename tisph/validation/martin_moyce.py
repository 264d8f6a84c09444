"""Martin & Moyce (1952), dam-break surge front on a dry horizontal floor.

Source: J. C. Martin and W. J. Moyce, "An experimental study of the collapse of liquid columns on a
rigid horizontal plane", Phil. Trans. R. Soc. Lond. A 244 (1952) 312-324, Table 2, square column
(n^2 = 2, column height 2a, width a). T = t sqrt(2 g / a), Z = x / a with x the front position
measured from the back wall.
"""

import numpy as np

T = np.array([0.41, 0.84, 1.19, 1.43, 1.63, 1.83, 1.98, 2.20, 2.32, 2.51, 2.65, 2.83, 2.98, 3.11, 3.33])
Z = np.array([1.11, 1.22, 1.44, 1.67, 1.89, 2.11, 2.33, 2.56, 2.78, 3.00, 3.22, 3.44, 3.67, 3.89, 4.11])


def front_rms_error(t, front_x, a, g=9.81, T_max=3.3):
    """RMS of Z_sim - Z_ref at the reference times T <= T_max (Z_sim interpolated in time).

    Reference points later than the simulated time are skipped; returns (rms, number of points).
    """
    t = np.asarray(t, float)
    front_x = np.asarray(front_x, float)
    Ts = t * np.sqrt(2.0 * g / a)
    sel = (T_max >= T) & (Ts.max() + 1e-12 >= T)
    if not sel.any():
        return float("nan"), 0
    Zs = np.interp(T[sel], Ts, front_x / a)
    return float(np.sqrt(np.mean((Zs - Z[sel]) ** 2))), int(sel.sum())
