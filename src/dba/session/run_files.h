// The files one run of a command reads and writes, checked before any work
// is done: every output against the rule of io/output_target.h and for
// whether a file can be made there, and every pair: two outputs naming one
// file, or an output naming a file the run reads, are refused (UsageError,
// exit status 2) naming both, unless the pair is deliberate in-place work
// the command allows (`-o` over the problem it reads, `--checkpoint F
// --resume F`).
//
// Thread safety: one owner; Check touches only the files named.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "dba/io/colmap_model.h"
#include "dba/io/output_target.h"

namespace dba {

class RunFiles {
 public:
  // A file the run reads; a COLMAP model directory stands for its model
  // files. An empty path is skipped.
  void Input(const std::string& flag, const std::string& path);
  // A file the run writes. An empty path is skipped.
  void Output(const std::string& flag, const std::string& path, bool make_directory = false);
  // A file the run writes again and again and reads back (a checkpoint): a
  // FIFO or a character device is refused.
  void RewrittenOutput(const std::string& flag, const std::string& path);
  // A COLMAP model written into the directory `dir` (made when missing):
  // its cameras, images and points3D files in `format`; no other output may
  // name any file a reader of the model takes (io/colmap_model.h
  // ColmapModelFiles: rigs and frames, either format).
  // `with_rigs`: the model written holds COLMAP >= 3.12 rigs and frames
  // (in `format`; the other format's files there are refused); otherwise a
  // directory holding such files is refused.
  void ModelOutput(const std::string& flag, const std::string& dir, ColmapFormat format,
                   bool with_rigs = false);
  // The output `output_flag` may name what `input_flag` reads: it is
  // replaced when the run is done, after all reading.
  void AllowInPlace(const std::string& output_flag, const std::string& input_flag);

  // First puts right what killed runs left beside any of the files
  // (io/stale_temporaries.h), then checks. Throws UsageError for a refused
  // path or pair, std::runtime_error where a file cannot be made (a missing
  // or read-only directory).
  void Check() const;

 private:
  // kModelFile: a file of a COLMAP model written that this run does not
  // write (only compared with the other outputs).
  enum class Use { kReplaced, kRewritten, kModelFile };
  struct Named {
    std::string flag, path;
    bool make_directory = false;  // a model file, its directory made when missing
    Use use = Use::kReplaced;
  };
  bool Allowed(const std::string& output_flag, const std::string& input_flag) const;
  void Recover() const;
  void CheckPairs() const;
  std::vector<Named> inputs_, outputs_;
  std::vector<std::pair<std::string, std::string>> in_place_;
};

}  // namespace dba
