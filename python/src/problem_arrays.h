// NumPy arrays <-> Problem for the Python module: the problem as flat
// arrays (cameras, points, observations with their camera and point indices,
// intrinsic groups, fixed flags) and back, checked on the way in.
//
// Thread safety: call with the GIL held (the functions create and read
// Python objects).
#pragma once

#include <optional>
#include <string>

#include <pybind11/numpy.h>
#include <pybind11/pybind11.h>

#include "dba/problem/problem.h"

namespace dba::python {

namespace py = pybind11;

using DoubleArray = py::array_t<double, py::array::c_style | py::array::forcecast>;
using IndexArray = py::array_t<int64_t, py::array::c_style | py::array::forcecast>;
using FlagArray = py::array_t<bool, py::array::c_style | py::array::forcecast>;

// The arrays of solve_arrays. camera_model "bal": cameras (N, 9), no
// intrinsics. "photo": cameras (N, 6) poses, intrinsics (G, S) and
// camera_intrinsics (N,) the group of each image, lens_models the model of
// each group by name (absent: every group RADIAL, S = 5), each group's
// parameters in its model's order in the first columns (S at least the
// largest count, at most 16; the rest 0). observations (M, 2) pixels with
// camera_indices (M,) and point_indices (M,) in any order.
struct ProblemArrays {
  std::string camera_model = "bal";
  DoubleArray cameras, points, observations;
  IndexArray camera_indices, point_indices;
  std::optional<DoubleArray> intrinsics;
  std::optional<IndexArray> camera_intrinsics;
  std::optional<FlagArray> fixed_cameras;     // (N,) True: the pose/camera is held
  std::optional<FlagArray> fixed_intrinsics;  // (G, S) True: held
  std::optional<std::vector<std::string>> lens_models;  // (G,) names
  // Rigs ("photo"; docs/design.md §1.7): frame_indices (N,) each image's
  // frame, rig_from_world (F, 6) the frames' poses, sensor_from_rig (G, 6)
  // each group's pose in its rig, sensor_kinds (G,) 0 the rig's origin (its
  // pose zero), 1 refined, 2 held (absent: 0 where the pose is zero, else
  // 1). The images' poses are then composed from them (`cameras` gives only
  // their count).
  std::optional<IndexArray> frame_indices, sensor_kinds;
  std::optional<DoubleArray> rig_from_world, sensor_from_rig;
};

// An argument of solve_arrays as the array it must be, its dtype checked
// first and never cast across kinds: numbers (float or integer dtypes) for
// a DoubleArray, integers for an IndexArray, booleans for a FlagArray (a
// sequence is taken as NumPy makes it an array; an empty one of any dtype).
// py::type_error naming the argument, the dtype given and the one expected:
// "camera_indices: expected an integer array, got dtype float64".
DoubleArray AsDoubleArray(const py::handle& value, const char* name);
IndexArray AsIndexArray(const py::handle& value, const char* name);
FlagArray AsFlagArray(const py::handle& value, const char* name);

// Builds the problem (observations stored point-major, stable). Throws
// std::invalid_argument naming the array and what is wrong: a shape, an
// index out of range, a non-finite value, a point without observations.
Problem ProblemFromArrays(const ProblemArrays& arrays);

// The problem as a dict of new arrays with the keys of ProblemArrays
// (camera_model a string; for "bal", intrinsics (0, 5) and camera_intrinsics
// (0,); fixed_cameras (N,) and fixed_intrinsics (G, 5) always present).
py::dict ProblemToArrays(const Problem& problem);

}  // namespace dba::python
