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
#include <span>
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
// Its parts, for a problem spread over ranks: the camera side (model,
// counts, image groups, fixings), and the observations as a sum over the
// points of a hash of each point's (global id, its observations' global
// cameras and pixels), so any split of the points sums to the same value.
// Empty `global_point` / `global_camera`: the problem's own numbering.
uint64_t CameraSideFingerprint(const Problem& side, int64_t num_points);
uint64_t ObservationsFingerprint(const Problem& problem, std::span<const int64_t> global_point,
                                 std::span<const int32_t> global_camera);
uint64_t CombineFingerprints(uint64_t camera_side, uint64_t observations);

void WriteCheckpoint(const std::string& path, const Checkpoint& checkpoint);
// The same with the parameters from where they are (`state`'s own vectors
// are not read).
void WriteCheckpoint(const std::string& path, const Checkpoint& state,
                     std::span<const double> cameras, std::span<const double> points);
// InputError naming the path for a file that is not a whole checkpoint.
Checkpoint ReadCheckpoint(const std::string& path);
// InputError naming `path` when the checkpoint was written for another
// input: another fingerprint, or other numbers of parameters.
void CheckCheckpointFits(const Checkpoint& checkpoint, const std::string& path,
                         uint64_t fingerprint, size_t camera_values, size_t point_values);
// Moves the checkpoint's parameters into `problem` (after CheckCheckpointFits):
// the solve holds them once, not twice (2 GB at a million images).
void ApplyCheckpoint(Checkpoint&& checkpoint, const std::string& path, Problem* problem);

// A solve's checkpoints: after accepted LM iterations, at most one per
// `every_s` seconds (0: after each). The caller asks Due after every
// iteration and, when it says yes, gathers the parameters and calls Write.
class CheckpointWriter {
 public:
  // `accepted_done`: accepted iterations before this run (a resumed solve).
  CheckpointWriter(std::string path, double every_s, uint64_t fingerprint, int64_t accepted_done);
  // The fingerprint, when it is known only once the problem is spread.
  void set_fingerprint(uint64_t fingerprint) { fingerprint_ = fingerprint; }
  const std::string& path() const { return path_; }

  // Counts accepted iterations; true when this one is to be written.
  bool Due(bool step_accepted);
  // For tests, DBA_KILL_AFTER_CHECKPOINT=N: SIGKILL right after writing the
  // checkpoint of iteration N (no handler runs, as with a real kill).
  void Write(int64_t iteration, double next_lambda, double cost,
             const std::vector<double>& cameras, const std::vector<double>& points);

 private:
  std::string path_;
  double every_s_;
  uint64_t fingerprint_;
  int64_t accepted_;
  bool written_ = false;
  double last_write_ = 0.0;  // steady-clock seconds
};

}  // namespace dba
