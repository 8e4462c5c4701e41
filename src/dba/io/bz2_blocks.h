// The pieces of a bzip2 stream that can be decoded apart (docs/design.md
// §4.3). A stream is "BZh" and a level digit, then blocks, each starting
// with the 48-bit magic 0x314159265359 and its 32-bit CRC, then the
// end-of-stream magic 0x177245385090 and the stream's combined CRC
// (c = (c << 1 | c >> 31) ^ block_crc over its blocks), padded to a byte.
// Magics are bit-aligned, not byte-aligned. A block is decoded by libbz2 as
// a stream of its own: "BZh" + level + the block's bits + the end-of-stream
// magic + the block's CRC as the combined one; libbz2 then checks both.
// A magic can occur by chance inside compressed data: such a block fails to
// decode, and is decoded again joined to the next (Bz2Block::Join).
//
// Thread safety: pure functions and values; DecodeBz2Block uses a cache of
// libbz2's buffers per thread.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

namespace dba {

inline constexpr uint64_t kBz2BlockMagic = 0x314159265359;
inline constexpr uint64_t kBz2EndMagic = 0x177245385090;

// A magic found at a bit offset (bits counted from the first byte's most
// significant bit, as bzip2 writes them).
struct Bz2Magic {
  int64_t bit = 0;
  bool end_of_stream = false;
};

// The first block or end-of-stream magic starting at a bit in [from_bit,
// 8 * size - 47) of data[0, size), or nullopt.
std::optional<Bz2Magic> FindBz2Magic(const uint8_t* data, size_t size, int64_t from_bit);

// `count` (<= 57) bits of `data` from `bit`, most significant first; the
// bytes they touch must be in data.
uint64_t ReadBits(const uint8_t* data, int64_t bit, int count);

// The stream's combined CRC after a block whose CRC is `block_crc`.
inline uint32_t CombineBz2Crc(uint32_t combined, uint32_t block_crc) {
  return ((combined << 1) | (combined >> 31)) ^ block_crc;
}

// A block's bits, copied out of the file as a one-block stream.
struct Bz2Block {
  std::vector<uint8_t> stream;  // "BZh" level, the block's bits, the end, the CRC
  int64_t bits = 0;             // the block's bits in `stream` (from byte 4)
  uint32_t crc = 0;             // the CRC the block stores (32 bits after its magic)
  char level = '9';
  int64_t file_byte = 0;        // where the block starts in the file (its first byte)
  int64_t file_end_byte = 0;    // where it ends (the byte holding its last bit, + 1)

  // Bits [begin_bit, end_bit) of data, which start with a block magic.
  static Bz2Block FromBits(const uint8_t* data, int64_t begin_bit, int64_t end_bit, char level);
  // This block followed by `next` (a magic found by chance ended this one).
  static Bz2Block Join(const Bz2Block& block, const Bz2Block& next);
};

// Decodes the block into *text (replaced); false with *why when libbz2
// refuses it (corrupt data, a CRC that does not match) or the block's bits do
// not end exactly where its end-of-stream magic was placed.
bool DecodeBz2Block(const Bz2Block& block, std::vector<char>* text, std::string* why);

}  // namespace dba
