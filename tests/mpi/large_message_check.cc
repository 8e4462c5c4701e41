// A message over 1 GiB through Communicator, under `mpirun -np 2`: MPI counts
// are int, so Communicator splits every transfer into chunks of at most 2^30
// bytes. Rank 0 sends rank 1 a vector of 2^30 + 4,099 bytes and broadcasts
// another of 2^30 + 3 bytes; both ranks check every byte and the traffic
// counted. Exit status 0 only when both ranks saw the right bytes.
#include <cstdint>
#include <cstdio>
#include <vector>

#include "dba/cluster/communicator.h"

namespace {

// A byte pattern that a chunk sent twice, dropped or misplaced would break.
uint8_t PatternByte(uint64_t i, uint64_t seed) {
  const uint64_t x = (i + seed) * 0x9E3779B97F4A7C15ull;
  return static_cast<uint8_t>(x >> 56);
}

std::vector<uint8_t> Pattern(uint64_t n, uint64_t seed) {
  std::vector<uint8_t> v(n);
  for (uint64_t i = 0; i < n; ++i) v[i] = PatternByte(i, seed);
  return v;
}

// The first index where v differs from the pattern, or v.size().
uint64_t FirstMismatch(const std::vector<uint8_t>& v, uint64_t seed) {
  for (uint64_t i = 0; i < v.size(); ++i) {
    if (v[i] != PatternByte(i, seed)) return i;
  }
  return v.size();
}

}  // namespace

int main(int argc, char** argv) {
  dba::Communicator comm(&argc, &argv);
  if (comm.size() != 2) {
    std::fprintf(stderr, "large_message_check: run under mpirun -np 2 (size %d)\n", comm.size());
    return 2;
  }
  constexpr uint64_t kPointToPoint = (uint64_t{1} << 30) + 4099;
  constexpr uint64_t kBroadcast = (uint64_t{1} << 30) + 3;
  int failures = 0;

  // Point to point, with the length in front (SendVector/RecvVector).
  if (comm.rank() == 0) {
    comm.SendVector(1, dba::Traffic::kDistribution, Pattern(kPointToPoint, 1));
  } else {
    const std::vector<uint8_t> got = comm.RecvVector<uint8_t>(0, dba::Traffic::kDistribution);
    if (got.size() != kPointToPoint) {
      std::fprintf(stderr, "rank 1: received %llu bytes, expected %llu\n",
                   static_cast<unsigned long long>(got.size()),
                   static_cast<unsigned long long>(kPointToPoint));
      ++failures;
    } else if (const uint64_t i = FirstMismatch(got, 1); i != got.size()) {
      std::fprintf(stderr, "rank 1: point-to-point byte %llu wrong\n",
                   static_cast<unsigned long long>(i));
      ++failures;
    }
  }
  const int64_t expected_p2p = static_cast<int64_t>(kPointToPoint + sizeof(uint64_t));
  if (comm.stats().bytes[static_cast<int>(dba::Traffic::kDistribution)] != expected_p2p) {
    std::fprintf(stderr, "rank %d: counted %lld point-to-point bytes, expected %lld\n", comm.rank(),
                 static_cast<long long>(comm.stats().bytes[0]), static_cast<long long>(expected_p2p));
    ++failures;
  }

  // Broadcast from rank 0.
  {
    std::vector<uint8_t> v = comm.rank() == 0 ? Pattern(kBroadcast, 2) : std::vector<uint8_t>(kBroadcast);
    comm.Broadcast(dba::Traffic::kResult, std::span<uint8_t>(v));
    if (const uint64_t i = FirstMismatch(v, 2); i != v.size()) {
      std::fprintf(stderr, "rank %d: broadcast byte %llu wrong\n", comm.rank(),
                   static_cast<unsigned long long>(i));
      ++failures;
    }
    if (comm.stats().bytes[static_cast<int>(dba::Traffic::kResult)] != static_cast<int64_t>(kBroadcast)) {
      std::fprintf(stderr, "rank %d: counted %lld broadcast bytes, expected %llu\n", comm.rank(),
                   static_cast<long long>(comm.stats().bytes[static_cast<int>(dba::Traffic::kResult)]),
                   static_cast<unsigned long long>(kBroadcast));
      ++failures;
    }
  }

  // Every rank's verdict at rank 0.
  const double mine = failures;
  const std::vector<double> all = comm.Gather(dba::Traffic::kControl, std::span<const double>(&mine, 1));
  if (comm.rank() == 0) {
    const bool ok = all.size() == 2 && all[0] == 0 && all[1] == 0;
    std::printf("large_message_check: %s (%llu bytes point to point, %llu broadcast)\n",
                ok ? "ok" : "FAILED", static_cast<unsigned long long>(kPointToPoint),
                static_cast<unsigned long long>(kBroadcast));
    return ok ? 0 : 1;
  }
  return failures == 0 ? 0 : 1;
}
