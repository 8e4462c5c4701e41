// Race-free multithreaded symmetric BSMC product; see symmetric_multiply.h.
#include "dba/bsmc/symmetric_multiply.h"

#include <omp.h>

#ifdef __AVX2__
#include <immintrin.h>
#endif

#include <Eigen/Core>
#include <algorithm>
#include <cstring>
#include <stdexcept>

#include "dba/bsmc/block_shape.h"

namespace dba {
namespace {

// y_i += B x_j and, unless diagonal, y_j += Bᵀ x_i for one r x c block
// stored as T (double, or float for a narrowed off-diagonal block; the sums
// are in double either way).
template <int R, int C, class T>
inline void ApplyBlock(const T* block, int r, int c, const double* x_j,
                       const double* x_i, double* y_i, double* y_j) {
  using MatR = Eigen::Matrix<T, R, C, Eigen::RowMajor>;
  Eigen::Map<const MatR> stored(block, r, c);
  const auto B = stored.template cast<double>();
  // lazyProduct keeps fixed-size blocks in registers instead of going
  // through Eigen's general matrix-vector kernel.
  Eigen::Map<Eigen::Matrix<double, R, 1>>(y_i, r).noalias() +=
      B.lazyProduct(Eigen::Map<const Eigen::Matrix<double, C, 1>>(x_j, c));
  if (y_j != nullptr) {
    Eigen::Map<Eigen::Matrix<double, C, 1>>(y_j, c).noalias() +=
        B.transpose().lazyProduct(Eigen::Map<const Eigen::Matrix<double, R, 1>>(x_i, r));
  }
}

#ifdef __AVX2__
// Four (two) stored values as doubles.
inline __m256d Load4(const double* p) { return _mm256_loadu_pd(p); }
inline __m256d Load4(const float* p) { return _mm256_cvtps_pd(_mm_loadu_ps(p)); }
inline __m128d Load2(const double* p) { return _mm_loadu_pd(p); }
inline __m128d Load2(const float* p) {
  return _mm_cvtps_pd(_mm_castsi128_ps(_mm_loadl_epi64(reinterpret_cast<const __m128i*>(p))));
}

// Four dot products at once: lane k of the result is the sum of d_k's lanes.
inline __m256d SumEachOfFour(__m256d d0, __m256d d1, __m256d d2, __m256d d3) {
  const __m256d t0 = _mm256_hadd_pd(d0, d1);  // d0 01, d1 01, d0 23, d1 23
  const __m256d t1 = _mm256_hadd_pd(d2, d3);
  return _mm256_add_pd(_mm256_permute2f128_pd(t0, t1, 0x20),
                       _mm256_permute2f128_pd(t0, t1, 0x31));
}

// A 9 x 9 block (BAL cameras) both ways in one pass over its rows, with
// AVX2 and FMA: row x is two 4-wide vectors and one scalar; it adds its
// multiple x_i[x] into y_j's running sums and gives the dot product y_i[x]
// (reduced four rows at a time). 162 FMAs per 648 bytes, so the product
// streams S at the memory's speed instead of waiting on Eigen's per-row
// reductions (bench/README.md, "The PCG product").
template <class T>
inline void ApplyBlock9x9(const T* __restrict B, const double* __restrict x_j,
                          const double* __restrict x_i, double* __restrict y_i,
                          double* __restrict y_j) {
  const __m256d xj0 = _mm256_loadu_pd(x_j), xj1 = _mm256_loadu_pd(x_j + 4);
  const double xj8 = x_j[8];
  __m256d acc0 = _mm256_setzero_pd(), acc1 = _mm256_setzero_pd();
  double acc8 = 0.0;
  __m256d dot[8];
  double tail[9];  // column 8's share of each row's dot product
  for (int x = 0; x < 9; ++x) {
    const T* row = B + 9 * x;
    const __m256d b0 = Load4(row), b1 = Load4(row + 4);
    const double b8 = row[8];
    const __m256d xi = _mm256_broadcast_sd(x_i + x);
    acc0 = _mm256_fmadd_pd(b0, xi, acc0);
    acc1 = _mm256_fmadd_pd(b1, xi, acc1);
    acc8 += b8 * x_i[x];
    const __m256d d = _mm256_fmadd_pd(b1, xj1, _mm256_mul_pd(b0, xj0));
    tail[x] = b8 * xj8;
    if (x < 8) {
      dot[x] = d;
    } else {  // the ninth row alone
      const __m128d h = _mm_add_pd(_mm256_castpd256_pd128(d), _mm256_extractf128_pd(d, 1));
      y_i[8] += _mm_cvtsd_f64(_mm_add_sd(h, _mm_unpackhi_pd(h, h))) + tail[8];
    }
  }
  const __m256d s0 = _mm256_add_pd(SumEachOfFour(dot[0], dot[1], dot[2], dot[3]),
                                   _mm256_loadu_pd(tail));
  const __m256d s1 = _mm256_add_pd(SumEachOfFour(dot[4], dot[5], dot[6], dot[7]),
                                   _mm256_loadu_pd(tail + 4));
  _mm256_storeu_pd(y_i, _mm256_add_pd(_mm256_loadu_pd(y_i), s0));
  _mm256_storeu_pd(y_i + 4, _mm256_add_pd(_mm256_loadu_pd(y_i + 4), s1));
  _mm256_storeu_pd(y_j, _mm256_add_pd(_mm256_loadu_pd(y_j), acc0));
  _mm256_storeu_pd(y_j + 4, _mm256_add_pd(_mm256_loadu_pd(y_j + 4), acc1));
  y_j[8] += acc8;
}

// The 6 x 6 pose block of the photogrammetric model the same way: row x is
// a 4-wide and a 2-wide vector.
template <class T>
inline void ApplyBlock6x6(const T* __restrict B, const double* __restrict x_j,
                          const double* __restrict x_i, double* __restrict y_i,
                          double* __restrict y_j) {
  const __m256d xj0 = _mm256_loadu_pd(x_j);
  const __m128d xj4 = _mm_loadu_pd(x_j + 4);
  __m256d acc0 = _mm256_setzero_pd();
  __m128d acc4 = _mm_setzero_pd();
  __m256d dot[4];
  double row_dot[6];
  for (int x = 0; x < 6; ++x) {
    const T* row = B + 6 * x;
    const __m256d b0 = Load4(row);
    const __m128d b4 = Load2(row + 4);
    acc0 = _mm256_fmadd_pd(b0, _mm256_broadcast_sd(x_i + x), acc0);
    acc4 = _mm_fmadd_pd(b4, _mm_set1_pd(x_i[x]), acc4);
    const __m128d t = _mm_mul_pd(b4, xj4);
    const double tail = _mm_cvtsd_f64(_mm_add_sd(t, _mm_unpackhi_pd(t, t)));
    const __m256d d = _mm256_mul_pd(b0, xj0);
    if (x < 4) {
      dot[x] = d;
      row_dot[x] = tail;
    } else {
      const __m128d h = _mm_add_pd(_mm256_castpd256_pd128(d), _mm256_extractf128_pd(d, 1));
      row_dot[x] = _mm_cvtsd_f64(_mm_add_sd(h, _mm_unpackhi_pd(h, h))) + tail;
    }
  }
  const __m256d s0 = _mm256_add_pd(SumEachOfFour(dot[0], dot[1], dot[2], dot[3]),
                                   _mm256_loadu_pd(row_dot));
  _mm256_storeu_pd(y_i, _mm256_add_pd(_mm256_loadu_pd(y_i), s0));
  y_i[4] += row_dot[4];
  y_i[5] += row_dot[5];
  _mm256_storeu_pd(y_j, _mm256_add_pd(_mm256_loadu_pd(y_j), acc0));
  _mm_storeu_pd(y_j + 4, _mm_add_pd(_mm_loadu_pd(y_j + 4), acc4));
}
#endif

// y_i += S_ij x_j, y_j += S_ijᵀ x_i for one stored off-diagonal block.
template <class T>
inline void ApplyOffDiagonal(const T* block, int r, int c, const double* x_j, const double* x_i,
                             double* y_i, double* y_j) {
  WithBlockShape(r, c, [&]<int R, int C>() {
#ifdef __AVX2__
    if constexpr (R == 9 && C == 9) {
      ApplyBlock9x9(block, x_j, x_i, y_i, y_j);
      return;
    } else if constexpr (R == 6 && C == 6) {
      ApplyBlock6x6(block, x_j, x_i, y_i, y_j);
      return;
    }
#endif
    ApplyBlock<R, C>(block, r, c, x_j, x_i, y_i, y_j);
  });
}

// Where the product reads S's blocks: S's own double values, or the
// narrowed ones (diagonal blocks in double beside, off-diagonal blocks as
// float over the front of S's buffer, block b of row i at value_offset(b)
// less the diagonal values of rows 0..i).
struct DoubleValues {
  const BsmcMatrix& m;
  const double* values = m.values().data();
  const double* diagonal(int32_t i) const { return values + m.value_offset(m.row_begin(i)); }
  const double* off_diagonal(int32_t, int64_t b) const { return values + m.value_offset(b); }
};
struct NarrowedValues {
  const BsmcMatrix& m;
  const double* diagonals;
  const int64_t* diagonal_offset;  // n + 1 entries
  const float* narrowed;
  const double* diagonal(int32_t i) const { return diagonals + diagonal_offset[i]; }
  const float* off_diagonal(int32_t i, int64_t b) const {
    return narrowed + (m.value_offset(b) - diagonal_offset[i + 1]);
  }
};

// Products of block rows [row0, row1). Transposed products for rows >= row1
// go to spill (indexed from scalar row spill_begin).
template <class Values>
void MultiplyRows(const BsmcMatrix& m, const Values& values, int32_t row0, int32_t row1,
                  const double* x, double* y, double* spill, int64_t spill_begin) {
  const int64_t own_end = m.scalar_offset(row1);
  for (int64_t s = m.scalar_offset(row0); s < own_end; ++s) y[s] = 0.0;
  for (int32_t i = row0; i < row1; ++i) {
    const int r = m.block_size(i);
    const int64_t oi = m.scalar_offset(i);
    WithBlockShape(r, r, [&]<int R, int C>() {
      ApplyBlock<R, C>(values.diagonal(i), r, r, x + oi, x + oi, y + oi, nullptr);
    });
    for (int64_t b = m.row_begin(i) + 1; b < m.row_end(i); ++b) {
      const int32_t j = m.block_col(b);
      const int64_t oj = m.scalar_offset(j);
      double* y_j = oj < own_end ? y + oj : spill + (oj - spill_begin);
      ApplyOffDiagonal(values.off_diagonal(i, b), r, m.block_size(j), x + oj, x + oi, y + oi, y_j);
    }
  }
}

// n doubles at `from` as floats at `to`, where `to` starts at or before
// `from` in memory (in place, narrowing toward the front): a chunk is read
// whole before it is written, and a write reaches only bytes already read.
void NarrowForward(const double* from, float* to, int64_t n) {
  constexpr int64_t kChunk = 256;
  float chunk[kChunk];
  for (int64_t k = 0; k < n; k += kChunk) {
    const int64_t m = std::min(kChunk, n - k);
    for (int64_t t = 0; t < m; ++t) chunk[t] = static_cast<float>(from[k + t]);
    std::memcpy(to + k, chunk, m * sizeof(float));
  }
}

}  // namespace

SymmetricMultiplier::SymmetricMultiplier(const BsmcMatrix& matrix, int num_threads,
                                         ProductPrecision precision)
    : matrix_(matrix), precision_(precision) {
  const int32_t n = matrix.num_block_rows();
  // A thread per at least kMinValuesPerThread values: below that, forking
  // costs more than it saves.
  constexpr int64_t kMinValuesPerThread = int64_t{1} << 17;
  num_threads = static_cast<int>(std::clamp<int64_t>(
      matrix.num_values() / kMinValuesPerThread, 1,
      std::min<int64_t>(num_threads, std::max<int32_t>(n, 1))));
  // Split rows so each thread gets about the same number of values.
  row_split_.assign(num_threads + 1, n);
  row_split_[0] = 0;
  const double total = static_cast<double>(matrix.num_values());
  int t = 1;
  for (int32_t i = 0; i < n && t < num_threads; ++i) {
    const double done =
        static_cast<double>(i == n - 1 ? matrix.num_values()
                                       : matrix.value_offset(matrix.row_end(i)));
    if (done >= total * t / num_threads) row_split_[t++] = i + 1;
  }
  for (; t < num_threads; ++t) row_split_[t] = n;
  // Each thread's spill covers [end of own rows, end of the largest column).
  spill_begin_.resize(num_threads);
  spill_.resize(num_threads);
  for (int t2 = 0; t2 < num_threads; ++t2) {
    const int32_t r0 = row_split_[t2], r1 = row_split_[t2 + 1];
    int32_t max_col = r1 - 1;
    for (int32_t i = r0; i < r1; ++i) {
      max_col = std::max(max_col, matrix.block_col(matrix.row_end(i) - 1));
    }
    spill_begin_[t2] = matrix.scalar_offset(r1);
    const int64_t spill_end = max_col >= r1 ? matrix.scalar_offset(max_col + 1)
                                            : spill_begin_[t2];
    spill_[t2].assign(spill_end - spill_begin_[t2], 0.0);
  }
  if (precision_ == ProductPrecision::kMixed) PlanNarrowing();
}

// Row i's off-diagonal values go from value index s_i (as doubles, byte
// 8 s_i) to float index f_i = s_i - (diagonal values of rows 0..i), byte
// 4 f_i. The rows of a round [r0, r1) narrow in parallel when the round's
// last float write ends at or before the first byte any row of it (or a
// later round) reads: f_end(r1 - 1) <= 2 s_r0. Rounds about double in
// length, so there are about log2(rows) of them.
void SymmetricMultiplier::PlanNarrowing() {
  const BsmcMatrix& m = matrix_;
  const int32_t n = m.num_block_rows();
  diagonal_offset_.assign(n + 1, 0);
  for (int32_t i = 0; i < n; ++i) {
    diagonal_offset_[i + 1] = diagonal_offset_[i] + int64_t{m.block_size(i)} * m.block_size(i);
  }
  diagonal_.Resize(diagonal_offset_[n]);
  auto off_begin = [&](int32_t i) { return m.value_offset(m.row_begin(i)) + m.block_size(i) * int64_t{m.block_size(i)}; };
  auto narrowed_end = [&](int32_t i) { return m.value_offset(m.row_end(i)) - diagonal_offset_[i + 1]; };
  round_.assign(1, 0);
  for (int32_t r0 = 0; r0 < n;) {
    int32_t r1 = r0 + 1;
    while (r1 < n && narrowed_end(r1) <= 2 * off_begin(r0)) ++r1;
    round_.push_back(r1);
    r0 = r1;
  }
}

void SymmetricMultiplier::Narrow(BsmcMatrix* S) {
  if (S != &matrix_) throw std::logic_error("SymmetricMultiplier::Narrow: not the multiplier's matrix");
  if (precision_ != ProductPrecision::kMixed) throw std::logic_error("SymmetricMultiplier::Narrow: not a mixed-precision multiplier");
  if (S->values_narrowed()) throw std::logic_error("SymmetricMultiplier::Narrow: S is narrowed already (re-form it first)");
  const int32_t n = S->num_block_rows();
  double* values = S->values().data();
  float* narrowed = reinterpret_cast<float*>(values);
  const int threads = num_threads();
  double* diagonal = diagonal_.data();
#pragma omp parallel num_threads(threads) if (threads > 1)
  {
    // The diagonal blocks first: the floats of earlier rows overwrite them.
#pragma omp for schedule(static)
    for (int32_t i = 0; i < n; ++i) {
      std::memcpy(diagonal + diagonal_offset_[i], S->block_values(S->row_begin(i)),
                  (diagonal_offset_[i + 1] - diagonal_offset_[i]) * sizeof(double));
    }
    for (size_t k = 0; k + 1 < round_.size(); ++k) {
#pragma omp for schedule(static)
      for (int32_t i = round_[k]; i < round_[k + 1]; ++i) {
        const int64_t begin = S->value_offset(S->row_begin(i) + 1), end = S->value_offset(S->row_end(i));
        NarrowForward(values + begin, narrowed + (begin - diagonal_offset_[i + 1]), end - begin);
      }
    }
  }
  S->MarkValuesNarrowed();
}

void SymmetricMultiplier::UseDoublePrecision() {
  precision_ = ProductPrecision::kDouble;
  diagonal_ = PlacedDoubles();
  diagonal_offset_ = {};
  round_ = {};
}

void SymmetricMultiplier::ReturnDiagonalPages() { diagonal_.ReturnPages(); }

void SymmetricMultiplier::Multiply(const double* x, double* y) const {
  if (precision_ == ProductPrecision::kMixed) {
    if (!matrix_.values_narrowed()) {
      throw std::logic_error("SymmetricMultiplier: mixed-precision product before Narrow");
    }
    MultiplyWith(NarrowedValues{matrix_, diagonal_.data(), diagonal_offset_.data(),
                                reinterpret_cast<const float*>(matrix_.values().data())},
                 x, y);
  } else {
    if (matrix_.values_narrowed()) {
      throw std::logic_error("SymmetricMultiplier: a double product of narrowed values");
    }
    MultiplyWith(DoubleValues{matrix_}, x, y);
  }
}

template <class Values>
void SymmetricMultiplier::MultiplyWith(const Values& values, const double* x, double* y) const {
  const int num_threads = this->num_threads();
  if (num_threads == 1) {
    MultiplyRows(matrix_, values, 0, matrix_.num_block_rows(), x, y, nullptr, 0);
    return;
  }
  const int64_t n = matrix_.num_rows();
#pragma omp parallel num_threads(num_threads)
  {
    const int t = omp_get_thread_num();
    std::vector<double>& spill = spill_[t];
    std::fill(spill.begin(), spill.end(), 0.0);
    MultiplyRows(matrix_, values, row_split_[t], row_split_[t + 1], x, y, spill.data(),
                 spill_begin_[t]);
#pragma omp barrier
    // Add the spills: each scalar row s is summed by one thread, over the
    // earlier threads in a fixed order.
#pragma omp for schedule(static)
    for (int64_t s = 0; s < n; ++s) {
      for (int u = 0; u < num_threads; ++u) {
        const int64_t k = s - spill_begin_[u];
        if (k >= 0 && k < static_cast<int64_t>(spill_[u].size())) {
          y[s] += spill_[u][k];
        }
      }
    }
  }
}

int64_t SymmetricMultiplier::MemoryBytes() const {
  int64_t values = diagonal_.size();
  for (const auto& s : spill_) values += static_cast<int64_t>(s.size());
  return values * int64_t{sizeof(double)} +
         static_cast<int64_t>(diagonal_offset_.size() * sizeof(int64_t) + round_.size() * sizeof(int32_t));
}

void SymmetricMultiplySerial(const BsmcMatrix& matrix, const double* x,
                             double* y) {
  MultiplyRows(matrix, DoubleValues{matrix}, 0, matrix.num_block_rows(), x, y, nullptr, 0);
}

}  // namespace dba
