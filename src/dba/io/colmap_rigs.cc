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
#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "dba/common/error.h"
#include "dba/io/binary_file.h"
#include "dba/io/colmap_lines_internal.h"
#include "dba/io/colmap_model_internal.h"

namespace dba {
namespace colmap_internal {
namespace {

constexpr uint64_t kMaxU32 = UINT32_MAX;

int32_t SensorType(Tokens& t) {
  const std::string_view f = t.Next("a sensor type");
  if (f == "CAMERA") return 0;
  if (f == "IMU") return 1;
  t.Fail("sensor type " + Quote(f) + " (COLMAP's are CAMERA and IMU)");
}

void ReadRigsText(const std::string& path, ColmapModel* model) {
  LineFile file(path);
  std::string_view line;
  while (file.NextData(&line)) {
    Tokens t(file, line);
    ColmapRig rig;
    rig.rig_id = static_cast<uint32_t>(t.Unsigned("RIG_ID", kMaxU32));
    const uint64_t n = t.Unsigned("NUM_SENSORS", 1u << 20);
    if (n == 0) file.Fail("a rig without sensors");
    rig.ref.type = SensorType(t);
    rig.ref.id = static_cast<uint32_t>(t.Unsigned("REF_SENSOR_ID", kMaxU32));
    for (uint64_t k = 1; k < n; ++k) {
      ColmapSensor s;
      s.type = SensorType(t);
      s.id = static_cast<uint32_t>(t.Unsigned("SENSOR_ID", kMaxU32));
      s.has_pose = t.Unsigned("HAS_POSE", 1) == 1;
      if (s.has_pose) t.Pose("the sensor's quaternion", &s.qvec, &s.tvec);
      rig.sensors.push_back(s);
    }
    t.End();
    model->rigs.push_back(std::move(rig));
  }
}

void ReadFramesText(const std::string& path, ColmapModel* model) {
  LineFile file(path);
  std::string_view line;
  while (file.NextData(&line)) {
    Tokens t(file, line);
    ColmapFrame frame;
    frame.frame_id = static_cast<uint32_t>(t.Unsigned("FRAME_ID", kMaxU32));
    frame.rig_id = static_cast<uint32_t>(t.Unsigned("RIG_ID", kMaxU32));
    t.Pose("the frame's quaternion", &frame.qvec, &frame.tvec);
    const uint64_t n = t.Unsigned("NUM_DATA_IDS", 1u << 20);
    for (uint64_t k = 0; k < n; ++k) {
      ColmapFrameData d;
      d.type = SensorType(t);
      d.sensor_id = static_cast<uint32_t>(t.Unsigned("SENSOR_ID", kMaxU32));
      d.data_id = t.Unsigned("DATA_ID", UINT64_MAX);
      frame.data.push_back(d);
    }
    t.End();
    model->frames.push_back(std::move(frame));
  }
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

// A pose of rigs.bin or frames.bin (7 f64): the quaternion a rotation
// (IsRotationQuaternion), the translation finite.
void ReadBinaryPose(BinaryFile& in, const char* what, std::array<double, 4>* q,
                    std::array<double, 3>* t) {
  in.Read(q->data(), sizeof *q, what);
  if (!IsRotationQuaternion(*q)) in.Fail(in.Entry() + what + "'s quaternion" + kNotARotation);
  in.Read(t->data(), sizeof *t, what);
  if (!std::all_of(t->begin(), t->end(), [](double v) { return std::isfinite(v); })) {
    in.Fail(in.Entry() + what + "'s translation is not finite");
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
    const uint32_t sensors = in.Get<uint32_t>("num_sensors");
    if (sensors == 0) in.Fail(in.Entry() + "a rig without sensors");
    rig.ref = ReadSensor(in);
    for (uint32_t k = 1; k < sensors; ++k) {
      ColmapSensor s = ReadSensor(in);
      const uint8_t has_pose = in.Get<uint8_t>("has_pose");
      if (has_pose > 1) in.Fail(in.Entry() + "has_pose " + std::to_string(has_pose) + " is not 0 or 1");
      s.has_pose = has_pose == 1;
      if (s.has_pose) ReadBinaryPose(in, "sensor_from_rig", &s.qvec, &s.tvec);
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
    ReadBinaryPose(in, "rig_from_world", &frame.qvec, &frame.tvec);
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
  if (!binary) {
    ReadRigsText(rigs, model);
    return ReadFramesText(frames, model);
  }
  ReadBinaryRigs(rigs, model);
  ReadBinaryFrames(frames, model);
}

}  // namespace colmap_internal
}  // namespace dba
