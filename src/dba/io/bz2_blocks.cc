// bzip2 blocks found, copied out and decoded apart; see bz2_blocks.h.
#include "dba/io/bz2_blocks.h"

#include <bzlib.h>

#include <algorithm>
#include <array>
#include <cstdlib>
#include <cstring>
#include <new>

namespace dba {
namespace {

// For two bytes at positions p + 1 and p + 2, the magics that may start in
// byte p: bit s for the block magic at bit offset s, bit 8 + s for the
// end-of-stream magic. Those bytes hold magic bits 8 - s .. 23 - s.
struct MagicFilter {
  std::array<uint16_t, 65536> shifts{};
  MagicFilter() {
    for (int s = 0; s < 8; ++s) {
      shifts[(kBz2BlockMagic >> (24 + s)) & 0xFFFF] |= uint16_t{1} << s;
      shifts[(kBz2EndMagic >> (24 + s)) & 0xFFFF] |= uint16_t{1} << (8 + s);
    }
  }
};

const MagicFilter& Filter() {
  static const MagicFilter filter;
  return filter;
}

// The magic at bit 8p + s, s the lowest of `shifts` (bits 0-7 and 8-15 as in
// MagicFilter) at or above `min_shift` that holds, if any.
std::optional<Bz2Magic> MagicAt(const uint8_t* data, size_t p, uint16_t shifts, int min_shift) {
  for (int s = min_shift; s < 8; ++s) {
    const bool block = (shifts >> s) & 1;
    const bool end = (shifts >> (8 + s)) & 1;
    if (!block && !end) continue;
    const int64_t bit = 8 * static_cast<int64_t>(p) + s;
    const uint64_t v = ReadBits(data, bit, 48);
    if (block && v == kBz2BlockMagic) return Bz2Magic{bit, false};
    if (end && v == kBz2EndMagic) return Bz2Magic{bit, true};
  }
  return std::nullopt;
}

// Appends bits, most significant first.
class BitWriter {
 public:
  explicit BitWriter(std::vector<uint8_t>* out) : out_(out) {}
  int64_t bits() const { return bits_; }
  void Put(uint64_t value, int count) {
    while (count > 0) {
      const int used = static_cast<int>(bits_ % 8);
      if (used == 0) out_->push_back(0);
      const int k = std::min(8 - used, count);
      const uint64_t chunk = (value >> (count - k)) & ((uint64_t{1} << k) - 1);
      out_->back() = static_cast<uint8_t>(out_->back() | (chunk << (8 - used - k)));
      bits_ += k;
      count -= k;
    }
  }
  // Bits [bit, bit + count) of src.
  void Copy(const uint8_t* src, int64_t bit, int64_t count) {
    if (bits_ % 8 != 0) {
      for (; count > 0; bit += 32, count -= 32) {
        const int k = static_cast<int>(std::min<int64_t>(32, count));
        Put(ReadBits(src, bit, k), k);
      }
      return;
    }
    const int s = static_cast<int>(bit % 8);
    const uint8_t* in = src + bit / 8;
    const int64_t bytes = (count + 7) / 8;
    const int64_t last = (bit + count - 1) / 8 - bit / 8;  // last byte of in that holds a bit
    const size_t at = out_->size();
    out_->resize(at + bytes);
    uint8_t* out = out_->data() + at;
    for (int64_t i = 0; i < bytes; ++i) {
      const unsigned next = i + 1 <= last ? in[i + 1] : 0;
      out[i] = static_cast<uint8_t>(s == 0 ? in[i] : (in[i] << s) | (next >> (8 - s)));
    }
    if (count % 8 != 0) out[bytes - 1] &= static_cast<uint8_t>(0xFF << (8 - count % 8));
    bits_ += count;
  }

 private:
  std::vector<uint8_t>* out_;
  int64_t bits_ = 0;
};

void StartStream(char level, BitWriter* w) {
  for (char c : {'B', 'Z', 'h', level}) w->Put(static_cast<uint8_t>(c), 8);
}

void EndStream(uint32_t crc, BitWriter* w) {
  w->Put(kBz2EndMagic, 48);
  w->Put(crc, 32);
}

// libbz2's two buffers (its state, and 4 bytes per byte of a block: 3.6 MB
// at level 9) kept per thread: allocated afresh for every block they were
// page-faulted in every time.
struct BufferCache {
  std::vector<void*> free;  // each preceded by its size
  ~BufferCache() {
    for (void* p : free) std::free(static_cast<char*>(p) - 16);
  }
};
thread_local BufferCache cache;

void* Allocate(void*, int n, int m) {
  const size_t size = static_cast<size_t>(n) * static_cast<size_t>(m);
  for (size_t i = 0; i < cache.free.size(); ++i) {
    void* p = cache.free[i];
    size_t held;
    std::memcpy(&held, static_cast<char*>(p) - 16, sizeof held);
    if (held == size) {
      cache.free.erase(cache.free.begin() + static_cast<std::ptrdiff_t>(i));
      return p;
    }
  }
  char* base = static_cast<char*>(std::malloc(size + 16));
  if (base == nullptr) return nullptr;
  std::memcpy(base, &size, sizeof size);
  return base + 16;
}

void Release(void*, void* p) {
  if (p == nullptr) return;
  if (cache.free.size() < 4) {
    cache.free.push_back(p);
  } else {
    std::free(static_cast<char*>(p) - 16);
  }
}

std::string LibBz2Error(int code) {
  switch (code) {
    case BZ_DATA_ERROR: return "checksum or format error";
    case BZ_DATA_ERROR_MAGIC: return "bad stream header";
    case BZ_MEM_ERROR: throw std::bad_alloc();
    default: return "libbz2 error " + std::to_string(code);
  }
}

}  // namespace

uint64_t ReadBits(const uint8_t* data, int64_t bit, int count) {
  const uint8_t* p = data + bit / 8;
  const int skip = static_cast<int>(bit % 8);
  const int bytes = (skip + count + 7) / 8;
  uint64_t v = 0;
  for (int i = 0; i < bytes; ++i) v = (v << 8) | p[i];
  v >>= 8 * bytes - skip - count;
  return count == 64 ? v : v & ((uint64_t{1} << count) - 1);
}

std::optional<Bz2Magic> FindBz2Magic(const uint8_t* data, size_t size, int64_t from_bit) {
  const uint16_t* shifts = Filter().shifts.data();
  const int64_t total = 8 * static_cast<int64_t>(size);
  if (from_bit < 0 || from_bit + 48 > total) return std::nullopt;
  size_t p = static_cast<size_t>(from_bit / 8);
  // The first byte: shifts below from_bit's are not looked at.
  if (p + 2 < size) {
    const uint16_t m = shifts[(data[p + 1] << 8) | data[p + 2]];
    if (m != 0) {
      for (int s = static_cast<int>(from_bit % 8); s < 8; ++s) {
        if (8 * static_cast<int64_t>(p) + s + 48 > total) return std::nullopt;
        if (auto found = MagicAt(data, p, m & ((0x101u << s)), s)) return found;
      }
    }
  }
  // A magic starting in byte p needs bytes up to p + 6 (p + 5 at shift 0).
  for (++p; p + 6 < size; ++p) {
    const uint16_t m = shifts[(data[p + 1] << 8) | data[p + 2]];
    if (m == 0) continue;
    if (auto found = MagicAt(data, p, m, 0)) return found;
  }
  if (p + 5 < size) {
    const uint16_t m = shifts[(data[p + 1] << 8) | data[p + 2]];
    if (m & 0x101) return MagicAt(data, p, m & 0x101, 0);
  }
  return std::nullopt;
}

Bz2Block Bz2Block::FromBits(const uint8_t* data, int64_t begin_bit, int64_t end_bit, char level) {
  Bz2Block b;
  b.level = level;
  b.bits = end_bit - begin_bit;
  b.crc = static_cast<uint32_t>(ReadBits(data, begin_bit + 48, 32));
  b.stream.reserve(static_cast<size_t>(b.bits / 8 + 16));
  BitWriter w(&b.stream);
  StartStream(level, &w);
  w.Copy(data, begin_bit, b.bits);
  EndStream(b.crc, &w);
  return b;
}

Bz2Block Bz2Block::Join(const Bz2Block& block, const Bz2Block& next) {
  Bz2Block b;
  b.level = block.level;
  b.bits = block.bits + next.bits;
  b.crc = block.crc;
  b.file_byte = block.file_byte;
  b.file_end_byte = next.file_end_byte;
  b.stream.reserve(static_cast<size_t>(b.bits / 8 + 16));
  BitWriter w(&b.stream);
  StartStream(b.level, &w);
  w.Copy(block.stream.data(), 32, block.bits);
  w.Copy(next.stream.data(), 32, next.bits);
  EndStream(b.crc, &w);
  return b;
}

bool DecodeBz2Block(const Bz2Block& block, std::vector<char>* text, std::string* why) {
  bz_stream s{};
  s.bzalloc = Allocate;
  s.bzfree = Release;
  int rc = BZ2_bzDecompressInit(&s, 0, 0);
  if (rc != BZ_OK) {
    *why = LibBz2Error(rc);
    return false;
  }
  s.next_in = reinterpret_cast<char*>(const_cast<uint8_t*>(block.stream.data()));
  s.avail_in = static_cast<unsigned>(block.stream.size());
  text->resize(static_cast<size_t>(block.level - '0') * 100000 + 4096);
  size_t produced = 0;
  for (;;) {
    if (produced == text->size()) text->resize(2 * text->size());
    s.next_out = text->data() + produced;
    s.avail_out = static_cast<unsigned>(std::min<size_t>(text->size() - produced, 1u << 30));
    const unsigned room = s.avail_out;
    rc = BZ2_bzDecompress(&s);
    produced += room - s.avail_out;
    if (rc == BZ_STREAM_END) break;
    if (rc != BZ_OK || (s.avail_in == 0 && s.avail_out > 0)) {
      BZ2_bzDecompressEnd(&s);
      *why = rc != BZ_OK ? LibBz2Error(rc) : "the block ends early";
      return false;
    }
  }
  const bool whole = s.avail_in == 0;
  BZ2_bzDecompressEnd(&s);
  if (!whole) {
    *why = "data after the block's end";
    return false;
  }
  text->resize(produced);
  return true;
}

}  // namespace dba
