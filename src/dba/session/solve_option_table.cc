// `dba solve`'s options, each declared once; see solve_option_table.h.
#include "dba/session/solve_option_table.h"

#include <stdexcept>

#include "dba/common/arguments.h"

namespace dba {
namespace {

using Spec = OptionSpec<SolveOptions>;

// A field of the options, for the factories below (const or not).
#define DBA_FIELD(path) [](auto& o) -> auto& { return o.path; }

const char* const kNoArrayFiles =
    "solve_arrays returns its result (Result.problem, Result.summary); it writes no file";
const char* const kColmapOnly = "applies to a COLMAP model directory; arrays give their groups";
const char* const kRanksOnly = "applies to runs on MPI ranks (mpirun); a Python solve is one process";
constexpr unsigned kNotArrays = kModeCommandLine | kModePythonFile;

Spec Base(std::string name, OptionKind kind, std::string value, std::string help) {
  return OptionEntry<SolveOptions>(std::move(name), kind, std::move(value), std::move(help));
}

template <class F>
Spec Path(std::string name, std::string value, std::string help, F field,
          unsigned modes = kModeAll, const char* not_here = "") {
  Spec s = PathOption<SolveOptions>(std::move(name), std::move(value), std::move(help), field);
  s.modes = modes;
  s.not_here = not_here;
  return s;
}

template <class F>
Spec Text(std::string name, std::string value, std::string help, F field) {
  return TextOption<SolveOptions>(std::move(name), std::move(value), std::move(help), field);
}

template <class F>
Spec Flag(std::string name, std::string help, F field) {
  return FlagOption<SolveOptions>(std::move(name), std::move(help), field);
}

template <class F>
Spec Number(std::string name, std::string value, std::string help, F field, double min, double max,
            bool above_min = false) {
  return NumberOption<SolveOptions>(std::move(name), std::move(value), std::move(help), field, min,
                                    max, above_min);
}

template <class F>
Spec Integer(std::string name, std::string value, std::string help, F field, int64_t min,
             int64_t max) {
  return IntegerOption<SolveOptions>(std::move(name), std::move(value), std::move(help), field,
                                     min, max);
}

template <class Apply, class Current>
Spec Choice(std::string name, std::vector<std::string> choices, std::string help, Apply apply,
            Current current) {
  return ChoiceOption<SolveOptions>(std::move(name), std::move(choices), std::move(help), apply,
                                    current);
}

// What options need (OptionSpec::needs), judged on the parsed options.
bool HasPriors(const SolveOptions& o) { return !o.geo.camera_priors_path.empty(); }
bool HasPriorsOrGcps(const SolveOptions& o) { return o.geo.any(); }
bool HasGcps(const SolveOptions& o) { return !o.geo.gcps_path.empty(); }
bool HasOutput(const SolveOptions& o) { return !o.output.empty(); }
bool Rejects(const SolveOptions& o) { return o.reject_outliers_px > 0; }
bool MaySolveByPcg(const SolveOptions& o) {
  const LinearSolverType t = o.lm.linear_solver.type;
  return t == LinearSolverType::kPcg || t == LinearSolverType::kAuto;
}
constexpr const char* kPcgNeeds = "--linear-solver pcg or auto";

const std::vector<std::string> kGauges = {"hold", "free", "colmap"};  // GaugeRule's order
const std::vector<std::string> kLosses = {"trivial", "huber", "soft_l1", "cauchy", "arctan", "tukey"};

LossType LossOf(size_t i) {
  LossType t = LossType::kTrivial;
  ParseLoss(kLosses[i], &t);
  return t;
}

std::vector<Spec> OutputOptions() {
  std::vector<Spec> t;
  t.push_back(Path("--output", "PATH",
                   "write the adjusted problem: .txt/.bz2 BAL text, .dba binary, or (COLMAP "
                   "input) a COLMAP model in the directory PATH (names, ids, colours and tracks "
                   "kept)",
                   DBA_FIELD(output), kNotArrays, kNoArrayFiles));
  t.back().alias = "-o";
  t.push_back(Choice(
      "--colmap-format", {"text", "binary"}, "format of a COLMAP output (default: the input's)",
      [](SolveOptions& o, size_t i) { o.colmap_format = i == 0 ? ColmapFormat::kText : ColmapFormat::kBinary; },
      [](const SolveOptions&) { return std::string(); }));
  t.back().modes = kNotArrays;
  t.back().not_here = kColmapOnly;
  SetNeeds(&t.back(), "-o", HasOutput);
  t.push_back(Choice(
      "--colmap-version", {"newest", "3.8"},
      "the COLMAP a COLMAP output is for: 3.8 (Debian 12's) refuses, before the solve, a model "
      "using a lens model COLMAP 3.8 cannot read (ids above 10, e.g. RAD_TAN_THIN_PRISM_FISHEYE); "
      "newest writes it with a warning",
      [](SolveOptions& o, size_t i) { o.colmap_38 = i == 1; },
      [](const SolveOptions& o) { return std::string(o.colmap_38 ? "3.8" : "newest"); }));
  t.back().modes = kNotArrays;
  t.back().not_here = kColmapOnly;
  SetNeeds(&t.back(), "-o", HasOutput);
  t.push_back(Path("--ply", "FILE",
                   "write the adjusted points as a binary PLY point cloud, with the COLMAP "
                   "colours, else coloured by height z from blue (low) to red (high)",
                   DBA_FIELD(ply_path), kNotArrays, kNoArrayFiles));
  t.push_back(Path("--report", "FILE.json", "write the summary and per-iteration log as JSON",
                   DBA_FIELD(report_path), kNotArrays, kNoArrayFiles));
  t.push_back(Path("--checkpoint", "FILE",
                   "after each accepted LM iteration, write all that decides where the solve "
                   "ends to FILE (whole or not at all, with a checksum), to --resume from (rank 0 "
                   "writes it in a distributed run, with --reject-outliers too); a file, never "
                   "a FIFO or a device",
                   DBA_FIELD(checkpoint_path)));
  t.push_back(Number("--checkpoint-every", "S",
                     "at most one checkpoint per S seconds (0: after every accepted iteration; "
                     "the step that ends the solve is always written)",
                     DBA_FIELD(checkpoint_every_s), 0, 1e9));
  SetNeeds(&t.back(), "--checkpoint", [](const SolveOptions& o) { return !o.checkpoint_path.empty(); });
  t.push_back(Path("--resume", "FILE",
                   "continue the solve of INPUT from a --checkpoint FILE written with the same "
                   "input, fixings, loss, priors, control points and rejection: it ends where "
                   "the uninterrupted solve would",
                   DBA_FIELD(resume_path)));
  t.push_back(Path("--truth", "FILE",
                   "ground truth of a generated problem (dba generate --truth): report the RMS "
                   "against the noise-free observations, the camera/point errors after a "
                   "similarity alignment and, photogrammetric model, each intrinsic group's "
                   "errors (f, cx, cy, k1, k2)",
                   DBA_FIELD(truth_path)));
  t.push_back(Flag("--truth-absolute",
                   "with --truth: compare with no alignment (a georeferenced solve is in the "
                   "truth's frame)",
                   DBA_FIELD(truth_absolute)));
  SetNeeds(&t.back(), "--truth", [](const SolveOptions& o) { return !o.truth_path.empty(); });
  return t;
}

std::vector<Spec> FixingOptions() {
  std::vector<Spec> t;
  t.push_back(Choice(
      "--intrinsics", {"shared", "per-image"},
      "COLMAP input: one intrinsic group per COLMAP camera, or one per image",
      [](SolveOptions& o, size_t i) { o.unknowns.shared_intrinsics = i == 0; },
      [](const SolveOptions& o) { return std::string(o.unknowns.shared_intrinsics ? "shared" : "per-image"); }));
  t.back().modes = kNotArrays;
  t.back().not_here = kColmapOnly;
  Spec rig = Base("--rig-geometry", OptionKind::kText, "refine|fixed|fixed:IDS",
                  "a problem with rigs (.dba version 4, COLMAP rigs, arrays with frame_indices): "
                  "refine each rig's sensor poses (sensor_from_rig, the reference sensor held as "
                  "the rig's origin) where the problem poses them free, hold them all, or hold "
                  "those of the sensors listed (COLMAP camera ids, or 0-based intrinsic groups "
                  "of a .dba problem or arrays; default refine); the frames' poses "
                  "(rig_from_world) are always unknowns");
  rig.set = [](SolveOptions& o, const std::string& v) {
    ParseRigGeometry("--rig-geometry", v, &o.unknowns);
  };
  t.push_back(rig);

  Spec fix = Base("--fix-intrinsics", OptionKind::kText, "[GROUP:]NAMES",
                  "hold intrinsics fixed by name: all, or a comma-separated list of the groups' "
                  "lens models' names (COLMAP's: f, fx, fy, cx, cy, k1, k2, p1, p2, ...; see dba "
                  "solve --list-camera-models) or kinds (focal, principal_point, extra: every "
                  "other parameter), in every group whose model has the name, or in "
                  "GROUP only (a COLMAP camera id, or a 0-based group of a .dba problem); "
                  "repeatable (photogrammetric model only; the principal point is fixed unless "
                  "--refine-principal-point)");
  fix.repeatable = true;
  fix.set = [](SolveOptions& o, const std::string& v) {
    o.unknowns.fixed_intrinsics.push_back(ParseIntrinsicFixing("--fix-intrinsics", v));
  };
  t.push_back(fix);
  t.push_back(Flag("--refine-principal-point",
                   "photogrammetric model: the principal point (cx, cy) is an unknown; by default "
                   "it is held fixed, as COLMAP does (refine_principal_point 0) and as "
                   "photogrammetry does without a calibration target",
                   DBA_FIELD(unknowns.refine_principal_point)));
  Spec images = Base("--fix-images", OptionKind::kList, "LIST",
                     "hold these images' poses fixed: all, or COLMAP image ids or names for a "
                     "COLMAP input, 0-based camera indices otherwise (a BAL camera is then "
                     "fixed whole); with rigs an image's frame and its sensor's pose in the rig "
                     "are held (that sensor in every frame: an image of the rig's origin "
                     "sensor holds its frame alone)");
  images.set = [](SolveOptions& o, const std::string& v) {
    o.unknowns.fixed_images.clear();
    o.unknowns.fixed_image_names.clear();
    o.unknowns.fix_all_images = false;
    ParseImageFixing("--fix-images", v, &o.unknowns);
  };
  t.push_back(images);
  t.push_back(Choice(
      "--gauge", kGauges,
      "hold: what nothing else holds of the 7 degrees of freedom of the world (rotation, "
      "translation, scale) stays as loaded, the optimum mapped back by a similarity (the cost "
      "is unchanged): the images' centroid, the RMS spread of their centres about it and their "
      "mean orientation; with one image held fixed, the spread; camera priors, control points "
      "or two fixed images hold it themselves. free: the optimum where LM ends. "
      "colmap: what colmap bundle_adjuster holds, the first image's pose and the x of the "
      "second's translation (a COLMAP model's file order)",
      [](SolveOptions& o, size_t i) { o.gauge = static_cast<GaugeRule>(i); },
      [](const SolveOptions& o) { return kGauges[static_cast<size_t>(o.gauge)]; }));
  return t;
}

std::vector<Spec> LossOptions() {
  std::vector<Spec> t;
  t.push_back(Choice(
      "--loss", kLosses,
      "robust loss of each observation's squared reprojection error s, Ceres's definitions: "
      "the cost is 1/2 sum rho(s) (trivial: rho(s) = s); with --reject-outliers PX and no "
      "--loss, the first solve's is cauchy at scale 2 PX (or --loss-scale)",
      [](SolveOptions& o, size_t i) {
        o.lm.loss.type = LossOf(i);
        o.loss_given = true;
      },
      [](const SolveOptions& o) { return std::string(LossName(o.lm.loss.type)); }));
  // No image measurement is finer than about 0.02 px (a centroided
  // target): a scale under 0.01 px makes every observation an outlier, and
  // Tukey's loss gives those no weight (1e-6 ended at iteration 0).
  t.push_back(Number("--loss-scale", "PX",
                     "the loss's scale a in pixels: residuals beyond it are down-weighted (and "
                     "count as outliers in the RMS figures)",
                     DBA_FIELD(lm.loss.scale), 0.01, 1e4));
  t.back().set = [set = t.back().set](SolveOptions& o, const std::string& v) {
    set(o, v);
    o.loss_scale_given = true;
  };
  t.push_back(Number("--reject-outliers", "PX",
                     "after the solve, drop observations whose reprojection error exceeds PX "
                     "pixels and points left with fewer than 2 or seen under "
                     "--min-triangulation-angle, then solve again; until a round drops under "
                     "0.05% of the observations, at most 5 rounds; the outputs leave what was "
                     "dropped out (0: off). The first solve uses --loss, or without one cauchy at "
                     "scale 2 PX: a squared first solve is dragged by mismatches and its round "
                     "drops the inliers; cauchy at 2 PX drops every uniform mismatch and 0.7% of "
                     "the inliers on generated surveys, at PX 0.9% (bench/README.md). The solves "
                     "after a round use the squared loss, the efficient estimator once the "
                     "outliers are gone",
                     DBA_FIELD(reject_outliers_px), 1e-6, 1e6));
  t.back().default_text = [](const SolveOptions&) { return std::string("off"); };
  t.push_back(Flag("--reject-keep-loss", "keep the first solve's loss in the solves after a "
                   "rejection round", DBA_FIELD(reject_keep_loss)));
  SetNeeds(&t.back(), "--reject-outliers", Rejects);
  t.push_back(Number("--reject-max-share", "S",
                     "stop the run (exit 1, nothing written) when a rejection round would drop "
                     "more than the share S of the observations it starts with, or leave a free "
                     "image (with rigs a frame) that had them with fewer observations than "
                     "determine its pose (3; a BAL camera 5): the solve before it has not settled "
                     "on the inliers (it stopped at --max-iterations, or mismatches dragged a "
                     "squared loss) or PX is below the noise. On generated surveys a round drops "
                     "the mismatches' share and about 0.5% more (10% of them: 10.5%, 20%: 20.5%, "
                     "30%: 30.4%), after a squared first solve 96-99.8%; 1: no guard",
                     DBA_FIELD(reject_max_share), 0, 1, true));
  SetNeeds(&t.back(), "--reject-outliers", Rejects);
  t.push_back(Number("--min-triangulation-angle", "DEG",
                     "with --reject-outliers: a point whose rays meet at less than DEG degrees "
                     "(the largest angle between two of its observations' rays) goes too: its "
                     "depth is not determined (COLMAP's default; 0: off)",
                     DBA_FIELD(min_triangulation_angle_deg), 0, 179.9));
  SetNeeds(&t.back(), "--reject-outliers", Rejects);
  return t;
}

std::vector<Spec> GeoreferencingOptions() {
  std::vector<Spec> t;
  t.push_back(Path("--camera-priors", "FILE",
                   "GNSS camera centres in the solve: per line IMAGE X Y Z [SIGMA_XY SIGMA_Z], "
                   "IMAGE a COLMAP image name or a 0-based camera index, metres in a Cartesian "
                   "frame; reports the agreement per axis, CE90/LE90 and the priors flagged as "
                   "outliers (chi-square 3 dof 99.9%)",
                   DBA_FIELD(geo.camera_priors_path)));
  t.push_back(Text("--prior-crs", "CRS",
                   "the priors' coordinates in any 3D CRS PROJ knows (EPSG:4979: WGS84 "
                   "latitude, longitude, ellipsoidal height, EPSG's axis order); the solve and "
                   "its outputs are then in a local east-north-up frame at the priors' centre "
                   "(origin and PROJ pipeline in the report)",
                   DBA_FIELD(geo.prior_crs)));
  SetNeeds(&t.back(), "--camera-priors or --gcps", HasPriorsOrGcps);
  t.push_back(Path("--gcps", "FILE",
                   "ground control and check points: per point a line NAME X Y Z SIGMA_XY "
                   "SIGMA_Z control|check, and per measurement NAME IMAGE x y (the input's pixel "
                   "convention); control points are points of the solve with a prior, check "
                   "points are triangulated after it and compared (docs/georeferencing.md)",
                   DBA_FIELD(geo.gcps_path)));
  t.push_back(Text("--gcp-crs", "CRS",
                   "the GCPs' CRS (default: --prior-crs); converted to the same local frame, "
                   "refused where PROJ has only a ballpark height transformation (a missing "
                   "geoid grid)",
                   DBA_FIELD(geo.gcp_crs)));
  SetNeeds(&t.back(), "--gcps", HasGcps);
  t.push_back(Text("--output-crs", "CRS",
                   "with a CRS given: --ply and --camera-centres in this 3D CRS (converted back "
                   "from the local frame by PROJ); the problem outputs stay in the local frame",
                   DBA_FIELD(geo.output_crs)));
  SetNeeds(&t.back(), "--prior-crs or --gcp-crs", [](const SolveOptions& o) {
    return !o.geo.prior_crs.empty() || !o.geo.gcp_crs.empty();
  });
  t.back().modes = kNotArrays;
  t.back().not_here =
      "converts the files --ply and --camera-centres, which solve_arrays does not write; its "
      "result is in the local frame (Result.summary.report['georeferencing'])";
  t.push_back(Path("--camera-centres", "FILE", "the adjusted camera centres, IMAGE X Y Z per line",
                   DBA_FIELD(geo.camera_centres_path), kNotArrays, kNoArrayFiles));
  t.push_back(Path("--covariance", "FILE",
                   "every image's pose covariance at the optimum, a CSV line per image: the "
                   "centre's sigmas and covariance, the attitude's sigmas (degrees, about the "
                   "frame's x, y, z axes) and the 6x6 (radians, metres), exact, by selected "
                   "inversion of the reduced camera system; the datum named per line: inner "
                   "constraints over the camera centres when nothing holds the frame, else "
                   "absolute; an image the data do not determine marked undetermined; over "
                   "ranks the RCS is gathered on rank 0 (README.md, Precision); not with rigs; "
                   "Python: Result.covariance holds it as arrays (solve_arrays: covariance=True)",
                   DBA_FIELD(covariance_path), kNotArrays, kNoArrayFiles));
  t.push_back(Path("--point-covariance", "FILE",
                   "with --covariance: every point's covariance, a CSV line per point (its 0-based "
                   "index in the input, sigmas and the 3x3), in the datum and scale of --covariance; "
                   "one process",
                   DBA_FIELD(point_covariance_path), kNotArrays, kNoArrayFiles));
  SetNeeds(&t.back(), "--covariance", [](const SolveOptions& o) { return !o.covariance_path.empty(); });
  t.push_back(Choice(
      "--ply-colour", {"input", "sigma"},
      "the --ply points' colours: input (a COLMAP model's, else by height); sigma: by each "
      "point's sigma, sqrt(trace/3) of its --point-covariance block, blue (low) to red (high) "
      "over its 1st-99th percentiles, undetermined points blue",
      [](SolveOptions& o, size_t i) { o.ply_sigma = i == 1; },
      [](const SolveOptions& o) { return std::string(o.ply_sigma ? "sigma" : "input"); }));
  t.back().modes = kNotArrays;
  t.back().not_here = kNoArrayFiles;
  SetNeeds(&t.back(), "--ply", [](const SolveOptions& o) { return !o.ply_path.empty(); });
  t.push_back(Choice(
      "--covariance-scale", {"a-posteriori", "unit"},
      "a-posteriori: the covariances times the variance factor (the residuals' estimate of the "
      "pixel noise, squared: they hold whatever the images' real noise); unit: for a pixel "
      "sigma of 1 (Ceres's and COLMAP's convention)",
      [](SolveOptions& o, size_t i) { o.covariance_unit = i == 1; },
      [](const SolveOptions& o) { return std::string(o.covariance_unit ? "unit" : "a-posteriori"); }));
  SetNeeds(&t.back(), "--covariance", [](const SolveOptions& o) { return !o.covariance_path.empty(); });
  t.push_back(Path("--accuracy-report", "FILE",
                   "with --camera-priors or --gcps: the figures as a table, and each prior's, "
                   "control and check point's dx, dy, dz, squared Mahalanobis distance and flag",
                   DBA_FIELD(geo.accuracy_report_path), kNotArrays, kNoArrayFiles));
  SetNeeds(&t.back(), "--camera-priors or --gcps", HasPriorsOrGcps);
  Spec sigma = Base("--prior-sigma", OptionKind::kText, "XY,Z",
                    "sigma of the priors that give none (metres; sigma_xy per horizontal axis)");
  sigma.set = [](SolveOptions& o, const std::string& v) {
    const auto [xy, z] = ParseSigmaPair("--prior-sigma", v);
    o.geo.prior_sigma = Eigen::Vector2d(xy, z);
  };
  t.push_back(sigma);
  SetNeeds(&t.back(), "--camera-priors", HasPriors);
  t.push_back(Choice(
      "--prior-loss", kLosses,
      "the priors' robust loss, in units of sigma (chosen by measurement: bench/README.md)",
      [](SolveOptions& o, size_t i) { o.geo.prior_loss.type = LossOf(i); },
      [](const SolveOptions& o) { return std::string(LossName(o.geo.prior_loss.type)); }));
  SetNeeds(&t.back(), "--camera-priors", HasPriors);
  t.push_back(Number("--prior-loss-scale", "S", "its scale in units of sigma",
                     DBA_FIELD(geo.prior_loss.scale), 1e-3, 1e3));
  SetNeeds(&t.back(), "--camera-priors", HasPriors);
  Spec lever = Base("--lever-arm", OptionKind::kText, "X,Y,Z",
                    "where the GNSS antenna of the camera priors is, in metres, in the "
                    "camera's frame (x right, y down, z forward), with rigs in the rig's (its "
                    "reference sensor's): each prior is then on C + R^T (X,Y,Z) (default 0,0,0: "
                    "the camera's centre)");
  lever.set = [](SolveOptions& o, const std::string& v) {
    const std::array<double, 3> a = ParseTriple("--lever-arm", v, 1e3);
    o.geo.lever_arm = Eigen::Vector3d(a[0], a[1], a[2]);
  };
  t.push_back(lever);
  SetNeeds(&t.back(), "--camera-priors", HasPriors);
  t.push_back(Flag("--refine-lever-arm",
                   "estimate the lever arm (3 unknowns shared by every prior; --lever-arm is "
                   "its start): needs priors seen from several headings, and for its vertical "
                   "part control points; over MPI ranks the RCS is gathered (--rcs gather)",
                   DBA_FIELD(geo.refine_lever_arm)));
  SetNeeds(&t.back(), "--camera-priors", HasPriors);
  return t;
}

std::vector<Spec> LmOptionsTable() {
  std::vector<Spec> t;
  t.push_back(Integer("--threads", "N",
                      "threads per rank (default: the node's cores divided by its ranks; " +
                          std::to_string(DefaultThreads()) + " cores here)",
                      DBA_FIELD(lm.num_threads), 1, kMaxThreads));
  t.back().alias = "-t";
  t.back().default_text = {};
  t.push_back(Integer("--max-iterations", "N", "LM iteration limit", DBA_FIELD(lm.max_iterations),
                      0, 1000000000));
  t.push_back(Number("--function-tolerance", "X",
                     "stop when a step lowers the cost by less than this fraction, unless its "
                     "gain ratio was under 1/4 and its model promised more",
                     DBA_FIELD(lm.function_tolerance), 0, 1, false));
  t.push_back(Number("--gradient-tolerance", "X", "stop when max|J^T r| <= X",
                     DBA_FIELD(lm.gradient_tolerance), 0, 1e300));
  t.push_back(Number("--parameter-tolerance", "X",
                     "stop when |step| <= X (|x| + X), |x| with camera centres and points about "
                     "their centroids",
                     DBA_FIELD(lm.parameter_tolerance), 0, 1));
  // Under 1e-16, 1 + lambda rounds to 1: no damping at all (an RCS with a
  // free gauge is singular). Over 1e4 (1e8 times the default), the first
  // step is too short to count: at 1e7 problem-49-7776's fell below
  // --parameter-tolerance and LM ended where it started.
  t.push_back(Number("--initial-lambda", "X", "initial LM damping",
                     DBA_FIELD(lm.initial_lambda), 1e-16, 1e4));
  return t;
}

std::vector<Spec> LinearSolverOptionsTable();
std::vector<Spec> RunOptions();

std::vector<Spec> BuildTable() {
  std::vector<Spec> table;
  for (auto part : {OutputOptions(), FixingOptions(), LmOptionsTable(), LossOptions(),
                    GeoreferencingOptions(), LinearSolverOptionsTable(), RunOptions()}) {
    table.insert(table.end(), part.begin(), part.end());
  }
  return table;
}

std::vector<Spec> LinearSolverOptionsTable() {
  std::vector<Spec> t;
  t.push_back(Choice(
      "--linear-solver", {"auto", "dense", "sparse", "pcg"},
      "how the reduced camera system is solved: dense Cholesky (small), sparse Cholesky "
      "(medium), PCG (large); auto picks the cheapest by a cost model, a factorization only "
      "while its factor stays within 2x what a PCG solve holds",
      [](SolveOptions& o, size_t i) {
        ParseLinearSolver(std::vector<std::string>{"auto", "dense", "sparse", "pcg"}[i],
                          &o.lm.linear_solver.type);
      },
      [](const SolveOptions& o) { return std::string(LinearSolverName(o.lm.linear_solver.type)); }));
  t.push_back(Number("--eta", "X",
                     "PCG's truncated-Newton stop (Nash-Sofer): end at iteration i when i (Q_i - "
                     "Q_i-1) / Q_i < X for the quadratic model Q (0: off)",
                     DBA_FIELD(lm.linear_solver.pcg.eta), 0, 1));
  t.push_back(Choice(
      "--preconditioner", {"jacobi", "two-level"},
      "PCG's preconditioner: block-Jacobi, or two-level (block-Jacobi plus a coarse solve over "
      "aggregates of neighbouring cameras; for long strips)",
      [](SolveOptions& o, size_t i) {
        ParsePreconditioner(i == 0 ? "jacobi" : "two-level", &o.lm.linear_solver.preconditioner);
      },
      [](const SolveOptions& o) {
        return std::string(PreconditionerName(o.lm.linear_solver.preconditioner));
      }));
  t.push_back(Integer("--coarse-size", "N", "two-level: cameras per aggregate",
                      DBA_FIELD(lm.linear_solver.coarse_aggregate_size), 1, 1000000000));
  t.push_back(Choice(
      "--coarse-basis", {"similarity", "rigid", "parameters"},
      "two-level: the cameras of an aggregate share a similarity of the scene (rigid motion "
      "and scale), a rigid motion, or a parameter step",
      [](SolveOptions& o, size_t i) {
        ParseCoarseBasis(std::vector<std::string>{"similarity", "rigid", "parameters"}[i],
                         &o.lm.linear_solver.coarse_basis);
      },
      [](const SolveOptions& o) { return std::string(CoarseBasisName(o.lm.linear_solver.coarse_basis)); }));
  t.push_back(Number("--pcg-tolerance", "X", "PCG also stops at this relative residual",
                     DBA_FIELD(lm.linear_solver.pcg.relative_tolerance), 0, 1));
  t.push_back(Integer("--pcg-min-iterations", "N", "PCG iterations before the --eta test is taken",
                      DBA_FIELD(lm.linear_solver.pcg.min_iterations), 0, 1000000000));
  t.push_back(Integer("--pcg-max-iterations", "N", "PCG iteration limit, a safety net",
                      DBA_FIELD(lm.linear_solver.pcg.max_iterations), 1, 1000000000));
  t.push_back(Choice(
      "--pcg-precision", {"auto", "mixed", "double"},
      "the RCS in PCG's product: mixed keeps its off-diagonal blocks in float (the product "
      "reads about half the bytes; exact to 6e-8 relative per value), double as formed; auto: "
      "mixed with the --eta stop until LM's damping reaches float's rounding (6e-8) and its "
      "steps would take it lower, double from then on; double when --eta is 0",
      [](SolveOptions& o, size_t i) {
        ParsePcgPrecision(std::vector<std::string>{"auto", "mixed", "double"}[i],
                          &o.lm.linear_solver.pcg.precision);
      },
      [](const SolveOptions& o) { return std::string(PcgPrecisionName(o.lm.linear_solver.pcg.precision)); }));
  // Every option after --linear-solver is PCG's; --coarse-* the two-level
  // preconditioner's.
  for (size_t k = 1; k < t.size(); ++k) {
    if (t[k].name.starts_with("--coarse-")) {
      SetNeeds(&t[k], "--preconditioner two-level, with " + std::string(kPcgNeeds),
               [](const SolveOptions& o) {
                 return MaySolveByPcg(o) &&
                        o.lm.linear_solver.preconditioner == PreconditionerType::kTwoLevel;
               });
    } else {
      SetNeeds(&t[k], kPcgNeeds, MaySolveByPcg);
    }
  }
  return t;
}

std::vector<Spec> RunOptions() {
  std::vector<Spec> t;
  t.push_back(Choice(
      "--partition", {"equal", "cameras"},
      "how points are split over MPI ranks: 'equal' (the paper's equal counts) or 'cameras' "
      "(grouped by the cameras that see them)",
      [](SolveOptions& o, size_t i) { o.distributed.partition = ParsePartitionScheme(i == 0 ? "equal" : "cameras"); },
      [](const SolveOptions& o) { return std::string(PartitionSchemeName(o.distributed.partition)); }));
  using Rcs = DistributedOptions::Rcs;
  t.push_back(Choice(
      "--rcs", {"auto", "gather", "distributed"},
      "where the RCS lives with MPI: 'distributed' spreads its rows over the ranks and runs "
      "PCG across them (the --preconditioner's coarse solve on rank 0); 'gather' sums it on "
      "rank 0, which solves alone (the paper's); auto: distributed with more than one rank, "
      "unless --linear-solver is dense or sparse",
      [](SolveOptions& o, size_t i) { o.distributed.rcs = i == 0 ? Rcs::kAuto : i == 1 ? Rcs::kGather : Rcs::kDistributed; },
      [](const SolveOptions&) { return std::string("auto"); }));
  using Role = DistributedOptions::MainRole;
  t.push_back(Choice(
      "--main-rank", {"auto", "forms", "coordinates"},
      "whether rank 0 also forms a sub-RCS (auto: yes for up to 4 ranks)",
      [](SolveOptions& o, size_t i) { o.distributed.main_role = i == 0 ? Role::kAuto : i == 1 ? Role::kForms : Role::kCoordinates; },
      [](const SolveOptions&) { return std::string("auto"); }));
  for (size_t k = t.size() - 3; k < t.size(); ++k) {
    t[k].modes = kNotArrays;
    t[k].not_here = kRanksOnly;
  }
  Spec check = Base("--no-memory-check", OptionKind::kFlag, "",
                    "start even when the memory estimate (printed before the first iteration) "
                    "exceeds the memory available (MemAvailable, or a cgroup's limit; "
                    "distributed: each rank against its part of its node's)");
  check.set = [](SolveOptions& o, const std::string&) { o.memory_check = false; };
  t.push_back(check);
  t.push_back(Flag("--quiet",
                   "no per-iteration log, and no progress of long phases (shown on a terminal "
                   "only: RCS formation, PCG, back-substitution, with the time left)",
                   DBA_FIELD(quiet)));
  t.back().alias = "-q";
  return t;
}

#undef DBA_FIELD

}  // namespace

const std::vector<OptionSpec<SolveOptions>>& SolveOptionTable() {
  static const std::vector<OptionSpec<SolveOptions>> table = BuildTable();
  return table;
}

}  // namespace dba
