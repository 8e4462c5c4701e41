"""One row of bench/ground_control.sh: check points against their truth.

The generator's GCP file gives each point's surveyed position and, as a
comment, its true one; the accuracy report gives triangulated - surveyed.
The best similarity of the triangulated points onto the truth is Horn's
closed form (unit quaternion: the top eigenvector of his 4x4 matrix, by
power iteration), in plain Python (no numpy here).
"""
import json
import math
import sys

work, images, seed = sys.argv[1], int(sys.argv[2]), sys.argv[3]
surveyed, truth = {}, {}
for line in open(f"{work}/g.txt"):
    if "# true" in line and " check " in line:
        f = line.split()
        surveyed[f[0]] = [float(x) for x in f[1:4]]
        truth[f[0]] = [float(x) for x in line.split("# true")[1].split()]
tri = {}
for line in open(f"{work}/acc.txt"):
    f = line.split()
    if f and f[0] == "check":
        tri[f[1]] = [surveyed[f[1]][k] + float(f[2 + k]) for k in range(3)]
names = sorted(tri)
P = [tri[n] for n in names]
Q = [truth[n] for n in names]
n = len(P)


def rms(a, b):
    return math.sqrt(sum(sum((x[k] - y[k]) ** 2 for k in range(3)) for x, y in zip(a, b)) / len(a))


def similarity(P, Q):
    mp = [sum(p[k] for p in P) / len(P) for k in range(3)]
    mq = [sum(q[k] for q in Q) / len(Q) for k in range(3)]
    A = [[p[k] - mp[k] for k in range(3)] for p in P]
    B = [[q[k] - mq[k] for k in range(3)] for q in Q]
    S = [[sum(a[i] * b[j] for a, b in zip(A, B)) for j in range(3)] for i in range(3)]
    (xx, xy, xz), (yx, yy, yz), (zx, zy, zz) = S
    N = [[xx + yy + zz, yz - zy, zx - xz, xy - yx],
         [yz - zy, xx - yy - zz, xy + yx, zx + xz],
         [zx - xz, xy + yx, -xx + yy - zz, yz + zy],
         [xy - yx, zx + xz, yz + zy, -xx - yy + zz]]
    shift = sum(abs(v) for row in N for v in row)  # makes N + shift I positive definite
    q = [1.0, 0.0, 0.0, 0.0]
    for _ in range(2000):
        v = [sum(N[i][j] * q[j] for j in range(4)) + shift * q[i] for i in range(4)]
        norm = math.sqrt(sum(x * x for x in v))
        q = [x / norm for x in v]
    w, x, y, z = q
    R = [[1 - 2 * (y * y + z * z), 2 * (x * y - z * w), 2 * (x * z + y * w)],
         [2 * (x * y + z * w), 1 - 2 * (x * x + z * z), 2 * (y * z - x * w)],
         [2 * (x * z - y * w), 2 * (y * z + x * w), 1 - 2 * (x * x + y * y)]]
    RA = [[sum(R[i][j] * a[j] for j in range(3)) for i in range(3)] for a in A]
    s = sum(sum(ra[k] * b[k] for k in range(3)) for ra, b in zip(RA, B)) / sum(
        sum(v * v for v in a) for a in A)
    return [[s * ra[k] + mq[k] for k in range(3)] for ra in RA]


absolute = rms(P, Q)
aligned = rms(similarity(P, Q), Q)
with_ = json.load(open(f"{work}/with.json"))
without = json.load(open(f"{work}/without.json"))
per_it = lambda d: 1000 * (d["seconds"]["rcs_formation"] + d["seconds"]["linear_solve"] +
                           d["seconds"]["back_substitution"]) / max(1, d["iterations"])
print(f"| {seed} | {images} | {absolute:.4f} | {aligned:.4f} | {absolute / aligned:.3f} | "
      f"{with_['control_points']['rms_3d']:.4f} | {with_['iterations']} | "
      f"{per_it(with_):.0f} | {per_it(without):.0f} |")
