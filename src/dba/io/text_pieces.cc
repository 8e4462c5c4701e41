// Text in pieces, bzip2 blocks decoded ahead on a pool; see text_pieces.h.
#include "dba/io/text_pieces.h"

#include <algorithm>
#include <cerrno>
#include <cstring>

#include "dba/common/error.h"

namespace dba {
namespace {

constexpr size_t kPlainPiece = size_t{1} << 20;
constexpr size_t kWindowBytes = size_t{64} << 20;

std::string Bytes(const Bz2Block& b) {
  return "bytes " + std::to_string(b.file_byte) + "-" + std::to_string(b.file_end_byte);
}

}  // namespace

TextPieceSource::TextPieceSource(const std::string& path, int threads, Prepare prepare)
    : path_(path), prepare_(std::move(prepare)) {
  file_ = std::fopen(path.c_str(), "rb");
  if (file_ == nullptr) {
    throw InputError(path, 0, std::string("cannot open: ") + std::strerror(errno));
  }
  first_.resize(kPlainPiece);
  const size_t n = std::fread(first_.data(), 1, first_.size(), file_);
  if (n < first_.size() && std::ferror(file_)) {
    const int error = errno;
    std::fclose(file_);
    throw InputError(path, 1, std::string("read error: ") + std::strerror(error));
  }
  first_.resize(n);
  const bool bz2 = n >= 3 && std::memcmp(first_.data(), "BZh", 3) == 0;
  if (bz2) {
    splitter_ = std::make_unique<Bz2BlockSplitter>(
        file_, std::vector<uint8_t>(first_.begin(), first_.end()));
    std::vector<char>().swap(first_);
  }
  // A window of a few blocks per thread keeps every thread busy while the
  // reader is held up (its first piece allocates the problem's arrays).
  const int workers = std::max(1, threads);
  threads_ = static_cast<size_t>(workers);
  window_size_ = static_cast<size_t>(std::min(8 * workers + 8, 512));
  if (bz2 || prepare_) pool_ = std::make_unique<TaskPool>(workers);
}

TextPieceSource::~TextPieceSource() {
  cancelled_->store(true);
  window_.clear();
  pool_.reset();  // joins the task running, drops the rest
  if (file_ != nullptr) std::fclose(file_);
}

void TextPieceSource::Submit(const std::shared_ptr<Slot>& slot, bool decode) {
  pool_->Submit([slot, decode, prepare = prepare_, cancelled = cancelled_] {
    try {
      if (!cancelled->load()) {
        if (decode) slot->ok = DecodeBz2Block(slot->unit.block, &slot->piece->text, &slot->why);
        if (slot->ok && prepare) prepare(slot->piece.get());
      }
    } catch (...) {
      slot->failure = std::current_exception();
    }
    slot->done.store(true);
  });
}

void TextPieceSource::Wait(const Slot& slot) {
  if (!slot.done.load()) pool_->WaitUntil([&] { return slot.done.load(); });
  if (slot.failure) std::rethrow_exception(slot.failure);
}

void TextPieceSource::AddBlock(Bz2Unit unit) {
  auto slot = std::make_shared<Slot>();
  slot->unit = std::move(unit);
  const bool block = slot->unit.kind == Bz2Unit::kBlock;
  if (block) {
    Submit(slot, true);
  } else {
    slot->done.store(true);
    ended_ = slot->unit.kind == Bz2Unit::kEnd || slot->unit.kind == Bz2Unit::kError;
  }
  window_.push_back(std::move(slot));
}

void TextPieceSource::AddPlainPiece() {
  auto slot = std::make_shared<Slot>();
  std::vector<char>& text = slot->piece->text;
  if (!first_.empty()) {
    text.swap(first_);
  } else {
    text.resize(kPlainPiece);
    const size_t n = std::fread(text.data(), 1, text.size(), file_);
    text.resize(n);
    if (n == 0 && std::ferror(file_)) {
      slot->unit.kind = Bz2Unit::kError;
      slot->unit.error = std::string("read error: ") + std::strerror(errno);
    }
  }
  if (text.empty()) {  // kEnd, or the error
    slot->done.store(true);
    ended_ = true;
  } else {
    slot->unit.kind = Bz2Unit::kBlock;
    if (prepare_) {
      Submit(slot, false);
    } else {
      slot->done.store(true);
    }
  }
  window_.push_back(std::move(slot));
}

size_t TextPieceSource::WindowSlots() const {
  if (largest_piece_ == 0) return threads_ + 1;  // until the first piece says how large
  return std::clamp(kWindowBytes / largest_piece_, threads_ + 1, window_size_);
}

void TextPieceSource::Fill(size_t slots) {
  while (!ended_ && window_.size() < slots) {
    if (!splitter_) {
      AddPlainPiece();
      continue;
    }
    Bz2Unit unit;
    try {
      unit = splitter_->Next();
    } catch (const std::runtime_error& e) {  // a read error
      unit.kind = Bz2Unit::kError;
      unit.error = e.what();
    }
    AddBlock(std::move(unit));
  }
}

std::shared_ptr<const TextPiece> TextPieceSource::Next() {
  for (;;) {
    Fill(WindowSlots());
    if (window_.empty()) return nullptr;
    Slot& s = *window_.front();
    switch (s.unit.kind) {
      case Bz2Unit::kEnd: return nullptr;
      case Bz2Unit::kError: throw TextDataError(s.unit.error);
      case Bz2Unit::kStreamEnd:
        if (s.unit.stream_crc != combined_crc_) {
          throw TextDataError("corrupt bzip2 data: the stream's combined CRC at byte " +
                              std::to_string(s.unit.file_byte) + " does not match its blocks'");
        }
        combined_crc_ = 0;
        window_.pop_front();
        continue;
      case Bz2Unit::kBlock: break;
    }
    Wait(s);
    if (!s.ok) JoinOrRefuse();
    if (splitter_) combined_crc_ = CombineBz2Crc(combined_crc_, s.unit.block.crc);
    std::shared_ptr<const TextPiece> piece = std::move(s.piece);
    largest_piece_ = std::max(largest_piece_, piece->text.size());
    window_.pop_front();
    return piece;
  }
}

// The first block in the window failed: a magic by chance may have cut it.
// Joined to the next blocks of its stream, as long as a block can be, it is
// decoded again; still failing, it is refused.
void TextPieceSource::JoinOrRefuse() {
  Slot& front = *window_.front();
  Bz2Block joined = front.unit.block;
  const int64_t max_bits = Bz2BlockSplitter::MaxBlockBits(joined.level);
  for (size_t i = 1;; ++i) {
    Fill(i + 1);
    if (i >= window_.size()) break;
    const Bz2Unit& next = window_[i]->unit;
    if (next.kind != Bz2Unit::kBlock || next.stream != front.unit.stream ||
        joined.bits + next.block.bits > max_bits) {
      break;
    }
    joined = Bz2Block::Join(joined, next.block);
    std::string why;
    auto piece = std::make_shared<TextPiece>();
    if (!DecodeBz2Block(joined, &piece->text, &why)) continue;
    if (prepare_) prepare_(piece.get());
    front.piece = std::move(piece);
    front.ok = true;
    window_.erase(window_.begin() + 1, window_.begin() + static_cast<std::ptrdiff_t>(i) + 1);
    return;
  }
  throw TextDataError("corrupt bzip2 data in the block at " + Bytes(front.unit.block) + " (" +
                      front.why + ")");
}

}  // namespace dba
