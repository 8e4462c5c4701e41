# No option is silently ignored: every option dba solve accepts is passed to
# solve_arrays, and each either has its documented effect (on the result,
# the report, the log, or a file written) or is refused with a ValueError
# naming why. A new option without a row here fails the test.
import os
import pathlib
import subprocess

import numpy as np
import pytest

import dba

DBA = os.environ.get("DBA_BINARY", str(pathlib.Path(__file__).resolve().parents[2] / "build" / "dba"))


@pytest.fixture(scope="module")
def survey(tmp_path_factory):
    d = tmp_path_factory.mktemp("effects")
    subprocess.run([DBA, "generate", str(d / "s.dba"), "--model", "photo", "--images", "40",
                    "--cameras", "2", "--unaligned", "--priors", str(d / "p.txt"), "--gcps",
                    str(d / "g.txt"), "--control-points", "4", "--check-points", "2", "--outliers",
                    "0.02", "--truth", str(d / "t.dba"), "--seed", "11"], check=True,
                   capture_output=True)
    # The priors without their sigmas (for prior_sigma), and moved into
    # geocentric coordinates (for prior_crs and gcp_crs).
    rows = [l.split() for l in open(d / "p.txt") if not l.startswith("#")]
    (d / "nosigma.txt").write_text("".join(f"{r[0]} {r[1]} {r[2]} {r[3]}\n" for r in rows))
    off = (4193000.0, 815000.0, 4717000.0)
    (d / "ecef.txt").write_text("".join(
        f"{r[0]} {float(r[1]) + off[0]!r} {float(r[2]) + off[1]!r} {float(r[3]) + off[2]!r} 2 4\n"
        for r in rows))
    return d


def solve(d, **options):
    p = dba.read_problem(d / "s.dba")
    return dba.solve_arrays(p.cameras, p.points, p.observations, p.camera_indices,
                            p.point_indices, camera_model=p.camera_model, intrinsics=p.intrinsics,
                            camera_intrinsics=p.camera_intrinsics, fixed_cameras=p.fixed_cameras,
                            fixed_intrinsics=options.pop("fixed_intrinsics", p.fixed_intrinsics),
                            lens_models=p.lens_models,
                            threads=options.pop("threads", 2), **options)


def rep(r):
    return r.summary.report


def one_frame_per_image(d):
    p = dba.read_problem(d / "s.dba")
    return dict(frame_indices=np.arange(len(p.cameras)), rig_from_world=p.cameras,
                sensor_from_rig=np.zeros((2, 6)), sensor_kinds=np.array([0, 1]))


def first_round_share(r):
    first = rep(r)["outlier_rejection"]["rounds"][0]
    return first["observations_dropped"] / (first["observations_dropped"] + first["observations_left"])


def stopped_at_the_default_share(d):
    with pytest.raises(RuntimeError, match=r"would drop .* more than --reject-max-share 0\.25"):
        solve(d, reject_outliers=1.0)
    return True


def linear(r):
    return [it.linear_iterations for it in r.summary.history]


# keyword -> (options, what must hold of (result, baseline, directory))
EFFECTS = {
    "checkpoint": (lambda d: dict(checkpoint=d / "c.ckpt"),
                   lambda r, b, d: (d / "c.ckpt").exists() and rep(r)["checkpoints"]["written"] > 2),
    "checkpoint_every": (lambda d: dict(checkpoint=d / "c2.ckpt", checkpoint_every=1e9),
                         lambda r, b, d: rep(r)["checkpoints"]["written"] == 2),
    "resume": (lambda d: dict(resume=d / "c.ckpt"), lambda r, b, d: "resumed from" in r.log),
    "truth": (lambda d: dict(truth=d / "t.dba"),
              lambda r, b, d: "ground_truth" in rep(r) and not rep(r)["ground_truth"]["absolute"]),
    "truth_absolute": (lambda d: dict(truth=d / "t.dba", truth_absolute=True),
                       lambda r, b, d: rep(r)["ground_truth"]["absolute"]),
    "fix_intrinsics": (lambda d: dict(fix_intrinsics="f"),
                       lambda r, b, d: np.array_equal(r.intrinsics[:, 0],
                                                      dba.read_problem(d / "s.dba").intrinsics[:, 0])),
    "fix_images": (lambda d: dict(fix_images=[3]),
                   lambda r, b, d: np.array_equal(r.cameras[3], dba.read_problem(d / "s.dba").cameras[3])),
    # The generated survey holds its principal points fixed itself: here
    # without, they are fixed by default and refined when asked.
    "refine_principal_point": (
        lambda d: dict(refine_principal_point=True, fixed_intrinsics=np.zeros((2, 5), bool)),
        lambda r, b, d: np.array_equal(
            solve(d, fixed_intrinsics=np.zeros((2, 5), bool), quiet=True).intrinsics[:, 1:3],
            dba.read_problem(d / "s.dba").intrinsics[:, 1:3])
        and not np.array_equal(r.intrinsics[:, 1:3], dba.read_problem(d / "s.dba").intrinsics[:, 1:3])),
    # Each image its own frame, group 1 a refined sensor at the origin's
    # place: fixed holds its 6 unknowns.
    "rig_geometry": (lambda d: dict(rig_geometry="fixed", **one_frame_per_image(d)),
                     lambda r, b, d: rep(r)["camera_unknowns"] == rep(
                         solve(d, quiet=True, **one_frame_per_image(d)))["camera_unknowns"] - 6),
    "gauge": (lambda d: dict(gauge="free"),
              lambda r, b, d: rep(r)["gauge"].startswith("free")
              and rep(b)["gauge"].startswith("the centres' centroid, RMS spread and mean orientation")
              and not np.array_equal(r.cameras, b.cameras)),
    "threads": (lambda d: dict(threads=1), lambda r, b, d: rep(r)["threads"] == 1),
    "max_iterations": (lambda d: dict(max_iterations=2), lambda r, b, d: r.summary.iterations == 2),
    "function_tolerance": (lambda d: dict(function_tolerance=0.5),
                           lambda r, b, d: r.summary.iterations < b.summary.iterations),
    "gradient_tolerance": (lambda d: dict(gradient_tolerance=1e300),
                           lambda r, b, d: r.summary.termination == "gradient_tolerance"),
    "parameter_tolerance": (lambda d: dict(parameter_tolerance=1.0),
                            lambda r, b, d: r.summary.termination == "parameter_tolerance"),
    "initial_lambda": (lambda d: dict(initial_lambda=0.25),
                       lambda r, b, d: r.summary.history[0].lambda_ == 0.25),
    "loss": (lambda d: dict(loss="cauchy"), lambda r, b, d: rep(r)["loss"]["type"] == "cauchy"),
    "loss_scale": (lambda d: dict(loss="huber", loss_scale=3.5),
                   lambda r, b, d: rep(r)["loss"]["scale_px"] == 3.5),
    "reject_outliers": (lambda d: dict(reject_outliers=3.0),
                        lambda r, b, d: rep(r)["outlier_rejection"]["rounds"][0]["observations_dropped"] > 0),
    "reject_keep_loss": (lambda d: dict(loss="huber", reject_outliers=3.0, reject_keep_loss=True),
                         lambda r, b, d: rep(r)["final_loss"]["type"] == "huber"),
    # The guard raised lets through a round the default (0.25) stops (at 1 px
    # round 1 drops 47.5% here).
    "reject_max_share": (lambda d: dict(reject_outliers=1.0, reject_max_share=0.9),
                         lambda r, b, d: stopped_at_the_default_share(d) and first_round_share(r) > 0.25),
    "min_triangulation_angle": (lambda d: dict(reject_outliers=1000.0, min_triangulation_angle=20.0,
                                               reject_max_share=1.0),
                                lambda r, b, d: rep(r)["outlier_rejection"]["rounds"][0]["points_dropped_for_angle"] > 0),
    "camera_priors": (lambda d: dict(camera_priors=d / "p.txt"),
                      lambda r, b, d: rep(r)["camera_priors"]["count"] == 40),
    "prior_crs": (lambda d: dict(camera_priors=d / "ecef.txt", prior_crs="EPSG:4978"),
                  lambda r, b, d: rep(r)["georeferencing"]["has_local_frame"]),
    "gcps": (lambda d: dict(gcps=d / "g.txt"),
             lambda r, b, d: rep(r)["control_points"]["count"] == 4),
    "gcp_crs": (lambda d: dict(camera_priors=d / "ecef.txt", prior_crs="EPSG:4978",
                               gcps=d / "g.txt", gcp_crs="EPSG:4978"),
                lambda r, b, d: "EPSG:4978" in rep(r)["georeferencing"]["crs"]),
    "prior_sigma": (lambda d: dict(camera_priors=d / "nosigma.txt", prior_sigma="0.5,1"),
                    lambda r, b, d: rep(r)["camera_priors"]["count"] == 40),
    "prior_loss": (lambda d: dict(camera_priors=d / "p.txt", prior_loss="huber"),
                   lambda r, b, d: rep(r)["camera_priors"]["loss"]["type"] == "huber"),
    "prior_loss_scale": (lambda d: dict(camera_priors=d / "p.txt", prior_loss_scale=5.0),
                         lambda r, b, d: rep(r)["camera_priors"]["loss"]["scale"] == 5.0),
    "lever_arm": (lambda d: dict(camera_priors=d / "p.txt", lever_arm="0.1,0.2,0.3"),
                  lambda r, b, d: rep(r)["camera_priors"]["lever_arm"] == [0.1, 0.2, 0.3]),
    "refine_lever_arm": (lambda d: dict(camera_priors=d / "p.txt", refine_lever_arm=True),
                         lambda r, b, d: rep(r)["camera_priors"]["lever_arm_refined"]
                         and rep(r)["camera_priors"]["lever_arm"] != [0.0, 0.0, 0.0]),
    "linear_solver": (lambda d: dict(linear_solver="pcg"),
                      lambda r, b, d: r.summary.linear_solver == "pcg"),
    "eta": (lambda d: dict(linear_solver="pcg", eta=0.9),
            lambda r, b, d: rep(r)["linear_solver"]["options"]["eta"] == 0.9),
    "preconditioner": (lambda d: dict(linear_solver="pcg", preconditioner="jacobi"),
                       lambda r, b, d: rep(r)["linear_solver"]["options"]["preconditioner"] == "jacobi"),
    "coarse_size": (lambda d: dict(linear_solver="pcg", coarse_size=7),
                    lambda r, b, d: rep(r)["linear_solver"]["options"]["coarse_size"] == 7),
    "coarse_basis": (lambda d: dict(linear_solver="pcg", coarse_basis="rigid"),
                     lambda r, b, d: rep(r)["linear_solver"]["options"]["coarse_basis"] == "rigid"),
    "pcg_tolerance": (lambda d: dict(linear_solver="pcg", eta=0, pcg_tolerance=0.5),
                      lambda r, b, d: np.median(linear(r)) < 20),  # about 120 at eta=0 alone
    "pcg_min_iterations": (lambda d: dict(linear_solver="pcg", eta=0.9, pcg_min_iterations=25),
                           lambda r, b, d: all(  # unless the residual is at rounding
                               it.linear_iterations >= 25 or it.linear_relative_residual < 1e-9
                               for it in r.summary.history)),
    "pcg_max_iterations": (lambda d: dict(linear_solver="pcg", pcg_max_iterations=2),
                           lambda r, b, d: max(linear(r)) <= 2),
    "pcg_precision": (lambda d: dict(linear_solver="pcg", pcg_precision="double"),
                      lambda r, b, d: rep(r)["linear_solver"]["options"]["pcg_precision"] == "double"),
    "no_memory_check": (lambda d: dict(no_memory_check=True),
                        lambda r, b, d: not rep(r)["memory_check"]),
    "quiet": (lambda d: dict(quiet=True), lambda r, b, d: "iter " not in r.log),
    "covariance_scale": (lambda d: dict(covariance=True, covariance_scale="unit"),
                         lambda r, b, d: rep(r)["covariance"]["scale"] == "unit"
                         and r.covariance.pose.shape == (40, 6, 6)),
}


# Options whose keyword is an argument of solve_arrays that carries the
# same thing as arrays (--intrinsics FILE is `intrinsics=`; --covariance
# FILE is `covariance=True`, returned: tests/test_covariance.py).
ARRAY_ARGUMENTS = {"intrinsics", "covariance", "point_covariance"}


def test_every_option_has_its_effect_or_is_refused(survey, monkeypatch):
    baseline = solve(survey)
    options = {o["keyword"]: o for o in dba.solve_options()}
    missing = [k for k, o in options.items() if o["arrays"] and k not in EFFECTS]
    assert not missing, f"options without a row in EFFECTS: {missing}"
    for keyword in sorted(options):
        o = options[keyword]
        if not o["arrays"] and keyword in ARRAY_ARGUMENTS:
            continue  # the keyword is solve_arrays' own argument (the arrays' way)
        if not o["arrays"]:
            value = True if o["kind"] == "flag" else ("x" if o["kind"] != "integer" else 1)
            with pytest.raises(ValueError, match=f"{keyword}: "):
                solve(survey, **{keyword: value})
            continue
        opts, holds = EFFECTS[keyword]
        result = solve(survey, **opts(survey))
        assert holds(result, baseline, survey), keyword


def test_the_memory_check_refuses_and_no_memory_check_starts(survey, monkeypatch):
    monkeypatch.setenv("DBA_MEMORY_AVAILABLE", "1000")
    with pytest.raises(RuntimeError, match="the solve needs about .* is available"):
        solve(survey)
    assert solve(survey, no_memory_check=True).summary.iterations > 0
