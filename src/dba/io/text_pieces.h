// The text of a file, plain or bzip2 (by content: "BZh"), handed out in
// pieces in file order (docs/design.md §4.3). bzip2 blocks are cut out by
// io/bz2_block_splitter and decoded on a pool of threads, a window of blocks
// ahead of the reader: memory is bounded by the window, not the file. Every
// block's CRC and every stream's combined CRC are checked; a block that fails
// to decode is tried joined to the next ones of its stream (a magic by chance
// inside compressed data), then refused. Plain text is read in 1 MiB pieces.
// The window is 8 blocks per thread, fewer when blocks are large (a block
// of long runs decodes to up to 46 MB): about 64 MiB of text ahead at most,
// and one block per thread and one more at least.
// An optional `prepare` runs on each piece on the pool (the BAL reader counts
// its tokens there) before it is handed out.
//
// Thread safety: one owner; `prepare` runs on the pool's threads.
#pragma once

#include <atomic>
#include <cstdint>
#include <cstdio>
#include <deque>
#include <exception>
#include <functional>
#include <memory>
#include <stdexcept>
#include <string>
#include <vector>

#include "dba/common/task_pool.h"
#include "dba/io/bz2_block_splitter.h"
#include "dba/io/text_tokens.h"

namespace dba {

// Corrupt or truncated bzip2 data, or a read error, after all the text
// before it was handed out. The message names the byte, not the file.
class TextDataError : public std::runtime_error {
 public:
  using std::runtime_error::runtime_error;
};

struct TextPiece {
  std::vector<char> text;
  TextCounts counts;  // set by the BAL reader's `prepare`
};

class TextPieceSource {
 public:
  using Prepare = std::function<void(TextPiece*)>;
  // Opens `path` (InputError naming it when it cannot be opened or read).
  // `threads` decode bzip2 blocks; a pool is started for bzip2 or `prepare`.
  TextPieceSource(const std::string& path, int threads, Prepare prepare = {});
  ~TextPieceSource();
  TextPieceSource(const TextPieceSource&) = delete;
  TextPieceSource& operator=(const TextPieceSource&) = delete;

  // The next piece (never empty), or nullptr at the end of the file. Throws
  // TextDataError.
  std::shared_ptr<const TextPiece> Next();

  bool is_bz2() const { return splitter_ != nullptr; }
  // The pool the pieces are decoded on (for the reader's own tasks), or
  // nullptr for plain text without `prepare`.
  TaskPool* pool() { return pool_.get(); }

 private:
  struct Slot {
    Bz2Unit unit;
    std::shared_ptr<TextPiece> piece = std::make_shared<TextPiece>();
    std::atomic<bool> done{false};
    bool ok = true;
    std::string why;
    std::exception_ptr failure;
  };
  size_t WindowSlots() const;
  void Fill(size_t slots);
  void AddBlock(Bz2Unit unit);
  void AddPlainPiece();
  void Submit(const std::shared_ptr<Slot>& slot, bool decode);
  void Wait(const Slot& slot);
  void JoinOrRefuse();

  // Tasks hold their slot, a copy of `prepare` and the cancel flag, never
  // `this`: the pool's destructor joins the running ones.
  std::unique_ptr<TaskPool> pool_;
  std::shared_ptr<std::atomic<bool>> cancelled_ = std::make_shared<std::atomic<bool>>(false);
  std::string path_;
  FILE* file_ = nullptr;
  Prepare prepare_;
  std::unique_ptr<Bz2BlockSplitter> splitter_;
  std::vector<char> first_;  // plain text: the bytes read while sniffing
  std::deque<std::shared_ptr<Slot>> window_;
  size_t threads_ = 1;
  size_t window_size_ = 0;
  size_t largest_piece_ = 0;  // of those handed out
  bool ended_ = false;  // the last unit is in the window
  uint32_t combined_crc_ = 0;
};

}  // namespace dba
