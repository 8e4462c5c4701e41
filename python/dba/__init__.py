"""dba: exact Levenberg-Marquardt bundle adjustment (BSMC reduced camera system).

    import dba
    r = dba.solve("problem-49-7776-pre.txt.bz2", threads=2)
    print(r.summary.final_cost, r.summary.final_rms_px, r.summary.termination)

solve(path, **options) reads anything `dba solve` reads (BAL text or .bz2, a
.dba file, a COLMAP sparse model directory); solve_arrays(...) solves a problem
given as NumPy arrays; read_problem(path) returns a file's problem as arrays.
Options are the command line's, with '_' for '-' (`dba solve --help`):
threads, max_iterations, function_tolerance, gradient_tolerance,
parameter_tolerance, initial_lambda, linear_solver, eta, preconditioner,
coarse_size, coarse_basis, pcg_tolerance, pcg_max_iterations, loss,
loss_scale, fix_images, fix_intrinsics, quiet; for solve on a file also
output, report, ply, truth, intrinsics, colmap_format, reject_outliers,
reject_keep_loss.
verbose=True prints the per-iteration log and summary to the process's
stdout while solving; otherwise they are returned in Result.log.

Errors raise with the command line's messages: InputError (a ValueError,
with .file and .line) for malformed input, ValueError for bad options,
RuntimeError for other failures. The GIL is released during the solve.
"""
# This file: keyword options -> command-line arguments, and the extension's
# results (a JSON report and dicts of arrays) -> the dataclasses below.

import json
from dataclasses import dataclass, field

import numpy as np

from . import _dba
from ._dba import InputError

InputError.__module__ = "dba"  # shown as dba.InputError

__all__ = ["solve", "solve_arrays", "read_problem", "Problem", "Result", "Summary",
           "Iteration", "InputError"]


@dataclass
class Problem:
    """A problem as arrays. camera_model 'bal': cameras (N, 9) = angle-axis,
    translation, f, k1, k2. 'photo': cameras (N, 6) poses (angle-axis,
    translation), intrinsics (G, S) and camera_intrinsics (N,) the group of
    each camera, lens_models (G,) each group's model by name (COLMAP's, or
    BROWN; dba solve --list-camera-models), whose parameters fill the first
    columns of its row of intrinsics in the model's order (RADIAL: f, cx, cy,
    k1, k2). observations (M, 2) pixels of point point_indices[i] in camera
    camera_indices[i]. fixed_cameras (N,) and fixed_intrinsics (G, S): True
    where held fixed (a model's unused columns read True)."""
    camera_model: str
    cameras: np.ndarray
    points: np.ndarray
    observations: np.ndarray
    camera_indices: np.ndarray
    point_indices: np.ndarray
    intrinsics: np.ndarray
    camera_intrinsics: np.ndarray
    fixed_cameras: np.ndarray
    fixed_intrinsics: np.ndarray
    lens_models: list = None


@dataclass
class Iteration:
    """One LM iteration, as a line of the command line's log."""
    iteration: int
    cost: float
    rms_px: float
    gradient_max_norm: float
    lambda_: float
    linear_iterations: int
    linear_relative_residual: float
    linear_stop: str
    candidate_cost: float
    gain_ratio: float
    accepted: bool
    seconds: float


@dataclass
class Summary:
    """The solve's summary; `report` is the whole of `dba solve --report`'s JSON."""
    initial_cost: float
    final_cost: float
    initial_rms_px: float
    final_rms_px: float
    iterations: int
    accepted_iterations: int
    termination: str
    termination_message: str
    linear_solver: str
    seconds: dict          # load, setup, rcs_formation, linear_solve, back_substitution, write, total
    history: list = field(repr=False)  # of Iteration
    report: dict = field(repr=False)

    @classmethod
    def from_report(cls, report):
        history = []
        for it in report["history"]:
            it = dict(it)
            it["lambda_"] = it.pop("lambda")
            history.append(Iteration(**it))
        return cls(initial_cost=report["initial_cost"], final_cost=report["final_cost"],
                   initial_rms_px=report["initial_rms_px"], final_rms_px=report["final_rms_px"],
                   iterations=report["iterations"],
                   accepted_iterations=report["accepted_iterations"],
                   termination=report["termination"],
                   termination_message=report["termination_message"],
                   linear_solver=report["linear_solver"]["type"],
                   seconds=dict(report["seconds"]), history=history, report=report)


@dataclass
class Result:
    """The adjusted problem, the summary and the printed text of a solve."""
    problem: Problem
    summary: Summary
    log: str = field(repr=False)

    @property
    def cameras(self):
        return self.problem.cameras

    @property
    def points(self):
        return self.problem.points

    @property
    def intrinsics(self):
        return self.problem.intrinsics


def _arguments(options):
    """{'max_iterations': 20, 'quiet': True} -> ['--max-iterations', '20', '--quiet']."""
    args = []
    for name, value in options.items():
        flag = "--" + name.replace("_", "-")
        if isinstance(value, bool):
            if name not in ("quiet", "reject_keep_loss"):
                raise ValueError(f"{name}: expected a value, not {value!r}")
            if value:
                args.append(flag)
            continue
        if value is None:
            continue
        if isinstance(value, (list, tuple, np.ndarray)):
            value = ",".join(str(int(v)) if name == "fix_images" else str(v) for v in value)
        elif isinstance(value, float):
            value = repr(float(value))  # round-trips exactly (NumPy floats too)
        args += [flag, str(value)]
    return args


def _result(outcome):
    report, arrays, log = outcome
    return Result(problem=Problem(**arrays), summary=Summary.from_report(json.loads(report)),
                  log=log)


def solve(path, *, verbose=False, **options) -> Result:
    """Bundle-adjusts the problem at `path` as `dba solve path --option value ...`
    does (outputs included: output=, report=, ply=). Returns a Result."""
    return _result(_dba.solve([str(path)] + _arguments(options), verbose))


def solve_arrays(cameras, points, observations, camera_indices, point_indices, *,
                 camera_model="bal", intrinsics=None, camera_intrinsics=None,
                 fixed_cameras=None, fixed_intrinsics=None, lens_models=None, verbose=False,
                 **options) -> Result:
    """Bundle-adjusts a problem given as arrays (see Problem; observations in
    any order). The inputs are not modified; the Result holds the adjusted
    cameras, intrinsics and points (observations sorted by point)."""
    return _result(_dba.solve_arrays(camera_model, cameras, points, observations,
                                     camera_indices, point_indices, intrinsics,
                                     camera_intrinsics, fixed_cameras, fixed_intrinsics,
                                     lens_models, _arguments(options), verbose))


def read_problem(path) -> Problem:
    """The problem at `path` (BAL text or .bz2, .dba, COLMAP directory) as arrays."""
    return Problem(**_dba.read_problem(str(path)))
