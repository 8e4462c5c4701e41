#!/usr/bin/python3
"""Reference projections for the COLMAP camera models (plus dba's BROWN model).

An independent NumPy transcription of the ImgFromCam math of COLMAP's
src/colmap/sensor/models.h (camera model ids 0..17), used to generate test data
for dba's C++ camera models. It shares no code with dba.

Usage (from the repository root; Debian's python3 with python3-numpy):

    /usr/bin/python3 scripts/colmap_projections.py [OUTPUT]

OUTPUT defaults to tests/data/camera_models/projections.txt next to this script's
repository. Before writing, the script runs self-checks that compare every model
against a re-derivation by other means (special cases, inverse maps, other
formulas); it exits non-zero if one fails. Output is deterministic: all inputs
are decimal literals and every number is written with '%.17g'.

Output format, one case per line ('#' starts a comment line):

    MODEL_NAME NUM_PARAMS p_1 ... p_n u v w x y

(u, v, w) is a point in the camera frame, (x, y) its pixel, COLMAP's convention
(upper-left image corner at (0, 0)).
"""

import os
import sys

import numpy as np

F = np.float64
DBL_EPS = np.finfo(np.float64).eps  # std::numeric_limits<double>::epsilon()


class ProjectionFailed(Exception):
    pass


def _split(u, v, w):
    return F(u), F(v), F(w)


def _require_front(w):
    # Every perspective model except the division ones: w < eps -> failure.
    if w < DBL_EPS:
        raise ProjectionFailed("w < eps")


# ---------------------------------------------------------------------------
# Perspective models with a polynomial distortion in the normalized plane.


def simple_pinhole(p, u, v, w):
    u, v, w = _split(u, v, w)
    _require_front(w)
    f, cx, cy = p
    return f * u / w + cx, f * v / w + cy


def pinhole(p, u, v, w):
    u, v, w = _split(u, v, w)
    _require_front(w)
    fx, fy, cx, cy = p
    return fx * u / w + cx, fy * v / w + cy


def _radial_only(a, b, coeffs):
    """Offset (da, db) = (a, b) * sum_i coeffs[i] * r2^(i+1)."""
    r2 = a * a + b * b
    s = F(0)
    power = F(1)
    for c in coeffs:
        power = power * r2
        s = s + c * power
    return a * s, b * s


def simple_radial(p, u, v, w):
    u, v, w = _split(u, v, w)
    _require_front(w)
    f, cx, cy, k = p
    a, b = u / w, v / w
    da, db = _radial_only(a, b, [k])
    return f * (a + da) + cx, f * (b + db) + cy


def radial(p, u, v, w):
    u, v, w = _split(u, v, w)
    _require_front(w)
    f, cx, cy, k1, k2 = p
    a, b = u / w, v / w
    da, db = _radial_only(a, b, [k1, k2])
    return f * (a + da) + cx, f * (b + db) + cy


def _opencv_tangential(a, b, p1, p2):
    # OpenCV convention: x gets 2 p1 x y + p2 (r2 + 2 x^2),
    #                    y gets 2 p2 x y + p1 (r2 + 2 y^2).
    r2 = a * a + b * b
    return (2 * p1 * a * b + p2 * (r2 + 2 * a * a),
            2 * p2 * a * b + p1 * (r2 + 2 * b * b))


def opencv(p, u, v, w):
    u, v, w = _split(u, v, w)
    _require_front(w)
    fx, fy, cx, cy, k1, k2, p1, p2 = p
    a, b = u / w, v / w
    da, db = _radial_only(a, b, [k1, k2])
    ta, tb = _opencv_tangential(a, b, p1, p2)
    return fx * (a + da + ta) + cx, fy * (b + db + tb) + cy


def full_opencv(p, u, v, w):
    u, v, w = _split(u, v, w)
    _require_front(w)
    fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, k5, k6 = p
    a, b = u / w, v / w
    r2 = a * a + b * b
    r4 = r2 * r2
    r6 = r4 * r2
    ratio = (1 + k1 * r2 + k2 * r4 + k3 * r6) / (1 + k4 * r2 + k5 * r4 + k6 * r6)
    ta, tb = _opencv_tangential(a, b, p1, p2)
    return fx * (a * ratio + ta) + cx, fy * (b * ratio + tb) + cy


# ---------------------------------------------------------------------------
# FOV (Devernay-Faugeras), with COLMAP's two series branches.

FOV_EPS = F(1e-4)  # COLMAP's kEpsilon, compared against omega^2 and r^2


def fov_factor(omega, r2):
    """Factor s with distorted = s * undistorted, as COLMAP computes it."""
    omega2 = omega * omega
    if omega2 < FOV_EPS:
        # COLMAP's small-omega branch (see the self-check: this is the series
        # of the *undistortion* factor, not of the distortion factor).
        return omega2 * r2 / 3 - omega2 / 12 + 1
    if r2 < FOV_EPS:
        t = np.tan(omega / 2)
        return (-2 * t * (4 * r2 * t * t - 3)) / (3 * omega)
    r = np.sqrt(r2)
    return np.arctan(r * 2 * np.tan(omega / 2)) / (r * omega)


def fov(p, u, v, w):
    u, v, w = _split(u, v, w)
    _require_front(w)
    fx, fy, cx, cy, omega = p
    a, b = u / w, v / w
    s = fov_factor(F(omega), a * a + b * b)
    return fx * a * s + cx, fy * b * s + cy


# ---------------------------------------------------------------------------
# Fisheye family: normalized point -> (theta / r) * point, then distortion.


def fisheye_from_normal(a, b):
    r = np.sqrt(a * a + b * b)
    if r > DBL_EPS:
        s = np.arctan(r) / r
        return a * s, b * s
    return a, b


def simple_radial_fisheye(p, u, v, w):
    u, v, w = _split(u, v, w)
    _require_front(w)
    f, cx, cy, k = p
    a, b = fisheye_from_normal(u / w, v / w)
    da, db = _radial_only(a, b, [k])
    return f * (a + da) + cx, f * (b + db) + cy


def radial_fisheye(p, u, v, w):
    u, v, w = _split(u, v, w)
    _require_front(w)
    f, cx, cy, k1, k2 = p
    a, b = fisheye_from_normal(u / w, v / w)
    da, db = _radial_only(a, b, [k1, k2])
    return f * (a + da) + cx, f * (b + db) + cy


def opencv_fisheye(p, u, v, w):
    u, v, w = _split(u, v, w)
    _require_front(w)
    fx, fy, cx, cy, k1, k2, k3, k4 = p
    a, b = fisheye_from_normal(u / w, v / w)
    da, db = _radial_only(a, b, [k1, k2, k3, k4])
    return fx * (a + da) + cx, fy * (b + db) + cy


def thin_prism_fisheye(p, u, v, w):
    u, v, w = _split(u, v, w)
    _require_front(w)
    fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, sx1, sy1 = p
    a, b = fisheye_from_normal(u / w, v / w)
    r2 = a * a + b * b  # = theta^2
    da, db = _radial_only(a, b, [k1, k2, k3, k4])
    ta, tb = _opencv_tangential(a, b, p1, p2)
    return (fx * (a + da + ta + sx1 * r2) + cx,
            fy * (b + db + tb + sy1 * r2) + cy)


def rad_tan_thin_prism_fisheye(p, u, v, w):
    u, v, w = _split(u, v, w)
    _require_front(w)
    fx, fy, cx, cy = p[0:4]
    ks = p[4:10]
    p0, p1, s0, s1, s2, s3 = p[10:16]
    a, b = fisheye_from_normal(u / w, v / w)
    th2 = a * a + b * b
    radial_scale = F(1)
    power = F(1)
    for k in ks:
        power = power * th2
        radial_scale = radial_scale + k * power
    x = radial_scale * a
    y = radial_scale * b
    r2 = x * x + y * y
    r4 = r2 * r2
    # NB: p0 multiplies (r2 + 2 x^2) in x -- the opposite of OpenCV's p1/p2.
    xd = x + 2 * p1 * x * y + p0 * (r2 + 2 * x * x) + s0 * r2 + s1 * r4
    yd = y + 2 * p0 * x * y + p1 * (r2 + 2 * y * y) + s2 * r2 + s3 * r4
    return fx * xd + cx, fy * yd + cy


def simple_fisheye(p, u, v, w):
    u, v, w = _split(u, v, w)
    _require_front(w)
    f, cx, cy = p
    a, b = fisheye_from_normal(u / w, v / w)
    return f * a + cx, f * b + cy


def fisheye(p, u, v, w):
    u, v, w = _split(u, v, w)
    _require_front(w)
    fx, fy, cx, cy = p
    a, b = fisheye_from_normal(u / w, v / w)
    return fx * a + cx, fy * b + cy


# ---------------------------------------------------------------------------
# Division models (Fitzgibbon): undistorted = distorted / (1 + k |distorted|^2)
# in normalized coordinates; the projection solves that quadratic.


def _division_scale(k, u, v, w):
    rho2 = u * u + v * v
    disc2 = w * w - 4 * rho2 * k
    if disc2 < 0:
        raise ProjectionFailed("negative discriminant")
    return 2 / (w + np.sqrt(disc2))


def simple_division(p, u, v, w):
    u, v, w = _split(u, v, w)
    f, cx, cy, k = p
    s = _division_scale(F(k), u, v, w)  # no w > 0 test in COLMAP
    return f * s * u + cx, f * s * v + cy


def division(p, u, v, w):
    u, v, w = _split(u, v, w)
    fx, fy, cx, cy, k = p
    s = _division_scale(F(k), u, v, w)
    return fx * s * u + cx, fy * s * v + cy


# ---------------------------------------------------------------------------
# EUCM (Khomutenko et al. 2016).


def eucm(p, u, v, w):
    u, v, w = _split(u, v, w)
    _require_front(w)
    fx, fy, cx, cy, alpha, beta = p
    d2 = beta * (u * u + v * v) + w * w
    if d2 < 0:
        raise ProjectionFailed("negative rho^2")
    den = alpha * np.sqrt(d2) + (1.0 - alpha) * w
    if den < DBL_EPS:
        raise ProjectionFailed("den < eps")
    return fx * (u / den) + cx, fy * (v / den) + cy


# ---------------------------------------------------------------------------
# EQUIRECTANGULAR: params (width, height); whole sphere.


def equirectangular(p, u, v, w):
    u, v, w = _split(u, v, w)
    width, height = F(p[0]), F(p[1])
    horizontal = np.sqrt(u * u + w * w)
    if horizontal + abs(v) < DBL_EPS:
        raise ProjectionFailed("zero direction")
    azimuth = np.arctan2(u, w)  # from +Z towards +X
    elevation = np.arctan2(-v, horizontal)  # -Y (up) is +pi/2
    return ((azimuth / (2 * np.pi) + 0.5) * width,
            (0.5 - elevation / np.pi) * height)


# ---------------------------------------------------------------------------
# dba's BROWN: (f, cx, cy, k1, k2, k3, p1, p2, b1, b2).


def brown(p, u, v, w):
    u, v, w = _split(u, v, w)
    f, cx, cy, k1, k2, k3, p1, p2, b1, b2 = p
    a, b = u / w, v / w
    r2 = a * a + b * b
    radial_scale = 1 + k1 * r2 + k2 * r2 * r2 + k3 * r2 * r2 * r2
    xp = a * radial_scale + 2 * p1 * a * b + p2 * (r2 + 2 * a * a)
    yp = b * radial_scale + p1 * (r2 + 2 * b * b) + 2 * p2 * a * b
    return f * xp + b1 * xp + b2 * yp + cx, f * yp + cy


# ---------------------------------------------------------------------------
# Test cases.

# Perspective (narrow) points, w > 0; normalized radius 0 .. ~0.68.
POINTS_PERSPECTIVE = [
    (0.0, 0.0, 2.5),  # optical axis
    (0.012, -0.008, 1.3),  # ~0.6 deg
    (0.21, 0.14, 1.7),  # ~8 deg
    (-0.9, 0.45, 3.2),  # ~17 deg
    (1.1, -0.85, 2.9),  # ~26 deg
    (-0.35, -0.62, 1.05),  # ~34 deg
]

# Wide-angle points, w > 0, up to 80 deg off axis.
POINTS_WIDE = [
    (0.0, 0.0, 1.7),  # optical axis
    (0.004, 0.003, 0.9),  # ~0.3 deg (r^2 < 1e-4: FOV's small-radius branch)
    (0.3, -0.2, 1.4),  # ~14 deg
    (-1.2, 0.9, 1.1),  # ~54 deg
    (2.0, 1.3, 0.85),  # ~70 deg
    (-1.5, -3.2, 0.62),  # ~80 deg
]

# Whole sphere, including behind the camera (w < 0).
POINTS_SPHERE = [
    (0.0, 0.0, 1.0),  # forward: image centre
    (0.6, -0.25, 0.9),  # front right, up
    (-2.0, 0.7, 0.4),  # left, down
    (1.3, 0.5, -2.1),  # behind right
    (-0.35, -1.8, -0.9),  # behind left, steeply up
    (-0.05, 0.3, -1.5),  # almost straight behind, just left of the seam
]

# (name, function, params, points); names and parameter order as COLMAP's.
CASES = [
    ("SIMPLE_PINHOLE", simple_pinhole, [812.5, 498.3, 401.7], POINTS_PERSPECTIVE),
    ("PINHOLE", pinhole, [1105.2, 1098.6, 503.4, 396.9], POINTS_PERSPECTIVE),
    ("SIMPLE_RADIAL", simple_radial, [935.0, 501.2, 398.5, -0.087],
     POINTS_PERSPECTIVE),
    ("RADIAL", radial, [742.8, 497.6, 403.1, -0.112, 0.046], POINTS_PERSPECTIVE),
    ("OPENCV", opencv,
     [1024.3, 1019.7, 506.8, 395.2, -0.094, 0.061, 0.0012, -0.0008],
     POINTS_PERSPECTIVE),
    ("OPENCV_FISHEYE", opencv_fisheye,
     [385.6, 384.9, 502.3, 399.1, 0.031, -0.0074, 0.0016, -0.00021],
     POINTS_WIDE),
    ("FULL_OPENCV", full_opencv,
     [1210.4, 1207.9, 495.5, 404.6, -0.183, 0.094, 0.0009, -0.0011, 0.012,
      0.027, -0.008, 0.0031],
     POINTS_PERSPECTIVE),
    ("FOV", fov, [611.2, 609.8, 500.7, 399.4, 0.92], POINTS_WIDE),
    ("SIMPLE_RADIAL_FISHEYE", simple_radial_fisheye, [402.3, 499.0, 401.5, 0.024],
     POINTS_WIDE),
    ("RADIAL_FISHEYE", radial_fisheye, [418.7, 503.9, 397.2, -0.031, 0.0058],
     POINTS_WIDE),
    ("THIN_PRISM_FISHEYE", thin_prism_fisheye,
     [395.1, 394.2, 498.8, 402.6, 0.027, -0.0061, 0.0009, -0.0013, 0.0012,
      -0.00018, 0.0011, -0.0007],
     POINTS_WIDE),
    ("RAD_TAN_THIN_PRISM_FISHEYE", rad_tan_thin_prism_fisheye,
     [410.5, 409.8, 501.6, 398.4, 0.029, -0.0072, 0.0014, -0.00023, 3.1e-05,
      -2.2e-06, 0.0011, -0.0006, 0.0009, -0.00012, -0.0008, 0.00015],
     POINTS_WIDE),
    ("SIMPLE_DIVISION", simple_division, [688.4, 502.5, 397.8, -0.096],
     POINTS_PERSPECTIVE),
    ("DIVISION", division, [702.1, 699.3, 497.9, 401.8, -0.118],
     POINTS_PERSPECTIVE),
    ("SIMPLE_FISHEYE", simple_fisheye, [356.9, 500.4, 399.6], POINTS_WIDE),
    ("FISHEYE", fisheye, [361.3, 358.7, 498.1, 402.9], POINTS_WIDE),
    ("EUCM", eucm, [455.2, 453.6, 501.1, 398.7, 0.61, 1.08], POINTS_WIDE),
    ("EQUIRECTANGULAR", equirectangular, [2048.0, 1024.0], POINTS_SPHERE),
    ("BROWN", brown,
     [950.6, 499.2, 401.3, -0.103, 0.072, -0.018, 0.0011, -0.0007, 0.85, -0.42],
     POINTS_PERSPECTIVE),
]

# COLMAP's FOV with omega^2 < 1e-4 takes a series branch (see fov_factor);
# these extra cases pin that branch.
FOV_SMALL_OMEGA = ("FOV", fov, [598.4, 601.3, 502.2, 397.5, 0.008],
                   [(0.0, 0.0, 1.2), (0.33, -0.21, 1.1), (-1.4, 0.95, 1.3)])

MODEL_FUNCS = {name: func for name, func, _, _ in CASES}


def g17(value):
    return "%.17g" % float(value)


def generate_lines():
    lines = [
        "# Reference pixel projections for COLMAP's camera models (ids 0..17, from",
        "# src/colmap/sensor/models.h, ImgFromCam) and dba's BROWN model.",
        "# Generated by scripts/colmap_projections.py (an independent NumPy",
        "# transcription) with, from the repository root:",
        "#   /usr/bin/python3 scripts/colmap_projections.py",
        "# Do not edit; regenerate. One case per line:",
        "#   MODEL_NAME NUM_PARAMS p_1 ... p_n u v w x y",
        "# (u, v, w): point in the camera frame; (x, y): pixel, COLMAP's convention",
        "# (upper-left image corner at (0, 0)). Numbers are '%.17g'.",
    ]

    def emit(name, func, params, points):
        for (u, v, w) in points:
            x, y = func(params, u, v, w)
            fields = [name, str(len(params))] + [g17(q) for q in params]
            fields += [g17(u), g17(v), g17(w), g17(x), g17(y)]
            lines.append(" ".join(fields))

    for name, func, params, points in CASES:
        emit(name, func, params, points)
    lines.append("# FOV with omega^2 < 1e-4: COLMAP's small-omega series branch "
                 "(1 + omega^2 r^2 / 3 - omega^2 / 12),")
    lines.append("# which differs from the closed form atan(2 r tan(omega/2)) / "
                 "(r omega) by O(omega^2) (up to ~0.04 px here).")
    emit(*FOV_SMALL_OMEGA)
    return lines


# ---------------------------------------------------------------------------
# Self-checks: each model against a re-derivation by other means.


class Checker:
    def __init__(self):
        self.failures = []
        self.count = 0

    def close(self, label, got, want, tol=1e-9):
        self.count += 1
        got = np.asarray(got, dtype=np.float64)
        want = np.asarray(want, dtype=np.float64)
        err = float(np.max(np.abs(got - want)))
        if not err <= tol:
            self.failures.append("%s: got %r want %r (err %.3g > %.3g)"
                                 % (label, got.tolist(), want.tolist(), err, tol))


def _theta_phi(u, v, w):
    """Angle off the optical axis via arccos, and azimuth in the image plane."""
    n = np.sqrt(u * u + v * v + w * w)
    return np.arccos(w / n), np.arctan2(v, u)


def self_check():
    c = Checker()
    pts_n = POINTS_PERSPECTIVE
    pts_w = POINTS_WIDE

    # Pinhole family against each other with zero distortion.
    for (u, v, w) in pts_n:
        want = (700.0 * u / w + 510.0, 700.0 * v / w + 390.0)
        c.close("SIMPLE_PINHOLE", simple_pinhole([700.0, 510.0, 390.0], u, v, w), want)
        c.close("PINHOLE", pinhole([700.0, 700.0, 510.0, 390.0], u, v, w), want)
        c.close("SIMPLE_RADIAL k=0", simple_radial([700.0, 510.0, 390.0, 0.0], u, v, w), want)
        c.close("RADIAL k=0", radial([700.0, 510.0, 390.0, 0.0, 0.0], u, v, w), want)
        c.close("OPENCV 0", opencv([700.0, 700.0, 510.0, 390.0, 0, 0, 0, 0], u, v, w), want)
        c.close("FULL_OPENCV 0",
                full_opencv([700.0, 700.0, 510.0, 390.0] + [0.0] * 8, u, v, w), want)
        c.close("BROWN 0", brown([700.0, 510.0, 390.0] + [0.0] * 7, u, v, w), want)
        c.close("EUCM alpha=0", eucm([700.0, 700.0, 510.0, 390.0, 0.0, 1.3], u, v, w), want)
        c.close("DIVISION k=0", division([700.0, 700.0, 510.0, 390.0, 0.0], u, v, w), want)
        c.close("SIMPLE_DIVISION k=0",
                simple_division([700.0, 510.0, 390.0, 0.0], u, v, w), want)

        # Radial models written out as polynomials in r = tan(angle).
        r = np.hypot(u, v) / w
        phi = np.arctan2(v, u)
        rd = r * (1 - 0.087 * r ** 2)
        c.close("SIMPLE_RADIAL", simple_radial([935.0, 501.2, 398.5, -0.087], u, v, w),
                (935.0 * rd * np.cos(phi) + 501.2, 935.0 * rd * np.sin(phi) + 398.5))
        k = [0.05, -0.02, 0.004]
        rd = r * (1 + k[0] * r ** 2 + k[1] * r ** 4 + k[2] * r ** 6)
        c.close("FULL_OPENCV = OPENCV + k3",
                full_opencv([800.0, 790.0, 500.0, 400.0, k[0], k[1], 0.001, -0.002,
                             k[2], 0, 0, 0], u, v, w),
                np.add(opencv([800.0, 790.0, 500.0, 400.0, k[0], k[1], 0.001, -0.002],
                              u, v, w),
                       (800.0 * k[2] * r ** 6 * r * np.cos(phi),
                        790.0 * k[2] * r ** 6 * r * np.sin(phi))))
        # Rational radial: only the denominator.
        den = 1 + 0.03 * r ** 2 - 0.01 * r ** 4 + 0.002 * r ** 6
        c.close("FULL_OPENCV denominator",
                full_opencv([800.0, 800.0, 500.0, 400.0, 0, 0, 0, 0, 0, 0.03, -0.01,
                             0.002], u, v, w),
                (800.0 * r / den * np.cos(phi) + 500.0, 800.0 * r / den * np.sin(phi) + 400.0))
        # OPENCV tangential part against the matrix form of Brown-Conrady:
        # [dx, dy] = [[2xy, r2+2x2], [r2+2y2, 2xy]] [p1, p2].
        a, b = u / w, v / w
        m = np.array([[2 * a * b, r ** 2 + 2 * a * a], [r ** 2 + 2 * b * b, 2 * a * b]])
        t = m @ np.array([0.0012, -0.0008])
        c.close("OPENCV tangential",
                opencv([900.0, 880.0, 500.0, 400.0, 0, 0, 0.0012, -0.0008], u, v, w),
                (900.0 * (a + t[0]) + 500.0, 880.0 * (b + t[1]) + 400.0))
        # BROWN = OPENCV (+ k3 r^6) plus the affinity terms.
        pb = [950.6, 499.2, 401.3, -0.103, 0.072, -0.018, 0.0011, -0.0007, 0.85, -0.42]
        ox, oy = opencv([950.6, 950.6, 0.0, 0.0, -0.103, 0.072, 0.0011, -0.0007], u, v, w)
        xp = ox / 950.6 - 0.018 * r ** 6 * a
        yp = oy / 950.6 - 0.018 * r ** 6 * b
        c.close("BROWN vs OPENCV", brown(pb, u, v, w),
                (950.6 * xp + 0.85 * xp - 0.42 * yp + 499.2, 950.6 * yp + 401.3))

        # Division: COLMAP's closed-form CamFromImg must undo the projection,
        # and the distorted radius must solve rd / (1 + k rd^2) = r.
        for kk in (-0.096, 0.07):
            x, y = simple_division([688.4, 502.5, 397.8, kk], u, v, w)
            xd, yd = (x - 502.5) / 688.4, (y - 397.8) / 688.4
            den = 1 + kk * (xd * xd + yd * yd)
            c.close("SIMPLE_DIVISION inverse k=%g" % kk, (xd / den, yd / den), (u / w, v / w),
                    1e-14)
        x, y = division([702.1, 699.3, 497.9, 401.8, -0.118], u, v, w)
        xd, yd = (x - 497.9) / 702.1, (y - 401.8) / 699.3
        den = 1 - 0.118 * (xd * xd + yd * yd)
        c.close("DIVISION inverse", (xd / den, yd / den), (u / w, v / w), 1e-14)
        if r > 0:
            rd_root = np.roots([-0.118 * r, -1.0, r])  # k r rd^2 - rd + r = 0
            rd_root = min(q for q in rd_root.real if q > 0)
            c.close("DIVISION root", np.hypot(xd, yd), rd_root, 1e-13)

    # Fisheye family: zero distortion = equidistant f * theta with theta from
    # arccos; then the distortion models against each other.
    for (u, v, w) in pts_w:
        th, az = _theta_phi(u, v, w)
        fx, fy, cx, cy = 361.3, 358.7, 498.1, 402.9
        want = (fx * th * np.cos(az) + cx, fy * th * np.sin(az) + cy)
        c.close("FISHEYE", fisheye([fx, fy, cx, cy], u, v, w), want)
        c.close("SIMPLE_FISHEYE", simple_fisheye([fx, cx, cy], u, v, w),
                (fx * th * np.cos(az) + cx, fx * th * np.sin(az) + cy))
        c.close("OPENCV_FISHEYE 0", opencv_fisheye([fx, fy, cx, cy, 0, 0, 0, 0], u, v, w), want)
        c.close("THIN_PRISM 0", thin_prism_fisheye([fx, fy, cx, cy] + [0.0] * 8, u, v, w), want)
        c.close("RAD_TAN 0", rad_tan_thin_prism_fisheye([fx, fy, cx, cy] + [0.0] * 12, u, v, w),
                want)
        c.close("SIMPLE_RADIAL_FISHEYE 0",
                simple_radial_fisheye([fx, cx, cy, 0.0], u, v, w),
                (fx * th * np.cos(az) + cx, fx * th * np.sin(az) + cy))

        # Radial distortion: theta_d = theta (1 + k1 th^2 + k2 th^4 + ...).
        ks = [0.031, -0.0074, 0.0016, -0.00021, 3.1e-05, -2.2e-06]
        td4 = th * (1 + sum(k * th ** (2 * i + 2) for i, k in enumerate(ks[:4])))
        td6 = th * (1 + sum(k * th ** (2 * i + 2) for i, k in enumerate(ks)))
        want4 = (fx * td4 * np.cos(az) + cx, fy * td4 * np.sin(az) + cy)
        c.close("OPENCV_FISHEYE radial",
                opencv_fisheye([fx, fy, cx, cy] + ks[:4], u, v, w), want4)
        c.close("THIN_PRISM radial only",
                thin_prism_fisheye([fx, fy, cx, cy, ks[0], ks[1], 0, 0, ks[2], ks[3], 0, 0],
                                   u, v, w), want4)
        c.close("RAD_TAN k0..k3 = OPENCV_FISHEYE",
                rad_tan_thin_prism_fisheye([fx, fy, cx, cy] + ks[:4] + [0.0] * 8, u, v, w),
                want4)
        c.close("RAD_TAN radial 6",
                rad_tan_thin_prism_fisheye([fx, fy, cx, cy] + ks + [0.0] * 6, u, v, w),
                (fx * td6 * np.cos(az) + cx, fy * td6 * np.sin(az) + cy))
        td2 = th * (1 - 0.031 * th ** 2 + 0.0058 * th ** 4)
        c.close("RADIAL_FISHEYE",
                radial_fisheye([418.7, 503.9, 397.2, -0.031, 0.0058], u, v, w),
                (418.7 * td2 * np.cos(az) + 503.9, 418.7 * td2 * np.sin(az) + 397.2))
        c.close("RADIAL_FISHEYE = OPENCV_FISHEYE(k1,k2)",
                radial_fisheye([418.7, 503.9, 397.2, -0.031, 0.0058], u, v, w),
                opencv_fisheye([418.7, 418.7, 503.9, 397.2, -0.031, 0.0058, 0, 0], u, v, w))
        c.close("SIMPLE_RADIAL_FISHEYE = RADIAL_FISHEYE(k,0)",
                simple_radial_fisheye([402.3, 499.0, 401.5, 0.024], u, v, w),
                radial_fisheye([402.3, 499.0, 401.5, 0.024, 0.0], u, v, w))

        # Tangential + prism with no radial part: RAD_TAN(p0, p1, s0, s2) equals
        # THIN_PRISM with p1/p2 swapped and sx1 = s0, sy1 = s2 (both then act
        # on (theta cos az, theta sin az)).
        tp, tq = 0.0011, -0.0006
        c.close("RAD_TAN tangential = THIN_PRISM swapped",
                rad_tan_thin_prism_fisheye([fx, fy, cx, cy] + [0.0] * 6
                                           + [tp, tq, 0.0009, 0.0, -0.0008, 0.0], u, v, w),
                thin_prism_fisheye([fx, fy, cx, cy, 0, 0, tq, tp, 0, 0, 0.0009, -0.0008],
                                   u, v, w))
        # RAD_TAN s1, s3 are r^4 terms: check them alone by hand.
        c.close("RAD_TAN s1 s3",
                rad_tan_thin_prism_fisheye([fx, fy, cx, cy] + [0.0] * 8
                                           + [0.0, -0.00012, 0.0, 0.00015], u, v, w),
                (fx * (th * np.cos(az) - 0.00012 * th ** 4) + cx,
                 fy * (th * np.sin(az) + 0.00015 * th ** 4) + cy))
        # RAD_TAN applies tangential/prism on the radially distorted point.
        ptt = [410.5, 409.8, 501.6, 398.4] + ks + [tp, tq, 0.0009, -0.00012, -0.0008, 0.00015]
        xr, yr = td6 * np.cos(az), td6 * np.sin(az)
        rr2 = td6 ** 2
        c.close("RAD_TAN full",
                rad_tan_thin_prism_fisheye(ptt, u, v, w),
                (410.5 * (xr + 2 * tq * xr * yr + tp * (rr2 + 2 * xr * xr) + 0.0009 * rr2
                          - 0.00012 * rr2 ** 2) + 501.6,
                 409.8 * (yr + 2 * tp * xr * yr + tq * (rr2 + 2 * yr * yr) - 0.0008 * rr2
                          + 0.00015 * rr2 ** 2) + 398.4))
        # THIN_PRISM full by hand (OpenCV tangential convention, r^2 = theta^2).
        pt = [395.1, 394.2, 498.8, 402.6, 0.027, -0.0061, 0.0009, -0.0013, 0.0012,
              -0.00018, 0.0011, -0.0007]
        tdp = th * (1 + 0.027 * th ** 2 - 0.0061 * th ** 4 + 0.0012 * th ** 6
                    - 0.00018 * th ** 8)
        xa, ya = th * np.cos(az), th * np.sin(az)
        c.close("THIN_PRISM full",
                thin_prism_fisheye(pt, u, v, w),
                (395.1 * (tdp * np.cos(az) + 2 * 0.0009 * xa * ya
                          - 0.0013 * (th ** 2 + 2 * xa * xa) + 0.0011 * th ** 2) + 498.8,
                 394.2 * (tdp * np.sin(az) - 2 * 0.0013 * xa * ya
                          + 0.0009 * (th ** 2 + 2 * ya * ya) - 0.0007 * th ** 2) + 402.6))

        # EUCM: alpha = 1/2, beta = 1 is the stereographic projection
        # x = 2 tan(theta / 2); and COLMAP's closed-form CamFromImg inverts it.
        c.close("EUCM stereographic",
                eucm([455.2, 453.6, 501.1, 398.7, 0.5, 1.0], u, v, w),
                (455.2 * 2 * np.tan(th / 2) * np.cos(az) + 501.1,
                 453.6 * 2 * np.tan(th / 2) * np.sin(az) + 398.7))
        al, be = 0.61, 1.08
        x, y = eucm([455.2, 453.6, 501.1, 398.7, al, be], u, v, w)
        mx, my = (x - 501.1) / 455.2, (y - 398.7) / 453.6
        rr = mx * mx + my * my
        mz = (1 - be * al * al * rr) / (al * np.sqrt(1 - (2 * al - 1) * be * rr) + 1 - al)
        c.close("EUCM inverse", (mx / mz, my / mz), (u / w, v / w), 1e-12)
        # ... and in the Khomutenko form with d on the ellipsoid:
        # m = (u, v) / (alpha d + (1 - alpha) w), d = sqrt(beta(u^2+v^2) + w^2);
        # write it via the angle: u = n sin th cos az, w = n cos th.
        s_, c_ = np.sin(th), np.cos(th)
        den = al * np.sqrt(be * s_ * s_ + c_ * c_) + (1 - al) * c_
        c.close("EUCM angle form", (x, y),
                (455.2 * s_ * np.cos(az) / den + 501.1, 453.6 * s_ * np.sin(az) / den + 398.7))

        # FOV closed form via its inverse: r_u = tan(r_d omega) / (2 tan(omega / 2)).
        om = 0.92
        x, y = fov([611.2, 609.8, 500.7, 399.4, om], u, v, w)
        mx, my = (x - 500.7) / 611.2, (y - 399.4) / 609.8
        rd = np.hypot(mx, my)
        ru = np.hypot(u, v) / w
        if ru > 0:
            c.close("FOV inverse", np.tan(rd * om) / (2 * np.tan(om / 2)), ru, 1e-8)
            c.close("FOV direction", np.arctan2(my, mx), az, 1e-12)
        else:
            c.close("FOV axis", (x, y), (500.7, 399.4), 0)

    # FOV branches against high-precision closed forms (mpmath).
    try:
        import mpmath
        mpmath.mp.dps = 40

        def fov_exact(om, r2):
            om = mpmath.mpf(om)
            r = mpmath.sqrt(mpmath.mpf(r2))
            if r == 0:
                return 2 * mpmath.tan(om / 2) / om
            return mpmath.atan(2 * r * mpmath.tan(om / 2)) / (r * om)

        def fov_undist_exact(om, r2):
            om = mpmath.mpf(om)
            r = mpmath.sqrt(mpmath.mpf(r2))
            if r == 0:
                return om / (2 * mpmath.tan(om / 2))
            return mpmath.tan(r * om) / (2 * r * mpmath.tan(om / 2))

        # Closed-form branch: agrees with the exact factor. Small-radius branch
        # (r^2 < 1e-4): the series 2t/w (1 - (2rt)^2 / 3), t = tan(w/2), drops
        # the next term 2t/w (2rt)^4 / 5 of atan -- a gap of up to ~2e-9
        # (relative) at r^2 = 1e-4; check that this is the whole difference.
        for r2 in (0.0, 1e-8, 3.1e-5, 9.9e-5, 1.01e-4, 0.066, 2.8, 32.0):
            got = fov_factor(F(0.92), F(r2))
            exact = fov_exact(0.92, r2)
            if r2 < 1e-4:
                t = mpmath.tan(mpmath.mpf(0.92) / 2)
                z = 2 * mpmath.sqrt(mpmath.mpf(r2)) * t
                next_term = 2 * t / mpmath.mpf(0.92) * z ** 4 / 5
                c.close("FOV small-r branch r2=%g" % r2, got, float(exact - next_term), 1e-12)
            else:
                c.close("FOV factor r2=%g" % r2, got, float(exact), 1e-14)
        # Small-omega branch: equals the series of the UNdistortion factor,
        # not of the distortion factor (COLMAP quirk). Record, don't fail.
        om = 0.008
        for r2 in (0.0, 0.25, 1.0, 4.0):
            got = float(fov_factor(F(om), F(r2)))
            c.close("FOV small omega = undistortion series r2=%g" % r2, got,
                    float(fov_undist_exact(om, r2)), 1e-7)
            c.close("FOV small omega vs exact r2=%g (expected O(omega^2) gap)" % r2, got,
                    float(fov_exact(om, r2)), 4 * om * om * (1 + r2))
    except ImportError:
        print("note: mpmath missing, FOV branch checks skipped", file=sys.stderr)

    # EQUIRECTANGULAR: longitude via arccos, latitude via arcsin.
    W, H = 2048.0, 1024.0
    for (u, v, w) in POINTS_SPHERE:
        n = np.sqrt(u * u + v * v + w * w)
        lon = np.arccos(w / np.hypot(u, w)) * (1.0 if u >= 0 else -1.0)
        lat = -np.arcsin(v / n)
        c.close("EQUIRECTANGULAR", equirectangular([W, H], u, v, w),
                (W * (0.5 + lon / (2 * np.pi)), H * (0.5 - lat / np.pi)), 1e-9)
        # COLMAP's CamRayFromImg inverse must give back the direction.
        x, y = equirectangular([W, H], u, v, w)
        az = 2 * np.pi * (x / W - 0.5)
        el = np.pi * (0.5 - y / H)
        ray = np.array([np.cos(el) * np.sin(az), -np.sin(el), np.cos(el) * np.cos(az)])
        c.close("EQUIRECTANGULAR ray", ray, np.array([u, v, w]) / n, 1e-14)

    # Every model is invariant under positive scaling of (u, v, w).
    for name, func, params, points in CASES + [FOV_SMALL_OMEGA]:
        for (u, v, w) in points:
            c.close("%s scale" % name, func(params, 2.75 * u, 2.75 * v, 2.75 * w),
                    func(params, u, v, w), 1e-9)

    # Failures where COLMAP reports them.
    for name, func, params, _ in CASES:
        if name in ("EQUIRECTANGULAR", "BROWN", "SIMPLE_DIVISION", "DIVISION"):
            continue
        c.count += 1
        try:
            func(params, 0.1, 0.2, -1.0)
            c.failures.append("%s: w < 0 should fail" % name)
        except ProjectionFailed:
            pass
    return c


def main(argv):
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    out = argv[1] if len(argv) > 1 else os.path.join(
        root, "tests", "data", "camera_models", "projections.txt")

    checker = self_check()
    if checker.failures:
        for f in checker.failures:
            print("SELF-CHECK FAILED: " + f, file=sys.stderr)
        return 1
    print("self-checks: %d passed" % checker.count, file=sys.stderr)

    lines = generate_lines()
    os.makedirs(os.path.dirname(out), exist_ok=True)
    with open(out, "w") as fh:
        fh.write("\n".join(lines) + "\n")
    print("wrote %d cases to %s" % (sum(1 for l in lines if not l.startswith("#")), out),
          file=sys.stderr)
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))
