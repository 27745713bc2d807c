// How well this machine runs two threads at the moment: two loops with nothing to share
// between the threads, each timed on 1 and on 2 OpenMP threads in turns (1 2 2 1 ..., 20 rounds),
// so that ci/bench-dem.sh can print the machine's own 2-thread ratio next to the engines'.
//   compute: 12 independent multiply-add chains per thread (no memory traffic), fixed total work;
//   stream:  a sum over 32 MB of doubles (beyond the L2 of both cores), split between the threads.
// And what two threads that DO share pay, which those loops do not see (the fast engine's
// threads share the particles next to the cut between their ranges, and meet at barriers):
//   line:    one cache line bounced between the two threads, nanoseconds per round trip;
//   barrier: an OpenMP barrier of the two threads, microseconds.
// The round trip changes with where the two vCPUs sit, and with it the fast engine's 2-thread
// ratio (docs/machine.md "Two states of the VM").
// Prints one line: "scaling probe: compute <ratio> stream <ratio> line <ns> barrier <us>"
// (ratios: time on 1 thread / on 2). Built by ci/bench-dem.sh with `g++ -O2 -fopenmp`.
#include <omp.h>

#include <atomic>
#include <chrono>
#include <cstdio>
#include <vector>

namespace {

double chains(long iterations) {
  double a[12];
  for (int k = 0; k < 12; ++k) a[k] = 1.0 + 1e-3 * k;
  for (long i = 0; i < iterations; ++i) {
    for (int k = 0; k < 12; ++k) a[k] = a[k] * 0.9999999 + 1e-7;
  }
  double sum = 0.0;
  for (const double x : a) sum += x;
  return sum;
}

double stream(const std::vector<double>& data, int passes, int thread, int threads) {
  const std::size_t lo = data.size() * thread / threads, hi = data.size() * (thread + 1) / threads;
  double sum = 0.0;
  for (int p = 0; p < passes; ++p) {
    for (std::size_t i = lo; i < hi; ++i) sum += data[i];
  }
  return sum;
}

/// Nanoseconds per round trip of one cache line between two threads: thread 0 writes an odd
/// value and waits for the next even one, thread 1 the reverse.
double line_round_trip(long rounds) {
  alignas(64) std::atomic<long> flag{0};
  double seconds = 0.0;
#pragma omp parallel num_threads(2)
  {
    const int me = omp_get_thread_num();
#pragma omp barrier
    const auto t0 = std::chrono::steady_clock::now();
    for (long r = 0; r < rounds; ++r) {
      if (me == 0) {
        flag.store(2 * r + 1, std::memory_order_release);
        while (flag.load(std::memory_order_acquire) != 2 * r + 2) {
        }
      } else {
        while (flag.load(std::memory_order_acquire) != 2 * r + 1) {
        }
        flag.store(2 * r + 2, std::memory_order_release);
      }
    }
    if (me == 0) seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count();
  }
  return 1e9 * seconds / static_cast<double>(rounds);
}

/// Microseconds per OpenMP barrier of two threads.
double barrier_time(long rounds) {
  const auto t0 = std::chrono::steady_clock::now();
#pragma omp parallel num_threads(2)
  for (long r = 0; r < rounds; ++r) {
#pragma omp barrier
  }
  return 1e6 * std::chrono::duration<double>(std::chrono::steady_clock::now() - t0).count() / static_cast<double>(rounds);
}

}  // namespace

int main() {
  const std::vector<double> data(std::size_t{1} << 22, 1.0);  // 32 MB
  double seconds[2][2] = {};  // [loop][threads - 1]
  double sink = 0.0;
  for (int round = 0; round < 20; ++round) {
    for (int k = 0; k < 2; ++k) {
      const int threads = (round % 2 == 0 ? k : 1 - k) + 1;
      const auto t0 = std::chrono::steady_clock::now();
#pragma omp parallel num_threads(threads) reduction(+ : sink)
      sink += chains(20000000 / threads);
      const auto t1 = std::chrono::steady_clock::now();
#pragma omp parallel num_threads(threads) reduction(+ : sink)
      sink += stream(data, 10, omp_get_thread_num(), threads);
      const auto t2 = std::chrono::steady_clock::now();
      seconds[0][threads - 1] += std::chrono::duration<double>(t1 - t0).count();
      seconds[1][threads - 1] += std::chrono::duration<double>(t2 - t1).count();
    }
  }
  const double line_ns = line_round_trip(100000);
  const double barrier_us = barrier_time(100000);
  std::printf("scaling probe: compute %.3f stream %.3f line %.0f ns barrier %.2f us (checksum %.6g)\n",
              seconds[0][0] / seconds[0][1], seconds[1][0] / seconds[1][1], line_ns, barrier_us, sink);
  return 0;
}
