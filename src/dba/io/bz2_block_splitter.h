// A bzip2 file cut into its blocks, in file order, for decoding apart
// (docs/design.md §4.3): the stream headers read, every block's bits copied
// out as a one-block stream (io/bz2_blocks), every stream's end and stored
// combined CRC reported, concatenated streams (pbzip2's output, `cat a.bz2
// b.bz2`) followed one after another. A block ends where the next block or
// end-of-stream magic starts; an end-of-stream magic counts as one when EOF
// or another stream follows it (else it was data, and the block goes on).
// The blocks are not decoded here: a magic that occurs by chance inside a
// block cuts it in two, and the decoder joins them again.
//
// Memory: the bytes of the block being cut plus one read (4 MiB). A block
// longer than any bzip2 writes is refused.
//
// Thread safety: one owner.
#pragma once

#include <cstdint>
#include <cstdio>
#include <deque>
#include <string>
#include <vector>

#include "dba/io/bz2_blocks.h"

namespace dba {

struct Bz2Unit {
  enum Kind { kBlock, kStreamEnd, kEnd, kError };
  Kind kind = kEnd;
  Bz2Block block;           // kBlock
  int64_t stream = 0;       // the stream it belongs to, counted from 0
  uint32_t stream_crc = 0;  // kStreamEnd: the combined CRC the stream stores
  int64_t file_byte = 0;    // kStreamEnd, kError: where in the file
  std::string error;        // kError: what is wrong (it names the byte)
};

class Bz2BlockSplitter {
 public:
  // Reads `file` from where `first` (bytes already read from it, from its
  // start) ends.
  Bz2BlockSplitter(FILE* file, std::vector<uint8_t> first);

  // The next unit; after kEnd or kError, kEnd again.
  Bz2Unit Next();

  // The most bits a block of `level` may take: 23 (the longest Huffman code)
  // per byte of the block, and its tables.
  static int64_t MaxBlockBits(char level) { return (int64_t{level - '0'} * 100000 * 23 + 65536 * 8); }

 private:
  enum State { kHeader, kInBlock, kDone };
  void Step();
  void ReadHeader();
  void FindBlockEnd();
  bool EndsStream(int64_t bit);
  void EmitBlock(int64_t begin_bit, int64_t end_bit);
  void EndStream(int64_t bit);
  void AtEndOfData();
  void Fail(const std::string& what, int64_t byte);
  bool Have(int64_t end_byte);  // the file's bytes before end_byte are in buf_
  void Compact();
  uint64_t Bits(int64_t bit, int count) const;

  FILE* file_;
  std::vector<uint8_t> buf_;  // the file's bytes from base_
  int64_t base_ = 0;
  bool eof_ = false;
  std::deque<Bz2Unit> ready_;

  State state_ = kHeader;
  int64_t stream_ = -1;
  char level_ = '9';
  int64_t header_byte_ = 0;  // kHeader: where the next stream starts
  int64_t block_bit_ = 0;    // kInBlock: where the block starts
  int64_t scan_bit_ = 0;     // kInBlock: where the search for its end goes on
  int64_t data_end_ = -1;    // an end-of-stream magic followed by what is not a stream
};

}  // namespace dba
