// Two-level additive preconditioner M⁻¹ = B⁻¹ + Rᵀ (R S Rᵀ)⁻¹ R; see
// two_level_preconditioner.h.
#include "dba/common/check.h"
#include "dba/solver/two_level_preconditioner.h"

#include <omp.h>

#include <algorithm>
#include <atomic>
#include <exception>
#include <stdexcept>
#include <string>

namespace dba {
namespace {

// Blocks of up to kMaxBlock unknowns (a 16-parameter intrinsic group; the
// constructor checks), coarse blocks one more (the scale direction): the
// size of Update's scratch.
constexpr int kMaxBlock = 16;

using Mat3 = Eigen::Matrix3d;
using Panel = Eigen::Map<Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>, 0,
                         Eigen::OuterStride<>>;
using ConstPanel = Eigen::Map<const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>, 0,
                              Eigen::OuterStride<>>;
using Slab = Eigen::Map<Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>, 0,
                        Eigen::OuterStride<>>;
using ConstSlab = Eigen::Map<const Eigen::Matrix<double, 3, Eigen::Dynamic, Eigen::RowMajor>, 0,
                             Eigen::OuterStride<>>;

// N_iᵀ S_ij N_j for an r x c block (row-major; r' x c', one row and column
// more for a basis with a scale column), in two halves by 3x3 panels.
//
// Right: sn = S_ij N_j replaces the pose's columns (δω, δC) by (S_t B, S_ω A + S_t C) and
// appends S_t D (r x c'). `sn` may not alias `s`.
void RightTransform(const double* s, const CoarseRowBasis& Nj, int r, int c, double* sn) {
  const int cc = c + (Nj.scale ? 1 : 0);
  for (int x = 0; x < r; ++x) std::copy(s + x * c, s + x * c + c, sn + x * cc);
  if (!Nj.rigid) return;
  ConstPanel s_w(s, r, 3, Eigen::OuterStride<>(c)), s_t(s + 3, r, 3, Eigen::OuterStride<>(c));
  Panel(sn, r, 3, Eigen::OuterStride<>(cc)).noalias() = s_t * Nj.B;
  Panel o_t(sn + 3, r, 3, Eigen::OuterStride<>(cc));
  o_t.noalias() = s_w * Nj.A;
  o_t.noalias() += s_t * Nj.C;
  if (Nj.scale) {
    for (int x = 0; x < r; ++x) sn[x * cc + c] = s_t.row(x).dot(Nj.D.transpose());
  }
}

// Left: out = N_iᵀ sn replaces the pose's rows (δω, δC) of the r x cc `sn` by (Bᵀ T_t,
// Aᵀ T_ω + Cᵀ T_t) and appends Dᵀ T_t. `out` may not alias `sn`.
void LeftTransform(const CoarseRowBasis& Ni, const double* sn, int r, int cc, double* out) {
  std::copy(sn, sn + r * cc, out);
  if (!Ni.rigid) return;
  ConstSlab t_w(sn, 3, cc, Eigen::OuterStride<>(cc)), t_t(sn + 3 * cc, 3, cc, Eigen::OuterStride<>(cc));
  Slab(out, 3, cc, Eigen::OuterStride<>(cc)).noalias() = Ni.B.transpose() * t_t;
  Slab o_t(out + 3 * cc, 3, cc, Eigen::OuterStride<>(cc));
  o_t.noalias() = Ni.A.transpose() * t_w;
  o_t.noalias() += Ni.C.transpose() * t_t;
  if (Ni.scale) {
    Eigen::Map<Eigen::Matrix<double, 1, Eigen::Dynamic>>(out + r * cc, cc).noalias() =
        Ni.D.transpose() * t_t;
  }
}

}  // namespace

// Each row's neighbours (neighbour[begin[i]..begin[i+1])) in the order of
// their places in `order`, which lists the first n rows (a rank's own: it
// may list more).
static void SortByPlace(const std::vector<int32_t>& order, int32_t n,
                        const std::vector<int64_t>& begin, std::vector<int32_t>* neighbour) {
  std::vector<int32_t> place(static_cast<size_t>(n));
  for (int32_t k = 0; k < n; ++k) place[order[k]] = k;
  for (int32_t i = 0; i < n; ++i) {
    std::sort(neighbour->begin() + begin[i], neighbour->begin() + begin[i + 1],
              [&](int32_t a, int32_t b) { return place[a] < place[b]; });
  }
}

std::vector<int32_t> AggregateBlockRows(const BsmcMatrix& S, int target,
                                        const std::vector<uint8_t>& kind, int32_t num_block_rows,
                                        const std::vector<int32_t>& order) {
  auto same_kind = [&](int32_t i, int32_t j) {
    return S.block_size(i) == S.block_size(j) && (kind.empty() || kind[i] == kind[j]);
  };
  const int32_t n = num_block_rows < 0 ? S.num_block_rows() : num_block_rows;
  // Both directions of the block graph (S stores the upper triangle).
  std::vector<int64_t> begin(n + 1, 0);
  for (int32_t i = 0; i < n; ++i) {
    for (int64_t b = S.row_begin(i) + 1; b < S.row_end(i) && S.block_col(b) < n; ++b) {
      ++begin[i + 1];
      ++begin[S.block_col(b) + 1];
    }
  }
  for (int32_t i = 0; i < n; ++i) begin[i + 1] += begin[i];
  std::vector<int32_t> neighbour(begin[n]);
  std::vector<int64_t> fill(begin.begin(), begin.end() - 1);
  for (int32_t i = 0; i < n; ++i) {
    for (int64_t b = S.row_begin(i) + 1; b < S.row_end(i) && S.block_col(b) < n; ++b) {
      const int32_t j = S.block_col(b);
      neighbour[fill[i]++] = j;
      neighbour[fill[j]++] = i;
    }
  }
  if (!order.empty()) SortByPlace(order, n, begin, &neighbour);
  // Greedy: a seed row, then breadth-first over its not yet aggregated
  // neighbours of the same size until the aggregate is full.
  std::vector<int32_t> aggregate(n, -1);
  std::vector<int32_t> queue;
  int32_t count = 0;
  for (int32_t s = 0; s < n; ++s) {
    const int32_t seed = order.empty() ? s : order[s];
    if (aggregate[seed] >= 0) continue;
    const int32_t a = count++;
    aggregate[seed] = a;
    queue.assign(1, seed);
    int members = 1;
    for (size_t q = 0; q < queue.size() && members < target; ++q) {
      const int32_t i = queue[q];
      for (int64_t k = begin[i]; k < begin[i + 1] && members < target; ++k) {
        const int32_t j = neighbour[k];
        if (aggregate[j] >= 0 || !same_kind(j, seed)) continue;
        aggregate[j] = a;
        queue.push_back(j);
        ++members;
      }
    }
  }
  return aggregate;
}

// Each row's kind of basis (identity 0, rigid 1, rigid with scale 3): rows
// of one aggregate share it.
std::vector<uint8_t> BasisKinds(const BsmcMatrix& S, const std::vector<CoarseRowBasis>& bases) {
  if (bases.empty()) return {};
  if (static_cast<int32_t>(bases.size()) != S.num_block_rows()) {
    throw std::invalid_argument("TwoLevelPreconditioner: one basis per block row expected");
  }
  std::vector<uint8_t> kind(bases.size());
  for (size_t i = 0; i < bases.size(); ++i) {
    if (bases[i].scale && !bases[i].rigid) {
      throw std::invalid_argument("TwoLevelPreconditioner: a scale column without a rigid basis");
    }
    kind[i] = (bases[i].rigid ? 1 : 0) | (bases[i].scale ? 2 : 0);
    if (bases[i].rigid && (S.block_size(i) < 6 || S.block_size(i) > 9)) {
      throw std::invalid_argument("TwoLevelPreconditioner: a rigid basis on a row of " +
                                  std::to_string(S.block_size(i)) + " unknowns");
    }
  }
  return kind;
}

// The scale columns as the coarse space uses them. A lone row's scale is
// one of its translations (D = B (C - c̄)), and a single scaled aggregate's
// scale is the global gauge alone (a null direction of S that only λ
// damps): both would leave R S Rᵀ (nearly) singular, so they go. The rest
// scale about their aggregate's own centre: D_i - B_i o_a, o_a the mean of
// B_jᵀ D_j over the aggregate (for the rigid-motion basis B = I and
// Bᵀ D = C - c̄, so o_a is the aggregate's centre). The span is the same (a
// common translation is added), but D no longer carries the distance to the
// scene's centre, which the coarse Cholesky would have to cancel (a
// 10,000-image survey with tracks of ~4: 3,748 PCG iterations against 682).
int64_t ScaledAggregates(const std::vector<int32_t>& aggregate, int32_t num_aggregates,
                         const std::vector<CoarseRowBasis>& bases) {
  if (bases.empty()) return 0;
  std::vector<int32_t> members(num_aggregates, 0);
  for (int32_t a : aggregate) ++members[a];
  std::vector<uint8_t> scaled(num_aggregates, 0);
  for (size_t i = 0; i < bases.size(); ++i) {
    if (bases[i].scale && members[aggregate[i]] > 1) scaled[aggregate[i]] = 1;
  }
  return std::count(scaled.begin(), scaled.end(), 1);
}

void SettleScaleColumns(const std::vector<int32_t>& aggregate, int32_t num_aggregates,
                        std::vector<CoarseRowBasis>* bases, int64_t scaled_elsewhere) {
  if (bases->empty()) return;
  std::vector<int32_t> members(num_aggregates, 0);
  for (int32_t a : aggregate) ++members[a];
  if (ScaledAggregates(aggregate, num_aggregates, *bases) + scaled_elsewhere < 2) {
    for (CoarseRowBasis& N : *bases) N.scale = false;
    return;
  }
  for (size_t i = 0; i < bases->size(); ++i) {
    if (members[aggregate[i]] == 1) (*bases)[i].scale = false;
  }
  std::vector<Eigen::Vector3d> centre(num_aggregates, Eigen::Vector3d::Zero());
  for (size_t i = 0; i < bases->size(); ++i) {
    const CoarseRowBasis& N = (*bases)[i];
    if (N.scale) centre[aggregate[i]] += N.B.transpose() * N.D / members[aggregate[i]];
  }
  for (size_t i = 0; i < bases->size(); ++i) {
    CoarseRowBasis& N = (*bases)[i];
    if (N.scale) N.D -= N.B * centre[aggregate[i]];
  }
}

TwoLevelPreconditioner::TwoLevelPreconditioner(const BsmcMatrix& S, int aggregate_size,
                                               int num_threads, std::vector<CoarseRowBasis> bases,
                                               const std::vector<int32_t>& aggregation_order)
    : S_(S),
      n_(S.num_block_rows()),
      jacobi_(S, num_threads),
      aggregate_(AggregateBlockRows(S, aggregate_size, BasisKinds(S, bases), -1, aggregation_order)),
      bases_(std::move(bases)) {
  const int32_t num_aggregates =
      aggregate_.empty() ? 0 : *std::max_element(aggregate_.begin(), aggregate_.end()) + 1;
  SettleScaleColumns(aggregate_, num_aggregates, &bases_);
  std::vector<int32_t> sizes(num_aggregates, 0);
  for (int32_t i = 0; i < S.num_block_rows(); ++i) sizes[aggregate_[i]] = CoarseSize(i);
  BuildCoarse(std::move(sizes), num_threads);
  // Dense up to 1,024 coarse unknowns, sparse above: the coarse matrix only
  // couples neighbouring aggregates, and its dense factor is read twice per
  // PCG iteration. Measured (bench/README.md): 400 unknowns (u2k) dense
  // 0.25 s against sparse 0.36 s of linear solve; 1,560 (s10k) dense 1.47 s
  // against sparse 1.28 s.
  coarse_solver_ = MakeCholeskySolver(coarse_, 1024);
}

TwoLevelPreconditioner::TwoLevelPreconditioner(const BsmcMatrix& S, int num_threads,
                                               int32_t num_own_rows, std::vector<int32_t> aggregate,
                                               std::vector<int32_t> coarse_sizes,
                                               std::vector<CoarseRowBasis> bases,
                                               std::unique_ptr<CholeskySolver> coarse_solver)
    : S_(S),
      n_(num_own_rows),
      jacobi_(S, num_threads, num_own_rows),
      aggregate_(std::move(aggregate)),
      bases_(std::move(bases)),
      coarse_solver_(std::move(coarse_solver)) {
  BuildCoarse(std::move(coarse_sizes), num_threads);
}

void TwoLevelPreconditioner::BuildCoarse(std::vector<int32_t> sizes, int num_threads) {
  const BsmcMatrix& S = S_;
  for (int32_t i = 0; i < S.num_block_rows(); ++i) {
    if (S.block_size(i) > kMaxBlock) {
      throw std::invalid_argument("TwoLevelPreconditioner: a block of " +
                                  std::to_string(S.block_size(i)) + " unknowns (at most " +
                                  std::to_string(kMaxBlock) + ")");
    }
  }
  const int32_t num_aggregates = static_cast<int32_t>(sizes.size());
  // Coarse pattern: every S block (i, j) of the rows preconditioned lands in
  // (A_i, A_j), upper.
  const int64_t blocks = n_ > 0 ? S.row_end(n_ - 1) : 0;
  std::vector<uint64_t> pattern;
  pattern.reserve(blocks + num_aggregates);
  for (int32_t a = 0; a < num_aggregates; ++a) pattern.push_back(PackBlock(a, a));
  for (int32_t i = 0; i < n_; ++i) {
    for (int64_t b = S.row_begin(i); b < S.row_end(i); ++b) {
      const int32_t ai = aggregate_[i], aj = aggregate_[S.block_col(b)];
      pattern.push_back(PackBlock(std::min(ai, aj), std::max(ai, aj)));
    }
  }
  std::sort(pattern.begin(), pattern.end());
  pattern.erase(std::unique(pattern.begin(), pattern.end()), pattern.end());
  coarse_ = BsmcMatrix::BuildFromPattern(std::move(sizes), pattern);
  coarse_block_.resize(blocks);
  transposed_.resize(blocks);
  mirrored_.resize(blocks);
  for (int32_t i = 0; i < n_; ++i) {
    for (int64_t b = S.row_begin(i); b < S.row_end(i); ++b) {
      const int32_t j = S.block_col(b);
      const int32_t ai = aggregate_[i], aj = aggregate_[j];
      coarse_block_[b] = coarse_.FindBlock(std::min(ai, aj), std::max(ai, aj));
      DBA_DCHECK(coarse_block_[b] >= 0);  // the coarse pattern holds every aggregate pair
      transposed_[b] = ai > aj;
      mirrored_[b] = ai == aj && i != j;
    }
  }
  // Update's rows split into contiguous ranges of about equal block counts,
  // one per thread (a thread per at least 16K blocks).
  const int threads = static_cast<int>(
      std::clamp<int64_t>(blocks / (int64_t{1} << 14), 1, std::max(num_threads, 1)));
  thread_rows_.assign(threads + 1, n_);
  thread_rows_[0] = 0;
  for (int32_t i = 0, t = 1; i < n_ && t < threads; ++i) {
    if (S.row_end(i) * threads >= blocks * t) thread_rows_[t++] = i + 1;
  }
  partial_.Resize((threads - 1) * coarse_.num_values());
  rc_.resize(coarse_.num_rows());
  // Apply's R: the rows preconditioned, grouped by aggregate, in increasing
  // order within each.
  aggregate_row_begin_.assign(num_aggregates + 1, 0);
  for (int32_t i = 0; i < n_; ++i) ++aggregate_row_begin_[aggregate_[i] + 1];
  for (int32_t a = 0; a < num_aggregates; ++a) {
    aggregate_row_begin_[a + 1] += aggregate_row_begin_[a];
  }
  aggregate_rows_.resize(n_);
  std::vector<int32_t> next(aggregate_row_begin_.begin(), aggregate_row_begin_.end() - 1);
  for (int32_t i = 0; i < n_; ++i) aggregate_rows_[next[aggregate_[i]]++] = i;
  // Those with rows here (on a rank, its own: a contiguous part of the
  // global numbering, which a static split of all aggregates would give to
  // one thread).
  own_aggregates_.clear();
  for (int32_t a = 0; a < num_aggregates; ++a) {
    if (aggregate_row_begin_[a + 1] > aggregate_row_begin_[a]) own_aggregates_.push_back(a);
  }
  num_threads_ = std::max(num_threads, 1);
}

// The coarse matrix summed over all threads, then its factorization
// (serial: CHOLMOD on one BLAS thread, and on more than one rank the coarse
// solver's messages, which FUNNELED MPI allows the main thread) on thread 0
// while the others invert block-Jacobi's blocks, a chunk of rows at a time;
// thread 0 takes chunks too once it has factorized. Each block's inverse is
// the same whoever computes it.
void TwoLevelPreconditioner::Update(const BsmcMatrix& S) {
  DBA_DCHECK(!S.values_narrowed());
  SumCoarse(S);
  jacobi_.AllocateNumeric();
  const int32_t rows = jacobi_.num_block_rows();
  constexpr int64_t kChunk = 4096;
  std::atomic<int64_t> next{0};
  std::exception_ptr failure;
  const int threads = rows > 256 ? num_threads_ : 1;
#pragma omp parallel num_threads(threads) if (threads > 1)
  {
    if (omp_get_thread_num() == 0) {
      // An exception may not leave the parallel region: kept, and rethrown
      // after it.
      try {
        coarse_ok_ = coarse_solver_->Factorize(coarse_);
      } catch (...) {
        failure = std::current_exception();
      }
    }
    for (int64_t begin; (begin = next.fetch_add(kChunk)) < rows;) {
      jacobi_.UpdateRows(S, static_cast<int32_t>(begin),
                         static_cast<int32_t>(std::min<int64_t>(begin + kChunk, rows)));
    }
  }
  if (failure) std::rethrow_exception(failure);
}

void TwoLevelPreconditioner::SumCoarse(const BsmcMatrix& S) {
  const int threads = static_cast<int>(thread_rows_.size()) - 1;
  const int64_t num_values = coarse_.num_values();
  double* const partial = partial_.data();  // allocated here
  // Part t (rows thread_rows_[t] to [t + 1]) sums into its own array, on
  // whichever thread the team gives it (a team may be smaller than asked).
#pragma omp parallel num_threads(threads) if (threads > 1)
  for (int t = omp_get_thread_num(); t < threads; t += omp_get_num_threads()) {
    double* sum = t == 0 ? coarse_.values().data() : partial + (t - 1) * num_values;
    if (t == 0) {
      coarse_.SetZero();  // nothing to write where its pages were given back
    } else {
      std::fill(sum, sum + num_values, 0.0);
    }
    // Row i's blocks that land in the same coarse block the same way (S's
    // columns are sorted, and an aggregate's cameras mostly neighbours) are
    // summed after the right half of the transform and take the left half
    // once: Σ_j N_iᵀ S_ij N_j = N_iᵀ (Σ_j S_ij N_j).
    double right[kMaxBlock * (kMaxBlock + 1)], sum_right[kMaxBlock * (kMaxBlock + 1)],
        transformed[(kMaxBlock + 1) * (kMaxBlock + 1)];
    for (int32_t i = thread_rows_[t]; i < thread_rows_[t + 1]; ++i) {
      const int r = S.block_size(i), ci = CoarseSize(i);
      for (int64_t b = S.row_begin(i); b < S.row_end(i);) {
        const int c = S.block_size(S.block_col(b)), cj = CoarseSize(S.block_col(b));
        int64_t end = b + 1;  // of the group
        while (end < S.row_end(i) && coarse_block_[end] == coarse_block_[b] &&
               transposed_[end] == transposed_[b] && mirrored_[end] == mirrored_[b]) {
          ++end;
        }
        RightTransform(S.block_values(b), Basis(S.block_col(b)), r, c, sum_right);
        for (int64_t g = b + 1; g < end; ++g) {
          RightTransform(S.block_values(g), Basis(S.block_col(g)), r, c, right);
          for (int k = 0; k < r * cj; ++k) sum_right[k] += right[k];
        }
        LeftTransform(Basis(i), sum_right, r, cj, transformed);
        const double* v = transformed;
        double* c_block = sum + coarse_.value_offset(coarse_block_[b]);
        // N_iᵀ S_ij N_j lands as is, or transposed where A_i > A_j; both
        // where i < j share an aggregate (S_ji = S_ijᵀ lands in the same
        // block).
        if (!transposed_[b]) {
          for (int k = 0; k < ci * cj; ++k) c_block[k] += v[k];
        }
        if (transposed_[b] || mirrored_[b]) {
          for (int x = 0; x < ci; ++x) {
            for (int y = 0; y < cj; ++y) c_block[y * ci + x] += v[x * cj + y];
          }
        }
        b = end;
      }
    }
  }
  // The parts' sums in order: the same coarse matrix for any schedule.
  double* c = coarse_.values().data();
  for (int t = 1; t < threads; ++t) {
    const double* p = partial + (t - 1) * num_values;
    for (int64_t k = 0; k < num_values; ++k) c[k] += p[k];
  }
  // Summed: pages of its own go back now, not beside the factorization and
  // PCG.
  partial_.ReturnPages();
}

// z = B⁻¹ r + Rᵀ (R S Rᵀ)⁻¹ R r. The two terms are independent: thread 0
// solves the coarse system (serial: CHOLMOD's triangular solves, and on
// more than one rank the coarse solver's messages, which FUNNELED MPI allows
// the main thread) while the others apply block-Jacobi. R r is summed
// aggregate by aggregate (each aggregate's rows in increasing order) and
// Rᵀ applied row by row, both over all threads; the result does not depend
// on the number of threads.
void TwoLevelPreconditioner::Apply(const double* r, double* z) const {
  if (!coarse_ok_) {  // block-Jacobi alone
    jacobi_.Apply(r, z);
    return;
  }
  std::fill(rc_.begin(), rc_.end(), 0.0);
  const int32_t num_own = static_cast<int32_t>(own_aggregates_.size());
  const int32_t n = n_;
  const int threads = n > 256 ? num_threads_ : 1;
  std::exception_ptr failure;
#pragma omp parallel num_threads(threads) if (threads > 1)
  {
    // rc = R r: each row's N_iᵀ r_i summed into its aggregate.
#pragma omp for schedule(static)
    for (int32_t k = 0; k < num_own; ++k) {
      const int32_t a = own_aggregates_[k];
      double* ra = rc_.data() + coarse_.scalar_offset(a);
      for (int32_t x = aggregate_row_begin_[a]; x < aggregate_row_begin_[a + 1]; ++x) {
        const int32_t i = aggregate_rows_[x];
        const double* ri = r + S_.scalar_offset(i);
        int d = 0;
        if (!bases_.empty() && bases_[i].rigid) {
          const CoarseRowBasis& N = bases_[i];
          const Eigen::Map<const Eigen::Vector3d> r_w(ri), r_t(ri + 3);
          Eigen::Map<Eigen::Vector3d>(ra).noalias() += N.B.transpose() * r_t;
          Eigen::Map<Eigen::Vector3d>(ra + 3).noalias() +=
              N.A.transpose() * r_w + N.C.transpose() * r_t;
          if (N.scale) ra[S_.block_size(i)] += N.D.dot(r_t);
          d = 6;
        }
        for (; d < S_.block_size(i); ++d) ra[d] += ri[d];
      }
    }
    const int t = omp_get_thread_num(), team = omp_get_num_threads();
    if (t == 0) {
      // An exception may not leave the parallel region: kept, and rethrown
      // after it (a failed solve, a lost rank).
      try {
        coarse_solver_->SolveFactored(rc_.data(), rc_.data());
      } catch (...) {
        failure = std::current_exception();
      }
    }
    // z = B⁻¹ r: rows split over threads 1.. (all of them on a single thread).
    const int workers = std::max(team - 1, 1), w = team == 1 ? 0 : t - 1;
    if (w >= 0) jacobi_.ApplyShare(r, z, w, workers);
#pragma omp barrier
    // z += Rᵀ rc: each row's N_i times its aggregate's coarse solution.
#pragma omp for schedule(static)
    for (int32_t i = 0; i < n; ++i) {
      double* zi = z + S_.scalar_offset(i);
      const double* ca = rc_.data() + coarse_.scalar_offset(aggregate_[i]);
      int d = 0;
      if (!bases_.empty() && bases_[i].rigid) {
        const CoarseRowBasis& N = bases_[i];
        const Eigen::Map<const Eigen::Vector3d> c_translation(ca), c_rotation(ca + 3);
        Eigen::Map<Eigen::Vector3d>(zi).noalias() += N.A * c_rotation;
        Eigen::Map<Eigen::Vector3d>(zi + 3).noalias() += N.B * c_translation + N.C * c_rotation;
        if (N.scale) Eigen::Map<Eigen::Vector3d>(zi + 3) += N.D * ca[S_.block_size(i)];
        d = 6;
      }
      for (; d < S_.block_size(i); ++d) zi[d] += ca[d];
    }
  }
  if (failure) std::rethrow_exception(failure);
}

int64_t TwoLevelPreconditioner::NumericDoubles() const {
  return jacobi_.NumericDoubles() + coarse_.num_values();
}

void TwoLevelPreconditioner::PlaceNumeric(double* place) {
  jacobi_.PlaceNumeric(place);
  coarse_.PlaceValues(place == nullptr ? nullptr : place + jacobi_.NumericDoubles());
}

void TwoLevelPreconditioner::ReturnNumericPages() {
  jacobi_.ReturnNumericPages();
  coarse_.ZeroValuesAndReturnPages();  // SumCoarse rewrites them; lent ones stay the lender's
}

int64_t TwoLevelPreconditioner::MemoryBytes() const {
  return jacobi_.MemoryBytes() + coarse_.ValueBytes() + coarse_.StructureBytes() +
         coarse_solver_->MemoryBytes() + static_cast<int64_t>(coarse_block_.size()) * 10 +
         static_cast<int64_t>(aggregate_.size() + aggregate_rows_.size() +
                              aggregate_row_begin_.size() + own_aggregates_.size()) * 4 +
         static_cast<int64_t>(bases_.size() * sizeof(CoarseRowBasis)) +
         partial_.size() * 8;
}

}  // namespace dba
