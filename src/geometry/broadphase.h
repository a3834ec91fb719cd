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
//
// The tree is kept across rebuilds, and so are the pairs it reported (a Verlet list of where the
// particles were inserted): a rebuild queries the tree only for the particles that left their fat
// boxes, and tests the kept pairs exactly again.
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
  // The particles were numbered anew: the next query inserts them all again.
  void forget_particles();
  // (particle, segment) pairs with distance(centre, segment) < r + skin, sorted.
  // In a periodic cell, the particle's images around it count too (walls need not lie in the cell).
  void wall_pairs(const double* x, const double* y, const double* r, int n, const std::vector<Vec2>& a,
                  const std::vector<Vec2>& b, const PeriodicCell& cell, std::vector<CandidatePair>& out);

 private:
  b2AABB box(double x0, double y0, double x1, double y1) const;
  // A particle's fat box: its disc's box around its anchor (where it was last inserted), widened
  // by this many base skins per side. Wider boxes keep more anchors' pairs, each tested exactly at
  // every rebuild (8 bytes each); narrower ones re-insert and query more particles. Chosen by
  // timing rebuilds of the flowing benchmark pile (README, Performance).
  static constexpr double fat_margin = 3.0;
  double skin_, scale_;
  b2DynamicTree particles_;
  std::vector<int32> particle_proxy_;
  std::vector<double> anchor_x_, anchor_y_;
  // The anchors' pairs (a Verlet list of the anchors, sorted): pairs whose anchors are within the
  // skin and two margins per axis, for the skin and cell they were found with. A rebuild queries
  // the tree for the re-inserted particles only and keeps the other pairs. (The radii are taken
  // to stay those of the first call while the number of particles does.)
  std::vector<CandidatePair> anchor_pairs_, found_;
  std::vector<char> moved_;
  double anchored_skin_ = -1;
  PeriodicCell anchored_cell_;
  std::vector<int32> segment_proxy_;
  b2DynamicTree segments_;
};

}  // namespace kiln
