// The options of a solve: help and parser; see solve_options.h.
#include "dba/session/solve_options.h"

#include <iostream>
#include <stdexcept>
#include <thread>

#include "dba/common/arguments.h"
#include "dba/common/error.h"
#include "dba/rcs/robust_loss.h"

namespace dba {

#ifdef DBA_HAVE_CHOLMOD
#define DBA_SPARSE_NAME "CHOLMOD"
#else
#define DBA_SPARSE_NAME "Eigen"
#endif

int DefaultThreads() {
  const unsigned n = std::thread::hardware_concurrency();
  return n == 0 ? 1 : static_cast<int>(n);
}

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
         "                             run; with --reject-outliers in one process)\n"
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

SolveOptions ParseSolveArguments(const std::vector<std::string>& args,
                                        bool* help) {
  SolveOptions o;
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


}  // namespace dba
