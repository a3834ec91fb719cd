// The broadphase keeps its tree across rebuilds and re-inserts only particles that left their fat
// box: whatever the particles did in between, its candidate pairs must be exactly the pairs a
// brute-force search finds (gap below the skin), in a closed box and in a periodic cell, and far
// from the origin, where the float tree's coordinates are coarse.
#include <catch2/catch.hpp>

#include <algorithm>
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

// `n` discs of radii 1 to 1.5 mm in a square of `side` at `origin`, moved 200 times by random steps
// of up to `stride` skins per axis (some steps leave the fat boxes, most do not), the skin widened
// 2.5 times for ten moves in every fifty; after each move the lists of a broadphase kept all
// along must equal the brute-force pairs.
void check_kept_tree(double origin, double stride, bool periodic, double side = 0.06, int n = 400,
                     unsigned seed = 7) {
  const double skin = 0.4e-3;
  PeriodicCell cell;
  if (periodic) {
    cell.x = cell.y = true;
    cell.x0 = cell.y0 = origin;
    cell.x1 = cell.y1 = origin + side;
  }
  std::mt19937 rng(seed);
  std::uniform_real_distribution<double> u(0, 1);
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
    // A step longer than the base skin covers widens the skin for a while (DemSystem::rebuild).
    const double wide = move % 50 >= 40 ? 2.5 * skin : skin;
    broadphase.set_skin(wide);
    broadphase.particle_pairs(x.data(), y.data(), r.data(), n, cell, pairs);
    const std::vector<CandidatePair> expected = brute_force(x, y, r, wide, cell);
    REQUIRE(pairs == expected);
    found += static_cast<int>(pairs.size());
  }
  CHECK(found > 200 * n / 4);  // the discs are close enough to have neighbours to find
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

TEST_CASE("broadphase finds the pairs across both edges of a narrow periodic cell", "[broadphase]") {
  // A 1 mm disc at x = 5.39 mm and a 0.9 mm one at 0.01 mm in a cell 8 mm long (eight largest
  // radii, the narrowest the scene reader accepts), the skin widened to 1 mm: their nearest images
  // are 2.62 mm apart, within 1 + 0.9 + 1 mm. The first disc's query reaches both edges; looking
  // across the lower one only, the pair was missed.
  PeriodicCell cell;
  cell.x = true;
  cell.x1 = 8e-3;
  const std::vector<double> x{5.39e-3, 0.01e-3}, y{0, 0}, r{1e-3, 0.9e-3};
  kiln::Broadphase broadphase(0.4e-3);
  broadphase.set_skin(1e-3);
  std::vector<CandidatePair> pairs;
  broadphase.particle_pairs(x.data(), y.data(), r.data(), 2, cell, pairs);
  REQUIRE(pairs == std::vector<CandidatePair>{{0, 1}});
  // Ten discs in cells of 9.5 mm, many seeds: the kept pairs near both edges of both axes.
  for (unsigned seed = 1; seed <= 100; ++seed) {
    CAPTURE(seed);
    check_kept_tree(0.0, 0.3, true, 9.5e-3, 10, seed);
  }
}

TEST_CASE("broadphase finds its pairs again when the periodic cell changes", "[broadphase]") {
  // Two discs 8 mm apart along x: no pair in a 30 mm cell, a pair across the edge of a 10 mm one,
  // though neither disc moved (the kept pairs were found for the first cell).
  PeriodicCell wide, narrow;
  wide.x = narrow.x = true;
  wide.x1 = 0.03;
  narrow.x1 = 0.01;
  const std::vector<double> x{0.5e-3, 8.5e-3}, y{0, 0}, r{1e-3, 1e-3};
  kiln::Broadphase broadphase(0.4e-3);
  std::vector<CandidatePair> pairs;
  broadphase.particle_pairs(x.data(), y.data(), r.data(), 2, wide, pairs);
  CHECK(pairs.empty());
  broadphase.particle_pairs(x.data(), y.data(), r.data(), 2, narrow, pairs);
  REQUIRE(pairs == std::vector<CandidatePair>{{0, 1}});
}

TEST_CASE("a scan of a state visits every pair within the skin, box and periodic cell, near and far from the origin",
          "[broadphase]") {
  // The start check's scan (its own tree, nothing kept): the distinct pairs it visits must be the
  // brute-force pairs, in a closed box, a periodic cell, a narrow one and 40 km out.
  struct Setup {
    double origin, side;
    bool periodic;
    int n;
  };
  for (const Setup s : {Setup{0, 0.06, false, 400}, Setup{0, 0.06, true, 400}, Setup{0, 9.5e-3, true, 10},
                        Setup{4e4, 0.06, true, 400}}) {
    CAPTURE(s.origin, s.side, s.periodic);
    PeriodicCell cell;
    if (s.periodic) {
      cell.x = cell.y = true;
      cell.x0 = cell.y0 = s.origin;
      cell.x1 = cell.y1 = s.origin + s.side;
    }
    for (unsigned seed = 1; seed <= 20; ++seed) {
      std::mt19937 rng(seed);
      std::uniform_real_distribution<double> u(0, 1);
      std::vector<double> x(s.n), y(s.n), r(s.n);
      for (int i = 0; i < s.n; ++i) {
        x[i] = s.origin + s.side * u(rng);
        y[i] = s.origin + s.side * u(rng);
        r[i] = 1e-3 * (1 + 0.5 * u(rng));
      }
      const double skin = 1e-3;
      std::vector<CandidatePair> visited;
      kiln::Broadphase(skin).scan_particle_pairs(x.data(), y.data(), r.data(), s.n, cell, [&](int i, int j) {
        visited.push_back({i, j});
        return true;
      });
      std::sort(visited.begin(), visited.end());
      visited.erase(std::unique(visited.begin(), visited.end()), visited.end());
      REQUIRE(visited == brute_force(x, y, r, skin, cell));
    }
  }
}

TEST_CASE("a scan stops at the first visit that refuses: a million discs on one point cost one visit",
          "[broadphase]") {
  // What a typed lattice spacing of 1e-9 m or a repeated CSV row gives: every pair within reach.
  // Listed, these are 5e11 pairs; scanned, the first visit ends it.
  const int n = 1000000;
  const std::vector<double> x(n, 0.0), y(n, 0.0), r(n, 1e-3);
  int visits = 0;
  kiln::Broadphase(1e-6).scan_particle_pairs(x.data(), y.data(), r.data(), n, PeriodicCell{}, [&](int, int) {
    ++visits;
    return false;
  });
  CHECK(visits == 1);
}
