# The covariance as arrays (Result.covariance): solve_arrays(covariance=True)
# gives the figures dba solve --covariance writes, to the 9 digits the file
# holds; unit scale is a-posteriori over the variance factor; points with
# their input indices; a held image NaN and marked; what it needs refused.
import csv

import numpy as np
import pytest

import dba
from conftest import SHARED_DATA

P16 = SHARED_DATA / "bal" / "problem-16-22106-pre.txt.bz2"
TIGHT = dict(linear_solver="dense", function_tolerance=1e-12, parameter_tolerance=1e-14)


@pytest.fixture(scope="module")
def p16():
    return dba.read_problem(P16)


def arrays(p, **options):
    return dba.solve_arrays(p.cameras, p.points, p.observations, p.camera_indices, p.point_indices,
                            fixed_cameras=p.fixed_cameras, **TIGHT, **options)


def file_blocks(path):
    rows = list(csv.reader(open(path)))
    assert rows[0][14] == "p11"
    blocks = []
    for row in rows[1:]:
        m = np.full((6, 6), np.nan)
        if row[14]:
            upper = iter(float(v) for v in row[14:35])
            for a in range(6):
                for c in range(a, 6):
                    m[a, c] = m[c, a] = next(upper)
        blocks.append((row[1], m))
    return blocks


def test_arrays_hold_the_files_figures(p16, tmp_path):
    r = arrays(p16, covariance=True, point_covariance=True)
    f = dba.solve(P16, covariance=tmp_path / "c.csv", point_covariance=tmp_path / "p.csv", **TIGHT)
    c = r.covariance
    assert c.pose.shape == (16, 6, 6) and c.state == ["inner"] * 16
    for (state, m), pose in zip(file_blocks(tmp_path / "c.csv"), c.pose):
        assert state == "inner"
        assert np.abs(pose - m).max() <= 1e-7 * np.diag(m).max()
    assert np.abs(f.covariance.pose - c.pose).max() <= 1e-7 * np.abs(c.pose).max()
    assert np.allclose(c.centre_sigma, np.sqrt(c.pose[:, [3, 4, 5], [3, 4, 5]]))
    assert c.points.shape == (22106, 3, 3) and (c.point_index == np.arange(22106)).all()
    rows = list(csv.reader(open(tmp_path / "p.csv")))[1:]
    assert np.allclose([float(v) for v in rows[100][1:4]], np.sqrt(np.diag(c.points[100])), rtol=1e-7)
    assert (np.linalg.eigvalsh(c.points) > 0).all()


def test_unit_scale_is_a_posteriori_over_the_variance_factor(p16):
    a = arrays(p16, covariance=True)
    u = arrays(p16, covariance=True, covariance_scale="unit")
    factor = u.summary.report["covariance"]["variance_factor"]
    assert u.summary.report["covariance"]["scale"] == "unit"
    assert 0.2 < factor < 1.0
    assert np.allclose(a.covariance.pose, factor * u.covariance.pose, rtol=1e-9, atol=0)


def test_a_held_image_is_nan_and_marked(p16):
    r = arrays(p16, covariance=True, fix_images=[0, 5])
    c = r.covariance
    assert c.state[0] == c.state[5] == "held" and c.state[1] == "absolute"
    assert np.isnan(c.pose[[0, 5]]).all() and np.isfinite(c.pose[1]).all()


def test_without_it_none_and_what_it_needs_refused(p16):
    assert arrays(p16).covariance is None
    with pytest.raises(ValueError, match="point_covariance needs covariance=True"):
        arrays(p16, point_covariance=True)
    with pytest.raises(TypeError, match="expected True or False"):
        arrays(p16, covariance="c.csv")
