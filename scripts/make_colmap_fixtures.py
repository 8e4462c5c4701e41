#!/usr/bin/env python3
"""Writes the small COLMAP sparse-model fixtures under tests/data/colmap_models.

One tiny model per COLMAP camera model (ids 0..17, COLMAP's
src/colmap/sensor/models.h), each in both of COLMAP's formats:

  tests/data/colmap_models/<MODEL>/text/{cameras,images,points3D}.txt
  tests/data/colmap_models/<MODEL>/binary/{cameras,images,points3D}.bin

Every model holds 2 cameras of that camera model (realistic, distinct
parameters), 4 images (2 per camera) looking at a small point cloud, 12 3D
points each observed by 2 to 4 images, and 1 or 2 2D points per image that
have no 3D point (POINT3D_ID -1). The 2D observations are the projections
through the camera model (COLMAP's ImgFromCam) plus a little Gaussian noise;
a point's ERROR is the mean length of that noise. 3D points are listed in a
scrambled id order and ids are not contiguous, as COLMAP writes them.

The text and binary files of a model hold exactly the same values: every
value is rounded to a few decimals first, and the text holds the shortest
decimal that reads back to the same double (what std::to_chars writes, and
so what dba's COLMAP text writer writes: a text fixture written back by dba
is byte-identical). The binary layout is COLMAP's (little-endian):

  cameras.bin   u64 count; per camera u32 camera_id, i32 model_id,
                u64 width, u64 height, f64 params[num_params]
  images.bin    u64 count; per image u32 image_id, f64 qvec[4] (w, x, y, z),
                f64 tvec[3], u32 camera_id, name + NUL, u64 num_points2D,
                per 2D point f64 x, f64 y, u64 point3D_id (2^64 - 1: none)
  points3D.bin  u64 count; per point u64 point3D_id, f64 xyz[3], u8 rgb[3],
                f64 error, u64 track_length, per element u32 image_id,
                u32 point2D_idx

Deterministic: standard library only, its own seeded generator (only
random.Random.random(), whose sequence Python guarantees for a given seed),
no timestamps. Running it again rewrites identical files.

Usage: scripts/make_colmap_fixtures.py [--out DIR]
  (default DIR: tests/data/colmap_models beside this script's repository)
"""

import argparse
import math
import os
import random
import struct
import sys

# COLMAP's camera models: (id, name, parameter names), in id order.
MODELS = [
    (0, "SIMPLE_PINHOLE", "f cx cy"),
    (1, "PINHOLE", "fx fy cx cy"),
    (2, "SIMPLE_RADIAL", "f cx cy k"),
    (3, "RADIAL", "f cx cy k1 k2"),
    (4, "OPENCV", "fx fy cx cy k1 k2 p1 p2"),
    (5, "OPENCV_FISHEYE", "fx fy cx cy k1 k2 k3 k4"),
    (6, "FULL_OPENCV", "fx fy cx cy k1 k2 p1 p2 k3 k4 k5 k6"),
    (7, "FOV", "fx fy cx cy omega"),
    (8, "SIMPLE_RADIAL_FISHEYE", "f cx cy k"),
    (9, "RADIAL_FISHEYE", "f cx cy k1 k2"),
    (10, "THIN_PRISM_FISHEYE", "fx fy cx cy k1 k2 p1 p2 k3 k4 sx1 sy1"),
    (11, "RAD_TAN_THIN_PRISM_FISHEYE",
     "fx fy cx cy k0 k1 k2 k3 k4 k5 p0 p1 s0 s1 s2 s3"),
    (12, "SIMPLE_DIVISION", "f cx cy k"),
    (13, "DIVISION", "fx fy cx cy k"),
    (14, "SIMPLE_FISHEYE", "f cx cy"),
    (15, "FISHEYE", "fx fy cx cy"),
    (16, "EUCM", "fx fy cx cy alpha beta"),
    (17, "EQUIRECTANGULAR", "w h"),
]

# Per camera model, its two cameras: (width, height, params). Values of real
# devices' magnitudes (phones, action and fisheye cameras, EuRoC / TUM-VI /
# ETH3D / Aria-like rigs, 360 cameras).
CAMERAS = {
    "SIMPLE_PINHOLE": [
        (1920, 1080, [1534.2871, 961.3724, 538.9186]),
        (1600, 1200, [1318.6425, 797.4183, 603.2571]),
    ],
    "PINHOLE": [
        (1920, 1080, [1536.8142, 1533.4907, 958.7216, 541.3388]),
        (1600, 1200, [1321.0973, 1319.8461, 802.5539, 598.1167]),
    ],
    "SIMPLE_RADIAL": [
        (1920, 1080, [1529.6613, 962.1478, 537.4402, -0.0412738]),
        (1600, 1200, [1316.2294, 801.9035, 597.6612, 0.0231457]),
    ],
    "RADIAL": [
        (1920, 1080, [1527.3356, 959.8841, 540.2217, -0.0893214, 0.0127351]),
        (1600, 1200, [1314.9182, 798.2736, 601.4459, -0.0512876, 0.0071093]),
    ],
    "OPENCV": [
        (1920, 1080, [1538.2917, 1535.9742, 957.1843, 542.6629,
                      -0.1127364, 0.0934512, 0.00041372, -0.00028841]),
        (1280, 960, [1041.7385, 1043.2216, 641.9034, 478.3381,
                     -0.2318472, 0.1196635, -0.00062214, 0.00017789]),
    ],
    "OPENCV_FISHEYE": [
        (1920, 1440, [731.2248, 730.6917, 962.4183, 718.8856,
                      0.0512637, -0.0143291, 0.0031178, -0.00051246]),
        (1280, 1024, [412.5391, 412.8274, 638.2147, 513.7759,
                      -0.0097423, 0.0386172, -0.0211854, 0.0039127]),
    ],
    "FULL_OPENCV": [
        (1920, 1080, [1541.6638, 1539.1285, 961.0492, 536.7714,
                      -0.2841137, 0.0915246, 0.00037418, -0.00019273,
                      -0.0152339, 0.0121874, -0.0043126, 0.00091375]),
        (1600, 1200, [1323.4459, 1321.8817, 796.6328, 604.0192,
                      -0.1736528, 0.0428817, -0.00052461, 0.00033807,
                      -0.0061254, 0.0079312, -0.0012847, 0.00027736]),
    ],
    "FOV": [
        (640, 480, [256.7124, 257.0389, 318.4421, 241.1186, 0.9213374]),
        (752, 480, [365.3318, 366.0752, 376.9087, 238.6613, 0.9342851]),
    ],
    "SIMPLE_RADIAL_FISHEYE": [
        (1920, 1440, [742.3318, 959.2184, 719.6127, 0.0312466]),
        (1280, 1024, [418.9473, 641.3856, 510.9271, -0.0176534]),
    ],
    "RADIAL_FISHEYE": [
        (1920, 1440, [738.5127, 961.7719, 721.4638, 0.0284413, -0.0046172]),
        (1280, 1024, [415.2286, 637.9914, 514.2382, -0.0231745, 0.0058829]),
    ],
    "THIN_PRISM_FISHEYE": [
        (752, 480, [451.3712, 451.2148, 374.3647, 234.7713,
                    -0.0219318, 0.0125426, 0.0014267, 0.00012374,
                    -0.0088159, 0.0016472, -0.00047381, 0.00018256]),
        (752, 480, [452.8294, 452.6613, 377.1286, 236.4419,
                    -0.0201177, 0.0107346, -0.00093825, 0.00031442,
                    -0.0069728, 0.0012251, 0.00036614, -0.00021947]),
    ],
    "RAD_TAN_THIN_PRISM_FISHEYE": [
        (1408, 1408, [611.2847, 610.9731, 715.1163, 716.8394,
                      0.0384127, -0.0127346, 0.0035218, -0.00061174,
                      0.000043219, -0.0000021137, 0.00041368, -0.00017253,
                      0.00072114, -0.00013267, -0.00046382, 0.000051176]),
        (640, 480, [241.6238, 241.4472, 318.7296, 237.5581,
                    -0.0261843, 0.0198472, -0.0064315, 0.0011827,
                    -0.00011453, 0.0000043791, -0.00029416, 0.00022687,
                    -0.00051329, 0.000087614, 0.00033518, -0.000039262]),
    ],
    "SIMPLE_DIVISION": [
        (1920, 1080, [1327.4188, 958.6271, 541.3342, -0.1847326]),
        (1600, 1200, [1102.7736, 803.1264, 596.8817, -0.1268451]),
    ],
    "DIVISION": [
        (1920, 1080, [1331.2749, 1329.6812, 962.3318, 538.1127, -0.1792214]),
        (1600, 1200, [1104.3381, 1105.9146, 799.5572, 602.2293, -0.1311867]),
    ],
    "SIMPLE_FISHEYE": [
        (1920, 1440, [735.8627, 958.3374, 722.1843]),
        (1280, 1024, [411.7368, 642.0516, 509.6628]),
    ],
    "FISHEYE": [
        (1920, 1440, [734.9261, 735.6684, 963.1129, 717.2458]),
        (1280, 1024, [413.4417, 412.2953, 636.8842, 515.3371]),
    ],
    "EUCM": [
        (752, 480, [460.7631, 459.4872, 365.8146, 249.1733, 0.5655218, 1.1846337]),
        (512, 512, [191.1437, 190.9763, 254.9318, 256.8972, 0.6313442, 1.0150928]),
    ],
    "EQUIRECTANGULAR": [
        (5376, 2688, [5376, 2688]),
        (5760, 2880, [5760, 2880]),
    ],
}

# Image file names of the 4 images (camera 1: images 1, 2; camera 2: 3, 4).
IMAGE_NAMES = ["cam1/IMG_4817.JPG", "cam1/IMG_4823.JPG",
               "cam2/DSC01536.JPG", "cam2/DSC01541.JPG"]
NUM_POINTS = 12


# ---------------------------------------------------------------------------
# Deterministic randomness (only Random.random(), stable across Python
# versions for an integer seed).

class Rng:
    def __init__(self, seed):
        self.r = random.Random(seed)

    def uniform(self, a, b):
        return a + (b - a) * self.r.random()

    def integer(self, a, b):  # a..b inclusive
        return min(b, a + int(self.r.random() * (b - a + 1)))

    def gauss(self, sigma):
        u1 = 1.0 - self.r.random()  # (0, 1]
        u2 = self.r.random()
        return sigma * math.sqrt(-2.0 * math.log(u1)) * math.cos(2.0 * math.pi * u2)

    def shuffle(self, items):
        for i in range(len(items) - 1, 0, -1):
            j = self.integer(0, i)
            items[i], items[j] = items[j], items[i]


# ---------------------------------------------------------------------------
# Geometry.

def sub(a, b):
    return [a[0] - b[0], a[1] - b[1], a[2] - b[2]]


def cross(a, b):
    return [a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0]]


def normalized(a):
    n = math.sqrt(a[0] * a[0] + a[1] * a[1] + a[2] * a[2])
    return [a[0] / n, a[1] / n, a[2] / n]


def look_at(center, target, up, roll):
    """World -> camera rotation (rows: camera x right, y down, z forward)."""
    z = normalized(sub(target, center))
    x = normalized(cross(z, up))
    y = cross(z, x)
    c, s = math.cos(roll), math.sin(roll)
    xr = [c * x[i] + s * y[i] for i in range(3)]
    yr = [-s * x[i] + c * y[i] for i in range(3)]
    return [xr, yr, z]


def quaternion(R):
    """Unit quaternion (w, x, y, z) of a rotation matrix, w >= 0."""
    tr = R[0][0] + R[1][1] + R[2][2]
    if tr > 0:
        s = 2.0 * math.sqrt(tr + 1.0)
        q = [0.25 * s, (R[2][1] - R[1][2]) / s, (R[0][2] - R[2][0]) / s,
             (R[1][0] - R[0][1]) / s]
    elif R[0][0] > R[1][1] and R[0][0] > R[2][2]:
        s = 2.0 * math.sqrt(1.0 + R[0][0] - R[1][1] - R[2][2])
        q = [(R[2][1] - R[1][2]) / s, 0.25 * s, (R[0][1] + R[1][0]) / s,
             (R[0][2] + R[2][0]) / s]
    elif R[1][1] > R[2][2]:
        s = 2.0 * math.sqrt(1.0 + R[1][1] - R[0][0] - R[2][2])
        q = [(R[0][2] - R[2][0]) / s, (R[0][1] + R[1][0]) / s, 0.25 * s,
             (R[1][2] + R[2][1]) / s]
    else:
        s = 2.0 * math.sqrt(1.0 + R[2][2] - R[0][0] - R[1][1])
        q = [(R[1][0] - R[0][1]) / s, (R[0][2] + R[2][0]) / s,
             (R[1][2] + R[2][1]) / s, 0.25 * s]
    if q[0] < 0:
        q = [-v for v in q]
    n = math.sqrt(sum(v * v for v in q))
    return [v / n for v in q]


def rotation(q):
    w, x, y, z = q
    return [[1 - 2 * (y * y + z * z), 2 * (x * y - w * z), 2 * (x * z + w * y)],
            [2 * (x * y + w * z), 1 - 2 * (x * x + z * z), 2 * (y * z - w * x)],
            [2 * (x * z - w * y), 2 * (y * z + w * x), 1 - 2 * (x * x + y * y)]]


def to_camera(q, t, X):
    R = rotation(q)
    return [R[i][0] * X[0] + R[i][1] * X[1] + R[i][2] * X[2] + t[i] for i in range(3)]


# ---------------------------------------------------------------------------
# COLMAP's projections (ImgFromCam), camera frame (u, v, w) -> pixel.

def fisheye_from_normal(u, v):
    r = math.hypot(u, v)
    if r < 1e-12:
        return u, v
    theta = math.atan(r)
    return u * theta / r, v * theta / r


def project(model, p, u, v, w):
    """Pixel (x, y) of camera point (u, v, w), or None where COLMAP fails."""
    if model == "EQUIRECTANGULAR":
        width, height = p
        horizontal = math.hypot(u, w)
        theta = math.atan2(u, w)
        phi = math.atan2(-v, horizontal)
        return ((theta / (2 * math.pi) + 0.5) * width, (0.5 - phi / math.pi) * height)
    if w < 1e-6:
        return None
    a, b = u / w, v / w
    if model == "SIMPLE_PINHOLE":
        return p[0] * a + p[1], p[0] * b + p[2]
    if model == "PINHOLE":
        return p[0] * a + p[2], p[1] * b + p[3]
    if model in ("SIMPLE_RADIAL", "RADIAL"):
        r2 = a * a + b * b
        radial = p[3] * r2 + (p[4] * r2 * r2 if model == "RADIAL" else 0.0)
        return p[0] * a * (1 + radial) + p[1], p[0] * b * (1 + radial) + p[2]
    if model == "OPENCV":
        k1, k2, p1, p2 = p[4:8]
        r2 = a * a + b * b
        radial = k1 * r2 + k2 * r2 * r2
        x = a + a * radial + 2 * p1 * a * b + p2 * (r2 + 2 * a * a)
        y = b + b * radial + 2 * p2 * a * b + p1 * (r2 + 2 * b * b)
        return p[0] * x + p[2], p[1] * y + p[3]
    if model == "FULL_OPENCV":
        k1, k2, p1, p2, k3, k4, k5, k6 = p[4:12]
        r2 = a * a + b * b
        r4, r6 = r2 * r2, r2 * r2 * r2
        radial = (1 + k1 * r2 + k2 * r4 + k3 * r6) / (1 + k4 * r2 + k5 * r4 + k6 * r6)
        x = a * radial + 2 * p1 * a * b + p2 * (r2 + 2 * a * a)
        y = b * radial + 2 * p2 * a * b + p1 * (r2 + 2 * b * b)
        return p[0] * x + p[2], p[1] * y + p[3]
    if model == "FOV":
        omega = p[4]
        r = math.hypot(a, b)
        factor = math.atan(r * 2 * math.tan(omega / 2)) / (r * omega) if r > 1e-9 else 1.0
        return p[0] * a * factor + p[2], p[1] * b * factor + p[3]
    if model in ("SIMPLE_DIVISION", "DIVISION"):
        if model == "SIMPLE_DIVISION":
            fx, fy, cx, cy, k = p[0], p[0], p[1], p[2], p[3]
        else:
            fx, fy, cx, cy, k = p
        rho2 = a * a + b * b
        disc2 = 1 - 4 * rho2 * k
        if disc2 < 0:
            return None
        s = 2 / (1 + math.sqrt(disc2))
        return fx * s * a + cx, fy * s * b + cy
    if model == "EUCM":
        fx, fy, cx, cy, alpha, beta = p
        rho = math.sqrt(beta * (u * u + v * v) + w * w)
        den = alpha * rho + (1 - alpha) * w
        return fx * u / den + cx, fy * v / den + cy

    # Fisheye models: equidistant angle, then the model's distortion.
    uu, vv = fisheye_from_normal(a, b)
    th2 = uu * uu + vv * vv
    if model in ("SIMPLE_FISHEYE", "FISHEYE"):
        du = dv = 0.0
    elif model in ("SIMPLE_RADIAL_FISHEYE", "RADIAL_FISHEYE"):
        radial = p[3] * th2 + (p[4] * th2 * th2 if model == "RADIAL_FISHEYE" else 0.0)
        du, dv = uu * radial, vv * radial
    elif model == "OPENCV_FISHEYE":
        k1, k2, k3, k4 = p[4:8]
        radial = k1 * th2 + k2 * th2 ** 2 + k3 * th2 ** 3 + k4 * th2 ** 4
        du, dv = uu * radial, vv * radial
    elif model == "THIN_PRISM_FISHEYE":
        k1, k2, p1, p2, k3, k4, sx1, sy1 = p[4:12]
        radial = k1 * th2 + k2 * th2 ** 2 + k3 * th2 ** 3 + k4 * th2 ** 4
        du = uu * radial + 2 * p1 * uu * vv + p2 * (th2 + 2 * uu * uu) + sx1 * th2
        dv = vv * radial + 2 * p2 * uu * vv + p1 * (th2 + 2 * vv * vv) + sy1 * th2
    elif model == "RAD_TAN_THIN_PRISM_FISHEYE":
        k = p[4:10]
        p0, p1, s0, s1, s2, s3 = p[10:16]
        th_radial = 1.0
        power = 1.0
        for ki in k:
            power *= th2
            th_radial += ki * power
        x, y = th_radial * uu, th_radial * vv
        r2 = x * x + y * y
        xd = x + 2 * p1 * x * y + p0 * (r2 + 2 * x * x) + s0 * r2 + s1 * r2 * r2
        yd = y + 2 * p0 * x * y + p1 * (r2 + 2 * y * y) + s2 * r2 + s3 * r2 * r2
        du, dv = xd - uu, yd - vv
    else:
        raise ValueError(model)
    if model in ("SIMPLE_RADIAL_FISHEYE", "RADIAL_FISHEYE", "SIMPLE_FISHEYE"):
        fx = fy = p[0]
        cx, cy = p[1], p[2]
    else:
        fx, fy, cx, cy = p[0:4]
    return fx * (uu + du) + cx, fy * (vv + dv) + cy


# ---------------------------------------------------------------------------
# Number formatting: the shortest decimal that reads back to the same double,
# laid out as std::to_chars(double) does (fixed or scientific, whichever is
# shorter, fixed on a tie; exponent with a sign and at least two digits).

def fmt(v):
    if isinstance(v, int):
        return str(v)
    if v != v or v in (float("inf"), float("-inf")):
        raise ValueError("non-finite value")
    if v == 0:
        return "-0" if math.copysign(1.0, v) < 0 else "0"
    sign = "-" if v < 0 else ""
    r = repr(abs(v))  # shortest round-trip digits
    mantissa, _, exp = r.partition("e")
    exp = int(exp) if exp else 0
    if "." in mantissa:
        ip, fp = mantissa.split(".")
    else:
        ip, fp = mantissa, ""
    digits = (ip + fp).lstrip("0")
    # Decimal exponent of the first significant digit.
    if ip.strip("0"):
        point = len(ip.lstrip("0")) + exp  # digits before the decimal point
    else:
        point = exp - (len(fp) - len(fp.lstrip("0")))
    digits = digits.rstrip("0")
    n = len(digits)
    # Fixed.
    if point <= 0:
        fixed = "0." + "0" * (-point) + digits
    elif point >= n:
        fixed = digits + "0" * (point - n)
    else:
        fixed = digits[:point] + "." + digits[point:]
    # Scientific.
    e = point - 1
    sci = digits[0] + ("." + digits[1:] if n > 1 else "")
    sci += "e" + ("-" if e < 0 else "+") + ("%02d" % abs(e))
    return sign + (fixed if len(fixed) <= len(sci) else sci)


# ---------------------------------------------------------------------------
# Building a model.

def build(model_id, model, seed):
    rng = Rng(seed)
    cams = CAMERAS[model]
    cameras = []  # (camera_id, model_id, width, height, params)
    for c, (w, h, params) in enumerate(cams):
        cameras.append((c + 1, model_id, w, h, [float(x) for x in params]))

    # Poses: 4 images on an arc around the cloud (z up), looking at it.
    equirect = model == "EQUIRECTANGULAR"
    images = []  # dicts
    azimuths = [-38.0, -13.0, 12.0, 36.0]
    for i in range(4):
        az = math.radians(azimuths[i] + rng.uniform(-4, 4))
        el = math.radians(rng.uniform(12, 24))
        dist = rng.uniform(3.2, 4.4) if equirect else rng.uniform(5.2, 6.4)
        center = [dist * math.cos(el) * math.sin(az), -dist * math.cos(el) * math.cos(az),
                  dist * math.sin(el) + 0.4]
        target = [rng.uniform(-0.3, 0.3), rng.uniform(-0.3, 0.3), rng.uniform(-0.2, 0.2)]
        R = look_at(center, target, [0, 0, 1], math.radians(rng.uniform(-3, 3)))
        q = [round(x, 10) for x in quaternion(R)]
        Rq = rotation(q)
        t = [round(-(Rq[k][0] * center[0] + Rq[k][1] * center[1] + Rq[k][2] * center[2]), 8)
             for k in range(3)]
        images.append({"id": i + 1, "q": q, "t": t, "camera": i // 2 + 1,
                       "name": IMAGE_NAMES[i], "points2D": []})

    def pixel(image, X):
        cam = cameras[image["camera"] - 1]
        u, v, w = to_camera(image["q"], image["t"], X)
        if not equirect and w < 0.5:
            return None
        xy = project(model, cam[4], u, v, w)
        if xy is None:
            return None
        margin = 24.0
        if not (margin <= xy[0] <= cam[2] - margin and margin <= xy[1] <= cam[3] - margin):
            return None
        return xy

    # Points: a cloud of about 3 x 3 x 1.6 m around the origin, each kept when
    # at least 2 images see it; its track is 2 to 4 of those images.
    points = []  # dicts
    point_ids = []
    next_id = rng.integer(2, 9)
    attempts = 0
    while len(points) < NUM_POINTS:
        attempts += 1
        if attempts > 10000:
            raise RuntimeError(model + ": cannot place the points")
        X = [round(rng.uniform(-1.5, 1.5), 8), round(rng.uniform(-1.5, 1.5), 8),
             round(rng.uniform(-0.8, 0.8), 8)]
        seen = [im for im in images if pixel(im, X) is not None]
        if len(seen) < 2:
            continue
        rng.shuffle(seen)
        n = min(len(seen), rng.integer(2, 4))
        track_images = sorted(seen[:n], key=lambda im: im["id"])
        obs = []
        for im in track_images:
            x, y = pixel(im, X)
            nx, ny = rng.gauss(0.45), rng.gauss(0.45)
            obs.append((im, round(x + nx, 4), round(y + ny, 4), math.hypot(nx, ny)))
        if any(not (0 < o[1] < cameras[o[0]["camera"] - 1][2] and
                    0 < o[2] < cameras[o[0]["camera"] - 1][3]) for o in obs):
            continue
        error = round(sum(o[3] for o in obs) / len(obs), 6)
        rgb = [rng.integer(40, 230) for _ in range(3)]
        points.append({"id": next_id, "xyz": X, "rgb": rgb, "error": error, "obs": obs})
        point_ids.append(next_id)
        next_id += rng.integer(1, 6)

    # 2D points per image: the observations and 1 or 2 without a 3D point,
    # in a scrambled (keypoint-like) order.
    entries = {im["id"]: [] for im in images}
    for pt in points:
        for im, x, y, _ in pt["obs"]:
            entries[im["id"]].append([x, y, pt["id"]])
    for im in images:
        cam = cameras[im["camera"] - 1]
        for _ in range(rng.integer(1, 2)):
            entries[im["id"]].append([round(rng.uniform(30, cam[2] - 30), 4),
                                      round(rng.uniform(30, cam[3] - 30), 4), -1])
        e = entries[im["id"]]
        rng.shuffle(e)
        im["points2D"] = e

    # Tracks: (image_id, point2D_idx), in the order of the observations.
    for pt in points:
        track = []
        for im, x, y, _ in pt["obs"]:
            idx = next(k for k, e in enumerate(im["points2D"])
                       if e[2] == pt["id"] and e[0] == x and e[1] == y)
            track.append((im["id"], idx))
        pt["track"] = track
    rng.shuffle(points)  # COLMAP lists points in hash-map order
    return cameras, images, points


# ---------------------------------------------------------------------------
# Writers.

def write_text(dirname, cameras, images, points):
    os.makedirs(dirname, exist_ok=True)
    lines = ["# Camera list with one line of data per camera:",
             "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]",
             "# Number of cameras: %d" % len(cameras)]
    for cid, mid, w, h, params in cameras:
        lines.append(" ".join([str(cid), MODELS[mid][1], str(w), str(h)] +
                              [fmt(p) for p in params]))
    write_file(os.path.join(dirname, "cameras.txt"), "\n".join(lines) + "\n")

    linked = sum(1 for im in images for e in im["points2D"] if e[2] != -1)
    lines = ["# Image list with two lines of data per image:",
             "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME",
             "#   POINTS2D[] as (X, Y, POINT3D_ID)",
             "# Number of images: %d, mean observations per image: %s" %
             (len(images), fmt(linked / len(images)))]
    for im in images:
        lines.append(" ".join([str(im["id"])] + [fmt(v) for v in im["q"]] +
                              [fmt(v) for v in im["t"]] + [str(im["camera"]), im["name"]]))
        lines.append(" ".join("%s %s %d" % (fmt(x), fmt(y), pid)
                              for x, y, pid in im["points2D"]))
    write_file(os.path.join(dirname, "images.txt"), "\n".join(lines) + "\n")

    num_obs = sum(len(pt["track"]) for pt in points)
    lines = ["# 3D point list with one line of data per point:",
             "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)",
             "# Number of points: %d, mean track length: %s" %
             (len(points), fmt(num_obs / len(points)))]
    for pt in points:
        fields = [str(pt["id"])] + [fmt(v) for v in pt["xyz"]] + \
                 [str(c) for c in pt["rgb"]] + [fmt(pt["error"])]
        for image_id, idx in pt["track"]:
            fields += [str(image_id), str(idx)]
        lines.append(" ".join(fields))
    write_file(os.path.join(dirname, "points3D.txt"), "\n".join(lines) + "\n")


INVALID_POINT3D = 2 ** 64 - 1


def write_binary(dirname, cameras, images, points):
    os.makedirs(dirname, exist_ok=True)
    out = [struct.pack("<Q", len(cameras))]
    for cid, mid, w, h, params in cameras:
        out.append(struct.pack("<IiQQ", cid, mid, w, h))
        out.append(struct.pack("<%dd" % len(params), *params))
    write_file(os.path.join(dirname, "cameras.bin"), b"".join(out))

    out = [struct.pack("<Q", len(images))]
    for im in images:
        out.append(struct.pack("<I4d3dI", im["id"], *im["q"], *im["t"], im["camera"]))
        out.append(im["name"].encode("utf-8") + b"\0")
        out.append(struct.pack("<Q", len(im["points2D"])))
        for x, y, pid in im["points2D"]:
            out.append(struct.pack("<ddQ", x, y, INVALID_POINT3D if pid == -1 else pid))
    write_file(os.path.join(dirname, "images.bin"), b"".join(out))

    out = [struct.pack("<Q", len(points))]
    for pt in points:
        out.append(struct.pack("<Q3d3BdQ", pt["id"], *pt["xyz"], *pt["rgb"], pt["error"],
                               len(pt["track"])))
        for image_id, idx in pt["track"]:
            out.append(struct.pack("<II", image_id, idx))
    write_file(os.path.join(dirname, "points3D.bin"), b"".join(out))


def write_file(path, data):
    mode = "wb" if isinstance(data, bytes) else "w"
    kwargs = {} if isinstance(data, bytes) else {"encoding": "utf-8", "newline": "\n"}
    with open(path, mode, **kwargs) as f:
        f.write(data)


def main():
    here = os.path.dirname(os.path.abspath(__file__))
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--out", default=os.path.join(here, "..", "tests", "data",
                                                      "colmap_models"),
                        help="output directory (default: tests/data/colmap_models)")
    args = parser.parse_args()
    out = os.path.normpath(args.out)
    for model_id, model, names in MODELS:
        cams = CAMERAS[model]
        for w, h, params in cams:
            assert len(params) == len(names.split()), model
        cameras, images, points = build(model_id, model, seed=1000 + model_id)
        write_text(os.path.join(out, model, "text"), cameras, images, points)
        write_binary(os.path.join(out, model, "binary"), cameras, images, points)
    print("wrote %d models under %s" % (len(MODELS), out))
    return 0


if __name__ == "__main__":
    sys.exit(main())
