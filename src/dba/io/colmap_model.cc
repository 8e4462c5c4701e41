// COLMAP sparse models: camera model table, validation, format detection and
// the intrinsics mapping; see colmap_model.h.
#include "dba/io/colmap_model.h"
#include "dba/io/stale_temporaries.h"

#include "dba/io/colmap_model_internal.h"

#include "dba/io/temporary_registry.h"

#include <unistd.h>

#include <algorithm>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>
#include <charconv>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>
#include <stdexcept>
#include <unordered_map>

#include "dba/common/error.h"
#include "dba/io/colmap_binary.h"
#include "dba/io/colmap_text.h"
#include "dba/problem/lens_ranges.h"
#include "dba/problem/pixel_range.h"

namespace dba {
namespace {

uint64_t Bits(double v) { return std::bit_cast<uint64_t>(v); }

std::string Num(double v) {
  char buf[64];
  std::snprintf(buf, sizeof buf, "%.17g", v);
  return buf;
}

// The rigs and frames against the model: rig ids unique, a camera in at
// most one rig and in the model; each frame names a rig of the model, each
// of its data a sensor of that rig, a camera's an image of the model with
// that camera, one per camera (a frame is one exposure); no image in two
// frames and (when there are frames) every image in one: COLMAP >= 3.12
// takes each image's pose from its frame and cannot load an image without
// one.
void CheckRigsAndFrames(const ColmapModel& model, const std::string& dir, bool binary) {
  if (model.frames.empty() && model.rigs.empty()) return;
  const std::string ext = binary ? ".bin" : ".txt";
  const std::string rigs = colmap_internal::JoinPath(dir, "rigs" + ext);
  const std::string frames = colmap_internal::JoinPath(dir, "frames" + ext);
  std::unordered_map<uint32_t, const ColmapRig*> rig_of_id;
  std::unordered_map<uint32_t, uint32_t> rig_of_camera, camera_of_image;
  std::unordered_map<uint32_t, int> cameras;
  for (const ColmapCamera& c : model.cameras) cameras.emplace(c.camera_id, 0);
  for (const ColmapRig& r : model.rigs) {
    const std::string rig = "rig " + std::to_string(r.rig_id) + ": ";
    if (!rig_of_id.emplace(r.rig_id, &r).second) throw InputError(rigs, 0, rig + "appears twice");
    std::vector<ColmapSensor> all{r.ref};
    all.insert(all.end(), r.sensors.begin(), r.sensors.end());
    for (const ColmapSensor& s : all) {
      if (s.type != 0) continue;
      if (!cameras.count(s.id)) {
        throw InputError(rigs, 0, rig + "camera " + std::to_string(s.id) + " is not in the model");
      }
      if (!rig_of_camera.emplace(s.id, r.rig_id).second) {
        throw InputError(rigs, 0, rig + "camera " + std::to_string(s.id) + " is also a sensor of rig " +
                                      std::to_string(rig_of_camera[s.id]));
      }
    }
  }
  for (const ColmapImage& im : model.images) camera_of_image.emplace(im.image_id, im.camera_id);
  std::unordered_map<uint64_t, uint32_t> frame_of_image;
  for (const ColmapFrame& f : model.frames) {
    const std::string frame = "frame " + std::to_string(f.frame_id) + ": ";
    const auto rig = rig_of_id.find(f.rig_id);
    if (rig == rig_of_id.end()) {
      throw InputError(frames, 0, frame + "names rig " + std::to_string(f.rig_id) + ", which the rigs do not hold");
    }
    std::unordered_map<uint32_t, uint64_t> image_of_camera;  // this frame's
    for (const ColmapFrameData& d : f.data) {
      const ColmapRig& r = *rig->second;
      const bool of_rig = (r.ref.type == d.type && r.ref.id == d.sensor_id) ||
                          std::any_of(r.sensors.begin(), r.sensors.end(), [&](const ColmapSensor& s) {
                            return s.type == d.type && s.id == d.sensor_id;
                          });
      if (!of_rig) {
        throw InputError(frames, 0, frame + "sensor " + std::to_string(d.sensor_id) +
                                        " is not a sensor of rig " + std::to_string(f.rig_id));
      }
      if (d.type != 0) continue;
      const auto image = d.data_id <= UINT32_MAX ? camera_of_image.find(static_cast<uint32_t>(d.data_id))
                                                 : camera_of_image.end();
      if (image == camera_of_image.end() || image->second != d.sensor_id) {
        throw InputError(frames, 0, frame + "names image " + std::to_string(d.data_id) + " with camera " +
                                        std::to_string(d.sensor_id) + ", which the model does not hold");
      }
      if (!frame_of_image.emplace(d.data_id, f.frame_id).second) {
        throw InputError(frames, 0, frame + "image " + std::to_string(d.data_id) + " is also in frame " +
                                        std::to_string(frame_of_image[d.data_id]));
      }
      if (const auto [other, fresh] = image_of_camera.emplace(d.sensor_id, d.data_id); !fresh) {
        throw InputError(frames, 0, frame + "images " + std::to_string(other->second) + " and " +
                                        std::to_string(d.data_id) + " are both of camera " +
                                        std::to_string(d.sensor_id) +
                                        " (a frame is one exposure: one image per sensor)");
      }
    }
  }
  for (const ColmapImage& im : model.images) {
    if (!frame_of_image.count(im.image_id)) {
      throw InputError(frames, 0, "image " + std::to_string(im.image_id) +
                                      " is in no frame (COLMAP >= 3.12 takes each image's pose "
                                      "from its frame)");
    }
  }
}

}  // namespace

std::span<const ColmapCameraModelInfo> ColmapCameraModels() {
  // The lens table lists COLMAP's models first, in id order.
  return LensModels().first(static_cast<size_t>(LensModel::kEquirectangular) + 1);
}

const ColmapCameraModelInfo* FindColmapCameraModel(std::string_view name) {
  const LensModelInfo* m = FindLensModel(name);
  return m != nullptr && m->colmap ? m : nullptr;
}

const ColmapCameraModelInfo* FindColmapCameraModel(int32_t id) {
  const LensModelInfo* m = FindLensModel(id);
  return m != nullptr && m->colmap ? m : nullptr;
}

std::string ColmapCamera::ModelName() const {
  const ColmapCameraModelInfo* m = FindColmapCameraModel(model_id);
  return m != nullptr ? std::string(m->name) : "UNKNOWN(" + std::to_string(model_id) + ")";
}

int64_t ColmapModel::NumObservations() const {
  int64_t n = 0;
  for (const auto& p : points3D) n += static_cast<int64_t>(p.track.size());
  return n;
}

int64_t ColmapModel::NumPoints2DWithPoint3D() const {
  int64_t n = 0;
  for (const auto& im : images) {
    for (const auto& p : im.points2D) n += p.point3D_id != kColmapNoPoint3D;
  }
  return n;
}

// ---------------------------------------------------------------------------

std::string FirstColmapModelDifference(const ColmapModel& a, const ColmapModel& b) {
  auto same = [](double x, double y) { return Bits(x) == Bits(y); };
  if (a.cameras.size() != b.cameras.size()) {
    return "camera count " + std::to_string(a.cameras.size()) + " vs " +
           std::to_string(b.cameras.size());
  }
  for (size_t i = 0; i < a.cameras.size(); ++i) {
    const ColmapCamera& x = a.cameras[i];
    const ColmapCamera& y = b.cameras[i];
    const std::string at = "camera #" + std::to_string(i) + " (id " +
                           std::to_string(x.camera_id) + "): ";
    if (x.camera_id != y.camera_id) return at + "camera_id differs";
    if (x.model_id != y.model_id) return at + "model " + x.ModelName() + " vs " + y.ModelName();
    if (x.width != y.width || x.height != y.height) return at + "size differs";
    if (x.params.size() != y.params.size()) return at + "parameter count differs";
    for (size_t k = 0; k < x.params.size(); ++k) {
      if (!same(x.params[k], y.params[k])) {
        return at + "param " + std::to_string(k) + ": " + Num(x.params[k]) + " vs " +
               Num(y.params[k]);
      }
    }
  }
  if (a.images.size() != b.images.size()) {
    return "image count " + std::to_string(a.images.size()) + " vs " +
           std::to_string(b.images.size());
  }
  for (size_t i = 0; i < a.images.size(); ++i) {
    const ColmapImage& x = a.images[i];
    const ColmapImage& y = b.images[i];
    const std::string at =
        "image #" + std::to_string(i) + " (id " + std::to_string(x.image_id) + "): ";
    if (x.image_id != y.image_id) return at + "image_id differs";
    for (int k = 0; k < 4; ++k) {
      if (!same(x.qvec[k], y.qvec[k])) {
        return at + "qvec[" + std::to_string(k) + "]: " + Num(x.qvec[k]) + " vs " +
               Num(y.qvec[k]);
      }
    }
    for (int k = 0; k < 3; ++k) {
      if (!same(x.tvec[k], y.tvec[k])) {
        return at + "tvec[" + std::to_string(k) + "]: " + Num(x.tvec[k]) + " vs " +
               Num(y.tvec[k]);
      }
    }
    if (x.camera_id != y.camera_id) return at + "camera_id differs";
    if (x.name != y.name) return at + "name '" + x.name + "' vs '" + y.name + "'";
    if (x.points2D.size() != y.points2D.size()) {
      return at + "point2D count " + std::to_string(x.points2D.size()) + " vs " +
             std::to_string(y.points2D.size());
    }
    for (size_t k = 0; k < x.points2D.size(); ++k) {
      const ColmapPoint2D& p = x.points2D[k];
      const ColmapPoint2D& q = y.points2D[k];
      if (!same(p.x, q.x) || !same(p.y, q.y) || p.point3D_id != q.point3D_id) {
        return at + "point2D " + std::to_string(k) + ": (" + Num(p.x) + ", " + Num(p.y) +
               ", " + std::to_string(p.point3D_id) + ") vs (" + Num(q.x) + ", " + Num(q.y) +
               ", " + std::to_string(q.point3D_id) + ")";
      }
    }
  }
  if (a.points3D.size() != b.points3D.size()) {
    return "point3D count " + std::to_string(a.points3D.size()) + " vs " +
           std::to_string(b.points3D.size());
  }
  for (size_t i = 0; i < a.points3D.size(); ++i) {
    const ColmapPoint3D& x = a.points3D[i];
    const ColmapPoint3D& y = b.points3D[i];
    const std::string at =
        "point3D #" + std::to_string(i) + " (id " + std::to_string(x.point3D_id) + "): ";
    if (x.point3D_id != y.point3D_id) return at + "point3D_id differs";
    for (int k = 0; k < 3; ++k) {
      if (!same(x.xyz[k], y.xyz[k])) {
        return at + "xyz[" + std::to_string(k) + "]: " + Num(x.xyz[k]) + " vs " +
               Num(y.xyz[k]);
      }
    }
    if (x.rgb != y.rgb) return at + "rgb differs";
    if (!same(x.error, y.error)) return at + "error " + Num(x.error) + " vs " + Num(y.error);
    if (x.track != y.track) return at + "track differs";
  }
  return "";
}

// ---------------------------------------------------------------------------

namespace colmap_internal {

bool IsRotationQuaternion(const std::array<double, 4>& q) {
  const double norm = std::sqrt(q[0] * q[0] + q[1] * q[1] + q[2] * q[2] + q[3] * q[3]);
  return norm > 0 && std::isfinite(norm);
}

// A value no camera has: an image of no pixels (or beyond a million on a
// side), a parameter out of its lens model's range (problem/lens_ranges.h),
// an EQUIRECTANGULAR whose w, h differ from the image's size; empty when none.
std::string AbsurdCameraValue(const ColmapCamera& c, const ColmapCameraModelInfo& m) {
  constexpr auto kMaxSide = static_cast<uint64_t>(kMaxImageSidePixels);
  if (c.width < 1 || c.height < 1 || c.width > kMaxSide || c.height > kMaxSide) {
    return "image size " + std::to_string(c.width) + " x " + std::to_string(c.height) +
           " is outside 1 to 1000000 pixels a side";
  }
  const std::string out_of_range = LensValueOutOfRange(m.id, c.params.data());
  if (!out_of_range.empty()) return out_of_range;
  if (m.id == LensModel::kEquirectangular &&
      (c.params[0] != static_cast<double>(c.width) || c.params[1] != static_cast<double>(c.height))) {
    return "EQUIRECTANGULAR's w, h are " + Num(c.params[0]) + ", " + Num(c.params[1]) + " but the image is " + std::to_string(c.width) + " x " +
           std::to_string(c.height) + " (w and h are the image's size)";
  }
  return {};
}

namespace {

bool AllFinite(const double* v, size_t n) {
  for (size_t i = 0; i < n; ++i) {
    if (!std::isfinite(v[i])) return false;
  }
  return true;
}

// ValidateColmapModel's checks in their order: the cameras, the images and
// their 2D points, the tracks against the images, and every 2D point that
// names a 3D point listed by that point's track.
class ColmapModelValidator {
 public:
  ColmapModelValidator(const ColmapModel& model, const std::string& dir,
                       const std::string& extension, const ColmapSourceLines* lines)
      : model_(model),
        lines_(lines),
        cameras_file_(JoinPath(dir, "cameras" + extension)),
        images_file_(JoinPath(dir, "images" + extension)),
        points_file_(JoinPath(dir, "points3D" + extension)) {}

  void Run() {
    CheckCameras();
    CheckImages();
    CheckTracks();
    CheckEveryObservationIsTracked();
  }

 private:
  int64_t LineOf(const std::vector<int64_t> ColmapSourceLines::*member, size_t i) const {
    if (lines_ == nullptr) return 0;
    const std::vector<int64_t>& v = lines_->*member;
    return i < v.size() ? v[i] : 0;
  }

  // In binary files entries have no line: named by position.
  std::string Entry(const char* kind, size_t i, int64_t id) const {
    std::string s = kind;
    if (lines_ == nullptr) s += " #" + std::to_string(i) + " (id " + std::to_string(id) + ")";
    else s += " " + std::to_string(id);
    return s + ": ";
  }

  void CheckCameras();
  void CheckImages();
  void CheckImagePoints(const ColmapImage& im, size_t i, int64_t line) const;
  void CheckTracks();
  void CheckEveryObservationIsTracked() const;

  const ColmapModel& model_;
  const ColmapSourceLines* lines_;
  const std::string cameras_file_, images_file_, points_file_;
  std::unordered_map<uint32_t, size_t> camera_index_;
  std::unordered_map<uint32_t, size_t> image_index_;
  std::vector<size_t> image_offset_;  // the first 2D point of each image, of all
  std::vector<uint8_t> visited_;  // [image_offset_[i] + k]: a track lists 2D point k of image i
  std::unordered_map<int64_t, size_t> point_index_;
};

void ColmapModelValidator::CheckCameras() {
  camera_index_.reserve(model_.cameras.size());
  for (size_t i = 0; i < model_.cameras.size(); ++i) {
    const ColmapCamera& c = model_.cameras[i];
    const int64_t line = LineOf(&ColmapSourceLines::cameras, i);
    auto at = [&] { return Entry("camera", i, c.camera_id); };
    if (!camera_index_.emplace(c.camera_id, i).second) {
      throw InputError(cameras_file_, line, at() + "camera_id appears twice");
    }
    const ColmapCameraModelInfo* m = FindColmapCameraModel(c.model_id);
    if (m == nullptr) {
      throw InputError(cameras_file_, line,
                       at() + "unknown camera model id " + std::to_string(c.model_id));
    }
    if (c.params.size() != static_cast<size_t>(m->num_params)) {
      throw InputError(cameras_file_, line,
                       at() + m->name + " has " + std::to_string(m->num_params) + " parameters (" +
                           m->params + "), the camera has " + std::to_string(c.params.size()));
    }
    if (!AllFinite(c.params.data(), c.params.size())) {
      throw InputError(cameras_file_, line, at() + "non-finite camera parameter");
    }
    const std::string absurd = AbsurdCameraValue(c, *m);
    if (!absurd.empty()) throw InputError(cameras_file_, line, at() + absurd);
  }
}

void ColmapModelValidator::CheckImages() {
  image_index_.reserve(model_.images.size());
  std::unordered_map<std::string_view, int64_t> image_name;  // name -> its line (or entry)
  image_offset_.assign(model_.images.size() + 1, 0);
  for (size_t i = 0; i < model_.images.size(); ++i) {
    const ColmapImage& im = model_.images[i];
    const int64_t line = LineOf(&ColmapSourceLines::images, i);
    auto at = [&] { return Entry("image", i, im.image_id); };
    if (!image_index_.emplace(im.image_id, i).second) {
      throw InputError(images_file_, line, at() + "image_id appears twice");
    }
    // Priors and ground control bind to images by name.
    const auto [named, fresh] = image_name.emplace(im.name, lines_ ? line : static_cast<int64_t>(i));
    if (!fresh) {
      throw InputError(images_file_, line,
                       at() + "the name '" + Clipped(im.name) + "' is also image " +
                           (lines_ ? "on line " : "entry #") + std::to_string(named->second) +
                           "'s: image names must be unique");
    }
    if (!camera_index_.contains(im.camera_id)) {
      throw InputError(images_file_, line,
                       at() + "camera_id " + std::to_string(im.camera_id) + " is not in " +
                           cameras_file_);
    }
    if (!AllFinite(im.qvec.data(), 4) || !AllFinite(im.tvec.data(), 3)) {
      throw InputError(images_file_, line, at() + "non-finite qvec or tvec");
    }
    if (!IsRotationQuaternion(im.qvec)) throw InputError(images_file_, line, at() + "qvec" + kNotARotation);
    CheckImagePoints(im, i, line);
    image_offset_[i + 1] = image_offset_[i] + im.points2D.size();
  }
}

void ColmapModelValidator::CheckImagePoints(const ColmapImage& im, size_t i, int64_t line) const {
  for (size_t k = 0; k < im.points2D.size(); ++k) {
    const ColmapPoint2D& p = im.points2D[k];
    const std::string out_of_range = PixelOutOfRange(p.x, p.y);
    if (!out_of_range.empty()) {
      throw InputError(images_file_, line > 0 ? line + 1 : 0,
                       Entry("image", i, im.image_id) + "point2D " + std::to_string(k) + ": " +
                           out_of_range);
    }
    if (p.point3D_id < kColmapNoPoint3D) {
      throw InputError(images_file_, line > 0 ? line + 1 : 0,
                       Entry("image", i, im.image_id) + "point2D " + std::to_string(k) +
                           " has point3D_id " + std::to_string(p.point3D_id) +
                           " (expected -1 or >= 0)");
    }
  }
}

void ColmapModelValidator::CheckTracks() {
  visited_.assign(image_offset_.back(), 0);
  point_index_.reserve(model_.points3D.size());
  for (size_t i = 0; i < model_.points3D.size(); ++i) {
    const ColmapPoint3D& p = model_.points3D[i];
    const int64_t line = LineOf(&ColmapSourceLines::points3D, i);
    auto at = [&] { return Entry("point3D", i, p.point3D_id); };
    if (p.point3D_id < 0) throw InputError(points_file_, line, at() + "point3D_id must be >= 0");
    if (!point_index_.emplace(p.point3D_id, i).second) {
      throw InputError(points_file_, line, at() + "point3D_id appears twice");
    }
    if (!AllFinite(p.xyz.data(), 3) || !std::isfinite(p.error)) {
      throw InputError(points_file_, line, at() + "non-finite xyz or error");
    }
    for (size_t t = 0; t < p.track.size(); ++t) {
      const ColmapTrackElement& e = p.track[t];
      auto el = [&] {
        return at() + "track element " + std::to_string(t) + " (image " +
               std::to_string(e.image_id) + ", point2D_idx " + std::to_string(e.point2D_idx) +
               "): ";
      };
      auto it = image_index_.find(e.image_id);
      if (it == image_index_.end()) {
        throw InputError(points_file_, line, el() + "no such image in " + images_file_);
      }
      const ColmapImage& im = model_.images[it->second];
      if (e.point2D_idx >= im.points2D.size()) {
        throw InputError(points_file_, line,
                         el() + "the image has only " + std::to_string(im.points2D.size()) +
                             " 2D points");
      }
      const int64_t back = im.points2D[e.point2D_idx].point3D_id;
      if (back != p.point3D_id) {
        throw InputError(points_file_, line,
                         el() + "that 2D point refers to point3D_id " + std::to_string(back) +
                             ", not back to this point");
      }
      uint8_t& seen = visited_[image_offset_[it->second] + e.point2D_idx];
      if (seen) throw InputError(points_file_, line, el() + "listed twice");
      seen = 1;
    }
  }
}

void ColmapModelValidator::CheckEveryObservationIsTracked() const {
  for (size_t i = 0; i < model_.images.size(); ++i) {
    const ColmapImage& im = model_.images[i];
    const int64_t line = LineOf(&ColmapSourceLines::images, i);
    for (size_t k = 0; k < im.points2D.size(); ++k) {
      const int64_t id = im.points2D[k].point3D_id;
      if (id == kColmapNoPoint3D || visited_[image_offset_[i] + k]) continue;
      const std::string what = point_index_.contains(id)
                                   ? " whose track does not list this 2D point"
                                   : " which is not in " + points_file_;
      throw InputError(images_file_, line > 0 ? line + 1 : 0,
                       Entry("image", i, im.image_id) + "point2D " + std::to_string(k) +
                           " refers to point3D_id " + std::to_string(id) + what);
    }
  }
}

}  // namespace

void ValidateColmapModel(const ColmapModel& model, const std::string& dir,
                         const std::string& extension, const ColmapSourceLines* lines) {
  ColmapModelValidator(model, dir, extension, lines).Run();
}

std::string JoinPath(const std::string& dir, const std::string& name) {
  if (dir.empty()) return name;
  if (dir.back() == '/') return dir + name;
  return dir + "/" + name;
}

void EnsureDirectory(const std::string& dir) {
  std::error_code ec;
  std::filesystem::create_directories(dir, ec);
  if (ec) throw std::runtime_error(dir + ": cannot create directory: " + ec.message());
  if (!std::filesystem::is_directory(dir, ec)) {
    throw std::runtime_error(dir + ": not a directory");
  }
}

void CheckWritable(const ColmapModel& model, bool text) {
  for (const ColmapCamera& c : model.cameras) {
    const ColmapCameraModelInfo* m = FindColmapCameraModel(c.model_id);
    if (m == nullptr) {
      throw std::invalid_argument("COLMAP camera " + std::to_string(c.camera_id) +
                                  ": unknown camera model id " + std::to_string(c.model_id));
    }
    if (c.params.size() != static_cast<size_t>(m->num_params)) {
      throw std::invalid_argument("COLMAP camera " + std::to_string(c.camera_id) + ": " +
                                  m->name + " needs " + std::to_string(m->num_params) +
                                  " parameters, has " + std::to_string(c.params.size()));
    }
  }
  for (const ColmapImage& im : model.images) {
    const std::string& n = im.name;
    const std::string_view bad = text ? std::string_view("\0\r\n", 3) : std::string_view("\0", 1);
    auto blank = [](char ch) { return ch == ' ' || ch == '\t' || ch == '\v' || ch == '\f'; };
    const bool unreadable =
        n.find_first_of(bad) != std::string::npos ||
        (text && (n.empty() || blank(n.front()) || blank(n.back())));
    if (unreadable) {
      throw std::invalid_argument(
          "COLMAP image " + std::to_string(im.image_id) + ": name '" + n + "' cannot be written " +
          (text ? "as text (empty, NUL/CR/LF, or leading or trailing blanks)" : "(NUL byte)"));
    }
  }
}

}  // namespace colmap_internal

void ValidateColmapModel(const ColmapModel& model, const std::string& dir,
                         const std::string& extension) {
  colmap_internal::ValidateColmapModel(model, dir, extension, nullptr);
}

// ---------------------------------------------------------------------------

std::span<const char* const> ColmapModelFiles() {
  static constexpr const char* kFiles[] = {"cameras.txt", "images.txt", "points3D.txt",
                                           "rigs.txt",    "frames.txt", "cameras.bin",
                                           "images.bin",  "points3D.bin", "rigs.bin",
                                           "frames.bin"};
  return kFiles;
}

std::optional<ColmapFormat> DetectColmapFormat(const std::string& dir) {
  auto all = [&](const char* ext) {
    for (const char* stem : {"cameras", "images", "points3D"}) {
      std::error_code ec;
      if (!std::filesystem::is_regular_file(
              colmap_internal::JoinPath(dir, std::string(stem) + ext), ec)) {
        return false;
      }
    }
    return true;
  };
  if (all(".bin")) return ColmapFormat::kBinary;
  if (all(".txt")) return ColmapFormat::kText;
  return std::nullopt;
}

bool HasRigsOrFrames(const std::string& dir) {
  std::error_code ec;
  for (const char* name : {"rigs.txt", "rigs.bin", "frames.txt", "frames.bin"}) {
    if (std::filesystem::exists(colmap_internal::JoinPath(dir, name), ec)) return true;
  }
  return false;
}

ColmapModel ReadColmapModel(const std::string& dir) {
  std::error_code ec;
  if (!std::filesystem::exists(dir, ec)) {
    throw InputError(dir, 0, "no such directory (expected a COLMAP sparse model directory)");
  }
  if (!std::filesystem::is_directory(dir, ec)) {
    throw InputError(dir, 0,
                     "not a directory (expected a COLMAP sparse model directory holding "
                     "cameras, images and points3D as .txt or .bin)");
  }
  // A write into this model that a dead process left unfinished is undone
  // or finished first (io/stale_temporaries.h): the model is read whole,
  // old or new, its rigs and frames included.
  for (const char* name : ColmapModelFiles()) {
    RecoverStaleTemporaries(colmap_internal::JoinPath(dir, name));
  }
  const std::optional<ColmapFormat> format = DetectColmapFormat(dir);
  if (format.has_value()) {
    const bool binary = format == ColmapFormat::kBinary;
    ColmapModel rigs;
    colmap_internal::ReadRigsAndFrames(dir, binary, &rigs);
    ColmapModel model = binary ? ReadColmapBinary(dir) : ReadColmapText(dir);
    model.rigs = std::move(rigs.rigs);
    model.frames = std::move(rigs.frames);
    CheckRigsAndFrames(model, dir, binary);
    return model;
  }

  std::string found;
  for (const char* name : {"cameras.txt", "images.txt", "points3D.txt", "cameras.bin",
                           "images.bin", "points3D.bin"}) {
    if (std::filesystem::is_regular_file(colmap_internal::JoinPath(dir, name), ec)) {
      found += found.empty() ? "" : ", ";
      found += name;
    }
  }
  std::string what =
      "no complete COLMAP model: expected cameras.txt, images.txt and points3D.txt, or "
      "cameras.bin, images.bin and points3D.bin; found " +
      (found.empty() ? std::string("none of them") : found);
  const std::string nested = colmap_internal::JoinPath(dir, "sparse/0");
  if (DetectColmapFormat(nested).has_value()) what += " (did you mean " + nested + "?)";
  throw InputError(dir, 0, what);
}

// ---------------------------------------------------------------------------

LensModel LensModelOfColmapCamera(const ColmapCamera& camera, const std::string& file) {
  const std::string at = "camera " + std::to_string(camera.camera_id) + ": ";
  const LensModelInfo* m = FindLensModel(camera.model_id);
  if (m == nullptr || !m->colmap) {
    throw InputError(file, 0,
                     at + "unknown camera model id " + std::to_string(camera.model_id) +
                         " (COLMAP's models: " + LensModelNames() + ")");
  }
  if (camera.params.size() != static_cast<size_t>(m->num_params)) {
    throw InputError(file, 0,
                     at + m->name + " needs " + std::to_string(m->num_params) +
                         " parameters, the camera has " + std::to_string(camera.params.size()));
  }
  return m->id;
}

}  // namespace dba
