#include "src/scene/wall_geometry.h"

#include <algorithm>
#include <cmath>

namespace kiln {

void add_polyline(std::vector<Segment>& out, const std::vector<Vec2>& points, bool closed, int wall) {
  const int first = static_cast<int>(out.size());
  const int n = static_cast<int>(points.size());
  const int count = closed ? n : n - 1;
  for (int k = 0; k < count; ++k) {
    Segment s;
    s.a = points[k];
    s.b = points[(k + 1) % n];
    s.wall = wall;
    s.prev = k > 0 ? first + k - 1 : (closed ? first + count - 1 : -1);
    s.next_shared = k + 1 < count || closed;
    out.push_back(s);
  }
}

std::vector<Vec2> arc_points(Vec2 centre, double radius, double from, double to, double tolerance) {
  const double span = to - from;
  // Largest chord angle whose sagitta stays within the tolerance.
  const double max_step = 2 * std::acos(std::max(-1.0, 1 - tolerance / radius));
  const int pieces = std::max(1, static_cast<int>(std::ceil(std::abs(span) / max_step)));
  std::vector<Vec2> pts;
  for (int k = 0; k <= pieces; ++k) {
    const double phi = from + span * k / pieces;
    pts.push_back(centre + Vec2{radius * std::cos(phi), radius * std::sin(phi)});
  }
  return pts;
}

}  // namespace kiln
