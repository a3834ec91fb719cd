#include "src/scene/wall_motion.h"

#include <algorithm>
#include <cmath>

#include "src/scene/scene_parts.h"

namespace kiln {

namespace {

double travel_time(const WallMotion& m) {
  const double speed = norm(m.velocity);
  return speed > 0 ? m.distance / speed : 0.0;
}

// The farthest any end point of wall `wall` lies from `centre`, in the given distance.
template <class Distance>
double reach(const std::vector<Segment>& segments, int wall, Vec2 centre, Distance distance) {
  double far = 0;
  for (const Segment& s : segments)
    if (s.wall == wall) far = std::max({far, distance(s.a - centre), distance(s.b - centre)});
  return far;
}

}  // namespace

Vec2 WallMotion::point_at(Vec2 p0, double t) const {
  switch (kind) {
    case Kind::fixed:
      return p0;
    case Kind::translate:
      return p0 + std::min(t, travel_time(*this)) * velocity;
    case Kind::load_controlled:  // its driven part; DemSystem adds the free one
      return p0 + t * velocity;
    case Kind::rotate:
      return centre + rotated(p0 - centre, omega * t);
  }
  return p0;
}

Vec2 WallMotion::velocity_at(Vec2 p, double t) const {
  switch (kind) {
    case Kind::fixed:
      return {};
    case Kind::translate:
      return t < travel_time(*this) ? velocity : Vec2{};
    case Kind::load_controlled:
      return velocity;
    case Kind::rotate:
      return omega * perp(p - centre);
  }
  return {};
}

Vec2 WallMotion::acceleration_at(Vec2 p, double /*t*/) const {
  switch (kind) {
    case Kind::fixed:
    case Kind::translate:  // its stop is a jump (velocity_jumps), not an acceleration
    case Kind::load_controlled:
      return {};
    case Kind::rotate:
      return (-omega * omega) * (p - centre);
  }
  return {};
}

std::optional<Vec2> WallMotion::centre_of_rotation() const {
  switch (kind) {
    case Kind::fixed:
    case Kind::translate:
    case Kind::load_controlled:
      return std::nullopt;
    case Kind::rotate:
      return centre;
  }
  return std::nullopt;
}

bool WallMotion::velocity_jumps() const {
  switch (kind) {
    case Kind::fixed:
    case Kind::rotate:
    case Kind::load_controlled:
      return false;
    case Kind::translate:
      return std::isfinite(distance);
  }
  return false;
}

// Speeds with hypot, which does not overflow below 1.8e308 (the stability estimate refuses what
// is still not finite).
double WallMotion::largest_speed(const std::vector<Segment>& segments, int wall) const {
  switch (kind) {
    case Kind::fixed:
      return 0;
    case Kind::translate:
    case Kind::load_controlled:  // its driven speed; the free one along the load is the run's
      return std::hypot(velocity.x, velocity.y);
    case Kind::rotate:
      return reach(segments, wall, centre, [&](Vec2 d) { return std::abs(omega) * std::hypot(d.x, d.y); });
  }
  return 0;
}

double WallMotion::max_displacement(const std::vector<Segment>& segments, int wall, double t0, double t1) const {
  switch (kind) {
    case Kind::fixed:
      return 0;
    case Kind::load_controlled:
      return norm(velocity) * std::abs(t1 - t0);
    case Kind::translate: {
      const double tt = travel_time(*this);
      return norm(velocity) * std::max(0.0, std::min(t1, tt) - std::min(t0, tt));
    }
    case Kind::rotate: {
      // Chord length of the arc swept by the farthest point.
      const double angle = std::min(std::abs(omega * (t1 - t0)), M_PI);
      return 2 * reach(segments, wall, centre, norm) * std::sin(angle / 2);
    }
  }
  return 0;
}

namespace scene_parts {

std::vector<std::string> wall_motion_keys() {
  return {"type", "velocity", "distance", "centre", "rpm", "load", "mass", "damping"};
}

WallMotion read_motion(const SceneNode& m) {
  WallMotion motion;
  const std::string kind = m["type"].choice({"fixed", "translate", "rotate", "load_controlled"});
  if (kind == "fixed") {
    m.allow({"type"});
  } else if (kind == "load_controlled") {
    m.allow({"type", "velocity", "load", "mass", "damping"});
    motion.kind = WallMotion::Kind::load_controlled;
    motion.velocity = m.has("velocity") ? m["velocity"].vec2() : Vec2{};
    motion.load = m["load"].vec2();
    motion.mass = m["mass"].positive();
    motion.damping = m["damping"].non_negative();  // stated, as the load and mass are (0 allowed)
    if (norm(motion.load) == 0) m["load"].fail("a load-controlled wall needs a non-zero load (N)");
    // The body is driven along the velocity and free along the load: the two must not share a direction.
    if (std::abs(dot(motion.velocity, motion.load)) > 1e-12 * norm(motion.velocity) * norm(motion.load))
      m["velocity"].fail("the driven velocity must be perpendicular to the load: the wall is free along the load");
  } else if (kind == "translate") {
    m.allow({"type", "velocity", "distance"});
    motion.kind = WallMotion::Kind::translate;
    motion.velocity = m["velocity"].vec2();
    motion.distance = m.has("distance") ? m["distance"].non_negative() : INFINITY;
  } else {
    m.allow({"type", "centre", "rpm"});
    motion.kind = WallMotion::Kind::rotate;
    motion.centre = point(m["centre"]);
    motion.omega = m["rpm"].number() * 2 * M_PI / 60;
    if (!std::isfinite(motion.omega)) m["rpm"].fail("the angular speed overflows double precision");
  }
  return motion;
}

}  // namespace scene_parts

}  // namespace kiln
