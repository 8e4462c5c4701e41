// COLMAP binary models: reading and writing; see colmap_binary.h.
#include "dba/io/colmap_binary.h"

#include <bit>
#include <cstdio>
#include <cstring>
#include <limits>
#include <memory>
#include <string_view>
#include <unordered_map>

#include "dba/common/error.h"
#include "dba/io/atomic_output_file.h"
#include "dba/io/colmap_model_internal.h"
#include "dba/io/binary_file.h"

namespace dba {
namespace {

using colmap_internal::JoinPath;

constexpr uint64_t kInvalidPoint3D = std::numeric_limits<uint64_t>::max();

void ReadCameras(const std::string& path, ColmapModel* model) {
  BinaryFile in(path);
  const uint64_t n = in.Count("the number of cameras", 24);
  model->cameras.resize(n);
  for (uint64_t i = 0; i < n; ++i) {
    ColmapCamera& c = model->cameras[i];
    in.SetEntry("camera", i);
    c.camera_id = in.Get<uint32_t>("camera_id");
    in.SetEntryId(c.camera_id);
    const uint64_t model_at = in.offset();
    c.model_id = in.Get<int32_t>("model_id");
    const ColmapCameraModelInfo* m = FindColmapCameraModel(c.model_id);
    if (m == nullptr) {
      throw InputError(path, 0,
                       "at byte " + std::to_string(model_at) + ": " + in.Entry() +
                           "unknown camera model id " + std::to_string(c.model_id) +
                           " (COLMAP's ids are 0 to " +
                           std::to_string(ColmapCameraModels().size() - 1) + ")");
    }
    c.width = in.Get<uint64_t>("width");
    c.height = in.Get<uint64_t>("height");
    c.params.resize(m->num_params);
    const std::string what = std::string(m->name) + " parameters (" + m->params + ")";
    in.Read(c.params.data(), sizeof(double) * c.params.size(), what.c_str());
  }
  in.ExpectEnd("the last camera");
}

void ReadImages(const std::string& path, ColmapModel* model) {
  BinaryFile in(path);
  // Smallest image: id, qvec, tvec, camera_id, name NUL, point count.
  const uint64_t n = in.Count("the number of images", 4 + 56 + 4 + 1 + 8);
  model->images.resize(n);
  for (uint64_t i = 0; i < n; ++i) {
    ColmapImage& im = model->images[i];
    in.SetEntry("image", i);
    im.image_id = in.Get<uint32_t>("image_id");
    in.SetEntryId(im.image_id);
    in.Read(im.qvec.data(), sizeof im.qvec, "qvec");
    in.Read(im.tvec.data(), sizeof im.tvec, "tvec");
    im.camera_id = in.Get<uint32_t>("camera_id");
    im.name = in.String("name");
    const uint64_t np = in.Count("number of 2D points", 24);
    im.points2D.resize(np);
    for (uint64_t k = 0; k < np; ++k) {
      unsigned char raw[24];
      in.Read(raw, sizeof raw, "2D points");
      ColmapPoint2D& p = im.points2D[k];
      uint64_t id;
      std::memcpy(&p.x, raw, 8);
      std::memcpy(&p.y, raw + 8, 8);
      std::memcpy(&id, raw + 16, 8);
      if (id == kInvalidPoint3D) {
        p.point3D_id = kColmapNoPoint3D;
      } else if (id > static_cast<uint64_t>(std::numeric_limits<int64_t>::max())) {
        in.Fail(in.Entry() + "2D point " + std::to_string(k) + ": point3D_id " +
                std::to_string(id) + " is out of range");
      } else {
        p.point3D_id = static_cast<int64_t>(id);
      }
    }
  }
  in.ExpectEnd("the last image");
}

void ReadPoints3D(const std::string& path, ColmapModel* model) {
  BinaryFile in(path);
  // Smallest point: id, xyz, rgb, error, track length.
  const uint64_t n = in.Count("the number of points", 8 + 24 + 3 + 8 + 8);
  model->points3D.resize(n);
  for (uint64_t i = 0; i < n; ++i) {
    ColmapPoint3D& p = model->points3D[i];
    in.SetEntry("point3D", i);
    const uint64_t id = in.Get<uint64_t>("point3D_id");
    if (id > static_cast<uint64_t>(std::numeric_limits<int64_t>::max())) {
      in.Fail(in.Entry() + "point3D_id " + std::to_string(id) + " is out of range");
    }
    p.point3D_id = static_cast<int64_t>(id);
    in.SetEntryId(id);
    in.Read(p.xyz.data(), sizeof p.xyz, "xyz");
    in.Read(p.rgb.data(), sizeof p.rgb, "rgb");
    p.error = in.Get<double>("error");
    const uint64_t nt = in.Count("track length", 8);
    p.track.resize(nt);
    static_assert(sizeof(ColmapTrackElement) == 8);
    in.Read(p.track.data(), 8 * nt, "track");
  }
  in.ExpectEnd("the last point");
}

// Little-endian values into an output file.
class BinaryOut {
 public:
  explicit BinaryOut(const std::string& path) : file_(path) {}
  template <typename T>
  void Put(T v) {
    file_.Write(&v, sizeof v);
  }
  void Bytes(const void* p, size_t n) { file_.Write(p, n); }
  AtomicOutputFile& file() { return file_; }

 private:
  AtomicOutputFile file_;
};

void WriteCameras(const ColmapModel& model, BinaryOut& out) {
  out.Put<uint64_t>(model.cameras.size());
  for (const ColmapCamera& c : model.cameras) {
    out.Put<uint32_t>(c.camera_id);
    out.Put<int32_t>(c.model_id);
    out.Put<uint64_t>(c.width);
    out.Put<uint64_t>(c.height);
    out.Bytes(c.params.data(), sizeof(double) * c.params.size());
  }
}

void WriteImages(const ColmapModel& model, BinaryOut& out) {
  out.Put<uint64_t>(model.images.size());
  for (const ColmapImage& im : model.images) {
    out.Put<uint32_t>(im.image_id);
    out.Bytes(im.qvec.data(), sizeof im.qvec);
    out.Bytes(im.tvec.data(), sizeof im.tvec);
    out.Put<uint32_t>(im.camera_id);
    out.Bytes(im.name.c_str(), im.name.size() + 1);
    out.Put<uint64_t>(im.points2D.size());
    for (const ColmapPoint2D& p : im.points2D) {
      unsigned char raw[24];
      const uint64_t id = p.point3D_id == kColmapNoPoint3D
                              ? kInvalidPoint3D
                              : static_cast<uint64_t>(p.point3D_id);
      std::memcpy(raw, &p.x, 8);
      std::memcpy(raw + 8, &p.y, 8);
      std::memcpy(raw + 16, &id, 8);
      out.Bytes(raw, sizeof raw);
    }
  }
}

void WritePoints3D(const ColmapModel& model, BinaryOut& out) {
  out.Put<uint64_t>(model.points3D.size());
  for (const ColmapPoint3D& p : model.points3D) {
    out.Put<uint64_t>(static_cast<uint64_t>(p.point3D_id));
    out.Bytes(p.xyz.data(), sizeof p.xyz);
    out.Bytes(p.rgb.data(), sizeof p.rgb);
    out.Put<double>(p.error);
    out.Put<uint64_t>(p.track.size());
    out.Bytes(p.track.data(), 8 * p.track.size());
  }
}

void WriteRigs(const ColmapModel& model, BinaryOut& out) {
  out.Put<uint64_t>(model.rigs.size());
  for (const ColmapRig& r : model.rigs) {
    out.Put<uint32_t>(r.rig_id);
    out.Put<uint32_t>(static_cast<uint32_t>(r.sensors.size() + 1));
    out.Put<int32_t>(r.ref.type);
    out.Put<uint32_t>(r.ref.id);
    for (const ColmapSensor& x : r.sensors) {
      out.Put<int32_t>(x.type);
      out.Put<uint32_t>(x.id);
      out.Put<uint8_t>(x.has_pose ? 1 : 0);
      if (!x.has_pose) continue;
      out.Bytes(x.qvec.data(), sizeof x.qvec);
      out.Bytes(x.tvec.data(), sizeof x.tvec);
    }
  }
}

void WriteFrames(const ColmapModel& model, BinaryOut& out) {
  out.Put<uint64_t>(model.frames.size());
  for (const ColmapFrame& f : model.frames) {
    out.Put<uint32_t>(f.frame_id);
    out.Put<uint32_t>(f.rig_id);
    out.Bytes(f.qvec.data(), sizeof f.qvec);
    out.Bytes(f.tvec.data(), sizeof f.tvec);
    out.Put<uint32_t>(static_cast<uint32_t>(f.data.size()));
    for (const ColmapFrameData& d : f.data) {
      out.Put<int32_t>(d.type);
      out.Put<uint32_t>(d.sensor_id);
      out.Put<uint64_t>(d.data_id);
    }
  }
}

}  // namespace

ColmapModel ReadColmapBinary(const std::string& dir) {
  ColmapModel model;
  ReadCameras(JoinPath(dir, "cameras.bin"), &model);
  ReadImages(JoinPath(dir, "images.bin"), &model);
  ReadPoints3D(JoinPath(dir, "points3D.bin"), &model);
  colmap_internal::ValidateColmapModel(model, dir, ".bin", nullptr);
  return model;
}

void WriteColmapBinary(const ColmapModel& model, const std::string& dir) {
  colmap_internal::CheckWritable(model, false);
  colmap_internal::EnsureDirectory(dir);
  BinaryOut cameras(JoinPath(dir, "cameras.bin")), images(JoinPath(dir, "images.bin")),
      points(JoinPath(dir, "points3D.bin"));
  WriteCameras(model, cameras);
  WriteImages(model, images);
  WritePoints3D(model, points);
  if (!model.frames.empty() || !model.rigs.empty()) {
    BinaryOut rigs(JoinPath(dir, "rigs.bin")), frames(JoinPath(dir, "frames.bin"));
    WriteRigs(model, rigs);
    WriteFrames(model, frames);
    CommitTogether({&cameras.file(), &images.file(), &points.file(), &rigs.file(), &frames.file()});
    return;
  }
  // All three on disk before any replaces a file of the old model.
  CommitTogether({&cameras.file(), &images.file(), &points.file()});
}

}  // namespace dba
