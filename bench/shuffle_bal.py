#!/usr/bin/python3
"""Renumbers a BAL problem's points and cameras by a seeded random
permutation and writes it with its observations sorted camera by camera (as
BAL files come): the same problem in an order dba did not choose.

    /usr/bin/python3 bench/shuffle_bal.py IN.txt[.bz2] OUT.txt SEED  (numpy: python3-numpy)
"""
import bz2
import sys

import numpy as np


def read(path):
    opener = bz2.open if path.endswith(".bz2") else open
    with opener(path, "rt") as f:
        data = f.read().split()
    nc, npts, no = int(data[0]), int(data[1]), int(data[2])
    obs = np.array(data[3:3 + 4 * no], dtype=object).reshape(no, 4)
    rest = np.array(data[3 + 4 * no:], dtype=object)
    cams = rest[:9 * nc].reshape(nc, 9)
    pts = rest[9 * nc:9 * nc + 3 * npts].reshape(npts, 3)
    return obs, cams, pts


def main():
    src, dst, seed = sys.argv[1], sys.argv[2], int(sys.argv[3])
    obs, cams, pts = read(src)
    rng = np.random.default_rng(seed)
    camera_perm = rng.permutation(len(cams))  # new -> old
    point_perm = rng.permutation(len(pts))
    camera_new = np.argsort(camera_perm)      # old -> new
    point_new = np.argsort(point_perm)
    c = camera_new[obs[:, 0].astype(np.int64)]
    p = point_new[obs[:, 1].astype(np.int64)]
    by_camera = np.lexsort((p, c))
    with open(dst, "w") as f:
        f.write(f"{len(cams)} {len(pts)} {len(obs)}\n")
        for j in by_camera:
            f.write(f"{c[j]} {p[j]} {obs[j, 2]} {obs[j, 3]}\n")
        for i in camera_perm:
            f.write("\n".join(cams[i]) + "\n")
        for k in point_perm:
            f.write("\n".join(pts[k]) + "\n")


if __name__ == "__main__":
    main()
