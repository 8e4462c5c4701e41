// Selected inversion: the entries of Z = S⁻¹ on the pattern of S's sparse
// Cholesky factor, computed from the factor in place of it, without the dense
// inverse (Takahashi, Fagan and Chen 1973; Erisman and Tinney 1975). With
// P S Pᵀ = L Lᵀ and Z here in the factor's order, Lᵀ Z = L⁻¹ read at row j,
// columns m >= j (L⁻¹ is lower triangular with 1/L_jj on its diagonal):
//
//   Z_ij = -(1/L_jj) Σ_{k > j, L_kj ≠ 0} L_kj Z_ik          (i > j, L_ij ≠ 0)
//   Z_jj = 1/L_jj² - (1/L_jj) Σ_{k > j, L_kj ≠ 0} L_kj Z_kj
//
// Column j needs Z only at rows and columns of column j's pattern, and those
// entries lie in the pattern of L (the rows of column j below it are a
// clique of the filled graph), so the columns are computed from the last to
// the first, each over the values of L it replaces. Cost: Σ_j Σ_{k ∈ col j}
// |col k| multiply-adds, the order of the factorization's flops; memory: the
// factor's. docs/design.md §7.
//
// Thread safety: pure functions on their arguments.
#pragma once

#include <cstdint>
#include <vector>

namespace dba {

// A sparse lower-triangular factor L of P S Pᵀ = L Lᵀ in compressed columns:
// each column's rows increasing, its diagonal first.
struct CholeskyFactor {
  std::vector<int64_t> perm;     // factor position k holds S's row perm[k]
  std::vector<int64_t> col_ptr;  // n + 1
  std::vector<int64_t> row_idx;
  std::vector<double> values;
  int64_t size() const { return static_cast<int64_t>(perm.size()); }
};

// Sorts each column's rows (values alike) and checks the diagonal is first
// and positive; throws std::logic_error otherwise.
void SortFactorColumns(CholeskyFactor* factor);

// Replaces L's values by Z = S⁻¹ on L's pattern (the lower triangle, in the
// factor's order).
void InvertOnPattern(CholeskyFactor* factor);

// Z's entries by S's indices, after InvertOnPattern.
class InverseOnPattern {
 public:
  explicit InverseOnPattern(CholeskyFactor inverse);
  // (S⁻¹)_ij; std::out_of_range when (i, j) is outside the factor's pattern.
  double At(int64_t i, int64_t j) const;
  int64_t nonzeros() const { return static_cast<int64_t>(z_.row_idx.size()); }

 private:
  CholeskyFactor z_;
  std::vector<int64_t> position_;  // S's row i sits at factor position position_[i]
};

}  // namespace dba
