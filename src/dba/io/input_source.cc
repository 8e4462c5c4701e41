// An input's kind decided once, and a problem of any kind read; see
// input_source.h.
#include "dba/io/input_source.h"

#include <filesystem>

#include "dba/camera/rig_pose.h"
#include "dba/io/colmap_problem.h"
#include "dba/io/read_problem.h"

namespace dba {

const char* InputSource::KindName() const {
  switch (kind) {
    case InputKind::kColmap: return "COLMAP model";
    case InputKind::kBinary: return "dba binary";
    case InputKind::kBalText: break;
  }
  return "BAL text";
}

InputSource DecideInput(const std::string& path) {
  InputSource source;
  source.path = path;
  std::error_code ec;
  if (std::filesystem::is_directory(path, ec)) {
    if (const std::optional<ColmapFormat> format = DetectColmapFormat(path)) {
      source.kind = InputKind::kColmap;
      source.colmap_format = *format;
    }
    return source;  // another directory: ReadProblem says what it holds
  }
  if (IsBinaryProblem(path)) source.kind = InputKind::kBinary;
  return source;
}

Fixings DefaultFixings() {
  Fixings f;
  f.principal_point = true;
  return f;
}

Problem ReadInputProblem(const InputSource& source, const Fixings& fixings) {
  Problem p;
  if (source.colmap()) {
    const ColmapModel model = ReadColmapModel(source.path);
    p = std::move(ProblemFromColmap(model, ColmapProblemOptions(), source.path).problem);
  } else {
    p = ReadProblem(source.path);
  }
  ApplyFixings(fixings, &p);
  ComposeRigImages(&p);  // the frames are authoritative
  return p;
}

}  // namespace dba
