// BSMC storage, block lookup and byte accounting; see bsmc_matrix.h.
#include "dba/bsmc/bsmc_matrix.h"

#include <algorithm>
#include <stdexcept>
#include <string>
#include <utility>

#include "dba/common/memory.h"

namespace dba {

BsmcMatrix BsmcMatrix::BuildFromPattern(std::vector<int32_t> block_sizes,
                                        std::span<const uint64_t> sorted_blocks) {
  BsmcMatrix m = BuildStructure(std::move(block_sizes), sorted_blocks);
  m.AllocateValues();
  return m;
}

BsmcMatrix::BsmcMatrix(const BsmcMatrix& other)
    : block_size_(other.block_size_),
      scalar_offset_(other.scalar_offset_),
      row_begin_(other.row_begin_),
      block_col_(other.block_col_),
      value_offset_(other.value_offset_),
      values_(other.values().begin(), other.values().end()),
      values_narrowed_(other.values_narrowed_),
      values_zero_(other.values_zero_) {}

BsmcMatrix& BsmcMatrix::operator=(const BsmcMatrix& other) {
  if (this != &other) *this = BsmcMatrix(other);
  return *this;
}

BsmcMatrix::BsmcMatrix(BsmcMatrix&& other) noexcept
    : block_size_(std::move(other.block_size_)),
      scalar_offset_(std::move(other.scalar_offset_)),
      row_begin_(std::move(other.row_begin_)),
      block_col_(std::move(other.block_col_)),
      value_offset_(std::move(other.value_offset_)),
      values_(std::move(other.values_)),
      placed_(std::exchange(other.placed_, nullptr)),
      values_narrowed_(other.values_narrowed_),
      values_zero_(other.values_zero_) {}

BsmcMatrix& BsmcMatrix::operator=(BsmcMatrix&& other) noexcept {
  if (this != &other) {
    block_size_ = std::move(other.block_size_);
    scalar_offset_ = std::move(other.scalar_offset_);
    row_begin_ = std::move(other.row_begin_);
    block_col_ = std::move(other.block_col_);
    value_offset_ = std::move(other.value_offset_);
    values_ = std::move(other.values_);
    placed_ = std::exchange(other.placed_, nullptr);
    values_narrowed_ = other.values_narrowed_;
    values_zero_ = other.values_zero_;
  }
  return *this;
}

void BsmcMatrix::AllocateValues() {
  placed_ = nullptr;
  AssignZeros(&values_, static_cast<size_t>(value_offset_.back()));
  values_zero_ = false;
}

void BsmcMatrix::PlaceValues(double* place) {
  if (place == nullptr) {
    if (placed_ != nullptr) AllocateValues();
    return;
  }
  std::vector<double>().swap(values_);
  placed_ = place;
  values_narrowed_ = false;
  values_zero_ = false;
}

BsmcMatrix BsmcMatrix::BuildStructure(std::vector<int32_t> block_sizes,
                                      std::span<const uint64_t> sorted_blocks) {
  BsmcMatrix m;
  const int64_t n = static_cast<int64_t>(block_sizes.size());
  m.block_size_ = std::move(block_sizes);
  m.scalar_offset_.resize(n + 1);
  m.scalar_offset_[0] = 0;
  for (int64_t i = 0; i < n; ++i) {
    m.scalar_offset_[i + 1] = m.scalar_offset_[i] + m.block_size_[i];
  }
  const int64_t nnzb = static_cast<int64_t>(sorted_blocks.size());
  m.row_begin_.assign(n + 1, 0);
  m.block_col_.resize(nnzb);
  m.value_offset_.resize(nnzb + 1);
  m.value_offset_[0] = 0;
  for (int64_t b = 0; b < nnzb; ++b) {
    const int32_t r = PackedRow(sorted_blocks[b]);
    const int32_t c = PackedCol(sorted_blocks[b]);
    if (r < 0 || r > c || c >= n ||
        (b > 0 && sorted_blocks[b] <= sorted_blocks[b - 1])) {
      throw std::invalid_argument(
          "BsmcMatrix: block pattern not sorted, not unique or not upper "
          "triangular at block " + std::to_string(b));
    }
    ++m.row_begin_[r + 1];
    m.block_col_[b] = c;
    m.value_offset_[b + 1] = m.value_offset_[b] +
                             int64_t{m.block_size_[r]} * m.block_size_[c];
  }
  for (int64_t i = 0; i < n; ++i) {
    m.row_begin_[i + 1] += m.row_begin_[i];
    if (m.row_begin_[i + 1] == m.row_begin_[i] ||
        m.block_col_[m.row_begin_[i]] != i) {
      throw std::invalid_argument("BsmcMatrix: diagonal block " +
                                  std::to_string(i) + " missing");
    }
  }
  return m;
}

int64_t BsmcMatrix::FindBlock(int32_t row, int32_t col) const {
  const auto first = block_col_.begin() + row_begin_[row];
  const auto last = block_col_.begin() + row_begin_[row + 1];
  const auto it = std::lower_bound(first, last, col);
  if (it == last || *it != col) return -1;
  return it - block_col_.begin();
}

int32_t BsmcMatrix::BlockRow(int64_t b) const {
  const auto it = std::upper_bound(row_begin_.begin(), row_begin_.end(), b);
  return static_cast<int32_t>(it - row_begin_.begin() - 1);
}

void BsmcMatrix::SetZero() {
  if (!values_zero_) std::ranges::fill(values(), 0.0);
  values_narrowed_ = false;
  values_zero_ = false;
}

void BsmcMatrix::ZeroValuesAndReturnPages() {
  values_narrowed_ = false;
  // Lent values are the lender's meanwhile: kept, and zeroed by the next
  // SetZero.
  values_zero_ = placed_ == nullptr;
  if (values_zero_) ZeroAndReturnPages(values_.data(), static_cast<int64_t>(values_.size()));
}

int64_t BsmcMatrix::StructureBytes() const {
  return static_cast<int64_t>(block_size_.size() * sizeof(int32_t) +
                              scalar_offset_.size() * sizeof(int64_t) +
                              row_begin_.size() * sizeof(int64_t) +
                              block_col_.size() * sizeof(int32_t) +
                              value_offset_.size() * sizeof(int64_t));
}

int64_t BsmcMatrix::CsrBytes(bool upper_only) const {
  // Scalar non-zeros: off-diagonal blocks twice unless upper_only; diagonal
  // blocks count fully (or their upper triangle c(c+1)/2).
  int64_t nnz = 0;
  for (int32_t i = 0; i < num_block_rows(); ++i) {
    for (int64_t b = row_begin_[i]; b < row_begin_[i + 1]; ++b) {
      const int64_t ci = block_size_[i], cj = block_size_[block_col_[b]];
      if (block_col_[b] == i) {
        nnz += upper_only ? ci * (ci + 1) / 2 : ci * ci;
      } else {
        nnz += upper_only ? ci * cj : 2 * ci * cj;
      }
    }
  }
  return nnz * int64_t{sizeof(double) + sizeof(int32_t)} +
         (num_rows() + 1) * int64_t{sizeof(int64_t)};
}

}  // namespace dba
