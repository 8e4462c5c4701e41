// Where the world's origin is changes nothing in a solve: the same survey in
// its own frame and moved 5,000 km away (a projected CRS's coordinates) takes
// the same LM iterations to the same costs, in both camera models. A pose's
// step turns the camera about its own centre (camera/pose_step.h); with the
// translation stepped additively the two runs part from the second iteration
// (a rotation step then swings the camera about the origin).
#include <gtest/gtest.h>

#include <cmath>
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

std::vector<double> CostHistory(Problem problem) {
  LmOptions options;  // the defaults
  std::vector<double> costs;
  BundleAdjust(options, &problem, [&](const IterationSummary& s) { costs.push_back(s.cost); });
  return costs;
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
  MoveOrigin(Vec3(3.2e6, -4.1e6, 250.0), &far);

  const std::vector<double> a = CostHistory(here), b = CostHistory(far);
  ASSERT_GE(a.size(), 4u);
  ASSERT_EQ(a.size(), b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    EXPECT_LE(std::abs(a[i] - b[i]), 1e-9 * a[i])
        << "iteration " << i + 1 << ": " << a[i] << " here, " << b[i] << " 5,000 km away";
  }
}

TEST(OriginIndependence, BalSurveySolvesTheSameFarFromTheOrigin) {
  ExpectTheSameSolveAnywhere(CameraModel::kBal);
}

TEST(OriginIndependence, PhotoSurveySolvesTheSameFarFromTheOrigin) {
  ExpectTheSameSolveAnywhere(CameraModel::kPhoto);
}

}  // namespace
}  // namespace dba
