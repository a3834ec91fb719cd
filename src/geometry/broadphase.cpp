#include "src/geometry/broadphase.h"

#include "src/geometry/curve_order.h"

#include <algorithm>
#include <cmath>
#include <cstdint>

namespace kiln {

namespace {

double segment_distance(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double len2 = dot(ab, ab);
  const double s = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return norm(p - (a + s * ab));
}

}  // namespace

b2AABB Broadphase::box(double x0, double y0, double x1, double y1) const {
  b2AABB bb;
  bb.lowerBound.Set(static_cast<float>(x0 * scale_), static_cast<float>(y0 * scale_));
  bb.upperBound.Set(static_cast<float>(x1 * scale_), static_cast<float>(y1 * scale_));
  return bb;
}

// In the order a fill drew them (at random), Box2D's incremental tree grew boxes that spanned the
// scene, and each query of a sparse fill met a good part of the tree: the start check of 10^6
// discs took 150 s, growing as n^1.8.
void Broadphase::insert_along_curve(b2DynamicTree& tree, const double* x, const double* y, const double* r, int n,
                                    std::vector<int>& order, Progress* progress) const {
  std::vector<uint64_t> keys;
  hilbert_order(x, y, n, order, keys);
  for (int k = 0; k < n; ++k) {
    if (progress && k % 4096 == 0) progress->update_items(k, n, "discs in the tree");
    const int i = order[k];
    tree.CreateProxy(box(x[i] - r[i], y[i] - r[i], x[i] + r[i], y[i] + r[i]), as_user_data(i));
  }
}

void Broadphase::forget_particles() {
  for (int32 id : particle_proxy_) particles_.DestroyProxy(id);
  particle_proxy_.clear();
  anchor_pairs_.clear();
}

void Broadphase::particle_pairs(const double* x, const double* y, const double* r, int n, const PeriodicCell& cell,
                                std::vector<CandidatePair>& out) {
  // Keep the tree across rebuilds: a particle is re-inserted only when it has left its fat box,
  // its disc's box around its anchor widened by fat_margin per side (Box2D's own padding, a tenth
  // of a skin, would have re-inserted nearly every particle of a flowing pile at every rebuild).
  const double margin = fat_margin / scale_;
  auto fat_box = [&](int i) {
    const double reach = r[i] + margin;
    return box(anchor_x_[i] - reach, anchor_y_[i] - reach, anchor_x_[i] + reach, anchor_y_[i] + reach);
  };
  // Every particle counts as re-inserted when the tree is new, or the skin or the cell changed
  // (the kept pairs were found for those).
  const bool inserted = static_cast<int>(particle_proxy_.size()) != n;
  moved_.assign(n, inserted || skin_ != anchored_skin_ || !(cell == anchored_cell_));
  if (inserted) {
    forget_particles();
    anchor_x_.assign(x, x + n);
    anchor_y_.assign(y, y + n);
    // Along a Hilbert curve, as insert_along_curve says why (a run's particles are mostly in that
    // order already; a scene's first build, in a fill's, is not).
    std::vector<uint64_t> keys;
    hilbert_order(x, y, n, curve_, keys);
    particle_proxy_.resize(n);
    for (int i : curve_) particle_proxy_[i] = particles_.CreateProxy(fat_box(i), as_user_data(i));
  } else {
    for (int i = 0; i < n; ++i) {
      if (std::abs(x[i] - anchor_x_[i]) <= margin && std::abs(y[i] - anchor_y_[i]) <= margin) continue;
      anchor_x_[i] = x[i];
      anchor_y_[i] = y[i];
      particles_.MoveProxy(particle_proxy_[i], fat_box(i), b2Vec2(0, 0));
      moved_[i] = 1;
    }
  }
  anchored_skin_ = skin_;
  anchored_cell_ = cell;
  // The anchors' pairs: fat boxes that overlap a particle's anchor box widened by the skin, found
  // again only for the particles re-inserted; the others' anchors and boxes did not change. Each
  // position lies within a margin of its anchor, so a pair within the skin has anchors within the
  // skin and two margins: every pair within the skin is an anchors' pair.
  found_.clear();
  const double lx = cell.x ? cell.length_x() : 0, ly = cell.y ? cell.length_y() : 0;
  // In a periodic cell a particle near an edge also looks for neighbours around its images across
  // that edge, when any neighbour (the largest one included) could reach it there.
  const double largest = cell.any() && n > 0 ? *std::max_element(r, r + n) : 0.0;
  // A first build queries along the curve its tree was built on (neighbouring queries walk the same
  // nodes); a rebuild, the few re-inserted particles in their order.
  for (int k = 0; k < n; ++k) {
    const int i = inserted ? curve_[k] : k;
    if (!moved_[i]) continue;
    const size_t first = found_.size();
    const double ax = anchor_x_[i], ay = anchor_y_[i], reach = r[i] + skin_ + margin;
    // A pair of two re-inserted particles is taken from its first particle's query only.
    auto accept = [&](int j) {
      if (j > i)
        found_.push_back({i, j});
      else if (j < i && !moved_[j])
        found_.push_back({j, i});
    };
    // Across every edge the query could reach a fat box over: in a narrow cell, both edges of an
    // axis (one side only missed pairs of a small disc near a large one's far image).
    const double across = reach + margin + largest;
    double ox[3] = {0, 0, 0}, oy[3] = {0, 0, 0};
    int images_x = 1, images_y = 1;
    if (cell.x && ax - across < cell.x0) ox[images_x++] = lx;
    if (cell.x && ax + across >= cell.x1) ox[images_x++] = -lx;
    if (cell.y && ay - across < cell.y0) oy[images_y++] = ly;
    if (cell.y && ay + across >= cell.y1) oy[images_y++] = -ly;
    for (int ix = 0; ix < images_x; ++ix)
      for (int iy = 0; iy < images_y; ++iy)
        query(particles_, box(ax + ox[ix] - reach, ay + oy[iy] - reach, ax + ox[ix] + reach, ay + oy[iy] + reach),
              accept);
    std::sort(found_.begin() + first, found_.end());
    if (images_x * images_y > 1) found_.erase(std::unique(found_.begin() + first, found_.end()), found_.end());
  }
  // When every particle was queried the pairs come sorted (each query's own, in the order of their
  // first particles); else the few found from their second particle are out of place.
  if (!std::is_sorted(found_.begin(), found_.end())) std::sort(found_.begin(), found_.end());
  // The kept pairs (neither particle re-inserted) merged with the found ones, in place from the
  // back: no third list, whose capacity would stay as large as the anchors' pairs.
  const auto kept_end = std::remove_if(anchor_pairs_.begin(), anchor_pairs_.end(),
                                       [&](const CandidatePair& p) { return moved_[p.i] || moved_[p.j]; });
  const size_t kept = kept_end - anchor_pairs_.begin();
  if (inserted) std::vector<int>().swap(curve_);
  if (kept == 0) {  // every particle queried (the first build, a new skin): the found pairs are all
    anchor_pairs_.swap(found_);
    std::vector<CandidatePair>().swap(found_);  // a rebuild re-inserts a few: keep no large capacity
  } else {
    anchor_pairs_.resize(kept + found_.size());
    for (size_t to = anchor_pairs_.size(), a = kept, f = found_.size(); f > 0;)
      anchor_pairs_[--to] = a > 0 && found_[f - 1] < anchor_pairs_[a - 1] ? anchor_pairs_[--a] : found_[--f];
  }
  // The exact test, in double precision on the nearest images, without a branch on its outcome
  // (a sixth pass it, in no order a predictor follows): each pair is written and kept or not.
  out.clear();
  const size_t total = anchor_pairs_.size();
  constexpr size_t chunk = 256;
  CandidatePair kept_pairs[chunk];
  for (size_t begin = 0; begin < total; begin += chunk) {
    const size_t end = std::min(total, begin + chunk);
    size_t count = 0;
    for (size_t q = begin; q < end; ++q) {
      const CandidatePair p = anchor_pairs_[q];
      const Vec2 d = cell.minimum_image(x[p.j] - x[p.i], y[p.j] - y[p.i]);
      const double rr = r[p.i] + r[p.j] + skin_;
      kept_pairs[count] = p;
      count += d.x * d.x + d.y * d.y < rr * rr;
    }
    out.insert(out.end(), kept_pairs, kept_pairs + count);
  }
}

void Broadphase::wall_pairs(const double* x, const double* y, const double* r, int n, const std::vector<Vec2>& a,
                            const std::vector<Vec2>& b, const PeriodicCell& cell, std::vector<CandidatePair>& out) {
  // Walls may move between rebuilds: rebuild their (small) tree from the current geometry.
  for (int32 id : segment_proxy_) segments_.DestroyProxy(id);
  segment_proxy_.clear();
  // In a periodic cell each segment enters the tree shifted by whole periods to have its middle in
  // the cell: a wall driven along a periodic axis leaves the cell, and the particles' neighbouring
  // images must still find it.
  for (size_t s = 0; s < a.size(); ++s) {
    const Vec2 mid = 0.5 * (a[s] + b[s]), shift = cell.wrap(mid) - mid;
    segment_proxy_.push_back(segments_.CreateProxy(
        box(std::min(a[s].x, b[s].x) + shift.x, std::min(a[s].y, b[s].y) + shift.y,
            std::max(a[s].x, b[s].x) + shift.x, std::max(a[s].y, b[s].y) + shift.y),
        as_user_data(static_cast<int>(s))));
  }
  out.clear();
  // Periodic: the segments may reach out of the cell (a wall that translates along it), so every
  // neighbouring image of the particle is looked up; the exact test takes the image nearest the
  // segment's middle, as the contact does (DemSystem::wall_hit).
  const int kx = cell.x ? 1 : 0, ky = cell.y ? 1 : 0;
  const double lx = cell.x ? cell.length_x() : 0, ly = cell.y ? cell.length_y() : 0;
  for (int i = 0; i < n; ++i) {
    const size_t first = out.size();
    const double reach = r[i] + skin_;
    auto accept = [&](int s) {
      const Vec2 p = cell.image_near({x[i], y[i]}, 0.5 * (a[s] + b[s]));
      if (segment_distance(p, a[s], b[s]) < reach) out.push_back({i, s});
    };
    for (int ix = -kx; ix <= kx; ++ix)
      for (int iy = -ky; iy <= ky; ++iy) {
        const double cx = x[i] + ix * lx, cy = y[i] + iy * ly;
        query(segments_, box(cx - reach, cy - reach, cx + reach, cy + reach), accept);
      }
    std::sort(out.begin() + first, out.end());
    if (cell.any()) out.erase(std::unique(out.begin() + first, out.end()), out.end());
  }
}

}  // namespace kiln
