// Where the world's origin is changes nothing in a solve: the same survey in
// its own frame and moved 6,400 km away (ECEF coordinates) takes the same LM
// iterations to the same costs and stops the same way, in both camera
// models. A pose's
// step turns the camera about its own centre (camera/pose_step.h); with the
// translation stepped additively the two runs part from the second iteration
// (a rotation step then swings the camera about the origin).
#include <gtest/gtest.h>

#include <cmath>
#include <string>
#include <vector>

#include "dba/camera/pose_similarity.h"
#include "dba/io/read_problem.h"
#include "dba/lm/bundle_adjust.h"
#include "dba/synthetic/uav_generator.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

// The problem with the world's origin moved to -o: every point X - o, every
// camera seeing it where it did.
void MoveOrigin(const Vec3& o, Problem* problem) {
  Similarity shift;
  shift.translation = -o;
  for (int64_t i = 0; i < problem->num_images(); ++i) MovePose(shift, problem->camera(i));
  for (int64_t k = 0; k < problem->num_points(); ++k) {
    double* X = problem->point(k);
    for (int a = 0; a < 3; ++a) X[a] -= o[a];
  }
}

struct Solve {
  std::vector<double> costs;  // at each iteration's start
  LmSummary summary;
};

Solve SolveWithTheDefaults(Problem problem) {
  LmOptions options;
  Solve solve;
  solve.summary =
      BundleAdjust(options, &problem, [&](const IterationSummary& s) {
        solve.costs.push_back(s.cost);
      }).lm;
  return solve;
}

void ExpectTheSameSolveAnywhere(CameraModel model) {
  UavSurveyOptions o;
  o.images = 300;
  o.features_per_image = 200;
  o.forward_overlap = 0.6;
  o.side_overlap = 0.3;
  o.model = model;
  const std::string path = testing::TempPath("origin.dba");
  GenerateUavSurvey(o, path, "");
  const Problem here = ReadProblem(path);
  Problem far = here;
  MoveOrigin(Vec3(4.2e6, 0.17e6, 4.8e6), &far);  // ECEF: 6,400 km away

  const Solve a = SolveWithTheDefaults(here), b = SolveWithTheDefaults(far);
  ASSERT_GE(a.costs.size(), 4u);
  ASSERT_EQ(a.costs.size(), b.costs.size());
  for (size_t i = 0; i < a.costs.size(); ++i) {
    EXPECT_LE(std::abs(a.costs[i] - b.costs[i]), 1e-9 * a.costs[i])
        << "iteration " << i + 1 << ": " << a.costs[i] << " here, " << b.costs[i]
        << " 6,400 km away";
  }
  // The last step too: far away its ‖δ‖ must not look tiny against ‖x‖
  // (lm/parameter_norm.h).
  EXPECT_EQ(TerminationReasonName(b.summary.termination),
            std::string(TerminationReasonName(a.summary.termination)));
  EXPECT_EQ(b.summary.accepted_iterations, a.summary.accepted_iterations);
  EXPECT_LE(std::abs(a.summary.final_cost - b.summary.final_cost), 1e-9 * a.summary.final_cost);
}

TEST(OriginIndependence, BalSurveySolvesTheSameFarFromTheOrigin) {
  ExpectTheSameSolveAnywhere(CameraModel::kBal);
}

TEST(OriginIndependence, PhotoSurveySolvesTheSameFarFromTheOrigin) {
  ExpectTheSameSolveAnywhere(CameraModel::kPhoto);
}

}  // namespace
}  // namespace dba
