// The analyse stage's covariance (--covariance): the datum the solve's
// gauge leaves, the pose covariances (precision/camera_covariance.h) and
// the variance factor, on the main rank at the optimum.
#include <stdexcept>
#include <utility>

#include "dba/common/error.h"
#include "dba/common/timer.h"
#include "dba/precision/external_datum.h"
#include "dba/precision/point_covariance.h"
#include "dba/precision/undetermined_unknowns.h"
#include "dba/session/solve_session.h"

namespace dba {
namespace {

// What the data leave free of the frame at the optimum: nothing with priors
// or control points or two held images; the scale beside one held image;
// else the similarity's 7.
GaugeFreedom FreedomAtOptimum(const Problem& problem, bool external) {
  if (external) return {0, {}};
  const GaugeReference ref = TakeGaugeReference(problem, GaugeRule::kHold);
  switch (ref.hold) {
    case GaugeHold::kFixedImages:
      return {0, {}};
    case GaugeHold::kFixedImage:
      return {1, CameraCentre(problem.camera(ref.anchor))};
    default:
      return {7, {}};
  }
}

// Priors and control points that do not hold the frame themselves (along
// one line, or at one place), when no held image does: named, not inverted.
void RefuseFrameLeftFree(const Problem& problem, const Georeference& geo) {
  if (geo.priors.empty() && geo.control_points == 0) return;
  const GaugeHold held = TakeGaugeReference(problem, GaugeRule::kHold).hold;
  if (held == GaugeHold::kFixedImages || held == GaugeHold::kFixedImage) return;
  std::vector<SurveyedPosition> at;
  for (const CameraCentrePrior& p : geo.priors.priors) at.push_back({p.centre, p.sigma.maxCoeff()});
  for (const GroundControlPoint& p : geo.gcps.points) {
    if (p.control) at.push_back({p.position, p.sigma.maxCoeff()});
  }
  if (const std::string free = FrameLeftFreeBy(at); !free.empty()) {
    throw UsageError("--covariance: " + free + " (the data only hold it through the positions' noise); "
                     "add control points or priors off it, or hold two images (--fix-images)");
  }
}

}  // namespace

// Before the solve: what the covariance cannot be taken of, refused by name.
void SolveSession::CheckCovarianceRequest() const {
  if (options_.ply_sigma && options_.point_covariance_path.empty()) {
    throw UsageError("--ply-colour sigma needs --point-covariance (the points' sigmas)");
  }
  if (!options_.point_covariance_path.empty() && comm_->size() > 1) {
    throw UsageError("--point-covariance: one process only (over ranks the points stay on their ranks)");
  }
  if (result_.problem.has_rigs()) {
    throw UsageError("--covariance: rig models are not supported yet (the images' covariances "
                     "compose frame and sensor blocks)");
  }
  if (comm_->size() > 1 && options_.distributed.rcs == DistributedOptions::Rcs::kDistributed) {
    throw UsageError("--covariance on " + std::to_string(comm_->size()) +
                     " ranks factors S on rank 0: not with --rcs distributed (by default it is gathered there)");
  }
  RefuseFrameLeftFree(result_.problem, result_.geo);
}

// The control points' predicted σ (unit pixel variance; scaled with the
// rest in TakeCovariance): the problem's last points, in the order of the
// ground control's control points.
void SolveSession::ControlPointSigmas(const Problem& problem, const UnknownLayout& layout,
                                      const CameraSideInverse& inverse) {
  const Georeference& geo = result_.geo;
  if (geo.control_points == 0) return;
  std::vector<int64_t> which;
  for (int64_t c = 0; c < geo.control_points; ++c) which.push_back(problem.num_points() - geo.control_points + c);
  const std::vector<Eigen::Matrix3d> sigma =
      PointCovariancesOf(problem, layout, result_.report.final_loss, inverse, which, lm_.num_threads);
  size_t c = 0;
  for (const GroundControlPoint& p : geo.gcps.points) {
    if (p.control && c < sigma.size()) result_.report.covariance.control_points.push_back({p.name, sigma[c++]});
  }
}

// The redundancy r and the variance factor σ̂₀² = Σρ / r, before any work:
// without redundancy a-posteriori has nothing to scale by.
void SolveSession::VarianceFactor(const UnknownLayout& layout, int free) {
  const Georeference& geo = result_.geo;
  SolveReport& report = result_.report;
  SolveReport::Covariance& c = report.covariance;
  c.unit = options_.covariance_unit;
  const int64_t priors = static_cast<int64_t>(geo.priors.priors.size());
  // The points solved last: after rejection rounds, those the last left.
  const int64_t points = rounds_.empty() ? report.num_points : rounds_.back().points_left;
  c.redundancy = 2 * report.solve.ba.lm.num_observations + 3 * (priors + geo.control_points) -
                 (layout.num_unknowns() + 3 * (points + geo.control_points)) + free;
  if (c.redundancy > 0) {
    c.variance_factor = 2.0 * report.solve.ba.lm.final_cost / static_cast<double>(c.redundancy);
  } else if (!c.unit) {
    throw std::runtime_error("--covariance: no redundancy (r = " + std::to_string(c.redundancy) +
                             "), no variance factor to scale by; use --covariance-scale unit");
  }
}

// Images and groups the data do not determine: in the report, and said.
void SolveSession::SayUndetermined(const CameraCovariances& covariances) {
  SolveReport::Covariance& c = result_.report.covariance;
  const auto name = [&](int64_t i) {
    const std::vector<std::string>& names = result_.names.problem;
    return i < static_cast<int64_t>(names.size()) ? names[i] : std::to_string(i);
  };
  for (int64_t i : covariances.undetermined_images) c.undetermined_images.push_back(name(i));
  c.undetermined_groups = covariances.undetermined_groups;
  if (options_.quiet || (c.undetermined_images.empty() && c.undetermined_groups.empty())) return;
  if (!c.undetermined_images.empty()) {
    out_ << "covariance: " << c.undetermined_images.size() << " image(s) the data do not determine (first: "
         << c.undetermined_images[0] << ": too few observations?), marked undetermined in "
         << options_.covariance_path << "; the rest computed without their undetermined directions\n";
  }
  if (!c.undetermined_groups.empty()) {
    out_ << "covariance: " << c.undetermined_groups.size() << " intrinsic group(s) with a parameter nothing "
         << "observes (first: group " << c.undetermined_groups[0] << " (0-based)), left out of the report\n";
  }
}

void SolveSession::TakeCovariance(const Problem& problem, const RcsSystem& rcs) {
  const Georeference& geo = result_.geo;
  const GaugeFreedom freedom = FreedomAtOptimum(problem, !geo.priors.empty() || geo.control_points > 0);
  // The undetermined directions are free too: r counts the determined.
  UndeterminedUnknowns undetermined = FindUndeterminedUnknowns(rcs.S);
  VarianceFactor(rcs.layout, freedom.free + static_cast<int>(undetermined.pins.size()));
  if (!options_.quiet) out_ << "covariance: selected inversion of S at the optimum\n";
  const Timer timer;
  const CameraSideInverse inverse(problem, rcs, freedom, lm_.num_threads, std::move(undetermined));
  result_.covariance = CameraBlocks(problem, rcs.layout, inverse);
  SayUndetermined(*result_.covariance);
  if (!options_.point_covariance_path.empty()) {
    result_.point_covariance =
        PointCovariances(problem, rcs.layout, result_.report.final_loss, inverse, lm_.num_threads);
    int64_t& undetermined = result_.report.covariance.undetermined_points = 0;
    for (const Eigen::Matrix3d& p : result_.point_covariance) undetermined += !p.allFinite();
    if (undetermined > 0 && !options_.quiet) {
      out_ << "covariance: " << undetermined << " point(s) their observations do not determine (one "
           << "observation, or parallel rays): their lines in " << options_.point_covariance_path << " are empty\n";
    }
  }
  ControlPointSigmas(problem, rcs.layout, inverse);
  SolveReport::Covariance& c = result_.report.covariance;
  c.computed = true;
  c.datum = freedom.free == 0 ? "absolute" : "inner";
  c.factor_nonzeros = result_.covariance->factor_nonzeros = inverse.factor_values();
  c.inversion_flops = result_.covariance->inversion_flops = inverse.inversion_flops();
  c.factor_seconds = result_.covariance->factor_seconds = inverse.factor_seconds();
  c.seconds = result_.covariance->seconds = timer.Seconds();
  for (const IntrinsicsCovariance& g : result_.covariance->intrinsics) {
    c.intrinsics.push_back({g.group, g.parameters, c.Scale() * g.covariance});
  }
  for (auto& point : c.control_points) point.covariance *= c.Scale();
  std::erase_if(c.control_points, [](const auto& p) { return !p.covariance.allFinite(); });
}

}  // namespace dba
