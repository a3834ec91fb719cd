// The basic shapes (chapter 9): line, polyline, polygon, rect (rounded corners), circle, ellipse,
// and which reader draws each element.
#include "src/scene/svg_parts.h"

#include <algorithm>
#include <map>
#include <numbers>

namespace kiln::svg {

namespace {

double coordinate(pugi::xml_node n, const char* name) { return length_attribute(n, name).value_or(0); }

// A width, height or radius: required and > 0 (section 9: a negative value is an error, zero
// draws nothing, which for a wall is an error too).
double extent(pugi::xml_node n, const char* name) {
  const std::optional<double> value = length_attribute(n, name);
  if (!value) throw Malformed(std::string("attribute ") + name + " is missing");
  if (!(*value > 0)) throw Malformed(std::string(name) + " must be > 0, found " + n.attribute(name).value());
  return *value;
}

void read_line(pugi::xml_node n, Pen& pen) {
  pen.trace.to(pen.world({coordinate(n, "x1"), coordinate(n, "y1")}));
  pen.trace.to(pen.world({coordinate(n, "x2"), coordinate(n, "y2")}));
  pen.finish(false);
}

void read_points(pugi::xml_node n, Pen& pen, bool closed) {
  const char* text = n.attribute("points").value();
  std::vector<double> v;
  try {
    v = number_list(text);
  } catch (const Malformed& e) {
    throw Malformed(std::string("points ") + excerpt(text) + ": " + e.what());
  }
  if (v.size() % 2 != 0) throw Malformed("points needs pairs of numbers, found " + std::to_string(v.size()));
  for (size_t k = 0; k < v.size(); k += 2) pen.trace.to(pen.world({v[k], v[k + 1]}));
  pen.finish(closed);
}

// The full ellipse, from t = 0 (cx + rx, cy) in the positive angle direction (section 9.4).
void draw_ellipse(Pen& pen, Vec2 centre, double rx, double ry) {
  const Ellipse e = world_ellipse(pen.to_world, centre, {rx, 0}, {0, ry});
  pen.trace.to(e.at(0));
  arc_interior(pen.trace, e, 0, 2 * std::numbers::pi, 3);
  pen.finish(true);
}

void read_polyline(pugi::xml_node n, Pen& pen) { read_points(n, pen, false); }

void read_polygon(pugi::xml_node n, Pen& pen) { read_points(n, pen, true); }

void read_circle(pugi::xml_node n, Pen& pen) {
  const double r = extent(n, "r");
  draw_ellipse(pen, {coordinate(n, "cx"), coordinate(n, "cy")}, r, r);
}

void read_ellipse(pugi::xml_node n, Pen& pen) {
  const double rx = extent(n, "rx"), ry = extent(n, "ry");
  draw_ellipse(pen, {coordinate(n, "cx"), coordinate(n, "cy")}, rx, ry);
}

// Corner radii of a rect (section 9.2): one given stands for both; negative is an error; each is
// clamped to half its side; a zero one makes square corners (its arcs would be lines, F.6.2).
std::array<double, 2> corner_radii(pugi::xml_node n, double width, double height) {
  std::optional<double> rx = length_attribute(n, "rx"), ry = length_attribute(n, "ry");
  if (rx.value_or(0) < 0 || ry.value_or(0) < 0) throw Malformed("rx and ry must be >= 0");
  if (!rx) rx = ry;
  if (!ry) ry = rx;
  if (rx.value_or(0) == 0 || ry.value_or(0) == 0) return {0, 0};
  return {std::min(*rx, width / 2), std::min(*ry, height / 2)};
}

// Clockwise on screen from the top edge's left end (x + rx, y), as section 9.2's equivalent path;
// each corner is a quarter ellipse between exact end points (one point when the radii are zero).
// The last corner ends where the outline started, which closing drops.
void read_rect(pugi::xml_node n, Pen& pen) {
  const double x = coordinate(n, "x"), y = coordinate(n, "y"), w = extent(n, "width"), h = extent(n, "height");
  const auto [rx, ry] = corner_radii(n, w, h);
  const std::array<Vec2, 4> centre{
      {{x + w - rx, y + ry}, {x + w - rx, y + h - ry}, {x + rx, y + h - ry}, {x + rx, y + ry}}};
  const std::array<Vec2, 4> first{{{x + w - rx, y}, {x + w, y + h - ry}, {x + rx, y + h}, {x, y + ry}}};
  const std::array<Vec2, 4> last{{{x + w, y + ry}, {x + w - rx, y + h}, {x, y + h - ry}, {x + rx, y}}};
  pen.trace.to(pen.world(last[3]));
  for (int k = 0; k < 4; ++k) {
    pen.trace.to(pen.world(first[k]));
    if (rx > 0) {
      const Ellipse corner = world_ellipse(pen.to_world, centre[k], {rx, 0}, {0, ry});
      arc_interior(pen.trace, corner, (k - 1) * std::numbers::pi / 2, std::numbers::pi / 2);
    }
    pen.trace.to(pen.world(last[k]));
  }
  pen.finish(true);
}

}  // namespace

std::optional<double> length_attribute(pugi::xml_node n, const char* name) {
  const pugi::xml_attribute a = n.attribute(name);
  if (!a) return std::nullopt;
  try {
    return length_value(a.value());
  } catch (const Malformed& e) {
    throw Malformed(std::string(name) + " " + excerpt(a.value()) + ": " + e.what());
  }
}

ShapeReader shape_reader(std::string_view name) {
  static const std::map<std::string_view, ShapeReader> readers{
      {"path", read_path},
      {"line", read_line},
      {"polyline", read_polyline},
      {"polygon", read_polygon},
      {"rect", read_rect},
      {"circle", read_circle},
      {"ellipse", read_ellipse}};
  const auto found = readers.find(name);
  return found == readers.end() ? nullptr : found->second;
}

}  // namespace kiln::svg
