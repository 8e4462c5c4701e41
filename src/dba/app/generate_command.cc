// `dba generate`; see generate_command.h.
#include "dba/app/generate_command.h"

#include <unistd.h>

#include <cstdio>
#include <iostream>
#include <stdexcept>
#include <tuple>

#include "dba/io/atomic_output_file.h"
#include "dba/io/path_kind.h"
#include "dba/session/run_files.h"
#include "dba/common/arguments.h"
#include "dba/common/memory.h"
#include "dba/synthetic/uav_generator.h"

namespace dba {
namespace {

void PrintHelp(std::ostream& out) {
  const UavSurveyOptions d;
  out << "Usage: dba generate OUTPUT [options]\n"
         "\n"
         "Writes a synthetic UAV survey with a known ground truth: nadir images along\n"
         "parallel flight strips over rolling terrain, every ground point observed by\n"
         "each image whose footprint holds it. OUTPUT ending in .dba is the binary\n"
         "format, written in two streaming passes (memory: the images plus a chunk);\n"
         "anything else is BAL text, built in memory (small sizes). The same options\n"
         "and seed give byte-identical files.\n"
         "\n"
         "Camera models: 'bal' writes one 9-parameter BAL camera per image (images of\n"
         "one physical camera get the same intrinsic values, as separate unknowns);\n"
         "'photo' writes a pose per image and one shared intrinsic group per physical\n"
         "camera, COLMAP's axes, .dba outputs only; the group's lens model is RADIAL\n"
         "(f, cx, cy, k1, k2) unless --camera-model names another.\n"
         "\n"
         "Options:\n"
         "  --images N              images (default " << d.images << ")\n"
         "  --features F            mean observations per image (default " << d.features_per_image << ")\n"
         "  --forward-overlap X     along-strip overlap in (0, 1) (default " << d.forward_overlap << ")\n"
         "  --side-overlap X        between-strip overlap in (0, 1) (default " << d.side_overlap << ")\n"
         "  --cameras C             physical cameras, one per strip in turn, whose intrinsics\n"
         "                          their images share (default " << d.physical_cameras << ")\n"
         "  --model bal|photo       camera model (default bal; see above)\n"
         "  --camera-model NAME     the groups' lens model (--model photo): any of\n"
         "                          dba solve --list-camera-models, with typical values\n"
         "                          (default RADIAL)\n"
         "  --field-of-view DEG     the lens's field of view across the image, in (0, 160)\n"
         "                          (default: that of a " << d.focal_px << " px focal length, about 53);\n"
         "                          fisheye models get the equidistant focal length, so\n"
         "                          wide angles and high-order terms are observed\n"
         "  --noise S               pixel noise sigma (default " << d.pixel_noise << ")\n"
         "  --priors FILE           also write GNSS camera-centre priors (dba solve\n"
         "                          --camera-priors): the true centres with noise\n"
         "  --gnss-sigma XY,Z       their σ in metres (default " << d.gnss_sigma_xy << "," << d.gnss_sigma_z << ")\n"
         "  --gnss-outliers F       a fraction F of the images gets a gross error of 20 to\n"
         "                          50 m instead (marked '# outlier' in the file)\n"
         "  --gcps FILE             also write ground control (dba solve --gcps): surveyed\n"
         "                          ground points measured in the images that see them\n"
         "  --control-points N      control points in it (default 0)\n"
         "  --check-points M        check points in it (default 0)\n"
         "  --gcp-sigma XY,Z        their survey σ in metres (default " << d.gcp_sigma_xy << "," << d.gcp_sigma_z << ")\n"
         "  --unaligned             start the survey in a random similarity frame (scale,\n"
         "                          rotation, shift), as a reconstruction before\n"
         "                          georeferencing; the truth stays in the world frame\n"
         "  --outliers F            replace a fraction F of the observations by mismatches:\n"
         "                          uniform random pixels of the image, at least 50 px from\n"
         "                          the true projection (default 0); the ground truth keeps\n"
         "                          the true pixels, so dba solve --truth tells them apart\n"
         "  --seed S                random seed (default " << d.seed << ")\n"
         "  --truth FILE            also write the ground truth (true parameters, noise-free\n"
         "                          observations), same format; give it to dba solve --truth\n"
         "  -h, --help              this text\n";
}

}  // namespace

int GenerateMain(const std::vector<std::string>& args) {
  UavSurveyOptions o;
  std::string output, truth;
  try {
    for (size_t i = 0; i < args.size(); ++i) {
      const std::string& a = args[i];
      auto value = [&]() -> const std::string& {
        if (i + 1 >= args.size()) throw std::invalid_argument(a + ": missing value");
        if (args[i + 1].empty()) throw std::invalid_argument(a + ": an empty value");
        return args[++i];
      };
      if (a == "-h" || a == "--help") {
        PrintHelp(std::cout);
        return 0;
      } else if (a == "--images") {
        o.images = ParseIntegerArgument(a, value(), 2);
      } else if (a == "--features") {
        o.features_per_image = ParseNumberArgument(a, value(), 1e-9);
      } else if (a == "--forward-overlap") {
        o.forward_overlap = ParseNumberArgument(a, value());
      } else if (a == "--side-overlap") {
        o.side_overlap = ParseNumberArgument(a, value());
      } else if (a == "--cameras") {
        o.physical_cameras = static_cast<int>(ParseIntegerArgument(a, value(), 1, 1000000));
      } else if (a == "--model") {
        const std::string& v = value();
        if (v == "bal") o.model = CameraModel::kBal;
        else if (v == "photo") o.model = CameraModel::kPhoto;
        else throw std::invalid_argument(a + ": expected bal or photo, got '" + v + "'");
      } else if (a == "--camera-model") {
        const std::string& v = value();
        const LensModelInfo* m = FindLensModel(v);
        if (m == nullptr) {
          throw std::invalid_argument(a + ": unknown camera model '" + v + "' (known: " +
                                      LensModelNames() + ")");
        }
        o.camera_model = m->id;
      } else if (a == "--field-of-view") {
        o.field_of_view = ParseNumberArgument(a, value());
        if (!(o.field_of_view > 0 && o.field_of_view < 160)) {
          throw std::invalid_argument(a + ": must be in (0, 160) degrees");
        }
      } else if (a == "--priors") {
        o.priors_path = value();
      } else if (a == "--gnss-sigma") {
        std::tie(o.gnss_sigma_xy, o.gnss_sigma_z) = ParseSigmaPair(a, value());
      } else if (a == "--gnss-outliers") {
        o.gnss_outliers = ParseNumberArgument(a, value());
        if (!(o.gnss_outliers >= 0 && o.gnss_outliers < 1)) {
          throw std::invalid_argument(a + ": must be in [0, 1)");
        }
      } else if (a == "--gcps") {
        o.gcps_path = value();
      } else if (a == "--control-points") {
        o.control_points = ParseIntegerArgument(a, value(), 0, 100000);
      } else if (a == "--check-points") {
        o.check_points = ParseIntegerArgument(a, value(), 0, 100000);
      } else if (a == "--gcp-sigma") {
        std::tie(o.gcp_sigma_xy, o.gcp_sigma_z) = ParseSigmaPair(a, value());
      } else if (a == "--unaligned") {
        o.unaligned = true;
      } else if (a == "--noise") {
        o.pixel_noise = ParseNumberArgument(a, value());
      } else if (a == "--seed") {
        o.seed = static_cast<uint64_t>(ParseIntegerArgument(a, value(), 0));
      } else if (a == "--outliers") {
        o.outlier_fraction = ParseNumberArgument(a, value());
        if (!(o.outlier_fraction >= 0 && o.outlier_fraction < 1)) {
          throw std::invalid_argument(a + ": must be in [0, 1)");
        }
      } else if (a == "--truth") {
        truth = value();
      } else if (!a.empty() && a[0] == '-') {
        throw std::invalid_argument("unknown option '" + a + "' (see dba generate --help)");
      } else if (output.empty()) {
        output = a;
      } else {
        throw std::invalid_argument("more than one output: '" + output + "' and '" + a + "'");
      }
    }
    if (output.empty()) throw std::invalid_argument("missing OUTPUT (see dba generate --help)");
    if (o.gcps_path.empty() != (o.control_points + o.check_points == 0)) {
      throw std::invalid_argument(o.gcps_path.empty()
                                      ? "--control-points/--check-points: no --gcps FILE to write"
                                      : "--gcps: give --control-points N and/or --check-points M");
    }
    auto binary = [](const std::string& p) {
      return KindOfPath(p) == PathKind::kBinary;
    };
    if (o.camera_model != LensModel::kRadial && o.model != CameraModel::kPhoto) {
      throw std::invalid_argument("--camera-model needs --model photo (a BAL camera is its own model)");
    }
    if (o.model == CameraModel::kPhoto && (!binary(output) || (!truth.empty() && !binary(truth)))) {
      throw std::invalid_argument(
          "--model photo needs .dba files (the BAL text format cannot hold shared intrinsics)");
    }
  } catch (const std::exception& e) {
    std::cerr << "dba generate: " << e.what() << "\n";
    return 2;
  }
  try {
    RunFiles files;  // four outputs, four files (session/run_files.h)
    files.Output("OUTPUT", output);
    files.Output("--truth", truth);
    files.Output("--priors", o.priors_path);
    files.Output("--gcps", o.gcps_path);
    files.Check();
  } catch (const UsageError& e) {
    std::cerr << "dba generate: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "dba generate: error: " << e.what() << "\n";
    return 1;
  }
  try {
    // Every file appears when all are written, or none does.
    OutputTransaction outputs;
    // Progress on a terminal only: a log file gets the summary line.
    const bool tty = ::isatty(2) != 0;
    int last = -1;
    const UavSurveySummary s = GenerateUavSurvey(o, output, truth, [&](double f) {
      const int pct = static_cast<int>(100 * f);
      if (tty && pct != last) {
        std::fprintf(stderr, "\rgenerating: %3d%%", pct);
        last = pct;
      }
    });
    outputs.Commit();
    if (tty) std::fprintf(stderr, "\n");
    const std::string groups =
        o.model == CameraModel::kPhoto
            ? " (photo model, " + std::to_string(s.intrinsic_groups) + " intrinsic groups)"
            : "";
    std::printf("%s: %ld images%s in %ld strips of %ld, %ld points, %ld observations "
                "(%.1f per image, %.2f per point), %.2f s, peak memory %.1f MiB\n",
                output.c_str(), static_cast<long>(s.images), groups.c_str(),
                static_cast<long>(s.strips),
                static_cast<long>(s.images_per_strip), static_cast<long>(s.points),
                static_cast<long>(s.observations), double(s.observations) / s.images,
                double(s.observations) / std::max<int64_t>(s.points, 1), s.seconds,
                PeakResidentBytes() / 1048576.0);
    return 0;
  } catch (const std::exception& e) {
    std::cerr << "dba generate: error: " << e.what() << "\n";
    return 1;
  }
}

}  // namespace dba
