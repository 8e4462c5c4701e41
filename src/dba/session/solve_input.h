// What `dba solve` reads and writes besides the solve itself: the input as a
// problem (BAL text, dba binary, or a COLMAP sparse model directory), which
// of its parameters are unknowns, and the outputs (problem files, a COLMAP
// model written back, a PLY point cloud).
//
// Thread safety: functions touch only the files they name.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include <array>
#include <unordered_map>
#include <unordered_set>

#include <Eigen/Core>

#include "dba/io/image_names.h"
#include "dba/problem/fixings.h"
#include "dba/io/colmap_model.h"
#include "dba/io/colmap_problem.h"
#include "dba/io/input_source.h"
#include "dba/lm/outlier_rejection.h"
#include "dba/problem/problem.h"

namespace dba {

// Which parameters are unknowns.
struct UnknownsOptions {
  // COLMAP input: one intrinsic group per COLMAP camera (true), or one per
  // image.
  bool shared_intrinsics = true;
  // Intrinsics held fixed by name (photogrammetric model only), in every
  // group or in one: a COLMAP camera id for a COLMAP input, a 0-based group
  // index otherwise.
  std::vector<IntrinsicFixing> fixed_intrinsics;
  // Images whose pose (BAL: whole camera) is held fixed: COLMAP image ids for
  // a COLMAP input, 0-based camera indices otherwise.
  std::vector<int64_t> fixed_images;
  // --fix-images all, and images named (COLMAP input: its image names).
  bool fix_all_images = false;
  std::vector<std::string> fixed_image_names;
  // The photogrammetric model's principal points are held fixed unless
  // asked (COLMAP's refine_principal_point 0, photogrammetric practice
  // without a calibration target).
  bool refine_principal_point = false;
  // Rigs: the sensors' poses (sensor_from_rig) refined as the problem poses
  // them (true), or all held (--rig-geometry fixed); or those of these
  // sensors held (--rig-geometry fixed:IDS: COLMAP camera ids, or 0-based
  // groups of a .dba problem or arrays).
  bool refine_rig_geometry = true;
  std::vector<int64_t> held_sensors;
  bool rig_geometry_given = false;  // --rig-geometry: the problem must have rigs
};

// --fix-images's value into `u`: all, or comma-separated ids and (COLMAP)
// image names. UsageError naming the flag for an empty item.
void ParseImageFixing(const std::string& flag, const std::string& value, UnknownsOptions* u);

// "[GROUP:]NAMES" -> the names (a comma-separated list, or all; none gives
// no names) in group GROUP, or in every group. The names are checked
// against the models when the input is read; throws UsageError naming the
// flag for an empty list or a bad group.
IntrinsicFixing ParseIntrinsicFixing(const std::string& flag, const std::string& value);
// "3,7,12" -> ids; throws std::invalid_argument naming the flag.
std::vector<int64_t> ParseIdList(const std::string& flag, const std::string& value);

// Reads the input and marks the fixed parameters. Throws InputError for bad
// input (file, line or entry, what is wrong), std::invalid_argument for
// fixings that do not fit the problem (an index out of range, intrinsics of
// a BAL problem). `names` (optional): a COLMAP input's image names (left
// empty for other inputs).
// A COLMAP input's cameras as COLMAP counts them: all the model's, and
// those the problem's images use.
struct ColmapCameraCounts {
  int64_t all = 0, used = 0;
  int64_t sensors_not_modelled = 0;  // ColmapProblem's
};
Problem LoadSolveInput(const InputSource& input, const UnknownsOptions& unknowns,
                       ImageNames* names = nullptr, ColmapCameraCounts* cameras = nullptr);

// The command line's fixings of a problem read from a file (not COLMAP) as
// data (problem/fixings.h), checked against its camera side: UsageError for
// an image or group that does not exist, intrinsics of a BAL problem, or a
// name no targeted group's model has.
Fixings CheckedFixings(const UnknownsOptions& unknowns, const CameraSide& side);
// The command line's fixings as data, unchecked (a rank reading its share
// of a .dba applies them).
Fixings FixingsOf(const UnknownsOptions& unknowns);
// --rig-geometry's value into `u`: refine, fixed or fixed:ID,ID...
// UsageError naming the flag otherwise.
void ParseRigGeometry(const std::string& flag, const std::string& value, UnknownsOptions* u);
// CheckedFixings, then marks them in `problem` (--rig-geometry's held
// sensors too), then composes the images' poses from the frames (rigs).
void ApplyFixings(const UnknownsOptions& unknowns, Problem* problem);

// Output kinds, by the output path: .dba binary, .txt/.bz2 BAL text,
// anything else a COLMAP model directory (COLMAP input only).
enum class OutputKind { kBinary, kBalText, kColmap };
// Throws std::invalid_argument when the output cannot hold the problem (BAL
// text and the photogrammetric model, a COLMAP directory for a non-COLMAP
// input), when `colmap_format` is given for another kind of output, or when
// the output directory holds a COLMAP model in the other format (it would
// shadow the one written), before any solving.
OutputKind CheckOutput(const InputSource& input, const std::string& output, CameraModel model,
                       std::optional<ColmapFormat> colmap_format = std::nullopt);

// A COLMAP input as read: the model, and the problem cut from it with the
// map back to the model's entries.
struct ColmapInput {
  ColmapModel model;
  ColmapProblem source;
  ColmapFormat format = ColmapFormat::kBinary;  // the input's
};
ColmapInput ReadColmapInput(const InputSource& input, const UnknownsOptions& unknowns);

// Writes the adjusted cameras and points into `input.model` and saves it to
// the directory `output`, as text or binary (default: the input's). Every
// image's camera, intrinsics and points are updated as UpdateColmapModel
// says.
// With `kept` (after outlier rejection: a flag per observation and per point
// of the problem as loaded), what was dropped leaves the model too
// (RemoveDroppedObservations); `points` are then in the loaded numbering.
void WriteColmapOutput(const std::vector<double>& cameras, const std::vector<double>& points,
                       const std::string& output, std::optional<ColmapFormat> format,
                       ColmapInput* input, const KeptObservations* kept = nullptr);

// The colours of the problem's points (3 per point).
std::vector<uint8_t> PointColours(const ColmapInput& input);

}  // namespace dba
