// Block-based sparse matrix compression (BSMC), paper section 4, docs/design.md §2.
//
// A symmetric block matrix S stored as its upper triangle (diagonal blocks
// included), one block as the storage unit:
//
//   block_size[i]    unknowns of block row/column i (may differ per block)
//   row_begin[i]     first stored block of block row i (size n + 1)
//   block_col[b]     block column of stored block b, sorted within a row
//   value_offset[b]  start of block b in `values` (size nnzb + 1, 64-bit)
//   values           all blocks back to back, each row-major c_i x c_j
//
// The structure is built once (symbolic phase, BuildFromPattern); each LM
// iteration only refills `values` (numeric phase). Block (i, j), i <= j, is
// found by binary search inside block row i: log2(s_i) comparisons for a row
// with s_i blocks (paper Table 1).
//
// Thread safety: const methods are safe to call concurrently; writing distinct
// blocks from different threads is safe, writing the same block is not.
#pragma once

#include <algorithm>
#include <cstdint>
#include <span>
#include <vector>

namespace dba {

// A block position (row, col) with row <= col packed in 64 bits, so a sorted
// vector of them is sorted by row, then column.
inline uint64_t PackBlock(int32_t row, int32_t col) {
  return (static_cast<uint64_t>(static_cast<uint32_t>(row)) << 32) |
         static_cast<uint32_t>(col);
}
inline int32_t PackedRow(uint64_t p) { return static_cast<int32_t>(p >> 32); }
inline int32_t PackedCol(uint64_t p) {
  return static_cast<int32_t>(p & 0xffffffffu);
}

class BsmcMatrix {
 public:
  BsmcMatrix() = default;
  // A copy holds its values in storage of its own (lent ones copied); a
  // move takes the place lent with it.
  BsmcMatrix(const BsmcMatrix& other);
  BsmcMatrix& operator=(const BsmcMatrix& other);
  BsmcMatrix(BsmcMatrix&& other) noexcept;
  BsmcMatrix& operator=(BsmcMatrix&& other) noexcept;

  // Symbolic phase. `block_sizes[i]` is the size of block row i;
  // `sorted_blocks` holds every stored block (row <= col) packed with
  // PackBlock, sorted and without duplicates. Every diagonal block must be
  // present. Values are zero.
  static BsmcMatrix BuildFromPattern(std::vector<int32_t> block_sizes,
                                     std::span<const uint64_t> sorted_blocks);
  // The same structure without the values (none allocated: num_values()
  // and ValueBytes() say what they will take), for sizing before the
  // allocation; AllocateValues() then makes it BuildFromPattern's matrix.
  static BsmcMatrix BuildStructure(std::vector<int32_t> block_sizes,
                                   std::span<const uint64_t> sorted_blocks);
  void AllocateValues();
  // Frees the values (the structure stays); AllocateValues brings them back,
  // zero.
  void ReleaseValues() {
    std::vector<double>().swap(values_);
    placed_ = nullptr;
    values_narrowed_ = false;
    values_zero_ = false;
  }
  // The values at a place the caller lends (num_values() doubles, whose
  // contents are lost) instead of storage of their own, which is freed;
  // nullptr: storage of their own again (allocated, zero, if the values were
  // placed; else as they are). Writers start with
  // SetZero as always; the lender's pages are never given back from here
  // (ZeroValuesAndReturnPages leaves them to the next SetZero).
  void PlaceValues(double* place);
  bool values_placed() const { return placed_ != nullptr; }
  bool has_values() const {
    return placed_ != nullptr || static_cast<int64_t>(values_.size()) == num_values();
  }

  int32_t num_block_rows() const {
    return static_cast<int32_t>(block_size_.size());
  }
  int64_t num_blocks() const { return static_cast<int64_t>(block_col_.size()); }
  // Scalar size of the matrix (sum of block sizes).
  int64_t num_rows() const { return scalar_offset_.back(); }
  int64_t num_values() const { return value_offset_.back(); }

  int32_t block_size(int32_t i) const { return block_size_[i]; }
  // Offset of block row i in a scalar vector.
  int64_t scalar_offset(int32_t i) const { return scalar_offset_[i]; }
  int64_t row_begin(int32_t i) const { return row_begin_[i]; }
  int64_t row_end(int32_t i) const { return row_begin_[i + 1]; }
  int32_t block_col(int64_t b) const { return block_col_[b]; }
  int64_t value_offset(int64_t b) const { return value_offset_[b]; }

  // Paper's second operation: position (row, col) -> stored block id, or -1
  // if the block is not stored. Requires row <= col.
  int64_t FindBlock(int32_t row, int32_t col) const;
  // FindBlock searching forward from `from`, a stored block of `row` whose
  // column is at most `col`: a galloping search (1, 2, 4, ... blocks ahead,
  // then a binary search inside the last step), log2 of the distance instead
  // of the row's length. For the columns of one row visited in increasing
  // order (a point's cameras sorted), each search starting at the last.
  int64_t SeekBlock(int64_t from, int32_t row, int32_t col) const {
    const int32_t* c = block_col_.data();
    const int64_t end = row_begin_[row + 1];
    if (c[from] >= col) return c[from] == col ? from : -1;
    int64_t low = from, step = 1;  // c[low] < col
    while (low + step < end && c[low + step] < col) {
      low += step;
      step *= 2;
    }
    int64_t high = std::min(low + step, end);  // c[high] >= col, or the end
    while (high - low > 1) {
      const int64_t mid = low + (high - low) / 2;
      (c[mid] < col ? low : high) = mid;
    }
    return high < end && c[high] == col ? high : -1;
  }
  // Paper's first operation: stored block id -> block row (binary search over
  // row_begin); the block column is block_col(b).
  int32_t BlockRow(int64_t b) const;

  double* block_values(int64_t b) { return values().data() + value_offset_[b]; }
  const double* block_values(int64_t b) const { return values().data() + value_offset_[b]; }
  // The diagonal block of row i is the first block of the row.
  int64_t diagonal_block(int32_t i) const { return row_begin_[i]; }

  // All blocks back to back (empty while the structure has no values).
  std::span<double> values() {
    return placed_ != nullptr ? std::span<double>(placed_, num_values()) : std::span<double>(values_);
  }
  std::span<const double> values() const {
    return placed_ != nullptr ? std::span<const double>(placed_, num_values())
                              : std::span<const double>(values_);
  }
  // Before the values are summed (a formation): nothing to write when they
  // were given back since (ZeroValuesAndReturnPages).
  void SetZero();
  // The values are not needed until the next SetZero (a rank's own rows
  // between a distributed solve and the next reduce-scatter): their pages go
  // back to the system, and they read zero, taking memory again only as they
  // are written (lent values: left as they are, see PlaceValues). Writers of
  // the values start with SetZero.
  void ZeroValuesAndReturnPages();
  // A mixed-precision product (bsmc/symmetric_multiply.h) narrowed the
  // values in place: they are not S's doubles until SetZero.
  bool values_narrowed() const { return values_narrowed_; }
  void MarkValuesNarrowed() {
    values_narrowed_ = true;
    values_zero_ = false;
  }

  // Bytes of the structure (block sizes, offsets, column ids) and of the
  // values, as held (docs/design.md §2, paper eq. 9).
  int64_t StructureBytes() const;
  int64_t ValueBytes() const { return num_values() * int64_t{sizeof(double)}; }
  // Bytes of the same matrix in scalar CSR (paper eq. 8): both triangles,
  // 8-byte values, 4-byte column indices, 8-byte row pointers (64-bit, since
  // the number of non-zeros can pass 2^31). With `upper_only`, the CSR of the
  // upper triangle only.
  int64_t CsrBytes(bool upper_only = false) const;

 private:
  std::vector<int32_t> block_size_;
  std::vector<int64_t> scalar_offset_{0};
  std::vector<int64_t> row_begin_{0};
  std::vector<int32_t> block_col_;
  std::vector<int64_t> value_offset_{0};
  std::vector<double> values_;  // storage of their own
  double* placed_ = nullptr;     // or lent (PlaceValues)
  bool values_narrowed_ = false;
  bool values_zero_ = false;  // given back since the last SetZero
};

}  // namespace dba
