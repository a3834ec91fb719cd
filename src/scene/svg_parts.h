// The SVG reader's parts, one file each: the micro-syntaxes inside attributes (svg_syntax.cpp),
// transforms (svg_transforms.cpp), flattening curves into the pen's polylines (svg_flattening.cpp),
// path data (svg_paths.cpp), the basic shapes (svg_shapes.cpp); svg_geometry.cpp walks the
// document. Internal to src/scene/. Section numbers refer to SVG 1.1 (Second Edition), 2011.
#pragma once
#include <array>
#include <cmath>
#include <optional>
#include <stdexcept>
#include <string>
#include <string_view>
#include <vector>

#include <pugixml.hpp>

#include "src/base/error.h"
#include "src/scene/svg_geometry.h"

namespace kiln::svg {

inline constexpr double max_points = 1'000'000;

// A fault inside one element (a number, a command, the point budget); the reader adds the file,
// the line and the element to its message.
struct Malformed : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A character for a message; a byte that is not printable ASCII (part of a UTF-8 sequence, say)
// by its code.
std::string quoted(char c);
bool one_of(char c, std::string_view set);
// The text of an attribute for a message, shortened: path data can be megabytes long.
std::string excerpt(std::string_view text);

// ---- The micro-syntaxes (svg_syntax.cpp) ----

// Reads the numbers, flags, letters and punctuation of an attribute value. Numbers follow the
// path data grammar (section 8.3.9): sign? (digits ("." digits?)? | "." digits) exponent?, read
// greedily, so ".5.5" is two numbers and so is "-1-2". Between two values: whitespace and at most
// one comma; a comma must stand between two values.
class Scanner {
 public:
  explicit Scanner(std::string_view text) : text_(text) {}

  bool at_end() {
    skip_space();
    return pos_ == text_.size();
  }
  char peek() {
    skip_space();
    return pos_ < text_.size() ? text_[pos_] : '\0';
  }
  // Whether a number (or flag) comes next, after the comma that may separate it from the last one.
  bool at_number() {
    skip_space();
    if (pos_ < text_.size() && text_[pos_] == ',') {
      if (!after_value_) throw Malformed("unexpected ',' at " + where());
      ++pos_;
      skip_space();
      after_value_ = false;
      if (!starts_number()) throw Malformed("the comma before " + where() + " is not followed by a number");
    }
    return starts_number();
  }
  double number();
  // An arc flag (section 8.3.8): the single character 0 or 1, so "011" is three values.
  bool flag() {
    skip_space();
    const char c = pos_ < text_.size() ? text_[pos_] : '\0';
    if (c != '0' && c != '1') throw Malformed("an arc flag must be 0 or 1, found " + quoted(c) + " at " + where());
    ++pos_;
    after_value_ = true;
    return c == '1';
  }
  // Takes the character peek() returned (a path command).
  void take() {
    skip_space();
    ++pos_;
    after_value_ = false;
  }
  std::string_view word() {
    skip_space();
    const size_t start = pos_;
    while (pos_ < text_.size() && std::isalpha(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    return text_.substr(start, pos_ - start);
  }
  bool accept(char c) {
    if (peek() != c) return false;
    ++pos_;
    after_value_ = false;
    return true;
  }
  void expect(char c) {
    if (!accept(c)) throw unexpected("expected " + quoted(c));
  }
  // The fault of finding what is at the current position when `wanted` was expected.
  Malformed unexpected(const std::string& wanted) {
    if (at_end()) return Malformed(wanted + ", found the end");
    return Malformed(wanted + ", found " + quoted(text_[pos_]) + " at " + where());
  }
  std::string where() const { return "character " + std::to_string(pos_ + 1); }

 private:
  // SVG's white space (section 8.3.9: wsp): space, tab, line feed, carriage return.
  void skip_space() {
    while (pos_ < text_.size() && one_of(text_[pos_], " \t\n\r")) ++pos_;
  }
  bool starts_number() const {
    return pos_ < text_.size() && (std::isdigit(static_cast<unsigned char>(text_[pos_])) ||
                                   one_of(text_[pos_], "+-."));
  }
  size_t digits() {
    const size_t start = pos_;
    while (pos_ < text_.size() && std::isdigit(static_cast<unsigned char>(text_[pos_]))) ++pos_;
    return pos_ - start;
  }

  std::string_view text_;
  size_t pos_ = 0;
  bool after_value_ = false;  // a comma may follow
};

// All the numbers of a list (points, viewBox); the text must hold nothing else.
std::vector<double> number_list(std::string_view text);
// A <length> (section 4.2) in user units: a number with px or no unit, or an absolute unit at 96 px
// per inch (CSS 2.1 and SVG 2; SVG 1.1 still said 90, browsers and Inkscape 0.92+ use 96).
double length_value(std::string_view text);

// ---- Transforms (section 7.4; svg_transforms.cpp) ----

struct Affine {
  double a = 1, b = 0, c = 0, d = 1, e = 0, f = 0;
};

// m * n applies n first: a transform list applies its items right to left, and an element's own
// transform applies before its parents' (section 7.5).
Affine operator*(const Affine& m, const Affine& n);
inline Vec2 apply(const Affine& m, Vec2 p) { return {m.a * p.x + m.c * p.y + m.e, m.b * p.x + m.d * p.y + m.f}; }
inline Vec2 apply_linear(const Affine& m, Vec2 v) { return {m.a * v.x + m.c * v.y, m.b * v.x + m.d * v.y}; }
// cos and sin of an angle in degrees, exact at multiples of 90 so that rotate(90) keeps straight
// walls exactly horizontal or vertical.
std::array<double, 2> cos_sin_degrees(double degrees);
// An element's transform list composed after its parents' (`outer`). Refuses a list that maps the
// drawing onto a line or a point, and a composition beyond double precision.
Affine composed(const Affine& outer, std::string_view list);

// ---- Polylines, the point budget, curve flattening (svg_flattening.cpp) ----

// Counts every point kept, bounding the work and memory of a huge file or a tiny tolerance.
class Budget {
 public:
  explicit Budget(double tolerance) : tolerance_(tolerance) {}
  void check(double more) const {
    if (!(used_ + more <= max_points))
      throw Malformed("the drawing needs more than 1,000,000 points at a tolerance of " + message_number(tolerance_) +
                      " m: use a larger tolerance");
  }
  void take() {
    check(1);
    ++used_;
  }

 private:
  double tolerance_;
  double used_ = 0;
};

// The polyline being drawn, in world coordinates.
class Trace {
 public:
  Trace(Budget& budget, double tolerance) : budget_(budget), tolerance_(tolerance) {}
  double tolerance() const { return tolerance_; }
  void reserve(double more) const { budget_.check(more); }
  void to(Vec2 p) {
    if (!std::isfinite(p.x) || !std::isfinite(p.y))
      throw Malformed("a point lies beyond double precision in world coordinates");
    if (!points_.empty() && coincident(p, points_.back())) return;
    budget_.take();
    points_.push_back(p);
  }
  // The polyline drawn since the last finish, or nothing when it is less than a segment. A closed
  // one of two points is their segment: closing it would only retrace it.
  std::optional<SvgPolyline> finish(bool closed) {
    std::vector<Vec2> points = std::move(points_);
    points_.clear();
    if (closed && points.size() > 2 && coincident(points.back(), points.front())) points.pop_back();
    if (points.size() < 2) return std::nullopt;
    const bool ring = closed && points.size() > 2;
    return SvgPolyline{std::move(points), ring};
  }

 private:
  bool coincident(Vec2 p, Vec2 q) const { return norm(p - q) <= 1e-6 * tolerance_; }

  Budget& budget_;
  double tolerance_;
  std::vector<Vec2> points_;
};

// A world-space ellipse c + u cos(t) + v sin(t): the image under an affine map of an SVG circle,
// ellipse or arc, with the parameter t of the original.
struct Ellipse {
  Vec2 c, u, v;
  Vec2 at(double t) const { return c + std::cos(t) * u + std::sin(t) * v; }
};

Ellipse world_ellipse(const Affine& m, Vec2 centre, Vec2 u, Vec2 v);
// The points strictly inside an arc of the ellipse from t = from over `sweep`; the caller draws
// its end points exactly.
void arc_interior(Trace& trace, const Ellipse& e, double from, double sweep, int least = 1);
// A cubic Bezier from the trace's last point p0, in world coordinates (an affine map of the
// control points maps the curve). |B''| <= 6 max(|p0 - 2p1 + p2|, |p1 - 2p2 + p3|).
void cubic_to(Trace& trace, Vec2 p0, Vec2 p1, Vec2 p2, Vec2 p3);
// A quadratic Bezier: B'' = 2 (p0 - 2p1 + p2).
void quadratic_to(Trace& trace, Vec2 p0, Vec2 p1, Vec2 p2);

// What one drawing element draws with: its map to the world, the trace, and the lines it drew.
struct Pen {
  Affine to_world;
  Trace trace;
  std::vector<SvgPolyline> lines;

  Vec2 world(Vec2 p) const { return apply(to_world, p); }
  void finish(bool closed) {
    if (auto line = trace.finish(closed)) lines.push_back(std::move(*line));
  }
};

// ---- Paths (chapter 8; svg_paths.cpp) and basic shapes (chapter 9; svg_shapes.cpp) ----

void read_path(pugi::xml_node n, Pen& pen);
std::optional<double> length_attribute(pugi::xml_node n, const char* name);
using ShapeReader = void (*)(pugi::xml_node, Pen&);
ShapeReader shape_reader(std::string_view name);

}  // namespace kiln::svg
