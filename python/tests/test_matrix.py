# One solve, every way in: each feature in each mode {the command line in one
# process, on 3 MPI ranks, Python's solve on the file, Python's
# solve_arrays} agrees with the one-process command line (final cost to
# 1e-9 relative with an exact, dense linear solve; the adjusted parameters
# and the files written to 1e-9), or is refused (exit 2, or ValueError)
# naming why: only where the mode has no place for the feature.
import json
import math
import os
import pathlib
import shutil
import subprocess
import sys

import numpy as np
import pytest

import dba

DBA = os.environ.get("DBA_BINARY", str(pathlib.Path(__file__).resolve().parents[2] / "build" / "dba"))
# An exact linear solve and LM run to its end (the optimum, up to rounding),
# with the gauge held (two images fixed: without, runs that sum in other
# orders end apart by a similarity of the whole block, at the same cost), so
# parameters, not only costs, can be compared.
TIGHT = ["--linear-solver", "dense", "-t", "2", "--function-tolerance", "1e-15",
         "--parameter-tolerance", "1e-15", "--max-iterations", "300", "--fix-images", "0,1"]
TIGHT_KEYWORDS = dict(linear_solver="dense", function_tolerance=1e-15, parameter_tolerance=1e-15,
                      max_iterations=300, fix_images=[0, 1])
MODES = ["cli", "mpi", "solve", "arrays"]


def ecef_offset():
    """A point on the WGS84 ellipsoid (48 N, 11 E, 500 m): the generated
    frame moved there, so its coordinates are geocentric (EPSG:4978)."""
    a, f = 6378137.0, 1 / 298.257223563
    e2 = f * (2 - f)
    lat, lon, h = math.radians(48.0), math.radians(11.0), 500.0
    n = a / math.sqrt(1 - e2 * math.sin(lat) ** 2)
    return ((n + h) * math.cos(lat) * math.cos(lon), (n + h) * math.cos(lat) * math.sin(lon),
            (n * (1 - e2) + h) * math.sin(lat))


def shifted(src, dst, columns):
    """Copies a priors or GCP file with X Y Z (at `columns`) moved by the
    offset, on the lines that have them."""
    off = ecef_offset()
    out = []
    for line in open(src):
        f = line.split()
        if line.startswith("#") or len(f) <= max(columns) or f[-1] not in ("control", "check") and len(f) < 6:
            out.append(line)
            continue
        for k, c in enumerate(columns):
            f[c] = repr(float(f[c]) + off[k])
        out.append(" ".join(f) + "\n")
    pathlib.Path(dst).write_text("".join(out))


@pytest.fixture(scope="module")
def survey(tmp_path_factory):
    d = tmp_path_factory.mktemp("matrix")
    subprocess.run([DBA, "generate", str(d / "s.dba"), "--model", "photo", "--images", "60",
                    "--cameras", "2", "--unaligned", "--priors", str(d / "s.priors"), "--gcps",
                    str(d / "s.gcps"), "--control-points", "4", "--check-points", "3",
                    "--truth", str(d / "t.dba"), "--seed", "7"],
                   check=True, capture_output=True)
    shifted(d / "s.priors", d / "ecef.priors", [1, 2, 3])
    lines = []
    for line in open(d / "s.gcps"):
        f = line.split()
        if not line.startswith("#") and len(f) >= 7 and f[6] in ("control", "check"):
            off = ecef_offset()
            f[1:4] = [repr(float(f[1 + k]) + off[k]) for k in range(3)]
            line = " ".join(f) + "\n"
        lines.append(line)
    (d / "ecef.gcps").write_text("".join(lines))
    return d


def features(d):
    """name -> (options as keywords, the files each writes besides the report)."""
    return {
        "priors_in_a_crs": dict(camera_priors=d / "ecef.priors", prior_crs="EPSG:4978"),
        "control_and_check_points": dict(gcps=d / "s.gcps"),
        "robust_loss_with_rejection": dict(loss="huber", loss_scale=2.0, reject_outliers=3.0),
        "fixed_intrinsics_by_name": dict(fix_intrinsics=["f,k1", "0:cx"]),
        "output_crs": dict(camera_priors=d / "ecef.priors", gcps=d / "ecef.gcps",
                           prior_crs="EPSG:4978", output_crs="EPSG:4979",
                           camera_centres=d / "centres-{mode}.txt"),
        "truth": dict(truth=d / "t.dba"),
        "checkpoint_killed_and_resumed": dict(loss="cauchy", reject_outliers=3.0,
                                              checkpoint=d / "c-{mode}.ckpt"),
    }


def arguments(options, mode):
    args = []
    for k, v in options.items():
        flag = "--" + k.replace("_", "-")
        for one in (v if isinstance(v, list) else [v]):
            args += [flag, str(one).replace("{mode}", mode)]
    return args


def run_cli(d, name, options, mode, kill=None):
    out = d / f"{name}-{mode}.dba"
    report = d / f"{name}-{mode}.json"
    cmd = [DBA, "solve", str(d / "s.dba"), "-q", *TIGHT, "-o", str(out), "--report", str(report),
           *arguments(options, mode)]
    if mode == "mpi":
        cmd = ["mpirun", "--allow-run-as-root", "--oversubscribe", "--bind-to", "none", "-np", "3",
               *cmd]
        cmd[cmd.index("-t") + 1] = "1"
    env = dict(os.environ, **({"DBA_KILL_AFTER_CHECKPOINT": str(kill)} if kill else {}))
    r = subprocess.run(cmd, capture_output=True, text=True, env=env, timeout=300)
    return r, out, report


def python_options(options, mode):
    return {k: ([str(x).replace("{mode}", mode) for x in v] if isinstance(v, list)
                else (str(v).replace("{mode}", mode) if isinstance(v, (str, pathlib.Path)) else v))
            for k, v in options.items()}


def run_python(d, name, options, mode):
    """dba.solve on the file, or dba.solve_arrays on its arrays: the result
    and the parameters it returns."""
    opts = python_options(options, mode)
    if mode == "solve":
        return dba.solve(d / "s.dba", threads=2, quiet=True, **TIGHT_KEYWORDS,
                         output=str(d / f"{name}-{mode}.dba"), **opts)
    p = dba.read_problem(d / "s.dba")
    return dba.solve_arrays(p.cameras, p.points, p.observations, p.camera_indices,
                            p.point_indices, camera_model=p.camera_model, intrinsics=p.intrinsics,
                            camera_intrinsics=p.camera_intrinsics, fixed_cameras=p.fixed_cameras,
                            fixed_intrinsics=p.fixed_intrinsics, lens_models=p.lens_models,
                            threads=2, quiet=True, **TIGHT_KEYWORDS, **opts)


KILL_IN_PYTHON = """
import sys, dba
sys.path.insert(0, {tests!r})
import test_matrix as m, pathlib
d = pathlib.Path({d!r})
m.run_python(d, {name!r}, m.features(d)[{name!r}], {mode!r})
"""


def same(a, b, rel=1e-7):
    """Parameters to 1e-7 of their scale: at the optimum the cost is flat to
    rounding (its values agree to 1e-9, asserted apart), the parameters are
    fixed only to about the square root of that (measured: 1e-8 between 3
    ranks and one process, 1e-12 between the modes of one process)."""
    a, b = np.asarray(a, dtype=float), np.asarray(b, dtype=float)
    assert a.shape == b.shape
    scale = max(np.abs(b).max(), 1.0)
    assert np.abs(a - b).max() <= rel * scale, np.abs(a - b).max() / scale


@pytest.fixture(scope="module")
def reference(survey):
    refs = {}
    for name, options in features(survey).items():
        if name == "checkpoint_killed_and_resumed":
            options = {k: v for k, v in options.items() if k != "checkpoint"}
        r, out, report = run_cli(survey, name, options, "cli")
        assert r.returncode == 0, r.stderr
        refs[name] = (json.loads(report.read_text()), dba.read_problem(out), out)
    return refs


@pytest.mark.parametrize("mode", MODES)
@pytest.mark.parametrize("name", ["priors_in_a_crs", "control_and_check_points",
                                  "robust_loss_with_rejection", "fixed_intrinsics_by_name",
                                  "output_crs", "truth", "checkpoint_killed_and_resumed"])
def test_feature_in_mode(survey, reference, name, mode):
    d = survey
    options = features(d)[name]
    want, want_problem, want_file = reference[name]
    if mode == "arrays" and name == "output_crs":
        with pytest.raises(ValueError, match="output_crs: .*solve_arrays"):
            run_python(d, name, options, mode)
        return
    if name == "checkpoint_killed_and_resumed":
        if mode in ("cli", "mpi"):
            r, _, _ = run_cli(d, name, options, mode, kill=3)
            assert r.returncode != 0
        else:
            env = dict(os.environ, DBA_KILL_AFTER_CHECKPOINT="3")
            code = KILL_IN_PYTHON.format(tests=str(pathlib.Path(__file__).parent), d=str(d),
                                         name=name, mode=mode)
            r = subprocess.run([sys.executable, "-c", code], env=env, capture_output=True, text=True)
            assert r.returncode == -9, r.stderr
        assert (d / f"c-{mode}.ckpt").exists()
        options = dict(options, resume=d / f"c-{mode}.ckpt")
    if mode in ("cli", "mpi"):
        r, out, report = run_cli(d, name, options, mode)
        assert r.returncode == 0, r.stdout + r.stderr
        got, got_problem = json.loads(report.read_text()), dba.read_problem(out)
    else:
        result = run_python(d, name, options, mode)
        got, got_problem = result.summary.report, result.problem
    assert got["final_cost"] == pytest.approx(want["final_cost"], rel=1e-9)
    same(got_problem.cameras, want_problem.cameras)
    same(got_problem.points, want_problem.points)
    same(got_problem.intrinsics, want_problem.intrinsics)
    if name == "truth":
        assert got["ground_truth"]["point_rms"] == pytest.approx(want["ground_truth"]["point_rms"], rel=1e-6)
    if name in ("control_and_check_points", "output_crs"):
        assert got["check_points"]["rms_3d"] == pytest.approx(want["check_points"]["rms_3d"], rel=1e-6)
    if name == "output_crs":
        a = [l.split()[1:] for l in open(d / "centres-cli.txt") if not l.startswith("#")]
        b = [l.split()[1:] for l in open(d / f"centres-{mode}.txt") if not l.startswith("#")]
        same(np.array(b, dtype=float), np.array(a, dtype=float))  # printed to 1e-6 m
