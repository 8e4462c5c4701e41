// Tests of io/bal_parallel_reader: a multi-block .bz2 and its plain text
// give the same problem, bit for bit, on 1-4 threads and equal to the line
// by line reader's (grouped or not, tokens cut between pieces); a bad token
// deep in a multi-block file is refused by ReadBal naming its exact line;
// damage anywhere (a block, the stream's CRC, a cut) names file and byte.
#include "dba/io/bal_parallel_reader.h"

#include <bzlib.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cstring>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "dba/common/error.h"
#include "dba/io/bal_reader.h"
#include "dba/testing/bz2_test_data.h"
#include "dba/testing/temp_files.h"

namespace dba {
namespace {

using testing::Bz2Compress;

std::string WriteFile(const std::string& name, const std::string& bytes) {
  const std::string path = testing::TempPath("bal_parallel_reader_test_" + name);
  EXPECT_TRUE(testing::WriteFileBytes(path, bytes));
  return path;
}

// The text of a shared BAL file (as bzcat gives it).
std::string SharedText(const std::string& name) {
  const std::string packed = testing::ReadFileBytes(DBA_SHARED_DATA_DIR "/bal/" + name);
  std::vector<char> out(size_t{16} << 20);
  unsigned len = static_cast<unsigned>(out.size());
  EXPECT_EQ(BZ2_bzBuffToBuffDecompress(out.data(), &len, const_cast<char*>(packed.data()),
                                       static_cast<unsigned>(packed.size()), 0, 0),
            BZ_OK);
  return std::string(out.data(), len);
}

template <typename T>
bool SameBits(const std::vector<T>& a, const std::vector<T>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(T)) == 0;
}

void ExpectSameBits(const Problem& a, const Problem& b) {
  EXPECT_TRUE(SameBits(a.cameras, b.cameras));
  EXPECT_TRUE(SameBits(a.points, b.points));
  EXPECT_TRUE(SameBits(a.point_offsets, b.point_offsets));
  EXPECT_TRUE(SameBits(a.obs_camera, b.obs_camera));
  EXPECT_TRUE(SameBits(a.obs_pixel, b.obs_pixel));
}

Problem Parallel(const std::string& path, int threads) {
  std::optional<Problem> p = ReadBalInParallel(path, threads);
  EXPECT_TRUE(p.has_value()) << path << " on " << threads << " threads";
  return p.has_value() ? std::move(*p) : Problem();
}

TEST(BalParallelReaderTest, MultiBlockBz2AndItsTextSameBitsOnAnyThreads) {
  const std::string text = SharedText("problem-16-22106-pre.txt.bz2");  // 4.8 MB
  const std::string plain = WriteFile("p16.txt", text);
  const std::string packed = WriteFile("p16.bz2", Bz2Compress(text, 1));  // 48 blocks
  const Problem reference = ReadBalLineByLine(plain);
  ASSERT_EQ(reference.num_observations(), 83718);
  for (int threads : {1, 2, 4}) {
    SCOPED_TRACE(threads);
    ExpectSameBits(Parallel(plain, threads), reference);
    ExpectSameBits(Parallel(packed, threads), reference);
  }
  ExpectSameBits(ReadBal(packed), reference);
}

TEST(BalParallelReaderTest, UngroupedObservationsSameAsLineByLine) {
  std::istringstream in(SharedText("problem-49-7776-pre.txt.bz2"));
  std::string header, line;
  std::getline(in, header);
  std::vector<std::string> obs(31843);
  for (std::string& o : obs) std::getline(in, o);
  std::shuffle(obs.begin(), obs.end(), std::mt19937(11));
  std::string text = header + "\n";
  for (const std::string& o : obs) text += o + "\n";
  while (std::getline(in, line)) text += line + "\n";
  const std::string path = WriteFile("shuffled.bz2", Bz2Compress(text, 1));
  const Problem reference = ReadBalLineByLine(path);
  for (int threads : {1, 3}) ExpectSameBits(Parallel(path, threads), reference);
}

TEST(BalParallelReaderTest, OneLineOfTokensCutBetweenPieces) {
  std::string text = SharedText("problem-49-7776-pre.txt.bz2");  // 1.8 MB
  std::replace(text.begin(), text.end(), '\n', ' ');
  text.back() = '\n';
  const std::string plain = WriteFile("one_line.txt", text);  // two 1 MiB pieces
  const std::string packed = WriteFile("one_line.bz2", Bz2Compress(text, 1));
  const Problem reference = ReadBalLineByLine(plain);
  ExpectSameBits(Parallel(plain, 2), reference);
  ExpectSameBits(Parallel(packed, 2), reference);
}

// The text with the token `index` (0-based) of line `line` (1-based) replaced.
std::string WithToken(const std::string& text, int64_t line, int index, const std::string& token) {
  size_t at = 0;
  for (int64_t l = 1; l < line; ++l) at = text.find('\n', at) + 1;
  const size_t end = text.find('\n', at);
  std::istringstream fields(text.substr(at, end - at));
  std::vector<std::string> f;
  for (std::string s; fields >> s;) f.push_back(s);
  f.at(index) = token;
  std::string replaced;
  for (const std::string& s : f) replaced += (replaced.empty() ? "" : " ") + s;
  return text.substr(0, at) + replaced + text.substr(end);
}

TEST(BalParallelReaderTest, ABadTokenDeepInAMultiBlockFileNamesItsLine) {
  const std::string text = SharedText("problem-49-7776-pre.txt.bz2");  // 18 blocks at level 1
  struct Case {
    int64_t line;
    int index;
    std::string token, phrase;
  };
  // An observation (header on line 1), a camera parameter, a point's last
  // coordinate: 1 + 31843 + 9 * 49 + 3 * 7776 lines.
  const Case cases[] = {
      {30001, 2, "x1.5", "expected observation 29999 of 31843 ('camera point x y'), found 'x1.5' "
                         "(not a number)"},
      {31844 + 100, 0, "1e999", "expected 9 camera parameters for camera 11, found '1e999' (out "
                                "of the double range)"},
      {31844 + 441 + 23328, 0, "nan", "expected 3 coordinates for point 7775, found non-finite "
                                      "value 'nan'"},
  };
  for (const Case& c : cases) {
    const std::string path = WriteFile("bad_token.bz2", Bz2Compress(WithToken(text, c.line, c.index, c.token), 1));
    EXPECT_FALSE(ReadBalInParallel(path, 2).has_value());
    try {
      ReadBal(path, 2);
      ADD_FAILURE() << "no error for line " << c.line;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      EXPECT_EQ(e.line(), c.line) << e.what();
      EXPECT_NE(std::string(e.what()).find(c.phrase), std::string::npos) << e.what();
    }
  }
}

TEST(BalParallelReaderTest, DamagedBz2IsRefusedNamingFileAndByte) {
  const std::string text = SharedText("problem-49-7776-pre.txt.bz2");
  const std::string good = Bz2Compress(text, 1);  // 18 blocks
  auto flipped = [&](size_t at) {
    std::string bad = good;
    bad[at] = static_cast<char>(bad[at] ^ 0x20);
    return bad;
  };
  struct Case {
    std::string bytes, phrase;
    int64_t min_line;  // the lines of the blocks before were read
  };
  const Case cases[] = {
      {flipped(60), "corrupt bzip2 data in the block at bytes 4-", 1},
      {flipped(good.size() / 2), "corrupt bzip2 data in the block at bytes ", 20000},
      {flipped(good.size() - 200), "corrupt bzip2 data in the block at bytes ", 50000},
      {flipped(good.size() - 2), "corrupt bzip2 data: the stream's combined CRC at byte ", 55614},
      {good.substr(0, good.size() * 2 / 3), "truncated bzip2 data: the file ends inside the block at byte ",
       30000},
  };
  for (const Case& c : cases) {
    const std::string path = WriteFile("damaged.bz2", c.bytes);
    EXPECT_FALSE(ReadBalInParallel(path, 2).has_value());
    try {
      ReadBal(path, 2);
      ADD_FAILURE() << "no error: " << c.phrase;
    } catch (const InputError& e) {
      EXPECT_EQ(e.file(), path);
      EXPECT_GE(e.line(), c.min_line) << e.what();
      EXPECT_NE(std::string(e.what()).find(c.phrase), std::string::npos) << e.what();
    }
  }
}

}  // namespace
}  // namespace dba
