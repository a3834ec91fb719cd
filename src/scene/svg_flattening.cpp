// Curves flattened in world coordinates so that no chord departs from the curve by more than the
// tolerance: arcs of ellipses by the sagitta rule, Beziers by the interpolation error bound.
#include "src/scene/svg_parts.h"

#include <algorithm>
#include <numbers>

namespace kiln::svg {

namespace {

// Equal steps in t over `sweep` (at least `least`) whose chords stay within the tolerance. The
// ellipse is the image of a unit circle under [u v], where a chord of angle s departs from its arc
// by 1 - cos(s/2); the map stretches that by at most its largest singular value, the semi-major
// axis A. So A (1 - cos(s/2)) = 2 A sin^2(s/4) <= tolerance: the sagitta rule of arc_points
// (wall_geometry.h), in the asin form that stays accurate when the tolerance is tiny.
int arc_pieces(const Ellipse& e, double sweep, int least, const Trace& trace) {
  const double mean = (dot(e.u, e.u) + dot(e.v, e.v)) / 2;
  const double half_gap = (dot(e.u, e.u) - dot(e.v, e.v)) / 2;
  const double semi_major = std::sqrt(mean + std::hypot(half_gap, dot(e.u, e.v)));
  const double step = 4 * std::asin(std::sqrt(std::min(1.0, trace.tolerance() / (2 * semi_major))));
  const double pieces = std::max<double>(least, std::ceil(std::abs(sweep) / step));
  trace.reserve(pieces);
  return static_cast<int>(pieces);
}

// Equal steps in the parameter: a curve leaves the chord of a step dt by at most
// max|B''| dt^2 / 8 (the interpolation error bound), so n steps suffice once
// max|B''| / (8 n^2) <= tolerance.
int bezier_pieces(double max_second_derivative, const Trace& trace) {
  const double pieces = std::max(1.0, std::ceil(std::sqrt(max_second_derivative / (8 * trace.tolerance()))));
  trace.reserve(pieces);
  return static_cast<int>(pieces);
}

}  // namespace

Ellipse world_ellipse(const Affine& m, Vec2 centre, Vec2 u, Vec2 v) {
  return {apply(m, centre), apply_linear(m, u), apply_linear(m, v)};
}

// The points strictly inside an arc of the ellipse from t = from over `sweep`; the caller draws
// its end points exactly.
void arc_interior(Trace& trace, const Ellipse& e, double from, double sweep, int least) {
  const int pieces = arc_pieces(e, sweep, least, trace);
  for (int k = 1; k < pieces; ++k) trace.to(e.at(from + sweep * k / pieces));
}

// A cubic Bezier from the trace's last point p0, in world coordinates (an affine map of the
// control points maps the curve). |B''| <= 6 max(|p0 - 2p1 + p2|, |p1 - 2p2 + p3|).
void cubic_to(Trace& trace, Vec2 p0, Vec2 p1, Vec2 p2, Vec2 p3) {
  const double bend = 6 * std::max(norm(p0 - 2 * p1 + p2), norm(p1 - 2 * p2 + p3));
  const int pieces = bezier_pieces(bend, trace);
  for (int k = 1; k < pieces; ++k) {
    const double t = static_cast<double>(k) / pieces, s = 1 - t;
    trace.to(s * s * s * p0 + 3 * s * s * t * p1 + 3 * s * t * t * p2 + t * t * t * p3);
  }
  trace.to(p3);
}

// A quadratic Bezier: B'' = 2 (p0 - 2p1 + p2).
void quadratic_to(Trace& trace, Vec2 p0, Vec2 p1, Vec2 p2) {
  const int pieces = bezier_pieces(2 * norm(p0 - 2 * p1 + p2), trace);
  for (int k = 1; k < pieces; ++k) {
    const double t = static_cast<double>(k) / pieces, s = 1 - t;
    trace.to(s * s * p0 + 2 * s * t * p1 + t * t * p2);
  }
  trace.to(p2);
}

}  // namespace kiln::svg
