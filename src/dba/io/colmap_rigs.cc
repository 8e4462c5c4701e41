// COLMAP >= 3.12's trivial rigs and frames, text and binary; see
// colmap_model_internal.h. The layouts are COLMAP's (its
// reconstruction_io_text.cc and reconstruction_io_binary.cc):
//   rigs.txt    RIG_ID NUM_SENSORS REF_SENSOR_TYPE REF_SENSOR_ID [SENSOR_TYPE
//               SENSOR_ID HAS_POSE [QW QX QY QZ TX TY TZ]]...
//   frames.txt  FRAME_ID RIG_ID QW QX QY QZ TX TY TZ NUM_DATA_IDS [SENSOR_TYPE
//               SENSOR_ID DATA_ID]...
//   rigs.bin    u64 count; per rig: u32 rig_id, u32 num_sensors, then the
//               reference sensor (i32 type, u32 id), then per other sensor
//               i32 type, u32 id, u8 has_pose [7 f64]
//   frames.bin  u64 count; per frame: u32 frame_id, u32 rig_id, 7 f64
//               rig_from_world, u32 num_data_ids, per data i32 sensor type,
//               u32 sensor id, u64 data id (the image id)
// Sensor type 0 (text CAMERA) is a camera; 1 (IMU) is not.
#include <charconv>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <sstream>
#include <string>
#include <vector>

#include "dba/common/error.h"
#include "dba/io/binary_file.h"
#include "dba/io/colmap_model_internal.h"

namespace dba {
namespace colmap_internal {
namespace {

constexpr int32_t kCameraSensor = 0;

// One data line of rigs.txt or frames.txt, split at blanks.
using Fields = std::vector<std::string>;

uint32_t Id(const std::string& path, int64_t line, const std::string& field) {
  uint32_t x = 0;
  const auto [end, err] = std::from_chars(field.data(), field.data() + field.size(), x);
  if (err != std::errc() || end != field.data() + field.size()) {
    throw InputError(path, line, "'" + Clipped(field) + "' is not an id");
  }
  return x;
}

// Calls `take` with each data line's fields and its line number.
template <typename Take>
void ForEachDataLine(const std::string& path, Take take) {
  std::ifstream in(path);
  std::string line;
  for (int64_t n = 1; in && std::getline(in, line); ++n) {
    std::istringstream tokens(line);
    const Fields v{std::istream_iterator<std::string>(tokens), {}};
    if (!v.empty() && v[0][0] != '#') take(v, n);
  }
}

// `count` (rigs' sensors or frames' data) must be 1, of a camera.
void RequireOne(const std::string& path, int64_t line, const std::string& count, bool camera,
                const char* what) {
  if (count != "1") {
    throw InputError(path, line, count + " " + what +
                                     " is not modelled yet (one camera per rig, one image per frame)");
  }
  if (!camera) throw InputError(path, line, "a sensor that is not a camera is not modelled yet");
}

void ReadText(const std::string& dir, ColmapModel* model) {
  const std::string rigs = JoinPath(dir, "rigs.txt"), frames = JoinPath(dir, "frames.txt");
  ForEachDataLine(rigs, [&](const Fields& v, int64_t n) {
    if (v.size() < 2) throw InputError(rigs, n, "too few fields");
    RequireOne(rigs, n, v[1], v.size() < 3 || v[2] == "CAMERA", "sensors: a rig of several cameras");
    if (v.size() != 4) throw InputError(rigs, n, "expected 4 fields, a camera's");
    model->rigs.push_back({Id(rigs, n, v[0]), Id(rigs, n, v[3])});
  });
  ForEachDataLine(frames, [&](const Fields& v, int64_t n) {
    if (v.size() < 10) throw InputError(frames, n, "too few fields");
    RequireOne(frames, n, v[9], v.size() < 11 || v[10] == "CAMERA", "images: a frame of several images");
    if (v.size() != 13) throw InputError(frames, n, "expected 13 fields, a camera's");
    model->frames.push_back({Id(frames, n, v[0]), Id(frames, n, v[1]), Id(frames, n, v[11]),
                             Id(frames, n, v[12])});
  });
}

// A count (a rig's sensors, a frame's data) that must be 1, then the sensor
// type that must be a camera's; `what` names what else the count would mean.
void ReadOneCamera(BinaryFile& in, const char* count_name, const char* what) {
  const uint32_t count = in.Get<uint32_t>(count_name);
  if (count != 1) {
    in.Fail(in.Entry() + std::to_string(count) + " " + what +
            " is not modelled yet (one camera per rig, one image per frame)");
  }
  if (in.Get<int32_t>("the sensor's type") != kCameraSensor) {
    in.Fail(in.Entry() + "a sensor that is not a camera is not modelled yet");
  }
}

void ReadBinaryRigs(const std::string& path, ColmapModel* model) {
  BinaryFile in(path);
  const uint64_t n = in.Count("the number of rigs", 8);
  for (uint64_t i = 0; i < n; ++i) {
    in.SetEntry("rig", i);
    ColmapRig rig;
    rig.rig_id = in.Get<uint32_t>("rig_id");
    in.SetEntryId(rig.rig_id);
    ReadOneCamera(in, "num_sensors", "sensors: a rig of several cameras (or none)");
    rig.camera_id = in.Get<uint32_t>("the reference sensor's id");
    model->rigs.push_back(rig);
  }
  in.ExpectEnd("the last rig");
}

void ReadBinaryFrames(const std::string& path, ColmapModel* model) {
  BinaryFile in(path);
  const uint64_t n = in.Count("the number of frames", 4 + 4 + 56 + 4);
  for (uint64_t i = 0; i < n; ++i) {
    in.SetEntry("frame", i);
    ColmapFrame frame;
    frame.frame_id = in.Get<uint32_t>("frame_id");
    in.SetEntryId(frame.frame_id);
    frame.rig_id = in.Get<uint32_t>("rig_id");
    double pose[7];
    in.Read(pose, sizeof pose, "rig_from_world");  // the image's (one image per frame)
    ReadOneCamera(in, "num_data_ids", "images: a frame of several images (or none)");
    frame.camera_id = in.Get<uint32_t>("the sensor's id");
    const uint64_t image = in.Get<uint64_t>("the image id");
    if (image > UINT32_MAX) in.Fail(in.Entry() + "image id " + std::to_string(image) + " is beyond 32 bits");
    frame.image_id = static_cast<uint32_t>(image);
    model->frames.push_back(frame);
  }
  in.ExpectEnd("the last frame");
}

}  // namespace

void ReadTrivialRigsAndFrames(const std::string& dir, bool binary, ColmapModel* model) {
  std::error_code ec;
  const std::string ext = binary ? ".bin" : ".txt";
  const std::string rigs = JoinPath(dir, "rigs" + ext), frames = JoinPath(dir, "frames" + ext);
  const bool have_rigs = std::filesystem::exists(rigs, ec);
  if (have_rigs != std::filesystem::exists(frames, ec)) {
    throw InputError(have_rigs ? frames : rigs, 0,
                     "missing: COLMAP >= 3.12 writes rigs and frames together");
  }
  if (!have_rigs) return;
  if (!binary) return ReadText(dir, model);
  ReadBinaryRigs(rigs, model);
  ReadBinaryFrames(frames, model);
}

}  // namespace colmap_internal
}  // namespace dba
