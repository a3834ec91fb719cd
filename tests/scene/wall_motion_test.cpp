// Wall motions (src/scene/wall_motion.h): each kind's position, velocity and acceleration agree
// with one another, and its largest speed and displacement bound what its points do.
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "src/scene/scene.h"
#include "src/scene/wall_geometry.h"

using namespace kiln;

namespace {

// One motion of each kind, moving a wall of two segments around the origin.
std::vector<WallMotion> one_of_each_kind() {
  WallMotion fixed;
  WallMotion slide;
  slide.kind = WallMotion::Kind::translate;
  slide.velocity = {0.3, -0.4};
  slide.distance = 0.1;
  WallMotion drum;
  drum.kind = WallMotion::Kind::rotate;
  drum.centre = {0.05, -0.02};
  drum.omega = -3.0;
  WallMotion body;
  body.kind = WallMotion::Kind::load_controlled;
  body.velocity = {4.0, 0};
  body.load = {0, -1};
  body.mass = 0.01;
  return {fixed, slide, drum, body};
}

std::vector<Segment> wall() {
  std::vector<Segment> segments;
  add_polyline(segments, {{-0.1, 0}, {0.1, 0}, {0.1, 0.2}}, false, 0);
  return segments;
}

}  // namespace

TEST_CASE("a translating wall stops after its distance and a rotating wall moves at omega x r", "[walls]") {
  WallMotion slide;
  slide.kind = WallMotion::Kind::translate;
  slide.velocity = {0.01, 0};
  slide.distance = 0.001;
  CHECK(slide.point_at({0, 0}, 0.05).x == Approx(0.0005));
  CHECK(slide.point_at({0, 0}, 1.0).x == Approx(0.001));
  CHECK(slide.velocity_at({0, 0}, 0.05).x == Approx(0.01));
  CHECK(slide.velocity_at({0, 0}, 0.2).x == 0.0);
  CHECK(slide.velocity_jumps());
  WallMotion drum;
  drum.kind = WallMotion::Kind::rotate;
  drum.omega = 2.0;
  const Vec2 u = drum.velocity_at({0.5, 0}, 0);
  CHECK(u.x == Approx(0).margin(1e-15));
  CHECK(u.y == Approx(1.0));
  CHECK(drum.point_at({1, 0}, M_PI / 4).y == Approx(1.0));  // omega t = pi/2
  CHECK(drum.spin() == 2.0);
}

TEST_CASE("every kind of wall motion: its velocity is the rate of its position and its acceleration that of its "
          "velocity",
          "[walls]") {
  const double h = 1e-6;
  for (const WallMotion& m : one_of_each_kind())
    for (const Segment& s : wall())
      for (double t : {0.01, 0.35}) {  // the translation stops at 0.2 s
        INFO("kind " << static_cast<int>(m.kind) << " at t = " << t);
        const Vec2 rate = (1 / (2 * h)) * (m.point_at(s.b, t + h) - m.point_at(s.b, t - h));
        const Vec2 u = m.velocity_at(m.point_at(s.b, t), t);
        CHECK(rate.x == Approx(u.x).margin(1e-8));
        CHECK(rate.y == Approx(u.y).margin(1e-8));
        const Vec2 p = m.point_at(s.b, t);
        const Vec2 change = (1 / (2 * h)) * (m.velocity_at(m.point_at(s.b, t + h), t + h) -
                                             m.velocity_at(m.point_at(s.b, t - h), t - h));
        const Vec2 a = m.acceleration_at(p, t);
        CHECK(change.x == Approx(a.x).margin(1e-6));
        CHECK(change.y == Approx(a.y).margin(1e-6));
      }
}

TEST_CASE("every kind of wall motion: no point of the wall moves faster than its largest speed or farther than its "
          "largest displacement",
          "[walls]") {
  const std::vector<Segment> segments = wall();
  for (const WallMotion& m : one_of_each_kind()) {
    INFO("kind " << static_cast<int>(m.kind));
    const double fastest = m.largest_speed(segments, 0);
    double seen = 0;
    for (double t = 0; t < 1; t += 0.01)
      for (const Segment& s : segments)
        for (Vec2 p0 : {s.a, s.b}) {
          seen = std::max(seen, norm(m.velocity_at(m.point_at(p0, t), t)));
          for (double dt : {0.05, 0.5}) {
            const double moved = norm(m.point_at(p0, t + dt) - m.point_at(p0, t));
            CHECK(moved <= m.max_displacement(segments, 0, t, t + dt) * (1 + 1e-12));
          }
        }
    CHECK(seen <= fastest * (1 + 1e-12));
    CHECK(seen == Approx(fastest));  // a bound that is reached
    CHECK(m.moves() == (fastest > 0));
  }
}
