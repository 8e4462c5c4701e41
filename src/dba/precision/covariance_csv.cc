// The --covariance file; see covariance_csv.h.
#include "dba/precision/covariance_csv.h"

#include <algorithm>
#include <cmath>
#include <cstdio>

namespace dba {
namespace {

void Append(std::string* line, double v) {
  char number[32];
  std::snprintf(number, sizeof number, ",%.9g", v);
  *line += number;
}

// A name as one CSV field: quoted (quotes doubled) when it holds a comma,
// a quote or a line break.
std::string CsvField(const std::string& name) {
  if (name.find_first_of(",\"\r\n") == std::string::npos) return name;
  std::string quoted = "\"";
  for (char ch : name) quoted += ch == '"' ? std::string("\"\"") : std::string(1, ch);
  return quoted + "\"";
}

std::string Header() {
  std::string h =
      "image,datum,sigma_x,sigma_y,sigma_z,c_xx,c_xy,c_xz,c_yy,c_yz,c_zz,sigma_omega_deg,"
      "sigma_phi_deg,sigma_kappa_deg";
  for (int a = 1; a <= 6; ++a) {
    for (int c = a; c <= 6; ++c) h += ",p" + std::to_string(a) + std::to_string(c);
  }
  return h + ",x,y,z\n";
}

std::string PoseLine(const PoseCovariance& p) {
  std::string line;
  for (int a = 3; a < 6; ++a) Append(&line, std::sqrt(p(a, a)));
  for (int a = 3; a < 6; ++a) {
    for (int c = a; c < 6; ++c) Append(&line, p(a, c));
  }
  for (int a = 0; a < 3; ++a) Append(&line, std::sqrt(p(a, a)) * 180.0 / M_PI);
  for (int a = 0; a < 6; ++a) {
    for (int c = a; c < 6; ++c) Append(&line, p(a, c));
  }
  return line;
}

}  // namespace

Eigen::Matrix3d PointInOutputFrame(const Eigen::Matrix3d& point, const Similarity& moved, double scale) {
  const Eigen::Matrix3d Q = moved.scale * moved.rotation;
  return scale * (Q * point * Q.transpose());
}

std::string PointCovarianceCsv(const std::vector<Eigen::Matrix3d>& points,
                               const std::vector<int64_t>& loaded, const Similarity& moved, double scale) {
  std::string text = "point,sigma_x,sigma_y,sigma_z,c_xx,c_xy,c_xz,c_yy,c_yz,c_zz\n";
  for (size_t k = 0; k < loaded.size() && k < points.size(); ++k) {
    const Eigen::Matrix3d p = PointInOutputFrame(points[k], moved, scale);
    std::string line = std::to_string(loaded[k]);
    if (!p.allFinite()) {  // undetermined by its observations: empty fields
      text += line + std::string(9, ',') + "\n";
      continue;
    }
    for (int a = 0; a < 3; ++a) Append(&line, std::sqrt(p(a, a)));
    for (int a = 0; a < 3; ++a) {
      for (int c = a; c < 3; ++c) Append(&line, p(a, c));
    }
    text += line + "\n";
  }
  return text;
}

PoseCovariance PoseInOutputFrame(const PoseCovariance& pose, const Similarity& moved, double scale) {
  return scale * MovePoseCovariance(moved, pose);
}

std::string PoseState(const CameraCovariances& covariances, size_t image) {
  if (covariances.pose[image]) return covariances.datum_free == 0 ? "absolute" : "inner";
  const std::vector<int64_t>& undetermined = covariances.undetermined_images;
  const bool held = !std::binary_search(undetermined.begin(), undetermined.end(), static_cast<int64_t>(image));
  return held ? "held" : "undetermined";
}

std::string CovarianceCsv(const CameraCovariances& covariances, const std::vector<std::string>& names,
                          const std::vector<Vec3>& centres, const Similarity& moved, double scale) {
  std::string text = Header();
  for (size_t i = 0; i < covariances.pose.size(); ++i) {
    text += i < names.size() ? CsvField(names[i]) : std::to_string(i);
    text += "," + PoseState(covariances, i);
    text += covariances.pose[i] ? PoseLine(PoseInOutputFrame(*covariances.pose[i], moved, scale))
                                : std::string(33, ',');
    for (int a = 0; a < 3; ++a) Append(&text, i < centres.size() ? centres[i][a] : NAN);
    text += "\n";
  }
  return text;
}

}  // namespace dba
