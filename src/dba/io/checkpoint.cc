// Solve checkpoints; see checkpoint.h.
#include "dba/io/checkpoint.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <utility>

#include "dba/common/error.h"
#include "dba/io/atomic_output_file.h"
#include "dba/io/binary_file.h"

// xxHash (Debian libxxhash-dev) inlined: nothing to link, for dba or for
// a program built against the installed library.
#define XXH_INLINE_ALL
#include <xxhash.h>

namespace dba {
namespace {

constexpr char kMagic[8] = {'D', 'B', 'A', 'C', 'K', 'P', 'T', '2'};
constexpr char kMagicVersion1[8] = {'D', 'B', 'A', 'C', 'K', 'P', 'T', '1'};

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

void SetupFingerprint::Add(std::string_view name, const void* data, size_t bytes) {
  for (auto& [part, hash] : parts_) {
    if (part == name) {
      const uint64_t both[2] = {hash, XXH3_64bits(data, bytes)};
      hash = XXH3_64bits(both, sizeof both);
      return;
    }
  }
  parts_.emplace_back(std::string(name), XXH3_64bits(data, bytes));
}

namespace {

// An output file and the checksum of everything written to it.
class ChecksummedOut {
 public:
  explicit ChecksummedOut(const std::string& path) : out_(path), hash_(XXH3_createState()) {
    XXH3_64bits_reset(hash_);
  }
  ~ChecksummedOut() { XXH3_freeState(hash_); }
  void Write(const void* data, size_t bytes) {
    XXH3_64bits_update(hash_, data, bytes);
    out_.Write(data, bytes);
  }
  template <typename T>
  void Put(T v) {
    Write(&v, sizeof v);
  }
  template <typename T>
  void Array(std::span<const T> v) {
    Write(v.data(), v.size() * sizeof(T));
  }
  void Commit() {
    const uint64_t sum = XXH3_64bits_digest(hash_);
    out_.Write(&sum, sizeof sum);
    out_.Commit();
  }

 private:
  AtomicOutputFile out_;
  XXH3_state_t* hash_;
};

}  // namespace

void WriteCheckpoint(const std::string& path, const Checkpoint& c) {
  WriteCheckpoint(path, c, c.cameras, c.points, c.kept_observations, c.kept_points);
}

void WriteCheckpoint(const std::string& path, const Checkpoint& c, std::span<const double> cameras,
                     std::span<const double> points, std::span<const uint8_t> kept_observations,
                     std::span<const uint8_t> kept_points) {
  ChecksummedOut out(path);
  out.Write(kMagic, sizeof kMagic);
  out.Put<uint64_t>(c.fingerprint);
  out.Put<int32_t>(static_cast<int32_t>(c.setup.size()));
  for (const auto& [name, hash] : c.setup) {
    out.Put<uint16_t>(static_cast<uint16_t>(name.size()));
    out.Write(name.data(), name.size());
    out.Put<uint64_t>(hash);
  }
  out.Put<int64_t>(c.iterations);
  out.Put<int64_t>(c.accepted);
  out.Put<double>(c.lambda);
  out.Put<double>(c.cost);
  out.Put<int32_t>(c.ended);
  out.Put<int32_t>(c.round);
  for (size_t n : {cameras.size(), points.size(), kept_observations.size(), kept_points.size()}) {
    out.Put<int64_t>(static_cast<int64_t>(n));
  }
  out.Array(cameras);
  out.Array(points);
  out.Array(kept_observations);
  out.Array(kept_points);
  for (const auto& round : c.rounds) out.Array(std::span<const int64_t>(round));
  out.Commit();
}

namespace {

// A checkpoint being read in order, and the checksum of what was read.
class ChecksummedIn {
 public:
  explicit ChecksummedIn(const std::string& path) : in_(path), hash_(XXH3_createState()) {
    XXH3_64bits_reset(hash_);
  }
  ~ChecksummedIn() { XXH3_freeState(hash_); }
  void Read(void* data, size_t bytes, const char* what) {
    in_.Read(data, bytes, what);
    XXH3_64bits_update(hash_, data, bytes);
  }
  template <typename T>
  T Get(const char* what) {
    T v;
    Read(&v, sizeof v, what);
    return v;
  }
  uint64_t remaining() const { return in_.remaining(); }
  // The stored checksum against the one of every byte read.
  bool ChecksumHolds() {
    const uint64_t computed = XXH3_64bits_digest(hash_);
    uint64_t stored = 0;
    in_.Read(&stored, sizeof stored, "checksum");
    return stored == computed && in_.remaining() == 0;
  }

 private:
  BinaryFile in_;
  XXH3_state_t* hash_;
};

[[noreturn]] void Refuse(const std::string& path, const std::string& why) {
  throw InputError(path, 0, why);
}

std::string Number(double v) {
  char buf[32];
  std::snprintf(buf, sizeof buf, "%g", v);
  return buf;
}

// The fields before the arrays, each within what a solve writes.
void ReadState(ChecksummedIn& in, const std::string& path, Checkpoint* c) {
  c->fingerprint = in.Get<uint64_t>("input fingerprint");
  const int32_t parts = in.Get<int32_t>("setup parts");
  if (parts < 0 || parts > 64) Refuse(path, "damaged: " + std::to_string(parts) + " setup parts");
  for (int32_t p = 0; p < parts; ++p) {
    std::string name(in.Get<uint16_t>("setup part name length"), '\0');
    in.Read(name.data(), name.size(), "setup part name");
    c->setup.emplace_back(std::move(name), in.Get<uint64_t>("setup part"));
  }
  c->iterations = in.Get<int64_t>("iterations");
  c->accepted = in.Get<int64_t>("accepted iterations");
  c->lambda = in.Get<double>("lambda");
  c->cost = in.Get<double>("cost");
  c->ended = in.Get<int32_t>("termination");
  c->round = in.Get<int32_t>("rejection rounds");
  if (c->iterations < 0 || c->iterations >= (int64_t{1} << 31) || c->accepted < 0 ||
      c->accepted > c->iterations) {
    Refuse(path, "damaged: iterations " + std::to_string(c->iterations) + ", accepted " +
                     std::to_string(c->accepted) + " (at most 2^31 - 1, accepted at most all)");
  }
  if (!(c->lambda > 0.0 && c->lambda <= kCheckpointMaxLambda)) {
    Refuse(path, "damaged: damping " + Number(c->lambda) + " outside (0, 1e16]");
  }
  if (!(c->cost >= 0.0 && std::isfinite(c->cost))) {
    Refuse(path, "damaged: cost " + Number(c->cost) + " (finite and >= 0)");
  }
  if (c->ended < -1 || c->ended > kCheckpointMaxTermination || c->round < 0 ||
      c->round > kCheckpointMaxRounds) {
    Refuse(path, "damaged: termination " + std::to_string(c->ended) + ", rejection round " +
                     std::to_string(c->round));
  }
}

// The arrays, their sizes against the file's.
void ReadArrays(ChecksummedIn& in, const std::string& path, Checkpoint* c) {
  int64_t n[4];
  for (int64_t& x : n) x = in.Get<int64_t>("counts");
  const uint64_t need = 8 * static_cast<uint64_t>(n[0] + n[1]) + static_cast<uint64_t>(n[2] + n[3]) +
                        40 * static_cast<uint64_t>(c->round) + 8;
  if (n[0] < 0 || n[1] < 0 || n[2] < 0 || n[3] < 0 || n[1] % kPointSize != 0 ||
      need != in.remaining() || (n[2] == 0) != (n[3] == 0)) {
    Refuse(path, "truncated or damaged: its counts need " + std::to_string(need) + " bytes, " +
                     std::to_string(in.remaining()) + " are left");
  }
  c->cameras.resize(n[0]);
  c->points.resize(n[1]);
  c->kept_observations.resize(n[2]);
  c->kept_points.resize(n[3]);
  in.Read(c->cameras.data(), 8 * n[0], "camera values");
  in.Read(c->points.data(), 8 * n[1], "point values");
  in.Read(c->kept_observations.data(), n[2], "kept observations");
  in.Read(c->kept_points.data(), n[3], "kept points");
  c->rounds.resize(c->round);
  for (auto& round : c->rounds) in.Read(round.data(), sizeof round, "rejection round");
}

// What the checksum cannot tell: values no solve writes.
void CheckValues(const std::string& path, const Checkpoint& c) {
  const auto finite = [](const std::vector<double>& v) {
    return std::all_of(v.begin(), v.end(), [](double x) { return std::isfinite(x); });
  };
  if (!finite(c.cameras) || !finite(c.points)) Refuse(path, "damaged: a parameter is not finite");
  const auto flags = [](const std::vector<uint8_t>& v) {
    return std::all_of(v.begin(), v.end(), [](uint8_t x) { return x <= 1; });
  };
  if (!flags(c.kept_observations) || !flags(c.kept_points)) {
    Refuse(path, "damaged: a kept flag is neither 0 nor 1");
  }
}

}  // namespace

Checkpoint ReadCheckpoint(const std::string& path) {
  ChecksummedIn in(path);
  char magic[8];
  in.Read(magic, sizeof magic, "magic");
  if (std::memcmp(magic, kMagicVersion1, sizeof magic) == 0) {
    Refuse(path, "a checkpoint of an earlier dba (DBACKPT1: no checksum, no termination state); "
                 "start the solve again");
  }
  if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) {
    Refuse(path, "not a dba checkpoint (no DBACKPT2 at its start)");
  }
  Checkpoint c;
  ReadState(in, path, &c);
  ReadArrays(in, path, &c);
  if (!in.ChecksumHolds()) {
    Refuse(path, "damaged: its checksum does not match its contents (changed after it was "
                 "written)");
  }
  CheckValues(path, c);
  return c;
}

int32_t ReadCheckpointRound(const std::string& path) {
  try {
    ChecksummedIn in(path);
    char magic[8];
    in.Read(magic, sizeof magic, "magic");
    if (std::memcmp(magic, kMagic, sizeof kMagic) != 0) return -1;
    Checkpoint c;
    ReadState(in, path, &c);
    return c.round;
  } catch (const std::exception&) {
    return -1;
  }
}

void CheckCheckpointFits(const Checkpoint& c, const std::string& path, uint64_t fingerprint,
                         size_t camera_values, size_t point_values) {
  if (c.fingerprint != fingerprint || c.cameras.size() != camera_values ||
      c.points.size() != point_values) {
    throw InputError(path,
                     0,
                     "written for another input (or other --fix-images, --fix-intrinsics, "
                     "--intrinsics): its observations or fixings differ from this one's");
  }
}

void CheckCheckpointSetup(const Checkpoint& c, const std::string& path,
                          const SetupFingerprint& setup) {
  std::string differ;
  const auto note = [&](const std::string& what) { differ += (differ.empty() ? "" : "; ") + what; };
  for (const auto& [name, hash] : setup.parts()) {
    const auto it = std::find_if(c.setup.begin(), c.setup.end(),
                                 [&](const auto& p) { return p.first == name; });
    if (it == c.setup.end()) {
      note("written without " + name);
    } else if (it->second != hash) {
      note("written with other " + name);
    }
  }
  for (const auto& [name, hash] : c.setup) {
    const auto& mine = setup.parts();
    if (std::none_of(mine.begin(), mine.end(), [&](const auto& p) { return p.first == name; })) {
      note("written with " + name + ", which this run does not have");
    }
  }
  if (!differ.empty()) {
    throw UsageError("--resume " + path + ": " + differ +
                     "; resume with what the checkpoint was written with, or start again");
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
                                   SetupFingerprint setup, int64_t accepted_done)
    : path_(std::move(path)),
      every_s_(every_s),
      fingerprint_(fingerprint),
      setup_(std::move(setup)),
      accepted_(accepted_done) {}

bool CheckpointWriter::Due(bool step_accepted, bool ends) {
  if (step_accepted) ++accepted_;
  // The end of a round is written even when its last step was rejected:
  // a resume from it is where the solve ended, not a rerun of the steps
  // after an older checkpoint.
  if (ends) return true;
  return step_accepted && (!written_ || SteadySeconds() - last_write_ >= every_s_);
}

void CheckpointWriter::Write(const Checkpoint& state, std::span<const double> cameras,
                             std::span<const double> points,
                             std::span<const uint8_t> kept_observations,
                             std::span<const uint8_t> kept_points) {
  // From where the parameters are: a copy of the points (2 GB at 1M) would
  // sit beside S and the candidate points' buffer.
  Checkpoint header;
  header.fingerprint = fingerprint_;
  header.setup = setup_.parts();
  header.iterations = state.iterations;
  header.accepted = accepted_;
  header.lambda = state.lambda;
  header.cost = state.cost;
  header.ended = state.ended;
  header.round = state.round;
  header.rounds = state.rounds;
  WriteCheckpoint(path_, header, cameras, points, kept_observations, kept_points);
  written_ = true;
  ++writes_;
  last_write_ = SteadySeconds();
  if (const char* k = std::getenv("DBA_KILL_AFTER_CHECKPOINT");
      k != nullptr && std::atoll(k) == writes_) {
    std::raise(SIGKILL);
  }
}

}  // namespace dba
