# dba.solve_arrays: arrays read from a problem solve to the same cost as the
# file; observation order does not matter; fixed flags hold; the photo model
# with intrinsic groups; bad arrays and file-only options are refused.
import numpy as np
import pytest

import dba
from conftest import LADYBUG, LADYBUG_EXACT_COST, SHARED_DATA, TIME_PHASES


def solve_problem(p, **options):
    return dba.solve_arrays(p.cameras, p.points, p.observations, p.camera_indices,
                            p.point_indices, camera_model=p.camera_model,
                            intrinsics=p.intrinsics, camera_intrinsics=p.camera_intrinsics,
                            fixed_cameras=p.fixed_cameras, fixed_intrinsics=p.fixed_intrinsics,
                            lens_models=p.lens_models, **options)


def test_read_problem_arrays(ladybug_problem):
    p = ladybug_problem
    assert p.camera_model == "bal"
    assert p.cameras.shape == (49, 9) and p.points.shape == (7776, 3)
    assert p.observations.shape == (31843, 2)
    assert p.camera_indices.shape == p.point_indices.shape == (31843,)
    assert p.intrinsics.shape == (0, 5) and not p.fixed_cameras.any()


def test_arrays_round_trip_to_the_files_cost(ladybug_problem):
    # One thread: the same problem gives bit-identical solves (with more, the
    # order of the RCS sums varies).
    before = ladybug_problem.cameras.copy()
    from_file = dba.solve(LADYBUG, threads=1)
    r = solve_problem(ladybug_problem, threads=1)
    assert r.summary.final_cost == pytest.approx(LADYBUG_EXACT_COST, rel=1e-5)
    assert r.summary.initial_cost == from_file.summary.initial_cost
    assert r.summary.final_cost == from_file.summary.final_cost
    assert r.summary.iterations == from_file.summary.iterations
    np.testing.assert_array_equal(r.cameras, from_file.cameras)
    np.testing.assert_array_equal(r.points, from_file.points)
    np.testing.assert_array_equal(ladybug_problem.cameras, before)  # input untouched


def test_observation_order_does_not_matter(ladybug_problem):
    p = ladybug_problem
    order = np.random.default_rng(3).permutation(len(p.observations))
    r = dba.solve_arrays(p.cameras, p.points, p.observations[order], p.camera_indices[order],
                         p.point_indices[order], threads=2, max_iterations=3)
    reference = solve_problem(p, threads=2, max_iterations=3)
    assert r.summary.initial_cost == pytest.approx(reference.summary.initial_cost, rel=1e-12)
    assert r.summary.final_cost == pytest.approx(reference.summary.final_cost, rel=1e-6)


def test_fixed_cameras_do_not_move(ladybug_problem):
    p = ladybug_problem
    fixed = np.zeros(49, dtype=bool)
    fixed[[0, 7]] = True
    r = dba.solve_arrays(p.cameras, p.points, p.observations, p.camera_indices,
                         p.point_indices, fixed_cameras=fixed, threads=2, max_iterations=5)
    np.testing.assert_array_equal(r.cameras[[0, 7]], p.cameras[[0, 7]])
    assert not np.allclose(r.cameras[1], p.cameras[1])
    assert r.problem.fixed_cameras.tolist() == fixed.tolist()
    # The command line's --fix-images, by its option name.
    r2 = dba.solve_arrays(p.cameras, p.points, p.observations, p.camera_indices,
                          p.point_indices, fix_images=[0, 7], threads=2, max_iterations=5)
    assert r2.summary.final_cost == pytest.approx(r.summary.final_cost, rel=1e-9)


def test_photo_model_with_intrinsic_groups():
    model = SHARED_DATA / "colmap" / "mithunnallana_6img" / "sparse" / "0"
    p = dba.read_problem(model)
    assert p.camera_model == "photo" and p.intrinsics.shape == (1, 4)
    assert p.lens_models == ["SIMPLE_RADIAL"]
    from_file = dba.solve(model, threads=2)
    r = solve_problem(p, threads=2)
    assert r.summary.final_cost == pytest.approx(from_file.summary.final_cost, rel=1e-9)
    # Fixed intrinsics stay where they were.
    fixed = np.ones((1, 4), dtype=bool)
    held = dba.solve_arrays(p.cameras, p.points, p.observations, p.camera_indices,
                            p.point_indices, camera_model="photo", intrinsics=p.intrinsics,
                            camera_intrinsics=p.camera_intrinsics, fixed_intrinsics=fixed,
                            lens_models=p.lens_models, threads=2, max_iterations=5)
    np.testing.assert_array_equal(held.intrinsics, p.intrinsics)
    assert held.summary.final_cost < held.summary.initial_cost
    # The same camera as OPENCV (fx = fy = f, k1 = k, the rest 0): two
    # focal lengths and tangential terms, never above SIMPLE_RADIAL's cost.
    f, cx, cy, k = p.intrinsics[0]
    opencv = np.array([[f, f, cx, cy, k, 0, 0, 0]])
    r8 = dba.solve_arrays(p.cameras, p.points, p.observations, p.camera_indices,
                          p.point_indices, camera_model="photo", intrinsics=opencv,
                          camera_intrinsics=p.camera_intrinsics, lens_models=["OPENCV"],
                          threads=2)
    assert r8.problem.lens_models == ["OPENCV"] and r8.intrinsics.shape == (1, 8)
    assert r8.summary.final_cost <= from_file.summary.final_cost * (1 + 1e-5)
    assert r8.intrinsics[0, 0] != r8.intrinsics[0, 1]  # fx and fy apart
    with pytest.raises(ValueError, match=r"lens_models\[0\] = 'OPENCV5': unknown"):
        dba.solve_arrays(p.cameras, p.points, p.observations, p.camera_indices,
                         p.point_indices, camera_model="photo", intrinsics=opencv,
                         camera_intrinsics=p.camera_intrinsics, lens_models=["OPENCV5"])
    with pytest.raises(ValueError, match=r"OPENCV \(group 0\) has 8 parameters, the array 4"):
        dba.solve_arrays(p.cameras, p.points, p.observations, p.camera_indices,
                         p.point_indices, camera_model="photo", intrinsics=p.intrinsics,
                         camera_intrinsics=p.camera_intrinsics, lens_models=["OPENCV"])
    # A value no camera has (a focal length of 0) is refused by name.
    zero_f = p.intrinsics.copy()
    zero_f[0, 0] = 0.0
    with pytest.raises(ValueError, match=r"intrinsics\[0\]: SIMPLE_RADIAL's f is 0: it must be > 0"):
        dba.solve_arrays(p.cameras, p.points, p.observations, p.camera_indices,
                         p.point_indices, camera_model="photo", intrinsics=zero_f,
                         camera_intrinsics=p.camera_intrinsics, lens_models=p.lens_models)


def test_bad_arrays_are_refused(ladybug_problem):
    p = ladybug_problem
    bad = p.camera_indices.copy()
    bad[5] = 49
    with pytest.raises(ValueError, match=r"camera_indices\[5\] = 49: out of range \(49 cameras\)"):
        dba.solve_arrays(p.cameras, p.points, p.observations, bad, p.point_indices)
    with pytest.raises(ValueError, match=r"cameras: expected shape \(N, 9\), got \(49, 8\)"):
        dba.solve_arrays(p.cameras[:, :8], p.points, p.observations, p.camera_indices,
                         p.point_indices)
    points = p.points.copy()
    points[2, 1] = np.nan
    with pytest.raises(ValueError, match="points: value 7 is not finite"):
        dba.solve_arrays(p.cameras, points, p.observations, p.camera_indices, p.point_indices)
    far = p.observations.copy()
    far[3, 0] = 1e80
    with pytest.raises(ValueError, match=r"observations\[3\]: pixel \(1e\+80, .*\) is beyond 1e7 px"):
        dba.solve_arrays(p.cameras, p.points, far, p.camera_indices, p.point_indices)
    with pytest.raises(ValueError, match="output: solve_arrays returns its result"):
        dba.solve_arrays(p.cameras, p.points, p.observations, p.camera_indices,
                         p.point_indices, output="x.txt")


def test_times_add_up_from_the_call(ladybug_problem):
    s = solve_problem(ladybug_problem, threads=1).summary
    assert sum(s.seconds[k] for k in TIME_PHASES) == pytest.approx(s.seconds["total"], abs=1e-9)
    assert s.seconds["read"] > 0 and s.seconds["other"] >= 0
    assert s.seconds["total"] >= s.seconds["rcs_formation"] + s.seconds["linear_solve"]


def test_arrays_of_the_wrong_dtype_are_refused_not_cast(ladybug_problem):
    # Indices must be integers, flags booleans, values numbers: a float,
    # bool or str array was cast silently (1.7 -> 1, '12' -> 12, True -> 1).
    # Named: the argument, the dtype given, the one expected.
    p = ladybug_problem

    def solve(**change):
        a = dict(cameras=p.cameras, points=p.points, observations=p.observations,
                 camera_indices=p.camera_indices, point_indices=p.point_indices)
        a.update(change)
        return dba.solve_arrays(**a, max_iterations=1)
    cases = [
        (dict(camera_indices=p.camera_indices.astype(float)),
         "camera_indices: expected an integer array, got dtype float64"),
        (dict(point_indices=p.point_indices.astype(bool)),
         "point_indices: expected an integer array, got dtype bool"),
        (dict(camera_indices=p.camera_indices.astype(str)),
         "camera_indices: expected an integer array, got dtype <U2"),
        (dict(fixed_cameras=np.zeros(49, dtype=np.int64)),
         "fixed_cameras: expected a boolean array, got dtype int64"),
        (dict(fixed_cameras=np.zeros(49)),
         "fixed_cameras: expected a boolean array, got dtype float64"),
        (dict(observations=p.observations.astype(str)),
         r"observations: expected an array of numbers \(float or integer\), got dtype <U"),
        (dict(cameras=p.cameras.astype(complex)),
         r"cameras: expected an array of numbers \(float or integer\), got dtype complex128"),
        (dict(points=[[1, 2, "x"]]),
         r"points: expected an array of numbers \(float or integer\), got dtype <U"),
    ]
    for change, message in cases:
        with pytest.raises(TypeError, match=message):
            solve(**change)
    # Any integer width is an index, and integer values are numbers.
    r = solve(camera_indices=p.camera_indices.astype(np.int32),
              point_indices=p.point_indices.astype(np.uint32),
              fixed_cameras=np.zeros(49, dtype=bool), points=p.points.astype(np.float32))
    assert r.summary.iterations == 1
