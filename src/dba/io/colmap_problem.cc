// COLMAP model <-> photogrammetric problem; see colmap_problem.h.
#include "dba/io/colmap_problem.h"

#include <Eigen/Geometry>
#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>
#include <string>
#include <numeric>
#include <unordered_map>

#include "dba/camera/observation_residual.h"
#include "dba/camera/rig_pose.h"
#include "dba/common/error.h"
#include "dba/io/colmap_model_internal.h"

namespace dba {
namespace {

// Angle-axis of the quaternion (w, x, y, z) after normalising it; the
// rotation angle is in [0, π] (q and -q are the same rotation).
Vec3 QuaternionToAngleAxis(const std::array<double, 4>& q) {
  const Eigen::AngleAxisd aa(Eigen::Quaterniond(q[0], q[1], q[2], q[3]).normalized());
  return aa.angle() * aa.axis();
}

// Unit quaternion (w, x, y, z) of the angle-axis vector, with w >= 0.
std::array<double, 4> AngleAxisToQuaternion(const Vec3& omega) {
  const double theta = omega.norm();
  if (theta == 0) return {1, 0, 0, 0};
  Eigen::Quaterniond q(Eigen::AngleAxisd(theta, omega / theta));
  if (q.w() < 0) q.coeffs() = -q.coeffs();
  return {q.w(), q.x(), q.y(), q.z()};
}

// Whether q is as AngleAxisToQuaternion writes one: w >= 0, unit to a few
// ulps.
bool IsWrittenForm(const std::array<double, 4>& q) {
  const double norm2 = q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3];
  return q[0] >= 0 && std::abs(norm2 - 1.0) <= 8 * std::numeric_limits<double>::epsilon();
}

// Whether a rig of the model has a camera besides its reference sensor.
bool HasRealRigs(const ColmapModel& model) {
  for (const ColmapRig& r : model.rigs) {
    for (const ColmapSensor& s : r.sensors) {
      if (s.type == 0) return true;
    }
  }
  return false;
}

void SetPose(const std::array<double, 4>& q, const std::array<double, 3>& t, double* pose) {
  const Vec3 omega = QuaternionToAngleAxis(q);
  for (int d = 0; d < 3; ++d) pose[d] = omega[d], pose[3 + d] = t[d];
}

// The rig's role of each group's camera: origin, or a sensor (and its pose,
// null when it has none), held where the model puts it when it stands for
// a reference sensor that is not a camera.
struct SensorRole {
  bool origin = false;
  const ColmapSensor* sensor = nullptr;
  bool held = false;
};

// A rig whose reference sensor is not a camera (an IMU): its first camera,
// held at its pose in the rig, places the rig's frame as an origin camera
// would (the frames and the other sensors are then unknowns as usual).
const ColmapSensor* CameraHoldingTheOrigin(const ColmapRig& r, const std::string& source) {
  for (const ColmapSensor& s : r.sensors) {
    if (s.type != 0) continue;
    if (!s.has_pose) {
      throw InputError(source, 0, "rig " + std::to_string(r.rig_id) +
                                      ": its reference sensor is not a camera, and its first "
                                      "camera (" + std::to_string(s.id) +
                                      ") has no pose in it (HAS_POSE 0): nothing places the "
                                      "rig's frame");
    }
    return &s;
  }
  return nullptr;
}

std::vector<SensorRole> SensorRoles(const ColmapModel& model, const ColmapProblem& out,
                                    const std::string& source) {
  std::unordered_map<uint32_t, SensorRole> role;
  for (const ColmapRig& r : model.rigs) {
    const ColmapSensor* holder = r.ref.type == 0 ? nullptr : CameraHoldingTheOrigin(r, source);
    if (r.ref.type == 0) role[r.ref.id] = {true, nullptr};
    for (const ColmapSensor& s : r.sensors) {
      if (s.type == 0) role[s.id] = {false, &s, &s == holder};
    }
  }
  std::vector<SensorRole> roles;
  for (int64_t c : out.group_camera) roles.push_back(role[model.cameras[c].camera_id]);
  return roles;
}

// The problem's frames and sensors from the model's (see the header).
void AddRigs(const ColmapModel& model, const std::vector<int32_t>& problem_camera,
             const std::unordered_map<uint32_t, int64_t>& image_of_id, const std::string& source,
             ColmapProblem* out) {
  Problem& bp = out->problem;
  const int64_t n = bp.num_images(), groups = bp.num_groups();
  const std::vector<SensorRole> roles = SensorRoles(model, *out, source);
  bp.image_frame.assign(n, -1);
  for (size_t x = 0; x < model.frames.size(); ++x) {
    bool used = false;
    for (const ColmapFrameData& d : model.frames[x].data) {
      if (d.type != 0) continue;
      const int32_t i = problem_camera[image_of_id.at(static_cast<uint32_t>(d.data_id))];
      if (i < 0) continue;
      bp.image_frame[i] = static_cast<int32_t>(out->frame_index.size());
      used = true;
    }
    if (used) out->frame_index.push_back(static_cast<int64_t>(x));
  }
  const int64_t frames = static_cast<int64_t>(out->frame_index.size());
  const std::vector<double> image_poses(bp.cameras.begin(), bp.cameras.begin() + kPhotoPoseSize * n);
  bp.cameras.resize(bp.cameras.size() + kPhotoPoseSize * (frames + groups), 0.0);
  bp.sensor_kind.assign(groups, kRigOrigin);
  for (int64_t f = 0; f < frames; ++f) {
    const ColmapFrame& frame = model.frames[out->frame_index[f]];
    SetPose(frame.qvec, frame.tvec, bp.cameras.data() + bp.frame_offset(f));
  }
  for (int64_t g = 0; g < groups; ++g) {
    if (roles[g].origin) continue;
    bp.sensor_kind[g] = roles[g].held ? kSensorHeld : kSensorRefined;
    double* sensor = bp.cameras.data() + bp.sensor_offset(g);
    if (roles[g].sensor != nullptr && roles[g].sensor->has_pose) {
      SetPose(roles[g].sensor->qvec, roles[g].sensor->tvec, sensor);
      continue;
    }
    // No pose: image ∘ frame⁻¹ at the first image of the group.
    for (int64_t i = 0; i < n; ++i) {
      if (bp.camera_intrinsics[i] != g) continue;
      ComposeWithInverse(image_poses.data() + kPhotoPoseSize * i,
                         bp.cameras.data() + bp.frame_offset(bp.image_frame[i]), sensor);
      break;
    }
  }
  ComposeRigImages(&bp);
}

}  // namespace

Fixings ColmapFixings(const ColmapModel& model, const ColmapProblem& problem,
                      const std::vector<uint32_t>& fixed_image_ids,
                      const std::vector<std::string>& fixed_image_names,
                      const std::vector<IntrinsicFixing>& fixed_intrinsics,
                      const std::string& source) {
  std::unordered_map<uint32_t, int64_t> problem_image_of_id;  // -1: not in the problem
  for (const ColmapImage& im : model.images) problem_image_of_id.emplace(im.image_id, -1);
  for (size_t i = 0; i < problem.image_index.size(); ++i) {
    problem_image_of_id[model.images[problem.image_index[i]].image_id] = static_cast<int64_t>(i);
  }
  Fixings f;
  for (const IntrinsicFixing& x : fixed_intrinsics) {
    if (x.group < 0) {
      f.intrinsics.push_back(x);
      continue;
    }
    // A COLMAP camera id: every group cut from that camera.
    const auto camera = std::find_if(model.cameras.begin(), model.cameras.end(),
                                     [&](const ColmapCamera& c) { return c.camera_id == x.group; });
    if (camera == model.cameras.end()) {
      throw UsageError("--fix-intrinsics: camera " + std::to_string(x.group) + ": " + source +
                       " has no camera with that id");
    }
    // Named against the camera's own model (it may have no image in the
    // problem, and its groups are numbered otherwise).
    const LensModelInfo& m = *FindLensModel(static_cast<int>(LensModelOfColmapCamera(*camera, source)));
    for (const std::string& name : x.names) {
      if (name != "all" && !LensModelKindMask(m.id, name) && !LensModelParamIndex(m.id, name)) {
        throw UsageError("--fix-intrinsics: no intrinsic parameter '" + Clipped(name) +
                         "' in COLMAP camera " + std::to_string(x.group) + "'s model " + m.name +
                         " (" + m.params + ")");
      }
    }
    for (size_t g = 0; g < problem.group_camera.size(); ++g) {
      if (model.cameras[problem.group_camera[g]].camera_id == x.group) {
        f.intrinsics.push_back({static_cast<int64_t>(g), x.names});
      }
    }
  }
  for (uint32_t id : fixed_image_ids) {
    auto it = problem_image_of_id.find(id);
    if (it == problem_image_of_id.end()) {
      throw UsageError("--fix-images: image " + std::to_string(id) + ": " + source +
                       " has no image with that id");
    }
    if (it->second >= 0) f.images.push_back(it->second);
  }
  for (const std::string& name : fixed_image_names) {
    const auto im = std::find_if(model.images.begin(), model.images.end(),
                                 [&](const ColmapImage& m) { return m.name == name; });
    if (im == model.images.end()) {
      throw UsageError("--fix-images: " + source + " has no image named '" + Clipped(name) + "'");
    }
    const int64_t i = problem_image_of_id[im->image_id];
    if (i >= 0) f.images.push_back(i);
  }
  return f;
}

namespace {

// The points whose tracks are long enough (their indices into out's
// point_index), the image of each of their track elements, and which images
// they use.
void KeepTracks(const ColmapModel& model, int64_t min_track_length,
                const std::unordered_map<uint32_t, int64_t>& image_of_id, const std::string& source,
                ColmapProblem* out, std::vector<int64_t>* track_image,
                std::vector<uint8_t>* image_used) {
  for (size_t k = 0; k < model.points3D.size(); ++k) {
    const ColmapPoint3D& p = model.points3D[k];
    if (static_cast<int64_t>(p.track.size()) < min_track_length) continue;
    out->point_index.push_back(static_cast<int64_t>(k));
    for (const ColmapTrackElement& e : p.track) {
      auto it = image_of_id.find(e.image_id);
      if (it == image_of_id.end() ||
          e.point2D_idx >= model.images[it->second].points2D.size()) {
        throw InputError(source, 0,
                         "3D point " + std::to_string(p.point3D_id) + ": track element (image " +
                             std::to_string(e.image_id) + ", 2D point " +
                             std::to_string(e.point2D_idx) + ") is not in the model");
      }
      track_image->push_back(it->second);
      (*image_used)[it->second] = 1;
    }
  }
}

// Problem cameras: the used images in image-id order (COLMAP writes its
// images in no particular order; the first, the lowest id, holds the gauge)
// into out's image_index; returns each model image's problem camera (-1:
// unused).
std::vector<int32_t> NumberUsedImages(const ColmapModel& model, const std::vector<uint8_t>& image_used,
                                      const std::string& source, ColmapProblem* out) {
  const int64_t num_images = static_cast<int64_t>(model.images.size());
  std::vector<int64_t> by_id(num_images);
  std::iota(by_id.begin(), by_id.end(), int64_t{0});
  std::sort(by_id.begin(), by_id.end(), [&](int64_t a, int64_t b) {
    return model.images[a].image_id < model.images[b].image_id;
  });
  std::vector<int32_t> problem_camera(num_images, -1);
  for (int64_t j : by_id) {
    if (!image_used[j]) continue;
    if (out->image_index.size() >= static_cast<size_t>(std::numeric_limits<int32_t>::max())) {
      throw InputError(source, 0, "more than 2^31 - 1 images");
    }
    problem_camera[j] = static_cast<int32_t>(out->image_index.size());
    out->image_index.push_back(j);
  }
  return problem_camera;
}

// The intrinsic groups: one per COLMAP camera used (shared) or per image,
// into out's group_camera and the problem's camera_intrinsics.
void GroupIntrinsics(const ColmapModel& model, const std::string& source, bool shared,
                     ColmapProblem* out) {
  const int64_t n = static_cast<int64_t>(out->image_index.size());
  std::unordered_map<uint32_t, int64_t> camera_of_id;
  for (size_t c = 0; c < model.cameras.size(); ++c) {
    camera_of_id.emplace(model.cameras[c].camera_id, static_cast<int64_t>(c));
  }
  std::vector<int64_t> image_camera(n);  // index into model.cameras
  for (int64_t i = 0; i < n; ++i) {
    const ColmapImage& im = model.images[out->image_index[i]];
    auto it = camera_of_id.find(im.camera_id);
    if (it == camera_of_id.end()) {
      throw InputError(source, 0,
                       "image " + std::to_string(im.image_id) + " (" + im.name +
                           "): its camera " + std::to_string(im.camera_id) +
                           " is not in the model");
    }
    image_camera[i] = it->second;
  }
  Problem& bp = out->problem;
  bp.camera_intrinsics.resize(n);
  if (!shared) {
    out->group_camera = image_camera;
    for (int64_t i = 0; i < n; ++i) bp.camera_intrinsics[i] = static_cast<int32_t>(i);
    return;
  }
  std::vector<int32_t> group_of_camera(model.cameras.size(), -1);
  for (int64_t i = 0; i < n; ++i) group_of_camera[image_camera[i]] = 0;
  for (size_t c = 0; c < model.cameras.size(); ++c) {
    if (group_of_camera[c] < 0) continue;
    group_of_camera[c] = static_cast<int32_t>(out->group_camera.size());
    out->group_camera.push_back(static_cast<int64_t>(c));
  }
  for (int64_t i = 0; i < n; ++i) bp.camera_intrinsics[i] = group_of_camera[image_camera[i]];
}

// Parameters: poses, then intrinsic groups (each camera's params as they
// are: COLMAP's model is the group's lens model).
void FillPosesAndIntrinsics(const ColmapModel& model, const std::string& source, ColmapProblem* out) {
  Problem& bp = out->problem;
  const int64_t n = static_cast<int64_t>(out->image_index.size());
  const int64_t num_groups = static_cast<int64_t>(out->group_camera.size());
  bp.group_models.resize(num_groups);
  bp.intrinsics_size = 1;
  for (int64_t g = 0; g < num_groups; ++g) {
    bp.group_models[g] = LensModelOfColmapCamera(model.cameras[out->group_camera[g]], source);
    bp.intrinsics_size = std::max(bp.intrinsics_size, LensModelParams(bp.group_models[g]));
  }
  bp.cameras.assign(kPhotoPoseSize * n + int64_t{bp.intrinsics_size} * num_groups, 0.0);
  for (int64_t i = 0; i < n; ++i) {
    const ColmapImage& im = model.images[out->image_index[i]];
    if (!colmap_internal::IsRotationQuaternion(im.qvec)) {
      throw InputError(source, 0, "image " + std::to_string(im.image_id) + " (" + im.name +
                                      "): its quaternion" + colmap_internal::kNotARotation);
    }
    const Vec3 omega = QuaternionToAngleAxis(im.qvec);
    double* pose = bp.camera(i);
    for (int d = 0; d < 3; ++d) {
      pose[d] = omega[d];
      pose[3 + d] = im.tvec[d];
    }
  }
  for (int64_t g = 0; g < num_groups; ++g) {
    const std::vector<double>& params = model.cameras[out->group_camera[g]].params;
    std::copy(params.begin(), params.end(), bp.intrinsics(g));
  }
}

// Points and their observations, point-major.
void FillPointsAndObservations(const ColmapModel& model, const std::vector<int64_t>& track_image,
                               const std::vector<int32_t>& problem_camera, ColmapProblem* out) {
  Problem& bp = out->problem;
  const int64_t num_points = static_cast<int64_t>(out->point_index.size());
  bp.points.resize(kPointSize * num_points);
  bp.point_offsets.resize(num_points + 1);
  bp.point_offsets[0] = 0;
  bp.obs_camera.resize(track_image.size());
  bp.obs_pixel.resize(2 * track_image.size());
  int64_t obs = 0;
  for (int64_t k = 0; k < num_points; ++k) {
    const ColmapPoint3D& p = model.points3D[out->point_index[k]];
    for (int d = 0; d < 3; ++d) bp.point(k)[d] = p.xyz[d];
    for (const ColmapTrackElement& e : p.track) {
      const int64_t j = track_image[obs];
      const ColmapPoint2D& xy = model.images[j].points2D[e.point2D_idx];
      bp.obs_camera[obs] = problem_camera[j];
      bp.obs_pixel[2 * obs] = xy.x;
      bp.obs_pixel[2 * obs + 1] = xy.y;
      ++obs;
    }
    bp.point_offsets[k + 1] = obs;
  }
}

}  // namespace

ColmapProblem ProblemFromColmap(const ColmapModel& model, const ColmapProblemOptions& options,
                                const std::string& source) {
  if (options.min_track_length < 1) {
    throw std::invalid_argument("ProblemFromColmap: min_track_length must be at least 1, not " +
                                std::to_string(options.min_track_length));
  }
  const int64_t num_images = static_cast<int64_t>(model.images.size());
  std::unordered_map<uint32_t, int64_t> image_of_id;
  for (int64_t j = 0; j < num_images; ++j) image_of_id.emplace(model.images[j].image_id, j);
  ColmapProblem out;
  std::vector<int64_t> track_image;  // image index of every kept track element
  std::vector<uint8_t> image_used(num_images, 0);
  KeepTracks(model, options.min_track_length, image_of_id, source, &out, &track_image, &image_used);
  const std::vector<int32_t> problem_camera = NumberUsedImages(model, image_used, source, &out);
  out.problem.model = CameraModel::kPhoto;
  GroupIntrinsics(model, source, options.shared_intrinsics, &out);
  FillPosesAndIntrinsics(model, source, &out);
  if (HasRealRigs(model)) {
    if (!options.shared_intrinsics) {
      throw UsageError("--intrinsics per-image: " + source +
                       " has rigs of several cameras, whose sensors are their cameras (one "
                       "intrinsic group per COLMAP camera)");
    }
    AddRigs(model, problem_camera, image_of_id, source, &out);
  }
  for (const ColmapRig& r : model.rigs) {
    out.sensors_not_modelled += r.ref.type != 0;
    for (const ColmapSensor& s : r.sensors) out.sensors_not_modelled += s.type != 0;
  }
  FillPointsAndObservations(model, track_image, problem_camera, &out);
  return out;
}

namespace {

// Quaternion of a solved rotation, keeping `q` bit for bit when it is in the
// written form and the solve left it (the round trip through angle-axis is
// exact only to rounding).
void SetQuaternion(const double* omega, std::array<double, 4>* q) {
  const Vec3 w(omega[0], omega[1], omega[2]);
  if (!IsWrittenForm(*q) || QuaternionToAngleAxis(*q) != w) *q = AngleAxisToQuaternion(w);
}

// The frames' poses: the solved ones with rigs, and the sensors'; without
// them each (trivial) frame at its camera image's pose.
void UpdateFrames(const ColmapProblem& source, const Problem& adjusted, ColmapModel* model) {
  if (model->frames.empty()) return;
  if (adjusted.has_rigs()) {
    for (size_t f = 0; f < source.frame_index.size(); ++f) {
      ColmapFrame& frame = model->frames[source.frame_index[f]];
      const double* pose = adjusted.cameras.data() + adjusted.frame_offset(static_cast<int64_t>(f));
      SetQuaternion(pose, &frame.qvec);
      frame.tvec = {pose[3], pose[4], pose[5]};
    }
    for (int64_t g = 0; g < adjusted.num_groups(); ++g) {
      if (adjusted.sensor_kind[g] == kRigOrigin) continue;
      const uint32_t id = model->cameras[source.group_camera[g]].camera_id;
      const double* pose = adjusted.cameras.data() + adjusted.sensor_offset(g);
      for (ColmapRig& r : model->rigs) {
        for (ColmapSensor& s : r.sensors) {
          if (s.type != 0 || s.id != id) continue;
          if (!s.has_pose) s.qvec = {1, 0, 0, 0};
          s.has_pose = true;
          SetQuaternion(pose, &s.qvec);
          s.tvec = {pose[3], pose[4], pose[5]};
        }
      }
    }
    return;
  }
  std::unordered_map<uint32_t, const ColmapImage*> image_of_id;
  for (const ColmapImage& im : model->images) image_of_id.emplace(im.image_id, &im);
  for (ColmapFrame& frame : model->frames) {
    for (const ColmapFrameData& d : frame.data) {
      if (d.type != 0) continue;
      const ColmapImage& im = *image_of_id.at(static_cast<uint32_t>(d.data_id));
      frame.qvec = im.qvec;
      frame.tvec = im.tvec;
    }
  }
}

[[noreturn]] void FailUpdate(const std::string& what) {
  throw std::invalid_argument("UpdateColmapModel: " + what);
}

// The adjusted problem against the source problem and its maps into the
// model; returns each model image's problem camera (-1: not in the problem).
std::vector<int32_t> CheckUpdateMaps(const ColmapProblem& source, const Problem& adjusted,
                                     const ColmapModel& model) {
  const Problem& sp = source.problem;
  if (adjusted.model != CameraModel::kPhoto) FailUpdate("the adjusted problem is not kPhoto");
  if (adjusted.camera_intrinsics != sp.camera_intrinsics ||
      adjusted.cameras.size() != sp.cameras.size() ||
      adjusted.points.size() != sp.points.size() ||
      adjusted.point_offsets != sp.point_offsets || adjusted.obs_camera != sp.obs_camera ||
      adjusted.obs_pixel.size() != sp.obs_pixel.size()) {
    FailUpdate("the adjusted problem's structure differs from the source problem's");
  }
  const int64_t n = adjusted.num_images();
  if (static_cast<int64_t>(source.image_index.size()) != n ||
      static_cast<int64_t>(source.group_camera.size()) != adjusted.num_groups() ||
      static_cast<int64_t>(source.point_index.size()) != adjusted.num_points()) {
    FailUpdate("the index maps do not match the problem's sizes");
  }
  const int64_t num_images = static_cast<int64_t>(model.images.size());
  std::vector<int32_t> problem_camera(num_images, -1);
  for (int64_t i = 0; i < n; ++i) {
    const int64_t j = source.image_index[i];
    if (j < 0 || j >= num_images) FailUpdate("image index out of the model's range");
    problem_camera[j] = static_cast<int32_t>(i);
  }
  for (int64_t c : source.group_camera) {
    if (c < 0 || c >= static_cast<int64_t>(model.cameras.size())) {
      FailUpdate("camera index out of the model's range");
    }
  }
  for (int64_t k : source.point_index) {
    if (k < 0 || k >= static_cast<int64_t>(model.points3D.size())) {
      FailUpdate("point index out of the model's range");
    }
  }
  return problem_camera;
}

// Intrinsics: into the camera its group owns (the group of the camera's
// first image), or a new camera; returns each group's camera id.
std::vector<uint32_t> UpdateCameras(const ColmapProblem& source, const Problem& adjusted,
                                    const std::vector<int32_t>& problem_camera, ColmapModel* model) {
  const int64_t num_images = static_cast<int64_t>(model->images.size());
  const int64_t num_cameras = static_cast<int64_t>(model->cameras.size());
  std::unordered_map<uint32_t, int64_t> camera_of_id;
  uint64_t max_id = 0;
  for (int64_t c = 0; c < num_cameras; ++c) {
    camera_of_id.emplace(model->cameras[c].camera_id, c);
    max_id = std::max<uint64_t>(max_id, model->cameras[c].camera_id);
  }
  std::vector<int64_t> owner_group(num_cameras, -2);  // -2: no user yet, -1: not in problem
  for (int64_t j = 0; j < num_images; ++j) {
    auto it = camera_of_id.find(model->images[j].camera_id);
    if (it == camera_of_id.end()) FailUpdate("an image's camera is not in the model");
    const int64_t c = it->second;
    const int32_t i = problem_camera[j];
    if (i >= 0 && source.group_camera[adjusted.camera_intrinsics[i]] != c) {
      FailUpdate("image " + std::to_string(model->images[j].image_id) +
                 "'s camera is not its intrinsic group's camera");
    }
    if (owner_group[c] == -2) owner_group[c] = i >= 0 ? adjusted.camera_intrinsics[i] : -1;
  }
  std::vector<uint32_t> group_id(adjusted.num_groups());
  for (int64_t g = 0; g < adjusted.num_groups(); ++g) {
    const int64_t c = source.group_camera[g];
    const double* x = adjusted.intrinsics(g);
    const auto set_params = [&](ColmapCamera* camera) {
      std::copy(x, x + camera->params.size(), camera->params.begin());
    };
    if (owner_group[c] == g) {
      set_params(&model->cameras[c]);
      group_id[g] = model->cameras[c].camera_id;
      continue;
    }
    if (max_id >= std::numeric_limits<uint32_t>::max()) FailUpdate("no camera id left for a new camera");
    ColmapCamera camera = model->cameras[c];
    camera.camera_id = static_cast<uint32_t>(++max_id);
    set_params(&camera);
    group_id[g] = camera.camera_id;
    model->cameras.push_back(std::move(camera));
  }
  return group_id;
}

// Points, with their mean reprojection error.
void UpdatePoints(const ColmapProblem& source, const Problem& adjusted, ColmapModel* model) {
  for (int64_t k = 0; k < adjusted.num_points(); ++k) {
    ColmapPoint3D& p = model->points3D[source.point_index[k]];
    const double* X = adjusted.point(k);
    p.xyz = {X[0], X[1], X[2]};
    const int64_t begin = adjusted.point_offsets[k], end = adjusted.point_offsets[k + 1];
    double sum = 0;
    for (int64_t o = begin; o < end; ++o) {
      const int32_t i = adjusted.obs_camera[o];
      sum += ObservationResidual(adjusted, adjusted.cameras.data(), i, X, adjusted.pixel(o)).norm();
    }
    if (end > begin) p.error = sum / static_cast<double>(end - begin);
  }
}

}  // namespace

void UpdateColmapModel(const ColmapProblem& source, const Problem& adjusted,
                       ColmapModel* model) {
  const std::vector<int32_t> problem_camera = CheckUpdateMaps(source, adjusted, *model);
  const std::vector<uint32_t> group_id = UpdateCameras(source, adjusted, problem_camera, model);
  // Poses.
  for (int64_t i = 0; i < adjusted.num_images(); ++i) {
    ColmapImage& im = model->images[source.image_index[i]];
    const double* pose = adjusted.camera(i);
    // A rotation the solve did not change keeps its quaternion bit for bit
    // when that is already in the written form (unit to rounding, w >= 0):
    // the round trip through angle-axis is exact only to rounding.
    const Vec3 omega(pose[0], pose[1], pose[2]);
    if (!IsWrittenForm(im.qvec) || QuaternionToAngleAxis(im.qvec) != omega) {
      im.qvec = AngleAxisToQuaternion(omega);
    }
    im.tvec = {pose[3], pose[4], pose[5]};
    im.camera_id = group_id[adjusted.camera_intrinsics[i]];
  }
  UpdateFrames(source, adjusted, model);
  UpdatePoints(source, adjusted, model);
}

void RemoveDroppedObservations(const ColmapProblem& source, const Problem& adjusted,
                               const std::vector<uint8_t>& observation_kept,
                               const std::vector<uint8_t>& point_kept, ColmapModel* model) {
  const Problem& sp = source.problem;
  auto fail = [](const std::string& what) {
    throw std::invalid_argument("RemoveDroppedObservations: " + what);
  };
  if (static_cast<int64_t>(observation_kept.size()) != sp.num_observations() ||
      static_cast<int64_t>(point_kept.size()) != sp.num_points()) {
    fail("the kept flags do not match the problem's observations and points");
  }
  std::unordered_map<uint32_t, size_t> image_of_id;
  for (size_t j = 0; j < model->images.size(); ++j) image_of_id[model->images[j].image_id] = j;
  auto unlink = [&](const ColmapTrackElement& e) {
    auto it = image_of_id.find(e.image_id);
    if (it == image_of_id.end() || e.point2D_idx >= model->images[it->second].points2D.size()) {
      fail("a track element is not in the model");
    }
    model->images[it->second].points2D[e.point2D_idx].point3D_id = kColmapNoPoint3D;
  };
  std::vector<uint8_t> remove(model->points3D.size(), 0);
  for (int64_t k = 0; k < sp.num_points(); ++k) {
    const int64_t m = source.point_index[k];
    if (m < 0 || m >= static_cast<int64_t>(model->points3D.size())) fail("point index out of range");
    ColmapPoint3D& p = model->points3D[m];
    const int64_t first = sp.point_offsets[k];
    if (static_cast<int64_t>(p.track.size()) != sp.point_offsets[k + 1] - first) {
      fail("a track's length differs from its point's observations");
    }
    if (adjusted.num_observations() != sp.num_observations()) fail("adjusted is not source's problem");
    if (!point_kept[k]) {
      for (const ColmapTrackElement& e : p.track) unlink(e);
      remove[m] = 1;
      continue;
    }
    size_t kept = 0;
    double sum = 0;
    for (size_t j = 0; j < p.track.size(); ++j) {
      const int64_t o = first + static_cast<int64_t>(j);
      if (observation_kept[o]) {
        p.track[kept++] = p.track[j];
        sum += ObservationResidual(adjusted, adjusted.cameras.data(), adjusted.obs_camera[o],
                                   adjusted.point(k), adjusted.pixel(o))
                   .norm();
      } else {
        unlink(p.track[j]);
      }
    }
    p.track.resize(kept);
    if (kept > 0) p.error = sum / static_cast<double>(kept);
  }
  size_t kept_points = 0;
  for (size_t m = 0; m < model->points3D.size(); ++m) {
    if (remove[m]) continue;
    // Not onto itself: a vector moved onto itself is left empty.
    if (kept_points != m) model->points3D[kept_points] = std::move(model->points3D[m]);
    ++kept_points;
  }
  model->points3D.resize(kept_points);
}

}  // namespace dba
