// Walls: the vertex rule (one force at a polyline joint), flattening tolerance.
#include <catch2/catch.hpp>
#include <cmath>

#include "src/scene/wall_geometry.h"

using namespace kiln;

TEST_CASE("a disc resting on a flat polyline joint touches exactly one segment", "[walls]") {
  std::vector<Segment> segs;
  add_polyline(segs, {{-1, 0}, {0, 0}, {1, 0}}, false, 0);
  std::vector<Vec2> a{segs[0].a, segs[1].a}, b{segs[0].b, segs[1].b};
  for (double x : {-1e-3, 0.0, 1e-3}) {
    WallHit hit;
    const int count = disc_segment_contact(segs, a, b, 0, {x, 0.9e-3}, 1e-3, hit) +
                      disc_segment_contact(segs, a, b, 1, {x, 0.9e-3}, 1e-3, hit);
    CHECK(count == 1);
  }
}

TEST_CASE("a convex corner is touched once, through its vertex, from the wedge beyond both faces", "[walls]") {
  std::vector<Segment> segs;
  add_polyline(segs, {{-1, 0}, {0, 0}, {0, -1}}, false, 0);  // a step down: convex corner at the origin
  std::vector<Vec2> a{segs[0].a, segs[1].a}, b{segs[0].b, segs[1].b};
  WallHit h0, h1;
  const Vec2 c{0.5e-3, 0.5e-3};
  const bool t0 = disc_segment_contact(segs, a, b, 0, c, 1e-3, h0);
  const bool t1 = disc_segment_contact(segs, a, b, 1, c, 1e-3, h1);
  CHECK(t0 + t1 == 1);
  const WallHit& h = t0 ? h0 : h1;
  CHECK(h.overlap == Approx(1e-3 - std::sqrt(0.5) * 1e-3));
  CHECK(h.normal.x == Approx(-std::sqrt(0.5)));
}

TEST_CASE("an inner (concave) corner pushes from both faces", "[walls]") {
  std::vector<Segment> segs;
  add_polyline(segs, {{0, 1}, {0, 0}, {1, 0}}, false, 0);  // floor meets a left wall
  std::vector<Vec2> a{segs[0].a, segs[1].a}, b{segs[0].b, segs[1].b};
  WallHit hit;
  CHECK(disc_segment_contact(segs, a, b, 0, {0.9e-3, 0.9e-3}, 1e-3, hit));
  CHECK(disc_segment_contact(segs, a, b, 1, {0.9e-3, 0.9e-3}, 1e-3, hit));
}

TEST_CASE("arc flattening keeps every chord within the tolerance", "[walls]") {
  const double R = 0.0762, tol = 1e-5;
  const auto pts = arc_points({0, 0}, R, 0, 2 * M_PI, tol);
  for (size_t k = 0; k + 1 < pts.size(); ++k) {
    const Vec2 mid = 0.5 * (pts[k] + pts[k + 1]);
    CHECK(R - norm(mid) <= tol * (1 + 1e-9));
  }
  CHECK(norm(pts.front() - pts.back()) < 1e-12);
}
