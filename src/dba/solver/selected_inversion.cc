// Takahashi's recursion on a sparse Cholesky factor; see selected_inversion.h.
#include "dba/solver/selected_inversion.h"

#include <algorithm>
#include <numeric>
#include <stdexcept>
#include <string>

namespace dba {

void SortFactorColumns(CholeskyFactor* f) {
  const int64_t n = f->size();
  std::vector<int64_t> order;
  std::vector<int64_t> rows;
  std::vector<double> values;
  for (int64_t j = 0; j < n; ++j) {
    const int64_t begin = f->col_ptr[j], end = f->col_ptr[j + 1];
    order.resize(end - begin);
    std::iota(order.begin(), order.end(), begin);
    std::sort(order.begin(), order.end(),
              [&](int64_t a, int64_t b) { return f->row_idx[a] < f->row_idx[b]; });
    rows.clear();
    values.clear();
    for (int64_t k : order) {
      rows.push_back(f->row_idx[k]);
      values.push_back(f->values[k]);
    }
    std::copy(rows.begin(), rows.end(), f->row_idx.begin() + begin);
    std::copy(values.begin(), values.end(), f->values.begin() + begin);
    if (end == begin || f->row_idx[begin] != j || !(f->values[begin] > 0.0)) {
      throw std::logic_error("Cholesky factor: column " + std::to_string(j) +
                             " has no positive diagonal first");
    }
  }
}

namespace {

// z[a] += Σ over column k = rows[b] of Z (rows >= k, increasing, containing
// every rows[a] with a >= b) of the products the recursion needs: for each
// a >= b, l[b] Z(rows[a], k) into z[a] and, a > b, l[a] Z(rows[a], k) into
// z[b] (Z is symmetric: Z(k, rows[a]) for row rows[b] = k).
void AddColumnProducts(const CholeskyFactor& f, const int64_t* rows, const double* l, int64_t count,
                       int64_t b, double* z) {
  const int64_t k = rows[b];
  int64_t p = f.col_ptr[k];
  const int64_t end = f.col_ptr[k + 1];
  for (int64_t a = b; a < count; ++a) {
    while (p < end && f.row_idx[p] < rows[a]) ++p;
    if (p == end || f.row_idx[p] != rows[a]) {
      throw std::logic_error("selected inversion: the factor's pattern is not filled (column " +
                             std::to_string(k) + ", row " + std::to_string(rows[a]) + ")");
    }
    const double zak = f.values[p];
    z[a] += l[b] * zak;
    if (a > b) z[b] += l[a] * zak;
  }
}

}  // namespace

void InvertOnPattern(CholeskyFactor* factor) {
  CholeskyFactor& f = *factor;
  std::vector<double> l, z;
  for (int64_t j = f.size() - 1; j >= 0; --j) {
    const int64_t begin = f.col_ptr[j] + 1, end = f.col_ptr[j + 1];
    const int64_t count = end - begin;
    const double d = f.values[begin - 1];
    const int64_t* rows = f.row_idx.data() + begin;
    l.assign(f.values.begin() + begin, f.values.begin() + end);
    z.assign(count, 0.0);
    for (int64_t b = 0; b < count; ++b) AddColumnProducts(f, rows, l.data(), count, b, z.data());
    double diagonal = 1.0 / (d * d);
    for (int64_t a = 0; a < count; ++a) {
      const double zij = -z[a] / d;
      f.values[begin + a] = zij;
      diagonal -= l[a] * zij / d;
    }
    f.values[begin - 1] = diagonal;
  }
}

InverseOnPattern::InverseOnPattern(CholeskyFactor inverse) : z_(std::move(inverse)) {
  position_.resize(z_.size());
  for (int64_t k = 0; k < z_.size(); ++k) position_[z_.perm[k]] = k;
}

double InverseOnPattern::At(int64_t i, int64_t j) const {
  int64_t a = position_[i], b = position_[j];
  if (a < b) std::swap(a, b);
  const auto first = z_.row_idx.begin() + z_.col_ptr[b];
  const auto last = z_.row_idx.begin() + z_.col_ptr[b + 1];
  const auto it = std::lower_bound(first, last, a);
  if (it == last || *it != a) {
    throw std::out_of_range("S⁻¹(" + std::to_string(i) + ", " + std::to_string(j) +
                            ") is outside the factor's pattern");
  }
  return z_.values[it - z_.row_idx.begin()];
}

}  // namespace dba
