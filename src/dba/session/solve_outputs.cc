// What a solve writes; see solve_outputs.h.
#include "dba/session/solve_outputs.h"

#include <cmath>
#include <iostream>
#include <limits>
#include <ostream>

#include "dba/common/error.h"
#include "dba/common/fault_seam.h"
#include "dba/common/memory.h"
#include "dba/common/timer.h"
#include "dba/io/atomic_output_file.h"
#include "dba/io/binary_problem.h"
#include "dba/io/path_kind.h"
#include "dba/io/ply_writer.h"
#include "dba/io/read_problem.h"
#include "dba/precision/covariance_csv.h"
#include "dba/session/run_files.h"

namespace dba {
namespace {

// --ply-colour sigma: each point's sqrt(trace/3) on the ramp (control
// points after the loaded ones, and undetermined points: NaN, blue).
std::vector<uint8_t> SigmaColours(const SolveResult& result) {
  std::vector<double> sigma(result.problem.num_points(), std::numeric_limits<double>::quiet_NaN());
  for (size_t k = 0; k < result.point_covariance.size() && k < sigma.size(); ++k) {
    sigma[k] = std::sqrt(result.point_covariance[k].trace() / 3.0);
  }
  return RampColours(sigma);
}

// --ply: the points left, with a COLMAP input's colours or by sigma.
void WritePointCloud(const SolveOptions& options, const SolveResult& result,
                     const std::optional<ColmapInput>& colmap) {
  std::vector<uint8_t> rgb;
  if (options.ply_sigma) {
    rgb = SigmaColours(result);
  } else if (colmap) {
    rgb = PointColours(*colmap);
    if (result.kept) {  // the colours of the points left
      std::vector<uint8_t> left;
      for (size_t k = 0; k < result.kept->point.size(); ++k) {
        if (result.kept->point[k]) left.insert(left.end(), &rgb[3 * k], &rgb[3 * k + 3]);
      }
      rgb.swap(left);
    }
  }
  const std::vector<double>& points = result.problem.points;
  WritePointCloudPly(options.ply_path,
                     options.geo.output_crs.empty() ? points
                                                    : InOutputCrs(options.geo, result.geo, points),
                     rgb);
}

// -o: a COLMAP model, a .dba streamed from a .dba the ranks read, or the
// problem (read again where the ranks held its observations).
void WriteAdjustedProblem(const SolveOptions& options, int ranks, SolveResult* result,
                          std::optional<ColmapInput>* colmap) {
  Problem& problem = result->problem;
  const bool kept = result->kept.has_value();
  const OutputKind kind =
      CheckOutput(result->source, options.output, problem.model, options.colmap_format);
  if (kind == OutputKind::kColmap) {
    WriteColmapOutput(problem.cameras, kept ? result->all_points : problem.points, options.output,
                      options.colmap_format, &**colmap, kept ? &*result->kept : nullptr);
    return;
  }
  if (ranks > 1 && result->ranks_read_file && kind == OutputKind::kBinary && !kept) {
    // Binary to binary: stream the observations from the input; the camera
    // side (values and what was held fixed) is the solve's.
    WriteBinaryWithNewParameters(options.input, options.output, problem, problem.points);
    return;
  }
  if (ranks > 1) {
    // The observations were handed to the ranks (and released here, so the
    // main rank's memory during the solve is its share's): read them again.
    Problem full = *colmap ? std::move((*colmap)->source.problem)
                           : LoadSolveInput(result->source, options.unknowns);
    full.cameras.swap(problem.cameras);
    full.points.swap(kept ? result->all_points : problem.points);
    if (kept) KeepOnly(*result->kept, &full);
    problem = std::move(full);
  }
  WriteProblem(problem, options.output);
}

// A lens model COLMAP 3.8 cannot read (it knows ids 0-10, up to
// THIN_PRISM_FISHEYE): refused for --colmap-version 3.8, else a warning.
void CheckColmapVersion(const SolveOptions& options, const CameraSide& side) {
  constexpr int kLastOf38 = static_cast<int>(LensModel::kThinPrismFisheye);
  for (int64_t g = 0; g < side.num_groups(); ++g) {
    const LensModel m = side.group_model(g);
    if (static_cast<int>(m) <= kLastOf38) continue;
    const std::string what = "-o " + options.output + ": intrinsic group " + std::to_string(g) +
                             " is " + Info(m).name + ", which COLMAP 3.8 (Debian 12's) cannot read";
    if (options.colmap_38) throw UsageError(what + " (--colmap-version 3.8)");
    std::cerr << "dba solve: warning: " << what
              << "; a newer COLMAP reads it (--colmap-version 3.8 refuses such an output)\n";
    return;
  }
}

}  // namespace

std::vector<int64_t> LoadedPointIndices(const SolveResult& result) {
  std::vector<int64_t> loaded;
  const int64_t count = result.report.num_points;
  for (int64_t k = 0; k < count; ++k) {
    if (!result.kept || result.kept->point[k]) loaded.push_back(k);
  }
  return loaded;
}

void CheckSolveFiles(const SolveOptions& o, const InputSource& input) {
  RunFiles files;
  files.Input("INPUT", o.input);
  files.Input("--truth", o.truth_path);
  files.Input("--resume", o.resume_path);
  files.Input("--camera-priors", o.geo.camera_priors_path);
  files.Input("--gcps", o.geo.gcps_path);
  if (!o.output.empty() && KindOfPath(o.output) == PathKind::kOther && input.colmap()) {
    files.ModelOutput("-o", o.output, o.colmap_format.value_or(input.colmap_format),
                      HasRigsOrFrames(o.input));
  } else {
    files.Output("-o", o.output);
  }
  files.Output("--report", o.report_path);
  files.Output("--ply", o.ply_path);
  files.RewrittenOutput("--checkpoint", o.checkpoint_path);
  files.Output("--camera-centres", o.geo.camera_centres_path);
  files.Output("--accuracy-report", o.geo.accuracy_report_path);
  files.Output("--covariance", o.covariance_path);
  files.Output("--point-covariance", o.point_covariance_path);
  files.AllowInPlace("-o", "INPUT");
  files.AllowInPlace("--checkpoint", "--resume");
  files.Check();
}

void CheckSolveOutputs(const SolveOptions& options, const SolveInput& input,
                       const Communicator& comm) {
  if (!comm.is_main() || options.output.empty()) return;
  const CameraModel model = input.ranks_read_file ? ReadBinaryProblemHeader(input.name).model
                                                  : input.problem.model;
  if (CheckOutput(input.source, options.output, model, options.colmap_format) ==
      OutputKind::kColmap) {
    CheckColmapVersion(options, input.problem);
  }
}

void WriteSolveOutputs(const SolveOptions& options, int ranks, const Timer& since_start,
                       SolveResult* result, std::ostream& out) {
  // Every output of the run appears when all are written, or none does.
  OutputTransaction outputs;
  SolveReport& report = result->report;
  Timer write_timer;
  if (ranks > 1) FaultPoint(0, "write", 1);
  // A COLMAP input is read once more, for what the outputs keep from it
  // (names, colours, tracks; the observations a distributed run handed out).
  // Deliberate: keeping the model through the solve instead would hold about
  // 32 bytes per observation (its points2D and tracks) beside the problem's
  // 20, in the phase where memory peaks; the re-read costs time only.
  std::optional<ColmapInput> colmap;
  if (result->source.colmap() && (!options.output.empty() || !options.ply_path.empty())) {
    colmap = ReadColmapInput(result->source, options.unknowns);
  }
  if (!options.ply_path.empty()) WritePointCloud(options, *result, colmap);
  if (!options.output.empty()) {
    WriteAdjustedProblem(options, ranks, result, &colmap);
  }
  if (!options.geo.camera_centres_path.empty()) {
    // Named as the input names them (COLMAP), else by index.
    WriteCameraCentres(options.geo, result->geo, result->problem, result->names.problem);
  }
  if (!options.geo.accuracy_report_path.empty()) {
    WriteFileAtomically(options.geo.accuracy_report_path, AccuracyReportTable(report.geo.accuracy));
  }
  if (result->covariance) {
    const double scale = report.covariance.Scale();
    std::vector<Vec3> centres;
    for (int64_t i = 0; i < result->problem.num_images(); ++i) {
      centres.push_back(CameraCentre(result->problem.camera(i)));
    }
    WriteFileAtomically(options.covariance_path, CovarianceCsv(*result->covariance, result->names.problem,
                                                               centres, result->gauge_moved, scale));
  }
  if (!options.point_covariance_path.empty() && result->covariance) {
    WriteFileAtomically(options.point_covariance_path,
                        PointCovarianceCsv(result->point_covariance, LoadedPointIndices(*result),
                                           result->gauge_moved, report.covariance.Scale()));
  }
  report.write_seconds = write_timer.Seconds();
  report.peak_memory_bytes = PeakResidentBytes();
  report.total_seconds = since_start.Seconds();
  const nlohmann::ordered_json summary = SolveSummary(report);
  if (!options.report_path.empty()) WriteFileAtomically(options.report_path, summary.dump(2) + "\n");
  outputs.Commit();
  PrintSolveSummary(summary, out);
  if (!options.output.empty()) out << "  output              " << options.output << "\n";
  if (!options.ply_path.empty()) out << "  point cloud         " << options.ply_path << "\n";
  if (!options.report_path.empty()) out << "  report              " << options.report_path << "\n";
  if (result->covariance) out << "  covariance          " << options.covariance_path << "\n";
}

}  // namespace dba

namespace dba {

SolveResult RunSolve(const SolveOptions& options, Communicator* comm, std::ostream& out,
                     const Timer& since_start) {
  const double startup_seconds = since_start.Seconds();
  const InputSource source = DecideInput(options.input);  // on every rank: all read
  if (comm->is_main()) CheckSolveFiles(options, source);
  const Timer read;
  SolveInput input = LoadInput(options, source, comm);
  input.read_seconds = read.Seconds();
  CheckSolveOutputs(options, input, *comm);
  SolveResult result = SolveSession(options, comm, out).Run(std::move(input));
  result.report.startup_seconds = startup_seconds;
  if (comm->is_main()) WriteSolveOutputs(options, comm->size(), since_start, &result, out);
  if (!result.covariance_error.empty()) {
    throw std::runtime_error(result.covariance_error + " (the solve's other outputs are written; no covariance file)");
  }
  return result;
}

}  // namespace dba
