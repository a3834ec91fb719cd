#include "src/geometry/broadphase.h"

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

void* as_user_data(int index) { return reinterpret_cast<void*>(static_cast<intptr_t>(index)); }
int from_user_data(void* p) { return static_cast<int>(reinterpret_cast<intptr_t>(p)); }

// Calls fn(index) for every proxy whose fat box overlaps `box` (Box2D's templated, non-virtual query).
template <class F>
void query(const b2DynamicTree& tree, const b2AABB& box, F& fn) {
  struct Callback {
    const b2DynamicTree* tree;
    F* fn;
    bool QueryCallback(int32 proxy_id) {
      (*fn)(from_user_data(tree->GetUserData(proxy_id)));
      return true;
    }
  } callback{&tree, &fn};
  tree.Query(&callback, box);
}

}  // namespace

b2AABB Broadphase::box(double x0, double y0, double x1, double y1) const {
  b2AABB bb;
  bb.lowerBound.Set(static_cast<float>(x0 * scale_), static_cast<float>(y0 * scale_));
  bb.upperBound.Set(static_cast<float>(x1 * scale_), static_cast<float>(y1 * scale_));
  return bb;
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
  if (static_cast<int>(particle_proxy_.size()) != n) {
    for (int32 id : particle_proxy_) particles_.DestroyProxy(id);
    particle_proxy_.clear();
    anchor_x_.assign(x, x + n);
    anchor_y_.assign(y, y + n);
    for (int i = 0; i < n; ++i) particle_proxy_.push_back(particles_.CreateProxy(fat_box(i), as_user_data(i)));
  } else {
    for (int i = 0; i < n; ++i) {
      if (std::abs(x[i] - anchor_x_[i]) <= margin && std::abs(y[i] - anchor_y_[i]) <= margin) continue;
      anchor_x_[i] = x[i];
      anchor_y_[i] = y[i];
      particles_.MoveProxy(particle_proxy_[i], fat_box(i), b2Vec2(0, 0));
    }
  }
  out.clear();
  // In a periodic cell a particle near an edge also looks for neighbours around its images
  // across that edge; the exact test takes the nearest images.
  const double lx = cell.x ? cell.length_x() : 0, ly = cell.y ? cell.length_y() : 0;
  // A pair is kept from its first particle's query only: that particle looks across an edge when
  // any neighbour (the largest one included) could reach it there.
  const double largest = cell.any() && n > 0 ? *std::max_element(r, r + n) : 0.0;
  for (int i = 0; i < n; ++i) {
    const size_t first = out.size();
    const double reach = r[i] + skin_;
    auto accept = [&](int j) {
      if (j <= i) return;
      const Vec2 d = cell.minimum_image(x[j] - x[i], y[j] - y[i]);
      const double rr = r[i] + r[j] + skin_;
      if (d.x * d.x + d.y * d.y < rr * rr) out.push_back({i, j});
    };
    const double across = reach + largest;
    const int sx = cell.x ? (x[i] - across < cell.x0 ? 1 : x[i] + across >= cell.x1 ? -1 : 0) : 0;
    const int sy = cell.y ? (y[i] - across < cell.y0 ? 1 : y[i] + across >= cell.y1 ? -1 : 0) : 0;
    for (int ix = 0; ix <= (sx != 0); ++ix)
      for (int iy = 0; iy <= (sy != 0); ++iy) {
        const double ox = ix * sx * lx, oy = iy * sy * ly;
        query(particles_, box(x[i] + ox - reach, y[i] + oy - reach, x[i] + ox + reach, y[i] + oy + reach), accept);
      }
    std::sort(out.begin() + first, out.end());
    if (sx || sy) out.erase(std::unique(out.begin() + first, out.end()), out.end());
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
