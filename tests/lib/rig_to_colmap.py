"""Writes a generated rig problem (.dba version 4, dba generate --rig) as a
COLMAP >= 3.12 text model with rigs and frames: camera s+1 per sensor s
(RADIAL, 1000 x 1000), image f*S+s+1 the sensor s of frame f+1, rig 1 with
camera 1 its origin and the others posed (HAS_POSE 1, or 0 with --no-pose),
each frame at its origin image's pose. The images' poses are composed from
the frames and sensors, so every sensor's pose is image o frame^-1 of frame 1.
--imu-origin: the rig's reference sensor an IMU at camera 1's place (camera 1
then a posed sensor at the identity), each frame with its IMU datum.
Usage: rig_to_colmap.py RIG.dba SENSORS OUT_DIR [--no-pose] [--imu-origin]"""
import os
import sys

import numpy as np

import dba
from gauge_check import angle_axis as rot  # R(ω), Rodrigues

path, sensors, out = sys.argv[1], int(sys.argv[2]), sys.argv[3]
no_pose = "--no-pose" in sys.argv
imu = "--imu-origin" in sys.argv
p = dba.read_problem(path)
n = len(p.cameras)


def quat(R):
    w = np.sqrt(max(0.0, 1 + R[0, 0] + R[1, 1] + R[2, 2])) / 2
    x = np.copysign(np.sqrt(max(0.0, 1 + R[0, 0] - R[1, 1] - R[2, 2])) / 2, R[2, 1] - R[1, 2])
    y = np.copysign(np.sqrt(max(0.0, 1 - R[0, 0] + R[1, 1] - R[2, 2])) / 2, R[0, 2] - R[2, 0])
    z = np.copysign(np.sqrt(max(0.0, 1 - R[0, 0] - R[1, 1] + R[2, 2])) / 2, R[1, 0] - R[0, 1])
    return np.array([w, x, y, z])


def fmt(v):
    return " ".join(repr(float(x)) for x in v)


os.makedirs(out, exist_ok=True)
with open(f"{out}/cameras.txt", "w") as f:
    for s in range(sensors):
        f.write(f"{s + 1} RADIAL 1000 1000 {fmt(p.intrinsics[s][:5])}\n")
# 2D points per image, in observation order, and each point's track.
points2d = [[] for _ in range(n)]
tracks = [[] for _ in range(len(p.points))]
for (x, y), i, k in zip(p.observations, p.camera_indices, p.point_indices):
    tracks[k].append((i + 1, len(points2d[i])))
    points2d[i].append((x, y, k + 1))
poses = [(rot(c[:3]), c[3:6]) for c in p.cameras]
with open(f"{out}/images.txt", "w") as f:
    for i, (R, t) in enumerate(poses):
        f.write(f"{i + 1} {fmt(quat(R))} {fmt(t)} {i % sensors + 1} img{i + 1:05d}.jpg\n")
        f.write(" ".join(f"{x!r} {y!r} {k}" for x, y, k in points2d[i]) + "\n")
with open(f"{out}/points3D.txt", "w") as f:
    for k, X in enumerate(p.points):
        f.write(f"{k + 1} {fmt(X)} 128 128 128 0.5 " + " ".join(f"{i} {j}" for i, j in tracks[k]) + "\n")
# sensor s about the origin: image s o image 0 ^-1 in frame 1.
R0, t0 = poses[0]
with open(f"{out}/rigs.txt", "w") as f:
    line = f"1 {sensors + 1} IMU 1 CAMERA 1 1 1 0 0 0 0 0 0" if imu else f"1 {sensors} CAMERA 1"
    for s in range(1, sensors):
        R, t = poses[s]
        Rs = R @ R0.T
        ts = t - Rs @ t0
        line += f" CAMERA {s + 1} 0" if no_pose else f" CAMERA {s + 1} 1 {fmt(quat(Rs))} {fmt(ts)}"
    f.write(line + "\n")
with open(f"{out}/frames.txt", "w") as f:
    for fr in range(n // sensors):
        R, t = poses[fr * sensors]
        data = " ".join(f"CAMERA {s + 1} {fr * sensors + s + 1}" for s in range(sensors))
        if imu:
            data += f" IMU 1 {fr + 1}"
        f.write(f"{fr + 1} 1 {fmt(quat(R))} {fmt(t)} {sensors + imu} {data}\n")
