// BSMC versus CSR (paper section 4), on the RCS of every real BAL
// problem and of synthetic UAV surveys of growing size (real values: the RCS
// is formed by FormRcs at the initial parameters).
//
//   Bytes/<case>            counters: bsmc_MiB, csr_MiB, ratio = CSR/BSMC,
//                           eq10 = the paper's predicted Y_C/Y_B for the same
//                           n, c = 9 and sparsity α; eq8_MiB / eq9_MiB = the
//                           paper's Y_C and Y_B; sparsity α, blocks per row.
//   Find/<fmt>/<case>       the paper's second operation (Table 1), position
//                           -> storage, for random stored blocks (i, j):
//                           BSMC      FindBlock(i, j): binary search in block
//                                     row i (log2 s_i);
//                           CSR1      the same block's scalar entry (r, c),
//                                     one binary search in scalar row r;
//                           CSRblock  every scalar row of the block (c binary
//                                     searches, the paper's Σ log2(c s_i)).
//   Row/<fmt>/<case>        the first operation, storage -> position, for a
//                           random stored block / scalar entry: BSMC BlockRow
//                           (binary search over n row starts) against CSR
//                           (binary search over n·c row pointers).
//   Scan/<fmt>/<case>       the first operation when storage is walked in
//                           order (what the matvec does): position of every
//                           block (BSMC) / entry (CSR); counters ns_per_item
//                           and ns_per_scalar.
//   Matvec/BSMC/<case>/T    the symmetric product y = S x of PCG with T
//                           threads; GB/s = (values + 12 bytes per block +
//                           3 vectors) / time, pct_triad = GB/s against a
//                           triad run just before and after it with the
//                           threads the product really uses (one below 2^17
//                           values per thread).
//   Matvec/CSR/<case>       plain CSR product of the full matrix (1 thread).
//   PcgIteration/<case>/T   one iteration of dba's PCG (matvec, block-Jacobi,
//                           vector updates, dots), against the matvec alone:
//                           counter over_matvec = PCG iteration / matvec time.
//   Triad/T                 STREAM triad a = b + 3 c over 3 x 256 MiB with T
//                           threads: the machine's memory bandwidth.
//
// Real problems: every file in $DBA_BAL_DIR, else in DBA_BAL_DIR (compile
// definition: ../shared/data/bal beside the source tree). Synthetic: UAV
// surveys (dba generate's model, 300 features per image, default overlaps) of
// $DBA_BSMC_UAV_SIZES images (comma separated; default 1000,4000,16000).
//
//   ./build/bench/bsmc_benchmark [--benchmark_filter=...]
//   bash bench/bsmc.sh   (runs it and writes bench/results/bsmc.md)
#include <benchmark/benchmark.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <memory>
#include <random>
#include <sstream>
#include <string>
#include <vector>

#include "dba/bsmc/symmetric_multiply.h"
#include "dba/io/read_problem.h"
#include "dba/rcs/form_rcs.h"
#include "dba/solver/block_jacobi.h"
#include "dba/solver/pcg.h"
#include "dba/synthetic/uav_generator.h"

namespace dba {
namespace {

constexpr int kCameraSize = 9;  // BAL: c = 9 unknowns per camera
constexpr int kQueries = 1 << 14;

double Since(std::chrono::steady_clock::time_point t0) {
  return std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
}

// Scalar CSR of the full symmetric matrix: 8-byte values, 4-byte column ids,
// 8-byte row pointers (the layout CsrBytes() counts).
struct Csr {
  std::vector<int64_t> row_ptr;
  std::vector<int32_t> col;
  std::vector<double> values;
};

// Walking the blocks by block row, then column, visits every scalar row's
// transposed entries (columns left of the diagonal block) before its own, in
// increasing column order: one counting pass and one filling pass give sorted
// rows without a sort.
Csr ToCsr(const BsmcMatrix& m) {
  const int64_t n = m.num_rows();
  Csr csr;
  csr.row_ptr.assign(n + 1, 0);
  for (int32_t i = 0; i < m.num_block_rows(); ++i) {
    for (int64_t b = m.row_begin(i); b < m.row_end(i); ++b) {
      const int32_t j = m.block_col(b);
      for (int r = 0; r < m.block_size(i); ++r) csr.row_ptr[m.scalar_offset(i) + r + 1] += m.block_size(j);
      if (j != i) {
        for (int c = 0; c < m.block_size(j); ++c) csr.row_ptr[m.scalar_offset(j) + c + 1] += m.block_size(i);
      }
    }
  }
  for (int64_t r = 0; r < n; ++r) csr.row_ptr[r + 1] += csr.row_ptr[r];
  csr.col.resize(csr.row_ptr[n]);
  csr.values.resize(csr.row_ptr[n]);
  std::vector<int64_t> next(csr.row_ptr.begin(), csr.row_ptr.end() - 1);
  for (int32_t i = 0; i < m.num_block_rows(); ++i) {
    for (int64_t b = m.row_begin(i); b < m.row_end(i); ++b) {
      const int32_t j = m.block_col(b);
      const int ri = m.block_size(i), cj = m.block_size(j);
      const double* v = m.block_values(b);
      for (int r = 0; r < ri; ++r) {
        for (int c = 0; c < cj; ++c) {
          const int64_t R = m.scalar_offset(i) + r, C = m.scalar_offset(j) + c;
          csr.col[next[R]] = static_cast<int32_t>(C);
          csr.values[next[R]++] = v[r * cj + c];
          if (j != i) {
            csr.col[next[C]] = static_cast<int32_t>(R);
            csr.values[next[C]++] = v[r * cj + c];
          }
        }
      }
    }
  }
  return csr;
}

struct Case {
  BsmcMatrix matrix;
  Csr csr;
  std::vector<double> jtj_diagonal;  // for the damped system of the PCG benchmark
  int64_t observations = 0;
};

std::string BalDir() {
  if (const char* e = std::getenv("DBA_BAL_DIR"); e != nullptr && *e != '\0') return e;
  return DBA_BAL_DIR;
}

std::vector<int64_t> UavSizes() {
  std::vector<int64_t> sizes;
  std::string s = "1000,4000,16000";
  if (const char* e = std::getenv("DBA_BSMC_UAV_SIZES"); e != nullptr && *e != '\0') s = e;
  std::stringstream in(s);
  for (std::string item; std::getline(in, item, ',');) {
    if (!item.empty()) sizes.push_back(std::stoll(item));
  }
  return sizes;
}

// Case names: "bal/<file name without .txt.bz2>" or "uav-<images>".
std::vector<std::string> CaseNames() {
  std::vector<std::string> names;
  std::error_code ec;
  for (const auto& e : std::filesystem::directory_iterator(BalDir(), ec)) {
    if (!e.is_regular_file()) continue;
    std::string f = e.path().filename().string();
    for (const char* ext : {".bz2", ".txt"}) {
      if (f.size() > std::string(ext).size() && f.ends_with(ext)) f.resize(f.size() - std::string(ext).size());
    }
    names.push_back("bal/" + f);
  }
  std::sort(names.begin(), names.end());
  for (int64_t n : UavSizes()) names.push_back("uav-" + std::to_string(n));
  return names;
}

Problem LoadCase(const std::string& name) {
  if (name.rfind("bal/", 0) == 0) {
    for (const char* ext : {".txt.bz2", ".bz2", ".txt", ""}) {
      const std::string path = BalDir() + "/" + name.substr(4) + ext;
      if (std::filesystem::exists(path)) return ReadProblem(path);
    }
    throw std::runtime_error("no BAL file for " + name);
  }
  UavSurveyOptions o;
  o.images = std::stoll(name.substr(4));
  const std::string path = (std::filesystem::temp_directory_path() /
                            ("dba-bsmc-benchmark-" + std::to_string(getpid()) + ".dba")).string();
  GenerateUavSurvey(o, path, "");
  Problem p = ReadProblem(path);
  std::filesystem::remove(path);
  return p;
}

// The RCS of the case at its initial parameters, built once and kept.
Case& GetCase(const std::string& name) {
  static std::map<std::string, std::unique_ptr<Case>> cases;
  auto it = cases.find(name);
  if (it != cases.end()) return *it->second;
  auto c = std::make_unique<Case>();
  {
    Problem p = LoadCase(name);
    RcsSystem sys = RcsSystem::ForProblem(p);
    FormRcs(p, 1e-4, DampingBounds{}, 2, &sys);
    c->observations = p.num_observations();
    c->matrix = std::move(sys.S);
    c->jtj_diagonal = std::move(sys.camera_side_jtj_diagonal);
  }
  c->csr = ToCsr(c->matrix);
  return *cases.emplace(name, std::move(c)).first->second;
}

// Random stored blocks (i, j) and, inside each, a random scalar (r, c).
struct Queries {
  std::vector<int64_t> block;
  std::vector<int32_t> row, col;          // block position
  std::vector<int64_t> srow;              // scalar row inside the block
  std::vector<int32_t> scol;              // scalar column inside the block
};

const Queries& GetQueries(const std::string& name) {
  static std::map<std::string, Queries> all;
  auto it = all.find(name);
  if (it != all.end()) return it->second;
  const BsmcMatrix& m = GetCase(name).matrix;
  std::mt19937_64 rng(1);
  Queries q;
  for (int k = 0; k < kQueries; ++k) {
    const int64_t b = static_cast<int64_t>(rng() % m.num_blocks());
    const int32_t i = m.BlockRow(b), j = m.block_col(b);
    q.block.push_back(b);
    q.row.push_back(i);
    q.col.push_back(j);
    q.srow.push_back(m.scalar_offset(i) + static_cast<int64_t>(rng() % m.block_size(i)));
    q.scol.push_back(static_cast<int32_t>(m.scalar_offset(j) + static_cast<int64_t>(rng() % m.block_size(j))));
  }
  return all.emplace(name, std::move(q)).first->second;
}

void Bytes(benchmark::State& state, const std::string& name) {
  Case& c = GetCase(name);
  const BsmcMatrix& m = c.matrix;
  for (auto _ : state) benchmark::DoNotOptimize(m.StructureBytes());
  const double n = m.num_block_rows(), cc = kCameraSize;
  const double alpha = (2.0 * m.num_blocks() - n) / (n * n);  // non-zero blocks / n²
  const double bsmc = static_cast<double>(m.StructureBytes() + m.ValueBytes());
  const double eq8 = alpha * n * n * cc * cc * 12 + n * cc * 4;
  const double eq9 = (alpha * n * n + n) / 2 * (cc * cc * 8 + 12) + n * 4;
  state.counters["cameras"] = n;
  state.counters["observations"] = static_cast<double>(c.observations);
  state.counters["blocks"] = static_cast<double>(m.num_blocks());
  state.counters["sparsity"] = alpha;
  state.counters["bsmc_MiB"] = bsmc / 1048576.0;
  state.counters["csr_MiB"] = static_cast<double>(m.CsrBytes()) / 1048576.0;
  state.counters["ratio"] = static_cast<double>(m.CsrBytes()) / bsmc;
  state.counters["eq8_MiB"] = eq8 / 1048576.0;
  state.counters["eq9_MiB"] = eq9 / 1048576.0;
  state.counters["eq10"] = (6 * alpha * n * cc * cc + 2 * cc) /
                           (2 * alpha * n * cc * cc + 2 * cc * cc + 3 * alpha + 5);
}

// Position -> block in BSMC: binary search in block row i.
void FindBsmc(benchmark::State& state, const std::string& name) {
  const BsmcMatrix& m = GetCase(name).matrix;
  const Queries& q = GetQueries(name);
  size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(m.FindBlock(q.row[k], q.col[k]));
    k = (k + 1) & (kQueries - 1);
  }
}

// Position -> entry in CSR: the same block's scalar (r, c), one binary search.
void FindCsr1(benchmark::State& state, const std::string& name) {
  const Csr& csr = GetCase(name).csr;
  const Queries& q = GetQueries(name);
  size_t k = 0;
  for (auto _ : state) {
    const int64_t r = q.srow[k];
    benchmark::DoNotOptimize(std::lower_bound(csr.col.begin() + csr.row_ptr[r],
                                              csr.col.begin() + csr.row_ptr[r + 1], q.scol[k]));
    k = (k + 1) & (kQueries - 1);
  }
}

// Position -> block in CSR: the block's entries lie in c scalar rows, one
// binary search per row (the paper's Σ_i log2(c s_i)).
void FindCsrBlock(benchmark::State& state, const std::string& name) {
  const Case& c = GetCase(name);
  const Csr& csr = c.csr;
  const Queries& q = GetQueries(name);
  size_t k = 0;
  for (auto _ : state) {
    const int64_t r0 = c.matrix.scalar_offset(q.row[k]);
    const int32_t col0 = static_cast<int32_t>(c.matrix.scalar_offset(q.col[k]));
    for (int r = 0; r < c.matrix.block_size(q.row[k]); ++r) {
      benchmark::DoNotOptimize(std::lower_bound(csr.col.begin() + csr.row_ptr[r0 + r],
                                                csr.col.begin() + csr.row_ptr[r0 + r + 1], col0));
    }
    k = (k + 1) & (kQueries - 1);
  }
}

// Storage -> position, random: the block row of a stored block.
void RowBsmc(benchmark::State& state, const std::string& name) {
  const BsmcMatrix& m = GetCase(name).matrix;
  const Queries& q = GetQueries(name);
  size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(m.BlockRow(q.block[k]));
    k = (k + 1) & (kQueries - 1);
  }
}

// Storage -> position, random: the scalar row of a stored CSR entry.
void RowCsr(benchmark::State& state, const std::string& name) {
  const Csr& csr = GetCase(name).csr;
  std::mt19937_64 rng(2);
  std::vector<int64_t> entries(kQueries);
  for (int64_t& e : entries) e = static_cast<int64_t>(rng() % csr.col.size());
  size_t k = 0;
  for (auto _ : state) {
    benchmark::DoNotOptimize(std::upper_bound(csr.row_ptr.begin(), csr.row_ptr.end(), entries[k]) - 1);
    k = (k + 1) & (kQueries - 1);
  }
}

// Storage -> position, sequential: every block's (row, col, value offset).
void ScanBsmc(benchmark::State& state, const std::string& name) {
  const BsmcMatrix& m = GetCase(name).matrix;
  const auto t0 = std::chrono::steady_clock::now();
  for (auto _ : state) {
    int64_t sum = 0;
    for (int32_t i = 0; i < m.num_block_rows(); ++i) {
      for (int64_t b = m.row_begin(i); b < m.row_end(i); ++b) sum += i + m.block_col(b) + m.value_offset(b);
    }
    benchmark::DoNotOptimize(sum);
  }
  const double ns = 1e9 * Since(t0) / static_cast<double>(std::max<int64_t>(state.iterations(), 1));
  state.counters["ns_per_item"] = ns / static_cast<double>(m.num_blocks());
  state.counters["ns_per_scalar"] = ns / static_cast<double>(m.num_values());
}

// Storage -> position, sequential: every CSR entry's (row, col).
void ScanCsr(benchmark::State& state, const std::string& name) {
  const Csr& csr = GetCase(name).csr;
  const int64_t rows = static_cast<int64_t>(csr.row_ptr.size()) - 1;
  const auto t0 = std::chrono::steady_clock::now();
  for (auto _ : state) {
    int64_t sum = 0;
    for (int64_t r = 0; r < rows; ++r) {
      for (int64_t e = csr.row_ptr[r]; e < csr.row_ptr[r + 1]; ++e) sum += r + csr.col[e];
    }
    benchmark::DoNotOptimize(sum);
  }
  const double ns = 1e9 * Since(t0) / static_cast<double>(std::max<int64_t>(state.iterations(), 1));
  state.counters["ns_per_item"] = ns / static_cast<double>(csr.col.size());
  state.counters["ns_per_scalar"] = ns / static_cast<double>(csr.col.size());
}

// STREAM triad a = b + 3 c over 3 x 256 MiB (far larger than the caches),
// allocated once and first touched by two threads.
struct TriadArrays {
  static constexpr int64_t n = int64_t{1} << 25;
  std::unique_ptr<double[]> a{new double[n]}, b{new double[n]}, c{new double[n]};
  TriadArrays() {
#pragma omp parallel for num_threads(2) schedule(static)
    for (int64_t i = 0; i < n; ++i) a[i] = 0.0, b[i] = 1.0, c[i] = 2.0;
  }
  void Run(int threads) {
    double* __restrict pa = a.get();
    const double* __restrict pb = b.get();
    const double* __restrict pc = c.get();
#pragma omp parallel for num_threads(threads) schedule(static)
    for (int64_t i = 0; i < n; ++i) pa[i] = pb[i] + 3.0 * pc[i];
    benchmark::DoNotOptimize(pa);
  }
  static constexpr double kBytes = 24.0 * n;
};

TriadArrays& Arrays() {
  static TriadArrays arrays;
  return arrays;
}

// Triad GB/s with `threads` threads, averaged over about `seconds`.
double TriadGBs(int threads, double seconds) {
  TriadArrays& t = Arrays();
  t.Run(threads);  // warm up
  const auto t0 = std::chrono::steady_clock::now();
  int64_t reps = 0;
  do {
    t.Run(threads);
    ++reps;
  } while (Since(t0) < seconds);
  return TriadArrays::kBytes * static_cast<double>(reps) / Since(t0) / 1e9;
}

void Triad(benchmark::State& state) {
  const int threads = static_cast<int>(state.range(0));
  TriadArrays& t = Arrays();
  for (auto _ : state) t.Run(threads);
  state.counters["GB/s"] = benchmark::Counter(TriadArrays::kBytes * state.iterations() / 1e9,
                                              benchmark::Counter::kIsRate);
}

// The memory bandwidth of a shared (virtual) machine drifts with its
// neighbours' load, so each product is put next to a triad run just before
// and just after it, with the threads the product really uses.
// Mixed precision (float off-diagonal blocks, bsmc/symmetric_multiply.h)
// reads 4 bytes per off-diagonal value and 8 per diagonal one.
void Matvec(benchmark::State& state, const std::string& name, ProductPrecision precision) {
  BsmcMatrix m = GetCase(name).matrix;  // a copy: narrowing rewrites it
  const int threads = static_cast<int>(state.range(0));
  SymmetricMultiplier multiplier(m, threads, precision);
  int64_t diagonal_values = 0;
  for (int32_t i = 0; i < m.num_block_rows(); ++i) diagonal_values += int64_t{m.block_size(i)} * m.block_size(i);
  const int64_t value_bytes = precision == ProductPrecision::kMixed
                                  ? 4 * (m.num_values() - diagonal_values) + 8 * diagonal_values
                                  : m.ValueBytes();
  if (precision == ProductPrecision::kMixed) multiplier.Narrow(&m);
  std::vector<double> x(m.num_rows(), 1.0), y(m.num_rows());
  const double triad_before = TriadGBs(multiplier.num_threads(), 0.15);
  const auto t0 = std::chrono::steady_clock::now();
  for (auto _ : state) {
    multiplier.Multiply(x.data(), y.data());
    benchmark::DoNotOptimize(y.data());
  }
  const double elapsed = Since(t0);
  const double triad = 0.5 * (triad_before + TriadGBs(multiplier.num_threads(), 0.15));
  const double bytes = static_cast<double>(value_bytes + 12 * m.num_blocks() + 3 * 8 * m.num_rows());
  state.counters["GB/s"] = benchmark::Counter(bytes * state.iterations() / 1e9, benchmark::Counter::kIsRate);
  state.counters["triad_GB/s"] = triad;
  state.counters["pct_triad"] = 100.0 * bytes * state.iterations() / 1e9 / elapsed / triad;
  state.counters["threads_used"] = multiplier.num_threads();
  state.counters["MiB"] = bytes / 1048576.0;
}

void CsrMatvec(benchmark::State& state, const std::string& name) {
  const Csr& csr = GetCase(name).csr;
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
  state.counters["GB/s"] = benchmark::Counter(bytes * state.iterations() / 1e9, benchmark::Counter::kIsRate);
  state.counters["MiB"] = bytes / 1048576.0;
}

// One PCG iteration of dba's solver on the damped RCS (λ = 1e-4), tolerance
// 0 so every call runs exactly `kPcgIterations` iterations (or stops at a
// breakdown, which the counter `iterations` would show).
void PcgIteration(benchmark::State& state, const std::string& name) {
  constexpr int kPcgIterations = 20;
  Case& c = GetCase(name);
  const int threads = static_cast<int>(state.range(0));
  BsmcMatrix S = c.matrix;  // a damped copy
  DampCameraBlocks(1e-4, DampingBounds{}, c.jtj_diagonal, &S);
  const SymmetricMultiplier multiplier(S, threads);
  BlockJacobiPreconditioner preconditioner(S, threads);
  preconditioner.Update(S);
  PcgScratch scratch;
  std::vector<double> b(S.num_rows()), y(S.num_rows());
  std::mt19937_64 rng(3);
  std::uniform_real_distribution<double> u(-1.0, 1.0);
  for (double& v : b) v = u(rng);
  PcgOptions options;
  options.relative_tolerance = 0.0;
  options.eta = 0.0;
  options.residual_reset_period = 0;
  options.max_iterations = kPcgIterations;
  options.num_threads = threads;
  int64_t iterations = 0;
  const auto t_pcg = std::chrono::steady_clock::now();
  for (auto _ : state) {
    iterations += SolvePcg(multiplier, preconditioner, b.data(), y.data(), options, &scratch).iterations;
  }
  const double pcg_seconds = Since(t_pcg);
  // Matvec alone on the same matrix, for the ratio.
  std::vector<double> x(S.num_rows(), 1.0), z(S.num_rows());
  const auto t0 = std::chrono::steady_clock::now();
  int64_t reps = 0;
  double elapsed = 0.0;
  do {
    multiplier.Multiply(x.data(), z.data());
    ++reps;
    elapsed = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  } while (elapsed < 0.2);
  const double iteration_us = 1e6 * pcg_seconds / static_cast<double>(std::max<int64_t>(iterations, 1));
  const double matvec_us = 1e6 * elapsed / static_cast<double>(reps);
  state.counters["us_per_iteration"] = iteration_us;
  state.counters["matvec_us"] = matvec_us;
  state.counters["over_matvec"] = iteration_us / matvec_us;
  state.counters["iterations"] = static_cast<double>(iterations) / std::max<int64_t>(state.iterations(), 1);
}

void Register() {
  benchmark::RegisterBenchmark("Triad", Triad)->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
  for (const std::string& name : CaseNames()) {
    benchmark::RegisterBenchmark(("Bytes/" + name).c_str(), Bytes, name)->Iterations(1);
    benchmark::RegisterBenchmark(("Find/BSMC/" + name).c_str(), FindBsmc, name);
    benchmark::RegisterBenchmark(("Find/CSR1/" + name).c_str(), FindCsr1, name);
    benchmark::RegisterBenchmark(("Find/CSRblock/" + name).c_str(), FindCsrBlock, name);
    benchmark::RegisterBenchmark(("Row/BSMC/" + name).c_str(), RowBsmc, name);
    benchmark::RegisterBenchmark(("Row/CSR/" + name).c_str(), RowCsr, name);
    benchmark::RegisterBenchmark(("Scan/BSMC/" + name).c_str(), ScanBsmc, name)->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("Scan/CSR/" + name).c_str(), ScanCsr, name)->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("Matvec/BSMC/" + name).c_str(), Matvec, name, ProductPrecision::kDouble)
        ->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("Matvec/BSMC-mixed/" + name).c_str(), Matvec, name, ProductPrecision::kMixed)
        ->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("Matvec/CSR/" + name).c_str(), CsrMatvec, name)
        ->UseRealTime()->Unit(benchmark::kMicrosecond);
    benchmark::RegisterBenchmark(("PcgIteration/" + name).c_str(), PcgIteration, name)
        ->Arg(1)->Arg(2)->UseRealTime()->Unit(benchmark::kMillisecond);
  }
}

}  // namespace
}  // namespace dba

int main(int argc, char** argv) {
  benchmark::Initialize(&argc, argv);
  if (benchmark::ReportUnrecognizedArguments(argc, argv)) return 1;
  dba::Register();
  benchmark::RunSpecifiedBenchmarks();
  benchmark::Shutdown();
  return 0;
}
