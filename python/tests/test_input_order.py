# The order a problem comes in changes no result beyond rounding:
# a survey with its points and cameras renumbered by a random permutation
# (observations re-sorted camera by camera, as BAL files are) solves, with a
# tight direct solve, to the ordered solve's parameters within 1e-9 relative
# once renumbered back; the results come back in the input's own order.
import subprocess

import numpy as np
import pytest

import dba
from test_options_effect import DBA


@pytest.fixture(scope="module")
def survey_dir(tmp_path_factory):
    d = tmp_path_factory.mktemp("order")
    subprocess.run([DBA, "generate", str(d / "s.dba"), "--images", "60", "--seed", "4",
                    "--priors", str(d / "s.priors")], check=True, capture_output=True)
    return d


@pytest.fixture(scope="module")
def survey(survey_dir):
    return dba.read_problem(survey_dir / "s.dba")


# The free gauge: LM's own optimum is compared (the held gauge,
# tests/cli_gauge.sh, would map both alike: it is the cameras' mean, the
# same in any numbering).
def solve(cameras, points, observations, camera_indices, point_indices, **options):
    return dba.solve_arrays(cameras, points, observations, camera_indices, point_indices,
                            camera_model="bal", threads=2, linear_solver="sparse",
                            max_iterations=15, function_tolerance=1e-12,
                            **{"quiet": True, "gauge": "free", **options})


def shuffle(p, seed):
    """The survey's points and cameras renumbered (observations camera by
    camera), and the old -> new maps of both."""
    rng = np.random.default_rng(seed)
    point_perm = rng.permutation(len(p.points))   # new -> old
    camera_perm = rng.permutation(len(p.cameras))
    point_new = np.argsort(point_perm)            # old -> new
    camera_new = np.argsort(camera_perm)
    cams = camera_new[p.camera_indices]
    pts = point_new[p.point_indices]
    by_camera = np.lexsort((pts, cams))           # camera by camera, as BAL files are
    arrays = (p.cameras[camera_perm], p.points[point_perm], p.observations[by_camera],
              cams[by_camera], pts[by_camera])
    return arrays, point_new, camera_new


def assert_same_parameters(shuffled, ordered, point_new, camera_new):
    np.testing.assert_allclose(shuffled.cameras[camera_new], ordered.cameras, rtol=1e-9,
                               atol=1e-9 * np.abs(ordered.cameras).max())
    np.testing.assert_allclose(shuffled.points[point_new], ordered.points, rtol=1e-9,
                               atol=1e-9 * np.abs(ordered.points).max())


def test_a_shuffled_survey_solves_to_the_ordered_ones_parameters(survey):
    p = survey
    ordered = solve(p.cameras, p.points, p.observations, p.camera_indices, p.point_indices,
                    quiet=False)
    arrays, point_new, camera_new = shuffle(p, 11)
    shuffled = solve(*arrays, quiet=False)
    assert "points walked in a spatial order" in shuffled.log
    assert "points walked" not in ordered.log
    assert shuffled.summary.iterations == ordered.summary.iterations
    assert shuffled.summary.final_cost == pytest.approx(ordered.summary.final_cost, rel=1e-9)
    # Results in the input's order: renumbered back, the same parameters.
    assert_same_parameters(shuffled, ordered, point_new, camera_new)


def test_camera_priors_and_fixed_cameras_follow_their_images_through_the_walk(survey, survey_dir):
    # The walked solve renumbers the cameras; priors and fixed flags are the
    # images' own (every third image has a prior, images 5 and 17 are fixed).
    p = survey
    rows = [r.split() for r in (survey_dir / "s.priors").read_text().splitlines()
            if r and not r.startswith("#")][::3]
    fixed = np.zeros(len(p.cameras), dtype=bool)
    fixed[[5, 17]] = True
    arrays, point_new, camera_new = shuffle(p, 12)

    def with_priors(name, numbering):
        path = survey_dir / name
        path.write_text("".join(f"{numbering[int(r[0])]} {' '.join(r[1:])}\n" for r in rows))
        return path

    ordered = solve(p.cameras, p.points, p.observations, p.camera_indices, p.point_indices,
                    fixed_cameras=fixed,
                    camera_priors=with_priors("o.priors", np.arange(len(p.cameras))))
    shuffled_fixed = np.zeros_like(fixed)
    shuffled_fixed[camera_new[[5, 17]]] = True
    shuffled = solve(*arrays, fixed_cameras=shuffled_fixed, quiet=False,
                     camera_priors=with_priors("s2.priors", camera_new))
    assert "points walked in a spatial order" in shuffled.log
    assert shuffled.summary.final_cost == pytest.approx(ordered.summary.final_cost, rel=1e-9)
    assert_same_parameters(shuffled, ordered, point_new, camera_new)


def test_the_result_keeps_the_inputs_point_order(survey):
    # Each point stays where it was given: the solve moves it by about the
    # noise, far less than the distance to any other point.
    p = survey
    r = solve(p.cameras, p.points, p.observations, p.camera_indices, p.point_indices)
    moved = np.linalg.norm(r.points - p.points, axis=1)
    assert np.median(moved) < 1.0
    assert np.array_equal(r.problem.point_indices, p.point_indices)
