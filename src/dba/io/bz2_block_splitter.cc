// bzip2 streams cut into blocks; see bz2_block_splitter.h.
#include "dba/io/bz2_block_splitter.h"

#include <algorithm>
#include <cerrno>
#include <cstring>
#include <stdexcept>

namespace dba {
namespace {

constexpr size_t kReadBytes = size_t{4} << 20;

bool IsLevel(uint8_t c) { return c >= '1' && c <= '9'; }

std::string AtByte(int64_t byte) { return " at byte " + std::to_string(byte); }

}  // namespace

Bz2BlockSplitter::Bz2BlockSplitter(FILE* file, std::vector<uint8_t> first)
    : file_(file), buf_(std::move(first)) {}

Bz2Unit Bz2BlockSplitter::Next() {
  Compact();
  while (ready_.empty()) Step();
  Bz2Unit unit = std::move(ready_.front());
  ready_.pop_front();
  return unit;
}

void Bz2BlockSplitter::Step() {
  switch (state_) {
    case kHeader: ReadHeader(); return;
    case kInBlock: FindBlockEnd(); return;
    case kDone: ready_.push_back(Bz2Unit{}); return;
  }
}

bool Bz2BlockSplitter::Have(int64_t end_byte) {
  while (base_ + static_cast<int64_t>(buf_.size()) < end_byte && !eof_) {
    const size_t at = buf_.size();
    buf_.resize(at + kReadBytes);
    const size_t n = std::fread(buf_.data() + at, 1, kReadBytes, file_);
    buf_.resize(at + n);
    if (n < kReadBytes) {
      if (std::ferror(file_)) {
        throw std::runtime_error(std::string("read error: ") + std::strerror(errno));
      }
      eof_ = true;
    }
  }
  return base_ + static_cast<int64_t>(buf_.size()) >= end_byte;
}

// Drops the bytes before what is still to be cut, once they are a read's
// worth (so each byte moves about once).
void Bz2BlockSplitter::Compact() {
  const int64_t keep = state_ == kInBlock ? block_bit_ / 8 : header_byte_;
  const int64_t dead = keep - base_;
  if (dead < static_cast<int64_t>(kReadBytes)) return;
  buf_.erase(buf_.begin(), buf_.begin() + static_cast<std::ptrdiff_t>(dead));
  base_ = keep;
}

uint64_t Bz2BlockSplitter::Bits(int64_t bit, int count) const {
  return ReadBits(buf_.data(), bit - 8 * base_, count);
}

void Bz2BlockSplitter::Fail(const std::string& what, int64_t byte) {
  Bz2Unit u;
  u.kind = Bz2Unit::kError;
  u.error = what + AtByte(byte);
  u.file_byte = byte;
  ready_.push_back(std::move(u));
  state_ = kDone;
}

void Bz2BlockSplitter::ReadHeader() {
  const int64_t p = header_byte_;
  if (!Have(p + 1) && stream_ >= 0) {  // the end of the file, between streams
    state_ = kDone;
    return;
  }
  const bool header = Have(p + 4) && std::memcmp(&buf_[p - base_], "BZh", 3) == 0 &&
                      IsLevel(buf_[p + 3 - base_]);
  if (!header) {
    Fail(stream_ >= 0 ? "trailing data after the bzip2 stream is not bzip2"
                      : "corrupt bzip2 data (bad stream header)",
         p);
    return;
  }
  level_ = static_cast<char>(buf_[p + 3 - base_]);
  ++stream_;
  const int64_t first = 8 * (p + 4);
  if (!Have(p + 10)) {
    Fail("truncated bzip2 data: the file ends inside the stream header", p);
    return;
  }
  const uint64_t magic = Bits(first, 48);
  if (magic == kBz2EndMagic) {  // a stream without blocks
    EndStream(first);
  } else if (magic == kBz2BlockMagic) {
    state_ = kInBlock;
    block_bit_ = first;
    scan_bit_ = first + 80;  // past the magic and the block's CRC
    data_end_ = -1;
  } else {
    Fail("corrupt bzip2 data (no block after the stream header)", p + 4);
  }
}

// Looks for the magic that ends the block; reads on until one or the end.
void Bz2BlockSplitter::FindBlockEnd() {
  for (;;) {
    const int64_t avail_bits = 8 * (base_ + static_cast<int64_t>(buf_.size()));
    const std::optional<Bz2Magic> m = FindBz2Magic(buf_.data(), buf_.size(), scan_bit_ - 8 * base_);
    if (m.has_value()) {
      const int64_t bit = m->bit + 8 * base_;
      if (!m->end_of_stream) {
        EmitBlock(block_bit_, bit);
        block_bit_ = bit;
        scan_bit_ = bit + 80;
        data_end_ = -1;
        return;
      }
      if (EndsStream(bit)) {
        EmitBlock(block_bit_, bit);
        EndStream(bit);
        return;
      }
      if (data_end_ < 0) data_end_ = bit;  // trailing data, or a magic by chance
      scan_bit_ = bit + 1;
      continue;
    }
    scan_bit_ = std::max(scan_bit_, avail_bits - 47);
    if (avail_bits - block_bit_ > MaxBlockBits(level_)) {
      if (data_end_ >= 0) return AtEndOfData();
      return Fail("corrupt bzip2 data (no block or stream end within " +
                      std::to_string(MaxBlockBits(level_) / 8) + " bytes of the block)",
                  block_bit_ / 8);
    }
    if (!Have(avail_bits / 8 + 1)) return AtEndOfData();
  }
}

// An end-of-stream magic at `bit` ends the stream when the file ends after
// its CRC or another stream starts there.
bool Bz2BlockSplitter::EndsStream(int64_t bit) {
  const int64_t end = (bit + 80 + 7) / 8;
  if (!Have(end)) return false;
  if (!Have(end + 1)) return true;
  if (!Have(end + 10)) return false;
  const uint8_t* h = &buf_[end - base_];
  if (std::memcmp(h, "BZh", 3) != 0 || !IsLevel(h[3])) return false;
  const uint64_t magic = Bits(8 * (end + 4), 48);
  return magic == kBz2BlockMagic || magic == kBz2EndMagic;
}

void Bz2BlockSplitter::EmitBlock(int64_t begin_bit, int64_t end_bit) {
  Bz2Unit u;
  u.kind = Bz2Unit::kBlock;
  u.block = Bz2Block::FromBits(buf_.data(), begin_bit - 8 * base_, end_bit - 8 * base_, level_);
  u.block.file_byte = begin_bit / 8;
  u.block.file_end_byte = (end_bit + 7) / 8;
  u.stream = stream_;
  ready_.push_back(std::move(u));
}

void Bz2BlockSplitter::EndStream(int64_t bit) {
  Bz2Unit u;
  u.kind = Bz2Unit::kStreamEnd;
  u.stream = stream_;
  u.stream_crc = static_cast<uint32_t>(Bits(bit + 48, 32));
  u.file_byte = bit / 8;
  ready_.push_back(std::move(u));
  header_byte_ = (bit + 80 + 7) / 8;
  state_ = kHeader;
}

// No magic ends the block before the data does: the data ended at an
// end-of-stream magic followed by something else, or the file is cut short.
void Bz2BlockSplitter::AtEndOfData() {
  if (data_end_ >= 0 && Have((data_end_ + 80 + 7) / 8)) {
    EmitBlock(block_bit_, data_end_);
    EndStream(data_end_);
    const int64_t after = header_byte_;
    return Fail("trailing data after the bzip2 stream is not bzip2", after);
  }
  Fail("truncated bzip2 data: the file ends inside the block", block_bit_ / 8);
}

}  // namespace dba
