// Initial particle placement: random non-overlapping fill of a region, and lattices.
// Deterministic for a given seed on every platform (own integer-to-double conversion).
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "src/base/vec2.h"

namespace kiln {

// Splittable, portable random numbers (SplitMix64): the same sequence everywhere.
class Random {
 public:
  explicit Random(uint64_t seed) : state_(seed) {}
  uint64_t next() {
    uint64_t z = (state_ += 0x9E3779B97F4A7C15ull);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9ull;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBull;
    return z ^ (z >> 31);
  }
  double uniform() { return static_cast<double>(next() >> 11) * 0x1.0p-53; }  // [0, 1)
  double uniform(double lo, double hi) { return lo + (hi - lo) * uniform(); }

 private:
  uint64_t state_;
};

// The seed of ensemble member `member` (src/scene/scene.h) for a seed a scene declares: the
// seed itself for member 0, otherwise a SplitMix64 draw from the two, so that members differ in
// every stream and no two (seed, member) pairs of a scene share one by an offset.
inline uint64_t ensemble_seed(uint64_t seed, long long member) {
  return member == 0 ? seed : Random(seed ^ (static_cast<uint64_t>(member) * 0xD1B54A32D192ED03ull)).next();
}

struct RadiusDistribution {
  bool random() const { return min != max; }
  double min = 0, max = 0;  // uniform in [min, max]; min == max for one size
  double draw(Random& rng) const { return min == max ? min : rng.uniform(min, max); }
};

// A polygon region (counter-clockwise or clockwise); a rectangle is a polygon of four corners.
struct Region {
  std::vector<Vec2> corners;
  bool contains_disc(Vec2 centre, double radius) const;
  Vec2 lower() const;
  Vec2 upper() const;
  double area() const;  // m^2 (shoelace formula; a self-crossing polygon counts its loops' net area)
};

// Why `count` discs with radii in [radii.min, radii.max] cannot fit in `region`, or "" when its
// size alone does not rule them out. Shrunk to radius r_min about their centres, discs that fit
// still fit: their centres lie at least r_min inside the region and 2 r_min apart. In a convex
// region of area A and perimeter P that allows at most A / (2 sqrt 3 r_min^2) + P / (4 r_min) + 1
// of them (N. Oler, "An inequality in the geometry of numbers", Acta Math. 105, 1961: at most
// 2/sqrt 3 A' + P'/2 + 1 points a unit apart in a convex A', P'); in any other, pi r_min^2 each
// must not exceed A.
std::string fill_cannot_fit(const Region& region, long long count, const RadiusDistribution& radii);

struct Placement {
  std::vector<Vec2> position;
  std::vector<double> radius;
};

// Random sequential addition: draw a radius, then try up to `attempts` random centres inside
// the region that overlap no placed disc (nor `existing` ones). Fails with a message if `count`
// discs cannot be placed.
Placement random_fill(const Region& region, int count, const RadiusDistribution& radii, uint64_t seed,
                      long attempts, const std::vector<Vec2>& existing_position,
                      const std::vector<double>& existing_radius);

// Rows x columns lattice from `origin` (lower-left centre). Hexagonal rows are offset by half a
// spacing and spaced spacing*sqrt(3)/2 apart. `jitter` moves each centre uniformly by up to that
// distance in x and y.
Placement lattice(bool hexagonal, Vec2 origin, double spacing, int rows, int columns,
                  const RadiusDistribution& radii, double jitter, uint64_t seed);

}  // namespace kiln
