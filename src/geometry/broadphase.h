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

#include <algorithm>
#include <cstdint>
#include <type_traits>
#include <vector>

#include "src/base/progress.h"
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

  // One look at a state that may be anything a user wrote (the start check), where the lists
  // above could hold every pair of a million discs typed onto one point: calls visit(i, j) for
  // every pair i < j of discs within r_i + r_j + skin of each other (in a periodic cell, every
  // pair whose nearest images are; some pairs may be visited twice, once per image), keeping
  // nothing but a tree of its own, and stops at the first visit that returns false. Memory O(n);
  // time O(n log n) plus the candidates visited before it stops. `progress`, when given, is told
  // how many discs are in the tree (10^7 discs: a third of the time), then how many were queried.
  template <class Visit>
  void scan_particle_pairs(const double* x, const double* y, const double* r, int n, const PeriodicCell& cell,
                           Visit&& visit, Progress* progress = nullptr) const;

  // Calls fn(index) for every proxy of `tree` whose fat box overlaps `box`, with Box2D's
  // templated, non-virtual query; when fn returns bool, false ends the query. Returns false when
  // it was ended so.
  template <class F>
  static bool query(const b2DynamicTree& tree, const b2AABB& box, F& fn);
  static void* as_user_data(int index) { return reinterpret_cast<void*>(static_cast<intptr_t>(index)); }
  static int from_user_data(void* p) { return static_cast<int>(reinterpret_cast<intptr_t>(p)); }

 private:
  b2AABB box(double x0, double y0, double x1, double y1) const;
  // Every disc's box into `tree`, along a Hilbert curve (broadphase.cpp says why); `order` is that curve's.
  void insert_along_curve(b2DynamicTree& tree, const double* x, const double* y, const double* r, int n,
                          std::vector<int>& order, Progress* progress = nullptr) const;
  // A particle's fat box: its disc's box around its anchor (where it was last inserted), widened
  // by this many base skins per side. Wider boxes keep more anchors' pairs, each tested exactly at
  // every rebuild (8 bytes each); narrower ones re-insert and query more particles. Chosen by
  // timing rebuilds of the flowing benchmark pile (README, Performance).
  static constexpr double fat_margin = 3.0;
  double skin_, scale_;
  b2DynamicTree particles_;
  std::vector<int32> particle_proxy_;
  std::vector<int> curve_;  // a first build's insertion order (a Hilbert curve), freed after it
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

template <class F>
bool Broadphase::query(const b2DynamicTree& tree, const b2AABB& box, F& fn) {
  struct Callback {
    const b2DynamicTree* tree;
    F* fn;
    bool going = true;
    bool QueryCallback(int32 proxy_id) {
      if constexpr (std::is_same_v<decltype((*fn)(0)), bool>)
        going = (*fn)(from_user_data(tree->GetUserData(proxy_id)));
      else
        (*fn)(from_user_data(tree->GetUserData(proxy_id)));
      return going;
    }
  } callback{&tree, &fn};
  tree.Query(&callback, box);
  return callback.going;
}

template <class Visit>
void Broadphase::scan_particle_pairs(const double* x, const double* y, const double* r, int n,
                                     const PeriodicCell& cell, Visit&& visit, Progress* progress) const {
  b2DynamicTree tree;
  std::vector<int> order;  // queried along the curve too: neighbouring queries walk the same nodes
  insert_along_curve(tree, x, y, r, n, order, progress);
  if (progress) progress->next_stage();
  std::vector<int> rank(n);  // a pair is taken from the query of its first along the curve
  for (int k = 0; k < n; ++k) rank[order[k]] = k;
  const int kx = cell.x ? 1 : 0, ky = cell.y ? 1 : 0;
  const double lx = cell.x ? cell.length_x() : 0, ly = cell.y ? cell.length_y() : 0;
  for (int i : order) {
    if (progress && rank[i] % 4096 == 0) progress->update_items(rank[i], n, "discs queried");
    auto candidate = [&](int j) {
      if (rank[j] <= rank[i]) return true;
      const Vec2 d = cell.minimum_image(x[j] - x[i], y[j] - y[i]);
      const double reach = r[i] + r[j] + skin_;
      return d.x * d.x + d.y * d.y >= reach * reach || visit(std::min(i, j), std::max(i, j));
    };
    // Disc j within the skin of disc i has its box overlapping i's box widened by the skin.
    const double reach = r[i] + skin_;
    for (int ix = -kx; ix <= kx; ++ix)
      for (int iy = -ky; iy <= ky; ++iy) {
        const double cx = x[i] + ix * lx, cy = y[i] + iy * ly;
        if (!query(tree, box(cx - reach, cy - reach, cx + reach, cy + reach), candidate)) return;
      }
  }
}

}  // namespace kiln
