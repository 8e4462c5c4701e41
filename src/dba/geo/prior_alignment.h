// Before LM, a robust similarity from the current camera centres to their
// priors (what COLMAP does before a georeferenced bundle adjustment), so
// that LM starts close: RANSAC over triples of priors (deterministic), the
// inliers those within 5σ of the prior after the triple's similarity, then
// Umeyama's least-squares similarity (Eigen::umeyama) on the best set's
// inliers, applied to the poses and points by camera/pose_similarity.h.
//
// For centres on a line (a single strip) the rotation about that line is not
// determined by centres alone: `collinear` says so, and the roll is the
// fit's arbitrary one until the priors (or control points) inside LM set it.
//
// Thread safety: pure functions (ApplySimilarity writes *problem).
#pragma once

#include <Eigen/Core>

#include "dba/camera/pose_similarity.h"
#include "dba/rcs/camera_centre_prior.h"
#include "dba/problem/problem.h"

namespace dba {

struct SimilarityFit : Similarity {
  int64_t inliers = 0;
  bool collinear = false;
};

// From the priors' antennas at `lever_arm` (rcs/camera_centre_prior.h)
// onto the priors. Throws std::invalid_argument when fewer than 3 priors are
// given.
SimilarityFit AlignToPriors(const CameraPriors& priors, const CameraSide& side,
                            const Vec3& lever_arm);

// The same from any points `from` onto `to` (σ per point: the inliers are
// within 5σ); throws std::invalid_argument for fewer than 3.
SimilarityFit FitSimilarity(const std::vector<Vec3>& from, const std::vector<Vec3>& to,
                            const std::vector<double>& sigma);

// Moves the problem's cameras (with rigs, frames and sensors' places) and
// points by the similarity.
void ApplySimilarity(const SimilarityFit& fit, CameraSide* side, std::vector<double>* points);

}  // namespace dba
