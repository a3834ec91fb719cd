// The broadphase keeps its tree across rebuilds and re-inserts only particles that left their fat
// box: whatever the particles did in between, its candidate pairs must be exactly the pairs a
// brute-force search finds (gap below the skin), in a closed box and in a periodic cell, and far
// from the origin, where the float tree's coordinates are coarse.
#include <catch2/catch.hpp>

#include <cmath>
#include <random>
#include <vector>

#include "src/geometry/broadphase.h"

namespace {

using kiln::CandidatePair;
using kiln::PeriodicCell;

std::vector<CandidatePair> brute_force(const std::vector<double>& x, const std::vector<double>& y,
                                       const std::vector<double>& r, double skin, const PeriodicCell& cell) {
  std::vector<CandidatePair> pairs;
  const int n = static_cast<int>(x.size());
  for (int i = 0; i < n; ++i)
    for (int j = i + 1; j < n; ++j) {
      const kiln::Vec2 d = cell.minimum_image(x[j] - x[i], y[j] - y[i]);
      const double reach = r[i] + r[j] + skin;
      if (d.x * d.x + d.y * d.y < reach * reach) pairs.push_back({i, j});
    }
  return pairs;
}

// 400 discs of radii 1 to 1.5 mm in a 60 mm square at `origin`, moved 200 times by random steps of
// up to `stride` skins per axis (some steps leave the fat boxes, most do not); after each move the
// lists of a broadphase kept all along must equal the brute-force pairs.
void check_kept_tree(double origin, double stride, bool periodic) {
  const double skin = 0.4e-3, side = 0.06;
  PeriodicCell cell;
  if (periodic) {
    cell.x = cell.y = true;
    cell.x0 = cell.y0 = origin;
    cell.x1 = cell.y1 = origin + side;
  }
  std::mt19937 rng(7);
  std::uniform_real_distribution<double> u(0, 1);
  const int n = 400;
  std::vector<double> x(n), y(n), r(n);
  for (int i = 0; i < n; ++i) {
    x[i] = origin + side * u(rng);
    y[i] = origin + side * u(rng);
    r[i] = 1e-3 * (1 + 0.5 * u(rng));
  }
  kiln::Broadphase broadphase(skin);
  std::vector<CandidatePair> pairs;
  int found = 0;
  for (int move = 0; move < 200; ++move) {
    for (int i = 0; i < n; ++i) {
      x[i] += stride * skin * (2 * u(rng) - 1);
      y[i] += stride * skin * (2 * u(rng) - 1);
      if (periodic) {  // the tree sees each particle's place in the cell
        x[i] = origin + std::fmod(x[i] - origin + side, side);
        y[i] = origin + std::fmod(y[i] - origin + side, side);
      }
    }
    broadphase.particle_pairs(x.data(), y.data(), r.data(), n, cell, pairs);
    const std::vector<CandidatePair> expected = brute_force(x, y, r, skin, cell);
    REQUIRE(pairs == expected);
    found += static_cast<int>(pairs.size());
  }
  CHECK(found > 200 * n / 2);  // the discs are close enough to have neighbours to find
}

}  // namespace

TEST_CASE("broadphase kept across rebuilds finds exactly the pairs within the skin, box and periodic cell",
          "[broadphase]") {
  for (const bool periodic : {false, true}) {
    CAPTURE(periodic);
    check_kept_tree(0.0, 0.3, periodic);  // most moves stay inside the fat boxes
    check_kept_tree(0.0, 3.0, periodic);  // every move leaves them
  }
}

TEST_CASE("broadphase finds exactly the pairs within the skin far from the origin, where floats are coarse",
          "[broadphase]") {
  // 40 km from the origin the tree (one skin a unit) works at 1e8 units, where a float's spacing
  // is 8 units, more than a disc's box and the fat boxes' slack: only the monotone rounding and
  // Box2D's inclusive overlap test keep every pair (broadphase.h).
  check_kept_tree(4e4, 0.3, false);
  check_kept_tree(4e4, 3.0, true);
}
