"""Mao (1986), scour beneath a pipe lying on a sand bed in a steady current: the time series of
the scour depth S/D and the bed profiles at t = 11, 18 and 25 s, pipe diameter D = 0.05 m.

Source: Y. Mao, "The interaction between a pipeline and an erodible bed", Series Paper 39,
Technical University of Denmark (1986), as digitised and distributed with SedFoam
(github.com/SedFoam/sedfoam, tutorials/Py/DATA/Mao_depth_expe.txt, Mao_11s_expe.txt,
Mao_18s_expe.txt, Mao_25s_expe.txt; used by Mathieu et al. 2019, Water 11:1727, for their
tutorial 2DPipelineScour). Profiles: x and y in metres from the pipe's centre, flow to +x; the
undisturbed bed is at y = -D/2 (the pipe touched it).

The two sets do not agree with each other by about 0.1 D: the deepest point of the 11 s profile is
S/D = 0.70, the time series reads 0.59 at 11 s (0.61 at 12 s); both are kept as published and
compared separately.
"""

import numpy as np

D = 0.05

# (t s, S/D)
DEPTH = np.array(
    [
        (0.1696, 3.6573e-3),
        (1.3808, 0.0713),
        (1.9379, 0.1033),
        (2.2527, 0.1243),
        (2.6402, 0.1609),
        (3.4396, 0.2002),
        (3.6817, 0.2221),
        (3.8269, 0.2404),
        (4.7231, 0.2943),
        (5.7406, 0.3382),
        (6.5886, 0.3693),
        (6.5641, 0.3949),
        (7.1456, 0.4095),
        (7.4605, 0.4314),
        (8.1146, 0.4607),
        (8.6718, 0.4863),
        (9.1804, 0.5119),
        (10.1012, 0.5366),
        (10.5615, 0.5585),
        (11.9909, 0.6097),
        (12.5966, 0.6371),
        (13.6141, 0.6663),
        (14.7046, 0.6911),
        (15.9888, 0.7203),
        (17.1277, 0.745),
        (18.5575, 0.766),
        (19.9872, 0.788),
        (21.6593, 0.8136),
        (22.9921, 0.8255),
        (25.0763, 0.8456),
        (26.7727, 0.8612),
        (28.6145, 0.8795),
        (30.5049, 0.8868),
        (31.959, 0.8941),
        (34.019, 0.9005),
        (36.685, 0.9088),
        (38.6239, 0.9115),
        (40.8052, 0.9097),
        (42.7441, 0.9116),
        (45.0465, 0.9106),
        (46.6461, 0.9125),
        (48.5851, 0.9116),
    ]
)

# t (s) -> (x m, y m) from the pipe's centre
PROFILES = {
    11.0: np.array(
        [
            (-0.0964, -0.0249),
            (-0.0905, -0.0248),
            (-0.0863, -0.0255),
            (-0.0795, -0.0264),
            (-0.0735, -0.0276),
            (-0.0664, -0.0292),
            (-0.0602, -0.0316),
            (-0.0534, -0.0345),
            (-0.0478, -0.0377),
            (-0.0427, -0.0411),
            (-0.0371, -0.0447),
            (-0.0316, -0.0479),
            (-0.0269, -0.0513),
            (-0.0212, -0.0545),
            (-0.0138, -0.0571),
            (-5.0115e-3, -0.0592),
            (3.7374e-3, -0.06),
            (0.0151, -0.0585),
            (0.0255, -0.0556),
            (0.035, -0.0509),
            (0.0448, -0.0468),
            (0.0532, -0.0429),
            (0.063, -0.0392),
            (0.0752, -0.0342),
            (0.0882, -0.0292),
            (0.0998, -0.0245),
            (0.1126, -0.0203),
            (0.1259, -0.0157),
            (0.1378, -0.0126),
            (0.153, -9.6136e-3),
            (0.1663, -8.6309e-3),
            (0.1788, -8.3086e-3),
            (0.1897, -9.3039e-3),
            (0.198, -0.0114),
            (0.207, -0.0131),
            (0.2165, -0.0151),
            (0.2251, -0.0165),
            (0.2348, -0.0179),
            (0.2406, -0.0191),
            (0.2483, -0.0199),
            (0.2541, -0.0216),
            (0.2599, -0.0229),
            (0.2676, -0.0247),
        ]
    ),
    18.0: np.array(
        [
            (-0.0961, -0.0262),
            (-0.0903, -0.0273),
            (-0.0832, -0.0288),
            (-0.0763, -0.0312),
            (-0.0689, -0.0332),
            (-0.0626, -0.0362),
            (-0.0559, -0.0397),
            (-0.0503, -0.0429),
            (-0.0438, -0.0466),
            (-0.0365, -0.0512),
            (-0.0292, -0.0551),
            (-0.0208, -0.0586),
            (-0.0134, -0.0615),
            (-6.2495e-3, -0.0636),
            (2.6993e-3, -0.0654),
            (0.0125, -0.0659),
            (0.022, -0.0656),
            (0.0331, -0.0638),
            (0.0418, -0.062),
            (0.0508, -0.0594),
            (0.0598, -0.0569),
            (0.0682, -0.0544),
            (0.0774, -0.0511),
            (0.0869, -0.0476),
            (0.0954, -0.0435),
            (0.103, -0.04),
            (0.1095, -0.037),
            (0.1179, -0.0325),
            (0.1295, -0.0263),
            (0.1379, -0.021),
            (0.1475, -0.0171),
            (0.159, -0.0141),
            (0.1683, -0.0121),
            (0.1796, -0.0104),
            (0.1926, -8.9622e-3),
            (0.2033, -8.5172e-3),
            (0.211, -8.5449e-3),
            (0.2225, -8.3581e-3),
            (0.2328, -8.9629e-3),
            (0.2438, -9.2371e-3),
            (0.2561, -0.0103),
            (0.266, -0.0113),
            (0.2781, -0.013),
            (0.2854, -0.0143),
            (0.2905, -0.0149),
        ]
    ),
    25.0: np.array(
        [
            (-0.0993, -0.03),
            (-0.0937, -0.0308),
            (-0.0875, -0.0316),
            (-0.0808, -0.033),
            (-0.0725, -0.0357),
            (-0.0646, -0.0398),
            (-0.0567, -0.0446),
            (-0.0488, -0.0495),
            (-0.0396, -0.0539),
            (-0.0313, -0.0582),
            (-0.0226, -0.0621),
            (-0.0144, -0.0653),
            (-0.0054, -0.0679),
            (0.0040, -0.0702),
            (0.0131, -0.0716),
            (0.0222, -0.072),
            (0.0338, -0.0713),
            (0.0422, -0.0697),
            (0.0518, -0.0674),
            (0.0607, -0.0647),
            (0.0694, -0.0625),
            (0.0791, -0.0608),
            (0.0873, -0.0591),
            (0.0963, -0.0563),
            (0.1062, -0.0514),
            (0.1177, -0.0452),
            (0.1284, -0.0384),
            (0.1389, -0.0329),
            (0.1496, -0.0293),
            (0.1644, -0.0266),
            (0.1776, -0.0242),
            (0.1901, -0.0222),
            (0.2029, -0.0204),
            (0.2147, -0.0193),
            (0.228, -0.0189),
            (0.2452, -0.0189),
            (0.2593, -0.0184),
            (0.2734, -0.0179),
            (0.2833, -0.0182),
            (0.2896, -0.0186),
        ]
    ),
}


_BY_TIME = DEPTH[np.argsort(DEPTH[:, 0])]  # the digitised series has one pair out of order


def depth_at(t):
    """Mao's S/D at the times t (linear between the points)."""
    return np.interp(t, _BY_TIME[:, 0], _BY_TIME[:, 1])


def time_of_depth(s):
    """The first time Mao's S/D reaches s (0 if s <= 0): the experiment's time at which a run
    that starts from an initial hole of depth s stands."""
    d = _BY_TIME
    if s <= d[0, 1]:
        return 0.0
    k = int(np.argmax(d[:, 1] >= s)) if (d[:, 1] >= s).any() else len(d) - 1
    t0, t1, s0, s1 = d[k - 1, 0], d[k, 0], d[k - 1, 1], d[k, 1]
    return float(t0 + (s - s0) * (t1 - t0) / (s1 - s0)) if s1 > s0 else float(t1)


def depth_error(t, s_over_d, t_max=15.0):
    """Largest and RMS |S/D_sim - S/D_Mao| at the simulated times t <= t_max (experiment's clock)."""
    t, s = np.asarray(t, float), np.asarray(s_over_d, float)
    m = (t <= t_max) & np.isfinite(s)
    if not m.any():
        return float("nan"), float("nan")
    e = s[m] - depth_at(t[m])
    return float(np.abs(e).max()), float(np.sqrt(np.mean(e * e)))


def profile_bed(t_profile, x_rel, diameter=D, taper=2.0):
    """Mao's measured bed at the published time t_profile as a height above the undisturbed bed
    (m) at x_rel from the pipe's centre, scaled to a pipe of this diameter; beyond the measured
    ends it returns to the undisturbed bed over `taper` diameters (the profiles end where the
    bed is within 0.01-0.2 D of it)."""
    ref = PROFILES[t_profile]
    k = diameter / D
    xs = np.concatenate([[ref[0, 0] - taper * D], ref[:, 0], [ref[-1, 0] + taper * D]]) * k
    ys = np.concatenate([[0.0], ref[:, 1] + D / 2, [0.0]]) * k
    return np.interp(np.asarray(x_rel, float), xs, ys, left=0.0, right=0.0)


def scour_profile_error(t_profile, x_rel, y_rel, diameter=D):
    """RMS of y_sim - y_Mao over Mao's points at the published time t_profile, in units of D:
    x_rel, y_rel the simulated bed from the pipe's centre (m), interpolated at Mao's x."""
    ref = PROFILES[t_profile]
    ys = np.interp(ref[:, 0], np.asarray(x_rel, float), np.asarray(y_rel, float))
    return float(np.sqrt(np.mean((ys - ref[:, 1]) ** 2)) / diameter)
