"""Where two COLMAP text models' images (or two BAL problems' cameras) are,
for the gauge tests (docs/design.md §1.6). Over the images both hold (by
image id; a BAL camera by its index):

  mean IN OUT [TOL]      OUT's centres' centroid (within TOL of IN's RMS
                         spread), RMS spread (TOL relative) and chordal mean
                         orientation (TOL rad) are IN's; default TOL 1e-9
  spread IN OUT [TOL]    only the RMS spread
  overlay A B TOL        every centre of B within TOL of A's RMS spread of A's
  colmap IN OUT ID1 ID2  ID1's pose (1e-9 rad) and ID2's x translation are IN's
                         (within 1e-9 of IN's RMS spread)

Exit 0 when it holds; otherwise 1, with the figures on stderr. With
--print, the figures go to stdout and the exit is 0."""
import bz2
import sys

import numpy as np


def rotation(q):
    w, x, y, z = np.asarray(q) / np.linalg.norm(q)
    return np.array([[1 - 2*(y*y + z*z), 2*(x*y - w*z), 2*(x*z + w*y)],
                     [2*(x*y + w*z), 1 - 2*(x*x + z*z), 2*(y*z - w*x)],
                     [2*(x*z - w*y), 2*(y*z + w*x), 1 - 2*(x*x + y*y)]])


def angle_axis(w):
    th = np.linalg.norm(w)
    if th == 0:
        return np.eye(3)
    k = w / th
    K = np.array([[0, -k[2], k[1]], [k[2], 0, -k[0]], [-k[1], k[0], 0]])
    return np.eye(3) + np.sin(th) * K + (1 - np.cos(th)) * K @ K


def centres(cameras):
    """C = -R(ω)ᵀ t of each row (ω, t, ...) of a cameras array."""
    return np.array([-angle_axis(c[:3]).T @ c[3:6] for c in cameras])


def onto(a, b):
    """a mapped onto b by the least-squares similarity (Umeyama)."""
    ma, mb = a.mean(0), b.mean(0)
    A, B = a - ma, b - mb
    U, S, Vt = np.linalg.svd(B.T @ A / len(a))
    D = np.eye(3)
    if np.linalg.det(U) * np.linalg.det(Vt) < 0:
        D[2, 2] = -1
    R = U @ D @ Vt
    s = np.trace(np.diag(S) @ D) / (A ** 2).sum(1).mean()
    return (s * (R @ A.T)).T + mb


def bal_poses(path):
    """{camera index: (R, t)} of a BAL problem (.txt or .bz2)."""
    f = bz2.open(path, "rt") if path.endswith(".bz2") else open(path)
    v = f.read().split()
    nc, no = int(v[0]), int(v[2])
    c = np.array(v[3 + 4 * no:3 + 4 * no + 9 * nc], dtype=float).reshape(nc, 9)
    return {i: (angle_axis(c[i, :3]), c[i, 3:6]) for i in range(nc)}


def poses(model):
    """{image id: (R, t)} of a COLMAP text model's images.txt, or a BAL file's cameras."""
    if model.endswith((".txt", ".bz2")):
        return bal_poses(model)
    lines = [l for l in open(f"{model}/images.txt") if not l.startswith("#")]
    out = {}
    for l in lines[0::2]:
        v = l.split()
        if len(v) >= 10:
            out[int(v[0])] = (rotation([float(a) for a in v[1:5]]), np.array([float(a) for a in v[5:8]]))
    return out


def angle(R):
    """|R - I|_F = 2√2 sin(θ/2): exact near θ = 0, where arccos of the trace is not."""
    return 2 * np.arcsin(min(1.0, np.linalg.norm(R - np.eye(3)) / (2 * np.sqrt(2))))


def mean(ps):
    C = np.array([-R.T @ t for R, t in ps])
    c = C.mean(0)
    rho = np.sqrt(((C - c) ** 2).sum(1).mean())
    U, _, Vt = np.linalg.svd(sum(R for R, _ in ps))
    M = U @ np.diag([1, 1, np.sign(np.linalg.det(U @ Vt))]) @ Vt
    return c, rho, M, C


def main(argv):
    printing = "--print" in argv
    argv = [a for a in argv if a != "--print"]
    what, a, b = argv[0], poses(argv[1]), poses(argv[2])
    ids = sorted(set(a) & set(b))
    c0, rho0, M0, C0 = mean([a[i] for i in ids])
    c1, rho1, M1, C1 = mean([b[i] for i in ids])
    if what == "colmap":
        i, j = int(argv[3]), int(argv[4])
        turn = angle(a[i][0].T @ b[i][0])
        moved = max(np.abs(a[i][1] - b[i][1]).max(), abs(a[j][1][0] - b[j][1][0])) / rho0
        figures = {"turn": turn, "moved": moved}
        ok = turn < 1e-9 and moved < 1e-9
    else:
        tol = float(argv[3]) if len(argv) > 3 else 1e-9
        figures = {"centroid": np.linalg.norm(c1 - c0) / rho0, "spread": rho1 / rho0 - 1,
                   "orientation": angle(M0.T @ M1),
                   "overlay": np.linalg.norm(C1 - C0, axis=1).max() / rho0}
        ok = {"mean": figures["centroid"] < tol and abs(figures["spread"]) < tol and figures["orientation"] < tol,
              "spread": abs(figures["spread"]) < tol,
              "overlay": figures["overlay"] < tol}[what]
    text = " ".join(f"{k} {v:.3g}" for k, v in figures.items())
    if printing:
        print(text)
        return 0
    if not ok:
        print(f"{what}: {text}", file=sys.stderr)
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
