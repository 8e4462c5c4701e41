// The lens models' table; see lens_model.h.
#include "dba/problem/lens_model.h"

#include <algorithm>
#include <stdexcept>

namespace dba {
namespace {

constexpr LensModelInfo kModels[] = {
    {LensModel::kSimplePinhole, "SIMPLE_PINHOLE", 3, "f, cx, cy", 0, true},
    {LensModel::kPinhole, "PINHOLE", 4, "fx, fy, cx, cy", 0, true},
    {LensModel::kSimpleRadial, "SIMPLE_RADIAL", 4, "f, cx, cy, k", 0, true},
    {LensModel::kRadial, "RADIAL", 5, "f, cx, cy, k1, k2", 0, true},
    {LensModel::kOpenCV, "OPENCV", 8, "fx, fy, cx, cy, k1, k2, p1, p2", 0, true},
    {LensModel::kOpenCVFisheye, "OPENCV_FISHEYE", 8, "fx, fy, cx, cy, k1, k2, k3, k4", 0, true},
    {LensModel::kFullOpenCV, "FULL_OPENCV", 12, "fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, k5, k6",
     0, true},
    {LensModel::kFov, "FOV", 5, "fx, fy, cx, cy, omega", 0, true},
    {LensModel::kSimpleRadialFisheye, "SIMPLE_RADIAL_FISHEYE", 4, "f, cx, cy, k", 0, true},
    {LensModel::kRadialFisheye, "RADIAL_FISHEYE", 5, "f, cx, cy, k1, k2", 0, true},
    {LensModel::kThinPrismFisheye, "THIN_PRISM_FISHEYE", 12,
     "fx, fy, cx, cy, k1, k2, p1, p2, k3, k4, sx1, sy1", 0, true},
    {LensModel::kRadTanThinPrismFisheye, "RAD_TAN_THIN_PRISM_FISHEYE", 16,
     "fx, fy, cx, cy, k0, k1, k2, k3, k4, k5, p0, p1, s0, s1, s2, s3", 0, true},
    {LensModel::kSimpleDivision, "SIMPLE_DIVISION", 4, "f, cx, cy, k", 0, true},
    {LensModel::kDivision, "DIVISION", 5, "fx, fy, cx, cy, k", 0, true},
    {LensModel::kSimpleFisheye, "SIMPLE_FISHEYE", 3, "f, cx, cy", 0, true},
    {LensModel::kFisheye, "FISHEYE", 4, "fx, fy, cx, cy", 0, true},
    {LensModel::kEucm, "EUCM", 6, "fx, fy, cx, cy, alpha, beta", 0, true},
    {LensModel::kEquirectangular, "EQUIRECTANGULAR", 2, "w, h", 3, true},
    {LensModel::kBrown, "BROWN", 10, "f, cx, cy, k1, k2, k3, p1, p2, b1, b2", 0, false},
};

// The j-th name of a ", "-separated list.
std::string_view NthName(std::string_view list, int j) {
  for (int i = 0; i < j; ++i) {
    const size_t comma = list.find(", ");
    if (comma == std::string_view::npos) return {};
    list.remove_prefix(comma + 2);
  }
  return list.substr(0, list.find(", "));
}

}  // namespace

std::span<const LensModelInfo> LensModels() { return kModels; }

const LensModelInfo* FindLensModel(std::string_view name) {
  for (const auto& m : kModels) {
    if (name == m.name) return &m;
  }
  return nullptr;
}

const LensModelInfo* FindLensModel(int id) {
  for (const auto& m : kModels) {
    if (static_cast<int>(m.id) == id) return &m;
  }
  return nullptr;
}

const LensModelInfo& Info(LensModel m) {
  const int id = static_cast<int>(m);
  constexpr int kColmapModels = static_cast<int>(LensModel::kEquirectangular) + 1;
  const LensModelInfo* info = id < kColmapModels ? &kModels[id] : FindLensModel(id);
  if (info == nullptr) {
    throw std::invalid_argument("unknown lens model id " + std::to_string(static_cast<int>(m)));
  }
  return *info;
}

uint16_t LensModelParamMask(LensModel m) {
  const LensModelInfo& info = Info(m);
  return static_cast<uint16_t>(((1u << info.num_params) - 1) & ~info.metadata_mask);
}

std::optional<int> LensModelParamIndex(LensModel m, std::string_view name) {
  const LensModelInfo& info = Info(m);
  for (int j = 0; j < info.num_params; ++j) {
    if (NthName(info.params, j) == name) return j;
  }
  return std::nullopt;
}

std::optional<uint16_t> LensModelKindMask(LensModel m, std::string_view kind) {
  uint16_t focal = 0, principal = 0;
  for (int j = 0; j < Info(m).num_params; ++j) {
    const std::string_view name = NthName(Info(m).params, j);
    if (name == "f" || name == "fx" || name == "fy") focal |= static_cast<uint16_t>(1u << j);
    if (name == "cx" || name == "cy") principal |= static_cast<uint16_t>(1u << j);
  }
  if (kind == "focal") return focal;
  if (kind == "principal_point") return principal;
  if (kind == "extra") return static_cast<uint16_t>(LensModelParamMask(m) & ~focal & ~principal);
  return std::nullopt;
}

std::string LensModelParamName(LensModel m, int j) {
  return std::string(NthName(Info(m).params, j));
}

std::string LensModelNames() {
  std::string s;
  for (const auto& m : kModels) {
    if (!s.empty()) s += ", ";
    s += m.name;
  }
  return s;
}

std::string LensModelTable() {
  std::string s;
  for (const auto& m : kModels) {
    std::string name = m.name;
    name.resize(std::max<size_t>(name.size() + 1, 28), ' ');
    s += "  " + name + m.params + (m.metadata_mask != 0 ? "  (never unknowns)" : "") +
         (m.colmap ? "" : "  (dba's own; not in COLMAP)") + "\n";
  }
  return s;
}

}  // namespace dba
