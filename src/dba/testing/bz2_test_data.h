// bzip2 data for the tests of io/ (bz2_blocks, text_pieces, the BAL
// readers): compression by libbz2 at a chosen level (level 1: 100 kB blocks,
// so small test data has several), and texts whose compressed blocks hold a
// block or end-of-stream magic by chance.
//
// Thread safety: pure functions.
#pragma once

#include <bzlib.h>

#include <cstdint>
#include <random>
#include <stdexcept>
#include <string>
#include <vector>

namespace dba::testing {

inline std::string Bz2Compress(const std::string& text, int level) {
  std::vector<char> out(text.size() + text.size() / 100 + 1024);
  unsigned int len = static_cast<unsigned>(out.size());
  const int rc = BZ2_bzBuffToBuffCompress(out.data(), &len, const_cast<char*>(text.data()),
                                          static_cast<unsigned>(text.size()), level, 0, 0);
  if (rc != BZ_OK) throw std::runtime_error("BZ2_bzBuffToBuffCompress: " + std::to_string(rc));
  return std::string(out.data(), len);
}

// `size` bytes whose every bzip2 block carries `magic` (48 bits) by chance:
// a block stores which byte values it uses as 16 bits (one per range of 16
// values), then 16 bits per range used. With every range used, ranges 4-6
// spell the magic when the bytes used there are its bits; the other ranges
// use one value each. Bytes drawn at random from that set, no run of 4 (a
// run would add its length's byte to the set).
inline std::string TextCarryingMagic(uint64_t magic, size_t size, uint32_t seed) {
  std::vector<unsigned char> values;
  for (int range = 0; range < 16; ++range) {
    const unsigned bits =
        range >= 4 && range <= 6 ? static_cast<unsigned>(magic >> (16 * (6 - range))) & 0xFFFF : 0x8000;
    for (int j = 0; j < 16; ++j) {
      if ((bits >> (15 - j)) & 1) values.push_back(static_cast<unsigned char>(16 * range + j));
    }
  }
  std::mt19937 random(seed);
  std::string text;
  text.reserve(size);
  while (text.size() < size) {
    const char c = static_cast<char>(values[random() % values.size()]);
    const size_t n = text.size();
    if (n >= 3 && text[n - 1] == c && text[n - 2] == c && text[n - 3] == c) continue;
    text.push_back(c);
  }
  return text;
}

}  // namespace dba::testing
