// dba solve's inputs and outputs; see solve_input.h.
#include "dba/session/solve_input.h"

#include <algorithm>
#include <numeric>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "dba/camera/rig_pose.h"
#include "dba/common/arguments.h"
#include "dba/common/error.h"
#include "dba/io/colmap_binary.h"
#include "dba/io/colmap_text.h"
#include "dba/io/path_kind.h"
#include "dba/io/read_problem.h"

namespace dba {
namespace {

std::vector<std::string> SplitCommas(const std::string& value) {
  std::vector<std::string> items;
  std::stringstream in(value);
  std::string item;
  while (std::getline(in, item, ',')) items.push_back(item);
  return items;
}

ColmapProblemOptions ColmapOptions(const UnknownsOptions& u) {
  ColmapProblemOptions o;
  o.shared_intrinsics = u.shared_intrinsics;
  return o;
}

// --fix-images of a COLMAP input: COLMAP image ids.
std::vector<uint32_t> ColmapImageIds(const UnknownsOptions& u) {
  std::vector<uint32_t> ids;
  for (int64_t id : u.fixed_images) {
    if (id < 0 || id > 0xffffffffLL) {
      throw UsageError("--fix-images: " + std::to_string(id) + " is not a COLMAP image id");
    }
    ids.push_back(static_cast<uint32_t>(id));
  }
  return ids;
}

}  // namespace

IntrinsicFixing ParseIntrinsicFixing(const std::string& flag, const std::string& value) {
  IntrinsicFixing fixing;
  std::string names = value;
  if (const size_t colon = value.find(':'); colon != std::string::npos) {
    fixing.group = ParseIdList(flag + " (group)", value.substr(0, colon)).front();
    if (value.substr(0, colon).find(',') != std::string::npos) {
      throw UsageError(flag + ": one group before ':' (got '" + value.substr(0, colon) + "')");
    }
    names = value.substr(colon + 1);
  }
  if (names == "none") return fixing;
  fixing.names = SplitCommas(names);
  if (fixing.names.empty()) throw UsageError(flag + ": empty list (use none to fix nothing)");
  for (const std::string& name : fixing.names) {
    if (name.empty()) throw UsageError(flag + ": an empty name in '" + value + "'");
  }
  return fixing;
}

std::vector<int64_t> ParseIdList(const std::string& flag, const std::string& value) {
  std::vector<int64_t> ids;
  for (const std::string& item : SplitCommas(value)) {
    size_t used = 0;
    long long id = -1;
    try {
      id = std::stoll(item, &used);
    } catch (const std::exception&) {
      used = 0;
    }
    if (item.empty() || used != item.size() || id < 0) {
      throw UsageError(flag + ": '" + item +
                                  "' is not a non-negative integer (expected e.g. 0,5,17)");
    }
    ids.push_back(id);
  }
  if (ids.empty()) throw UsageError(flag + ": empty list");
  return ids;
}

void ParseImageFixing(const std::string& flag, const std::string& value, UnknownsOptions* u) {
  if (value == "all") {
    u->fix_all_images = true;
    return;
  }
  for (const std::string& item : SplitCommas(value)) {
    if (item.empty()) throw UsageError(flag + ": an empty item in '" + Clipped(value) + "'");
    if (item.find_first_not_of("0123456789") == std::string::npos) {
      u->fixed_images.push_back(ParseIdList(flag, item).front());
    } else if (item[0] == '-' && item.find_first_not_of("0123456789", 1) == std::string::npos) {
      throw UsageError(flag + ": '" + item + "' is not a non-negative integer or an image name");
    } else {
      u->fixed_image_names.push_back(item);
    }
  }
  if (value.empty()) throw UsageError(flag + ": empty list");
}

Fixings FixingsOf(const UnknownsOptions& u) {
  Fixings f;
  f.images = u.fixed_images;
  for (const IntrinsicFixing& x : u.fixed_intrinsics) {
    if (!x.names.empty()) f.intrinsics.push_back(x);
  }
  f.all_images = u.fix_all_images;
  f.principal_point = !u.refine_principal_point;
  f.all_sensors = !u.refine_rig_geometry;
  f.sensors = u.held_sensors;
  return f;
}

void ApplyFixings(const UnknownsOptions& u, Problem* p) {
  if (!u.shared_intrinsics) {
    throw UsageError(
        "--intrinsics per-image applies to COLMAP models only (a .dba problem holds its "
        "own intrinsic groups)");
  }
  ApplyFixings(CheckedFixings(u, *p), p);
  ComposeRigImages(p);  // the frames are authoritative
}

void ParseRigGeometry(const std::string& flag, const std::string& value, UnknownsOptions* u) {
  u->rig_geometry_given = true;
  u->held_sensors.clear();
  u->refine_rig_geometry = value != "fixed";
  if (value == "refine" || value == "fixed") return;
  if (value.rfind("fixed:", 0) != 0) {
    throw UsageError(flag + ": '" + Clipped(value) +
                     "' is not refine, fixed or fixed:ID,ID... (sensors by COLMAP camera id, or "
                     "0-based intrinsic group of a .dba problem)");
  }
  u->held_sensors = ParseIdList(flag, value.substr(6));
}

namespace {

// --rig-geometry on a problem without rigs has nothing to hold or refine.
void RefuseRigGeometryWithoutRigs(const UnknownsOptions& u, const CameraSide& side) {
  if (u.rig_geometry_given && !side.has_rigs()) {
    throw UsageError(
        "--rig-geometry: the problem has no rigs (a .dba version 4 problem, a COLMAP model with "
        "rigs beyond single cameras, or arrays with frame_indices have them)");
  }
}

}  // namespace

Fixings CheckedFixings(const UnknownsOptions& u, const CameraSide& side) {
  RefuseRigGeometryWithoutRigs(u, side);
  for (int64_t i : u.fixed_images) {
    if (i >= side.num_images()) {
      throw UsageError("--fix-images: camera " + std::to_string(i) +
                       " does not exist (the problem has " + std::to_string(side.num_images()) +
                       " cameras, 0-based)");
    }
  }
  if (!u.fixed_image_names.empty()) {
    throw UsageError("--fix-images: '" + Clipped(u.fixed_image_names.front()) +
                     "': images have names in COLMAP models only; give 0-based indices");
  }
  for (int64_t g : u.held_sensors) {
    if (!side.has_rigs() || g >= side.num_groups()) {
      throw UsageError("--rig-geometry fixed:" + std::to_string(g) + ": " +
                       (side.has_rigs() ? "intrinsic group " + std::to_string(g) +
                                              " does not exist (the problem has " +
                                              std::to_string(side.num_groups()) + ", 0-based)"
                                        : std::string("the problem has no rigs")));
    }
  }
  const Fixings f = FixingsOf(u);
  if (!f.intrinsics.empty() && side.model != CameraModel::kPhoto) {
    throw UsageError(
        "--fix-intrinsics needs the photogrammetric model (a COLMAP model, or a .dba "
        "problem with shared intrinsics); a BAL camera's 9 parameters are one block");
  }
  try {
    FixedIntrinsicsAfter(f, side);  // the names against the groups' models
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--fix-intrinsics: ") + e.what());
  }
  return f;
}

Problem LoadSolveInput(const InputSource& input, const UnknownsOptions& unknowns,
                       ImageNames* names, ColmapCameraCounts* cameras) {
  if (input.colmap()) {
    ColmapInput in = ReadColmapInput(input, unknowns);
    if (cameras != nullptr) {
      cameras->all = static_cast<int64_t>(in.model.cameras.size());
      std::vector<int64_t> used;
      for (int64_t j : in.source.image_index) used.push_back(in.model.images[j].camera_id);
      std::sort(used.begin(), used.end());
      cameras->used = std::unique(used.begin(), used.end()) - used.begin();
      cameras->sensors_not_modelled = in.source.sensors_not_modelled;
    }
    if (names != nullptr) {
      for (const ColmapImage& im : in.model.images) names->others.insert(im.name);
      const Problem& p = in.source.problem;
      for (size_t i = 0; i < in.source.image_index.size(); ++i) {
        const ColmapImage& im = in.model.images[in.source.image_index[i]];
        names->problem.push_back(im.name);
        names->index.emplace(im.name, static_cast<int32_t>(i));
        names->others.erase(im.name);
        const ColmapCamera& c = in.model.cameras[in.source.group_camera[p.camera_intrinsics[i]]];
        names->size.push_back({c.width, c.height});
        names->id.push_back(im.image_id);
      }
      std::vector<int32_t>& order = names->read_order;
      order.resize(in.source.image_index.size());
      std::iota(order.begin(), order.end(), 0);
      std::sort(order.begin(), order.end(), [&](int32_t a, int32_t b) {
        return in.source.image_index[a] < in.source.image_index[b];
      });
    }
    return std::move(in.source.problem);
  }
  Problem p = ReadProblem(input.path);
  ApplyFixings(unknowns, &p);
  return p;
}

OutputKind CheckOutput(const InputSource& input, const std::string& output, CameraModel model,
                       std::optional<ColmapFormat> colmap_format) {
  const PathKind path_kind = KindOfPath(output);
  const bool file = path_kind != PathKind::kOther;
  if (file && colmap_format.has_value()) {
    throw UsageError("--colmap-format: -o " + output + " is not a COLMAP model directory");
  }
  if (path_kind == PathKind::kBinary) return OutputKind::kBinary;
  if (path_kind != PathKind::kOther) {
    if (model == CameraModel::kPhoto) {
      throw UsageError(
          "-o " + output +
          ": BAL text cannot hold shared intrinsics; write a .dba file" +
          (input.colmap() ? " or a COLMAP model directory" : ""));
    }
    return OutputKind::kBalText;
  }
  if (!input.colmap()) {
    throw UsageError("-o " + output +
                                ": expected a .txt, .bz2 or .dba file (a COLMAP model "
                                "directory is written only for a COLMAP input)");
  }
  const ColmapFormat format = colmap_format.value_or(input.colmap_format);
  const std::optional<ColmapFormat> there = DetectColmapFormat(output);
  if (there.has_value() && *there != format) {
    throw UsageError(
        "-o " + output + ": holds a COLMAP model in " +
        (*there == ColmapFormat::kText ? "text" : "binary") +
        " form, which would be read instead of the one written; remove it or use "
        "--colmap-format " + (*there == ColmapFormat::kText ? "text" : "binary"));
  }
  return OutputKind::kColmap;
}

namespace {

// --rig-geometry fixed:IDS of a COLMAP model: each camera id's group, which
// must be a sensor of the model's rigs.
std::vector<int64_t> SensorGroups(const ColmapInput& in, const std::vector<int64_t>& ids) {
  std::vector<int64_t> groups;
  const Problem& p = in.source.problem;
  for (int64_t id : ids) {
    int64_t found = -1;
    for (size_t g = 0; g < in.source.group_camera.size(); ++g) {
      if (in.model.cameras[in.source.group_camera[g]].camera_id == id) found = static_cast<int64_t>(g);
    }
    if (found < 0 || !p.has_rigs()) {
      throw UsageError("--rig-geometry fixed:" + std::to_string(id) + ": COLMAP camera " +
                       std::to_string(id) + " is not a sensor of the model's rigs" +
                       (p.has_rigs() ? "" : " (it has none beyond single cameras)"));
    }
    groups.push_back(found);
  }
  return groups;
}

}  // namespace

ColmapInput ReadColmapInput(const InputSource& input, const UnknownsOptions& unknowns) {
  const std::vector<uint32_t> fixed_ids = ColmapImageIds(unknowns);  // refused before reading
  const std::string& path = input.path;
  ColmapInput in;
  in.format = input.colmap_format;
  in.model = ReadColmapModel(path);
  in.source = ProblemFromColmap(in.model, ColmapOptions(unknowns), path);
  RefuseRigGeometryWithoutRigs(unknowns, in.source.problem);
  Fixings fixings = ColmapFixings(in.model, in.source, fixed_ids, unknowns.fixed_image_names,
                                  unknowns.fixed_intrinsics, path);
  fixings.all_images = unknowns.fix_all_images;
  fixings.principal_point = !unknowns.refine_principal_point;
  fixings.all_sensors = !unknowns.refine_rig_geometry;
  fixings.sensors = SensorGroups(in, unknowns.held_sensors);
  try {
    ApplyFixings(fixings, &in.source.problem);
  } catch (const std::invalid_argument& e) {
    throw UsageError(std::string("--fix-intrinsics: ") + e.what());
  }
  ComposeRigImages(&in.source.problem);  // the frames are authoritative
  return in;
}

void WriteColmapOutput(const std::vector<double>& cameras, const std::vector<double>& points,
                       const std::string& output, std::optional<ColmapFormat> format,
                       ColmapInput* input, const KeptObservations* kept) {
  Problem& adjusted = input->source.problem;
  if (adjusted.cameras.size() != cameras.size() || adjusted.points.size() != points.size()) {
    throw std::runtime_error("the COLMAP model changed during the solve");
  }
  adjusted.cameras = cameras;
  adjusted.points = points;
  UpdateColmapModel(input->source, adjusted, &input->model);
  if (kept != nullptr) {
    RemoveDroppedObservations(input->source, adjusted, kept->observation, kept->point,
                              &input->model);
  }
  if (format.value_or(input->format) == ColmapFormat::kText) {
    WriteColmapText(input->model, output);
  } else {
    WriteColmapBinary(input->model, output);
  }
}

std::vector<uint8_t> PointColours(const ColmapInput& input) {
  std::vector<uint8_t> rgb;
  rgb.reserve(3 * input.source.point_index.size());
  for (int64_t k : input.source.point_index) {
    const auto& c = input.model.points3D[k].rgb;
    rgb.insert(rgb.end(), c.begin(), c.end());
  }
  return rgb;
}

}  // namespace dba
