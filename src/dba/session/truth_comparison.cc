// A solve against a generated problem's ground truth; see truth_comparison.h.
#include "dba/session/truth_comparison.h"

#include <sstream>
#include <stdexcept>
#include <string_view>

#include "dba/common/error.h"
#include "dba/io/binary_problem.h"
#include "dba/io/text_line_reader.h"
#include "dba/synthetic/uav_generator.h"

namespace dba {

void CheckTruthFile(const std::string& path, const SolveReport& report) {
  int64_t cameras = 0, points = 0, observations = 0;
  if (IsBinaryProblem(path)) {
    const BinaryProblemHeader h = ReadBinaryProblemHeader(path);
    cameras = h.num_cameras, points = h.num_points, observations = h.num_observations;
  } else {
    // The header line only: the whole truth is read after the solve.
    TextLineReader reader(path);
    std::string_view line;
    while (reader.ReadLine(&line) && line.find_first_not_of(" \t\r") == std::string_view::npos) {
    }
    std::istringstream header{std::string(line)};
    if (!(header >> cameras >> points >> observations)) {
      throw InputError(path, reader.line_number(),
                       "expected header 'num_cameras num_points num_observations'");
    }
  }
  if (cameras != report.num_cameras || points != report.num_points ||
      observations != report.num_observations) {
    throw UsageError("--truth " + path + ": " + std::to_string(cameras) + " cameras, " +
                     std::to_string(points) + " points, " + std::to_string(observations) +
                     " observations; the problem has " + std::to_string(report.num_cameras) +
                     ", " + std::to_string(report.num_points) + ", " +
                     std::to_string(report.num_observations));
  }
}

void CountTrueOutliers(const Problem& truth, const std::vector<double>& loaded_pixels,
                       const std::vector<uint8_t>& kept, SolveReport* report) {
  if (static_cast<int64_t>(loaded_pixels.size()) != 2 * truth.num_observations() ||
      static_cast<int64_t>(kept.size()) < truth.num_observations()) {
    throw std::invalid_argument("the ground truth does not match the problem (different numbers "
                                "of observations)");
  }
  for (int64_t o = 0; o < truth.num_observations(); ++o) {
    const bool outlier = IsTrueOutlier(loaded_pixels.data() + 2 * o, truth.pixel(o));
    (outlier ? report->true_outliers : report->true_inliers) += 1;
    if (!kept[o]) (outlier ? report->true_outliers_dropped : report->true_inliers_dropped) += 1;
  }
  report->has_outlier_truth = true;
}

}  // namespace dba
