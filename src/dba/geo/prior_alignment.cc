// The robust similarity onto the priors; see prior_alignment.h.
#include "dba/geo/prior_alignment.h"

#include <Eigen/Eigenvalues>
#include <Eigen/Geometry>
#include <random>
#include <stdexcept>

#include "dba/camera/rig_pose.h"

namespace dba {
namespace {

SimilarityFit Umeyama(const Eigen::Matrix3Xd& from, const Eigen::Matrix3Xd& to) {
  const Eigen::Matrix4d m = Eigen::umeyama(from, to, true);
  SimilarityFit fit;
  const Mat3 sR = m.topLeftCorner<3, 3>();
  fit.scale = std::cbrt(sR.determinant());
  fit.rotation = sR / fit.scale;
  fit.translation = m.topRightCorner<3, 1>();
  return fit;
}

}  // namespace

SimilarityFit AlignToPriors(const CameraPriors& priors, const CameraSide& side,
                            const Vec3& lever_arm) {
  const int64_t n = static_cast<int64_t>(priors.priors.size());
  if (n < 3) {
    throw std::invalid_argument("the alignment onto the priors needs at least 3 priors, got " +
                                std::to_string(n));
  }
  std::vector<Vec3> from, to;
  std::vector<double> sigma;
  for (const CameraCentrePrior& p : priors.priors) {
    from.push_back(
        AntennaPosition(side.cameras.data() + ExposurePoseOffset(side, p.image), lever_arm));
    to.push_back(p.centre);
    sigma.push_back(p.sigma.maxCoeff());
  }
  return FitSimilarity(from, to, sigma);
}

SimilarityFit FitSimilarity(const std::vector<Vec3>& from_points, const std::vector<Vec3>& to_points,
                            const std::vector<double>& sigma) {
  const int64_t n = static_cast<int64_t>(from_points.size());
  if (n < 3) {
    throw std::invalid_argument("a similarity needs at least 3 points, got " + std::to_string(n));
  }
  Eigen::Matrix3Xd from(3, n), to(3, n);
  for (int64_t x = 0; x < n; ++x) from.col(x) = from_points[x], to.col(x) = to_points[x];
  // Collinear centres: the spread's second direction against the first.
  const Vec3 mean = to.rowwise().mean();
  const Eigen::Matrix3d spread = (to.colwise() - mean) * (to.colwise() - mean).transpose();
  const Eigen::Vector3d ev = Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d>(spread).eigenvalues();
  const bool collinear = ev[1] <= 1e-6 * ev[2];

  const auto inliers_of = [&](const SimilarityFit& f, std::vector<int64_t>* in) {
    in->clear();
    for (int64_t x = 0; x < n; ++x) {
      const Vec3 d = f.Apply(from.col(x)) - to.col(x);
      if (d.norm() <= 5.0 * sigma[x]) in->push_back(x);
    }
  };
  std::mt19937_64 rng(0x5eed);
  std::uniform_int_distribution<int64_t> pick(0, n - 1);
  std::vector<int64_t> best, in;
  const int trials = n == 3 ? 1 : 500;
  for (int trial = 0; trial < trials; ++trial) {
    int64_t a = 0, b = 1, c = 2;
    if (n > 3) {
      a = pick(rng), b = pick(rng), c = pick(rng);
      if (a == b || b == c || a == c) continue;
    }
    Eigen::Matrix3Xd f3(3, 3), t3(3, 3);
    f3 << from.col(a), from.col(b), from.col(c);
    t3 << to.col(a), to.col(b), to.col(c);
    const SimilarityFit f = Umeyama(f3, t3);
    if (!std::isfinite(f.scale) || !(f.scale > 0)) continue;
    inliers_of(f, &in);
    if (in.size() > best.size()) best = in;
  }
  if (best.size() < 3) {
    best.resize(n);
    for (int64_t x = 0; x < n; ++x) best[x] = x;  // no consensus: all of them
  }
  // Least squares on the inliers, then once more on the refit's inliers.
  SimilarityFit fit;
  for (int round = 0; round < 2; ++round) {
    Eigen::Matrix3Xd f(3, best.size()), t(3, best.size());
    for (size_t k = 0; k < best.size(); ++k) f.col(k) = from.col(best[k]), t.col(k) = to.col(best[k]);
    fit = Umeyama(f, t);
    inliers_of(fit, &in);
    if (in.size() < 3) break;
    best = in;
  }
  fit.inliers = static_cast<int64_t>(best.size());
  fit.collinear = collinear;
  // All centres (or all targets) at one place leave the scale undefined.
  if (!std::isfinite(fit.scale) || !(fit.scale > 0) || !fit.rotation.allFinite() ||
      !fit.translation.allFinite()) {
    throw std::invalid_argument(
        "the similarity onto the " + std::to_string(n) +
        " positions is not defined (scale " + std::to_string(fit.scale) +
        "): the positions, or the cameras' centres, are all at one place");
  }
  return fit;
}

void ApplySimilarity(const SimilarityFit& fit, CameraSide* side, std::vector<double>* points) {
  if (side->has_rigs()) {
    MoveRigFrames(fit, {}, side);
    ComposeRigImages(side);
  } else {
    for (int64_t i = 0; i < side->num_images(); ++i) MovePose(fit, side->camera(i));
  }
  for (size_t k = 0; k + 2 < points->size(); k += 3) {
    const Vec3 X = fit.Apply(Vec3((*points)[k], (*points)[k + 1], (*points)[k + 2]));
    for (int a = 0; a < 3; ++a) (*points)[k + a] = X[a];
  }
}

}  // namespace dba
