// A run's files checked before the work; see run_files.h.
#include "dba/session/run_files.h"

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>

#include "dba/common/error.h"

namespace dba {
namespace {

namespace fs = std::filesystem;

const char* const kModelStems[] = {"cameras", "images", "points3D"};

std::string Join(const std::string& dir, const std::string& name) {
  return (fs::path(dir) / name).string();
}

bool IsCharacterDevice(const std::string& path) {
  struct stat st {};
  return ::stat(path.c_str(), &st) == 0 && S_ISCHR(st.st_mode);
}

}  // namespace

void RunFiles::Input(const std::string& flag, const std::string& path) {
  if (path.empty()) return;
  std::error_code ec;
  if (!fs::is_directory(path, ec)) {
    inputs_.push_back({flag, path});
    return;
  }
  for (const char* stem : kModelStems) {  // a COLMAP model: its files
    for (const char* ext : {".txt", ".bin"}) inputs_.push_back({flag, Join(path, stem + std::string(ext))});
  }
}

void RunFiles::Output(const std::string& flag, const std::string& path, bool make_directory) {
  if (!path.empty()) outputs_.push_back({flag, path, make_directory});
}

void RunFiles::ModelOutput(const std::string& flag, const std::string& dir, ColmapFormat format,
                           bool with_rigs) {
  std::error_code ec;
  if (dir.empty()) throw UsageError(flag + ": an empty path names no directory");
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
    throw UsageError(flag + " " + dir + ": is not a directory (a COLMAP model is written into "
                     "a directory, made when missing)");
  }
  // COLMAP >= 3.12 takes each image's pose from its frame: rigs and frames
  // files left beside the model written would give it the old poses. A
  // model read with (trivial) rigs and frames writes them anew, in its
  // output's format; the other format's are stale.
  const std::string ext = format == ColmapFormat::kText ? ".txt" : ".bin";
  for (const char* stale : {"rigs.txt", "rigs.bin", "frames.txt", "frames.bin"}) {
    if ((!with_rigs || !std::string(stale).ends_with(ext)) && fs::exists(Join(dir, stale), ec)) {
      throw UsageError(flag + " " + dir + ": holds " + stale +
                       " (COLMAP >= 3.12 rigs and frames), which would give the images written "
                       "their old poses; write into another directory, or remove the rigs and "
                       "frames files (COLMAP >= 3.12 makes one rig per camera and one frame per "
                       "image for a model without them)");
    }
  }
  for (const char* stem : kModelStems) Output(flag, Join(dir, stem + ext), true);
}

void RunFiles::AllowInPlace(const std::string& output_flag, const std::string& input_flag) {
  in_place_.emplace_back(output_flag, input_flag);
}

bool RunFiles::Allowed(const std::string& output_flag, const std::string& input_flag) const {
  return std::find(in_place_.begin(), in_place_.end(), std::make_pair(output_flag, input_flag)) !=
         in_place_.end();
}

// First the pairs (by identity: one file however it is named), then each
// output against the rule, then whether a file can be made there.
void RunFiles::Check() const {
  std::vector<std::optional<FileIdentity>> in(inputs_.size());
  for (size_t i = 0; i < inputs_.size(); ++i) {
    if (!IsCharacterDevice(inputs_[i].path)) in[i] = ExistingFileIdentity(inputs_[i].path);
  }
  std::vector<std::optional<FileIdentity>> out(outputs_.size());
  for (size_t i = 0; i < outputs_.size(); ++i) {
    const Named& o = outputs_[i];
    if (IsCharacterDevice(o.path)) continue;  // no file to replace (/dev/null)
    out[i] = PathIdentity(o.path);
    for (size_t j = 0; j < i; ++j) {
      if (out[j] == out[i]) {
        throw UsageError(outputs_[j].flag + " " + outputs_[j].path + " and " + o.flag + " " +
                         o.path + " name one file: one output would replace the other");
      }
    }
    for (size_t j = 0; j < inputs_.size(); ++j) {
      if (in[j] != out[i] || Allowed(o.flag, inputs_[j].flag)) continue;
      throw UsageError(o.flag + " " + o.path + " names " + inputs_[j].flag + " " +
                       inputs_[j].path + ", which this run reads: the output would replace it");
    }
  }
  std::vector<OutputTarget> targets;
  for (const Named& o : outputs_) targets.push_back(ResolveOutputTarget(o.path, o.make_directory));
  for (const OutputTarget& t : targets) CheckCreatable(t);
}

}  // namespace dba
