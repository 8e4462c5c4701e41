// A run's files checked before the work; see run_files.h.
#include "dba/session/run_files.h"

#include <sys/stat.h>

#include <algorithm>
#include <filesystem>
#include <stdexcept>
#include <string_view>

#include "dba/common/error.h"
#include "dba/io/stale_temporaries.h"

namespace dba {
namespace {

namespace fs = std::filesystem;

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
  for (const char* name : ColmapModelFiles()) inputs_.push_back({flag, Join(path, name)});
}

void RunFiles::Output(const std::string& flag, const std::string& path, bool make_directory) {
  if (!path.empty()) outputs_.push_back({flag, path, make_directory});
}

void RunFiles::RewrittenOutput(const std::string& flag, const std::string& path) {
  Output(flag, path);
  if (!path.empty()) outputs_.back().use = Use::kRewritten;
}

void RunFiles::ModelOutput(const std::string& flag, const std::string& dir, ColmapFormat format,
                           bool with_rigs) {
  std::error_code ec;
  if (dir.empty()) throw UsageError(flag + ": an empty path names no directory");
  if (fs::exists(dir, ec) && !fs::is_directory(dir, ec)) {
    throw UsageError(flag + " " + dir + ": is not a directory (a COLMAP model is written into "
                     "a directory, made when missing)");
  }
  // The model's files written, and the others a reader of the model would
  // take: no other output may be one of them. COLMAP >= 3.12 takes each
  // image's pose from its frame: rigs and frames files left beside the
  // model written would give it the old poses. A model read with (trivial)
  // rigs and frames writes them anew, in its output's format; the other
  // format's are stale.
  const std::string_view ext = format == ColmapFormat::kText ? ".txt" : ".bin";
  for (const std::string_view name : ColmapModelFiles()) {
    const bool rig_file = name.starts_with("rigs") || name.starts_with("frames");
    const bool written = name.ends_with(ext) && (with_rigs || !rig_file);
    const std::string path = Join(dir, std::string(name));
    if (rig_file && !written && fs::exists(path, ec)) {
      throw UsageError(flag + " " + dir + ": holds " + std::string(name) +
                       " (COLMAP >= 3.12 rigs and frames), which would give the images written "
                       "their old poses; write into another directory, or remove the rigs and "
                       "frames files (COLMAP >= 3.12 makes one rig per camera and one frame per "
                       "image for a model without them)");
    }
    outputs_.push_back({flag, path, true, written ? Use::kReplaced : Use::kModelFile});
  }
}

void RunFiles::AllowInPlace(const std::string& output_flag, const std::string& input_flag) {
  in_place_.emplace_back(output_flag, input_flag);
}

bool RunFiles::Allowed(const std::string& output_flag, const std::string& input_flag) const {
  return std::find(in_place_.begin(), in_place_.end(), std::make_pair(output_flag, input_flag)) !=
         in_place_.end();
}

// What a killed run left beside any of the files (a temporary, a
// replacement half done) is put right before they are compared or read.
void RunFiles::Recover() const {
  for (const std::vector<Named>* files : {&inputs_, &outputs_}) {
    for (const Named& f : *files) {
      struct stat st {};
      if (::stat(f.path.c_str(), &st) == 0 && !S_ISREG(st.st_mode)) continue;  // never replaced
      std::error_code ec;
      const fs::path real = fs::weakly_canonical(f.path, ec);  // where its leftovers are
      RecoverStaleTemporaries(ec ? f.path : real.string());
    }
  }
}

// Two outputs, or an output and an input, that are one file: first two
// outputs written, then an input, then a file of a model written.
void RunFiles::CheckPairs() const {
  std::vector<std::optional<FileIdentity>> in(inputs_.size());
  for (size_t i = 0; i < inputs_.size(); ++i) {
    if (!IsCharacterDevice(inputs_[i].path)) in[i] = ExistingFileIdentity(inputs_[i].path);
  }
  std::vector<std::optional<FileIdentity>> out(outputs_.size());
  for (size_t i = 0; i < outputs_.size(); ++i) {
    const Named& o = outputs_[i];
    if (IsCharacterDevice(o.path)) continue;  // no file to replace (/dev/null)
    out[i] = PathIdentity(o.path);
    const bool written = o.use != Use::kModelFile;
    for (size_t j = 0; j < i && written; ++j) {
      if (out[j] != out[i] || outputs_[j].use == Use::kModelFile) continue;
      throw UsageError(outputs_[j].flag + " " + outputs_[j].path + " and " + o.flag + " " +
                       o.path + " name one file: one output would replace the other");
    }
    for (size_t j = 0; j < inputs_.size() && written; ++j) {
      if (in[j] != out[i] || Allowed(o.flag, inputs_[j].flag)) continue;
      throw UsageError(o.flag + " " + o.path + " names " + inputs_[j].flag + " " +
                       inputs_[j].path + ", which this run reads: the output would replace it");
    }
    for (size_t j = 0; j < i; ++j) {
      if (out[j] != out[i]) continue;
      const Named& model = written ? outputs_[j] : o;
      const Named& other = written ? o : outputs_[j];
      const fs::path file(model.path);
      throw UsageError(other.flag + " " + other.path + " is " + file.filename().string() +
                       " of the COLMAP model " + model.flag + " " + file.parent_path().string() +
                       ": a reader of the model would take it for the model's own");
    }
  }
}

// First what killed runs left, then the pairs (by identity: one file however
// it is named), then each output against the rule, then whether a file can
// be made there.
void RunFiles::Check() const {
  Recover();
  CheckPairs();
  std::vector<OutputTarget> targets;
  for (const Named& o : outputs_) {
    if (o.use == Use::kModelFile) continue;  // not written
    targets.push_back(ResolveOutputTarget(o.path, o.make_directory));
    if (o.use == Use::kRewritten && targets.back().mode == OutputMode::kStream) {
      throw UsageError(o.flag + " " + o.path + ": is " +
                       (IsCharacterDevice(o.path) ? "a character device" : "a FIFO") + "; " +
                       o.flag + " writes a file that it replaces at every write and --resume "
                       "reads back: name a file");
    }
  }
  for (const OutputTarget& t : targets) CheckCreatable(t);
}

}  // namespace dba
