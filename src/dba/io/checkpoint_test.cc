// Solve checkpoints: what is written is read back, a checkpoint only fits the
// input it was written for, and a damaged file is refused by name.
#include "dba/io/checkpoint.h"

#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>

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

TEST(Checkpoint, DamagedFilesAreRefusedByName) {
  const std::string path = testing::TempPath("damaged.ckpt");
  const Problem problem = SmallProblem();
  WriteCheckpoint(path, {ProblemFingerprint(problem), 2, 2, 1e-4, 1.0, problem.cameras, problem.points});
  const auto size = std::filesystem::file_size(path);
  std::filesystem::resize_file(path, size - 8);  // cut inside the points
  try {
    ReadCheckpoint(path);
    FAIL() << "a truncated checkpoint was read";
  } catch (const InputError& e) {
    EXPECT_NE(std::string(e.what()).find(path), std::string::npos) << e.what();
  }
  ASSERT_TRUE(testing::WriteFileBytes(path, "DBAPROB2 and more"));
  EXPECT_THROW(ReadCheckpoint(path), InputError);
}

}  // namespace
}  // namespace dba
