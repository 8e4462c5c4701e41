// Solve checkpoints; see checkpoint.h.
#include "dba/io/checkpoint.h"

#include <chrono>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <utility>

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

uint64_t CameraSideFingerprint(const Problem& side, int64_t num_points) {
  Fnv f;
  const int32_t model = static_cast<int32_t>(side.model);
  f.Add(&model, sizeof model);
  const int64_t sizes[2] = {static_cast<int64_t>(side.cameras.size()), kPointSize * num_points};
  f.Add(sizes, sizeof sizes);
  f.AddVector(side.camera_intrinsics);
  f.AddVector(side.fixed_cameras);
  f.AddVector(side.fixed_intrinsics);
  // The lens models (only when a problem has them, so fingerprints of the
  // paper's RADIAL-only problems stay what earlier versions wrote).
  if (!side.group_models.empty() || side.intrinsics_size != kPhotoIntrinsicsSize) {
    f.Add(&side.intrinsics_size, sizeof side.intrinsics_size);
    f.AddVector(side.group_models);
  }
  return f.h;
}

uint64_t ObservationsFingerprint(const Problem& problem, std::span<const int64_t> global_point,
                                 std::span<const int32_t> global_camera) {
  uint64_t sum = 0;
  for (int64_t k = 0; k < problem.num_points(); ++k) {
    Fnv f;
    const int64_t id = global_point.empty() ? k : global_point[k];
    f.Add(&id, sizeof id);
    for (int64_t o = problem.point_offsets[k]; o < problem.point_offsets[k + 1]; ++o) {
      const int32_t c = global_camera.empty() ? problem.obs_camera[o] : global_camera[problem.obs_camera[o]];
      f.Add(&c, sizeof c);
      f.Add(&problem.obs_pixel[2 * o], 2 * sizeof(double));
    }
    sum += f.h;  // mod 2^64: the same for any split of the points
  }
  return sum;
}

uint64_t CombineFingerprints(uint64_t camera_side, uint64_t observations) {
  Fnv f;
  f.h = camera_side;
  f.Add(&observations, sizeof observations);
  return f.h;
}

uint64_t ProblemFingerprint(const Problem& problem) {
  return CombineFingerprints(CameraSideFingerprint(problem, problem.num_points()),
                             ObservationsFingerprint(problem, {}, {}));
}

void WriteCheckpoint(const std::string& path, const Checkpoint& c) {
  WriteCheckpoint(path, c, c.cameras, c.points);
}

void WriteCheckpoint(const std::string& path, const Checkpoint& c, std::span<const double> cameras,
                     std::span<const double> points) {
  AtomicOutputFile out(path);
  out.Write(kMagic, sizeof kMagic);
  const int64_t counts[2] = {c.iterations, c.accepted};
  const double state[2] = {c.lambda, c.cost};
  const int64_t sizes[2] = {static_cast<int64_t>(cameras.size()),
                            static_cast<int64_t>(points.size())};
  out.Write(&c.fingerprint, sizeof c.fingerprint);
  out.Write(counts, sizeof counts);
  out.Write(state, sizeof state);
  out.Write(sizes, sizeof sizes);
  out.Write(cameras.data(), cameras.size() * sizeof(double));
  out.Write(points.data(), points.size() * sizeof(double));
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

void CheckCheckpointFits(const Checkpoint& c, const std::string& path, uint64_t fingerprint,
                         size_t camera_values, size_t point_values) {
  if (c.fingerprint != fingerprint || c.cameras.size() != camera_values ||
      c.points.size() != point_values) {
    throw InputError(path, 0,
                     "written for another input (or other --fix-images, --fix-intrinsics, "
                     "--intrinsics): its observations or fixings differ from this one's");
  }
}

void ApplyCheckpoint(Checkpoint&& c, const std::string& path, Problem* problem) {
  CheckCheckpointFits(c, path, ProblemFingerprint(*problem), problem->cameras.size(),
                      problem->points.size());
  problem->cameras = std::exchange(c.cameras, {});
  problem->points = std::exchange(c.points, {});
}

namespace {
double SteadySeconds() {
  return std::chrono::duration<double>(std::chrono::steady_clock::now().time_since_epoch()).count();
}
}  // namespace

CheckpointWriter::CheckpointWriter(std::string path, double every_s, uint64_t fingerprint,
                                   int64_t accepted_done)
    : path_(std::move(path)), every_s_(every_s), fingerprint_(fingerprint), accepted_(accepted_done) {}

bool CheckpointWriter::Due(bool step_accepted) {
  if (!step_accepted) return false;
  ++accepted_;
  return !written_ || SteadySeconds() - last_write_ >= every_s_;
}

void CheckpointWriter::Write(int64_t iteration, double next_lambda, double cost,
                             const std::vector<double>& cameras, const std::vector<double>& points) {
  // From where the parameters are: a copy of the points (2 GB at 1M) would
  // sit beside S and the candidate points' buffer.
  WriteCheckpoint(path_, {fingerprint_, iteration, accepted_, next_lambda, cost, {}, {}}, cameras,
                  points);
  written_ = true;
  last_write_ = SteadySeconds();
  if (const char* k = std::getenv("DBA_KILL_AFTER_CHECKPOINT");
      k != nullptr && std::atoll(k) == iteration) {
    std::raise(SIGKILL);
  }
}

}  // namespace dba
