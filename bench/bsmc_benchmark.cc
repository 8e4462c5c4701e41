// BSMC versus CSR (paper section 4) on RCS matrices of the real BAL problems
// and of synthetic banded problems of growing size:
//   - bytes of BSMC and of CSR, their ratio, and the paper's prediction
//     Y_C / Y_B (eq. 10) for the same n, c and sparsity α;
//   - the two access operations of the paper's Table 1: position -> block
//     (BSMC FindBlock, a binary search in the block row, against a CSR search
//     for the same entry) and block -> position (BSMC BlockRow against the CSR
//     row of a stored entry);
//   - the symmetric matrix-vector product, as time and GB/s, next to a
//     STREAM-style triad measured by the same program.
//
//   ./build/bench/bsmc_benchmark [--benchmark_filter=...]
#include <benchmark/benchmark.h>

#include <algorithm>
#include <filesystem>
#include <map>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "dba/bsmc/symmetric_multiply.h"
#include "dba/io/bal_reader.h"
#include "dba/rcs/form_rcs.h"
#include "dba/testing/random_bsmc.h"

namespace dba {
namespace {

// Scalar CSR of the full symmetric matrix, built from a BSMC one.
struct Csr {
  std::vector<int64_t> row_ptr;
  std::vector<int32_t> col;
  std::vector<double> values;
};

Csr ToCsr(const BsmcMatrix& m) {
  const int64_t n = m.num_rows();
  std::vector<std::vector<std::pair<int32_t, double>>> rows(n);
  for (int32_t i = 0; i < m.num_block_rows(); ++i) {
    for (int64_t b = m.row_begin(i); b < m.row_end(i); ++b) {
      const int32_t j = m.block_col(b);
      const int ri = m.block_size(i), cj = m.block_size(j);
      const double* v = m.block_values(b);
      for (int r = 0; r < ri; ++r) {
        for (int c = 0; c < cj; ++c) {
          const int64_t R = m.scalar_offset(i) + r, C = m.scalar_offset(j) + c;
          rows[R].push_back({static_cast<int32_t>(C), v[r * cj + c]});
          if (j != i) rows[C].push_back({static_cast<int32_t>(R), v[r * cj + c]});
        }
      }
    }
  }
  Csr csr;
  csr.row_ptr.push_back(0);
  for (auto& row : rows) {
    std::sort(row.begin(), row.end());
    for (auto& [c, v] : row) csr.col.push_back(c), csr.values.push_back(v);
    csr.row_ptr.push_back(static_cast<int64_t>(csr.col.size()));
  }
  return csr;
}

struct Case {
  BsmcMatrix matrix;
  std::unique_ptr<Csr> csr;
  int c = 9;  // unknowns per camera
};

// The RCS of a real problem (real values), or of a synthetic banded one.
Case& GetCase(const std::string& name) {
  static std::map<std::string, Case> cases;
  auto it = cases.find(name);
  if (it != cases.end()) return it->second;
  Case c;
  if (name.rfind("synthetic-", 0) == 0) {
    testing::RandomBsmcOptions o;
    o.block_rows = std::stoi(name.substr(10));
    o.sizes = {9};
    o.band = 12;  // a UAV block: each camera overlaps a bounded set
    o.fill = 0.7;
    o.positive_definite = true;
    c.matrix = testing::MakeRandomBsmc(o);
  } else {
    BalProblem p = ReadBal(std::string(DBA_SHARED_DATA_DIR) + "/bal/" + name);
    RcsSystem sys = RcsSystem::ForProblem(p);
    FormRcs(p, 1e-4, DampingBounds{}, 1, &sys);
    c.matrix = std::move(sys.S);
  }
  c.csr = std::make_unique<Csr>(ToCsr(c.matrix));
  return cases.emplace(name, std::move(c)).first->second;
}

const std::vector<std::string>& CaseNames() {
  static const std::vector<std::string> names = {
      "problem-49-7776-pre.txt.bz2", "problem-73-11032-pre.txt.bz2",
      "problem-16-22106-pre.txt.bz2", "synthetic-1000", "synthetic-10000",
      "synthetic-50000"};
  return names;
}

void Bytes(benchmark::State& state, const std::string& name) {
  Case& c = GetCase(name);
  const BsmcMatrix& m = c.matrix;
  for (auto _ : state) benchmark::DoNotOptimize(m.StructureBytes());
  const double n = m.num_block_rows(), cc = c.c;
  const double alpha = (2.0 * m.num_blocks() - n) / (n * n);  // non-zero block fraction
  const double bsmc = static_cast<double>(m.StructureBytes() + m.ValueBytes());
  state.counters["bsmc_MiB"] = bsmc / 1048576.0;
  state.counters["csr_MiB"] = m.CsrBytes() / 1048576.0;
  state.counters["ratio"] = m.CsrBytes() / bsmc;
  state.counters["eq10"] = (6 * alpha * n * cc * cc + 2 * cc) /
                           (2 * alpha * n * cc * cc + 2 * cc * cc + 3 * alpha + 5);
  state.counters["sparsity"] = alpha;
}

// Position -> block: BSMC's binary search in block row i over s_i blocks.
void FindBlock(benchmark::State& state, const std::string& name) {
  const BsmcMatrix& m = GetCase(name).matrix;
  std::mt19937 rng(1);
  std::vector<std::pair<int32_t, int32_t>> queries;
  for (int q = 0; q < 4096; ++q) {
    const int64_t b = rng() % m.num_blocks();
    queries.push_back({m.BlockRow(b), m.block_col(b)});
  }
  size_t q = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(m.FindBlock(queries[q].first, queries[q].second));
    q = (q + 1) & 4095;
  }
}

// Position -> entry in CSR: binary search for the column in the scalar row.
void FindCsr(benchmark::State& state, const std::string& name) {
  Case& c = GetCase(name);
  const Csr& csr = *c.csr;
  std::mt19937 rng(1);
  std::vector<std::pair<int64_t, int32_t>> queries;
  const int64_t rows = static_cast<int64_t>(csr.row_ptr.size()) - 1;
  for (int q = 0; q < 4096; ++q) {
    const int64_t r = rng() % rows;
    const int64_t e = csr.row_ptr[r] + rng() % (csr.row_ptr[r + 1] - csr.row_ptr[r]);
    queries.push_back({r, csr.col[e]});
  }
  size_t q = 0;
  for (auto _ : state) {
    const auto& [r, col] = queries[q];
    benchmark::DoNotOptimize(std::lower_bound(csr.col.begin() + csr.row_ptr[r],
                                              csr.col.begin() + csr.row_ptr[r + 1], col));
    q = (q + 1) & 4095;
  }
}

// Block -> position: the row of a stored block (its column is stored).
void BlockRow(benchmark::State& state, const std::string& name) {
  const BsmcMatrix& m = GetCase(name).matrix;
  std::mt19937 rng(2);
  std::vector<int64_t> blocks(4096);
  for (int64_t& b : blocks) b = rng() % m.num_blocks();
  size_t q = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(m.BlockRow(blocks[q]));
    q = (q + 1) & 4095;
  }
}

// Entry -> position in CSR: the row of a stored entry.
void CsrRow(benchmark::State& state, const std::string& name) {
  const Csr& csr = *GetCase(name).csr;
  std::mt19937 rng(2);
  std::vector<int64_t> entries(4096);
  for (int64_t& e : entries) e = rng() % static_cast<int64_t>(csr.col.size());
  size_t q = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(
        std::upper_bound(csr.row_ptr.begin(), csr.row_ptr.end(), entries[q]) - 1);
    q = (q + 1) & 4095;
  }
}

// y = S x with the BSMC symmetric product; GB/s counts the bytes that must
// be read or written once: values, column ids, offsets and the vectors.
void Matvec(benchmark::State& state, const std::string& name) {
  const BsmcMatrix& m = GetCase(name).matrix;
  const int threads = static_cast<int>(state.range(0));
  const SymmetricMultiplier multiplier(m, threads);
  std::vector<double> x(m.num_rows(), 1.0), y(m.num_rows());
  for (auto _ : state) {
    multiplier.Multiply(x.data(), y.data());
    benchmark::DoNotOptimize(y.data());
  }
  const double bytes = static_cast<double>(m.ValueBytes() + 12 * m.num_blocks() +
                                           3 * 8 * m.num_rows());
  state.counters["GB/s"] = benchmark::Counter(bytes * state.iterations() / 1e9,
                                              benchmark::Counter::kIsRate);
  state.counters["threads_used"] = multiplier.num_threads();
}

// CSR product of the full matrix, for reference (one thread).
void CsrMatvec(benchmark::State& state, const std::string& name) {
  const Csr& csr = *GetCase(name).csr;
  const int64_t rows = static_cast<int64_t>(csr.row_ptr.size()) - 1;
  std::vector<double> x(rows, 1.0), y(rows);
  for (auto _ : state) {
    for (int64_t r = 0; r < rows; ++r) {
      double s = 0;
      for (int64_t e = csr.row_ptr[r]; e < csr.row_ptr[r + 1]; ++e) s += csr.values[e] * x[csr.col[e]];
      y[r] = s;
    }
    benchmark::DoNotOptimize(y.data());
  }
  const double bytes = 12.0 * csr.col.size() + 8.0 * csr.row_ptr.size() + 16.0 * rows;
  state.counters["GB/s"] = benchmark::Counter(bytes * state.iterations() / 1e9,
                                              benchmark::Counter::kIsRate);
}

// STREAM triad a = b + s c over arrays far larger than the caches.
void Triad(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  const int64_t n = int64_t{1} << 25;  // 3 x 256 MiB
  std::vector<double> a(n, 0.0), b(n, 1.0), c(n, 2.0);
  for (auto _ : state) {
#pragma omp parallel for num_threads(threads) schedule(static)
    for (int64_t i = 0; i < n; ++i) a[i] = b[i] + 3.0 * c[i];
    benchmark::DoNotOptimize(a.data());
  }
  state.counters["GB/s"] =
      benchmark::Counter(24.0 * n * state.iterations() / 1e9, benchmark::Counter::kIsRate);
}

void Register() {
  benchmark::RegisterBenchmark("Triad", Triad)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
  for (const std::string& name : CaseNames()) {
    benchmark::RegisterBenchmark(("Bytes/" + name).c_str(), Bytes, name)->Iterations(1);
    benchmark::RegisterBenchmark(("FindBlock/BSMC/" + name).c_str(), FindBlock, name);
    benchmark::RegisterBenchmark(("FindBlock/CSR/" + name).c_str(), FindCsr, name);
    benchmark::RegisterBenchmark(("BlockRow/BSMC/" + name).c_str(), BlockRow, name);
    benchmark::RegisterBenchmark(("BlockRow/CSR/" + name).c_str(), CsrRow, name);
    benchmark::RegisterBenchmark(("Matvec/BSMC/" + name).c_str(), Matvec, name)
        ->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("Matvec/CSR/" + name).c_str(), CsrMatvec, name)
        ->UseRealTime()->Unit(benchmark::kMicrosecond);
  }
}

}  // namespace
}  // namespace dba

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  dba::Register();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
