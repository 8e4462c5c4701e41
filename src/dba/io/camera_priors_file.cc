// Reading camera priors; see camera_priors_file.h.
#include "dba/io/camera_priors_file.h"

#include <unordered_map>

#include "dba/common/error.h"
#include "dba/io/sigma_fields.h"
#include "dba/io/text_line_reader.h"
#include "dba/io/text_tokens.h"

namespace dba {

std::vector<CameraPriorRow> ReadCameraPriorsFile(const std::string& path) {
  TextLineReader in(path);
  std::vector<CameraPriorRow> rows;
  std::unordered_map<std::string, int64_t> seen;  // image -> its line
  std::string_view view;
  while (in.ReadLine(&view)) {
    const int64_t line = in.line_number();
    const std::vector<std::string> fields = CommentFreeFields(view);
    if (fields.empty()) continue;
    if (fields.size() != 4 && fields.size() != 6) {
      throw InputError(path, line,
                       "expected IMAGE X Y Z [SIGMA_XY SIGMA_Z] (4 or 6 fields), got " +
                           std::to_string(fields.size()));
    }
    static const char* const kNames[] = {"X", "Y", "Z", "SIGMA_XY", "SIGMA_Z"};
    double v[5] = {};
    for (size_t k = 1; k < fields.size(); ++k) {
      if (ParseDouble(fields[k], &v[k - 1]) != NumberStatus::kOk) {
        throw InputError(path, line,
                         std::string(kNames[k - 1]) + ": '" + Clipped(fields[k]) +
                             "' is not a finite number");
      }
    }
    CameraPriorRow row;
    row.image = fields[0];
    row.xyz = Eigen::Vector3d(v[0], v[1], v[2]);
    row.line = line;
    if (fields.size() == 6) {
      CheckSigmas(path, line, v[3], v[4], fields[4], fields[5]);
      row.sigma = Eigen::Vector2d(v[3], v[4]);
    }
    const auto [it, fresh] = seen.emplace(row.image, line);
    if (!fresh) {
      throw InputError(path, line, "image '" + Clipped(row.image) + "' already has a prior (line " +
                                       std::to_string(it->second) + ")");
    }
    rows.push_back(std::move(row));
  }
  if (rows.empty()) throw InputError(path, 0, "no priors (every line blank or a comment)");
  return rows;
}

}  // namespace dba
