// A solve's checkpoint (`dba solve --checkpoint PATH`, `--resume PATH`):
// after an accepted LM iteration, all that decides where the uninterrupted
// solve ends: the parameters, the LM state (after an accepted step Nielsen's
// ν is 2, so λ and the iteration counts are the whole of it;
// lm/nielsen_damping.h), whether that step ended the solve, the rounds of
// outlier rejection done and what they left, and the identity of the input
// and of everything else that shapes the result (the loss, the camera
// priors and control points, the rejection criteria: SetupFingerprint).
//
// Layout (version 2), little-endian:
//   "DBACKPT2"
//   u64 input fingerprint (ProblemFingerprint, control points included)
//   i32 setup parts, each u16 name length, the name, u64 its hash
//   i64 iterations done in this round, i64 accepted
//   f64 λ for the next iteration, f64 cost
//   i32 ended (-1: the round's LM goes on; else its termination reason)
//   i32 rejection rounds done
//   i64 camera values, i64 point values, i64 observation flags, i64 point flags
//   the cameras, the points (f64; with rejection every point as loaded),
//   the kept flags (u8 0/1, observations then points; none without
//   rejection), per rejection round 5 × i64 (RejectionRound's fields)
//   u64 XXH3-64 of every byte before it
// Written whole or not at all (io/atomic_output_file.h); read back only
// when the checksum and every field's range hold, so a flipped bit or a
// file from elsewhere is refused by name, never solved from.
//
// Thread safety: functions touch only the files they name.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "dba/problem/problem.h"

namespace dba {

struct Checkpoint {
  uint64_t fingerprint = 0;
  // SetupFingerprint's parts: what shaped the result besides the input.
  std::vector<std::pair<std::string, uint64_t>> setup;
  int64_t iterations = 0;  // LM iterations done in this round (accepted and rejected)
  int64_t accepted = 0;
  double lambda = 0.0;     // damping for the next iteration
  double cost = 0.0;       // at these parameters
  int32_t ended = -1;      // -1: going on; else the round's termination reason
  int32_t round = 0;       // rejection rounds done
  std::vector<double> cameras, points;
  // With outlier rejection: what is left, over the problem as loaded; the
  // rounds done (each RejectionRound's five counts).
  std::vector<uint8_t> kept_observations, kept_points;
  std::vector<std::array<int64_t, 5>> rounds;
};

// Largest values a checkpoint may hold: λ (LM gives up past it) and rounds.
inline constexpr double kCheckpointMaxLambda = 1e16;
inline constexpr int32_t kCheckpointMaxRounds = 5;
inline constexpr int32_t kCheckpointMaxTermination = 4;

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

// What shapes a solve's result besides its input (the loss, the priors,
// the control points, the rejection criteria), part by named part, each
// hashed (XXH3-64), so a checkpoint refused for another setup says which.
class SetupFingerprint {
 public:
  // Adds a named part's bytes to it (a part added again grows).
  void Add(std::string_view name, const void* data, size_t bytes);
  void Add(std::string_view name, double value) { Add(name, &value, sizeof value); }
  void Add(std::string_view name, std::string_view text) { Add(name, text.data(), text.size()); }
  const std::vector<std::pair<std::string, uint64_t>>& parts() const { return parts_; }

 private:
  std::vector<std::pair<std::string, uint64_t>> parts_;
};

void WriteCheckpoint(const std::string& path, const Checkpoint& checkpoint);
// The same with the parameters and flags from where they are (`state`'s own
// vectors are not read).
void WriteCheckpoint(const std::string& path, const Checkpoint& state,
                     std::span<const double> cameras, std::span<const double> points,
                     std::span<const uint8_t> kept_observations = {},
                     std::span<const uint8_t> kept_points = {});
// InputError naming the path for a file that is not a whole checkpoint: a
// wrong checksum, a value out of range, a non-finite parameter, an older
// version.
Checkpoint ReadCheckpoint(const std::string& path);
// The rejection rounds a checkpoint was written after, from its header
// alone (ReadCheckpoint checks the whole file); -1 where the header cannot
// be read.
int32_t ReadCheckpointRound(const std::string& path);
// InputError naming `path` when the checkpoint was written for another
// input: another fingerprint, or other numbers of parameters.
void CheckCheckpointFits(const Checkpoint& checkpoint, const std::string& path,
                         uint64_t fingerprint, size_t camera_values, size_t point_values);
// UsageError naming `path` and each part that differs when it was written
// with another setup than this run's.
void CheckCheckpointSetup(const Checkpoint& checkpoint, const std::string& path,
                          const SetupFingerprint& setup);
// Moves the checkpoint's parameters into `problem` (after CheckCheckpointFits):
// the solve holds them once, not twice (2 GB at a million images).
void ApplyCheckpoint(Checkpoint&& checkpoint, const std::string& path, Problem* problem);

// A solve's checkpoints: after accepted LM iterations, at most one per
// `every_s` seconds (0: after each), and always the one that ends a round.
// The caller asks Due after every iteration and, when it says yes, gathers
// the parameters and calls Write.
class CheckpointWriter {
 public:
  // `accepted_done`: accepted iterations before this run (a resumed solve).
  CheckpointWriter(std::string path, double every_s, uint64_t fingerprint,
                   SetupFingerprint setup, int64_t accepted_done);
  // The fingerprint, when it is known only once the problem is spread.
  void set_fingerprint(uint64_t fingerprint) { fingerprint_ = fingerprint; }
  const std::string& path() const { return path_; }
  // A new round of LM after an outlier rejection round: its counts start
  // at zero.
  void StartRound() { accepted_ = 0; }

  // Counts accepted iterations; true when this one is to be written: an
  // accepted one when `every_s` has passed, and the one that ends the
  // round's LM (`ends`) whether its step was accepted or not.
  bool Due(bool step_accepted, bool ends = false);
  // `state`: iterations, λ, cost, ended, round and rounds (its fingerprint,
  // setup and parameter vectors are not read); the parameters and flags
  // from where they are.
  // For tests, DBA_KILL_AFTER_CHECKPOINT=N: SIGKILL right after writing
  // this run's N-th checkpoint (no handler runs, as with a real kill); a
  // test hook, documented in README.md ("Test hooks").
  void Write(const Checkpoint& state, std::span<const double> cameras,
             std::span<const double> points, std::span<const uint8_t> kept_observations = {},
             std::span<const uint8_t> kept_points = {});
  int64_t accepted() const { return accepted_; }
  int64_t written() const { return writes_; }

 private:
  std::string path_;
  double every_s_;
  uint64_t fingerprint_;
  SetupFingerprint setup_;
  int64_t accepted_;
  bool written_ = false;
  int64_t writes_ = 0;
  double last_write_ = 0.0;  // steady-clock seconds
};

}  // namespace dba
