#include "src/scene/particle_fill.h"

#include <algorithm>
#include <cmath>
#include <sstream>
#include <stdexcept>
#include <unordered_map>

#include "src/base/progress.h"
#include "src/scene/wall_geometry.h"

namespace kiln {

namespace {

// Uniform grid of cell size >= largest diameter: a disc overlaps only discs in the 3x3 cells.
class OverlapGrid {
 public:
  OverlapGrid(Vec2 lower, double cell) : lower_(lower), cell_(cell) {}
  void add(Vec2 p, double r) {
    const int id = static_cast<int>(pos_.size());
    pos_.push_back(p);
    rad_.push_back(r);
    cells_[key(cell_of(p.x - lower_.x), cell_of(p.y - lower_.y))].push_back(id);
  }
  bool overlaps(Vec2 p, double r) const {
    const long cx = cell_of(p.x - lower_.x), cy = cell_of(p.y - lower_.y);
    for (long dx = -1; dx <= 1; ++dx)
      for (long dy = -1; dy <= 1; ++dy) {
        const auto it = cells_.find(key(cx + dx, cy + dy));
        if (it == cells_.end()) continue;
        for (int j : it->second) {
          const Vec2 d = p - pos_[j];
          const double rr = r + rad_[j];
          if (dot(d, d) < rr * rr) return true;
        }
      }
    return false;
  }

 private:
  long cell_of(double u) const { return static_cast<long>(std::floor(u / cell_)); }
  static long long key(long cx, long cy) { return (static_cast<long long>(cx) << 32) ^ (cy & 0xffffffffLL); }
  Vec2 lower_;
  double cell_;
  std::vector<Vec2> pos_;
  std::vector<double> rad_;
  std::unordered_map<long long, std::vector<int>> cells_;
};

}  // namespace

bool Region::contains_disc(Vec2 c, double r) const {
  // Even-odd point-in-polygon, then the disc must clear every edge.
  bool inside = false;
  const size_t n = corners.size();
  for (size_t i = 0, j = n - 1; i < n; j = i++) {
    const Vec2 a = corners[i], b = corners[j];
    if ((a.y > c.y) != (b.y > c.y) && c.x < (b.x - a.x) * (c.y - a.y) / (b.y - a.y) + a.x) inside = !inside;
  }
  if (!inside) return false;
  for (size_t i = 0, j = n - 1; i < n; j = i++)
    if (distance_to_segment(c, corners[j], corners[i]) < r) return false;
  return true;
}

Vec2 Region::lower() const {
  Vec2 lo = corners.front();
  for (Vec2 p : corners) lo = {std::min(lo.x, p.x), std::min(lo.y, p.y)};
  return lo;
}

Vec2 Region::upper() const {
  Vec2 hi = corners.front();
  for (Vec2 p : corners) hi = {std::max(hi.x, p.x), std::max(hi.y, p.y)};
  return hi;
}

double Region::area() const {
  double twice = 0;
  for (size_t i = 0, j = corners.size() - 1; i < corners.size(); j = i++)
    twice += corners[j].x * corners[i].y - corners[i].x * corners[j].y;
  return std::abs(twice) / 2;
}

std::string fill_cannot_fit(const Region& region, long long count, const RadiusDistribution& radii) {
  const double r = radii.min, area = region.area();
  double perimeter = 0, turn = 0;
  bool convex = true;
  const size_t n = region.corners.size();
  for (size_t i = 0; i < n; ++i) {
    const Vec2 a = region.corners[i], b = region.corners[(i + 1) % n], c = region.corners[(i + 2) % n];
    perimeter += std::hypot(b.x - a.x, b.y - a.y);
    const double cross = (b.x - a.x) * (c.y - b.y) - (b.y - a.y) * (c.x - b.x);
    if (cross * turn < 0) convex = false;
    if (cross != 0) turn = cross;
  }
  // A polygon whose edges cross is filled even-odd (contains_disc), where the shoelace area
  // cancels lobes against each other: no bound from it.
  for (size_t i = 0; i < n; ++i)
    for (size_t j = i + 2; j < n; ++j) {
      if (i == 0 && j == n - 1) continue;  // adjacent through the closing edge
      const Vec2 a = region.corners[i], b = region.corners[(i + 1) % n], c = region.corners[j], d = region.corners[(j + 1) % n];
      auto side = [](Vec2 p, Vec2 q, Vec2 x) { return (q.x - p.x) * (x.y - p.y) - (q.y - p.y) * (x.x - p.x); };
      if (side(a, b, c) * side(a, b, d) < 0 && side(c, d, a) * side(c, d, b) < 0) return "";
    }
  const double most = convex ? area / (2 * std::sqrt(3.0) * r * r) + perimeter / (4 * r) + 1 : area / (M_PI * r * r);
  if (static_cast<double>(count) <= most) return "";
  std::ostringstream s;
  s.precision(4);
  s << count << (count == 1 ? " disc" : " discs") << " of radius " << (radii.min == radii.max ? "" : "at least ") << r << " m cannot fit in the "
    << (convex ? "convex " : "") << "region of " << area << " m^2: at most " << std::floor(most)
    << (convex ? " (Oler's bound for discs in a convex region)" : " (their area alone)")
    << "; enlarge the region or lower the count";
  return s.str();
}

Placement random_fill(const Region& region, int count, const RadiusDistribution& radii, uint64_t seed,
                      long attempts, const std::vector<Vec2>& existing_position,
                      const std::vector<double>& existing_radius) {
  Random rng(seed);
  double rmax = radii.max;
  for (double r : existing_radius) rmax = std::max(rmax, r);
  OverlapGrid grid(region.lower(), 2 * rmax);
  for (size_t i = 0; i < existing_radius.size(); ++i) grid.add(existing_position[i], existing_radius[i]);
  const Vec2 lo = region.lower(), hi = region.upper();
  Placement out;
  // A fill of millions takes a minute or more (`kiln check` said nothing meanwhile): shown on a
  // terminal.
  Progress progress("placing discs", count < progress_min_items);
  for (int k = 0; k < count; ++k) {
    if (k % 4096 == 0) progress.update_items(k, count, "discs");
    const double r = radii.draw(rng);
    bool placed = false;
    for (long attempt = 0; attempt < attempts && !placed; ++attempt) {
      const Vec2 p{rng.uniform(lo.x + r, hi.x - r), rng.uniform(lo.y + r, hi.y - r)};
      if (!region.contains_disc(p, r) || grid.overlaps(p, r)) continue;
      grid.add(p, r);
      out.position.push_back(p);
      out.radius.push_back(r);
      placed = true;
    }
    if (!placed) {
      progress.finish();
      throw std::runtime_error("placed only " + std::to_string(k) + " of " + std::to_string(count) +
                               " particles after " + std::to_string(attempts) +
                               " attempts for the next one: enlarge the region or lower the count");
    }
  }
  progress.finish();
  return out;
}

Placement lattice(bool hexagonal, Vec2 origin, double spacing, int rows, int columns,
                  const RadiusDistribution& radii, double jitter, uint64_t seed) {
  Random rng(seed);
  Placement out;
  const double row_height = hexagonal ? spacing * std::sqrt(3.0) / 2 : spacing;
  out.position.reserve(static_cast<size_t>(rows) * static_cast<size_t>(columns));  // counts checked by the caller
  out.radius.reserve(out.position.capacity());
  for (int row = 0; row < rows; ++row)
    for (int col = 0; col < columns; ++col) {
      Vec2 p{origin.x + spacing * (col + (hexagonal && row % 2 ? 0.5 : 0.0)), origin.y + row_height * row};
      if (jitter > 0) p = p + Vec2{rng.uniform(-jitter, jitter), rng.uniform(-jitter, jitter)};
      out.position.push_back(p);
      out.radius.push_back(radii.draw(rng));
    }
  return out;
}

}  // namespace kiln
