// Race-free multithreaded symmetric BSMC product; see symmetric_multiply.h.
#include "dba/bsmc/symmetric_multiply.h"

#include <omp.h>

#ifdef __AVX2__
#include <immintrin.h>
#endif

#include <Eigen/Core>
#include <algorithm>

#include "dba/bsmc/block_shape.h"

namespace dba {
namespace {

// y_i += B x_j and, unless diagonal, y_j += Bᵀ x_i for one r x c block.
template <int R, int C>
inline void ApplyBlock(const double* block, int r, int c, const double* x_j,
                       const double* x_i, double* y_i, double* y_j) {
  using MatR = Eigen::Matrix<double, R, C, Eigen::RowMajor>;
  Eigen::Map<const MatR> B(block, r, c);
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
inline void ApplyBlock9x9(const double* __restrict B, const double* __restrict x_j,
                          const double* __restrict x_i, double* __restrict y_i,
                          double* __restrict y_j) {
  const __m256d xj0 = _mm256_loadu_pd(x_j), xj1 = _mm256_loadu_pd(x_j + 4);
  const double xj8 = x_j[8];
  __m256d acc0 = _mm256_setzero_pd(), acc1 = _mm256_setzero_pd();
  double acc8 = 0.0;
  __m256d dot[8];
  double tail[9];  // column 8's share of each row's dot product
  for (int x = 0; x < 9; ++x) {
    const double* row = B + 9 * x;
    const __m256d b0 = _mm256_loadu_pd(row), b1 = _mm256_loadu_pd(row + 4);
    const __m256d xi = _mm256_broadcast_sd(x_i + x);
    acc0 = _mm256_fmadd_pd(b0, xi, acc0);
    acc1 = _mm256_fmadd_pd(b1, xi, acc1);
    acc8 += row[8] * x_i[x];
    const __m256d d = _mm256_fmadd_pd(b1, xj1, _mm256_mul_pd(b0, xj0));
    tail[x] = row[8] * xj8;
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
inline void ApplyBlock6x6(const double* __restrict B, const double* __restrict x_j,
                          const double* __restrict x_i, double* __restrict y_i,
                          double* __restrict y_j) {
  const __m256d xj0 = _mm256_loadu_pd(x_j);
  const __m128d xj4 = _mm_loadu_pd(x_j + 4);
  __m256d acc0 = _mm256_setzero_pd();
  __m128d acc4 = _mm_setzero_pd();
  __m256d dot[4];
  double row_dot[6];
  for (int x = 0; x < 6; ++x) {
    const double* row = B + 6 * x;
    const __m256d b0 = _mm256_loadu_pd(row);
    const __m128d b4 = _mm_loadu_pd(row + 4);
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

// Products of block rows [row0, row1). Transposed products for rows >= row1
// go to spill (indexed from scalar row spill_begin).
void MultiplyRows(const BsmcMatrix& m, int32_t row0, int32_t row1,
                  const double* x, double* y, double* spill,
                  int64_t spill_begin) {
  const int64_t own_end = m.scalar_offset(row1);
  for (int64_t s = m.scalar_offset(row0); s < own_end; ++s) y[s] = 0.0;
  for (int32_t i = row0; i < row1; ++i) {
    const int r = m.block_size(i);
    const int64_t oi = m.scalar_offset(i);
    for (int64_t b = m.row_begin(i); b < m.row_end(i); ++b) {
      const int32_t j = m.block_col(b);
      const int c = m.block_size(j);
      const int64_t oj = m.scalar_offset(j);
      double* y_j = nullptr;
      if (j != i) y_j = oj < own_end ? y + oj : spill + (oj - spill_begin);
      WithBlockShape(r, c, [&]<int R, int C>() {
#ifdef __AVX2__
        if constexpr (R == 9 && C == 9) {
          if (y_j != nullptr) {
            ApplyBlock9x9(m.block_values(b), x + oj, x + oi, y + oi, y_j);
            return;
          }
        } else if constexpr (R == 6 && C == 6) {
          if (y_j != nullptr) {
            ApplyBlock6x6(m.block_values(b), x + oj, x + oi, y + oi, y_j);
            return;
          }
        }
#endif
        ApplyBlock<R, C>(m.block_values(b), r, c, x + oj, x + oi, y + oi, y_j);
      });
    }
  }
}

}  // namespace

SymmetricMultiplier::SymmetricMultiplier(const BsmcMatrix& matrix,
                                         int num_threads)
    : matrix_(matrix) {
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
}

void SymmetricMultiplier::Multiply(const double* x, double* y) const {
  const int num_threads = this->num_threads();
  if (num_threads == 1) {
    MultiplyRows(matrix_, 0, matrix_.num_block_rows(), x, y, nullptr, 0);
    return;
  }
  const int64_t n = matrix_.num_rows();
#pragma omp parallel num_threads(num_threads)
  {
    const int t = omp_get_thread_num();
    std::vector<double>& spill = spill_[t];
    std::fill(spill.begin(), spill.end(), 0.0);
    MultiplyRows(matrix_, row_split_[t], row_split_[t + 1], x, y, spill.data(),
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

int64_t SymmetricMultiplier::spill_size() const {
  int64_t total = 0;
  for (const auto& s : spill_) total += static_cast<int64_t>(s.size());
  return total;
}

void SymmetricMultiplySerial(const BsmcMatrix& matrix, const double* x,
                             double* y) {
  MultiplyRows(matrix, 0, matrix.num_block_rows(), x, y, nullptr, 0);
}

}  // namespace dba
