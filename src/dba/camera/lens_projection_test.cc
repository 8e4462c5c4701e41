// Every lens model's projection against values computed independently from
// COLMAP's formulas (scripts/colmap_projections.py, a NumPy transcription of
// COLMAP's src/colmap/sensor/models.h, and the Brown model's equations), at
// fixed points: tests/data/camera_models/projections.txt.
#include "dba/camera/lens_projection.h"

#include <gtest/gtest.h>

#include <fstream>
#include <map>
#include <sstream>
#include <string>
#include <vector>

namespace dba {
namespace {

TEST(LensProjection, MatchesAnIndependentTranscriptionOfColmapsFormulas) {
  const std::string path = std::string(DBA_TEST_DATA_DIR) + "/camera_models/projections.txt";
  std::ifstream in(path);
  ASSERT_TRUE(in) << path;
  std::map<std::string, int> cases;
  std::string line;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    std::istringstream s(line);
    std::string name;
    int n = 0;
    s >> name >> n;
    std::vector<double> params(n);
    for (double& p : params) s >> p;
    double u, v, w, x, y;
    s >> u >> v >> w >> x >> y;
    ASSERT_TRUE(s) << line;
    const LensModelInfo* m = FindLensModel(name);
    ASSERT_NE(m, nullptr) << name;
    ASSERT_EQ(m->num_params, n) << name;
    const Eigen::Vector2d px = LensProject(m->id, params.data(), Eigen::Vector3d(u, v, w),
                                           nullptr, nullptr);
    // FOV's small-radius branch is a series in COLMAP and the script alike.
    EXPECT_NEAR(px.x(), x, 1e-9 * (1 + std::abs(x))) << line;
    EXPECT_NEAR(px.y(), y, 1e-9 * (1 + std::abs(y))) << line;
    ++cases[name];
  }
  for (const LensModelInfo& m : LensModels()) {
    EXPECT_GE(cases[m.name], 6) << m.name << " has too few cases in " << path;
  }
}

}  // namespace
}  // namespace dba
