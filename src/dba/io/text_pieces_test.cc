// Tests of io/text_pieces (and the bz2_block_splitter under it): the text of
// multi-block, concatenated and empty bzip2 streams in order on 1-4 threads,
// blocks holding a magic by chance, and every kind of damage refused with
// its byte after the text before it: a flipped byte in the first, a middle
// and the last block, in the stream's CRC, a file cut short, trailing data.
#include "dba/io/text_pieces.h"

#include <gtest/gtest.h>

#include <regex>
#include <string>
#include <vector>

#include "dba/testing/bz2_test_data.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

using testing::Bz2Compress;

// Text bytes in a level-1 block (100,000 less libbz2's margin), for text
// without runs of 4 equal bytes (a run takes less).
constexpr size_t kBlockText = 99981;

std::string WriteFile(const std::string& name, const std::string& bytes) {
  const std::string path = testing::TempPath("text_pieces_test_" + name);
  EXPECT_TRUE(testing::WriteFileBytes(path, bytes));
  return path;
}

struct Read {
  std::string text;
  int pieces = 0;
  std::string error;  // empty: none
};

Read ReadAll(const std::string& path, int threads) {
  Read r;
  TextPieceSource source(path, threads);
  try {
    while (auto piece = source.Next()) {
      EXPECT_FALSE(piece->text.empty());
      r.text.append(piece->text.begin(), piece->text.end());
      ++r.pieces;
    }
    EXPECT_EQ(source.Next(), nullptr);  // stays at the end
  } catch (const TextDataError& e) {
    r.error = e.what();
  }
  return r;
}

std::string Lines(int64_t n, int64_t seed) {
  std::string s;
  for (int64_t i = 0; i < n; ++i) {
    s += std::to_string((i * 7919 + seed) % 100003) + " " + std::to_string(i) + " 0." +
         std::to_string((i * 104729 + seed) % 1000003) + "\n";
  }
  return s;
}

TEST(TextPiecesTest, MultiBlockStreamInOrderOnAnyThreads) {
  const std::string text = Lines(60000, 1);  // about 1.4 MB: 14+ blocks at level 1
  const std::string path = WriteFile("multi.bz2", Bz2Compress(text, 1));
  for (int threads : {1, 2, 4}) {
    const Read r = ReadAll(path, threads);
    EXPECT_EQ(r.error, "");
    EXPECT_EQ(r.text, text) << threads;
    EXPECT_EQ(r.pieces, static_cast<int>((text.size() + kBlockText - 1) / kBlockText)) << threads;
  }
}

TEST(TextPiecesTest, ConcatenatedAndEmptyStreamsReadAsOneText) {
  // pbzip2 writes one stream per chunk; `cat` joins any; the first part ends
  // inside a line; bzip2 of nothing is a stream without blocks.
  const std::string a = Lines(9000, 2) + "split ";
  const std::string b = "line\n" + Lines(7000, 3);
  const std::string path = WriteFile(
      "concat.bz2", Bz2Compress(a, 1) + Bz2Compress("", 9) + Bz2Compress(b, 5));
  const Read r = ReadAll(path, 3);
  EXPECT_EQ(r.error, "");
  EXPECT_EQ(r.text, a + b);
}

TEST(TextPiecesTest, PlainTextInMebibytePieces) {
  const std::string text = Lines(150000, 4);  // about 3.5 MB
  const Read r = ReadAll(WriteFile("plain.txt", text), 2);
  EXPECT_EQ(r.text, text);
  EXPECT_EQ(r.pieces, static_cast<int>((text.size() + (1 << 20) - 1) >> 20));
  TextPieceSource source(WriteFile("plain_empty.txt", ""), 2);
  EXPECT_FALSE(source.is_bz2());
  EXPECT_EQ(source.Next(), nullptr);
}

TEST(TextPiecesTest, MagicsByChanceInsideBlocksAreJoinedAgain) {
  // Every block carries a block magic (or an end-of-stream magic) in its
  // table of byte values: the splitter cuts there, the halves fail to
  // decode, joined they decode.
  for (uint64_t magic : {kBz2BlockMagic, kBz2EndMagic}) {
    const std::string text = testing::TextCarryingMagic(magic, 350000, 5);
    const std::string bz2 = Bz2Compress(text, 1);
    const std::string path = WriteFile("by_chance.bz2", bz2);
    for (int threads : {1, 3}) {
      const Read r = ReadAll(path, threads);
      EXPECT_EQ(r.error, "") << magic;
      EXPECT_TRUE(r.text == text) << magic << " on " << threads << " threads";
      EXPECT_EQ(r.pieces, 4);
    }
  }
}

// The byte range a "corrupt bzip2 data in the block at bytes X-Y" message
// names.
std::pair<long, long> NamedBlock(const std::string& message) {
  std::smatch m;
  if (!std::regex_search(message, m, std::regex("in the block at bytes ([0-9]+)-([0-9]+)"))) {
    return {-1, -1};
  }
  return {std::stol(m[1]), std::stol(m[2])};
}

TEST(TextPiecesTest, AFlippedByteIsRefusedWithItsBlockAfterTheTextBefore) {
  const std::string text = Lines(40000, 6);  // about 0.9 MB: 9+ blocks
  const std::string good = Bz2Compress(text, 1);
  const size_t first = 50, middle = good.size() / 2, last = good.size() - 300;
  for (size_t at : {first, middle, last}) {
    std::string bad = good;
    bad[at] = static_cast<char>(bad[at] ^ 0x04);
    const Read r = ReadAll(WriteFile("flipped.bz2", bad), 2);
    ASSERT_NE(r.error.find("corrupt bzip2 data in the block at bytes "), std::string::npos)
        << r.error;
    const auto [from, to] = NamedBlock(r.error);
    EXPECT_LE(from, static_cast<long>(at)) << r.error;
    EXPECT_GT(to, static_cast<long>(at)) << r.error;
    // The blocks before were handed out whole, nothing after.
    EXPECT_EQ(r.text, text.substr(0, r.text.size()));
    if (at == first) {
      EXPECT_EQ(r.text.size(), 0u);
    }
    if (at == last) {
      EXPECT_GE(r.text.size() + 2 * kBlockText, text.size());
    }
  }
}

TEST(TextPiecesTest, AFlippedStreamCrcIsRefusedWithItsByte) {
  const std::string text = Lines(20000, 7);
  std::string bad = Bz2Compress(text, 1);
  bad[bad.size() - 3] = static_cast<char>(bad[bad.size() - 3] ^ 0x01);  // in the CRC
  const Read r = ReadAll(WriteFile("stream_crc.bz2", bad), 2);
  EXPECT_EQ(r.text, text);  // every block was good
  // The end-of-stream magic starts 10 bytes before the end, or 9 when the
  // padding fits in the CRC's last byte.
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      r.error, m, std::regex("corrupt bzip2 data: the stream's combined CRC at byte ([0-9]+) does "
                             "not match its blocks'")))
      << r.error;
  EXPECT_GE(std::stol(m[1]), static_cast<long>(bad.size()) - 11);
  EXPECT_LE(std::stol(m[1]), static_cast<long>(bad.size()) - 10);
}

TEST(TextPiecesTest, AFileCutShortIsRefusedWithTheBlockItEndsIn) {
  const std::string text = Lines(40000, 8);
  const std::string good = Bz2Compress(text, 1);
  const Read r = ReadAll(WriteFile("cut.bz2", good.substr(0, good.size() / 2)), 2);
  std::smatch m;
  ASSERT_TRUE(std::regex_search(
      r.error, m, std::regex("truncated bzip2 data: the file ends inside the block at byte ([0-9]+)")))
      << r.error;
  EXPECT_LT(std::stol(m[1]), static_cast<long>(good.size() / 2));
  EXPECT_EQ(r.text, text.substr(0, r.text.size()));
  EXPECT_GT(r.text.size(), text.size() / 4);
}

TEST(TextPiecesTest, TrailingDataIsRefusedWithItsByte) {
  const std::string packed = Bz2Compress("1 2\n3 4\n", 9);
  const Read r = ReadAll(WriteFile("trailing.bz2", packed + "garbage"), 2);
  EXPECT_EQ(r.text, "1 2\n3 4\n");
  EXPECT_EQ(r.error, "trailing data after the bzip2 stream is not bzip2 at byte " +
                         std::to_string(packed.size()));
}

}  // namespace
}  // namespace dba
