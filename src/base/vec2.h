// Two-component double vector for contact geometry. Plain value type, no allocation.
#pragma once
#include <cmath>

namespace kiln {

struct Vec2 {
  double x = 0, y = 0;
};

inline Vec2 operator+(Vec2 a, Vec2 b) { return {a.x + b.x, a.y + b.y}; }
inline Vec2 operator-(Vec2 a, Vec2 b) { return {a.x - b.x, a.y - b.y}; }
inline Vec2 operator*(double s, Vec2 a) { return {s * a.x, s * a.y}; }
inline bool operator!=(Vec2 a, Vec2 b) { return a.x != b.x || a.y != b.y; }
inline double dot(Vec2 a, Vec2 b) { return a.x * b.x + a.y * b.y; }
inline double cross(Vec2 a, Vec2 b) { return a.x * b.y - a.y * b.x; }
inline double norm(Vec2 a) { return std::sqrt(dot(a, a)); }
// Counter-clockwise perpendicular: the tangent t = perp(n) with cross(n, t) = 1.
inline Vec2 perp(Vec2 a) { return {-a.y, a.x}; }
// Rotate a by angle theta (radians) about the origin.
inline Vec2 rotated(Vec2 a, double theta) {
  const double c = std::cos(theta), s = std::sin(theta);
  return {c * a.x - s * a.y, s * a.x + c * a.y};
}

}  // namespace kiln
