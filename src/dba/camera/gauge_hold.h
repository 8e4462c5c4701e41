// The gauge of a bundle: its cost does not change when a similarity of the
// world (rotation, translation, scale: 7 degrees of freedom) moves every
// camera and point (camera/pose_similarity.h), so an optimum is a family
// and LM ends at whichever member its path meets. What nothing else holds
// (camera priors or control points, images held fixed) is held here by
// mapping the optimum back, X' = s Q X + T, onto the input's frame
// (docs/design.md §1.6). A pose (R, t) maps to (R Qᵀ, s t − R Qᵀ T); the
// reprojection errors, the cost and the robust weights are unchanged.
//
// --gauge hold keeps, of the images' centres and rotations (with rigs the
// images' composed poses, so a rig and its images dropped to independent
// cameras hold alike), their centroid c̄, RMS spread ρ and chordal mean
// orientation M (camera/pose_set_mean.h) as loaded (c̄₀, ρ₀, M₀): the
// seven inner constraints of a free network. With the solved c̄, ρ, M
//
//   s = ρ₀ / ρ,   Q = M₀ᵀ M,   T = c̄₀ − s Q c̄        (X' = s Q (X − c̄) + c̄₀)
//
// since c̄ maps to s Q c̄ + T, ρ to s ρ and M to M Qᵀ. One fixed image F
// holds the rotation and translation, so only the scale is free, and only
// ρ is kept: s = ρ₀ / ρ, Q = I, T = (1 − s) C_F (scaled about F's centre).
// A held rig sensor away from its rig's origin holds the scale (s = 1);
// so do centres all at one place as loaded (ρ₀ = 0: no scale to keep).
// Two fixed images with distinct centres, camera priors or control points
// hold all 7 and nothing moves.
//
// --gauge colmap holds what `colmap bundle_adjuster` (3.8) holds: the pose
// of the first image A the input lists (a COLMAP model's file order) and
// the x of the second B's translation t_B (its SetConstantPose and
// SetConstantTvec(B, {0})). A keeps its pose when Q = R_A,0ᵀ R_A and
// T = R_A,0ᵀ (s t_A − t_A,0); then t_B maps to s u + R_B R_Aᵀ t_A,0 with
// u = t_B − R_B R_Aᵀ t_A, and its x is t_B,0's when
//
//   s = (t_B,0 − R_B R_Aᵀ t_A,0)ₓ / uₓ          (s = 1 unless a finite s > 0)
//
// Fixed images, priors or control points hold it as under hold.
//
// Thread safety: pure functions (MoveCameras writes its argument).
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "dba/camera/pose_set_mean.h"
#include "dba/camera/pose_similarity.h"
#include "dba/problem/problem.h"

namespace dba {

// --gauge: what is held of what nothing else holds.
enum class GaugeRule { kHold, kFree, kColmap };

enum class GaugeHold {
  kFree,         // --gauge free: the optimum LM ended at
  kExternal,     // camera priors or control points hold it
  kFixedImages,  // two fixed images with distinct centres hold it
  kFixedImage,   // one fixed image holds pose; the centres' RMS spread the scale
  kMean,         // the centres' centroid, RMS spread and mean orientation
  kColmap,       // `anchor`'s pose and the x of `second`'s translation
};

struct GaugeReference {
  GaugeHold hold = GaugeHold::kFree;
  int64_t anchor = -1;           // kFixedImage: the fixed image; kColmap: A
  int64_t second = -1;           // kColmap: B (-1: a single image)
  PoseSetMean mean;              // the images' as loaded
  std::array<double, 6> pose{};  // kColmap: A's pose as loaded (ω, t)
  double second_tx = 0.0;        // kColmap: t_B,0's x
  bool rig_scale = false;        // a held sensor's place holds the scale
};

// What holds the gauge of `side` as loaded under `rule` (kFree: nothing).
// `read_order`: the images in the order the input lists them (a COLMAP
// model's file order; empty: 0, 1, ...), whose first two kColmap holds.
// Camera priors and control points are the caller's to mark (kExternal).
GaugeReference TakeGaugeReference(const CameraSide& side, GaugeRule rule,
                                  std::span<const int32_t> read_order = {});

// The similarity bringing the solved `side` back onto the reference's frame
// (the identity when nothing is to be held; exactly the identity when what
// is held is bit for bit as taken, so an unmoved model is not rewritten).
Similarity GaugeMapping(const GaugeReference& ref, const CameraSide& side);

// Moves every image that is not held fixed by `s` (with rigs the frames
// and the sensors' places, the images composed anew).
void MoveCameras(const Similarity& s, CameraSide* side);
// Moves the points (kPointSize per point) whose flag in `moved` is set
// (every point when `moved` is empty) by `s`.
void MovePoints(const Similarity& s, std::vector<double>* points,
                const std::vector<uint8_t>& moved = {});

// "the centres' centroid, RMS spread and mean orientation (...)", "COLMAP's:
// image 1's pose and image 2's x translation (...)", ...; images named by
// `image_ids` (a COLMAP model's ids; empty: "image 3 (0-based)").
std::string DescribeGauge(const GaugeReference& ref, const Similarity& moved_by,
                          std::span<const int64_t> image_ids = {});

}  // namespace dba
