// `kiln bench`: particle-steps per second on the benchmark pile of ../shared/BENCH.md.
#pragma once

namespace kiln {

struct BenchOptions {
  int columns = 20;        // 50 rows x columns discs: 20 -> 1,000, 200 -> 10,000
  long steps = 20000;      // timed steps after the warm-up
  bool flowing = false;    // gravity tilted 30 degrees toward +x
  bool quiet = false;
};

int run_bench(const BenchOptions& options);

}  // namespace kiln
