// `dba solve`; see solve_command.h.
#include "dba/app/solve_command.h"

#include <omp.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <functional>
#include <memory>
#include <iostream>
#include <sstream>
#include <stdexcept>
#include <thread>

#include "dba/camera/observation_residual.h"
#include "dba/common/memory.h"
#include "dba/io/checkpoint.h"
#include "dba/common/error.h"
#include "dba/common/progress.h"
#include "dba/common/timer.h"
#include "dba/io/atomic_output_file.h"
#include "dba/io/text_line_reader.h"
#include "dba/io/read_problem.h"
#include "dba/io/bal_writer.h"
#include "dba/io/ply_writer.h"
#include "dba/app/arguments.h"
#include "dba/app/run_files.h"
#include "dba/io/path_kind.h"
#include "dba/app/solve_report.h"
#include "dba/cluster/mpi_point_workers.h"
#include "dba/synthetic/ground_truth.h"
#include "dba/synthetic/uav_generator.h"
#include "dba/lm/bundle_adjust.h"

namespace dba {
namespace {

#ifdef DBA_HAVE_CHOLMOD
#define DBA_SPARSE_NAME "CHOLMOD"
#else
#define DBA_SPARSE_NAME "Eigen"
#endif

int DefaultThreads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

}  // namespace

void PrintSolveHelp(std::ostream& out) {
  const LmOptions d;
  out << "Usage: dba solve INPUT [options]\n"
         "\n"
         "Bundle-adjusts INPUT with exact Levenberg-Marquardt: the reduced camera\n"
         "system is formed point by point in BSMC and solved by a dense or sparse\n"
         "Cholesky factorization or by truncated-Newton PCG, whichever is cheapest.\n"
         "Prints one line per iteration and a summary.\n"
         "\n"
         "INPUT is a BAL problem (plain text or .bz2; 9 parameters per camera), a dba\n"
         "binary problem (.dba; BAL cameras, or poses and shared intrinsics, e.g. from\n"
         "dba generate --model photo), or a COLMAP sparse model directory (cameras, images,\n"
         "points3D as .txt or .bin; e.g. project/sparse/0). A COLMAP model is solved\n"
         "in the photogrammetric model: per image a pose (6 unknowns), per physical\n"
         "camera an intrinsic group f, cx, cy, k1, k2 shared by its images\n"
         "(SIMPLE_PINHOLE, PINHOLE, SIMPLE_RADIAL, RADIAL; parameters a camera model\n"
         "lacks stay 0). Points with fewer than 2 observations are not adjusted.\n"
         "\n"
         "Distributed: started by mpirun or srun with N ranks, the points are split\n"
         "over the ranks, each forms its sub-RCS, rank 0 aggregates and solves.\n"
         "\n"
         "Options:\n"
         "  -o, --output PATH          write the adjusted problem: .txt/.bz2 BAL text,\n"
         "                             .dba binary, or (COLMAP input) a COLMAP model in the\n"
         "                             directory PATH (names, ids, colours and tracks kept);\n"
         "                             files are written to a temporary name and renamed\n"
         "  --colmap-format text|binary\n"
         "                             format of a COLMAP output (default: the input's)\n"
         "  --ply FILE                 write the adjusted points as a binary PLY point cloud,\n"
         "                             with the COLMAP colours, else coloured by height z\n"
         "                             from blue (low) to red (high)\n"
         "  --intrinsics shared|per-image\n"
         "                             COLMAP input: one intrinsic group per COLMAP camera\n"
         "                             (default: shared), or one per image\n"
         "  --fix-intrinsics [GROUP:]NAMES\n"
         "                             hold intrinsics fixed by name: all, or a comma-\n"
         "                             separated list of the groups' lens models' names\n"
         "                             (COLMAP's: f, fx, fy, cx, cy, k1, k2, p1, p2, ...;\n"
         "                             see dba solve --list-camera-models), in every group\n"
         "                             whose model has the name, or in GROUP only (a COLMAP\n"
         "                             camera id, or a 0-based group of a .dba problem);\n"
         "                             repeatable (photogrammetric model only)\n"
         "  --list-camera-models       print the lens models and their parameter names\n"
         "  --fix-images LIST          hold these images' poses fixed (gauge): COLMAP image\n"
         "                             ids for a COLMAP input, 0-based camera indices\n"
         "                             otherwise (a BAL camera is then fixed whole)\n"
         "  --report FILE.json         write the summary and per-iteration log as JSON\n"
         "  --checkpoint FILE          after each accepted LM iteration, write the parameters\n"
         "                             and the LM state to FILE (whole or not at all), to\n"
         "                             --resume from (rank 0 writes it in a distributed\n"
         "                             run; not with --reject-outliers)\n"
         "  --checkpoint-every S       at most one checkpoint per S seconds (default 0: after\n"
         "                             every accepted iteration)\n"
         "  --resume FILE              continue the solve of INPUT (the same input and\n"
         "                             fixings) from a --checkpoint FILE: it ends where the\n"
         "                             uninterrupted solve would\n"
         "  --truth FILE               ground truth of a generated problem (dba generate\n"
         "                             --truth): report the RMS against the noise-free\n"
         "                             observations, the camera/point errors after a\n"
         "                             similarity alignment and, photogrammetric model,\n"
         "                             each intrinsic group's errors (f, cx, cy, k1, k2)\n"
         "  --truth-absolute           with --truth: compare with no alignment (a\n"
         "                             georeferenced solve is in the truth's frame)\n"
         "  -t, --threads N            threads per rank (default: the node's cores divided\n"
         "                             by its ranks; " << DefaultThreads() << " cores here)\n"
         "  --loss trivial|huber|soft_l1|cauchy|arctan|tukey\n"
         "                             robust loss of each observation's squared reprojection\n"
         "                             error s, Ceres's definitions: the cost is 1/2 sum rho(s)\n"
         "                             (default " << LossName(d.loss.type) << ": rho(s) = s)\n"
         "  --loss-scale PX            the loss's scale a in pixels: residuals beyond it are\n"
         "                             down-weighted (and count as outliers in the RMS\n"
         "                             figures) (default " << d.loss.scale << ")\n"
         "  --reject-outliers PX       after the solve, drop observations whose reprojection\n"
         "                             error exceeds PX pixels and points left with fewer than\n"
         "                             2 or seen under --min-triangulation-angle, then solve\n"
         "                             again; until a round drops under 0.05%\n"
         "                             of the observations, at most 5 rounds; the outputs\n"
         "                             leave what was dropped out (default: off).\n"
         "                             The solves after a round use the squared loss, the\n"
         "                             efficient estimator once the outliers are gone\n"
         "  --reject-keep-loss         keep --loss in the solves after a rejection round\n"
         "  --camera-priors FILE       GNSS camera centres in the solve: per line IMAGE X Y Z\n"
         "                             [SIGMA_XY SIGMA_Z], IMAGE a COLMAP image name or a\n"
         "                             0-based camera index, metres in a Cartesian frame;\n"
         "                             reports the agreement per axis, CE90/LE90 and the\n"
         "                             priors flagged as outliers (χ²₃ 99.9%)\n"
         "  --prior-crs CRS            the priors' coordinates in any 3D CRS PROJ knows\n"
         "                             (EPSG:4979: WGS84 latitude, longitude, ellipsoidal\n"
         "                             height, EPSG's axis order); the solve and its outputs\n"
         "                             are then in a local east-north-up frame at the priors'\n"
         "                             centre (origin and PROJ pipeline in the report)\n"
         "  --gcps FILE                ground control and check points: per point a line\n"
         "                             NAME X Y Z SIGMA_XY SIGMA_Z control|check, and per\n"
         "                             measurement NAME IMAGE x y (the input's pixel\n"
         "                             convention); control points are points of the solve\n"
         "                             with a prior, check points are triangulated after it\n"
         "                             and compared (docs/georeferencing.md)\n"
         "  --gcp-crs CRS              the GCPs' CRS (default: --prior-crs); converted to\n"
         "                             the same local frame, refused where PROJ has only a\n"
         "                             ballpark height transformation (a missing geoid grid)\n"
         "  --output-crs CRS           with a CRS given: --ply and --camera-centres in this\n"
         "                             3D CRS (converted back from the local frame by PROJ);\n"
         "                             the problem outputs stay in the local frame\n"
         "  --camera-centres FILE      the adjusted camera centres, IMAGE X Y Z per line\n"
         "  --accuracy-report FILE     with --camera-priors or --gcps: the figures as a\n"
         "                             table, and each prior's, control and check point's dx,\n"
         "                             dy, dz, squared Mahalanobis distance and flag\n"
         "  --prior-sigma XY,Z         σ of the priors that give none (metres; σ_xy per\n"
         "                             horizontal axis)\n"
         "  --prior-loss NAME          the priors' robust loss, in units of σ (default\n"
         "                             cauchy, chosen by measurement: bench/README.md)\n"
         "  --prior-loss-scale S       its scale in units of σ (default 3)\n"
         "  --min-triangulation-angle DEG\n"
         "                             with --reject-outliers: a point whose rays meet at\n"
         "                             less than DEG degrees (the largest angle between two of\n"
         "                             its observations' rays) goes too: its depth is not\n"
         "                             determined (default " << RejectionCriteria().min_triangulation_angle_deg << ", COLMAP's; 0: off)\n"
         "  --max-iterations N         LM iteration limit (default " << d.max_iterations << ")\n"
         "  --function-tolerance X     stop when a step lowers the cost by less than\n"
         "                             this fraction, unless its gain ratio was under\n"
         "                             1/4 and its model promised more (default "
      << d.function_tolerance << ")\n"
         "  --gradient-tolerance X     stop when max|J^T r| <= X (default " << d.gradient_tolerance << ")\n"
         "  --parameter-tolerance X    stop when |step| <= X (|x| + X), |x| with camera centres and\n"
         "                             points about their centroids (default " << d.parameter_tolerance << ")\n"
         "  --initial-lambda X         initial LM damping (default " << d.initial_lambda << ")\n"
         "  --linear-solver auto|dense|sparse|pcg\n"
         "                             how the reduced camera system is solved: dense\n"
         "                             Cholesky (small), sparse Cholesky (medium, " DBA_SPARSE_NAME "),\n"
         "                             PCG (large); auto (default) picks the cheapest by a\n"
         "                             cost model, a factorization only while its factor\n"
         "                             stays within " << d.linear_solver.max_factor_memory_ratio << "x what a PCG solve holds (RCS,\n"
         "                             preconditioner, vectors, problem data)\n"
         "  --eta X                    PCG's truncated-Newton stop (Nash-Sofer): end at\n"
         "                             iteration i when i (Q_i - Q_i-1) / Q_i < X for the\n"
         "                             quadratic model Q (default " << d.linear_solver.pcg.eta << ", 0: off)\n"
         "  --preconditioner jacobi|two-level\n"
         "                             PCG's preconditioner: block-Jacobi, or two-level\n"
         "                             (block-Jacobi plus a coarse solve over aggregates of\n"
         "                             neighbouring cameras; for long strips) (default\n"
         "                             " << PreconditionerName(d.linear_solver.preconditioner) << ")\n"
         "  --coarse-size N            two-level: cameras per aggregate (default " << d.linear_solver.coarse_aggregate_size << ")\n"
         "  --coarse-basis similarity|rigid|parameters\n"
         "                             two-level: the cameras of an aggregate share a\n"
         "                             similarity of the scene (rigid motion and scale), a\n"
         "                             rigid motion, or a parameter step (default\n"
         "                             " << CoarseBasisName(d.linear_solver.coarse_basis) << ")\n"
         "  --pcg-tolerance X          PCG also stops at this relative residual (default\n"
         "                             " << d.linear_solver.pcg.relative_tolerance << ")\n"
         "  --pcg-min-iterations N     PCG iterations before the --eta test is taken\n"
         "                             (default " << d.linear_solver.pcg.min_iterations << ")\n"
         "  --pcg-max-iterations N     PCG iteration limit, a safety net (default " << d.linear_solver.pcg.max_iterations << ")\n"
         "  --pcg-precision auto|mixed|double\n"
         "                             the RCS in PCG's product: mixed keeps its\n"
         "                             off-diagonal blocks in float (the product reads\n"
         "                             about half the bytes; exact to 6e-8 relative per\n"
         "                             value), double as formed; auto (default): mixed\n"
         "                             with the --eta stop until LM's damping reaches\n"
         "                             float's rounding (6e-8) and its steps would take\n"
         "                             it lower, double from then on; double when --eta\n"
         "                             is 0\n"
         "  --partition equal|cameras  how points are split over MPI ranks: 'equal' (the\n"
         "                             paper's equal counts) or 'cameras' (grouped by the\n"
         "                             cameras that see them; default)\n"
         "  --rcs auto|gather|distributed\n"
         "                             where the RCS lives with MPI: 'distributed' spreads\n"
         "                             its rows over the ranks and runs PCG across them\n"
         "                             (the --preconditioner's coarse solve on rank 0);\n"
         "                             'gather' sums it on rank 0, which solves alone (the\n"
         "                             paper's); auto (default): distributed with more\n"
         "                             than one rank, unless --linear-solver is dense or\n"
         "                             sparse\n"
         "  --main-rank auto|forms|coordinates\n"
         "                             whether rank 0 also forms a sub-RCS (auto: yes for\n"
         "                             up to 4 ranks)\n"
         "  --no-memory-check          start even when the memory estimate (printed before\n"
         "                             the first iteration) exceeds the memory available\n"
         "                             (MemAvailable, or a cgroup's limit; distributed: each\n"
         "                             rank against its part of its node's)\n"
         "  -q, --quiet                no per-iteration log, and no progress of long phases\n"
         "                             (shown on a terminal only: RCS formation, PCG,\n"
         "                             back-substitution, with the time left)\n"
         "  -h, --help                 this text\n"
         "\n"
         "Outputs (-o, --report, --ply, --checkpoint, --camera-centres,\n"
         "--accuracy-report) are checked before the solve. A file, or a path that does\n"
         "not exist yet, is written to a temporary beside it and renamed over it: the\n"
         "run's outputs appear together when all are written, or none does. A symbolic\n"
         "link is written through (the file it leads to is replaced, the link kept). A\n"
         "character device or a FIFO (/dev/null, a pipe) is written plainly. Anything\n"
         "else (a directory, a socket, /proc) is refused, and so is an output naming an\n"
         "input or another output, except -o over the problem it reads (a COLMAP model\n"
         "replaced whole) and --checkpoint F --resume F.\n"
         "\n"
         "Exit status: 0 on success (whatever the termination reason), 1 on bad\n"
         "input or failure, 2 on bad arguments (outputs refused by the rule above\n"
         "included).\n";
}

SolveCommandOptions ParseSolveArguments(const std::vector<std::string>& args,
                                        bool* help) {
  SolveCommandOptions o;
  o.lm.num_threads = 0;  // auto: the node's cores divided by its ranks
  *help = false;
  for (size_t i = 0; i < args.size(); ++i) {
    const std::string& a = args[i];
    auto value = [&]() -> const std::string& {
      if (i + 1 >= args.size()) throw std::invalid_argument(a + ": missing value");
      if (args[i + 1].empty()) throw std::invalid_argument(a + ": an empty value");
      return args[++i];
    };
    if (a == "-h" || a == "--help") {
      *help = true;
      return o;
    } else if (a == "-o" || a == "--output") {
      o.output = value();
    } else if (a == "--report") {
      o.report_path = value();
    } else if (a == "--truth") {
      o.truth_path = value();
    } else if (a == "--truth-absolute") {
      o.truth_absolute = true;
    } else if (a == "--ply") {
      o.ply_path = value();
    } else if (a == "--checkpoint") {
      o.checkpoint_path = value();
    } else if (a == "--checkpoint-every") {
      o.checkpoint_every_s = ParseNumberArgument(a, value());
    } else if (a == "--resume") {
      o.resume_path = value();
    } else if (a == "--colmap-format") {
      const std::string& v = value();
      if (v == "text") o.colmap_format = ColmapFormat::kText;
      else if (v == "binary") o.colmap_format = ColmapFormat::kBinary;
      else throw std::invalid_argument(a + ": expected text or binary, got '" + v + "'");
    } else if (a == "--intrinsics") {
      const std::string& v = value();
      if (v == "shared") o.unknowns.shared_intrinsics = true;
      else if (v == "per-image") o.unknowns.shared_intrinsics = false;
      else throw std::invalid_argument(a + ": expected shared or per-image, got '" + v + "'");
    } else if (a == "--fix-intrinsics") {
      o.unknowns.fixed_intrinsics.push_back(ParseIntrinsicFixing(a, value()));
    } else if (a == "--fix-images") {
      o.unknowns.fixed_images = ParseIdList(a, value());
    } else if (a == "-t" || a == "--threads") {
      o.lm.num_threads = static_cast<int>(ParseIntegerArgument(a, value(), 1, kMaxThreads));
    } else if (a == "--max-iterations") {
      o.lm.max_iterations = static_cast<int>(ParseIntegerArgument(a, value(), 0, 1000000000));
    } else if (a == "--function-tolerance") {
      o.lm.function_tolerance = ParseNumberArgument(a, value());
    } else if (a == "--gradient-tolerance") {
      o.lm.gradient_tolerance = ParseNumberArgument(a, value());
    } else if (a == "--parameter-tolerance") {
      o.lm.parameter_tolerance = ParseNumberArgument(a, value());
    } else if (a == "--initial-lambda") {
      o.lm.initial_lambda = ParseNumberArgument(a, value());
      if (o.lm.initial_lambda <= 0) throw std::invalid_argument(a + ": must be > 0");
    } else if (a == "--linear-solver") {
      const std::string& v = value();
      if (!ParseLinearSolver(v, &o.lm.linear_solver.type)) {
        throw std::invalid_argument(a + ": expected auto, dense, sparse or pcg, got '" + v + "'");
      }
    } else if (a == "--preconditioner") {
      const std::string& v = value();
      if (!ParsePreconditioner(v, &o.lm.linear_solver.preconditioner)) {
        throw std::invalid_argument(a + ": expected jacobi or two-level, got '" + v + "'");
      }
    } else if (a == "--coarse-size") {
      o.lm.linear_solver.coarse_aggregate_size =
          static_cast<int>(ParseIntegerArgument(a, value(), 1, 1000000000));
    } else if (a == "--loss") {
      const std::string& v = value();
      if (!ParseLoss(v, &o.lm.loss.type)) {
        throw std::invalid_argument(a + ": expected trivial, huber, soft_l1, cauchy, arctan or tukey, got '" + v + "'");
      }
    } else if (a == "--loss-scale") {
      o.lm.loss.scale = ParseNumberArgument(a, value());
      if (!(o.lm.loss.scale > 0.0)) throw std::invalid_argument(a + ": must be > 0 (pixels)");
    } else if (a == "--no-memory-check") {
      o.memory_check = false;
    } else if (a == "--min-triangulation-angle") {
      o.min_triangulation_angle_deg = ParseNumberArgument(a, value());
      if (!(o.min_triangulation_angle_deg >= 0.0 && o.min_triangulation_angle_deg < 180.0)) {
        throw std::invalid_argument(a + ": must be in [0, 180) (degrees)");
      }
    } else if (a == "--reject-keep-loss") {
      o.reject_keep_loss = true;
    } else if (a == "--camera-priors") {
      o.geo.camera_priors_path = value();
    } else if (a == "--prior-sigma") {
      const auto [xy, z] = ParseSigmaPair(a, value());
      o.geo.prior_sigma = Eigen::Vector2d(xy, z);
    } else if (a == "--accuracy-report") {
      o.geo.accuracy_report_path = value();
    } else if (a == "--prior-crs") {
      o.geo.prior_crs = value();
    } else if (a == "--gcps") {
      o.geo.gcps_path = value();
    } else if (a == "--gcp-crs") {
      o.geo.gcp_crs = value();
    } else if (a == "--output-crs") {
      o.geo.output_crs = value();
    } else if (a == "--camera-centres") {
      o.geo.camera_centres_path = value();
    } else if (a == "--prior-loss") {
      const std::string& v = value();
      if (!ParseLoss(v, &o.geo.prior_loss.type)) {
        throw std::invalid_argument(a + ": expected trivial, huber, soft_l1, cauchy, arctan or tukey, got '" + v + "'");
      }
    } else if (a == "--prior-loss-scale") {
      o.geo.prior_loss.scale = ParseNumberArgument(a, value());
      if (!(o.geo.prior_loss.scale > 0.0)) throw std::invalid_argument(a + ": must be > 0 (in units of σ)");
    } else if (a == "--reject-outliers") {
      o.reject_outliers_px = ParseNumberArgument(a, value());
      if (!(o.reject_outliers_px > 0.0)) throw std::invalid_argument(a + ": must be > 0 (pixels)");
    } else if (a == "--coarse-basis") {
      const std::string& v = value();
      if (!ParseCoarseBasis(v, &o.lm.linear_solver.coarse_basis)) {
        throw std::invalid_argument(a + ": expected similarity, rigid or parameters, got '" + v + "'");
      }
    } else if (a == "--eta") {
      o.lm.linear_solver.pcg.eta = ParseNumberArgument(a, value());
      if (o.lm.linear_solver.pcg.eta < 0) throw std::invalid_argument(a + ": must be >= 0");
    } else if (a == "--pcg-tolerance") {
      o.lm.linear_solver.pcg.relative_tolerance = ParseNumberArgument(a, value());
    } else if (a == "--pcg-min-iterations") {
      o.lm.linear_solver.pcg.min_iterations =
          static_cast<int>(ParseIntegerArgument(a, value(), 0, 1000000000));
    } else if (a == "--pcg-precision") {
      const std::string& v = value();
      if (!ParsePcgPrecision(v, &o.lm.linear_solver.pcg.precision)) {
        throw std::invalid_argument(a + ": expected auto, mixed or double, got '" + v + "'");
      }
    } else if (a == "--pcg-max-iterations") {
      o.lm.linear_solver.pcg.max_iterations =
          static_cast<int>(ParseIntegerArgument(a, value(), 1, 1000000000));
    } else if (a == "--partition") {
      try {
        o.distributed.partition = ParsePartitionScheme(value());
      } catch (const std::invalid_argument& e) {
        throw std::invalid_argument(a + ": " + e.what());
      }
    } else if (a == "--rcs") {
      const std::string& v = value();
      using Rcs = DistributedOptions::Rcs;
      if (v == "auto") o.distributed.rcs = Rcs::kAuto;
      else if (v == "gather") o.distributed.rcs = Rcs::kGather;
      else if (v == "distributed") o.distributed.rcs = Rcs::kDistributed;
      else throw std::invalid_argument(a + ": expected auto, gather or distributed, got '" + v + "'");
    } else if (a == "--main-rank") {
      const std::string& v = value();
      using Role = DistributedOptions::MainRole;
      if (v == "auto") o.distributed.main_role = Role::kAuto;
      else if (v == "forms") o.distributed.main_role = Role::kForms;
      else if (v == "coordinates") o.distributed.main_role = Role::kCoordinates;
      else throw std::invalid_argument(a + ": expected auto, forms or coordinates, got '" + v + "'");
    } else if (a == "-q" || a == "--quiet") {
      o.quiet = true;
    } else if (!a.empty() && a[0] == '-') {
      throw std::invalid_argument("unknown option '" + a + "' (see dba solve --help)");
    } else if (o.input.empty()) {
      o.input = a;
    } else {
      throw std::invalid_argument("more than one input file: '" + o.input +
                                  "' and '" + a + "'");
    }
  }
  if (o.input.empty()) throw std::invalid_argument("missing INPUT (see dba solve --help)");
  if (o.colmap_format.has_value() && o.output.empty()) {
    throw std::invalid_argument("--colmap-format: no -o output to write");
  }
  if ((!o.checkpoint_path.empty() || !o.resume_path.empty()) && o.reject_outliers_px > 0) {
    throw std::invalid_argument("--checkpoint and --resume do not combine with --reject-outliers yet");
  }
  if (o.checkpoint_every_s > 0 && o.checkpoint_path.empty()) {
    throw std::invalid_argument("--checkpoint-every: no --checkpoint to write");
  }
  if (!o.geo.accuracy_report_path.empty() && !o.geo.any()) {
    throw std::invalid_argument("--accuracy-report needs --camera-priors FILE or --gcps FILE");
  }
  if (!o.geo.output_crs.empty() && !o.geo.any()) {
    throw std::invalid_argument("--output-crs needs --camera-priors or --gcps in a CRS");
  }
  if (!o.geo.gcp_crs.empty() && o.geo.gcps_path.empty()) {
    throw std::invalid_argument("--gcp-crs: no --gcps FILE");
  }
  if (!o.resume_path.empty() && !o.geo.gcps_path.empty()) {
    throw std::invalid_argument("--resume does not combine with --gcps yet (the checkpoint holds "
                                "the control points among the points)");
  }
  if (o.truth_absolute && o.truth_path.empty()) {
    throw std::invalid_argument("--truth-absolute needs --truth FILE");
  }
  if (o.distributed.rcs == DistributedOptions::Rcs::kDistributed) {
    if (o.lm.linear_solver.type == LinearSolverType::kDense ||
        o.lm.linear_solver.type == LinearSolverType::kSparse) {
      throw std::invalid_argument(std::string("--rcs distributed solves by PCG; --linear-solver ") +
                                  LinearSolverName(o.lm.linear_solver.type) +
                                  " needs --rcs gather");
    }
  }
  return o;
}

namespace {

// Every file the run reads and writes, checked before the input is read
// (app/run_files.h): -o may replace the problem it reads, --checkpoint the
// checkpoint --resume reads; any other output naming an input or another
// output is refused.
void CheckRunFiles(const SolveCommandOptions& o) {
  RunFiles files;
  files.Input("INPUT", o.input);
  files.Input("--truth", o.truth_path);
  files.Input("--resume", o.resume_path);
  files.Input("--camera-priors", o.geo.camera_priors_path);
  files.Input("--gcps", o.geo.gcps_path);
  if (!o.output.empty() && KindOfPath(o.output) == PathKind::kOther && IsColmapInput(o.input)) {
    files.ModelOutput("-o", o.output, o.colmap_format.value_or(*DetectColmapFormat(o.input)));
  } else {
    files.Output("-o", o.output);
  }
  files.Output("--report", o.report_path);
  files.Output("--ply", o.ply_path);
  files.Output("--checkpoint", o.checkpoint_path);
  files.Output("--camera-centres", o.geo.camera_centres_path);
  files.Output("--accuracy-report", o.geo.accuracy_report_path);
  files.AllowInPlace("-o", "INPUT");
  files.AllowInPlace("--checkpoint", "--resume");
  files.Check();
}

// The ground truth must exist and have the problem's counts (checked again,
// in full, after the solve).
void CheckTruthFile(const std::string& path, const SolveReport& report) {
  int64_t cameras = 0, points = 0, observations = 0;
  if (IsBinaryProblem(path)) {
    const BinaryProblemHeader h = ReadBinaryProblemHeader(path);
    cameras = h.num_cameras, points = h.num_points, observations = h.num_observations;
  } else {
    // The header line only: the whole truth is read after the solve.
    TextLineReader reader(path);
    std::string_view line;
    while (reader.ReadLine(&line) && line.find_first_not_of(" \t\r") == std::string_view::npos) {
    }
    std::istringstream header{std::string(line)};
    if (!(header >> cameras >> points >> observations)) {
      throw InputError(path, reader.line_number(),
                       "expected header 'num_cameras num_points num_observations'");
    }
  }
  if (cameras != report.num_cameras || points != report.num_points ||
      observations != report.num_observations) {
    throw UsageError("--truth " + path + ": " + std::to_string(cameras) + " cameras, " +
                     std::to_string(points) + " points, " + std::to_string(observations) +
                     " observations; the problem has " + std::to_string(report.num_cameras) +
                     ", " + std::to_string(report.num_points) + ", " +
                     std::to_string(report.num_observations));
  }
}

// Writes the problem's points into `all` at their loaded positions.
void ScatterPoints(const Problem& problem, const OriginalIndices& original,
                   std::vector<double>* all) {
  for (size_t k = 0; k < original.point.size(); ++k) {
    for (int d = 0; d < 3; ++d) (*all)[3 * original.point[k] + d] = problem.points[3 * k + d];
  }
}

// The log line of one round of --reject-outliers.
std::string RejectionRoundLine(const RejectionCriteria& criteria, int r, const RejectionRound& round) {
  char line[256];
  std::snprintf(line, sizeof line,
                "outlier rejection round %d (|r| > %g px, angle < %g deg): dropped %lld "
                "observations and %lld points (%lld for their angle); %lld observations, %lld "
                "points left\n",
                r, criteria.max_error_px, criteria.min_triangulation_angle_deg,
                static_cast<long long>(round.observations_dropped),
                static_cast<long long>(round.points_dropped),
                static_cast<long long>(round.points_small_angle),
                static_cast<long long>(round.observations_left),
                static_cast<long long>(round.points_left));
  return line;
}

// Rounds of --reject-outliers after the first solve, in one process; the
// points in the loaded numbering kept in `all_points`.
void RejectOutlierRounds(const RejectionCriteria& criteria, const LmOptions& resolve,
                         const std::function<void(const IterationSummary&)>& log,
                         const CameraPriors& priors, Problem* problem, OriginalIndices* original,
                         std::vector<double>* all_points, SolveReport* report, std::ostream& out) {
  *all_points = problem->points;
  report->rejection = RunRejectionRounds(
      [&] {
        ScatterPoints(*problem, *original, all_points);
        return DropOutliers(criteria, resolve.num_threads, problem, original);
      },
      [&] {
        AppendSolve(BundleAdjust(resolve, problem, log, {}, &priors), &report->solve.ba);
        report->final_loss = resolve.loss;
      },
      [&](int r, const RejectionRound& round) {
        out << RejectionRoundLine(criteria, r, round) << std::flush;
      });
  ScatterPoints(*problem, *original, all_points);
}

// The generator's mismatches among the loaded observations (their pixels
// `loaded_pixels`, the truth's order), and how many of them and of the true
// inliers the rejection dropped.
void CountTrueOutliers(const Problem& truth, const std::vector<double>& loaded_pixels,
                       const OriginalIndices& original, SolveReport* report) {
  if (static_cast<int64_t>(loaded_pixels.size()) != 2 * truth.num_observations()) {
    throw std::invalid_argument("the ground truth does not match the problem (different numbers "
                                "of observations)");
  }
  std::vector<uint8_t> kept(truth.num_observations(), 0);
  for (int64_t o : original.observation) kept[o] = 1;
  for (int64_t o = 0; o < truth.num_observations(); ++o) {
    const bool outlier = IsTrueOutlier(loaded_pixels.data() + 2 * o, truth.pixel(o));
    (outlier ? report->true_outliers : report->true_inliers) += 1;
    if (!kept[o]) (outlier ? report->true_outliers_dropped : report->true_inliers_dropped) += 1;
  }
  report->has_outlier_truth = true;
}

}  // namespace

// A problem whose initial cost is not finite cannot be adjusted: refused,
// naming the first observations that make it so.
void RefuseNonFiniteResiduals(const std::string& input, const Problem& problem) {
  const NonFiniteResiduals bad = FindNonFiniteResiduals(problem);
  if (bad.count == 0) return;
  std::string where;
  for (const NonFiniteResiduals::Where& w : bad.first) {
    where += (where.empty() ? "" : "; ") + std::string("observation ") +
             std::to_string(w.observation) + " (camera " + std::to_string(w.camera) +
             ", point " + std::to_string(w.point) + ")";
  }
  throw std::runtime_error(input + ": " + std::to_string(bad.count) +
                           " observation(s) have a non-finite reprojection error (nan or inf) at "
                           "the initial parameters, e.g. " + where +
                           "; correct or remove them (a point at a camera centre, or values "
                           "beyond double range)");
}

int RunSolveCommand(const SolveCommandOptions& options, Communicator* comm,
                    std::ostream& out, SolveOutcome* outcome) {
  const bool main = comm->is_main();
  LmOptions lm = options.lm;
  if (lm.num_threads == 0) {
    lm.num_threads = std::max(1, DefaultThreads() / comm->ranks_on_node());
  }
  // Every parallel region without a count of its own (loading, the
  // symbolic phase) takes the solve's threads too.
  omp_set_num_threads(lm.num_threads);
  // Progress of long phases: the main rank, on a terminal, without -q.
  EnableProgress(main && !options.quiet && options.progress);
  SolveReport report;
  report.input = options.input;
  report.threads = lm.num_threads;
  report.loss = lm.loss;
  report.final_loss = lm.loss;
  Problem problem;
  // Distributed runs on a binary file: every rank reads its own points;
  // not when georeferencing, which moves the whole block and adds control
  // points before the solve (the main rank reads it all and hands it out).
  const bool ranks_read_file =
      comm->size() > 1 && IsBinaryProblem(options.input) && !options.geo.any();
  std::optional<Checkpoint> resumed;  // main rank
  Georeference geo;                   // main rank: --camera-priors, --gcps
  ImageNames colmap_names;  // main rank, georeferencing or --camera-centres: a COLMAP input's
  if (main) {
    Timer load_timer;
    CheckRunFiles(options);
    CameraModel model = CameraModel::kBal;
    if (ranks_read_file) {
      const BinaryProblemHeader h = ReadBinaryProblemHeader(options.input);
      model = h.model;
      report.num_intrinsic_groups = h.num_intrinsics;
      report.num_cameras = h.num_cameras;
      report.num_points = h.num_points;
      report.num_observations = h.num_observations;
      // Checked here, before the solve; every rank holds them fixed in the
      // camera side it reads (the same command line on every rank).
      CheckedFixings(options.unknowns, ReadBinaryCameraSide(options.input));
    } else {
      problem = LoadSolveInput(options.input, options.unknowns,
                               options.geo.any() || !options.geo.camera_centres_path.empty()
                                   ? &colmap_names
                                   : nullptr);
      model = problem.model;
      report.num_cameras = problem.num_images();
      report.num_intrinsic_groups = problem.num_groups();
      report.num_points = problem.num_points();
      report.num_observations = problem.num_observations();
      report.problem_bytes = problem.MemoryBytes();
    }
    if (!options.resume_path.empty()) {
      resumed = ReadCheckpoint(options.resume_path);
      // Spread over the ranks, the problem is checked against it there.
      if (!ranks_read_file) ApplyCheckpoint(std::move(*resumed), options.resume_path, &problem);
      lm.initial_lambda = resumed->lambda;
      lm.iterations_done = static_cast<int>(resumed->iterations);
      lm.accepted_done = static_cast<int>(resumed->accepted);
      out << "resumed from " << options.resume_path << " after LM iteration "
          << resumed->iterations << "\n";
    }
    if (!ranks_read_file) RefuseNonFiniteResiduals(options.input, problem);
    // Refused before the solve, not after it: every output's kind and
    // directory, and the truth's counts.
    if (!options.output.empty()) {
      CheckOutput(options.input, options.output, model, options.colmap_format);
    }
    if (!options.truth_path.empty()) CheckTruthFile(options.truth_path, report);
    if (options.geo.any()) {
      geo = PrepareGeoreference(options.geo, colmap_names, &problem, &report.geo, out);
    }
    report.load_seconds = load_timer.Seconds();
    out << "dba solve " << options.input << ": " << report.num_cameras
        << (report.num_intrinsic_groups > 0
                ? " images, " + std::to_string(report.num_intrinsic_groups) + " intrinsic groups, "
                : " cameras, ")
        << report.num_points << " points, " << report.num_observations
        << " observations, " << comm->size() << (comm->size() == 1 ? " rank, " : " ranks, ")
        << lm.num_threads << " threads" << (comm->size() == 1 ? "" : " per rank") << "\n";
    if (!options.quiet) {
      // Large problems spend a while here before the first iteration line.
      char line[160];
      std::snprintf(line, sizeof line,
                    "loaded in %.1f s; building the RCS structure, then one line per "
                    "LM iteration\n",
                    report.load_seconds);
      out << line;
      // One process: the header follows the memory estimate (the symbolic
      // phase's end, below).
      if (comm->size() > 1) out << IterationLogHeader();
      out << std::flush;
    }
  }
  // Checkpoints after accepted iterations: the parameters the workers hold
  // (problem, updated in place; a distributed solve gathers its points
  // itself) and the LM state. A binary input spread over the ranks gets its
  // fingerprint once the ranks hold it.
  std::optional<CheckpointWriter> checkpoints;
  if (main && !options.checkpoint_path.empty()) {
    checkpoints.emplace(options.checkpoint_path, options.checkpoint_every_s,
                        ranks_read_file ? 0 : ProblemFingerprint(problem), lm.accepted_done);
  }
  auto log = [&](const IterationSummary& it) {
    if (!options.quiet) out << IterationLogLine(it) << std::flush;
    if (comm->size() == 1 && checkpoints && checkpoints->Due(it.step_accepted)) {
      checkpoints->Write(it.iteration, it.next_lambda, it.candidate_cost, problem.cameras,
                         problem.points);
    }
  };
  // Outlier rejection keeps the loaded points' numbering for the truth.
  std::vector<double> loaded_pixels, all_points;
  OriginalIndices original;
  report.reject_outliers_px = options.reject_outliers_px;
  if (options.reject_outliers_px > 0) {
    original = OriginalIndices::Identity(problem);
    // Without the control points' measurements (none held when the ranks
    // read the file).
    if (!options.truth_path.empty() && !ranks_read_file) {
      loaded_pixels.assign(problem.obs_pixel.begin(),
                           problem.obs_pixel.begin() + 2 * report.num_observations);
    }
  }
  if (comm->size() == 1) {
    // After the symbolic phase, before S's values: the peak estimated, and
    // the solve refused where it would not fit.
    auto check_memory = [&](const RcsSystem& structure) {
      report.memory_estimate =
          EstimateSolveMemory(problem, structure, lm, CurrentResidentBytes(), PeakResidentBytes());
      report.available_memory_bytes = AvailableMemoryBytes();
      if (!options.quiet) {
        const int64_t have = report.available_memory_bytes;
        out << "memory estimate " << report.memory_estimate.Describe()
            << (have > 0 ? "; available " + FormatBytes(have + report.memory_estimate.resident)
                         : std::string())
            << "\n" << IterationLogHeader() << std::flush;
      }
      if (options.memory_check) CheckMemoryFits(report.memory_estimate, report.available_memory_bytes);
    };
    report.solve.ba = BundleAdjust(lm, &problem, log, check_memory, &geo.priors);
    if (options.reject_outliers_px > 0) {
      LmOptions resolve = lm;
      if (!options.reject_keep_loss) resolve.loss = RobustLoss();
      RejectOutlierRounds({options.reject_outliers_px, options.min_triangulation_angle_deg}, resolve, log, geo.priors, &problem, &original, &all_points,
                          &report, out);
    }
  } else {
    DistributedOptions distributed = options.distributed;
    distributed.memory_check = options.memory_check;
    if (ranks_read_file) {
      distributed.fixings = Fixings{options.unknowns.fixed_images, {}};
      for (const IntrinsicFixing& x : options.unknowns.fixed_intrinsics) {
        if (!x.names.empty()) distributed.fixings.intrinsics.push_back(x);
      }
    }
    const RejectionCriteria criteria{options.reject_outliers_px, options.min_triangulation_angle_deg};
    distributed.reject_outliers = options.reject_outliers_px > 0;
    distributed.rejection = criteria;
    distributed.reject_keep_loss = options.reject_keep_loss;
    distributed.priors = geo.priors;
    DistributedHooks hooks;
    hooks.on_iteration = log;
    hooks.on_rejection_round = [&](int r, const RejectionRound& round) {
      out << RejectionRoundLine(criteria, r, round) << std::flush;
    };
    hooks.checkpoints = {checkpoints ? &*checkpoints : nullptr,
                         ranks_read_file && resumed ? &*resumed : nullptr, options.resume_path};
    report.solve = DistributedBundleAdjust(comm, lm, distributed,
                                           ranks_read_file ? options.input : std::string(),
                                           !options.output.empty() || !options.truth_path.empty() ||
                                               !options.ply_path.empty() ||
                                               !options.geo.gcps_path.empty(),
                                           &problem, hooks);
    report.memory_estimate = report.solve.memory_estimate;
    if (main && distributed.reject_outliers) {
      // As one process leaves it: the points left in `problem`, all of them
      // (loaded numbering) in all_points, where they came from in original.
      report.rejection = report.solve.rejection;
      if (report.rejection.front().observations_dropped > 0 && !options.reject_keep_loss) {
        report.final_loss = RobustLoss();
      }
      const KeptObservations& left = report.solve.kept;
      original.point.clear();
      original.observation.clear();
      for (size_t k = 0; k < left.point.size(); ++k) {
        if (left.point[k]) original.point.push_back(static_cast<int64_t>(k));
      }
      for (size_t o = 0; o < left.observation.size(); ++o) {
        if (left.observation[o]) original.observation.push_back(static_cast<int64_t>(o));
      }
      all_points.swap(problem.points);
      if (!all_points.empty()) {
        problem.points.resize(kPointSize * original.point.size());
        for (size_t k = 0; k < original.point.size(); ++k) {
          std::copy_n(&all_points[kPointSize * original.point[k]], kPointSize,
                      &problem.points[kPointSize * k]);
        }
      }
    }
    // The loaded pixels, for the truth (which are mismatches): read again
    // when the main rank never held the observations.
    if (main && !options.truth_path.empty() && loaded_pixels.empty()) {
      loaded_pixels = LoadSolveInput(options.input, options.unknowns).obs_pixel;
    }
  }
  if (!main) return 0;
  // Every output of the run appears when all are written, or none does.
  OutputTransaction outputs;

  // Georeferencing: the control points (the last points) out again, then
  // the block against the survey.
  if (!geo.empty()) {
    const LmSummary& lm_summary = report.solve.ba.lm;
    MeasureGeoreference(options.geo, geo,
                        {lm_summary.final_cost, lm_summary.num_observations,
                         report.solve.ba.rcs.camera_unknowns, report.num_points},
                        &problem, &report.geo);
    if (options.reject_outliers_px > 0) {
      all_points.resize(kPointSize * report.num_points);
      std::erase_if(original.point, [&](int64_t k) { return k >= report.num_points; });
      std::erase_if(original.observation, [&](int64_t o) { return o >= report.num_observations; });
    }
  }

  // Against the truth first: a truth file that does not fit fails the run
  // before any output is written.
  if (!options.truth_path.empty()) {
    // With outlier rejection the truth is compared in the loaded numbering,
    // over the points left (and their observations in the truth).
    const std::vector<double>& points =
        options.reject_outliers_px > 0 ? all_points : problem.points;
    std::vector<uint8_t> point_kept;
    if (options.reject_outliers_px > 0) {
      CountTrueOutliers(ReadProblem(options.truth_path), loaded_pixels, original, &report);
      point_kept.assign(report.num_points, 0);
      for (int64_t k : original.point) point_kept[k] = 1;
    }
    // The generated mismatches are left out of the RMS to the noise-free
    // pixels (their noise-free pixel is not what was matched).
    const std::vector<double>& pixels = loaded_pixels.empty() ? problem.obs_pixel : loaded_pixels;
    report.truth = CompareWithGroundTruthFile(options.truth_path, problem.cameras, points,
                                              problem.model, point_kept, pixels,
                                              options.truth_absolute);
    report.has_truth = true;
  }
  Timer write_timer;
  if (comm->size() > 1) MaybeInjectFault(0, "write", 1);
  // A COLMAP input is read once more, for what the outputs keep from it
  // (names, colours, tracks; the observations a distributed run handed out).
  // Deliberate: keeping the model through the solve instead would hold about
  // 32 bytes per observation (its points2D and tracks) beside the problem's
  // 20, in the phase where memory peaks; the re-read costs time only.
  const bool colmap_in = IsColmapInput(options.input);
  std::optional<ColmapInput> colmap;
  if (colmap_in && (!options.output.empty() || !options.ply_path.empty())) {
    colmap = ReadColmapInput(options.input, options.unknowns);
  }
  // After outlier rejection: what is left, in the loaded numbering.
  std::optional<KeptObservations> kept;
  if (options.reject_outliers_px > 0) {
    kept.emplace();
    kept->observation.assign(report.num_observations, 0);
    for (int64_t o : original.observation) kept->observation[o] = 1;
    kept->point.assign(report.num_points, 0);
    for (int64_t k : original.point) kept->point[k] = 1;
  }
  if (!options.ply_path.empty()) {
    std::vector<uint8_t> rgb;
    if (colmap) {
      rgb = PointColours(*colmap);
      if (kept) {  // the colours of the points left
        std::vector<uint8_t> left;
        left.reserve(3 * original.point.size());
        for (int64_t k : original.point) left.insert(left.end(), &rgb[3 * k], &rgb[3 * k + 3]);
        rgb.swap(left);
      }
    }
    if (options.geo.output_crs.empty()) {
      WritePointCloudPly(options.ply_path, problem.points, rgb);
    } else {
      WritePointCloudPly(options.ply_path, InOutputCrs(options.geo, geo, problem.points), rgb);
    }
  }
  if (!options.output.empty()) {
    const OutputKind kind =
        CheckOutput(options.input, options.output, problem.model, options.colmap_format);
    if (kind == OutputKind::kColmap) {
      WriteColmapOutput(problem.cameras, kept ? all_points : problem.points, options.output,
                        options.colmap_format, &*colmap, kept ? &*kept : nullptr);
    } else if (comm->size() > 1 && ranks_read_file && kind == OutputKind::kBinary && !kept) {
      // Binary to binary: stream the observations from the input; the camera
      // side (values and what was held fixed) is the solve's.
      WriteBinaryWithNewParameters(options.input, options.output, problem, problem.points);
    } else {
      if (comm->size() > 1) {
        // The observations were handed to the ranks (and released here, so
        // the main rank's memory during the solve is its share's): read them
        // again.
        Problem full = colmap ? std::move(colmap->source.problem)
                                 : LoadSolveInput(options.input, options.unknowns);
        full.cameras.swap(problem.cameras);
        full.points.swap(kept ? all_points : problem.points);
        if (kept) KeepOnly(*kept, &full);
        problem = std::move(full);
      }
      WriteProblem(problem, options.output);
    }
  }
  if (!options.geo.camera_centres_path.empty()) {
    // Named as the input names them (COLMAP), else by index.
    WriteCameraCentres(options.geo, geo, problem, colmap_names.problem);
  }
  report.write_seconds = write_timer.Seconds();
  report.peak_memory_bytes = PeakResidentBytes();
  if (!options.report_path.empty()) WriteFileAtomically(options.report_path, SolveReportJson(report));
  outputs.Commit();
  PrintSolveReport(report, out);
  if (!options.output.empty()) out << "  output              " << options.output << "\n";
  if (!options.ply_path.empty()) out << "  point cloud         " << options.ply_path << "\n";
  if (!options.report_path.empty()) out << "  report              " << options.report_path << "\n";
  if (outcome != nullptr) {
    outcome->report = std::move(report);
    outcome->problem = std::move(problem);
  }
  return 0;
}

int SolveMain(const std::vector<std::string>& args) {
  SolveCommandOptions options;
  try {
    if (std::find(args.begin(), args.end(), "--list-camera-models") != args.end()) {
      std::cout << "Lens models of intrinsic groups and their parameters (the names\n"
                   "--fix-intrinsics takes; COLMAP's models as COLMAP defines them):\n"
                << LensModelTable();
      return 0;
    }
    bool help = false;
    options = ParseSolveArguments(args, &help);
    if (help) {
      PrintSolveHelp(std::cout);
      return 0;
    }
  } catch (const std::exception& e) {
    std::cerr << "dba solve: " << e.what() << "\n";
    return 2;
  }
  Communicator comm(nullptr, nullptr);
  try {
    return RunSolveCommand(options, &comm, std::cout);
  } catch (const UsageError& e) {
    if (comm.size() > 1) comm.Abort(e.what(), 2);
    std::cerr << "dba solve: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    if (comm.size() > 1) comm.Abort(e.what());  // ends every rank
    std::cerr << "dba solve: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace dba
