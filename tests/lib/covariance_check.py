"""Checks of `dba solve --covariance FILE` outputs (tests/cli_covariance.sh).

  valid FILE IMAGES DATUM       IMAGES lines after the header, 38 columns, each
                                pose block symmetric positive semi-definite, its
                                sigmas the roots of its diagonal, DATUM (or held,
                                or undetermined)
  held FILE NAME [MARK]         the image NAME is marked held (or MARK), no figures
  same FILE1 FILE2 REL          equal figures (REL of each block's largest
                                diagonal entry), line by line
  scaled FILE1 FILE2 FACTOR     FILE2's blocks are FILE1's times FACTOR (1e-7: 9 digits written)
  matched FILE1 FILE2 REL       the same set of centre blocks whatever the
                                images' order (each FILE2 block has a FILE1 one)
  points FILE COUNT             a --point-covariance file: COUNT lines, indices
                                increasing, each 3x3 positive definite
"""
import csv
import math
import sys

import numpy as np


def read(path):
    with open(path, newline="") as f:
        rows = list(csv.reader(f))
    return rows[0], rows[1:]


def block(row):
    p = [float(v) for v in row[14:35]]
    m = np.zeros((6, 6))
    k = 0
    for a in range(6):
        for c in range(a, 6):
            m[a, c] = m[c, a] = p[k]
            k += 1
    return m


def valid(path, images, datum):
    header, rows = read(path)
    assert len(header) == 38 and header[:3] == ["image", "datum", "sigma_x"], header
    assert header[35:] == ["x", "y", "z"], header
    assert len(rows) == int(images), (len(rows), images)
    for row in rows:
        assert len(row) == 38, row
        assert all(math.isfinite(float(v)) for v in row[35:]), row  # the centre, always
        if row[1] in ("held", "undetermined"):
            assert all(v == "" for v in row[2:35]), row
            continue
        assert row[1] == datum, row[:2]
        m = block(row)
        w = np.linalg.eigvalsh(m)
        assert w.min() >= -1e-12 * w.max(), (row[0], w)
        for a in range(3):
            assert math.isclose(float(row[2 + a]) ** 2, m[3 + a, 3 + a], rel_tol=1e-6), row[0]
            deg = math.degrees(math.sqrt(m[a, a]))
            assert math.isclose(float(row[11 + a]), deg, rel_tol=1e-6), row[0]
        c = [float(v) for v in row[5:11]]
        assert np.allclose(c, [m[3, 3], m[3, 4], m[3, 5], m[4, 4], m[4, 5], m[5, 5]], rtol=1e-6)


def held(path, name, mark="held"):
    _, rows = read(path)
    row = next(r for r in rows if r[0] == name)
    assert row[1] == mark and all(v == "" for v in row[2:35]), row


def same(path1, path2, rel):
    _, a = read(path1)
    _, b = read(path2)
    assert len(a) == len(b)
    for ra, rb in zip(a, b):
        assert ra[:2] == rb[:2], (ra[:2], rb[:2])
        if ra[1] == "held":
            continue
        ma, mb = block(ra), block(rb)
        d = np.abs(ma - mb).max() / np.diag(ma).max()
        assert d <= float(rel), (ra[0], d)


def scaled(path1, path2, factor):
    _, a = read(path1)
    _, b = read(path2)
    for ra, rb in zip(a, b):
        if ra[1] != "held":
            assert np.allclose(block(rb), float(factor) * block(ra), rtol=1e-7, atol=0), ra[0]


def matched(path1, path2, rel):
    _, a = read(path1)
    _, b = read(path2)
    assert len(a) == len(b)
    blocks = [block(r) for r in a]
    for rb in b:
        mb = block(rb)
        best = min(np.abs(ma - mb).max() / np.diag(mb).max() for ma in blocks)
        assert best <= float(rel), (rb[0], best)


def points(path, count, undetermined=""):
    """count lines, positive definite; `undetermined` (comma-separated
    indices): exactly those lines empty."""
    empty = {int(i) for i in undetermined.split(",") if i}
    header, rows = read(path)
    assert header == ["point", "sigma_x", "sigma_y", "sigma_z", "c_xx", "c_xy", "c_xz", "c_yy", "c_yz",
                      "c_zz"], header
    assert len(rows) == int(count), (len(rows), count)
    last = -1
    for row in rows:
        assert int(row[0]) > last, row[0]
        last = int(row[0])
        assert (row[1:] == [""] * 9) == (last in empty), row
        if last in empty:
            continue
        c = [float(v) for v in row[4:10]]
        m = np.array([[c[0], c[1], c[2]], [c[1], c[3], c[4]], [c[2], c[4], c[5]]])
        assert np.linalg.eigvalsh(m).min() > 0, row[0]
        assert np.allclose([float(v) ** 2 for v in row[1:4]], np.diag(m), rtol=1e-6), row[0]


if __name__ == "__main__":
    try:
        globals()[sys.argv[1]](*sys.argv[2:])
    except AssertionError as e:
        print(f"covariance_check {' '.join(sys.argv[1:])}: {e}", file=sys.stderr)
        sys.exit(1)
