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

namespace {
double travel_time(const WallMotion& m) {
  const double speed = norm(m.velocity);
  return speed > 0 ? m.distance / speed : 0.0;
}
}  // namespace

Vec2 wall_point_at(const WallMotion& m, Vec2 p0, double t) {
  switch (m.kind) {
    case WallMotion::Kind::fixed:
      return p0;
    case WallMotion::Kind::translate:
      return p0 + std::min(t, travel_time(m)) * m.velocity;
    case WallMotion::Kind::load_controlled:  // its driven part; DemSystem adds the free one
      return p0 + t * m.velocity;
    case WallMotion::Kind::rotate:
      return m.centre + rotated(p0 - m.centre, m.omega * t);
  }
  return p0;
}

Vec2 wall_velocity_at(const WallMotion& m, Vec2 p, double t) {
  switch (m.kind) {
    case WallMotion::Kind::fixed:
      return {};
    case WallMotion::Kind::translate:
      return t < travel_time(m) ? m.velocity : Vec2{};
    case WallMotion::Kind::load_controlled:
      return m.velocity;
    case WallMotion::Kind::rotate:
      return m.omega * perp(p - m.centre);
  }
  return {};
}

double wall_max_displacement(const WallMotion& m, const std::vector<Segment>& segments, int wall, double t0,
                             double t1) {
  switch (m.kind) {
    case WallMotion::Kind::fixed:
      return 0;
    case WallMotion::Kind::load_controlled:
      return norm(m.velocity) * std::abs(t1 - t0);
    case WallMotion::Kind::translate: {
      const double tt = travel_time(m);
      return norm(m.velocity) * std::max(0.0, std::min(t1, tt) - std::min(t0, tt));
    }
    case WallMotion::Kind::rotate: {
      double reach = 0;
      for (const Segment& s : segments)
        if (s.wall == wall) reach = std::max({reach, norm(s.a - m.centre), norm(s.b - m.centre)});
      // Chord length of the arc swept by the farthest point.
      const double angle = std::min(std::abs(m.omega * (t1 - t0)), M_PI);
      return 2 * reach * std::sin(angle / 2);
    }
  }
  return 0;
}

}  // namespace kiln
