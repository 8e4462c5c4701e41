// Two-level additive preconditioner M⁻¹ = B⁻¹ + Rᵀ (R S Rᵀ)⁻¹ R; see
// two_level_preconditioner.h.
#include "dba/solver/two_level_preconditioner.h"

#include <algorithm>

namespace dba {

std::vector<int32_t> AggregateBlockRows(const BsmcMatrix& S, int target) {
  const int32_t n = S.num_block_rows();
  // Both directions of the block graph (S stores the upper triangle).
  std::vector<int64_t> begin(n + 1, 0);
  for (int32_t i = 0; i < n; ++i) {
    for (int64_t b = S.row_begin(i) + 1; b < S.row_end(i); ++b) {
      ++begin[i + 1];
      ++begin[S.block_col(b) + 1];
    }
  }
  for (int32_t i = 0; i < n; ++i) begin[i + 1] += begin[i];
  std::vector<int32_t> neighbour(begin[n]);
  std::vector<int64_t> fill(begin.begin(), begin.end() - 1);
  for (int32_t i = 0; i < n; ++i) {
    for (int64_t b = S.row_begin(i) + 1; b < S.row_end(i); ++b) {
      const int32_t j = S.block_col(b);
      neighbour[fill[i]++] = j;
      neighbour[fill[j]++] = i;
    }
  }
  // Greedy: a seed row, then breadth-first over its not yet aggregated
  // neighbours of the same size until the aggregate is full.
  std::vector<int32_t> aggregate(n, -1);
  std::vector<int32_t> queue;
  int32_t count = 0;
  for (int32_t seed = 0; seed < n; ++seed) {
    if (aggregate[seed] >= 0) continue;
    const int32_t a = count++;
    aggregate[seed] = a;
    queue.assign(1, seed);
    int members = 1;
    for (size_t q = 0; q < queue.size() && members < target; ++q) {
      const int32_t i = queue[q];
      for (int64_t k = begin[i]; k < begin[i + 1] && members < target; ++k) {
        const int32_t j = neighbour[k];
        if (aggregate[j] >= 0 || S.block_size(j) != S.block_size(seed)) continue;
        aggregate[j] = a;
        queue.push_back(j);
        ++members;
      }
    }
  }
  return aggregate;
}

TwoLevelPreconditioner::TwoLevelPreconditioner(const BsmcMatrix& S, int aggregate_size,
                                               int num_threads)
    : S_(S), jacobi_(S, num_threads), aggregate_(AggregateBlockRows(S, aggregate_size)) {
  const int32_t num_aggregates =
      aggregate_.empty() ? 0 : *std::max_element(aggregate_.begin(), aggregate_.end()) + 1;
  std::vector<int32_t> sizes(num_aggregates, 0);
  for (int32_t i = 0; i < S.num_block_rows(); ++i) sizes[aggregate_[i]] = S.block_size(i);
  // Coarse pattern: every S block (i, j) lands in (A_i, A_j), upper.
  std::vector<uint64_t> pattern;
  pattern.reserve(S.num_blocks() + num_aggregates);
  for (int32_t a = 0; a < num_aggregates; ++a) pattern.push_back(PackBlock(a, a));
  for (int32_t i = 0; i < S.num_block_rows(); ++i) {
    for (int64_t b = S.row_begin(i); b < S.row_end(i); ++b) {
      const int32_t ai = aggregate_[i], aj = aggregate_[S.block_col(b)];
      pattern.push_back(PackBlock(std::min(ai, aj), std::max(ai, aj)));
    }
  }
  std::sort(pattern.begin(), pattern.end());
  pattern.erase(std::unique(pattern.begin(), pattern.end()), pattern.end());
  coarse_ = BsmcMatrix::BuildFromPattern(std::move(sizes), pattern);
  coarse_block_.resize(S.num_blocks());
  transposed_.resize(S.num_blocks());
  mirrored_.resize(S.num_blocks());
  for (int32_t i = 0; i < S.num_block_rows(); ++i) {
    for (int64_t b = S.row_begin(i); b < S.row_end(i); ++b) {
      const int32_t j = S.block_col(b);
      const int32_t ai = aggregate_[i], aj = aggregate_[j];
      coarse_block_[b] = coarse_.FindBlock(std::min(ai, aj), std::max(ai, aj));
      transposed_[b] = ai > aj;
      mirrored_[b] = ai == aj && i != j;
    }
  }
  // Dense below ~2,000 coarse unknowns (a few ms), sparse above.
  coarse_solver_ = MakeCholeskySolver(coarse_, 2048);
  rc_.resize(coarse_.num_rows());
}

void TwoLevelPreconditioner::Update(const BsmcMatrix& S) {
  jacobi_.Update(S);
  coarse_.SetZero();
  for (int32_t i = 0; i < S.num_block_rows(); ++i) {
    const int ci = S.block_size(i);
    for (int64_t b = S.row_begin(i); b < S.row_end(i); ++b) {
      const int cj = S.block_size(S.block_col(b));
      const double* v = S.block_values(b);
      double* c = coarse_.block_values(coarse_block_[b]);
      // S_ij lands as is, or transposed where A_i > A_j; both where i < j
      // share an aggregate (S_ji = S_ijᵀ lands in the same block).
      if (!transposed_[b]) {
        for (int k = 0; k < ci * cj; ++k) c[k] += v[k];
      }
      if (transposed_[b] || mirrored_[b]) {
        for (int x = 0; x < ci; ++x) {
          for (int y = 0; y < cj; ++y) c[y * ci + x] += v[x * cj + y];
        }
      }
    }
  }
  coarse_ok_ = coarse_solver_->Factorize(coarse_);
}

void TwoLevelPreconditioner::Apply(const double* r, double* z) const {
  jacobi_.Apply(r, z);
  if (!coarse_ok_) return;  // block-Jacobi alone
  std::fill(rc_.begin(), rc_.end(), 0.0);
  const int32_t n = S_.num_block_rows();
  for (int32_t i = 0; i < n; ++i) {
    const int64_t o = S_.scalar_offset(i), oc = coarse_.scalar_offset(aggregate_[i]);
    for (int d = 0; d < S_.block_size(i); ++d) rc_[oc + d] += r[o + d];
  }
  coarse_solver_->SolveFactored(rc_.data(), rc_.data());
  for (int32_t i = 0; i < n; ++i) {
    const int64_t o = S_.scalar_offset(i), oc = coarse_.scalar_offset(aggregate_[i]);
    for (int d = 0; d < S_.block_size(i); ++d) z[o + d] += rc_[oc + d];
  }
}

int64_t TwoLevelPreconditioner::MemoryBytes() const {
  return jacobi_.MemoryBytes() + coarse_.ValueBytes() + coarse_.StructureBytes() +
         coarse_solver_->MemoryBytes() + static_cast<int64_t>(coarse_block_.size()) * 10 +
         static_cast<int64_t>(aggregate_.size()) * 4;
}

}  // namespace dba
