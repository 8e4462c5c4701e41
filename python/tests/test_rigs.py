# Rigs through Python (docs/design.md §1.7): read_problem returns a
# rig .dba's frames and sensors; solve_arrays given them solves the rig (6
# unknowns per frame and 6 per refined sensor) to the file's final cost with
# a tight direct solve (1e-9), returns the solved frames and sensors, holds
# them with rig_geometry='fixed', holds a fixed image's pose (its frame and
# its sensor), and refuses rig arrays that do not fit.
import subprocess

import numpy as np
import pytest

import dba
from test_options_effect import DBA

TIGHT = dict(threads=2, linear_solver="dense", function_tolerance=1e-12, quiet=True)


@pytest.fixture(scope="module")
def rig_path(tmp_path_factory):
    d = tmp_path_factory.mktemp("rig")
    subprocess.run([DBA, "generate", str(d / "r.dba"), "--model", "photo", "--rig", "stereo",
                    "--images", "80", "--seed", "3"], check=True, capture_output=True)
    return d / "r.dba"


@pytest.fixture(scope="module")
def rig(rig_path):
    return dba.read_problem(rig_path)


def arrays(p):
    return dict(camera_model="photo", intrinsics=p.intrinsics, camera_intrinsics=p.camera_intrinsics,
                lens_models=p.lens_models, frame_indices=p.frame_indices,
                rig_from_world=p.rig_from_world, sensor_from_rig=p.sensor_from_rig,
                sensor_kinds=p.sensor_kinds)


def test_read_problem_returns_the_rig(rig):
    assert rig.frame_indices.tolist() == [i // 2 for i in range(80)]
    assert rig.rig_from_world.shape == (40, 6) and rig.sensor_from_rig.shape == (2, 6)
    assert rig.sensor_kinds.tolist() == [0, 1]
    assert np.all(rig.sensor_from_rig[0] == 0)


def test_solve_arrays_solves_the_rig_as_the_file(rig, rig_path):
    from_file = dba.solve(rig_path, **TIGHT)
    r = dba.solve_arrays(rig.cameras, rig.points, rig.observations, rig.camera_indices,
                         rig.point_indices, **arrays(rig), **TIGHT)
    assert r.summary.report["camera_unknowns"] == 40 * 6 + 6 + 2 * 3
    assert r.summary.final_cost == pytest.approx(from_file.summary.final_cost, rel=1e-9)
    out = r.problem
    assert np.abs(out.sensor_from_rig[1] - rig.sensor_from_rig[1]).max() > 0  # refined
    assert np.all(out.sensor_from_rig[0] == 0)
    assert out.rig_from_world.shape == (40, 6)
    assert np.abs(out.rig_from_world - rig.rig_from_world).max() > 0
    held = dba.solve_arrays(rig.cameras, rig.points, rig.observations, rig.camera_indices,
                            rig.point_indices, **arrays(rig), rig_geometry="fixed", **TIGHT)
    assert held.summary.report["camera_unknowns"] == 40 * 6 + 2 * 3
    assert np.array_equal(held.problem.sensor_from_rig, rig.sensor_from_rig)


def test_fix_images_holds_the_images_pose(rig, rig_path):
    # Image 1 (the second camera in frame 0): its frame and its sensor held
    # (in every frame), so its pose is the input's where image 3 moves; the
    # file's solve the same.
    r = dba.solve_arrays(rig.cameras, rig.points, rig.observations, rig.camera_indices,
                         rig.point_indices, **arrays(rig), fix_images=[1], max_iterations=5,
                         **TIGHT)
    from_file = dba.solve(rig_path, fix_images=[1], max_iterations=5, **TIGHT)
    for out in (r, from_file):
        assert out.summary.report["camera_unknowns"] == 39 * 6 + 2 * 3
        assert np.abs(out.problem.cameras[1] - rig.cameras[1]).max() <= 1e-12
        assert np.abs(out.problem.cameras[3] - rig.cameras[3]).max() > 1e-6
    assert np.array_equal(r.problem.sensor_from_rig, rig.sensor_from_rig)
    assert np.array_equal(r.problem.rig_from_world[0], rig.rig_from_world[0])


def test_rig_arrays_that_do_not_fit_are_refused(rig):
    def solve(**change):
        a = {**arrays(rig), **change}
        return dba.solve_arrays(rig.cameras, rig.points, rig.observations, rig.camera_indices,
                                rig.point_indices, **a, **TIGHT)
    with pytest.raises(ValueError, match=r"frame_indices\[0\] = 99 is out of range \[0, 40\)"):
        solve(frame_indices=np.where(np.arange(80) == 0, 99, rig.frame_indices))
    with pytest.raises(ValueError, match="sensor_from_rig: expected one row per intrinsic group"):
        solve(sensor_from_rig=rig.sensor_from_rig[:1])
    with pytest.raises(ValueError, match=r"sensor_kinds\[1\] = 0: expected 0 \(the rig's origin"):
        solve(sensor_kinds=np.array([0, 0]))
    with pytest.raises(ValueError, match="need frame_indices"):
        solve(frame_indices=None)
    with pytest.raises(ValueError, match=r"frame_indices: frame 0 holds images 0 and 2 of sensor "
                                         r"\(group\) 0 \(a frame is one exposure"):
        solve(frame_indices=np.where(np.arange(80) == 2, 0, rig.frame_indices))


def test_solve_arrays_with_gnss_on_the_frames_and_a_lever_arm(tmp_path):
    # Priors on the frames at the antenna, a refined lever arm, a sensor held
    # by group: the arrays reach the file's solve (1e-9) and the same lever arm.
    subprocess.run([DBA, "generate", str(tmp_path / "g.dba"), "--model", "photo", "--rig",
                    "oblique5", "--images", "500", "--seed", "2", "--priors",
                    str(tmp_path / "p.txt"), "--gnss-sigma", "0.02,0.02", "--lever-arm",
                    "0.2,0.1,-0.3"], check=True, capture_output=True)
    options = dict(camera_priors=tmp_path / "p.txt", refine_lever_arm=True,
                   rig_geometry="fixed:2", **TIGHT)
    from_file = dba.solve(tmp_path / "g.dba", **options)
    p = dba.read_problem(tmp_path / "g.dba")
    r = dba.solve_arrays(p.cameras, p.points, p.observations, p.camera_indices, p.point_indices,
                         **arrays(p), **options)
    assert r.summary.report["camera_unknowns"] == 100 * 6 + 5 * 3 + 3 * 6 + 3
    assert r.summary.final_cost == pytest.approx(from_file.summary.final_cost, rel=1e-9)
    a, b = (x.summary.report["camera_priors"]["lever_arm"] for x in (r, from_file))
    assert np.allclose(a, b, atol=1e-9) and r.summary.report["camera_priors"]["lever_arm_refined"]
    # Held: its turn as given, its place only scaled with the world by the
    # alignment onto the priors (the input's units become metres).
    held, given = r.problem.sensor_from_rig[2], p.sensor_from_rig[2]
    assert np.array_equal(held[:3], given[:3])
    scale = held[3] / given[3]
    assert abs(scale - 1) < 0.02 and np.allclose(held[3:], scale * given[3:], rtol=0, atol=1e-15)


def test_rig_geometry_without_rigs_is_refused(rig):
    # The arrays without frames are a problem without rigs: nothing to hold.
    a = {k: v for k, v in arrays(rig).items()
         if k not in ("frame_indices", "rig_from_world", "sensor_from_rig", "sensor_kinds")}
    with pytest.raises(ValueError, match="--rig-geometry: the problem has no rigs"):
        dba.solve_arrays(rig.cameras, rig.points, rig.observations, rig.camera_indices,
                         rig.point_indices, **a, rig_geometry="fixed", **TIGHT)
