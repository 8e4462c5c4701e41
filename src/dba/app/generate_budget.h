// What `dba generate` will take before it starts: memory (the images, and
// for BAL text the whole problem) and the files' bytes, checked against
// the memory available and each output file system's free space.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dba/synthetic/uav_generator.h"

namespace dba {

struct GenerateBudget {
  int64_t observations = 0;  // about images × features per image
  int64_t memory_bytes = 0;  // growth beyond the process as it starts
  // Per output file: its path and about how many bytes it takes.
  std::vector<std::pair<std::string, int64_t>> files;
};

// Upper estimates: points are taken as half the observations (every point
// is seen at least twice).
GenerateBudget EstimateGenerate(const UavSurveyOptions& survey, const std::string& output,
                                const std::string& truth);

// Throws std::runtime_error naming the figures where the memory available
// (common/memory.h; -1: unknown, no check) or a file system's free space
// is short of the estimate.
void CheckGenerateFits(const GenerateBudget& budget, int64_t available_memory_bytes);

}  // namespace dba
