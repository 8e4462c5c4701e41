// COLMAP >= 3.12's rigs and frames, text and binary; see
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
// NUM_SENSORS counts the reference sensor. Sensor type 0 (text CAMERA) is a
// camera, 1 (IMU) is not.
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
#include "dba/io/text_tokens.h"

namespace dba {
namespace colmap_internal {
namespace {

// One data line of rigs.txt or frames.txt, split at blanks, and a cursor.
struct Fields {
  std::vector<std::string> v;
  size_t at = 0;
  const std::string& path;
  int64_t line;
  const std::string& Next(const char* what) {
    if (at >= v.size()) throw InputError(path, line, std::string("too few fields: no ") + what);
    return v[at++];
  }
  uint64_t Unsigned(const char* what, uint64_t max) {
    const std::string& f = Next(what);
    uint64_t x = 0;
    const auto [end, err] = std::from_chars(f.data(), f.data() + f.size(), x);
    if (err != std::errc() || end != f.data() + f.size() || x > max) {
      throw InputError(path, line, std::string(what) + ": '" + Clipped(f) + "' is not an id");
    }
    return x;
  }
  double Double(const char* what) {
    const std::string& f = Next(what);
    double x = 0;
    if (ParseDouble(f, &x) != NumberStatus::kOk) {
      throw InputError(path, line, std::string(what) + ": '" + Clipped(f) + "' is not a finite number");
    }
    return x;
  }
  int32_t SensorType() {
    const std::string& f = Next("a sensor type");
    if (f == "CAMERA") return 0;
    if (f == "IMU") return 1;
    throw InputError(path, line, "sensor type '" + Clipped(f) + "' (COLMAP's are CAMERA and IMU)");
  }
  template <size_t N>
  void Doubles(std::array<double, N>* out, const char* what) {
    for (double& x : *out) x = Double(what);
  }
  void End() {
    if (at != v.size()) {
      throw InputError(path, line, std::to_string(v.size() - at) + " fields after the entry's last");
    }
  }
};

// Calls `take` with each data line's fields.
template <typename Take>
void ForEachDataLine(const std::string& path, Take take) {
  std::ifstream in(path);
  std::string line;
  for (int64_t n = 1; in && std::getline(in, line); ++n) {
    std::istringstream tokens(line);
    Fields f{{std::istream_iterator<std::string>(tokens), {}}, 0, path, n};
    if (!f.v.empty() && f.v[0][0] != '#') take(f);
  }
}

void ReadText(const std::string& dir, ColmapModel* model) {
  const std::string rigs = JoinPath(dir, "rigs.txt"), frames = JoinPath(dir, "frames.txt");
  ForEachDataLine(rigs, [&](Fields& f) {
    ColmapRig rig;
    rig.rig_id = static_cast<uint32_t>(f.Unsigned("RIG_ID", UINT32_MAX));
    const uint64_t n = f.Unsigned("NUM_SENSORS", 1u << 20);
    if (n == 0) throw InputError(rigs, f.line, "a rig without sensors");
    rig.ref.type = f.SensorType();
    rig.ref.id = static_cast<uint32_t>(f.Unsigned("REF_SENSOR_ID", UINT32_MAX));
    for (uint64_t k = 1; k < n; ++k) {
      ColmapSensor s;
      s.type = f.SensorType();
      s.id = static_cast<uint32_t>(f.Unsigned("SENSOR_ID", UINT32_MAX));
      s.has_pose = f.Unsigned("HAS_POSE", 1) == 1;
      if (s.has_pose) {
        f.Doubles(&s.qvec, "a sensor's quaternion");
        f.Doubles(&s.tvec, "a sensor's translation");
      }
      rig.sensors.push_back(s);
    }
    f.End();
    model->rigs.push_back(std::move(rig));
  });
  ForEachDataLine(frames, [&](Fields& f) {
    ColmapFrame frame;
    frame.frame_id = static_cast<uint32_t>(f.Unsigned("FRAME_ID", UINT32_MAX));
    frame.rig_id = static_cast<uint32_t>(f.Unsigned("RIG_ID", UINT32_MAX));
    f.Doubles(&frame.qvec, "the frame's quaternion");
    f.Doubles(&frame.tvec, "the frame's translation");
    const uint64_t n = f.Unsigned("NUM_DATA_IDS", 1u << 20);
    for (uint64_t k = 0; k < n; ++k) {
      ColmapFrameData d;
      d.type = f.SensorType();
      d.sensor_id = static_cast<uint32_t>(f.Unsigned("SENSOR_ID", UINT32_MAX));
      d.data_id = f.Unsigned("DATA_ID", UINT64_MAX);
      frame.data.push_back(d);
    }
    f.End();
    model->frames.push_back(std::move(frame));
  });
}

ColmapSensor ReadSensor(BinaryFile& in) {
  ColmapSensor s;
  s.type = in.Get<int32_t>("the sensor's type");
  if (s.type != 0 && s.type != 1) {
    in.Fail(in.Entry() + "sensor type " + std::to_string(s.type) + " (COLMAP's are 0, a camera, and 1, an IMU)");
  }
  s.id = in.Get<uint32_t>("the sensor's id");
  return s;
}

void ReadBinaryRigs(const std::string& path, ColmapModel* model) {
  BinaryFile in(path);
  const uint64_t n = in.Count("the number of rigs", 8);
  for (uint64_t i = 0; i < n; ++i) {
    in.SetEntry("rig", i);
    ColmapRig rig;
    rig.rig_id = in.Get<uint32_t>("rig_id");
    in.SetEntryId(rig.rig_id);
    const uint32_t sensors = in.Get<uint32_t>("num_sensors");
    if (sensors == 0) in.Fail(in.Entry() + "a rig without sensors");
    rig.ref = ReadSensor(in);
    for (uint32_t k = 1; k < sensors; ++k) {
      ColmapSensor s = ReadSensor(in);
      const uint8_t has_pose = in.Get<uint8_t>("has_pose");
      if (has_pose > 1) in.Fail(in.Entry() + "has_pose " + std::to_string(has_pose) + " is not 0 or 1");
      s.has_pose = has_pose == 1;
      if (s.has_pose) {
        in.Read(s.qvec.data(), sizeof s.qvec, "sensor_from_rig");
        in.Read(s.tvec.data(), sizeof s.tvec, "sensor_from_rig");
      }
      rig.sensors.push_back(s);
    }
    model->rigs.push_back(std::move(rig));
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
    in.Read(frame.qvec.data(), sizeof frame.qvec, "rig_from_world");
    in.Read(frame.tvec.data(), sizeof frame.tvec, "rig_from_world");
    const uint32_t data = in.Get<uint32_t>("num_data_ids");
    for (uint32_t k = 0; k < data; ++k) {
      const ColmapSensor s = ReadSensor(in);
      frame.data.push_back({s.type, s.id, in.Get<uint64_t>("the data id")});
    }
    model->frames.push_back(std::move(frame));
  }
  in.ExpectEnd("the last frame");
}

}  // namespace

void ReadRigsAndFrames(const std::string& dir, bool binary, ColmapModel* model) {
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
