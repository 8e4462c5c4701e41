"""dba: exact Levenberg-Marquardt bundle adjustment (BSMC reduced camera system).

    import dba
    r = dba.solve("problem-49-7776-pre.txt.bz2", threads=2)
    print(r.summary.final_cost, r.summary.final_rms_px, r.summary.termination)

solve(path, **options) reads anything `dba solve` reads (BAL text or .bz2, a
.dba file, a COLMAP sparse model directory); solve_arrays(...) solves a problem
given as NumPy arrays; read_problem(path) returns a file's problem as arrays.
Options are the command line's, each declared once (solve_options() lists
them; `dba solve --help` and README.md's table are made from the same
declaration), with '_' for '-': threads=2, max_iterations=50,
linear_solver="pcg", loss="huber", loss_scale=2.0, fix_images=[0],
camera_priors="p.txt", checkpoint=path, quiet=True, ... Flags take True or
False, numbers take numbers, paths str or os.PathLike, lists sequences of
integers: anything else is a TypeError, never cast. solve_arrays takes every
option but the file outputs (its result is returned) and a COLMAP input's or
the MPI ranks' own, which it refuses (ValueError) naming why. Its arrays
too are checked, not cast: integer dtypes for indices, bool for fixed
flags, float or integer for values (else a TypeError naming the argument).
A path is a path, even one starting with '-'.
verbose=True prints the per-iteration log and summary to the process's
stdout while solving; otherwise they are returned in Result.log.

Errors raise with the command line's messages: InputError (a ValueError,
with .file and .line) for malformed input, ValueError for bad options,
RuntimeError for other failures. The GIL is released during the solve, and
Ctrl-C stops it: KeyboardInterrupt, with nothing written.
"""
# This file: keyword options -> command-line arguments, and the extension's
# results (a JSON report and dicts of arrays) -> the dataclasses below.

import json
import os
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

from . import _dba
from ._dba import InputError

InputError.__module__ = "dba"  # shown as dba.InputError

__all__ = ["solve", "solve_arrays", "solve_options", "read_problem", "Problem", "Result", "Summary",
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
    where held fixed (a model's unused columns read True). A problem with
    rigs (.dba version 4, a COLMAP model with rigs, or given to solve_arrays)
    also has frame_indices (N,) each image's frame, rig_from_world (F, 6) the
    frames' poses, sensor_from_rig (G, 6) each group's sensor pose in its rig
    and sensor_kinds (G,) 0 the rig's origin, 1 refined, 2 held; the images'
    poses in cameras are then composed from them."""
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
    frame_indices: np.ndarray = None
    rig_from_world: np.ndarray = None
    sensor_from_rig: np.ndarray = None
    sensor_kinds: np.ndarray = None


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
    # Wall time per phase from the call's start (startup, read, load, distribution, setup,
    # rcs_formation, linear_solve, back_substitution, analysis, write, other), adding up to total.
    seconds: dict
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
class Covariance:
    """The covariance of a solve (README.md, "Precision"), as its files give it:
    `pose` (images x 6 x 6: attitude errors about the frame's x, y, z axes in
    radians, then the centre) and `state` per image ("inner" or "absolute",
    the datum; "held" or "undetermined": NaN); with points, `points`
    (x 3 x 3, NaN where undetermined) and `point_index` (each point's index in
    the input). Scaled as the report's covariance.scale says."""
    pose: np.ndarray
    state: list
    points: Optional[np.ndarray] = None
    point_index: Optional[np.ndarray] = None

    @property
    def centre_sigma(self):
        """Each image's centre sigmas (x, y, z), images x 3."""
        return np.sqrt(np.diagonal(self.pose[:, 3:, 3:], axis1=1, axis2=2))


@dataclass
class Result:
    """The adjusted problem, the summary and the printed text of a solve; with
    covariance=... its Covariance."""
    problem: Problem
    summary: Summary
    log: str = field(repr=False)
    covariance: Optional[Covariance] = field(default=None, repr=False)

    @property
    def cameras(self):
        return self.problem.cameras

    @property
    def points(self):
        return self.problem.points

    @property
    def intrinsics(self):
        return self.problem.intrinsics


_OPTIONS = {o["keyword"]: o for o in _dba.solve_options()}


def _is_int(v):
    return isinstance(v, (int, np.integer)) and not isinstance(v, (bool, np.bool_))


def _is_number(v):
    return _is_int(v) or (isinstance(v, (float, np.floating)) and not isinstance(v, np.bool_))


def _value(name, spec, value):
    """One keyword's value as the command line's text, type-checked, not cast."""
    kind = spec["kind"]
    if kind == "integer":
        if not _is_int(value):
            raise TypeError(f"{name}: expected an integer, got {value!r}")
        return str(int(value))
    if kind == "number":
        if not _is_number(value):
            raise TypeError(f"{name}: expected a number, got {value!r}")
        return repr(float(value))  # round-trips exactly (NumPy floats too)
    if kind == "path":
        if not isinstance(value, (str, os.PathLike)):
            raise TypeError(f"{name}: expected a path (str or os.PathLike), got {value!r}")
        return os.fspath(value)
    if kind == "list":  # ids, COLMAP image names (never digits alone), or "all"
        if isinstance(value, str) and value == "all":
            return value
        if isinstance(value, (str, bytes)) or not isinstance(value, (list, tuple, np.ndarray)):
            raise TypeError(f"{name}: expected a sequence of integers (or image names), or 'all', got {value!r}")
        def item(v):
            if _is_int(v):
                return str(int(v))
            if isinstance(v, str) and v and not v.isdigit() and "," not in v:
                return v
            raise TypeError(f"{name}: expected integers or image names, got {list(value)!r}")
        return ",".join(item(v) for v in value)
    if not isinstance(value, str):  # text, choice
        raise TypeError(f"{name}: expected a str, got {value!r}")
    return value


def _arguments(options, mode):
    """Keyword options -> dba solve's arguments, by its option table:
    booleans for flags, numbers for numbers, str or os.PathLike for paths,
    sequences of integers for lists; refused (ValueError) where `mode`
    ("file" or "arrays") has no place for the option."""
    args = []
    for name, value in options.items():
        spec = _OPTIONS.get(name)
        if spec is None:
            raise TypeError(f"unknown option {name!r} (dba.solve_options() lists them)")
        if not spec[mode]:
            raise ValueError(f"{name}: {spec['not_here']}")
        if value is None:
            continue
        if spec["kind"] == "flag":
            if not isinstance(value, (bool, np.bool_)):
                raise TypeError(f"{name}: expected True or False, got {value!r}")
            if value:
                args.append(spec["flag"])
            continue
        values = value if spec["repeatable"] and isinstance(value, (list, tuple)) else [value]
        for v in values:
            args += [spec["flag"], _value(name, spec, v)]
    return args


def solve_options():
    """dba solve's options, as the keywords of solve and solve_arrays take
    them: one dict per option (keyword, flag, kind, choices, min, max,
    repeatable, file and arrays: where it applies, not_here: why not, needs:
    the option it means nothing without, e.g. '--camera-priors', help)."""
    return [dict(o) for o in _OPTIONS.values()]


def _result(outcome):
    report, arrays, log, covariance = outcome
    return Result(problem=Problem(**arrays), summary=Summary.from_report(json.loads(report)),
                  log=log, covariance=None if covariance is None else Covariance(**covariance))


def solve(path, *, verbose=False, **options) -> Result:
    """Bundle-adjusts the problem at `path` as `dba solve path --option value ...`
    does (outputs included: output=, report=, ply=). Returns a Result."""
    # After "--" the path is a path, whatever it starts with ('-').
    return _result(_dba.solve(_arguments(options, "file") + ["--", os.fspath(path)], verbose))


def solve_arrays(cameras, points, observations, camera_indices, point_indices, *,
                 camera_model="bal", intrinsics=None, camera_intrinsics=None,
                 fixed_cameras=None, fixed_intrinsics=None, lens_models=None, frame_indices=None,
                 rig_from_world=None, sensor_from_rig=None, sensor_kinds=None, verbose=False,
                 **options) -> Result:
    """Bundle-adjusts a problem given as arrays (see Problem; observations in
    any order). The inputs are not modified; the Result holds the adjusted
    cameras, intrinsics and points (observations sorted by point).
    covariance=True: the images' Covariance in the Result (point_covariance=True:
    the points' too), as dba solve --covariance writes it; with
    covariance_scale="unit" for a pixel sigma of 1."""
    wanted = _covariance_wanted(options)
    return _result(_dba.solve_arrays(camera_model, cameras, points, observations,
                                     camera_indices, point_indices, intrinsics,
                                     camera_intrinsics, fixed_cameras, fixed_intrinsics,
                                     lens_models, _arguments(options, "arrays"), verbose,
                                     frame_indices, rig_from_world, sensor_from_rig, sensor_kinds,
                                     wanted))


def _covariance_wanted(options):
    """solve_arrays's covariance=True / point_covariance=True (taken out of
    `options`): 0, 1 (the images') or 2 (and the points')."""
    wanted = []
    for name in ("covariance", "point_covariance"):
        value = options.pop(name, False)
        if not isinstance(value, (bool, np.bool_)):
            raise TypeError(f"{name}: solve_arrays returns it: expected True or False, got {value!r}")
        wanted.append(bool(value))
    if wanted[1] and not wanted[0]:
        raise ValueError("point_covariance needs covariance=True")
    return wanted[0] + wanted[1]


def read_problem(path) -> Problem:
    """The problem at `path` (BAL text or .bz2, .dba, COLMAP directory) as arrays."""
    return Problem(**_dba.read_problem(str(path)))
