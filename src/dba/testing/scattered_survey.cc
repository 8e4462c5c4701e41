// A generated survey with its points shuffled; see scattered_survey.h.
#include "dba/testing/scattered_survey.h"

#include <algorithm>
#include <numeric>
#include <random>

#include "dba/io/read_problem.h"
#include "dba/problem/point_order.h"
#include "dba/synthetic/uav_generator.h"
#include "dba/testing/temp_files.h"

namespace dba::testing {

ScatteredSurvey MakeScatteredSurvey(const std::string& name, int64_t images, int64_t features,
                                    uint32_t seed, uint32_t shuffle_seed) {
  UavSurveyOptions o;
  o.images = images;
  o.features_per_image = features;
  o.seed = seed;
  const std::string path = TempPath(name);
  GenerateUavSurvey(o, path, "");
  ScatteredSurvey s;
  s.spatial = ReadProblem(path);
  s.order.resize(s.spatial.num_points());
  std::iota(s.order.begin(), s.order.end(), int64_t{0});
  std::shuffle(s.order.begin(), s.order.end(), std::mt19937(shuffle_seed));
  s.scattered = s.spatial;
  PermutePoints(s.order, &s.scattered);
  return s;
}

}  // namespace dba::testing
