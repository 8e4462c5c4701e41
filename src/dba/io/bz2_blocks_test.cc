// Tests of io/bz2_blocks: magics found at every bit offset, a real stream's
// blocks decoded apart (their text and CRCs are the stream's), a block cut
// at a magic by chance decoded once joined, a damaged block refused.
#include "dba/io/bz2_blocks.h"

#include <gtest/gtest.h>

#include <cstring>
#include <random>
#include <string>
#include <vector>

#include "dba/testing/bz2_test_data.h"

namespace dba {
namespace {

using testing::Bz2Compress;

std::vector<uint8_t> Bytes(const std::string& s) { return std::vector<uint8_t>(s.begin(), s.end()); }

// Writes the 48 bits of `magic` at `bit` of data.
void PutMagic(std::vector<uint8_t>* data, int64_t bit, uint64_t magic) {
  for (int i = 0; i < 48; ++i, ++bit) {
    const uint8_t mask = static_cast<uint8_t>(0x80 >> (bit % 8));
    if ((magic >> (47 - i)) & 1) {
      (*data)[bit / 8] |= mask;
    } else {
      (*data)[bit / 8] &= static_cast<uint8_t>(~mask);
    }
  }
}

TEST(Bz2BlocksTest, FindsBothMagicsAtEveryBitOffset) {
  for (uint64_t magic : {kBz2BlockMagic, kBz2EndMagic}) {
    for (int64_t bit = 0; bit < 64; ++bit) {
      std::vector<uint8_t> data(32, 0);
      PutMagic(&data, 100 + bit, magic);
      const auto found = FindBz2Magic(data.data(), data.size(), 0);
      ASSERT_TRUE(found.has_value()) << bit;
      EXPECT_EQ(found->bit, 100 + bit);
      EXPECT_EQ(found->end_of_stream, magic == kBz2EndMagic);
      // From its own bit on it is found; from the next bit on it is not.
      EXPECT_EQ(FindBz2Magic(data.data(), data.size(), 100 + bit)->bit, 100 + bit);
      EXPECT_FALSE(FindBz2Magic(data.data(), data.size(), 101 + bit).has_value()) << bit;
    }
  }
}

TEST(Bz2BlocksTest, FindsAMagicEndingAtTheLastBit) {
  for (int64_t shift = 0; shift < 8; ++shift) {
    std::vector<uint8_t> data(16, 0xFF);
    const int64_t bit = 8 * 16 - 48 - shift;
    PutMagic(&data, bit, kBz2BlockMagic);
    const auto found = FindBz2Magic(data.data(), data.size(), 0);
    ASSERT_TRUE(found.has_value()) << shift;
    EXPECT_EQ(found->bit, bit);
    // Without its last byte it is not there.
    EXPECT_FALSE(FindBz2Magic(data.data(), data.size() - 1, 0).has_value()) << shift;
  }
}

TEST(Bz2BlocksTest, ReadBitsMostSignificantFirst) {
  const std::vector<uint8_t> data = {0x31, 0x41, 0x59, 0x26, 0x53, 0x59, 0xAB};
  EXPECT_EQ(ReadBits(data.data(), 0, 48), kBz2BlockMagic);
  EXPECT_EQ(ReadBits(data.data(), 4, 8), 0x14u);
  EXPECT_EQ(ReadBits(data.data(), 52, 4), 0xBu);
}

// The magics of a stream written by libbz2, in order.
std::vector<Bz2Magic> AllMagics(const std::vector<uint8_t>& data) {
  std::vector<Bz2Magic> found;
  int64_t from = 0;
  while (auto m = FindBz2Magic(data.data(), data.size(), from)) {
    found.push_back(*m);
    from = m->bit + 1;
  }
  return found;
}

std::string SomeText(size_t lines) {
  std::mt19937 random(7);
  std::string text;
  for (size_t i = 0; i < lines; ++i) {
    text += std::to_string(random() % 5000) + " " + std::to_string(i) + " " +
            std::to_string(static_cast<double>(random()) / 1e6) + "\n";
  }
  return text;
}

TEST(Bz2BlocksTest, BlocksOfAStreamDecodeApartToItsText) {
  const std::string text = SomeText(40000);  // about 1 MB: 10 blocks at level 1
  const std::vector<uint8_t> data = Bytes(Bz2Compress(text, 1));
  const std::vector<Bz2Magic> magics = AllMagics(data);
  ASSERT_GE(magics.size(), 4u);
  ASSERT_TRUE(magics.back().end_of_stream);
  EXPECT_EQ(magics.front().bit, 32);  // right after "BZh1"
  std::string decoded;
  uint32_t combined = 0;
  for (size_t i = 0; i + 1 < magics.size(); ++i) {
    ASSERT_FALSE(magics[i].end_of_stream);
    const Bz2Block block = Bz2Block::FromBits(data.data(), magics[i].bit, magics[i + 1].bit, '1');
    std::vector<char> piece;
    std::string why;
    ASSERT_TRUE(DecodeBz2Block(block, &piece, &why)) << i << ": " << why;
    EXPECT_LE(piece.size(), 100000u);
    decoded.append(piece.begin(), piece.end());
    combined = CombineBz2Crc(combined, block.crc);
  }
  EXPECT_EQ(decoded, text);
  EXPECT_EQ(combined, ReadBits(data.data(), magics.back().bit + 48, 32));
}

TEST(Bz2BlocksTest, ABlockCutInTwoDecodesOnlyJoined) {
  const std::string text = SomeText(3000);
  const std::vector<uint8_t> data = Bytes(Bz2Compress(text, 9));
  const std::vector<Bz2Magic> magics = AllMagics(data);
  ASSERT_EQ(magics.size(), 2u);
  const int64_t begin = magics[0].bit, end = magics[1].bit, cut = (begin + end) / 2 + 3;
  const Bz2Block head = Bz2Block::FromBits(data.data(), begin, cut, '9');
  Bz2Block tail = Bz2Block::FromBits(data.data(), cut, end, '9');
  std::vector<char> piece;
  std::string why;
  EXPECT_FALSE(DecodeBz2Block(head, &piece, &why));
  EXPECT_FALSE(DecodeBz2Block(tail, &piece, &why));
  const Bz2Block joined = Bz2Block::Join(head, tail);
  EXPECT_EQ(joined.bits, end - begin);
  ASSERT_TRUE(DecodeBz2Block(joined, &piece, &why)) << why;
  EXPECT_EQ(std::string(piece.begin(), piece.end()), text);
}

TEST(Bz2BlocksTest, ADamagedBlockIsRefused) {
  const std::string text = SomeText(3000);
  std::vector<uint8_t> data = Bytes(Bz2Compress(text, 9));
  const std::vector<Bz2Magic> magics = AllMagics(data);
  ASSERT_EQ(magics.size(), 2u);
  data[data.size() / 2] ^= 0x10;
  const Bz2Block block = Bz2Block::FromBits(data.data(), magics[0].bit, magics[1].bit, '9');
  std::vector<char> piece;
  std::string why;
  EXPECT_FALSE(DecodeBz2Block(block, &piece, &why));
  EXPECT_EQ(why, "checksum or format error");
}

TEST(Bz2BlocksTest, TextCanCarryAMagicIntoItsBlocks) {
  for (uint64_t magic : {kBz2BlockMagic, kBz2EndMagic}) {
    const std::string text = testing::TextCarryingMagic(magic, 50000, 3);
    const std::vector<uint8_t> data = Bytes(Bz2Compress(text, 9));
    const std::vector<Bz2Magic> magics = AllMagics(data);
    // The real block magic, the one by chance in the block's table of
    // byte values (after its CRC, randomised bit, origin and 80 bits of
    // that table), the real end.
    ASSERT_EQ(magics.size(), 3u);
    EXPECT_EQ(magics[1].bit, magics[0].bit + 48 + 32 + 1 + 24 + 16 + 64);
    EXPECT_EQ(magics[1].end_of_stream, magic == kBz2EndMagic);
  }
}

}  // namespace
}  // namespace dba
