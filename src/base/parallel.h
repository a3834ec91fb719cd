// Threads (OpenMP) whose results do not depend on how many there are. Loops that write one entry
// per index are split freely; sums are taken over fixed blocks of indices, each block summed in
// order by whichever thread has it and the blocks' sums added in order, so the bits of a sum are
// those of one thread's. Without OpenMP the pragmas are ignored and everything runs in order.
#pragma once
#include <algorithm>
#include <array>
#include <vector>
#ifdef _OPENMP
#include <omp.h>
#endif

namespace kiln {

// Indices per block of a sum: a block's work (a few microseconds) dwarfs a thread's start.
inline constexpr int sum_block = 1024;
inline int block_count(int n) { return (n + sum_block - 1) / sum_block; }
// Whether a loop over n items is worth the threads: below this a parallel region's start and
// join (a few microseconds) cost more than the loop (two discs bouncing take 10^6 steps).
inline bool parallel_worthwhile(long n) { return n >= 8192; }
// The threads a parallel region may have.
inline int thread_limit() {
#ifdef _OPENMP
  return omp_get_max_threads();
#else
  return 1;
#endif
}
// Whether a loop over n items runs on more than one thread.
inline bool runs_threaded(long n) { return parallel_worthwhile(n) && thread_limit() > 1; }

// K sums over [0, n) in fixed blocks: block(begin, end, out) adds the terms of indices
// [begin, end) to out[0..K), in order. `partial` is the caller's scratch (sized here; no
// allocation once it is large enough).
template <int K, class Block>
std::array<double, K> fixed_order_sums(int n, std::vector<std::array<double, K>>& partial, Block block) {
  const int blocks = block_count(n);
  partial.resize(blocks);
#pragma omp parallel for schedule(static) if (parallel_worthwhile(n))
  for (int b = 0; b < blocks; ++b) {
    std::array<double, K> sum{};
    block(b * sum_block, std::min(n, (b + 1) * sum_block), sum.data());
    partial[b] = sum;
  }
  std::array<double, K> total{};
  for (int b = 0; b < blocks; ++b)
    for (int c = 0; c < K; ++c) total[c] += partial[b][c];
  return total;
}

// sum_k a[k] b[k] over [begin, end), added to out. Four partial sums (indices by their remainder
// mod 4 from begin, added pairwise at the end): one running sum waits for each addition before the
// next (four cycles an element), four in flight fill the adder, and the order stays fixed.
inline void add_dot(const double* a, const double* b, int begin, int end, double& out) {
  double s0 = 0, s1 = 0, s2 = 0, s3 = 0;
  int k = begin;
  for (; k + 3 < end; k += 4) {
    s0 += a[k] * b[k];
    s1 += a[k + 1] * b[k + 1];
    s2 += a[k + 2] * b[k + 2];
    s3 += a[k + 3] * b[k + 3];
  }
  for (; k < end; ++k) s0 += a[k] * b[k];
  out += (s0 + s1) + (s2 + s3);
}

}  // namespace kiln
