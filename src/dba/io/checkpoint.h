// A solve's checkpoint (`dba solve --checkpoint PATH`, `--resume PATH`):
// after an accepted LM iteration, the parameters and the LM state an
// uninterrupted solve carries on with (after an accepted step Nielsen's ν is
// 2, so λ and the iteration counts are the whole state; lm/nielsen_damping.h).
//
// Layout, little-endian: "DBACKPT1"; u64 fingerprint of the input (model,
// counts, observations, fixings: ProblemFingerprint); i64 iterations done,
// i64 accepted; f64 λ for the next iteration, f64 cost; i64 camera values,
// i64 point values; the cameras, the points (f64 each). Written whole or not
// at all (io/atomic_output_file.h).
//
// Thread safety: functions touch only the files they name.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "dba/problem/problem.h"

namespace dba {

struct Checkpoint {
  uint64_t fingerprint = 0;
  int64_t iterations = 0;  // LM iterations done (accepted and rejected)
  int64_t accepted = 0;
  double lambda = 0.0;     // damping for the next iteration
  double cost = 0.0;       // at these parameters
  std::vector<double> cameras, points;
};

// A 64-bit FNV-1a hash of what makes a problem the same problem for a
// resume: model, counts, the observations (cameras, pixels, point offsets),
// the image groups and what is held fixed; not the parameters.
uint64_t ProblemFingerprint(const Problem& problem);

void WriteCheckpoint(const std::string& path, const Checkpoint& checkpoint);
// InputError naming the path for a file that is not a whole checkpoint.
Checkpoint ReadCheckpoint(const std::string& path);
// Puts the checkpoint's parameters into `problem`; InputError naming `path`
// when it was written for another input (fingerprint or sizes).
void ApplyCheckpoint(const Checkpoint& checkpoint, const std::string& path, Problem* problem);

}  // namespace dba
