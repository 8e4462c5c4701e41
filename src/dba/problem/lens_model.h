// The lens models of the photogrammetric camera: what an intrinsic group's
// parameters mean. Every COLMAP camera model (COLMAP's
// src/colmap/sensor/models.h: same ids, names, parameter order and pixel
// convention: origin at the image's top-left corner, y down, the first pixel's
// centre at (0.5, 0.5)), plus dba's own photogrammetric Brown–Conrady model.
// The projections and their Jacobians are in camera/lens_projection.h.
//
// A parameter is a focal length, a principal-point coordinate, an extra
// (distortion) parameter, or metadata (EQUIRECTANGULAR's image width and
// height): metadata are never unknowns.
//
// Thread safety: constant tables.
#pragma once

#include <cstdint>
#include <optional>
#include <span>
#include <string>
#include <string_view>

namespace dba {

// Most parameters of any model (RAD_TAN_THIN_PRISM_FISHEYE).
inline constexpr int kMaxIntrinsics = 16;

enum class LensModel : uint8_t {
  kSimplePinhole = 0,
  kPinhole = 1,
  kSimpleRadial = 2,
  kRadial = 3,
  kOpenCV = 4,
  kOpenCVFisheye = 5,
  kFullOpenCV = 6,
  kFov = 7,
  kSimpleRadialFisheye = 8,
  kRadialFisheye = 9,
  kThinPrismFisheye = 10,
  kRadTanThinPrismFisheye = 11,
  kSimpleDivision = 12,
  kDivision = 13,
  kSimpleFisheye = 14,
  kFisheye = 15,
  kEucm = 16,
  kEquirectangular = 17,
  // dba's own: f, cx, cy, k1, k2, k3, p1, p2, b1, b2 (lens_projection.h).
  kBrown = 32,
};

struct LensModelInfo {
  LensModel id;
  const char* name;        // COLMAP's name (BROWN for dba's own)
  int num_params;
  const char* params;      // the parameters' names, ", "-separated, in order
  uint16_t metadata_mask;  // bits of parameters that are never unknowns
  bool colmap;             // a COLMAP model (can be written to a COLMAP model)
};

// Every model, COLMAP's in id order, then Brown.
std::span<const LensModelInfo> LensModels();
// nullptr when unknown.
const LensModelInfo* FindLensModel(std::string_view name);
const LensModelInfo* FindLensModel(int id);
const LensModelInfo& Info(LensModel m);
inline int LensModelParams(LensModel m) { return Info(m).num_params; }
// The bits of the model's parameters that can be unknowns.
uint16_t LensModelParamMask(LensModel m);
// Index of the parameter called `name` in the model, if it has one.
std::optional<int> LensModelParamIndex(LensModel m, std::string_view name);
// The bits of a kind of parameter, by the kind's name (every model has
// these names): "focal" (f, fx, fy), "principal_point" (cx, cy), "extra"
// (every other parameter that can be an unknown: distortion, FOV's ω, EUCM's
// α and β; COLMAP's refine_extra_params); nullopt for another name.
std::optional<uint16_t> LensModelKindMask(LensModel m, std::string_view kind);
// The name of parameter j.
std::string LensModelParamName(LensModel m, int j);
// "SIMPLE_PINHOLE, PINHOLE, ..." : every model's name.
std::string LensModelNames();
// One line per model: its name and its parameters, for --help texts.
std::string LensModelTable();

}  // namespace dba
