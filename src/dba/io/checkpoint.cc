// Solve checkpoints; see checkpoint.h.
#include "dba/io/checkpoint.h"

#include <cstring>

#include "dba/common/error.h"
#include "dba/io/atomic_output_file.h"
#include "dba/io/binary_file.h"

namespace dba {
namespace {

constexpr char kMagic[8] = {'D', 'B', 'A', 'C', 'K', 'P', 'T', '1'};

// FNV-1a, 64 bits, over raw bytes.
struct Fnv {
  uint64_t h = 1469598103934665603ull;
  void Add(const void* data, size_t n) {
    const auto* p = static_cast<const unsigned char*>(data);
    for (size_t i = 0; i < n; ++i) h = (h ^ p[i]) * 1099511628211ull;
  }
  template <class T>
  void AddVector(const std::vector<T>& v) {
    const uint64_t n = v.size();
    Add(&n, sizeof n);
    Add(v.data(), v.size() * sizeof(T));
  }
};

}  // namespace

uint64_t ProblemFingerprint(const Problem& problem) {
  Fnv f;
  const int32_t model = static_cast<int32_t>(problem.model);
  f.Add(&model, sizeof model);
  const int64_t sizes[2] = {static_cast<int64_t>(problem.cameras.size()),
                            static_cast<int64_t>(problem.points.size())};
  f.Add(sizes, sizeof sizes);
  f.AddVector(problem.camera_intrinsics);
  f.AddVector(problem.fixed_cameras);
  f.AddVector(problem.fixed_intrinsics);
  f.AddVector(problem.point_offsets);
  f.AddVector(problem.obs_camera);
  f.AddVector(problem.obs_pixel);
  return f.h;
}

void WriteCheckpoint(const std::string& path, const Checkpoint& c) {
  AtomicOutputFile out(path);
  out.Write(kMagic, sizeof kMagic);
  const int64_t counts[2] = {c.iterations, c.accepted};
  const double state[2] = {c.lambda, c.cost};
  const int64_t sizes[2] = {static_cast<int64_t>(c.cameras.size()),
                            static_cast<int64_t>(c.points.size())};
  out.Write(&c.fingerprint, sizeof c.fingerprint);
  out.Write(counts, sizeof counts);
  out.Write(state, sizeof state);
  out.Write(sizes, sizeof sizes);
  out.Write(c.cameras.data(), c.cameras.size() * sizeof(double));
  out.Write(c.points.data(), c.points.size() * sizeof(double));
  out.Commit();
}

Checkpoint ReadCheckpoint(const std::string& path) {
  BinaryFile in(path);
  char magic[8];
  in.Read(magic, sizeof magic, "magic");
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) {
    throw InputError(path, 0, "not a dba checkpoint (no DBACKPT1 at its start)");
  }
  Checkpoint c;
  c.fingerprint = in.Get<uint64_t>("input fingerprint");
  c.iterations = in.Get<int64_t>("iterations");
  c.accepted = in.Get<int64_t>("accepted iterations");
  c.lambda = in.Get<double>("lambda");
  c.cost = in.Get<double>("cost");
  const uint64_t cameras = in.Count("camera values", sizeof(double));
  const uint64_t points = in.Count("point values", sizeof(double));
  if (cameras + points > in.remaining() / sizeof(double)) {
    throw InputError(path, 0, "truncated: its counts need " +
                                  std::to_string((cameras + points) * sizeof(double)) +
                                  " bytes of parameters, " + std::to_string(in.remaining()) +
                                  " are left");
  }
  c.cameras.resize(cameras);
  c.points.resize(points);
  in.Read(c.cameras.data(), cameras * sizeof(double), "camera values");
  in.Read(c.points.data(), points * sizeof(double), "point values");
  if (in.remaining() != 0) {
    throw InputError(path, 0, std::to_string(in.remaining()) + " bytes after the point values");
  }
  if (c.iterations < 0 || c.accepted < 0 || c.accepted > c.iterations || !(c.lambda > 0.0)) {
    throw InputError(path, 0, "its LM state is not one dba writes (iterations " +
                                  std::to_string(c.iterations) + ", accepted " +
                                  std::to_string(c.accepted) + ")");
  }
  return c;
}

void ApplyCheckpoint(const Checkpoint& c, const std::string& path, Problem* problem) {
  if (c.fingerprint != ProblemFingerprint(*problem) || c.cameras.size() != problem->cameras.size() ||
      c.points.size() != problem->points.size()) {
    throw InputError(path, 0,
                     "written for another input (or other --fix-images, --fix-intrinsics, "
                     "--intrinsics): its observations or fixings differ from this one's");
  }
  problem->cameras = c.cameras;
  problem->points = c.points;
}

}  // namespace dba
