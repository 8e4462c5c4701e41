// NumPy arrays <-> Problem; see problem_arrays.h.
#include "problem_arrays.h"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <stdexcept>
#include <vector>

#include "dba/camera/rig_pose.h"
#include "dba/problem/lens_ranges.h"
#include "dba/problem/pixel_range.h"
#include "dba/problem/rig_frames.h"

namespace dba::python {
namespace {

std::invalid_argument Bad(const std::string& what) { return std::invalid_argument(what); }

std::string Shape(const py::array& a) {
  std::string s = "(";
  for (py::ssize_t d = 0; d < a.ndim(); ++d) s += (d ? ", " : "") + std::to_string(a.shape(d));
  return s + (a.ndim() == 1 ? ",)" : ")");
}

// Rows of a (rows, cols) array; a 1-D array of cols values, or an empty one,
// is taken as one row or none.
int64_t Rows(const py::array& a, int cols, const char* name, const char* expected) {
  if (a.ndim() == 2 && a.shape(1) == cols) return a.shape(0);
  if (a.ndim() == 1 && a.shape(0) == 0) return 0;
  throw Bad(std::string(name) + ": expected shape " + expected + ", got " + Shape(a));
}

int64_t Length(const py::array& a, const char* name) {
  if (a.ndim() != 1) throw Bad(std::string(name) + ": expected a 1-D array, got shape " + Shape(a));
  return a.shape(0);
}

std::vector<double> Finite(const DoubleArray& a, const char* name) {
  std::vector<double> v(a.data(), a.data() + a.size());
  for (size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) {
      throw Bad(std::string(name) + ": value " + std::to_string(i) + " is not finite");
    }
  }
  return v;
}

template <typename T>
py::array_t<T> Array(const std::vector<T>& v, std::vector<py::ssize_t> shape) {
  py::array_t<T> a(shape);
  if (!v.empty()) std::memcpy(a.mutable_data(), v.data(), v.size() * sizeof(T));
  return a;
}

// `value` as an array whose dtype is of one of `kinds` (NumPy's dtype.kind
// letters), else py::type_error naming `name`, the dtype and `expected`.
py::array OfKind(const py::handle& value, const char* name, const std::string& kinds,
                 const char* expected) {
  const py::array a = py::array::ensure(value);
  if (!a) {
    PyErr_Clear();
    throw py::type_error(std::string(name) + ": expected " + expected + ", got " +
                         std::string(py::str(py::type::of(value).attr("__name__"))));
  }
  if (a.size() > 0 && kinds.find(a.dtype().kind()) == std::string::npos) {
    throw py::type_error(std::string(name) + ": expected " + expected + ", got dtype " +
                         std::string(py::str(a.dtype())));
  }
  return a;
}

}  // namespace

DoubleArray AsDoubleArray(const py::handle& value, const char* name) {
  return DoubleArray::ensure(OfKind(value, name, "fiu", "an array of numbers (float or integer)"));
}

IndexArray AsIndexArray(const py::handle& value, const char* name) {
  return IndexArray::ensure(OfKind(value, name, "iu", "an integer array"));
}

FlagArray AsFlagArray(const py::handle& value, const char* name) {
  return FlagArray::ensure(OfKind(value, name, "b", "a boolean array"));
}

namespace {

// The lens models of a 'photo' problem's groups (RADIAL without them).
void LensModelsFromArrays(const ProblemArrays& in, int64_t groups, Problem* p) {
  const py::array& k = *in.intrinsics;
  if (!in.lens_models) {
    if (p->intrinsics_size != kPhotoIntrinsicsSize) {
      throw Bad("intrinsics: expected shape (G, 5) (RADIAL: f, cx, cy, k1, k2) without lens_models, got " +
                Shape(k));
    }
    return;
  }
  if (static_cast<int64_t>(in.lens_models->size()) != groups) {
    throw Bad("lens_models: expected " + std::to_string(groups) +
              " names (one per intrinsic group), got " + std::to_string(in.lens_models->size()));
  }
  for (size_t g = 0; g < in.lens_models->size(); ++g) {
    const LensModelInfo* m = FindLensModel((*in.lens_models)[g]);
    if (m == nullptr) {
      throw Bad("lens_models[" + std::to_string(g) + "] = '" + (*in.lens_models)[g] +
                "': unknown (known: " + LensModelNames() + ")");
    }
    if (m->num_params > p->intrinsics_size) {
      throw Bad("intrinsics: " + std::string(m->name) + " (group " + std::to_string(g) + ") has " +
                std::to_string(m->num_params) + " parameters, the array " +
                std::to_string(p->intrinsics_size) + " columns");
    }
    p->group_models.push_back(m->id);
  }
}

// A 'photo' problem's intrinsic groups: values (after the poses), each
// camera's group, the models, what is held fixed.
void IntrinsicsFromArrays(const ProblemArrays& in, int64_t n, Problem* p) {
  if (!(in.intrinsics && in.intrinsics->size() > 0) ||
      !(in.camera_intrinsics && in.camera_intrinsics->size() > 0)) {
    throw Bad("camera_model 'photo' needs intrinsics (G, S) and camera_intrinsics (N,)");
  }
  const py::array& k = *in.intrinsics;
  if (k.ndim() != 2 || k.shape(1) < 1 || k.shape(1) > kMaxIntrinsics) {
    throw Bad("intrinsics: expected shape (G, S) with S from 1 to 16, got " + Shape(k));
  }
  const int64_t groups = k.shape(0);
  p->intrinsics_size = static_cast<int32_t>(k.shape(1));
  LensModelsFromArrays(in, groups, p);
  if (Length(*in.camera_intrinsics, "camera_intrinsics") != n) {
    throw Bad("camera_intrinsics: expected " + std::to_string(n) + " entries (one per camera), got " +
              Shape(*in.camera_intrinsics));
  }
  const std::vector<double> intrinsics = Finite(*in.intrinsics, "intrinsics");
  p->cameras.insert(p->cameras.end(), intrinsics.begin(), intrinsics.end());
  p->camera_intrinsics.resize(n);
  for (int64_t i = 0; i < n; ++i) {
    const int64_t g = in.camera_intrinsics->data()[i];
    if (g < 0 || g >= groups) {
      throw Bad("camera_intrinsics[" + std::to_string(i) + "] = " + std::to_string(g) +
                ": out of range (" + std::to_string(groups) + " intrinsic groups)");
    }
    p->camera_intrinsics[i] = static_cast<int32_t>(g);
  }
  for (int64_t g = 0; g < groups; ++g) {
    const std::string out_of_range =
        LensValueOutOfRange(p->group_model(g), intrinsics.data() + p->intrinsics_size * g);
    if (!out_of_range.empty()) throw Bad("intrinsics[" + std::to_string(g) + "]: " + out_of_range);
  }
  if (!in.fixed_intrinsics || in.fixed_intrinsics->size() == 0) return;
  const int s = p->intrinsics_size;
  if (in.fixed_intrinsics->ndim() != 2 || in.fixed_intrinsics->shape(0) != groups ||
      in.fixed_intrinsics->shape(1) != s) {
    throw Bad("fixed_intrinsics: expected shape (" + std::to_string(groups) + ", " +
              std::to_string(s) + "), got " + Shape(*in.fixed_intrinsics));
  }
  p->fixed_intrinsics.assign(groups, 0);
  for (int64_t g = 0; g < groups; ++g) {
    for (int d = 0; d < s; ++d) {
      if (in.fixed_intrinsics->data()[s * g + d]) p->fixed_intrinsics[g] |= static_cast<uint16_t>(1u << d);
    }
    // Only the model's own parameters (metadata and unused slots are never
    // unknowns anyway).
    p->fixed_intrinsics[g] &= LensModelParamMask(p->group_model(g));
  }
}

// The observations in any order, sorted by point (a stable counting sort);
// every index and pixel checked.
void ObservationsFromArrays(const ProblemArrays& in, int64_t n, int64_t num_points, int64_t m,
                            Problem* p) {
  const int64_t* cam = in.camera_indices.data();
  const int64_t* pt = in.point_indices.data();
  const double* px = in.observations.data();
  p->point_offsets.assign(num_points + 1, 0);
  for (int64_t o = 0; o < m; ++o) {
    if (cam[o] < 0 || cam[o] >= n) {
      throw Bad("camera_indices[" + std::to_string(o) + "] = " + std::to_string(cam[o]) +
                ": out of range (" + std::to_string(n) + " cameras)");
    }
    if (pt[o] < 0 || pt[o] >= num_points) {
      throw Bad("point_indices[" + std::to_string(o) + "] = " + std::to_string(pt[o]) +
                ": out of range (" + std::to_string(num_points) + " points)");
    }
    const std::string out_of_range = PixelOutOfRange(px[2 * o], px[2 * o + 1]);
    if (!out_of_range.empty()) throw Bad("observations[" + std::to_string(o) + "]: " + out_of_range);
    ++p->point_offsets[pt[o] + 1];
  }
  for (int64_t k = 0; k < num_points; ++k) {
    if (p->point_offsets[k + 1] == 0) {
      throw Bad("point " + std::to_string(k) + " has no observations (remove it)");
    }
    p->point_offsets[k + 1] += p->point_offsets[k];
  }
  p->obs_camera.resize(m);
  p->obs_pixel.resize(2 * m);
  std::vector<int64_t> next(p->point_offsets.begin(), p->point_offsets.end() - 1);
  for (int64_t o = 0; o < m; ++o) {
    const int64_t slot = next[pt[o]]++;
    p->obs_camera[slot] = static_cast<int32_t>(cam[o]);
    p->obs_pixel[2 * slot] = px[2 * o];
    p->obs_pixel[2 * slot + 1] = px[2 * o + 1];
  }
}

}  // namespace

// The rig arrays into `p` (see ProblemArrays), after its groups.
void RigsFromArrays(const ProblemArrays& in, int64_t n, Problem* p) {
  if (!in.frame_indices) {
    if (in.rig_from_world || in.sensor_from_rig || in.sensor_kinds) {
      throw Bad("rig_from_world, sensor_from_rig, sensor_kinds: need frame_indices");
    }
    return;
  }
  if (p->model != CameraModel::kPhoto) throw Bad("frame_indices: rigs need camera_model='photo'");
  if (!in.rig_from_world || !in.sensor_from_rig) {
    throw Bad("frame_indices: rigs need rig_from_world (F, 6) and sensor_from_rig (G, 6)");
  }
  const int64_t groups = p->num_groups();
  const int64_t frames = Rows(*in.rig_from_world, kPhotoPoseSize, "rig_from_world", "(F, 6)");
  if (Rows(*in.sensor_from_rig, kPhotoPoseSize, "sensor_from_rig", "(G, 6)") != groups) {
    throw Bad("sensor_from_rig: expected one row per intrinsic group (" + std::to_string(groups) +
              "), got " + Shape(*in.sensor_from_rig));
  }
  if (Length(*in.frame_indices, "frame_indices") != n) {
    throw Bad("frame_indices: expected " + std::to_string(n) + " entries (one per image), got " +
              Shape(*in.frame_indices));
  }
  std::vector<uint8_t> used(frames, 0);
  for (int64_t i = 0; i < n; ++i) {
    const int64_t f = in.frame_indices->data()[i];
    if (f < 0 || f >= frames) {
      throw Bad("frame_indices[" + std::to_string(i) + "] = " + std::to_string(f) +
                " is out of range [0, " + std::to_string(frames) + ")");
    }
    used[f] = 1;
    p->image_frame.push_back(static_cast<int32_t>(f));
  }
  for (int64_t f = 0; f < frames; ++f) {
    if (!used[f]) throw Bad("rig_from_world: frame " + std::to_string(f) + " has no image");
  }
  const std::vector<double> frame_poses = Finite(*in.rig_from_world, "rig_from_world");
  const std::vector<double> sensor_poses = Finite(*in.sensor_from_rig, "sensor_from_rig");
  for (int64_t g = 0; g < groups; ++g) {
    const double* s = sensor_poses.data() + kPhotoPoseSize * g;
    const bool zero = std::all_of(s, s + kPhotoPoseSize, [](double v) { return v == 0.0; });
    int64_t kind = zero ? kRigOrigin : kSensorRefined;
    if (in.sensor_kinds) {
      if (Length(*in.sensor_kinds, "sensor_kinds") != groups) {
        throw Bad("sensor_kinds: expected one per intrinsic group, got " + Shape(*in.sensor_kinds));
      }
      kind = in.sensor_kinds->data()[g];
    }
    if (kind < 0 || kind > kSensorHeld || (kind == kRigOrigin && !zero)) {
      throw Bad("sensor_kinds[" + std::to_string(g) + "] = " + std::to_string(kind) +
                ": expected 0 (the rig's origin, a zero pose), 1 (refined) or 2 (held)");
    }
    p->sensor_kind.push_back(static_cast<uint8_t>(kind));
  }
  if (const SensorTwice t = FindSensorTwice(*p); t.frame >= 0) {
    throw Bad("frame_indices: frame " + std::to_string(t.frame) + " holds images " +
              std::to_string(t.first) + " and " + std::to_string(t.second) +
              " of sensor (group) " + std::to_string(t.group) +
              " (a frame is one exposure: one image per sensor)");
  }
  p->cameras.insert(p->cameras.end(), frame_poses.begin(), frame_poses.end());
  p->cameras.insert(p->cameras.end(), sensor_poses.begin(), sensor_poses.end());
  ComposeRigImages(p);
}

Problem ProblemFromArrays(const ProblemArrays& in) {
  Problem p;
  if (in.camera_model == "bal") {
    p.model = CameraModel::kBal;
  } else if (in.camera_model == "photo") {
    p.model = CameraModel::kPhoto;
  } else {
    throw Bad("camera_model: expected 'bal' or 'photo', got '" + in.camera_model + "'");
  }
  const bool bal = p.model == CameraModel::kBal;
  const int64_t n = Rows(in.cameras, p.camera_size(), "cameras", bal ? "(N, 9)" : "(N, 6)");
  const int64_t num_points = Rows(in.points, kPointSize, "points", "(P, 3)");
  const int64_t m = Rows(in.observations, 2, "observations", "(M, 2)");
  if (Length(in.camera_indices, "camera_indices") != m ||
      Length(in.point_indices, "point_indices") != m) {
    throw Bad("camera_indices and point_indices: expected " + std::to_string(m) +
              " entries each (one per observation), got " + Shape(in.camera_indices) + " and " +
              Shape(in.point_indices));
  }
  if (n == 0 || num_points == 0 || m == 0) {
    throw Bad("the problem is empty: " + std::to_string(n) + " cameras, " +
              std::to_string(num_points) + " points, " + std::to_string(m) + " observations");
  }
  if (n > INT32_MAX) throw Bad("cameras: more than 2^31 - 1 cameras");
  p.cameras = Finite(in.cameras, "cameras");
  if (bal) {
    if ((in.intrinsics && in.intrinsics->size() > 0) ||
        (in.camera_intrinsics && in.camera_intrinsics->size() > 0) ||
        (in.fixed_intrinsics && in.fixed_intrinsics->size() > 0)) {
      throw Bad("intrinsics, camera_intrinsics, fixed_intrinsics: a 'bal' camera holds its own "
                "f, k1, k2 (use camera_model='photo' for shared intrinsics)");
    }
  } else {
    IntrinsicsFromArrays(in, n, &p);
  }
  RigsFromArrays(in, n, &p);
  if (in.fixed_cameras && in.fixed_cameras->size() > 0) {
    if (Length(*in.fixed_cameras, "fixed_cameras") != n) {
      throw Bad("fixed_cameras: expected " + std::to_string(n) + " entries (one per camera), got " +
                Shape(*in.fixed_cameras));
    }
    p.fixed_cameras.assign(in.fixed_cameras->data(), in.fixed_cameras->data() + n);
  }
  p.points = Finite(in.points, "points");
  ObservationsFromArrays(in, n, num_points, m, &p);
  return p;
}

py::dict ProblemToArrays(const Problem& p) {
  const int64_t n = p.num_images(), groups = p.num_groups();
  const int64_t num_points = p.num_points(), m = p.num_observations();
  const int size = p.camera_size();
  py::dict d;
  d["camera_model"] = p.model == CameraModel::kBal ? "bal" : "photo";
  const std::vector<double> poses(p.cameras.begin(), p.cameras.begin() + size * n);
  const auto groups_end = p.has_rigs() ? p.cameras.begin() + p.frames_offset() : p.cameras.end();
  const std::vector<double> intrinsics(p.cameras.begin() + size * n, groups_end);
  d["cameras"] = Array(poses, {n, size});
  const int slots = p.intrinsics_size;
  d["intrinsics"] = Array(intrinsics, {groups, slots});
  py::list lens_models;
  for (int64_t g = 0; g < groups; ++g) lens_models.append(Info(p.group_model(g)).name);
  d["lens_models"] = lens_models;
  std::vector<int64_t> groups_of(p.camera_intrinsics.begin(), p.camera_intrinsics.end());
  d["camera_intrinsics"] = Array(groups_of, {static_cast<py::ssize_t>(groups_of.size())});
  d["points"] = Array(p.points, {num_points, kPointSize});
  d["observations"] = Array(p.obs_pixel, {m, 2});
  std::vector<int64_t> cams(p.obs_camera.begin(), p.obs_camera.end());
  std::vector<int64_t> pts(m);
  // point_offsets may be empty after a distributed solve (no observations kept).
  for (int64_t k = 0; k + 1 < static_cast<int64_t>(p.point_offsets.size()); ++k) {
    for (int64_t o = p.point_offsets[k]; o < p.point_offsets[k + 1]; ++o) pts[o] = k;
  }
  d["camera_indices"] = Array(cams, {m});
  d["point_indices"] = Array(pts, {m});
  py::array_t<bool> fixed(std::vector<py::ssize_t>{n});
  for (int64_t i = 0; i < n; ++i) fixed.mutable_data()[i] = p.camera_fixed(i);
  d["fixed_cameras"] = fixed;
  py::array_t<bool> fixed_intrinsics(std::vector<py::ssize_t>{groups, slots});
  for (int64_t g = 0; g < groups; ++g) {
    for (int b = 0; b < slots; ++b) {
      fixed_intrinsics.mutable_data()[slots * g + b] = (p.intrinsics_free_mask(g) & (1u << b)) == 0;
    }
  }
  d["fixed_intrinsics"] = fixed_intrinsics;
  if (p.has_rigs()) {
    // Rigs (docs/design.md §1.7).
    const int64_t frames = p.num_frames();
    std::vector<int64_t> frame_of(p.image_frame.begin(), p.image_frame.end());
    d["frame_indices"] = Array(frame_of, {n});
    d["rig_from_world"] = Array(std::vector<double>(groups_end, groups_end + kPhotoPoseSize * frames),
                                {frames, kPhotoPoseSize});
    d["sensor_from_rig"] = Array(std::vector<double>(groups_end + kPhotoPoseSize * frames, p.cameras.end()),
                                 {groups, kPhotoPoseSize});
    std::vector<int64_t> kinds(p.sensor_kind.begin(), p.sensor_kind.end());
    d["sensor_kinds"] = Array(kinds, {groups});
  }
  return d;
}

}  // namespace dba::python
