// Solve checkpoints: what is written is read back, a checkpoint only fits the
// input it was written for, and a damaged file is refused by name.
#include "dba/io/checkpoint.h"

#include <gtest/gtest.h>

#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <limits>

#define XXH_INLINE_ALL
#include <xxhash.h>

#include "dba/common/error.h"
#include "dba/testing/synthetic_bal.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

Problem SmallProblem() {
  testing::SyntheticBalOptions o;
  o.num_cameras = 5;
  o.num_points = 30;
  o.pixel_noise = 0.5;
  return testing::MakeSyntheticBal(o).problem;
}

TEST(Checkpoint, RoundTripsAndFitsOnlyItsInput) {
  const std::string path = testing::TempPath("round_trip.ckpt");
  Problem problem = SmallProblem();
  Checkpoint c;
  c.fingerprint = ProblemFingerprint(problem);
  c.iterations = 7;
  c.accepted = 5;
  c.lambda = 3.5e-5;
  c.cost = 12.25;
  c.cameras = problem.cameras;
  c.points = problem.points;
  for (double& v : c.cameras) v += 0.125;
  WriteCheckpoint(path, c);
  Checkpoint r = ReadCheckpoint(path);
  EXPECT_EQ(r.fingerprint, c.fingerprint);
  EXPECT_EQ(r.iterations, 7);
  EXPECT_EQ(r.accepted, 5);
  EXPECT_EQ(r.lambda, 3.5e-5);
  EXPECT_EQ(r.cost, 12.25);
  EXPECT_EQ(r.cameras, c.cameras);
  EXPECT_EQ(r.points, c.points);
  const Checkpoint read = r;
  ApplyCheckpoint(std::move(r), path, &problem);
  EXPECT_EQ(problem.cameras, c.cameras);
  EXPECT_EQ(problem.points, c.points);
  // Moved, not copied: a resumed solve holds its parameters once.
  EXPECT_TRUE(r.cameras.empty());
  EXPECT_TRUE(r.points.empty());

  // The fingerprint ignores the parameters and sees the observations and
  // the fixings.
  EXPECT_EQ(ProblemFingerprint(problem), c.fingerprint);
  Problem moved = SmallProblem();
  moved.obs_pixel[3] += 1e-9;
  EXPECT_NE(ProblemFingerprint(moved), c.fingerprint);
  EXPECT_THROW(ApplyCheckpoint(Checkpoint(read), path, &moved), InputError);
  Problem fixed = SmallProblem();
  fixed.fixed_cameras.assign(fixed.num_images(), 0);
  fixed.fixed_cameras[1] = 1;
  EXPECT_THROW(ApplyCheckpoint(Checkpoint(read), path, &fixed), InputError);
}

Checkpoint Sample(const Problem& problem) {
  Checkpoint c;
  c.fingerprint = ProblemFingerprint(problem);
  c.iterations = 2;
  c.accepted = 2;
  c.lambda = 1e-4;
  c.cost = 1.0;
  c.cameras = problem.cameras;
  c.points = problem.points;
  return c;
}

// Offsets of the fixed-size fields after the magic and the fingerprint, in a
// checkpoint without setup parts.
constexpr size_t kIterations = 8 + 8 + 4;
constexpr size_t kLambda = kIterations + 16;
constexpr size_t kEnded = kLambda + 16;

std::string ReadError(const std::string& path) {
  try {
    ReadCheckpoint(path);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// Rewrites `bytes` at `offset` and the checksum after them, as a file written
// with those values would be: the checksum cannot tell, the ranges must.
void Rewrite(const std::string& path, size_t offset, const void* bytes, size_t n) {
  std::string file = testing::ReadFileBytes(path);
  std::memcpy(file.data() + offset, bytes, n);
  const uint64_t sum = XXH3_64bits(file.data(), file.size() - 8);
  std::memcpy(file.data() + file.size() - 8, &sum, 8);
  ASSERT_TRUE(testing::WriteFileBytes(path, file));
}

TEST(Checkpoint, DamagedFilesAreRefusedByName) {
  const std::string path = testing::TempPath("damaged.ckpt");
  const Problem problem = SmallProblem();
  WriteCheckpoint(path, Sample(problem));
  const auto size = std::filesystem::file_size(path);
  std::filesystem::resize_file(path, size - 12);  // cut inside the points
  EXPECT_NE(ReadError(path).find(path), std::string::npos);
  ASSERT_TRUE(testing::WriteFileBytes(path, "DBAPROB2 and more"));
  EXPECT_NE(ReadError(path).find("not a dba checkpoint"), std::string::npos);
  ASSERT_TRUE(testing::WriteFileBytes(path, "DBACKPT1 and more"));
  EXPECT_NE(ReadError(path).find("earlier dba"), std::string::npos);
}

// One flipped bit anywhere (an exponent of a point, the λ, a count, the
// checksum itself) is refused: a damaged checkpoint is never solved from.
TEST(Checkpoint, EveryFlippedBitIsRefused) {
  const std::string path = testing::TempPath("flipped.ckpt");
  const Problem problem = SmallProblem();
  WriteCheckpoint(path, Sample(problem));
  const std::string good = testing::ReadFileBytes(path);
  for (size_t byte = 0; byte < good.size(); byte += 7) {
    std::string bad = good;
    bad[byte] = static_cast<char>(bad[byte] ^ (1 << (byte % 8)));
    ASSERT_TRUE(testing::WriteFileBytes(path, bad));
    EXPECT_NE(ReadError(path), "") << "a flipped bit " << byte % 8 << " of byte " << byte
                                   << " was read";
  }
  ASSERT_TRUE(testing::WriteFileBytes(path, good));
  EXPECT_EQ(ReadError(path), "");
}

// Values no solve writes are refused even with a checksum that matches.
TEST(Checkpoint, FieldsOutOfRangeAreRefused) {
  const std::string path = testing::TempPath("range.ckpt");
  const Problem problem = SmallProblem();
  const auto expect_refused = [&](size_t offset, auto value, const char* says) {
    WriteCheckpoint(path, Sample(problem));
    Rewrite(path, offset, &value, sizeof value);
    const std::string why = ReadError(path);
    EXPECT_NE(why.find(says), std::string::npos) << "at " << offset << ": '" << why << "'";
  };
  expect_refused(kIterations, int64_t{(int64_t{1} << 31) + 5}, "iterations 2147483653");
  expect_refused(kIterations, int64_t{-1}, "iterations -1");
  expect_refused(kIterations + 8, int64_t{3}, "accepted 3");
  expect_refused(kLambda, std::numeric_limits<double>::infinity(), "damping inf");
  expect_refused(kLambda, 1e300, "damping 1e+300");
  expect_refused(kLambda, 0.0, "damping 0");
  expect_refused(kLambda + 8, std::nan(""), "cost nan");
  expect_refused(kLambda + 8, -1.0, "cost -1");
  expect_refused(kEnded, int32_t{9}, "termination 9");
  expect_refused(kEnded + 4, int32_t{6}, "rejection round 6");
  Checkpoint nan = Sample(problem);
  nan.points[7] = std::numeric_limits<double>::infinity();
  WriteCheckpoint(path, nan);
  EXPECT_NE(ReadError(path).find("not finite"), std::string::npos);
}

// The termination state, the rejection rounds and what they kept, and the
// setup's parts are read back as written.
TEST(Checkpoint, StateAndRejectionRoundTrip) {
  const std::string path = testing::TempPath("state.ckpt");
  const Problem problem = SmallProblem();
  Checkpoint c = Sample(problem);
  c.ended = 0;
  c.round = 2;
  c.kept_observations.assign(problem.num_observations(), 1);
  c.kept_observations[4] = 0;
  c.kept_points.assign(problem.num_points(), 1);
  c.kept_points[3] = 0;
  c.rounds = {{5, 1, 0, 95, 29}, {1, 0, 0, 94, 29}};
  SetupFingerprint setup;
  setup.Add("--loss", "huber");
  c.setup = setup.parts();
  WriteCheckpoint(path, c);
  const Checkpoint r = ReadCheckpoint(path);
  EXPECT_EQ(r.ended, 0);
  EXPECT_EQ(r.round, 2);
  EXPECT_EQ(r.kept_observations, c.kept_observations);
  EXPECT_EQ(r.kept_points, c.kept_points);
  EXPECT_EQ(r.rounds, c.rounds);
  EXPECT_EQ(r.setup, c.setup);
  // The round from the header alone; -1 for what is no checkpoint.
  EXPECT_EQ(ReadCheckpointRound(path), 2);
  EXPECT_EQ(ReadCheckpointRound(testing::TempPath("no_such.ckpt")), -1);
  const std::string other = testing::TempPath("not_a_checkpoint.ckpt");
  std::ofstream(other) << "3 4 5\n";
  EXPECT_EQ(ReadCheckpointRound(other), -1);
}

// Another loss, priors or control points than the checkpoint's are refused,
// naming each part that differs.
TEST(Checkpoint, AnotherSetupIsRefusedNamingWhatDiffers) {
  SetupFingerprint written;
  written.Add("--loss", "cauchy");
  written.Add("--camera-priors", 1.0);
  Checkpoint c;
  c.setup = written.parts();
  SetupFingerprint same;
  same.Add("--loss", "cauchy");
  same.Add("--camera-priors", 1.0);
  EXPECT_NO_THROW(CheckCheckpointSetup(c, "c.ckpt", same));
  SetupFingerprint other;
  other.Add("--loss", "huber");
  other.Add("--gcps", 2.0);
  try {
    CheckCheckpointSetup(c, "c.ckpt", other);
    FAIL() << "another setup was accepted";
  } catch (const UsageError& e) {
    const std::string why = e.what();
    EXPECT_NE(why.find("written with other --loss"), std::string::npos) << why;
    EXPECT_NE(why.find("written without --gcps"), std::string::npos) << why;
    EXPECT_NE(why.find("written with --camera-priors, which this run does not have"),
              std::string::npos)
        << why;
  }
}

}  // namespace
}  // namespace dba
