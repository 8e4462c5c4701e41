// `dba generate`; see generate_command.h.
#include "dba/app/generate_command.h"

#include <unistd.h>

#include <algorithm>
#include <cstdio>
#include <iostream>
#include <stdexcept>
#include <tuple>

#include "dba/io/atomic_output_file.h"
#include "dba/io/path_kind.h"
#include "dba/session/run_files.h"
#include "dba/common/arguments.h"
#include "dba/common/option_table.h"
#include "dba/app/generate_budget.h"
#include "dba/common/memory.h"
#include "dba/synthetic/rig_survey.h"
#include "dba/synthetic/uav_generator.h"

namespace dba {
namespace {

// dba generate's arguments: the survey's options, the output and the truth.
struct GenerateArgs {
  UavSurveyOptions survey;
  std::string output, truth;
  bool cameras_given = false;  // --cameras, refused with --rig
  bool images_given = false;   // --images; without it a rig survey takes a multiple of its sensors
};
using Spec = OptionSpec<GenerateArgs>;
#define DBA_FIELD(path) [](auto& a) -> auto& { return a.path; }

// `spec`, which also notes in `given` that the option was given.
Spec NotingGiven(Spec spec, bool GenerateArgs::*given) {
  spec.set = [set = spec.set, given](GenerateArgs& a, const std::string& v) {
    set(a, v);
    a.*given = true;
  };
  return spec;
}

// The sizes of the survey, bounded so that a run ends in minutes, not hours.
std::vector<Spec> SurveyOptions() {
  std::vector<Spec> t;
  t.push_back(NotingGiven(
      IntegerOption<GenerateArgs>(
          "--images", "N",
          "images (with --rig a multiple of its sensors; unset, the largest one up to the default)",
          DBA_FIELD(survey.images), 2, 100000000),
      &GenerateArgs::images_given));
  t.push_back(NumberOption<GenerateArgs>("--features", "F", "mean observations per image",
                                         DBA_FIELD(survey.features_per_image), 1, 100000));
  t.push_back(NumberOption<GenerateArgs>("--forward-overlap", "X", "along-strip overlap",
                                         DBA_FIELD(survey.forward_overlap), 0.05, 0.95));
  t.push_back(NumberOption<GenerateArgs>("--side-overlap", "X", "between-strip overlap",
                                         DBA_FIELD(survey.side_overlap), 0.05, 0.95));
  t.push_back(NotingGiven(
      IntegerOption<GenerateArgs>(
          "--cameras", "C",
          "physical cameras, one per strip in turn, whose intrinsics their images share (not "
          "with --rig, whose sensors are its cameras)",
          DBA_FIELD(survey.physical_cameras), 1, 1000000),
      &GenerateArgs::cameras_given));
  t.push_back(ChoiceOption<GenerateArgs>(
      "--rig", {"none", "oblique5", "stereo", "ring6"},
      "multi-camera rigs (--model photo): every exposure (frame) fires all of the rig's "
      "sensors; oblique5 a nadir and four 45-degree obliques, stereo two nadir cameras 60 cm "
      "apart, ring6 six 45-degree obliques around the vertical; --images counts the images, "
      "a multiple of the sensors (frames = images / sensors, two or more); the sensors' true poses are off the nominal by ~0.3 "
      "degrees and ~1 cm, which the problem starts from; .dba version 4",
      [](GenerateArgs& a, size_t i) {
        static const char* const names[] = {"", "oblique5", "stereo", "ring6"};
        a.survey.rig = names[i];
      },
      [](const GenerateArgs& a) { return a.survey.rig.empty() ? std::string("none") : a.survey.rig; }));
  t.push_back(ChoiceOption<GenerateArgs>(
      "--model", {"bal", "photo"}, "camera model (see above)",
      [](GenerateArgs& a, size_t i) { a.survey.model = i == 0 ? CameraModel::kBal : CameraModel::kPhoto; },
      [](const GenerateArgs&) { return std::string("bal"); }));
  Spec lens = OptionEntry<GenerateArgs>(
      "--camera-model", OptionKind::kText, "NAME",
      "the groups' lens model (--model photo): any of dba solve --list-camera-models, with "
      "typical values (default RADIAL)");
  lens.set = [](GenerateArgs& a, const std::string& v) {
    const LensModelInfo* m = FindLensModel(v);
    if (m == nullptr) {
      throw std::invalid_argument("--camera-model: unknown camera model '" + v + "' (known: " +
                                  LensModelNames() + ")");
    }
    a.survey.camera_model = m->id;
  };
  t.push_back(lens);
  t.push_back(NumberOption<GenerateArgs>(
      "--field-of-view", "DEG",
      "the lens's field of view across the image, below 160 (default: that of a 1000 px focal "
      "length, about 53); fisheye models get the equidistant focal length, so wide angles and "
      "high-order terms are observed",
      DBA_FIELD(survey.field_of_view), 0, 159.9, true));
  t.back().default_text = {};
  t.push_back(NumberOption<GenerateArgs>("--noise", "S", "pixel noise sigma",
                                         DBA_FIELD(survey.pixel_noise), 0, 100));
  t.push_back(NumberOption<GenerateArgs>(
      "--outliers", "F",
      "replace a fraction F of the observations by mismatches: uniform random pixels of the "
      "image, at least 50 px from the true projection; the ground truth keeps the true pixels, "
      "so dba solve --truth tells them apart",
      DBA_FIELD(survey.outlier_fraction), 0, 0.99));
  t.push_back(IntegerOption<GenerateArgs>("--seed", "S", "random seed", DBA_FIELD(survey.seed), 0,
                                          int64_t{1} << 62));
  t.push_back(FlagOption<GenerateArgs>(
      "--unaligned",
      "start the survey in a random similarity frame (scale, rotation, shift), as a "
      "reconstruction before georeferencing; the truth stays in the world frame",
      DBA_FIELD(survey.unaligned)));
  return t;
}

// A "XY,Z" pair of σ into two fields.
template <class F>
Spec SigmaOption(std::string name, std::string help, F fields) {
  Spec s = OptionEntry<GenerateArgs>(name, OptionKind::kText, "XY,Z", std::move(help));
  s.set = [=](GenerateArgs& a, const std::string& v) {
    std::tie(fields(a).first, fields(a).second) = ParseSigmaPair(name, v);
  };
  return s;
}

std::vector<Spec> OutputsAndGeoreference() {
  std::vector<Spec> t;
  t.push_back(PathOption<GenerateArgs>(
      "--truth", "FILE",
      "also write the ground truth (true parameters, noise-free observations), same format; "
      "give it to dba solve --truth",
      DBA_FIELD(truth)));
  t.push_back(PathOption<GenerateArgs>(
      "--priors", "FILE",
      "also write GNSS camera-centre priors (dba solve --camera-priors): the true centres with "
      "noise",
      DBA_FIELD(survey.priors_path)));
  t.push_back(SigmaOption("--gnss-sigma", "their sigma in metres (default 2,4)", [](GenerateArgs& a) {
    return std::pair<double&, double&>(a.survey.gnss_sigma_xy, a.survey.gnss_sigma_z);
  }));
  t.push_back(NumberOption<GenerateArgs>(
      "--gnss-outliers", "F",
      "a fraction F of the images gets a gross error of 20 to 50 m instead (marked '# outlier' "
      "in the file)",
      DBA_FIELD(survey.gnss_outliers), 0, 0.99));
  Spec lever = OptionEntry<GenerateArgs>(
      "--lever-arm", OptionKind::kText, "X,Y,Z",
      "the GNSS antenna in metres in the camera's frame (x right, y down, z forward), with "
      "--rig in the rig's: the priors are the true antenna positions C + R^T (X,Y,Z), with --rig "
      "one per frame (named by its first image) (default 0,0,0)");
  lever.set = [](GenerateArgs& a, const std::string& v) {
    const std::array<double, 3> x = ParseTriple("--lever-arm", v, 1e3);
    a.survey.lever_arm = Eigen::Vector3d(x[0], x[1], x[2]);
  };
  t.push_back(lever);
  t.push_back(PathOption<GenerateArgs>(
      "--gcps", "FILE",
      "also write ground control (dba solve --gcps): surveyed ground points measured in the "
      "images that see them",
      DBA_FIELD(survey.gcps_path)));
  t.push_back(IntegerOption<GenerateArgs>("--control-points", "N", "control points in it",
                                          DBA_FIELD(survey.control_points), 0, 100000));
  t.push_back(IntegerOption<GenerateArgs>("--check-points", "M", "check points in it",
                                          DBA_FIELD(survey.check_points), 0, 100000));
  t.push_back(SigmaOption("--gcp-sigma", "their survey sigma in metres (default 0.02,0.02)",
                          [](GenerateArgs& a) {
                            return std::pair<double&, double&>(a.survey.gcp_sigma_xy,
                                                               a.survey.gcp_sigma_z);
                          }));
  return t;
}

#undef DBA_FIELD

const std::vector<Spec>& GenerateOptionTable() {
  static const std::vector<Spec> table = [] {
    std::vector<Spec> t = SurveyOptions();
    for (Spec& s : OutputsAndGeoreference()) t.push_back(std::move(s));
    return t;
  }();
  return table;
}

void PrintGenerateHelp(std::ostream& out) {
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
         "Options:\n";
  PrintOptions(GenerateOptionTable(), GenerateArgs(), out);
  out << "  -h, --help                 this text\n";
}

// What needs another option, or a kind of output, to make sense.
void CheckGenerateArgs(const GenerateArgs& a) {
  const UavSurveyOptions& o = a.survey;
  if (a.output.empty()) throw std::invalid_argument("missing OUTPUT (see dba generate --help)");
  if (o.gcps_path.empty() != (o.control_points + o.check_points == 0)) {
    throw std::invalid_argument(o.gcps_path.empty()
                                    ? "--control-points/--check-points: no --gcps FILE to write"
                                    : "--gcps: give --control-points N and/or --check-points M");
  }
  auto binary = [](const std::string& p) { return KindOfPath(p) == PathKind::kBinary; };
  if (o.camera_model != LensModel::kRadial && o.model != CameraModel::kPhoto) {
    throw std::invalid_argument("--camera-model needs --model photo (a BAL camera is its own model)");
  }
  if (o.model == CameraModel::kPhoto && (!binary(a.output) || (!a.truth.empty() && !binary(a.truth)))) {
    throw std::invalid_argument(
        "--model photo needs .dba files (the BAL text format cannot hold shared intrinsics)");
  }
  CheckRigSurvey(o, a.cameras_given);
}

}  // namespace

int GenerateMain(const std::vector<std::string>& args) {
  GenerateArgs a;
  try {
    bool help = false;
    ParseOptions(
        GenerateOptionTable(), args, &a,
        [&](const std::string& p) {
          if (!a.output.empty()) {
            throw std::invalid_argument("more than one output: '" + a.output + "' and '" + p + "'");
          }
          a.output = p;
        },
        &help, "generate");
    if (help) {
      PrintGenerateHelp(std::cout);
      return 0;
    }
    if (!a.survey.rig.empty() && !a.images_given) {
      // The default count, in whole frames of the rig (two or more).
      const int64_t s = RigSensorCount(a.survey.rig);
      a.survey.images = std::max(2 * s, a.survey.images / s * s);
    }
    CheckGenerateArgs(a);
  } catch (const std::exception& e) {
    std::cerr << "dba generate: " << e.what() << "\n";
    return 2;
  }
  try {
    RunFiles files;  // four outputs, four files (session/run_files.h)
    files.Output("OUTPUT", a.output);
    files.Output("--truth", a.truth);
    files.Output("--priors", a.survey.priors_path);
    files.Output("--gcps", a.survey.gcps_path);
    files.Check();
  } catch (const UsageError& e) {
    std::cerr << "dba generate: " << e.what() << "\n";
    return 2;
  } catch (const std::exception& e) {
    std::cerr << "dba generate: error: " << e.what() << "\n";
    return 1;
  }
  try {
    CheckGenerateFits(EstimateGenerate(a.survey, a.output, a.truth), AvailableMemoryBytes());
    // Every file appears when all are written, or none does.
    OutputTransaction outputs;
    // Progress on a terminal only: a log file gets the summary line.
    const bool tty = ::isatty(2) != 0;
    int last = -1;
    const UavSurveySummary s = GenerateUavSurvey(a.survey, a.output, a.truth, [&](double f) {
      const int pct = static_cast<int>(100 * f);
      if (tty && pct != last) {
        std::fprintf(stderr, "\rgenerating: %3d%%", pct);
        last = pct;
      }
    });
    outputs.Commit();
    if (tty) std::fprintf(stderr, "\n");
    const std::string groups =
        a.survey.model == CameraModel::kPhoto
            ? " (photo model, " + std::to_string(s.intrinsic_groups) + " intrinsic groups" +
                  (s.frames > 0 ? ", " + std::to_string(s.frames) + " frames of a " +
                                      a.survey.rig + " rig)"
                                : ")")
            : "";
    std::printf("%s: %ld images%s in %ld strips of %ld, %ld points, %ld observations "
                "(%.1f per image, %.2f per point), %.2f s, peak memory %.1f MiB\n",
                a.output.c_str(), static_cast<long>(s.images), groups.c_str(),
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
