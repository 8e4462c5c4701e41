// COLMAP text models: reading and writing; see colmap_text.h.
#include "dba/io/colmap_text.h"

#include "dba/io/atomic_output_file.h"
#include "dba/io/colmap_lines_internal.h"
#include "dba/io/colmap_model_internal.h"

#include <charconv>
#include <cmath>
#include <fstream>
#include <limits>
#include <memory>
#include <unordered_map>

#include "dba/common/error.h"

namespace dba {
namespace {

using colmap_internal::JoinPath;
using colmap_internal::LineFile;
using colmap_internal::Quote;
using colmap_internal::Tokens;

constexpr uint64_t kMaxU32 = std::numeric_limits<uint32_t>::max();
constexpr uint64_t kMaxI64 = std::numeric_limits<int64_t>::max();

void ReadCameras(const std::string& path, ColmapModel* model,
                 colmap_internal::ColmapSourceLines* lines) {
  LineFile file(path);
  std::string_view line;
  while (file.NextData(&line)) {
    Tokens t(file, line);
    ColmapCamera c;
    c.camera_id = static_cast<uint32_t>(t.Unsigned("CAMERA_ID", kMaxU32));
    const std::string_view name = t.Next("MODEL");
    const ColmapCameraModelInfo* m = FindColmapCameraModel(name);
    if (m == nullptr) {
      std::string known;
      for (const auto& info : ColmapCameraModels()) {
        known += known.empty() ? "" : ", ";
        known += info.name;
      }
      file.Fail("unknown camera model " + Quote(name) + "; COLMAP's models are " + known);
    }
    c.model_id = static_cast<int32_t>(m->id);
    c.width = t.Unsigned("WIDTH", std::numeric_limits<uint64_t>::max());
    c.height = t.Unsigned("HEIGHT", std::numeric_limits<uint64_t>::max());
    c.params.reserve(m->num_params);
    while (!t.Done()) c.params.push_back(t.Double("camera parameter"));
    if (c.params.size() != static_cast<size_t>(m->num_params)) {
      file.Fail(std::string(m->name) + " has " + std::to_string(m->num_params) +
                " parameters (" + m->params + "), the line has " +
                std::to_string(c.params.size()));
    }
    model->cameras.push_back(std::move(c));
    lines->cameras.push_back(file.line_number());
  }
}

void ReadImages(const std::string& path, ColmapModel* model,
                colmap_internal::ColmapSourceLines* lines) {
  LineFile file(path);
  std::string_view line;
  while (file.NextData(&line)) {
    Tokens t(file, line);
    ColmapImage im;
    im.image_id = static_cast<uint32_t>(t.Unsigned("IMAGE_ID", kMaxU32));
    t.Pose("the image's quaternion", &im.qvec, &im.tvec);
    im.camera_id = static_cast<uint32_t>(t.Unsigned("CAMERA_ID", kMaxU32));
    im.name = std::string(t.Rest());
    if (im.name.empty()) file.Fail("expected NAME after CAMERA_ID");
    lines->images.push_back(file.line_number());

    // The POINTS2D line follows directly (it may be empty); COLMAP accepts a
    // file that ends before it, meaning no 2D points.
    if (file.Next(&line)) {
      Tokens p(file, line);
      while (!p.Done()) {
        ColmapPoint2D pt;
        pt.x = p.Double("X of a 2D point");
        pt.y = p.Double("Y of a 2D point");
        pt.point3D_id = p.Point3DRef("POINT3D_ID of a 2D point");
        im.points2D.push_back(pt);
      }
    }
    model->images.push_back(std::move(im));
  }
}

void ReadPoints3D(const std::string& path, ColmapModel* model,
                  colmap_internal::ColmapSourceLines* lines) {
  LineFile file(path);
  std::string_view line;
  while (file.NextData(&line)) {
    Tokens t(file, line);
    ColmapPoint3D p;
    p.point3D_id = static_cast<int64_t>(t.Unsigned("POINT3D_ID", kMaxI64));
    p.xyz[0] = t.Double("X");
    p.xyz[1] = t.Double("Y");
    p.xyz[2] = t.Double("Z");
    static const char* const kRgb[] = {"R", "G", "B"};
    for (int k = 0; k < 3; ++k) p.rgb[k] = static_cast<uint8_t>(t.Unsigned(kRgb[k], 255));
    p.error = t.Double("ERROR");
    while (!t.Done()) {
      ColmapTrackElement e;
      e.image_id = static_cast<uint32_t>(t.Unsigned("IMAGE_ID of a track element", kMaxU32));
      e.point2D_idx =
          static_cast<uint32_t>(t.Unsigned("POINT2D_IDX of a track element", kMaxU32));
      p.track.push_back(e);
    }
    model->points3D.push_back(std::move(p));
    lines->points3D.push_back(file.line_number());
  }
}

// ---------------------------------------------------------------------------
// Writing.

class TextOut {
 public:
  explicit TextOut(const std::string& path) : file_(path) {}
  TextOut& operator<<(std::string_view s) {
    file_.Write(s);
    return *this;
  }
  TextOut& operator<<(char c) {
    file_.Write(&c, 1);
    return *this;
  }
  TextOut& operator<<(double v) { return Number(v); }
  TextOut& operator<<(uint64_t v) { return Number(v); }
  TextOut& operator<<(int64_t v) { return Number(v); }
  TextOut& operator<<(uint32_t v) { return Number(v); }
  AtomicOutputFile& file() { return file_; }

 private:
  template <typename T>
  TextOut& Number(T v) {
    char buf[32];
    const auto [end, ec] = std::to_chars(buf, buf + sizeof buf, v);  // shortest round trip
    file_.Write(buf, static_cast<size_t>(end - buf));
    return *this;
  }
  AtomicOutputFile file_;
};

double Mean(int64_t total, size_t count) {
  return count == 0 ? 0.0 : static_cast<double>(total) / static_cast<double>(count);
}

void WriteCameras(const ColmapModel& model, TextOut& out) {
  out << "# Camera list with one line of data per camera:\n"
      << "#   CAMERA_ID, MODEL, WIDTH, HEIGHT, PARAMS[]\n"
      << "# Number of cameras: " << uint64_t{model.cameras.size()} << '\n';
  for (const ColmapCamera& c : model.cameras) {
    out << c.camera_id << ' ' << FindColmapCameraModel(c.model_id)->name << ' ' << c.width
        << ' ' << c.height;
    for (double p : c.params) out << ' ' << p;
    out << '\n';
  }
}

void WriteImages(const ColmapModel& model, TextOut& out) {
  out << "# Image list with two lines of data per image:\n"
      << "#   IMAGE_ID, QW, QX, QY, QZ, TX, TY, TZ, CAMERA_ID, NAME\n"
      << "#   POINTS2D[] as (X, Y, POINT3D_ID)\n"
      << "# Number of images: " << uint64_t{model.images.size()}
      << ", mean observations per image: "
      << Mean(model.NumPoints2DWithPoint3D(), model.images.size()) << '\n';
  for (const ColmapImage& im : model.images) {
    out << im.image_id;
    for (double q : im.qvec) out << ' ' << q;
    for (double v : im.tvec) out << ' ' << v;
    out << ' ' << im.camera_id << ' ' << std::string_view(im.name) << '\n';
    bool first = true;
    for (const ColmapPoint2D& p : im.points2D) {
      if (!first) out << ' ';
      first = false;
      out << p.x << ' ' << p.y << ' ' << p.point3D_id;
    }
    out << '\n';
  }
}

// COLMAP >= 3.12's rigs and frames, every value as held.
const char* SensorTypeName(int32_t type) { return type == 0 ? "CAMERA" : "IMU"; }

void WriteRigs(const ColmapModel& model, TextOut& out) {
  out << "# Rig calib list with one line of data per calib:\n"
      << "#   RIG_ID, NUM_SENSORS, REF_SENSOR_TYPE, REF_SENSOR_ID, SENSORS[] as (SENSOR_TYPE, "
         "SENSOR_ID, HAS_POSE, [QW, QX, QY, QZ, TX, TY, TZ])\n"
      << "# Number of rigs: " << uint64_t{model.rigs.size()} << '\n';
  for (const ColmapRig& r : model.rigs) {
    out << r.rig_id << ' ' << uint64_t{r.sensors.size() + 1} << ' ' << SensorTypeName(r.ref.type) << ' '
        << r.ref.id;
    for (const ColmapSensor& x : r.sensors) {
      out << ' ' << SensorTypeName(x.type) << ' ' << x.id << ' ' << (x.has_pose ? "1" : "0");
      if (!x.has_pose) continue;
      for (double q : x.qvec) out << ' ' << q;
      for (double v : x.tvec) out << ' ' << v;
    }
    out << '\n';
  }
}

void WriteFrames(const ColmapModel& model, TextOut& out) {
  out << "# Frame list with one line of data per frame:\n"
      << "#   FRAME_ID, RIG_ID, QW, QX, QY, QZ, TX, TY, TZ, NUM_DATA_IDS, DATA_IDS[] as "
         "(SENSOR_TYPE, SENSOR_ID, DATA_ID)\n"
      << "# Number of frames: " << uint64_t{model.frames.size()} << '\n';
  for (const ColmapFrame& f : model.frames) {
    out << f.frame_id << ' ' << f.rig_id;
    for (double q : f.qvec) out << ' ' << q;
    for (double v : f.tvec) out << ' ' << v;
    out << ' ' << uint64_t{f.data.size()};
    for (const ColmapFrameData& d : f.data) {
      out << ' ' << SensorTypeName(d.type) << ' ' << d.sensor_id << ' ' << d.data_id;
    }
    out << '\n';
  }
}

void WritePoints3D(const ColmapModel& model, TextOut& out) {
  out << "# 3D point list with one line of data per point:\n"
      << "#   POINT3D_ID, X, Y, Z, R, G, B, ERROR, TRACK[] as (IMAGE_ID, POINT2D_IDX)\n"
      << "# Number of points: " << uint64_t{model.points3D.size()}
      << ", mean track length: " << Mean(model.NumObservations(), model.points3D.size())
      << '\n';
  for (const ColmapPoint3D& p : model.points3D) {
    out << p.point3D_id << ' ' << p.xyz[0] << ' ' << p.xyz[1] << ' ' << p.xyz[2] << ' '
        << uint32_t{p.rgb[0]} << ' ' << uint32_t{p.rgb[1]} << ' ' << uint32_t{p.rgb[2]} << ' '
        << p.error;
    for (const ColmapTrackElement& e : p.track) out << ' ' << e.image_id << ' ' << e.point2D_idx;
    out << '\n';
  }
}

}  // namespace

ColmapModel ReadColmapText(const std::string& dir) {
  ColmapModel model;
  colmap_internal::ColmapSourceLines lines;
  ReadCameras(JoinPath(dir, "cameras.txt"), &model, &lines);
  ReadImages(JoinPath(dir, "images.txt"), &model, &lines);
  ReadPoints3D(JoinPath(dir, "points3D.txt"), &model, &lines);
  colmap_internal::ValidateColmapModel(model, dir, ".txt", &lines);
  return model;
}

void WriteColmapText(const ColmapModel& model, const std::string& dir) {
  colmap_internal::CheckWritable(model, true);
  colmap_internal::EnsureDirectory(dir);
  TextOut cameras(JoinPath(dir, "cameras.txt")), images(JoinPath(dir, "images.txt")),
      points(JoinPath(dir, "points3D.txt"));
  WriteCameras(model, cameras);
  WriteImages(model, images);
  WritePoints3D(model, points);
  if (!model.frames.empty() || !model.rigs.empty()) {
    TextOut rigs(JoinPath(dir, "rigs.txt")), frames(JoinPath(dir, "frames.txt"));
    WriteRigs(model, rigs);
    WriteFrames(model, frames);
    CommitTogether({&cameras.file(), &images.file(), &points.file(), &rigs.file(), &frames.file()});
    return;
  }
  // All three on disk before any replaces a file of the old model.
  CommitTogether({&cameras.file(), &images.file(), &points.file()});
}

}  // namespace dba
