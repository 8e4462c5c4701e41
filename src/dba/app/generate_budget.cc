// What dba generate takes, checked before it starts; see generate_budget.h.
#include "dba/app/generate_budget.h"

#include <sys/stat.h>
#include <sys/statvfs.h>

#include <filesystem>
#include <map>
#include <stdexcept>

#include "dba/io/path_kind.h"
#include "dba/lm/memory_estimate.h"

namespace dba {
namespace {

// Measured: a .dba file holds about 20 bytes per observation (camera index,
// pixel) and 32 per point; BAL text about 56 per observation all told.
// `dba generate` took 170 MiB for a million images (about 180 bytes each).
constexpr int64_t kBinaryPerObservation = 20, kBinaryPerPoint = 32, kBinaryPerImage = 200;
constexpr int64_t kTextPerObservation = 60, kTextPerImage = 250;
constexpr int64_t kPerImageInMemory = 200, kChunkBytes = int64_t{64} << 20;
// BAL text is built in memory: per observation the camera index and two
// pixels of the problem and of the truth, per point two positions; the
// vectors may double while they grow.
constexpr int64_t kTextMemoryPerObservation = 2 * (4 + 16 + 4 + 16), kTextMemoryPerPoint = 2 * 48;

// The file system's free space for an unprivileged writer, and its device.
std::pair<int64_t, uint64_t> FreeSpace(const std::string& path) {
  std::filesystem::path dir = std::filesystem::path(path).parent_path();
  if (dir.empty()) dir = ".";
  struct statvfs fs {};
  struct stat st {};
  if (::statvfs(dir.c_str(), &fs) != 0 || ::stat(dir.c_str(), &st) != 0) return {-1, 0};
  return {static_cast<int64_t>(fs.f_bavail) * static_cast<int64_t>(fs.f_frsize),
          static_cast<uint64_t>(st.st_dev)};
}

}  // namespace

GenerateBudget EstimateGenerate(const UavSurveyOptions& survey, const std::string& output,
                                const std::string& truth) {
  GenerateBudget b;
  b.observations = static_cast<int64_t>(static_cast<double>(survey.images) * survey.features_per_image);
  const int64_t points = b.observations / 2;
  const bool binary = KindOfPath(output) == PathKind::kBinary;
  b.memory_bytes = survey.images * kPerImageInMemory +
                   (binary ? kChunkBytes
                           : b.observations * kTextMemoryPerObservation + points * kTextMemoryPerPoint);
  for (const std::string& path : {output, truth}) {
    if (path.empty()) continue;
    const int64_t bytes = KindOfPath(path) == PathKind::kBinary
                              ? b.observations * kBinaryPerObservation + points * kBinaryPerPoint +
                                    survey.images * kBinaryPerImage
                              : b.observations * kTextPerObservation + survey.images * kTextPerImage;
    b.files.emplace_back(path, bytes);
  }
  return b;
}

void CheckGenerateFits(const GenerateBudget& budget, int64_t available_memory_bytes) {
  if (available_memory_bytes >= 0 && budget.memory_bytes > available_memory_bytes) {
    throw std::runtime_error("the survey (about " + std::to_string(budget.observations) +
                             " observations) needs about " + FormatBytes(budget.memory_bytes) +
                             " of memory but " + FormatBytes(available_memory_bytes) +
                             " is available: fewer --images or --features, or a .dba output "
                             "(streamed)");
  }
  // The files on one file system share its free space.
  std::map<uint64_t, int64_t> need;
  std::map<uint64_t, std::pair<std::string, int64_t>> space;
  for (const auto& [path, bytes] : budget.files) {
    const auto [free, device] = FreeSpace(path);
    if (free < 0) continue;  // not known: the write itself will say
    need[device] += bytes;
    space[device] = {path, free};
  }
  for (const auto& [device, bytes] : need) {
    const auto& [path, free] = space[device];
    if (bytes > free) {
      throw std::runtime_error(path + ": the survey's files need about " + FormatBytes(bytes) +
                               " but its file system has " + FormatBytes(free) + " free");
    }
  }
}

}  // namespace dba
