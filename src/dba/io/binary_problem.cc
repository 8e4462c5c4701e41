// The dba binary problem format; see binary_problem.h.
#include "dba/io/binary_problem.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <algorithm>
#include <array>
#include <bit>
#include <cerrno>
#include <cmath>
#include <cstring>

#include "dba/common/error.h"
#include "dba/io/atomic_output_file.h"
#include "dba/io/binary_file.h"
#include "dba/problem/lens_ranges.h"
#include "dba/problem/pixel_range.h"
#include "dba/problem/rig_frames.h"

namespace dba {
namespace {

static_assert(std::endian::native == std::endian::little,
              "the binary format is read and written on little-endian machines");

constexpr char kMagic[8] = {'D', 'B', 'A', 'P', 'R', 'O', 'B', '\n'};
constexpr uint32_t kVersion1 = 1;  // BAL only
constexpr uint32_t kVersion2 = 2;  // + photogrammetric model, fixed flags
constexpr uint32_t kVersion3 = 3;  // + a lens model per group, 1 to 16 intrinsic slots
constexpr uint32_t kVersion4 = 4;  // + rigs: frames, sensor poses, image frames, sensor kinds
constexpr int64_t kRigHeaderSize = 16;  // version 4: u64 frames, u64 rig section offset
constexpr uint32_t kByteOrderMark = 0x01020304;
constexpr uint32_t kBalModel = 1;
constexpr uint32_t kPhotoModel = 2;
constexpr uint32_t kHasFixedCameras = 1;
constexpr uint32_t kHasIntrinsicsFree = 2;
constexpr int64_t kHeaderSize = 128;

struct RawHeader {
  char magic[8];
  uint32_t version;
  uint32_t byte_order;
  uint32_t camera_model;
  uint32_t camera_size;
  uint64_t counts[3];
  uint64_t sections[5];
  uint64_t file_size;
  // Version 2 and 3 (version 1: zero).
  uint32_t intrinsic_groups;
  uint16_t optional_sections;
  uint16_t intrinsic_slots;  // version 3 (version 2: zero)
  uint64_t sections2[3];  // intrinsics, image groups, flags
};
static_assert(sizeof(RawHeader) == kHeaderSize);

int64_t Align8(int64_t x) { return (x + 7) & ~int64_t{7}; }


// The layout of a problem with these counts: version 2 only when the model
// or the flags need it. Throws std::invalid_argument for a group count that
// does not fit the model.
BinaryProblemHeader Layout(CameraModel model, int64_t cameras, int64_t groups, bool fixed,
                           bool free, int64_t points, int64_t observations, bool v3 = false,
                           int slots = kPhotoIntrinsicsSize, int64_t frames = -1) {
  const bool rigs = frames >= 0;
  if (rigs && (model != CameraModel::kPhoto || frames < 1 || frames > cameras)) {
    throw std::invalid_argument("binary problem: " + std::to_string(frames) +
                                " rig frames do not fit " + std::to_string(cameras) + " images");
  }
  const bool photo = model == CameraModel::kPhoto;
  if (photo ? (groups < 1 || groups > cameras) : (groups != 0 || free)) {
    throw std::invalid_argument("binary problem: " + std::to_string(groups) +
                                " intrinsic groups do not fit " + std::to_string(cameras) +
                                (photo ? " photogrammetric images" : " BAL cameras"));
  }
  BinaryProblemHeader h;
  h.version = rigs ? kVersion4 : v3 ? kVersion3 : photo || fixed || free ? kVersion2 : kVersion1;
  h.num_frames = frames;
  h.intrinsics_size = slots;
  h.model = model;
  h.camera_model = photo ? kPhotoModel : kBalModel;
  h.camera_size = photo ? kPhotoPoseSize : kBalCameraSize;
  h.num_cameras = cameras;
  h.num_intrinsics = groups;
  h.num_points = points;
  h.num_observations = observations;
  h.has_fixed_cameras = fixed;
  h.has_intrinsics_free = free;
  h.cameras_offset = kHeaderSize + (rigs ? kRigHeaderSize : 0);
  h.intrinsics_offset = h.cameras_offset + 8 * int64_t{h.camera_size} * cameras;
  // Version 4: the frames' and sensors' poses right after the intrinsics
  // (the rest of Problem::cameras).
  h.group_models_offset = h.intrinsics_offset + 8 * int64_t{slots} * groups +
                          (rigs ? 8 * kPhotoPoseSize * (frames + groups) : 0);
  h.image_groups_offset = Align8(h.group_models_offset + (v3 || rigs ? 2 * groups : 0));
  h.rig_offset = Align8(h.image_groups_offset + (photo ? 4 * cameras : 0));
  h.flags_offset = Align8(h.rig_offset + (rigs ? 4 * cameras + groups : 0));
  h.points_offset =
      Align8(h.flags_offset + (fixed ? cameras : 0) + (free ? (v3 ? 2 : 1) * groups : 0));
  h.point_offsets_offset = h.points_offset + 8 * kPointSize * points;
  h.obs_camera_offset = h.point_offsets_offset + 8 * (points + 1);
  h.obs_pixel_offset = Align8(h.obs_camera_offset + 4 * observations);
  h.file_size = h.obs_pixel_offset + 16 * observations;
  return h;
}

BinaryProblemHeader Layout(int64_t cameras, int64_t points, int64_t observations) {
  return Layout(CameraModel::kBal, cameras, 0, false, false, points, observations);
}

void CheckFinite(const BinaryFile& f, const std::vector<double>& v, const char* what) {
  for (size_t i = 0; i < v.size(); ++i) {
    if (!std::isfinite(v[i])) {
      throw InputError(f.path(), 0, std::string("non-finite value in ") + what + " at index " +
                                        std::to_string(i));
    }
  }
}

// Observation first_observation + i's pixel at pixels[2i, 2i+1], each in
// range (problem/pixel_range.h).
void CheckPixels(const std::string& path, std::span<const double> pixels,
                 int64_t first_observation) {
  for (size_t i = 0; i + 1 < pixels.size(); i += 2) {
    const std::string out_of_range = PixelOutOfRange(pixels[i], pixels[i + 1]);
    if (!out_of_range.empty()) {
      throw InputError(path, 0, "observation " + std::to_string(first_observation + i / 2) +
                                    ": " + out_of_range);
    }
  }
}

void CheckOffsets(const BinaryFile& f, const std::vector<int64_t>& offsets, int64_t first_point,
                  int64_t num_observations) {
  for (size_t k = 0; k + 1 < offsets.size(); ++k) {
    if (offsets[k + 1] <= offsets[k] || offsets[k + 1] > num_observations) {
      throw InputError(f.path(), 0,
                       "point offsets not increasing or past the observation count at point " +
                           std::to_string(first_point + static_cast<int64_t>(k)) +
                           " (every point needs an observation)");
    }
  }
}

void CheckCameras(const BinaryFile& f, std::span<const int32_t> cameras, int64_t num_cameras,
                  int64_t first_observation) {
  for (size_t j = 0; j < cameras.size(); ++j) {
    if (cameras[j] < 0 || cameras[j] >= num_cameras) {
      throw InputError(f.path(), 0,
                       "camera index " + std::to_string(cameras[j]) + " of observation " +
                           std::to_string(first_observation + static_cast<int64_t>(j)) +
                           " is out of range [0, " + std::to_string(num_cameras) + ")");
    }
  }
}

// The camera side of a file whose header `h` was checked: model, cameras
// (poses, then intrinsics), image groups and fixed flags, each checked.
// Version 4: each image's frame (every frame used) and each group's sensor
// kind; the rig's origin sensors hold the identity.
void ReadRigs(const BinaryFile& f, const BinaryProblemHeader& h, CameraSide* p) {
  p->image_frame = f.ReadArrayAt<int32_t>(h.rig_offset, h.num_cameras, "image frames");
  p->sensor_kind = f.ReadArrayAt<uint8_t>(h.rig_offset + 4 * h.num_cameras, h.num_intrinsics,
                                          "sensor kinds");
  std::vector<uint8_t> used(h.num_frames, 0);
  for (int64_t i = 0; i < h.num_cameras; ++i) {
    const int32_t fr = p->image_frame[i];
    if (fr < 0 || fr >= h.num_frames) {
      throw InputError(f.path(), 0, "frame " + std::to_string(fr) + " of image " +
                                        std::to_string(i) + " is out of range [0, " +
                                        std::to_string(h.num_frames) + ")");
    }
    used[fr] = 1;
  }
  for (int64_t fr = 0; fr < h.num_frames; ++fr) {
    if (!used[fr]) throw InputError(f.path(), 0, "frame " + std::to_string(fr) + " has no image");
  }
  if (const SensorTwice t = FindSensorTwice(*p); t.frame >= 0) {
    throw InputError(f.path(), 0, "frame " + std::to_string(t.frame) + ": images " +
                                      std::to_string(t.first) + " and " + std::to_string(t.second) +
                                      " are both of sensor (group) " + std::to_string(t.group) +
                                      " (a frame is one exposure: one image per sensor)");
  }
  for (int64_t g = 0; g < h.num_intrinsics; ++g) {
    const uint8_t kind = p->sensor_kind[g];
    if (kind > kSensorHeld) {
      throw InputError(f.path(), 0, "sensor kind " + std::to_string(kind) + " of group " +
                                        std::to_string(g) + " is not 0, 1 or 2");
    }
    const double* pose = p->cameras.data() + p->sensor_offset(g);
    if (kind == kRigOrigin && std::any_of(pose, pose + kPhotoPoseSize, [](double v) { return v != 0.0; })) {
      throw InputError(f.path(), 0, "group " + std::to_string(g) +
                                        " is its rig's origin but its sensor pose is not zero");
    }
  }
}

CameraSide ReadCameraSide(const BinaryFile& f, const BinaryProblemHeader& h) {
  CameraSide p;
  p.model = h.model;
  p.intrinsics_size = h.intrinsics_size;
  p.cameras = f.ReadArrayAt<double>(h.cameras_offset, h.camera_side_size(), "cameras");
  const int64_t poses = int64_t{h.camera_size} * h.num_cameras;
  for (int64_t i = 0; i < static_cast<int64_t>(p.cameras.size()); ++i) {
    if (std::isfinite(p.cameras[i])) continue;
    if (i < poses) {
      throw InputError(f.path(), 0, "non-finite value in cameras at index " + std::to_string(i));
    }
    if (i >= poses + int64_t{h.intrinsics_size} * h.num_intrinsics) {
      throw InputError(f.path(), 0, "non-finite value in the rig poses at index " + std::to_string(i));
    }
    throw InputError(f.path(), 0,
                     "non-finite value in intrinsics of group " +
                         std::to_string((i - poses) / h.intrinsics_size) + " (parameter " +
                         std::to_string((i - poses) % h.intrinsics_size) + ")");
  }
  if (h.version >= kVersion3) {
    // Per group: lens model id, parameter count.
    const std::vector<uint8_t> models =
        f.ReadArrayAt<uint8_t>(h.group_models_offset, 2 * h.num_intrinsics, "group models");
    p.group_models.resize(h.num_intrinsics);
    for (int64_t g = 0; g < h.num_intrinsics; ++g) {
      const LensModelInfo* m = FindLensModel(models[2 * g]);
      if (m == nullptr) {
        throw InputError(f.path(), 0,
                         "intrinsic group " + std::to_string(g) + ": unknown lens model id " +
                             std::to_string(models[2 * g]) + " (this dba knows " +
                             LensModelNames() + ")");
      }
      if (models[2 * g + 1] != m->num_params || m->num_params > h.intrinsics_size) {
        throw InputError(f.path(), 0,
                         "intrinsic group " + std::to_string(g) + ": " + m->name + " has " +
                             std::to_string(m->num_params) + " parameters, the file says " +
                             std::to_string(models[2 * g + 1]) + " in " +
                             std::to_string(h.intrinsics_size) + " slots per group");
      }
      p.group_models[g] = m->id;
    }
  }
  if (h.model == CameraModel::kPhoto) {
    p.camera_intrinsics = f.ReadArrayAt<int32_t>(h.image_groups_offset, h.num_cameras, "image groups");
    for (int64_t i = 0; i < h.num_cameras; ++i) {
      const int32_t g = p.camera_intrinsics[i];
      if (g < 0 || g >= h.num_intrinsics) {
        throw InputError(f.path(), 0,
                         "intrinsic group " + std::to_string(g) + " of image " +
                             std::to_string(i) + " is out of range [0, " +
                             std::to_string(h.num_intrinsics) + ")");
      }
    }
    for (int64_t g = 0; g < h.num_intrinsics; ++g) {
      const std::string out_of_range = LensValueOutOfRange(p.group_model(g), p.intrinsics(g));
      if (!out_of_range.empty()) {
        throw InputError(f.path(), 0, "intrinsic group " + std::to_string(g) + ": " + out_of_range);
      }
    }
  }
  if (h.num_frames >= 0) ReadRigs(f, h, &p);
  int64_t flags = h.flags_offset;
  if (h.has_fixed_cameras) {
    p.fixed_cameras = f.ReadArrayAt<uint8_t>(flags, h.num_cameras, "fixed cameras");
    flags += h.num_cameras;
    for (int64_t i = 0; i < h.num_cameras; ++i) {
      if (p.fixed_cameras[i] > 1) {
        throw InputError(f.path(), 0, "fixed flag " + std::to_string(p.fixed_cameras[i]) +
                                          " of camera " + std::to_string(i) + " is not 0 or 1");
      }
    }
  }
  if (h.has_intrinsics_free) {
    // The file stores the free parameters (u8 masks in version 2, u16 in
    // version 3); the problem the fixed ones.
    std::vector<uint16_t> free;
    if (h.version >= kVersion3) {
      free = f.ReadArrayAt<uint16_t>(flags, h.num_intrinsics, "free intrinsics");
    } else {
      const std::vector<uint8_t> v2 = f.ReadArrayAt<uint8_t>(flags, h.num_intrinsics, "free intrinsics");
      free.assign(v2.begin(), v2.end());
    }
    p.fixed_intrinsics.resize(h.num_intrinsics);
    for (int64_t g = 0; g < h.num_intrinsics; ++g) {
      const uint16_t all = LensModelParamMask(p.group_model(g));
      if ((free[g] & ~all) != 0) {
        throw InputError(f.path(), 0, "free-intrinsics mask " + std::to_string(free[g]) +
                                          " of group " + std::to_string(g) +
                                          " has bits beyond its " + Info(p.group_model(g)).name +
                                          " model's parameters (" + Info(p.group_model(g)).params +
                                          ")");
      }
      p.fixed_intrinsics[g] = static_cast<uint16_t>(all & ~free[g]);
    }
  }
  return p;
}

// The layout for the camera side `c` (model, cameras, image groups, flags)
// with these point counts; throws std::invalid_argument if `c` is
// inconsistent.
BinaryProblemHeader CameraSideLayout(const Problem& c, int64_t points, int64_t observations) {
  const bool photo = c.model == CameraModel::kPhoto;
  const int64_t n = c.num_images(), g = c.num_groups();
  const bool sizes_ok =
      photo ? c.intrinsics_size >= 1 && c.intrinsics_size <= kMaxIntrinsics &&
                  static_cast<int64_t>(c.cameras.size()) ==
                      kPhotoPoseSize * n + int64_t{c.intrinsics_size} * g +
                          (c.has_rigs() ? kPhotoPoseSize * (c.num_frames() + g) : 0) &&
                  (!c.has_rigs() || (static_cast<int64_t>(c.image_frame.size()) == n &&
                                     c.num_frames() >= 1)) &&
                  (c.group_models.empty() || static_cast<int64_t>(c.group_models.size()) == g)
            : c.cameras.size() % kBalCameraSize == 0 && c.camera_intrinsics.empty();
  if (!sizes_ok || (!c.fixed_cameras.empty() && static_cast<int64_t>(c.fixed_cameras.size()) != n) ||
      (!c.fixed_intrinsics.empty() && static_cast<int64_t>(c.fixed_intrinsics.size()) != g)) {
    throw std::invalid_argument(
        "BinaryProblemWriter: camera parameters, image groups and fixed flags do not agree");
  }
  // Version 3 only when version 2 cannot hold it: a model other than
  // RADIAL, or other than 5 slots per group.
  bool v3 = photo && c.intrinsics_size != kPhotoIntrinsicsSize;
  for (int64_t x = 0; photo && x < g; ++x) {
    const LensModel m = c.group_model(x);
    if (m != LensModel::kRadial) v3 = true;
    if (LensModelParams(m) > c.intrinsics_size) {
      throw std::invalid_argument("BinaryProblemWriter: group " + std::to_string(x) + "'s " +
                                  Info(m).name + " model has more parameters than " +
                                  std::to_string(c.intrinsics_size) + " slots");
    }
    if (!c.fixed_intrinsics.empty() && (c.fixed_intrinsics[x] & ~LensModelParamMask(m)) != 0) {
      throw std::invalid_argument("BinaryProblemWriter: fixed-intrinsics mask " +
                                  std::to_string(c.fixed_intrinsics[x]) + " of group " +
                                  std::to_string(x) + " has bits beyond its " + Info(m).name +
                                  " model's parameters");
    }
  }
  return Layout(c.model, n, g, !c.fixed_cameras.empty(), !c.fixed_intrinsics.empty(), points,
                observations, v3, photo ? c.intrinsics_size : kPhotoIntrinsicsSize,
                c.has_rigs() ? c.num_frames() : -1);
}

}  // namespace

bool IsBinaryProblem(const std::string& path) {
  // A .dba is read at offsets: a regular file. Opening a FIFO to look would
  // take its writer's data from the read that follows.
  struct stat st {};
  if (::stat(path.c_str(), &st) != 0 || !S_ISREG(st.st_mode)) return false;
  const int fd = ::open(path.c_str(), O_RDONLY);
  if (fd < 0) return false;
  char magic[8] = {};
  const bool ok = ::pread(fd, magic, 8, 0) == 8 && std::memcmp(magic, kMagic, 8) == 0;
  ::close(fd);
  return ok;
}

namespace {

// The camera model the header names, against its version: BAL (1, size 9)
// or, from version 2, photogrammetric (2, size 6); true for the latter.
bool PhotoModelOf(const std::string& path, const RawHeader& raw, bool v2) {
  const bool bal = raw.camera_model == kBalModel && raw.camera_size == kBalCameraSize;
  const bool photo = v2 && raw.camera_model == kPhotoModel && raw.camera_size == kPhotoPoseSize;
  if (!bal && !photo) {
    throw InputError(path, 0, "camera model " + std::to_string(raw.camera_model) + " of size " +
                                  std::to_string(raw.camera_size) +
                                  " is not supported in version " + std::to_string(raw.version) +
                                  " (expected 1, BAL, size 9" +
                                  (v2 ? "; or 2, photogrammetric, size 6)" : ")"));
  }
  return photo;
}

// Version 4's rig header: {frames, rig section offset}.
std::array<uint64_t, 2> ReadRigHeader(const std::string& path, const BinaryFile& f, int64_t size,
                                      const RawHeader& raw) {
  std::array<uint64_t, 2> rig_header{0, 0};
  if (size < kHeaderSize + kRigHeaderSize) {
    throw InputError(path, 0, "truncated: shorter than the version-4 header");
  }
  f.ReadAt(kHeaderSize, rig_header.data(), kRigHeaderSize, "the rig header");
  if (rig_header[0] < 1 || rig_header[0] > raw.counts[0]) {
    throw InputError(path, 0, "version 4 header: " + std::to_string(rig_header[0]) +
                                  " frames for " + std::to_string(raw.counts[0]) +
                                  " images (need 1 to one per image)");
  }
  return rig_header;
}

// The counts against each other and against the file's size: every camera,
// point and observation takes bytes of the file (at least 48, 32 and 20), so
// counts the file cannot hold are refused before any layout arithmetic,
// which then stays far from overflow.
void CheckHeaderCounts(const std::string& path, const RawHeader& raw, bool v2, int64_t size) {
  const uint64_t limit = uint64_t{1} << 60;
  if (raw.counts[0] == 0 || raw.counts[1] == 0 || raw.counts[2] == 0 || raw.counts[0] > (1u << 31) ||
      raw.counts[1] > limit || raw.counts[2] > limit || raw.counts[1] > raw.counts[2]) {
    throw InputError(path, 0, "implausible counts in the header");
  }
  const uint64_t bytes = static_cast<uint64_t>(std::max<int64_t>(size, 0));
  if (raw.counts[0] > bytes / 48 || raw.counts[1] > bytes / 32 || raw.counts[2] > bytes / 20 ||
      (v2 && raw.intrinsic_groups > bytes / 40)) {
    throw InputError(path, 0,
                     "the header's counts (" + std::to_string(raw.counts[0]) + " cameras, " +
                         std::to_string(raw.counts[1]) + " points, " +
                         std::to_string(raw.counts[2]) + " observations) need more than the " +
                         std::to_string(size) + " bytes of the file (corrupt header or truncated file)");
  }
}

// Versions 2 and 3's fields: the optional sections, the intrinsic groups
// and the intrinsic slots per group.
void CheckVersion2Fields(const std::string& path, const RawHeader& raw, bool v3, bool photo) {
  const int64_t cameras = static_cast<int64_t>(raw.counts[0]);
  if ((raw.optional_sections & ~(kHasFixedCameras | kHasIntrinsicsFree)) != 0 ||
      (!photo && (raw.optional_sections & kHasIntrinsicsFree) != 0)) {
    throw InputError(path, 0, "version 2/3 header: unknown optional sections " +
                                  std::to_string(raw.optional_sections) + " for camera model " +
                                  std::to_string(raw.camera_model));
  }
  if (photo ? (raw.intrinsic_groups < 1 || raw.intrinsic_groups > cameras)
            : raw.intrinsic_groups != 0) {
    throw InputError(path, 0, "version 2 header: intrinsic group count " +
                                  std::to_string(raw.intrinsic_groups) +
                                  " is inconsistent with " + std::to_string(cameras) +
                                  (photo ? " images (need 1 to one per image)"
                                         : " BAL cameras (need 0)"));
  }
  if (v3 ? !photo || raw.intrinsic_slots < 1 || raw.intrinsic_slots > kMaxIntrinsics
         : raw.intrinsic_slots != 0) {
    throw InputError(path, 0, "version " + std::to_string(raw.version) + " header: " +
                                  std::to_string(raw.intrinsic_slots) +
                                  " intrinsic slots per group (version 3: 1 to 16, "
                                  "photogrammetric model only; version 2: 0)");
  }
}

// The section table, the rig section (version 4) and the file size against
// what the counts lay out (`h`).
void CheckSectionTable(const std::string& path, const RawHeader& raw, const BinaryProblemHeader& h,
                       bool v2, const uint64_t* rig_offset, int64_t size) {
  if (rig_offset != nullptr && static_cast<int64_t>(*rig_offset) != h.rig_offset) {
    throw InputError(path, 0, "version 4 header: the rig section does not match the counts "
                              "(corrupt header)");
  }
  const int64_t sections[5] = {h.cameras_offset, h.points_offset, h.point_offsets_offset,
                               h.obs_camera_offset, h.obs_pixel_offset};
  for (int s = 0; s < 5; ++s) {
    if (static_cast<int64_t>(raw.sections[s]) != sections[s]) {
      throw InputError(path, 0, "section table does not match the counts (corrupt header)");
    }
  }
  if (v2) {  // a v2 file may hold what v1 could
    const int64_t sections2[3] = {h.intrinsics_offset, h.image_groups_offset, h.flags_offset};
    for (int s = 0; s < 3; ++s) {
      if (static_cast<int64_t>(raw.sections2[s]) != sections2[s]) {
        throw InputError(path, 0,
                         "version 2 header: intrinsics, image groups and flags sections do not "
                         "match the counts (corrupt header)");
      }
    }
  }
  if (static_cast<int64_t>(raw.file_size) != h.file_size) {
    throw InputError(path, 0, "the header's file-size field says " +
                                  std::to_string(raw.file_size) + " bytes, its counts need " +
                                  std::to_string(h.file_size) + " (corrupt header)");
  }
  if (size != h.file_size) {
    throw InputError(path, 0, "truncated or padded: the file has " + std::to_string(size) +
                                  " bytes, the header's counts need " +
                                  std::to_string(h.file_size));
  }
}

}  // namespace

BinaryProblemHeader ReadBinaryProblemHeader(const std::string& path) {
  const BinaryFile f(path);
  const int64_t size = static_cast<int64_t>(f.size());
  if (size < kHeaderSize) {
    throw InputError(path, 0, "truncated: " + std::to_string(size) +
                                  " bytes, shorter than the 128-byte header");
  }
  RawHeader raw;
  f.ReadAt(0, &raw, kHeaderSize, "the header");
  if (std::memcmp(raw.magic, kMagic, 8) != 0) {
    throw InputError(path, 0, "not a dba binary problem (bad magic)");
  }
  if (raw.byte_order != kByteOrderMark) {
    throw InputError(path, 0, "written with another byte order (big-endian?)");
  }
  if (raw.version < kVersion1 || raw.version > kVersion4) {
    throw InputError(path, 0, "format version " + std::to_string(raw.version) +
                                  ", this dba reads versions 1 to 4");
  }
  const bool v4 = raw.version == kVersion4;
  const bool v3 = raw.version == kVersion3 || v4;  // version 4 extends version 3
  const bool v2 = raw.version == kVersion2 || v3;  // version 3 extends version 2
  std::array<uint64_t, 2> rig_header{0, 0};  // frames, rig section offset
  if (v4) rig_header = ReadRigHeader(path, f, size, raw);
  const bool photo = PhotoModelOf(path, raw, v2);
  CheckHeaderCounts(path, raw, v2, size);
  if (v2) CheckVersion2Fields(path, raw, v3, photo);
  // (Version 1: the padding is not looked at, as before version 2.)
  const uint32_t optional = v2 ? raw.optional_sections : 0;
  BinaryProblemHeader h =
      Layout(photo ? CameraModel::kPhoto : CameraModel::kBal, static_cast<int64_t>(raw.counts[0]),
             v2 ? raw.intrinsic_groups : 0, (optional & kHasFixedCameras) != 0,
             (optional & kHasIntrinsicsFree) != 0,
             static_cast<int64_t>(raw.counts[1]), static_cast<int64_t>(raw.counts[2]), v3,
             v3 ? raw.intrinsic_slots : kPhotoIntrinsicsSize,
             v4 ? static_cast<int64_t>(rig_header[0]) : -1);
  h.version = raw.version;
  CheckSectionTable(path, raw, h, v2, v4 ? &rig_header[1] : nullptr, size);
  return h;
}

Problem ReadBinaryProblem(const std::string& path) {
  const BinaryProblemHeader h = ReadBinaryProblemHeader(path);
  const BinaryFile f(path);
  Problem p(ReadCameraSide(f, h));
  p.points = f.ReadArrayAt<double>(h.points_offset, kPointSize * h.num_points, "points");
  CheckFinite(f, p.points, "points");
  p.point_offsets = f.ReadArrayAt<int64_t>(h.point_offsets_offset, h.num_points + 1, "point offsets");
  if (p.point_offsets.front() != 0 || p.point_offsets.back() != h.num_observations) {
    throw InputError(path, 0, "point offsets do not span the observations");
  }
  CheckOffsets(f, p.point_offsets, 0, h.num_observations);
  p.obs_camera = f.ReadArrayAt<int32_t>(h.obs_camera_offset, h.num_observations, "observation cameras");
  CheckCameras(f, p.obs_camera, h.num_cameras, 0);
  p.obs_pixel = f.ReadArrayAt<double>(h.obs_pixel_offset, 2 * h.num_observations, "observation pixels");
  CheckPixels(path, p.obs_pixel, 0);
  return p;
}

CameraSide ReadBinaryCameraSide(const std::string& path) {
  const BinaryProblemHeader h = ReadBinaryProblemHeader(path);
  const BinaryFile f(path);
  return ReadCameraSide(f, h);
}

std::vector<double> ReadBinaryPointCoordinates(const std::string& path) {
  const BinaryProblemHeader h = ReadBinaryProblemHeader(path);
  const BinaryFile f(path);
  std::vector<double> v = f.ReadArrayAt<double>(h.points_offset, kPointSize * h.num_points, "points");
  CheckFinite(f, v, "points");
  return v;
}

void ForEachObservationChunk(
    const std::string& path, int64_t max_observations_per_chunk, bool with_pixels,
    const std::function<void(int64_t, std::span<const int64_t>, std::span<const int32_t>,
                             std::span<const double>)>& fn) {
  const BinaryProblemHeader h = ReadBinaryProblemHeader(path);
  const BinaryFile f(path);
  const int64_t points_per_read = 1 << 18;
  std::vector<int32_t> cameras;
  std::vector<double> pixels;
  for (int64_t k0 = 0; k0 < h.num_points;) {
    const int64_t n = std::min(points_per_read, h.num_points - k0);
    std::vector<int64_t> offsets =
        f.ReadArrayAt<int64_t>(h.point_offsets_offset + 8 * k0, n + 1, "point offsets");
    CheckOffsets(f, offsets, k0, h.num_observations);
    // Split the read into chunks of at most max_observations_per_chunk
    // (a single point may exceed it).
    int64_t a = 0;
    while (a < n) {
      int64_t b = a + 1;
      while (b < n && offsets[b + 1] - offsets[a] <= max_observations_per_chunk) ++b;
      const int64_t obs0 = offsets[a], obs1 = offsets[b];
      cameras.resize(obs1 - obs0);
      f.ReadAt(h.obs_camera_offset + 4 * obs0, cameras.data(), 4 * (obs1 - obs0),
             "observation cameras");
      CheckCameras(f, cameras, h.num_cameras, obs0);
      if (with_pixels) {
        pixels.resize(2 * (obs1 - obs0));
        f.ReadAt(h.obs_pixel_offset + 16 * obs0, pixels.data(), 16 * (obs1 - obs0),
               "observation pixels");
        CheckPixels(path, pixels, obs0);
      }
      fn(k0 + a, std::span<const int64_t>(offsets.data() + a, b - a + 1), cameras, pixels);
      a = b;
    }
    k0 += n;
  }
}

void ForEachVisibilityChunk(
    const std::string& path, int64_t max_observations_per_chunk,
    const std::function<void(int64_t, std::span<const int64_t>, std::span<const int32_t>)>& fn) {
  ForEachObservationChunk(path, max_observations_per_chunk, false,
                          [&](int64_t first, std::span<const int64_t> offsets,
                              std::span<const int32_t> cameras, std::span<const double>) {
                            fn(first, offsets, cameras);
                          });
}

Problem ReadBinaryPoints(const std::string& path, std::span<const int32_t> point_group,
                            int32_t group, std::vector<int64_t>* global_point) {
  const BinaryProblemHeader h = ReadBinaryProblemHeader(path);
  if (static_cast<int64_t>(point_group.size()) != h.num_points) {
    throw std::invalid_argument("ReadBinaryPoints: point_group has the wrong size");
  }
  const BinaryFile f(path);
  Problem p(ReadCameraSide(f, h));
  // Count first (offsets only), so the arrays are allocated once, exactly.
  int64_t my_points = 0, my_observations = 0;
  for (int64_t k0 = 0; k0 < h.num_points; k0 += 1 << 18) {
    const int64_t n = std::min<int64_t>(1 << 18, h.num_points - k0);
    const std::vector<int64_t> offsets =
        f.ReadArrayAt<int64_t>(h.point_offsets_offset + 8 * k0, n + 1, "point offsets");
    for (int64_t k = 0; k < n; ++k) {
      if (point_group[k0 + k] != group) continue;
      ++my_points;
      my_observations += std::max<int64_t>(0, offsets[k + 1] - offsets[k]);
    }
  }
  // (A corrupt file is refused below; cap the reservation by the header.)
  my_observations = std::min(my_observations, h.num_observations);
  p.points.reserve(kPointSize * my_points);
  p.point_offsets.reserve(my_points + 1);
  p.obs_camera.reserve(my_observations);
  p.obs_pixel.reserve(2 * my_observations);
  global_point->clear();
  global_point->reserve(my_points);
  p.point_offsets.push_back(0);
  std::vector<double> pixels, xyz;
  ForEachVisibilityChunk(
      path, int64_t{1} << 18,
      [&](int64_t first, std::span<const int64_t> offsets, std::span<const int32_t> cameras) {
        const int64_t n = static_cast<int64_t>(offsets.size()) - 1;
        bool any = false;
        for (int64_t k = 0; k < n && !any; ++k) any = point_group[first + k] == group;
        if (!any) return;
        const int64_t obs0 = offsets[0];
        xyz.resize(3 * n);
        f.ReadAt(h.points_offset + 24 * first, xyz.data(), 24 * n, "points");
        CheckFinite(f, xyz, "points");
        pixels.resize(2 * (offsets[n] - obs0));
        f.ReadAt(h.obs_pixel_offset + 16 * obs0, pixels.data(), 16 * (offsets[n] - obs0),
               "observation pixels");
        for (int64_t k = 0; k < n; ++k) {
          if (point_group[first + k] != group) continue;
          global_point->push_back(first + k);
          p.points.insert(p.points.end(), xyz.begin() + 3 * k, xyz.begin() + 3 * k + 3);
          for (int64_t o = offsets[k]; o < offsets[k + 1]; ++o) {
            p.obs_camera.push_back(cameras[o - obs0]);
            const std::span<const double> pixel(pixels.data() + 2 * (o - obs0), 2);
            CheckPixels(path, pixel, o);
            p.obs_pixel.insert(p.obs_pixel.end(), pixel.begin(), pixel.end());
          }
          p.point_offsets.push_back(p.num_observations());
        }
      });
  return p;
}

void WriteBinaryProblem(const Problem& p, const std::string& path) {
  BinaryProblemWriter writer(path, p, p.num_points(), p.num_observations());
  for (int64_t k = 0; k < p.num_points(); ++k) {
    const int64_t o0 = p.point_offsets[k], o1 = p.point_offsets[k + 1];
    writer.AppendPoint(p.point(k), std::span<const int32_t>(p.obs_camera.data() + o0, o1 - o0),
                       std::span<const double>(p.obs_pixel.data() + 2 * o0, 2 * (o1 - o0)));
  }
  writer.Commit();
}

void WriteBinaryWithNewParameters(const std::string& input, const std::string& output,
                                  const Problem& camera_side,
                                  const std::vector<double>& points) {
  const BinaryProblemHeader h = ReadBinaryProblemHeader(input);
  if (camera_side.model != h.model || camera_side.num_images() != h.num_cameras ||
      camera_side.num_groups() != h.num_intrinsics ||
      static_cast<int64_t>(camera_side.cameras.size()) != h.camera_side_size() ||
      static_cast<int64_t>(points.size()) != kPointSize * h.num_points) {
    throw std::invalid_argument("WriteBinaryWithNewParameters: model or parameter counts differ "
                                "from " + input);
  }
  // The observations were solved against the input's image groups (read and
  // checked here; small next to the observations streamed below).
  if (ReadBinaryCameraSide(input).camera_intrinsics != camera_side.camera_intrinsics) {
    throw std::invalid_argument("WriteBinaryWithNewParameters: image groups differ from " + input);
  }
  BinaryProblemWriter out(output, camera_side, h.num_points, h.num_observations);
  ForEachObservationChunk(input, 1 << 20, true,
                          [&](int64_t first, std::span<const int64_t> offsets,
                              std::span<const int32_t> c, std::span<const double> px) {
                            for (size_t k = 0; k + 1 < offsets.size(); ++k) {
                              const int64_t a = offsets[k] - offsets[0], b = offsets[k + 1] - offsets[0];
                              out.AppendPoint(points.data() + kPointSize * (first + static_cast<int64_t>(k)),
                                              c.subspan(a, b - a), px.subspan(2 * a, 2 * (b - a)));
                            }
                          });
  out.Commit();
}

BinaryProblemWriter::BinaryProblemWriter(const std::string& path, int64_t num_cameras,
                                         int64_t num_points, int64_t num_observations)
    : out_(path), h_(Layout(num_cameras, num_points, num_observations)) {
  WriteHeader();
}

BinaryProblemWriter::BinaryProblemWriter(const std::string& path, const Problem& c,
                                         int64_t num_points, int64_t num_observations)
    : out_(path), h_(CameraSideLayout(c, num_points, num_observations)) {
  WriteHeader();
  WriteCameras(c.cameras);
  const char zeros[8] = {};
  if (c.model == CameraModel::kPhoto) {
    for (int32_t g : c.camera_intrinsics) {
      if (g < 0 || g >= h_.num_intrinsics) {
        throw std::invalid_argument("BinaryProblemWriter: intrinsic group " + std::to_string(g) +
                                    " out of range [0, " + std::to_string(h_.num_intrinsics) + ")");
      }
    }
    if (h_.version >= kVersion3) {
      std::vector<uint8_t> models;
      for (int64_t g = 0; g < h_.num_intrinsics; ++g) {
        models.push_back(static_cast<uint8_t>(c.group_model(g)));
        models.push_back(static_cast<uint8_t>(LensModelParams(c.group_model(g))));
      }
      models.resize(h_.image_groups_offset - h_.group_models_offset, 0);  // zero padding
      Write(h_.group_models_offset, models.data(), static_cast<int64_t>(models.size()));
    }
    const int64_t end = h_.image_groups_offset + 4 * h_.num_cameras;
    Write(h_.image_groups_offset, c.camera_intrinsics.data(), 4 * h_.num_cameras);
    Write(end, zeros, h_.rig_offset - end);
    if (h_.num_frames >= 0) WriteRigs(c);
  }
  std::vector<uint8_t> flags;
  for (uint8_t f : c.fixed_cameras) flags.push_back(f != 0 ? 1 : 0);
  for (size_t g = 0; g < c.fixed_intrinsics.size(); ++g) {
    // The file stores the free ones (CameraSideLayout checked the masks).
    const uint16_t free =
        static_cast<uint16_t>(LensModelParamMask(c.group_model(g)) & ~c.fixed_intrinsics[g]);
    flags.push_back(static_cast<uint8_t>(free & 0xff));
    if (h_.version >= kVersion3) flags.push_back(static_cast<uint8_t>(free >> 8));
  }
  flags.resize(h_.points_offset - h_.flags_offset, 0);  // zero padding
  Write(h_.flags_offset, flags.data(), static_cast<int64_t>(flags.size()));
}

void BinaryProblemWriter::WriteRigs(const Problem& c) {
  std::vector<uint8_t> rig(4 * h_.num_cameras);
  for (int32_t fr : c.image_frame) {
    if (fr < 0 || fr >= h_.num_frames) {
      throw std::invalid_argument("BinaryProblemWriter: frame " + std::to_string(fr) +
                                  " out of range [0, " + std::to_string(h_.num_frames) + ")");
    }
  }
  if (static_cast<int64_t>(c.sensor_kind.size()) != h_.num_intrinsics) {
    throw std::invalid_argument("BinaryProblemWriter: a sensor kind per group needed");
  }
  std::memcpy(rig.data(), c.image_frame.data(), rig.size());
  rig.insert(rig.end(), c.sensor_kind.begin(), c.sensor_kind.end());
  rig.resize(h_.flags_offset - h_.rig_offset, 0);  // zero padding
  Write(h_.rig_offset, rig.data(), static_cast<int64_t>(rig.size()));
}

void BinaryProblemWriter::WriteHeader() {
  if (!out_.seekable()) {
    throw UsageError(out_.path() + ": a .dba file is written out of order and needs a regular "
                     "file, not a device or a FIFO");
  }
  RawHeader raw{};
  std::memcpy(raw.magic, kMagic, 8);
  raw.version = h_.version;
  raw.byte_order = kByteOrderMark;
  raw.camera_model = h_.camera_model;
  raw.camera_size = h_.camera_size;
  raw.counts[0] = h_.num_cameras;
  raw.counts[1] = h_.num_points;
  raw.counts[2] = h_.num_observations;
  const int64_t sections[5] = {h_.cameras_offset, h_.points_offset, h_.point_offsets_offset,
                               h_.obs_camera_offset, h_.obs_pixel_offset};
  for (int s = 0; s < 5; ++s) raw.sections[s] = sections[s];
  raw.file_size = h_.file_size;
  if (h_.version >= kVersion2) {
    raw.intrinsic_groups = static_cast<uint32_t>(h_.num_intrinsics);
    raw.optional_sections = static_cast<uint16_t>((h_.has_fixed_cameras ? kHasFixedCameras : 0) |
                                                  (h_.has_intrinsics_free ? kHasIntrinsicsFree : 0));
    if (h_.version >= kVersion3) raw.intrinsic_slots = static_cast<uint16_t>(h_.intrinsics_size);
    raw.sections2[0] = h_.intrinsics_offset;
    raw.sections2[1] = h_.image_groups_offset;
    raw.sections2[2] = h_.flags_offset;
  }
  Write(0, &raw, kHeaderSize);
  if (h_.num_frames >= 0) {
    const uint64_t rig_header[2] = {static_cast<uint64_t>(h_.num_frames),
                                    static_cast<uint64_t>(h_.rig_offset)};
    Write(kHeaderSize, rig_header, kRigHeaderSize);
  }
  offsets_.assign(1, 0);
}

void BinaryProblemWriter::Write(int64_t offset, const void* data, int64_t bytes) {
  const char* c = static_cast<const char*>(data);
  while (bytes > 0) {
    const ssize_t n =
        ::pwrite(out_.fd(), c, static_cast<size_t>(std::min<int64_t>(bytes, 1 << 30)), offset);
    if (n < 0 && errno == EINTR) continue;
    if (n <= 0) out_.Fail("write failed", errno);
    c += n;
    offset += n;
    bytes -= n;
  }
}

void BinaryProblemWriter::WriteCameras(std::span<const double> cameras) {
  if (static_cast<int64_t>(cameras.size()) != h_.camera_side_size()) {
    throw std::invalid_argument("BinaryProblemWriter: wrong number of camera parameters");
  }
  Write(h_.cameras_offset, cameras.data(), 8 * static_cast<int64_t>(cameras.size()));
  cameras_written_ = true;
}

void BinaryProblemWriter::AppendPoint(const double* xyz, std::span<const int32_t> cameras,
                                      std::span<const double> pixels) {
  const int64_t m = static_cast<int64_t>(cameras.size());
  if (m == 0 || static_cast<int64_t>(pixels.size()) != 2 * m ||
      points_ + 1 > h_.num_points || observations_ + m > h_.num_observations) {
    throw std::invalid_argument("BinaryProblemWriter: point beyond the announced counts");
  }
  for (int32_t c : cameras) {
    if (c < 0 || c >= h_.num_cameras) throw std::invalid_argument("BinaryProblemWriter: camera id out of range");
  }
  xyz_.insert(xyz_.end(), xyz, xyz + kPointSize);
  cameras_.insert(cameras_.end(), cameras.begin(), cameras.end());
  pixels_.insert(pixels_.end(), pixels.begin(), pixels.end());
  ++points_;
  observations_ += m;
  offsets_.push_back(observations_);
  if (cameras_.size() >= (size_t{1} << 18)) Flush();
}

void BinaryProblemWriter::Flush() {
  const int64_t n = points_ - flushed_points_, m = observations_ - flushed_observations_;
  Write(h_.points_offset + 24 * flushed_points_, xyz_.data(), 24 * n);
  // offsets_[0] is the start of this batch, already written with the last one.
  Write(h_.point_offsets_offset + 8 * flushed_points_, offsets_.data(), 8 * (n + 1));
  Write(h_.obs_camera_offset + 4 * flushed_observations_, cameras_.data(), 4 * m);
  Write(h_.obs_pixel_offset + 16 * flushed_observations_, pixels_.data(), 16 * m);
  flushed_points_ = points_;
  flushed_observations_ = observations_;
  xyz_.clear();
  cameras_.clear();
  pixels_.clear();
  offsets_.assign(1, observations_);
}

void BinaryProblemWriter::Commit() {
  Flush();
  if (!cameras_written_ || points_ != h_.num_points || observations_ != h_.num_observations) {
    throw std::logic_error("BinaryProblemWriter: fewer points or observations than announced");
  }
  // Padding after the observation cameras, and the exact file size.
  const int64_t pad = h_.obs_pixel_offset - (h_.obs_camera_offset + 4 * h_.num_observations);
  const char zeros[8] = {};
  if (pad > 0) Write(h_.obs_camera_offset + 4 * h_.num_observations, zeros, pad);
  if (::ftruncate(out_.fd(), h_.file_size) != 0) out_.Fail("truncate failed", errno);
  out_.Commit();
}

}  // namespace dba
