// `dba convert` and `dba info`; see convert_command.h.
#include "dba/app/convert_command.h"

#include <omp.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <optional>

#include "dba/bsmc/bsmc_matrix.h"
#include "dba/common/error.h"
#include "dba/common/memory.h"
#include "dba/common/option_table.h"
#include "dba/common/timer.h"
#include "dba/io/binary_problem.h"
#include "dba/io/colmap_binary.h"
#include "dba/io/colmap_text.h"
#include "dba/io/input_source.h"
#include "dba/io/path_kind.h"
#include "dba/io/read_problem.h"
#include "dba/lm/memory_estimate.h"
#include "dba/problem/random_renumbering.h"
#include "dba/rcs/rcs_pattern.h"
#include "dba/rcs/unknown_layout.h"
#include "dba/session/run_files.h"

namespace dba {
namespace {

bool WantsHelp(const std::vector<std::string>& args) {
  return std::find(args.begin(), args.end(), "--help") != args.end() ||
         std::find(args.begin(), args.end(), "-h") != args.end();
}

struct Stats {
  int64_t min = 0, max = 0;
  double mean = 0;
};

template <typename F>
Stats Statistics(int64_t n, F value) {
  Stats s;
  if (n == 0) return s;
  s.min = s.max = value(0);
  double sum = 0;
  for (int64_t i = 0; i < n; ++i) {
    const int64_t v = value(i);
    s.min = std::min(s.min, v);
    s.max = std::max(s.max, v);
    sum += static_cast<double>(v);
  }
  s.mean = sum / static_cast<double>(n);
  return s;
}

}  // namespace

// The input and the output, checked before reading (session/run_files.h): the
// output may replace the input (converted in place), nothing else.
void CheckConvertFiles(const InputSource& in, const std::string& out,
                       std::optional<ColmapFormat> format) {
  RunFiles files;
  files.Input("INPUT", in.path);
  if (in.colmap() && KindOfPath(out) == PathKind::kOther) {
    files.ModelOutput("OUTPUT", out, format.value_or(in.colmap_format), HasRigsOrFrames(in.path));
  } else {
    files.Output("OUTPUT", out);
  }
  files.AllowInPlace("OUTPUT", "INPUT");
  files.Check();
}

// A COLMAP model directory to a COLMAP directory (text or binary, every
// value as read: binary byte for byte) or to a photogrammetric .dba (each
// COLMAP camera an intrinsic group in its own lens model).
int ConvertColmap(const InputSource& input, const std::string& out,
                  std::optional<ColmapFormat> format) {
  Timer timer;
  const std::string& in = input.path;
  const ColmapModel model = ReadColmapModel(in);
  if (KindOfPath(out) == PathKind::kBinary) {
    if (format) throw std::invalid_argument("--colmap-format applies to a COLMAP output directory");
    const ColmapProblem cp = ProblemFromColmap(model, {}, in);
    WriteBinaryProblem(cp.problem, out);
    std::printf("%s -> %s: %ld images, %ld intrinsic groups, %ld points, %ld observations, %.2f s\n",
                in.c_str(), out.c_str(), static_cast<long>(cp.problem.num_images()),
                static_cast<long>(cp.problem.num_groups()), static_cast<long>(cp.problem.num_points()),
                static_cast<long>(cp.problem.num_observations()), timer.Seconds());
    return 0;
  }
  if (KindOfPath(out) != PathKind::kOther) {
    throw std::invalid_argument(out + ": a COLMAP model converts to a COLMAP directory or a .dba "
                                "(the BAL format cannot hold shared intrinsics)");
  }
  const ColmapFormat f = format.value_or(input.colmap_format);
  const std::optional<ColmapFormat> there = DetectColmapFormat(out);
  if (there && *there != f) {
    throw std::invalid_argument(out + ": holds a COLMAP model in the other form, which would be "
                                "read instead of the one written; remove it or use --colmap-format");
  }
  if (f == ColmapFormat::kText) {
    WriteColmapText(model, out);
  } else {
    WriteColmapBinary(model, out);
  }
  std::printf("%s -> %s (%s): %zu cameras, %zu images, %zu points, %.2f s\n", in.c_str(),
              out.c_str(), f == ColmapFormat::kText ? "text" : "binary", model.cameras.size(),
              model.images.size(), model.points3D.size(), timer.Seconds());
  return 0;
}

// dba convert's arguments.
struct ConvertArgs {
  std::vector<std::string> files;  // INPUT OUTPUT
  std::optional<ColmapFormat> colmap_format;
  int64_t shuffle_seed = -1;  // -1: keep the input's order
  bool drop_rigs = false;
};

OptionSpec<ConvertArgs> ShuffleOption() {
  OptionSpec<ConvertArgs> s = IntegerOption<ConvertArgs>(
      "--shuffle", "SEED",
      "renumber the points and cameras by a random permutation drawn from SEED (a BAL or .dba "
      "input; the same problem in an order nobody chose)",
      [](auto& a) -> auto& { return a.shuffle_seed; }, 0, int64_t{1} << 62);
  s.default_text = [](const ConvertArgs&) { return std::string(); };
  return s;
}

const std::vector<OptionSpec<ConvertArgs>>& ConvertOptionTable() {
  static const std::vector<OptionSpec<ConvertArgs>> table = {ChoiceOption<ConvertArgs>(
      "--colmap-format", {"text", "binary"},
      "a COLMAP output's form (default: the input's)",
      [](ConvertArgs& a, size_t i) { a.colmap_format = i == 0 ? ColmapFormat::kText : ColmapFormat::kBinary; },
      [](const ConvertArgs&) { return std::string(); }),
      ShuffleOption(),
      FlagOption<ConvertArgs>(
          "--drop-rigs",
          "a problem with rigs (.dba version 4): every image its own pose unknown, at its "
          "composed pose (the same images solved as independent cameras)",
          [](auto& a) -> bool& { return a.drop_rigs; })};
  return table;
}

void PrintConvertHelp(std::ostream& out) {
  out << "Usage: dba convert INPUT OUTPUT [--colmap-format text|binary] [--shuffle SEED]\n"
         "                   [--drop-rigs]\n"
         "\n"
         "Converts between BAL text (plain or .bz2) and the dba binary format,\n"
         "losslessly. The input kind is detected by content; the output kind by\n"
         "the extension: .dba is binary, .bz2 is compressed BAL, .txt BAL text;\n"
         "any other extension is refused for a BAL or .dba input. The output is\n"
         "written to a temporary name and renamed over OUTPUT (a symbolic link is\n"
         "written through; a device or a FIFO is written plainly; a directory is\n"
         "refused); OUTPUT may be INPUT (in place).\n"
         "A photogrammetric .dba (poses and shared intrinsics) converts to .dba\n"
         "only: the BAL format cannot hold shared intrinsics.\n"
         "\n"
         "A COLMAP model directory converts to a COLMAP directory (the input's form\n"
         "unless --colmap-format says; every value as read, binary byte for byte) or\n"
         "to a .dba (each COLMAP camera an intrinsic group in its own model).\n"
         "\n"
         "Options:\n";
  PrintOptions(ConvertOptionTable(), ConvertArgs(), out);
  out << "  -h, --help                 this text\n";
}

int ConvertMain(const std::vector<std::string>& all_args) {
  ConvertArgs parsed;
  try {
    bool help = false;
    ParseOptions(ConvertOptionTable(), all_args, &parsed,
                 [&](const std::string& f) { parsed.files.push_back(f); }, &help, "convert");
    if (help) {
      PrintConvertHelp(std::cout);
      return 0;
    }
    for (const std::string& f : parsed.files) {
      if (f.empty()) throw std::invalid_argument("an empty path names no file");
    }
    if (parsed.files.size() != 2) {
      throw std::invalid_argument("expected INPUT OUTPUT, got " +
                                  std::to_string(parsed.files.size()) + " files (see dba convert --help)");
    }
  } catch (const std::invalid_argument& e) {
    std::cerr << "dba convert: " << e.what() << "\n";
    return 2;
  }
  const std::vector<std::string>& args = parsed.files;
  const std::optional<ColmapFormat> colmap_format = parsed.colmap_format;
  const InputSource input = DecideInput(args[0]);
  if (!input.colmap() && colmap_format) {
    std::cerr << "dba convert: --colmap-format applies to a COLMAP input\n";
    return 2;
  }
  if (input.colmap() && (parsed.shuffle_seed >= 0 || parsed.drop_rigs)) {
    std::cerr << "dba convert: --shuffle and --drop-rigs apply to a BAL or .dba input (a COLMAP "
                 "model's ids are its own)\n";
    return 2;
  }
  try {
    CheckConvertFiles(input, args[1], colmap_format);
    if (input.colmap()) return ConvertColmap(input, args[1], colmap_format);
    Timer timer;
    const std::string& out = args[1];
    if (KindOfPath(out) == PathKind::kOther) {
      throw UsageError(out + ": expected a .txt or .bz2 (BAL text) or .dba file name (a COLMAP "
                       "model directory is written only from a COLMAP model)");
    }
    Problem problem = ReadProblem(args[0]);
    if (parsed.shuffle_seed >= 0) RenumberAtRandom(static_cast<uint64_t>(parsed.shuffle_seed), &problem);
    if (parsed.drop_rigs) problem.DropRigs();
    if (problem.model == CameraModel::kPhoto &&
        KindOfPath(out) != PathKind::kBinary) {
      throw std::invalid_argument(
          args[0] + " is a photogrammetric problem (" + std::to_string(problem.num_images()) +
          " images sharing " + std::to_string(problem.num_groups()) +
          " intrinsic groups): the BAL format cannot hold shared intrinsics, so it converts to "
          ".dba only");
    }
    WriteProblem(problem, out);
    const std::string cameras =
        problem.model == CameraModel::kPhoto
            ? std::to_string(problem.num_images()) + " images, " +
                  std::to_string(problem.num_groups()) + " intrinsic groups"
            : std::to_string(problem.num_images()) + " cameras";
    std::printf("%s -> %s%s: %s, %ld points, %ld observations, %.2f s\n",
                args[0].c_str(), args[1].c_str(),
                parsed.shuffle_seed >= 0 ? " (renumbered at random)" : "", cameras.c_str(),
                static_cast<long>(problem.num_points()),
                static_cast<long>(problem.num_observations()), timer.Seconds());
    return 0;
  } catch (const std::invalid_argument& e) {  // the arguments do not fit the input
    std::cerr << "dba convert: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "dba convert: error: " << e.what() << "\n";
    return 1;
  }
}

static void PrintInfoUsage(std::ostream& out) {
  out << "Usage: dba info FILE\n"
           "\n"
           "Prints the camera model and counts of a problem (BAL text or binary, or a\n"
           "COLMAP model directory;\n"
           "for the photogrammetric model also its intrinsic groups and what is held\n"
           "fixed), the statistics of its track lengths (observations per point) and\n"
           "camera degrees (observations per camera, cameras sharing a point with\n"
           "it), the size of its reduced camera system in BSMC next to CSR, and the\n"
           "peak memory dba solve would take with its defaults on this node's cores\n"
           "(one process; the estimate dba solve prints before its first iteration).\n";
}

// Which cameras share a point: the RCS's pattern when its rows are the
// cameras one to one (BAL, none held; 10 s of a 71M-observation file's
// info when built again), else built apart.
static std::vector<uint64_t> CameraGraphPattern(const Problem& p, const UnknownLayout& layout,
                                                const std::vector<uint64_t>& rcs) {
  bool rows_are_cameras = layout.num_block_rows() == p.num_images();
  for (int64_t i = 0; rows_are_cameras && i < p.num_images(); ++i) {
    rows_are_cameras = layout.camera_row(i) == i;
  }
  if (rows_are_cameras) return rcs;
  return RcsBlockPattern(p.num_images(), p.point_offsets, p.obs_camera);
}

int InfoMain(const std::vector<std::string>& args) {
  const bool option = args.size() == 1 && args[0].size() > 1 && args[0][0] == '-';
  const bool empty = args.size() == 1 && args[0].empty();
  if (WantsHelp(args) || args.size() != 1 || option || empty) {
    if (!WantsHelp(args)) {
      std::cerr << "dba info: "
                << (args.empty() ? std::string("missing FILE")
                    : option     ? "unknown option '" + args[0] + "'"
                    : empty      ? "an empty path names no file"
                                 : "one FILE, not " + std::to_string(args.size()) + " arguments")
                << "\n\n";
    }
    PrintInfoUsage(WantsHelp(args) ? std::cout : std::cerr);
    return WantsHelp(args) ? 0 : 2;
  }
  try {
    RunFiles file;  // what a killed run left of it put right first
    file.Input("FILE", args[0]);
    file.Check();
    const InputSource input = DecideInput(args[0]);
    const Problem p = ReadInputProblem(input, DefaultFixings());  // COLMAP models too
    const int64_t nc = p.num_images();
    const bool photo = p.model == CameraModel::kPhoto;
    const Stats track = Statistics(p.num_points(), [&](int64_t k) {
      return p.point_offsets[k + 1] - p.point_offsets[k];
    });
    std::vector<int64_t> per_camera(nc, 0);
    for (int32_t c : p.obs_camera) ++per_camera[c];
    const Stats obs = Statistics(nc, [&](int64_t i) { return per_camera[i]; });
    // The RCS over the unknowns: cameras (poses) and intrinsic groups that
    // are not held fixed.
    const UnknownLayout layout(p);
    const std::vector<uint64_t> rcs = RcsBlockPattern(p, layout);
    std::vector<int64_t> neighbours(nc, 0);
    for (uint64_t b : CameraGraphPattern(p, layout, rcs)) {
      if (PackedRow(b) != PackedCol(b)) ++neighbours[PackedRow(b)], ++neighbours[PackedCol(b)];
    }
    const Stats degree = Statistics(nc, [&](int64_t i) { return neighbours[i]; });
    // The structure alone: the values are never needed here.
    const RcsSystem structure = RcsSystem::ForPattern(layout, rcs, false);
    const BsmcMatrix& S = structure.S;
    const double rows = layout.num_block_rows();
    const double sparsity = (2.0 * static_cast<double>(rcs.size()) - rows) / (rows * rows);
    std::printf("%s (%s)\n", args[0].c_str(),
                input.KindName());
    std::printf("  model         %s\n",
                photo ? "photogrammetric (6-parameter pose per image, shared intrinsic groups)"
                      : "BAL (9 parameters per camera)");
    std::printf("  %s  %ld\n", photo ? "images      " : "cameras     ", static_cast<long>(nc));
    if (photo) {
      std::printf("  intrinsic groups  %ld\n", static_cast<long>(p.num_groups()));
      // Groups per lens model, in the table's order.
      for (const LensModelInfo& m : LensModels()) {
        int64_t n = 0;
        for (int64_t g = 0; g < p.num_groups(); ++g) n += p.group_model(g) == m.id;
        if (n > 0) std::printf("    %-26s %ld (%s)\n", m.name, static_cast<long>(n), m.params);
      }
    }
    std::printf("  points        %ld\n  observations  %ld\n",
                static_cast<long>(p.num_points()), static_cast<long>(p.num_observations()));
    const int64_t fixed = std::count_if(p.fixed_cameras.begin(), p.fixed_cameras.end(),
                                        [](uint8_t f) { return f != 0; });
    const int64_t partly = std::count_if(p.fixed_intrinsics.begin(), p.fixed_intrinsics.end(),
                                         [](uint16_t m) { return m != 0; });
    if (fixed > 0 || partly > 0) {
      std::printf("  held fixed    %ld %s; %ld intrinsic groups with fixed parameters\n",
                  static_cast<long>(fixed), photo ? "image poses" : "cameras",
                  static_cast<long>(partly));
    }
    std::printf("  track length (observations per point)   min %ld  mean %.2f  max %ld\n",
                static_cast<long>(track.min), track.mean, static_cast<long>(track.max));
    std::printf("  observations per camera                 min %ld  mean %.1f  max %ld\n",
                static_cast<long>(obs.min), obs.mean, static_cast<long>(obs.max));
    std::printf("  cameras sharing a point with a camera   min %ld  mean %.1f  max %ld\n",
                static_cast<long>(degree.min), degree.mean, static_cast<long>(degree.max));
    std::printf("  RCS: %ld block rows, %ld unknowns, %ld blocks in the upper triangle, "
                "sparsity %.3g\n",
                static_cast<long>(layout.num_block_rows()), static_cast<long>(layout.num_unknowns()),
                static_cast<long>(S.num_blocks()), sparsity);
    std::printf("  RCS in BSMC: %.3f MiB (structure %.3f MiB, values %.3f MiB); CSR: %.3f MiB (%.2fx)\n",
                (S.StructureBytes() + S.ValueBytes()) / 1048576.0, S.StructureBytes() / 1048576.0,
                S.ValueBytes() / 1048576.0, S.CsrBytes() / 1048576.0,
                static_cast<double>(S.CsrBytes()) / (S.StructureBytes() + S.ValueBytes()));
    LmOptions defaults;
    defaults.num_threads = omp_get_num_procs();
    const MemoryEstimate e = EstimateSolveMemory(p, structure, defaults, CurrentResidentBytes(),
                                                 PeakResidentBytes());
    const int64_t available = AvailableMemoryBytes();
    std::printf("  dba solve's peak memory (defaults, %d threads): about %s; available %s\n",
                defaults.num_threads, e.Describe().c_str(),
                available < 0 ? "not known"
                              : FormatBytes(available + CurrentResidentBytes()).c_str());
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "dba info: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace dba
