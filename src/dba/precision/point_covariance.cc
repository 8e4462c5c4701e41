// Points' covariances from their cameras' blocks; see point_covariance.h.
#include "dba/precision/point_covariance.h"

#include <algorithm>

#include "dba/rcs/eliminate_point.h"

namespace dba {
namespace {

// W over the unknowns point k's observations touch (sorted, each once).
template <class Model>
void Coupling(const UnknownLayout& layout, const PointSystem<Model>& sys, std::vector<int64_t>* rows,
              Eigen::MatrixXd* W) {
  rows->clear();
  const auto add = [&](int32_t r, int n) {
    for (int j = 0; j < n; ++j) rows->push_back(layout.row_offset(r) + j);
  };
  for (int a = 0; a < sys.num_obs; ++a) {
    if (sys.camera_row[a] >= 0) add(sys.camera_row[a], Model::kCamera);
    if (sys.intrinsics_row[a] >= 0) add(sys.intrinsics_row[a], layout.block_size(sys.intrinsics_row[a]));
  }
  std::sort(rows->begin(), rows->end());
  rows->erase(std::unique(rows->begin(), rows->end()), rows->end());
  W->setZero(static_cast<Eigen::Index>(rows->size()), 3);
  const auto at = [&](int32_t r) {
    return std::lower_bound(rows->begin(), rows->end(), layout.row_offset(r)) - rows->begin();
  };
  for (int a = 0; a < sys.num_obs; ++a) {
    if (sys.camera_row[a] >= 0) {
      W->middleRows(at(sys.camera_row[a]), Model::kCamera) += sys.J_c[a].transpose() * sys.J_p[a];
    }
    if constexpr (Model::kIntrinsics > 0) {
      if (sys.intrinsics_row[a] >= 0) {
        const int n = layout.block_size(sys.intrinsics_row[a]);
        W->middleRows(at(sys.intrinsics_row[a]), n) +=
            (sys.J_i[a].transpose() * sys.J_p[a]).topRows(n);
      }
    }
  }
}

// `which` empty: every point.
template <class Model>
void PointsWith(const Problem& problem, const UnknownLayout& layout, const RobustLoss& loss,
                const CameraSideInverse& inverse, int threads, const std::vector<int64_t>& which,
                std::vector<Eigen::Matrix3d>* out) {
  const int64_t n = which.empty() ? problem.num_points() : static_cast<int64_t>(which.size());
  out->resize(n);
#pragma omp parallel num_threads(threads) if (threads > 1)
  {
    PointSystem<Model> sys;
    std::vector<int64_t> rows;
    Eigen::MatrixXd W;
#pragma omp for schedule(dynamic, 256)
    for (int64_t k = 0; k < n; ++k) {
      LinearizePoint(problem, layout, loss, which.empty() ? k : which[k], &sys);
      Coupling(layout, sys, &rows, &W);
      (*out)[k] = inverse.PointBlock(rows, W, sys.V);
    }
  }
}

}  // namespace

std::vector<Eigen::Matrix3d> PointCovariancesOf(const Problem& problem, const UnknownLayout& layout,
                                                const RobustLoss& loss, const CameraSideInverse& inverse,
                                                const std::vector<int64_t>& which, int threads) {
  std::vector<Eigen::Matrix3d> out;
  if (problem.model == CameraModel::kBal) {
    PointsWith<BalModel>(problem, layout, loss, inverse, threads, which, &out);
  } else {
    WithPhotoModel(layout.max_intrinsics_block(), [&]<class M>() {
      PointsWith<M>(problem, layout, loss, inverse, threads, which, &out);
    });
  }
  return out;
}

std::vector<Eigen::Matrix3d> PointCovariances(const Problem& problem, const UnknownLayout& layout,
                                              const RobustLoss& loss, const CameraSideInverse& inverse,
                                              int threads) {
  return PointCovariancesOf(problem, layout, loss, inverse, {}, threads);
}

}  // namespace dba
