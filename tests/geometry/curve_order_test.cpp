// The Hilbert curve that orders the contact loop's particles (src/geometry/curve_order.h): it
// visits every cell once, each step to a neighbouring cell, and ranks a scattered set of places so
// that places close in space are close in rank.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <random>
#include <vector>

#include "src/geometry/curve_order.h"

namespace kiln {

TEST_CASE("the Hilbert curve fills the corner square of 4^k cells in its first 4^k steps, each to a neighbour",
          "[curve]") {
  // A curve of 2^15 cells a side starts in a corner and has filled the 2^k square there after
  // 4^k steps, for every k: the 64 x 64 corner holds exactly the indices 0 to 4,095.
  constexpr int side = 64;
  std::vector<int> cell_x(side * side, -1), cell_y(side * side, -1);
  for (int x = 0; x < side; ++x)
    for (int y = 0; y < side; ++y) {
      const uint32_t d = hilbert_index(x, y);
      REQUIRE(d < static_cast<uint32_t>(side * side));
      REQUIRE(cell_x[d] < 0);  // no index twice
      cell_x[d] = x;
      cell_y[d] = y;
    }
  for (int d = 1; d < side * side; ++d)
    CHECK(std::abs(cell_x[d] - cell_x[d - 1]) + std::abs(cell_y[d] - cell_y[d - 1]) == 1);
  // And the last cell of the whole grid is the corner next to the start, as the curve ends.
  CHECK(hilbert_index((1u << hilbert_bits) - 1, 0) == (1ull << (2 * hilbert_bits)) - 1);
}

TEST_CASE("places ranked along the curve have their neighbours within a few ranks; numbered at random, not",
          "[curve]") {
  // 40,000 discs' centres on a jittered square lattice, numbered at random: pairs of lattice
  // neighbours are nearly all far apart in index, and ranked along the curve nearly all close.
  constexpr int side = 200, n = side * side;
  std::mt19937 random(5);
  std::uniform_real_distribution<double> jitter(-0.1, 0.1);
  std::vector<int> label(n);
  for (int k = 0; k < n; ++k) label[k] = k;
  std::shuffle(label.begin(), label.end(), random);
  std::vector<double> x(n), y(n);
  for (int row = 0; row < side; ++row)
    for (int col = 0; col < side; ++col) {
      x[label[row * side + col]] = col + jitter(random);
      y[label[row * side + col]] = row + jitter(random);
    }
  std::vector<CandidatePair> by_index, by_rank;
  std::vector<int> order, keys_rank(n);
  std::vector<uint64_t> keys;
  hilbert_order(x.data(), y.data(), n, order, keys);
  std::vector<bool> seen(n, false);
  for (int r = 0; r < n; ++r) {
    REQUIRE(!seen[order[r]]);  // a permutation
    seen[order[r]] = true;
    keys_rank[order[r]] = r;
  }
  for (int row = 0; row < side; ++row)
    for (int col = 0; col + 1 < side; ++col) {
      const int a = label[row * side + col], b = label[row * side + col + 1], c = label[col * side + row],
                d = label[(col + 1) * side + row];
      by_index.push_back({a, b});
      by_index.push_back({c, d});
      by_rank.push_back({keys_rank[a], keys_rank[b]});
      by_rank.push_back({keys_rank[c], keys_rank[d]});
    }
  // Two indices drawn at random out of n are more than w apart with probability (1 - w/n)^2:
  // 0.806 here, give or take 0.003 over 79,600 pairs.
  CHECK(share_apart(by_index, 4096) == Approx(0.806).margin(0.01));
  CHECK(share_apart(by_rank, 4096) < 0.02);
  CHECK(share_apart(by_rank, 256) < 0.1);
}

}  // namespace kiln
