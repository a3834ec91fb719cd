// Candidate pairs from Box2D's dynamic AABB tree.
//
// Box2D 2.4.1's tree is float and pads every fat box by a fixed 0.1 length units
// (b2_aabbExtension), tuned for bodies of 0.1-10 units. kiln's grains are millimetres in metres,
// so the tree works in scaled units: one skin is one tree unit, which makes Box2D's padding a
// tenth of a skin (extra candidates only, removed by the exact test). Boxes are rounded to the
// nearest float: rounding is monotone and Box2D's overlap test counts touching boxes (its float
// differences keep their sign), so boxes that overlap in double precision still overlap in the
// tree and the tree can only report too many candidates, never too few (tests/geometry: at 40 km
// from the origin, where a float's spacing is 8 tree units). Every candidate is then checked in
// double precision: a pair is kept when its gap is below the skin.
#pragma once
#include <box2d/b2_dynamic_tree.h>

#include <cstdint>
#include <vector>

#include "src/geometry/periodic_cell.h"
#include "src/base/vec2.h"

namespace kiln {

struct CandidatePair {
  int i, j;  // particle pairs: i < j; wall pairs: particle i, segment j
  bool operator<(const CandidatePair& o) const { return i < o.i || (i == o.i && j < o.j); }
  bool operator==(const CandidatePair& o) const { return i == o.i && j == o.j; }
};

class Broadphase {
 public:
  explicit Broadphase(double skin) : skin_(skin), scale_(1.0 / skin) {}
  double skin() const { return skin_; }
  // A wider skin for the next queries (a step longer than the base skin covers); the tree keeps
  // its units, so Box2D's padding stays a tenth of the base skin.
  void set_skin(double skin) { skin_ = skin; }

  // Particle pairs with |x_i - x_j| < r_i + r_j + skin (nearest images in a periodic cell, whose
  // positions must lie in the cell and whose periods exceed twice that reach), sorted by (i, j).
  void particle_pairs(const double* x, const double* y, const double* r, int n, const PeriodicCell& cell,
                      std::vector<CandidatePair>& out);
  // (particle, segment) pairs with distance(centre, segment) < r + skin, sorted.
  // In a periodic cell, the particle's images around it count too (walls need not lie in the cell).
  void wall_pairs(const double* x, const double* y, const double* r, int n, const std::vector<Vec2>& a,
                  const std::vector<Vec2>& b, const PeriodicCell& cell, std::vector<CandidatePair>& out);

 private:
  b2AABB box(double x0, double y0, double x1, double y1) const;
  // A particle's fat box: its disc's box around its anchor (where it was last inserted), widened
  // by this many base skins per side. Wider boxes report more candidates to the exact test (the
  // lists do not change); narrower ones re-insert more particles. Chosen by timing rebuilds of the
  // flowing benchmark pile (README, Performance).
  static constexpr double fat_margin = 1.0;
  double skin_, scale_;
  b2DynamicTree particles_;
  std::vector<int32> particle_proxy_;
  std::vector<double> anchor_x_, anchor_y_;
  std::vector<int32> segment_proxy_;
  b2DynamicTree segments_;
};

}  // namespace kiln
