// Σ_c by selected inversion under the solve's datum; see
// camera_side_inverse.h (docs/design.md §8).
#include "dba/precision/camera_side_inverse.h"

#include <Eigen/Dense>
#include <cmath>
#include <limits>
#include <memory>
#include <stdexcept>
#include <string>
#include <utility>

#include "dba/bsmc/symmetric_multiply.h"
#include "dba/camera/pose_step.h"
#include "dba/common/timer.h"
#include "dba/rcs/eliminate_point.h"
#include "dba/solver/sparse_cholesky.h"

namespace dba {
namespace {

// The centre of camera row r (a pose (ω, t) where the row's parameters start).
Vec3 RowCentre(const CameraSide& side, const UnknownLayout& layout, int32_t r) {
  return CameraCentre(side.cameras.data() + layout.param_offset(r));
}

// The unknowns pinned to make S positive definite under `freedom`: the
// first determined camera row's six (7 free) and the coordinate along which
// the determined camera row farthest from its centre (1 free: from the held
// image's) lies farthest. `skip`: the undetermined rows.
std::vector<int64_t> PinnedUnknowns(const CameraSide& side, const UnknownLayout& layout,
                                    const GaugeFreedom& freedom, const std::vector<uint8_t>& skip) {
  std::vector<int64_t> pins;
  if (freedom.free == 0) return pins;
  int32_t first = 0;
  while (first < layout.num_camera_rows() && skip[first]) ++first;
  if (layout.num_camera_rows() - first < 2) {
    throw std::runtime_error("--covariance: fewer than two determined free images, nothing fixes the frame");
  }
  const Vec3 origin = freedom.free == 7 ? RowCentre(side, layout, first) : *freedom.scale_centre;
  if (freedom.free == 7) {
    for (int j = 0; j < kPoseSize; ++j) pins.push_back(layout.row_offset(first) + j);
  }
  int32_t far = -1;
  double far_distance = 0.0;
  for (int32_t r = 0; r < layout.num_camera_rows(); ++r) {
    const double d = (RowCentre(side, layout, r) - origin).norm();
    if (!skip[r] && d > far_distance) far_distance = d, far = r;
  }
  if (far < 0) throw std::runtime_error("--covariance: every image at one centre, no scale to hold");
  Eigen::Index axis;
  (RowCentre(side, layout, far) - origin).cwiseAbs().maxCoeff(&axis);
  pins.push_back(layout.row_offset(far) + 3 + axis);
  return pins;
}

// gᵀ S g against Σ S_ii g_i²: a null direction's cost relative to its
// scale (S g in `sg`).
double RelativeCost(const BsmcMatrix& S, const Eigen::VectorXd& g, const Eigen::VectorXd& sg) {
  double diagonal = 0.0;
  for (int32_t b = 0; b < S.num_block_rows(); ++b) {
    const double* v = S.block_values(S.diagonal_block(b));
    for (int a = 0; a < S.block_size(b); ++a) {
      const double x = g[S.scalar_offset(b) + a];
      diagonal += v[a * S.block_size(b) + a] * x * x;
    }
  }
  return std::abs(g.dot(sg)) / diagonal;
}

// The null space of S the pins remove: g_k = e_k − S_h⁻¹ S e_k (pins zero in
// S e_k; the d solves in one pass over the factor), each checked to be one.
Eigen::MatrixXd GaugeNullSpace(const BsmcMatrix& S, SparseCholeskySolver* held,
                               const std::vector<int64_t>& pins, const std::vector<uint8_t>& pinned) {
  const int64_t n = S.num_rows();
  const int d = static_cast<int>(pins.size());
  Eigen::MatrixXd E = Eigen::MatrixXd::Zero(n, d), columns(n, d), Y(n, d);
  for (int k = 0; k < d; ++k) {
    E(pins[k], k) = 1.0;
    SymmetricMultiplySerial(S, E.col(k).data(), columns.col(k).data());
    for (int64_t i = 0; i < n; ++i) {
      if (pinned[i]) columns(i, k) = 0.0;
    }
  }
  held->SolveFactoredColumns(columns.data(), d, Y.data());
  const Eigen::MatrixXd G = E - Y;
  Eigen::VectorXd sg(n);
  for (int k = 0; k < d; ++k) {
    SymmetricMultiplySerial(S, G.col(k).data(), sg.data());
    if (const double cost = RelativeCost(S, G.col(k), sg); cost > 1e-8) {
      throw std::runtime_error("--covariance: the data hold more of the frame than the gauge says "
                               "(a similarity direction costs " + std::to_string(cost) + " of its scale)");
    }
  }
  return G;
}

struct InnerDatum {
  Eigen::MatrixXd G, Y, K, N;
};

// The inner constraints over the determined centres (`skip`: undetermined).
InnerDatum InnerCentreDatum(const UnknownLayout& layout, Eigen::MatrixXd G, SparseCholeskySolver* held,
                            const std::vector<uint8_t>& pinned, const std::vector<uint8_t>& skip) {
  InnerDatum d;
  Eigen::MatrixXd WG = Eigen::MatrixXd::Zero(G.rows(), G.cols());
  for (int32_t r = 0; r < layout.num_camera_rows(); ++r) {
    if (!skip[r]) WG.middleRows(layout.row_offset(r) + 3, 3) = G.middleRows(layout.row_offset(r) + 3, 3);
  }
  // Σ_h W G: solves with pins zero on the right (their rows of Σ_h are zero).
  Eigen::MatrixXd B = WG;
  for (Eigen::Index i = 0; i < G.rows(); ++i) {
    if (pinned[i]) B.row(i).setZero();
  }
  d.Y.resize(G.rows(), G.cols());
  held->SolveFactoredColumns(B.data(), static_cast<int>(G.cols()), d.Y.data());
  const Eigen::MatrixXd M = G.transpose() * WG;
  const Eigen::MatrixXd M_inv = M.inverse();
  d.K = M_inv.transpose();
  d.N = M_inv * (WG.transpose() * d.Y) * M_inv.transpose();
  d.G = std::move(G);
  return d;
}

// The block row of S's scalar row `row` (-1: none).
int32_t BlockRowOf(const UnknownLayout& layout, int64_t row) {
  if (row < 0) return -1;
  int32_t r = 0;
  while (r + 1 < layout.num_block_rows() && layout.row_offset(r + 1) <= row) ++r;
  return r;
}

// " (first: image 3 (0-based); ...)" for block row r ("" for -1).
std::string NameOfRow(const UnknownLayout& layout, int32_t r) {
  if (r < 0) return "";
  std::string named;
  const bool camera = r < layout.num_camera_rows();
  for (int64_t i = 0; i < (camera ? layout.num_images() : layout.num_groups()); ++i) {
    if ((camera ? layout.camera_row(i) : layout.intrinsics_row(i)) == r) {
      named += (named.empty() ? "" : ", ") + std::to_string(i);
    }
  }
  return std::string(" (first: ") + (camera ? "image " : "intrinsic group ") + named + " (0-based)" +
         (camera ? ": too few observations?)" : ": a parameter nothing observes?)");
}

// S with the pins made the identity's, factored; not positive definite
// (a degeneracy no single row shows), refused naming the failed pivot's row.
std::unique_ptr<SparseCholeskySolver> FactorPinned(const UnknownLayout& layout, const BsmcMatrix& S,
                                                   const std::vector<uint8_t>& pinned, int threads) {
  auto held = std::make_unique<SparseCholeskySolver>(S, threads, BlockOrdering::kNestedDissection);
  if (!held->FactorizeWithIdentityRows(S, pinned)) {
    throw std::runtime_error("--covariance: the normal matrix at the optimum is not positive definite: "
                             "the data do not determine every camera unknown" +
                             NameOfRow(layout, BlockRowOf(layout, held->failed_row())));
  }
  return held;
}

}  // namespace

CameraSideInverse::CameraSideInverse(const CameraSide& side, const RcsSystem& rcs,
                                     const GaugeFreedom& freedom, int threads)
    : CameraSideInverse(side, rcs, freedom, threads, FindUndeterminedUnknowns(rcs.S)) {}

CameraSideInverse::CameraSideInverse(const CameraSide& side, const RcsSystem& rcs,
                                     const GaugeFreedom& freedom, int threads,
                                     UndeterminedUnknowns undetermined_unknowns)
    : free_(freedom.free), null_(std::move(undetermined_unknowns)) {
  const Timer timer;
  const UndeterminedUnknowns& undetermined = null_;
  undetermined_.assign(rcs.S.num_block_rows(), 0);
  null_of_.assign(rcs.S.num_rows(), -1);
  for (size_t u = 0; u < undetermined.rows.size(); ++u) {
    undetermined_[undetermined.rows[u]] = 1;
    null_of_[rcs.S.scalar_offset(undetermined.rows[u])] = static_cast<int32_t>(u);
  }
  const std::vector<int64_t> pins = PinnedUnknowns(side, rcs.layout, freedom, undetermined_);
  pinned_.assign(rcs.S.num_rows(), 0);
  for (int64_t p : pins) pinned_[p] = 1;
  for (int64_t p : undetermined.pins) pinned_[p] = 1;
  std::unique_ptr<SparseCholeskySolver> held = FactorPinned(rcs.layout, rcs.S, pinned_, threads);
  if (!pins.empty()) {
    InnerDatum d = InnerCentreDatum(rcs.layout, GaugeNullSpace(rcs.S, held.get(), pins, pinned_),
                                    held.get(), pinned_, undetermined_);
    G_ = std::move(d.G), Y_ = std::move(d.Y), K_ = std::move(d.K), N_ = std::move(d.N);
  }
  SupernodalFactor factor = held->TakeFactor();
  held.reset();
  factor_values_ = static_cast<int64_t>(factor.values.size());
  inversion_flops_ = InversionFlops(factor);
  factor_seconds_ = timer.Seconds();
  InvertOnPattern(&factor, threads);
  z_.emplace(std::move(factor));
}

Eigen::MatrixXd CameraSideInverse::Held(std::span<const int64_t> rows) const {
  const Eigen::Index n = static_cast<Eigen::Index>(rows.size());
  Eigen::MatrixXd held(n, n);
  for (Eigen::Index a = 0; a < n; ++a) {
    for (Eigen::Index b = 0; b <= a; ++b) {
      const bool pin = pinned_[rows[a]] || pinned_[rows[b]];
      held(a, b) = held(b, a) = pin ? 0.0 : z_->At(rows[a], rows[b]);
    }
  }
  return held;
}

Eigen::MatrixXd CameraSideInverse::DatumTerms(const Eigen::MatrixXd& g, const Eigen::MatrixXd& y) const {
  const Eigen::MatrixXd yk = y * K_ * g.transpose();
  return -yk - yk.transpose() + g * N_ * g.transpose();
}

Eigen::MatrixXd CameraSideInverse::Block(std::span<const int64_t> rows) const {
  Eigen::MatrixXd sigma = Held(rows);
  if (free_ == 0) return sigma;
  const Eigen::Index n = static_cast<Eigen::Index>(rows.size());
  Eigen::MatrixXd g(n, G_.cols()), y(n, G_.cols());
  for (Eigen::Index a = 0; a < n; ++a) g.row(a) = G_.row(rows[a]), y.row(a) = Y_.row(rows[a]);
  return sigma + DatumTerms(g, y);
}

bool CameraSideInverse::MovedByUndetermined(std::span<const int64_t> rows, const Eigen::MatrixXd& W) const {
  if (null_.rows.empty()) return false;
  for (size_t i = 0; i < rows.size(); ++i) {  // a block row's unknowns lie together in `rows`
    const int32_t u = null_of_[rows[i]];
    if (u >= 0 && MovedByNullDirections(null_.null[u], W.middleRows(i, null_.null[u].rows()))) return true;
  }
  return false;
}

Eigen::Matrix3d CameraSideInverse::PointBlock(std::span<const int64_t> rows, const Eigen::MatrixXd& W,
                                              const Eigen::Matrix3d& V) const {
  // A point its observations leave undetermined has no covariance: NaN.
  if (!PointDetermined(V) || MovedByUndetermined(rows, W)) {
    return Eigen::Matrix3d::Constant(std::numeric_limits<double>::quiet_NaN());
  }
  const Eigen::Matrix3d v_inv = V.inverse();
  const Eigen::MatrixXd T = v_inv * W.transpose();  // 3 × |rows|
  Eigen::Matrix3d sigma = v_inv + T * Held(rows) * T.transpose();
  if (free_ == 0) return sigma;
  const Eigen::Index n = static_cast<Eigen::Index>(rows.size());
  Eigen::MatrixXd g(n, G_.cols()), y(n, G_.cols());
  for (Eigen::Index a = 0; a < n; ++a) g.row(a) = G_.row(rows[a]), y.row(a) = Y_.row(rows[a]);
  // The point's rows of G and Y: −V⁻¹ Wᵀ times its unknowns'.
  sigma += DatumTerms(-T * g, -T * y);
  return sigma;
}

}  // namespace dba
