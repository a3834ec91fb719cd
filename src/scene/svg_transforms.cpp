// Transform lists (section 7.6) as affine maps [a c e; b d f; 0 0 1], composed element by element
// (section 7.5).
#include "src/scene/svg_parts.h"

#include <numbers>

namespace kiln::svg {

namespace {

Affine translation(double x, double y) { return {1, 0, 0, 1, x, y}; }

Affine rotation(double degrees) {
  const auto [c, s] = cos_sin_degrees(degrees);
  return {c, s, -s, c, 0, 0};
}

double skew_tangent(std::string_view name, double degrees) {
  if (std::fmod(std::abs(degrees), 180.0) == 90)
    throw Malformed("transform '" + std::string(name) + "' of 90 degrees is undefined (tan 90)");
  const auto [c, s] = cos_sin_degrees(degrees);
  return s / c;
}

// One item of a transform list (section 7.6).
Affine transform_item(std::string_view name, const std::vector<double>& v) {
  const size_t n = v.size();
  const auto takes = [&](bool fits, const char* counts) {
    if (!fits)
      throw Malformed("transform '" + std::string(name) + "' takes " + counts + " numbers, found " + std::to_string(n));
  };
  if (name == "matrix") {
    takes(n == 6, "6");
    return {v[0], v[1], v[2], v[3], v[4], v[5]};
  }
  if (name == "translate") {
    takes(n == 1 || n == 2, "1 or 2");
    return translation(v[0], n == 2 ? v[1] : 0);
  }
  if (name == "scale") {
    takes(n == 1 || n == 2, "1 or 2");
    return {v[0], 0, 0, n == 2 ? v[1] : v[0], 0, 0};
  }
  if (name == "rotate") {
    takes(n == 1 || n == 3, "1 or 3");
    if (n == 1) return rotation(v[0]);
    return translation(v[1], v[2]) * rotation(v[0]) * translation(-v[1], -v[2]);
  }
  if (name == "skewX") {
    takes(n == 1, "1");
    return {1, 0, skew_tangent(name, v[0]), 1, 0, 0};
  }
  if (name == "skewY") {
    takes(n == 1, "1");
    return {1, skew_tangent(name, v[0]), 0, 1, 0, 0};
  }
  throw Malformed("unknown transform '" + std::string(name) +
                  "' (matrix, translate, scale, rotate, skewX and skewY are read)");
}

// A transform list: items separated by white space and/or commas, each name(numbers).
Affine transform_list(std::string_view text) {
  Scanner s(text);
  Affine m;
  while (!s.at_end()) {
    const std::string_view name = s.word();
    if (name.empty()) throw s.unexpected("expected a transform name");
    s.expect('(');
    std::vector<double> values;
    while (s.at_number()) values.push_back(s.number());
    s.expect(')');
    m = m * transform_item(name, values);
    while (s.accept(',')) {  // items may be separated by commas as well as white space
    }
  }
  return m;
}

}  // namespace

// m * n applies n first: a transform list applies its items right to left, and an element's own
// transform applies before its parents' (section 7.5).
Affine operator*(const Affine& m, const Affine& n) {
  return {m.a * n.a + m.c * n.b, m.b * n.a + m.d * n.b, m.a * n.c + m.c * n.d,
          m.b * n.c + m.d * n.d, m.a * n.e + m.c * n.f + m.e, m.b * n.e + m.d * n.f + m.f};
}

// cos and sin of an angle in degrees, exact at multiples of 90 so that rotate(90) keeps straight
// walls exactly horizontal or vertical.
std::array<double, 2> cos_sin_degrees(double degrees) {
  const double reduced = std::fmod(degrees, 360.0);
  if (std::fmod(reduced, 90.0) == 0) {
    static constexpr std::array<std::array<double, 2>, 4> quarter{{{1, 0}, {0, 1}, {-1, 0}, {0, -1}}};
    return quarter[(static_cast<int>(reduced / 90) + 4) % 4];
  }
  const double radians = degrees * std::numbers::pi / 180;
  return {std::cos(radians), std::sin(radians)};
}

// An element's transform list composed after its parents' (`outer`). Refuses a list that maps the
// drawing onto a line or a point, and a composition beyond double precision.
Affine composed(const Affine& outer, std::string_view list) {
  const Affine own = transform_list(list);
  if (own.a * own.d - own.b * own.c == 0)
    throw Malformed("the transform is singular: it flattens the drawing to a line or a point");
  const Affine m = outer * own;
  for (double x : {m.a, m.b, m.c, m.d, m.e, m.f})
    if (!std::isfinite(x)) throw Malformed("the transforms overflow double precision");
  return m;
}

}  // namespace kiln::svg
