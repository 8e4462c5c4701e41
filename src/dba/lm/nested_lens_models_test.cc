// Nested lens models never end higher: the shipped SIMPLE_RADIAL model
// rewritten as RADIAL (k2 = 0), as OPENCV (fx = fy = f, k1 = k, the rest 0)
// and as FULL_OPENCV holds the simpler optimum among its own, so each richer
// model's final cost is at most the simpler one's × (1 + 1e-5); RADIAL with
// k2 held fixed is SIMPLE_RADIAL again and ends at its cost (1e-5).
#include <gtest/gtest.h>

#include <cstdio>
#include <string>
#include <vector>

#include "dba/io/colmap_model.h"
#include "dba/io/colmap_problem.h"
#include "dba/lm/bundle_adjust.h"
#include "dba/problem/fixings.h"

namespace dba {
namespace {

// The final cost of the shipped model with its cameras rewritten by `as`.
double FinalCost(LensModel as, const std::vector<std::string>& fixed = {}) {
  ColmapModel model =
      ReadColmapModel(std::string(DBA_SHARED_DATA_DIR) + "/colmap/mithunnallana_6img/sparse/0");
  for (ColmapCamera& c : model.cameras) {
    EXPECT_EQ(c.ModelName(), "SIMPLE_RADIAL");
    const double f = c.params[0], cx = c.params[1], cy = c.params[2], k = c.params[3];
    switch (as) {
      case LensModel::kSimpleRadial:
        break;
      case LensModel::kRadial:
        c.params = {f, cx, cy, k, 0};
        break;
      case LensModel::kOpenCV:
        c.params = {f, f, cx, cy, k, 0, 0, 0};
        break;
      case LensModel::kFullOpenCV:
        c.params = {f, f, cx, cy, k, 0, 0, 0, 0, 0, 0, 0};
        break;
      default:
        ADD_FAILURE() << "no rewriting as " << Info(as).name;
    }
    c.model_id = static_cast<int32_t>(as);
  }
  ColmapProblem cp = ProblemFromColmap(model, {}, "mithunnallana_6img");
  if (!fixed.empty()) ApplyFixings(Fixings{{}, {{-1, fixed}}}, &cp.problem);
  const BundleAdjustSummary s = BundleAdjust(LmOptions{}, &cp.problem);
  EXPECT_NE(s.lm.termination, TerminationReason::kMaxIterations) << Info(as).name;
  return s.lm.final_cost;
}

TEST(NestedLensModels, RicherModelsNeverEndHigher) {
  const double simple_radial = FinalCost(LensModel::kSimpleRadial);
  const double radial = FinalCost(LensModel::kRadial);
  const double opencv = FinalCost(LensModel::kOpenCV);
  const double full_opencv = FinalCost(LensModel::kFullOpenCV);
  EXPECT_LE(radial, simple_radial * (1 + 1e-5));
  EXPECT_LE(opencv, radial * (1 + 1e-5));
  EXPECT_LE(full_opencv, opencv * (1 + 1e-5));
  // The richer models do use their parameters on this real lens.
  EXPECT_LT(full_opencv, simple_radial);
  const double radial_k2_fixed = FinalCost(LensModel::kRadial, {"k2"});
  std::printf("  final costs: SIMPLE_RADIAL %.9g, RADIAL %.9g, OPENCV %.9g, FULL_OPENCV %.9g, "
              "RADIAL with k2 fixed %.9g\n",
              simple_radial, radial, opencv, full_opencv, radial_k2_fixed);
  EXPECT_NEAR(radial_k2_fixed, simple_radial, 1e-5 * simple_radial);
}

}  // namespace
}  // namespace dba
