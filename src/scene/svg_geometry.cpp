// SVG wall geometry: pugixml parses the XML; the micro-syntaxes inside attributes (path data,
// transform lists, points, viewBox, lengths) have a scanner of their own; curves are flattened in
// world coordinates. Section numbers refer to SVG 1.1 (Second Edition), 2011.
#include "src/scene/svg_geometry.h"

#include <algorithm>
#include <array>
#include <cctype>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <numbers>
#include <optional>
#include <sstream>
#include <stdexcept>
#include <string_view>

#include <pugixml.hpp>

#include "src/base/error.h"

namespace kiln {
namespace {

constexpr std::string_view svg_namespace = "http://www.w3.org/2000/svg";
constexpr std::string_view inkscape_namespace = "http://www.inkscape.org/namespaces/inkscape";
constexpr double max_points = 1'000'000;
constexpr int max_depth = 1000;  // keeps the recursive walk far from the end of the stack

// A fault inside one element (a number, a command, the point budget); the reader adds the file,
// the line and the element to its message.
struct Malformed : std::runtime_error {
  using std::runtime_error::runtime_error;
};

// A character for a message; a byte that is not printable ASCII (part of a UTF-8 sequence, say)
// by its code.
std::string quoted(char c) {
  const auto byte = static_cast<unsigned char>(c);
  if (std::isprint(byte)) return std::string("'") + c + "'";
  static constexpr char hex[] = "0123456789ABCDEF";
  return std::string("byte 0x") + hex[byte >> 4] + hex[byte & 15];
}

bool one_of(char c, std::string_view set) { return set.find(c) != std::string_view::npos; }

// The text of an attribute for a message, shortened: path data can be megabytes long.
std::string excerpt(std::string_view text) {
  constexpr size_t longest = 60;
  return "\"" + std::string(text.substr(0, longest)) + (text.size() > longest ? "...\"" : "\"");
}

// ---- The micro-syntaxes ----------------------------------------------------------------------

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

double Scanner::number() {
  skip_space();
  const size_t start = pos_;
  if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-')) ++pos_;
  size_t mantissa = digits();
  if (pos_ < text_.size() && text_[pos_] == '.') {
    ++pos_;
    mantissa += digits();
  }
  if (mantissa == 0) {
    pos_ = start;
    throw unexpected("expected a number");
  }
  if (pos_ < text_.size() && (text_[pos_] == 'e' || text_[pos_] == 'E')) {
    ++pos_;
    if (pos_ < text_.size() && (text_[pos_] == '+' || text_[pos_] == '-')) ++pos_;
    if (digits() == 0)
      throw Malformed("the number '" + std::string(text_.substr(start, pos_ - start)) + "' ending before " +
                      where() + " has an exponent without digits");
  }
  // from_chars: exact and independent of the locale; it takes no leading '+'.
  const char* first = text_.data() + start + (text_[start] == '+' ? 1 : 0);
  double value = 0;
  const auto [end, status] = std::from_chars(first, text_.data() + pos_, value);
  if (status != std::errc() || !std::isfinite(value))
    throw Malformed("the number '" + std::string(text_.substr(start, pos_ - start)) +
                    "' is beyond the range of double precision (not finite)");
  after_value_ = true;
  return value;
}

// All the numbers of a list (points, viewBox); the text must hold nothing else.
std::vector<double> number_list(std::string_view text) {
  Scanner s(text);
  std::vector<double> values;
  while (s.at_number()) values.push_back(s.number());
  if (!s.at_end()) throw s.unexpected("expected a number");
  return values;
}

// A <length> (section 4.2) in user units: a number with px or no unit, or an absolute unit at 96 px
// per inch (CSS 2.1 and SVG 2; SVG 1.1 still said 90, browsers and Inkscape 0.92+ use 96).
double length_value(std::string_view text) {
  Scanner s(text);
  if (!s.at_number()) throw s.unexpected("expected a length");
  const double value = s.number();
  if (s.accept('%')) throw Malformed("a length in % needs the viewport, which is not read");
  const std::string_view unit = s.word();
  if (!s.at_end()) throw s.unexpected("expected the end of the length");
  static const std::map<std::string_view, double> px_per_unit{
      {"", 1}, {"px", 1}, {"in", 96}, {"cm", 96 / 2.54}, {"mm", 96 / 25.4}, {"pt", 96.0 / 72}, {"pc", 16}};
  const auto known = px_per_unit.find(unit);
  if (known == px_per_unit.end())
    throw Malformed("unit '" + std::string(unit) + "' is not read (px, in, cm, mm, pt and pc are)");
  return value * known->second;
}

// ---- Transforms (section 7.4: [a c e; b d f; 0 0 1]) ----------------------------------------

struct Affine {
  double a = 1, b = 0, c = 0, d = 1, e = 0, f = 0;
};

// m * n applies n first: a transform list applies its items right to left, and an element's own
// transform applies before its parents' (section 7.5).
Affine operator*(const Affine& m, const Affine& n) {
  return {m.a * n.a + m.c * n.b, m.b * n.a + m.d * n.b, m.a * n.c + m.c * n.d,
          m.b * n.c + m.d * n.d, m.a * n.e + m.c * n.f + m.e, m.b * n.e + m.d * n.f + m.f};
}
Vec2 apply(const Affine& m, Vec2 p) { return {m.a * p.x + m.c * p.y + m.e, m.b * p.x + m.d * p.y + m.f}; }
Vec2 apply_linear(const Affine& m, Vec2 v) { return {m.a * v.x + m.c * v.y, m.b * v.x + m.d * v.y}; }

Affine translation(double x, double y) { return {1, 0, 0, 1, x, y}; }

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

// ---- Output: polylines, the point budget, curve flattening ---------------------------------

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

Ellipse world_ellipse(const Affine& m, Vec2 centre, Vec2 u, Vec2 v) {
  return {apply(m, centre), apply_linear(m, u), apply_linear(m, v)};
}

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

// The points strictly inside an arc of the ellipse from t = from over `sweep`; the caller draws
// its end points exactly.
void arc_interior(Trace& trace, const Ellipse& e, double from, double sweep, int least = 1) {
  const int pieces = arc_pieces(e, sweep, least, trace);
  for (int k = 1; k < pieces; ++k) trace.to(e.at(from + sweep * k / pieces));
}

// Equal steps in the parameter: a curve leaves the chord of a step dt by at most
// max|B''| dt^2 / 8 (the interpolation error bound), so n steps suffice once
// max|B''| / (8 n^2) <= tolerance.
int bezier_pieces(double max_second_derivative, const Trace& trace) {
  const double pieces = std::max(1.0, std::ceil(std::sqrt(max_second_derivative / (8 * trace.tolerance()))));
  trace.reserve(pieces);
  return static_cast<int>(pieces);
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

// ---- Paths (chapter 8) -------------------------------------------------------------------------

// The numbers each command takes; -1 for a letter that is no command.
int arity(char command) {
  switch (std::toupper(static_cast<unsigned char>(command))) {
    case 'Z': return 0;
    case 'H': case 'V': return 1;
    case 'M': case 'L': case 'T': return 2;
    case 'S': case 'Q': return 4;
    case 'C': return 6;
    case 'A': return 7;
    default: return -1;
  }
}

// An arc in endpoint form converted to centre form (appendix F.6.5), its radii corrected first
// (F.6.6): the centre, the radii, the start parameter and the signed sweep, in user units.
struct CentreArc {
  Vec2 centre;
  double rx, ry, start, sweep;
};

double angle_between(Vec2 u, Vec2 v) { return std::atan2(cross(u, v), dot(u, v)); }

CentreArc centre_arc(Vec2 p1, Vec2 p2, double rx, double ry, double cos_phi, double sin_phi, bool large,
                     bool sweep) {
  // F.6.5.1: the midpoint frame, rotated by -phi.
  const Vec2 h = 0.5 * (p1 - p2);
  const Vec2 q{cos_phi * h.x + sin_phi * h.y, -sin_phi * h.x + cos_phi * h.y};
  // F.6.6.2-3: radii too small to reach both end points grow, keeping their ratio.
  const double lambda = std::pow(q.x / rx, 2) + std::pow(q.y / ry, 2);
  rx *= std::max(1.0, std::sqrt(lambda));
  ry *= std::max(1.0, std::sqrt(lambda));
  // F.6.5.2, its radicand divided by rx^2 ry^2 (no overflow for large radii): (1 - lambda) / lambda,
  // which is 0 for radii that had to grow (rounding could leave it slightly negative).
  const double root = (large != sweep ? 1 : -1) * std::sqrt(std::max(0.0, (1 - lambda) / lambda));
  const Vec2 cq{root * rx * q.y / ry, -root * ry * q.x / rx};
  // F.6.5.3: back to user space.
  const Vec2 centre = Vec2{cos_phi * cq.x - sin_phi * cq.y, sin_phi * cq.x + cos_phi * cq.y} + 0.5 * (p1 + p2);
  // F.6.5.5-6: start angle and sweep, whose sign the sweep flag sets.
  const Vec2 from{(q.x - cq.x) / rx, (q.y - cq.y) / ry}, to{(-q.x - cq.x) / rx, (-q.y - cq.y) / ry};
  double delta = angle_between(from, to);
  if (!sweep && delta > 0) delta -= 2 * std::numbers::pi;
  if (sweep && delta < 0) delta += 2 * std::numbers::pi;
  return {centre, rx, ry, angle_between({1, 0}, from), delta};
}

// Draws the `d` attribute of one path: each subpath becomes a polyline of the pen's lines.
class PathReader {
 public:
  PathReader(std::string_view d, Pen& pen) : s_(d), pen_(pen) {}

  void read() {
    if (s_.at_end()) return;  // an empty path draws nothing (section 8.3.9)
    if (std::toupper(static_cast<unsigned char>(s_.peek())) != 'M')
      throw s_.unexpected("path data must start with a moveto (M or m)");
    while (!s_.at_end()) command();
    pen_.finish(false);
  }

 private:
  void command() {
    const char letter = s_.peek();
    const int count = arity(letter);
    if (count < 0) throw s_.unexpected("expected a command letter (M L H V C S Q T A Z)");
    s_.take();
    if (count == 0) {
      close();
      return;
    }
    // A command's numbers may repeat it (section 8.3.2); after a moveto they are linetos.
    char current = letter;
    int sets = 0;
    do {
      std::array<double, 7> v{};
      read_set(letter, count, sets, v);
      draw(current, v);
      previous_ = static_cast<char>(std::toupper(static_cast<unsigned char>(current)));
      if (current == 'M' || current == 'm') current = current == 'M' ? 'L' : 'l';
      ++sets;
    } while (s_.at_number());
  }

  void read_set(char letter, int count, int sets, std::array<double, 7>& v) {
    const bool arc = std::toupper(static_cast<unsigned char>(letter)) == 'A';
    for (int i = 0; i < count; ++i) {
      if (!s_.at_number()) {
        if (!s_.at_end() && arity(s_.peek()) < 0) throw s_.unexpected("expected a number");
        const std::string found = std::to_string(sets * count + i);
        throw Malformed("command " + quoted(letter) + " needs " + (sets == 0 ? "" : "a multiple of ") +
                        std::to_string(count) + " numbers, found " + found);
      }
      v[i] = arc && (i == 3 || i == 4) ? s_.flag() : s_.number();
    }
  }

  Vec2 at(const std::array<double, 7>& v, int i, bool relative) const {
    return relative ? cur_ + Vec2{v[i], v[i + 1]} : Vec2{v[i], v[i + 1]};
  }

  // S and T reflect the previous curve's last control point about the current point, when the
  // previous command was of their kind (section 8.3.6, 8.3.7); else they start at the current point.
  Vec2 reflected(char cubic_or_quadratic, char smooth) const {
    return previous_ == cubic_or_quadratic || previous_ == smooth ? 2 * cur_ - control_ : cur_;
  }

  void draw(char command, const std::array<double, 7>& v) {
    const bool rel = std::islower(static_cast<unsigned char>(command));
    switch (std::toupper(static_cast<unsigned char>(command))) {
      case 'M': return move(at(v, 0, rel));
      case 'L': return line(at(v, 0, rel));
      case 'H': return line({rel ? cur_.x + v[0] : v[0], cur_.y});
      case 'V': return line({cur_.x, rel ? cur_.y + v[0] : v[0]});
      case 'C': return cubic(at(v, 0, rel), at(v, 2, rel), at(v, 4, rel));
      case 'S': return cubic(reflected('C', 'S'), at(v, 0, rel), at(v, 2, rel));
      case 'Q': return quadratic(at(v, 0, rel), at(v, 2, rel));
      case 'T': return quadratic(reflected('Q', 'T'), at(v, 0, rel));
      case 'A': return arc(v, at(v, 5, rel));
    }
  }

  void move(Vec2 p) {
    pen_.finish(false);
    pen_.trace.to(pen_.world(p));
    cur_ = start_ = p;
    open_ = true;
  }
  // After Z a drawing command starts a new subpath at the closed one's start (section 8.3.3).
  void reopen() {
    if (open_) return;
    pen_.trace.to(pen_.world(start_));
    open_ = true;
  }
  void line(Vec2 p) {
    reopen();
    pen_.trace.to(pen_.world(p));
    cur_ = p;
  }
  void cubic(Vec2 c1, Vec2 c2, Vec2 p) {
    reopen();
    cubic_to(pen_.trace, pen_.world(cur_), pen_.world(c1), pen_.world(c2), pen_.world(p));
    control_ = c2;
    cur_ = p;
  }
  void quadratic(Vec2 c, Vec2 p) {
    reopen();
    quadratic_to(pen_.trace, pen_.world(cur_), pen_.world(c), pen_.world(p));
    control_ = c;
    cur_ = p;
  }
  // Appendix F.6.2: equal end points draw nothing, a zero radius draws a line, radii count unsigned.
  void arc(const std::array<double, 7>& v, Vec2 p) {
    reopen();
    if (p.x == cur_.x && p.y == cur_.y) return;
    const double rx = std::abs(v[0]), ry = std::abs(v[1]);
    if (rx == 0 || ry == 0) return line(p);
    const auto [c, s] = cos_sin_degrees(v[2]);
    const CentreArc a = centre_arc(cur_, p, rx, ry, c, s, v[3] != 0, v[4] != 0);
    const Ellipse e = world_ellipse(pen_.to_world, a.centre, {a.rx * c, a.rx * s}, {-a.ry * s, a.ry * c});
    arc_interior(pen_.trace, e, a.start, a.sweep);
    line(p);
  }
  void close() {
    if (open_) pen_.finish(true);
    open_ = false;
    cur_ = start_;
    previous_ = 'Z';
  }

  Scanner s_;
  Pen& pen_;
  Vec2 cur_, start_, control_;
  char previous_ = 0;  // the last command drawn, upper case
  bool open_ = false;  // a subpath is being drawn
};

// ---- Basic shapes (chapter 9) ------------------------------------------------------------------

std::optional<double> length_attribute(pugi::xml_node n, const char* name) {
  const pugi::xml_attribute a = n.attribute(name);
  if (!a) return std::nullopt;
  try {
    return length_value(a.value());
  } catch (const Malformed& e) {
    throw Malformed(std::string(name) + " " + excerpt(a.value()) + ": " + e.what());
  }
}

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

void read_path(pugi::xml_node n, Pen& pen) {
  const char* d = n.attribute("d").value();
  try {
    PathReader(d, pen).read();
  } catch (const Malformed& e) {
    throw Malformed(std::string("d ") + excerpt(d) + ": " + e.what());
  }
}

// ---- The document ------------------------------------------------------------------------------

std::string_view prefix_of(std::string_view name) {
  const size_t colon = name.find(':');
  return colon == std::string_view::npos ? std::string_view() : name.substr(0, colon);
}
std::string_view local_of(std::string_view name) {
  const size_t colon = name.find(':');
  return colon == std::string_view::npos ? name : name.substr(colon + 1);
}

// The namespace bound to `prefix` where n stands (Namespaces in XML 1.0), or nullptr.
const char* namespace_at(pugi::xml_node n, std::string_view prefix) {
  const std::string declaration = prefix.empty() ? "xmlns" : "xmlns:" + std::string(prefix);
  for (; n; n = n.parent())
    if (const pugi::xml_attribute a = n.attribute(declaration.c_str())) return a.value();
  return nullptr;
}

// A file that declares no namespace at all (hand-written) is taken as SVG while it uses no prefix.
bool in_svg_namespace(pugi::xml_node n) {
  const std::string_view prefix = prefix_of(n.name());
  const char* uri = namespace_at(n, prefix);
  return uri ? uri == svg_namespace : prefix.empty();
}

bool is_layer(pugi::xml_node g) {
  for (const pugi::xml_attribute a : g.attributes()) {
    const std::string_view name = a.name();
    if (local_of(name) != "groupmode" || prefix_of(name).empty()) continue;
    const char* uri = namespace_at(g, prefix_of(name));
    if (uri && uri == inkscape_namespace && std::string_view(a.value()) == "layer") return true;
  }
  return false;
}

std::string_view trimmed(std::string_view s) {
  const size_t first = s.find_first_not_of(" \t\n\r");
  if (first == std::string_view::npos) return {};
  return s.substr(first, s.find_last_not_of(" \t\n\r") - first + 1);
}

bool equals_ignoring_case(std::string_view a, std::string_view b) {
  return std::equal(a.begin(), a.end(), b.begin(), b.end(), [](char x, char y) {
    return std::tolower(static_cast<unsigned char>(x)) == std::tolower(static_cast<unsigned char>(y));
  });
}

// display="none", or display:none among the style attribute's declarations (CSS keywords and
// property names are case-insensitive; "!important" does not change the value).
bool hidden(pugi::xml_node n) {
  if (equals_ignoring_case(trimmed(n.attribute("display").value()), "none")) return true;
  std::string_view style = n.attribute("style").value();
  while (!style.empty()) {
    const size_t end = std::min(style.find(';'), style.size());
    const std::string_view declaration = style.substr(0, end);
    style.remove_prefix(std::min(end + 1, style.size()));
    const size_t colon = declaration.find(':');
    if (colon == std::string_view::npos) continue;
    std::string_view value = trimmed(declaration.substr(colon + 1));
    value = trimmed(value.substr(0, value.find('!')));
    if (equals_ignoring_case(trimmed(declaration.substr(0, colon)), "display") && equals_ignoring_case(value, "none"))
      return true;
  }
  return false;
}

// SVG 1.1 elements that never draw where they stand (definitions, descriptions, resources) or
// only animate what does.
bool draws_nothing(std::string_view name) {
  static constexpr std::array<std::string_view, 26> names{
      "defs", "metadata", "title", "desc", "style", "script", "symbol", "marker", "clipPath",
      "mask", "pattern", "linearGradient", "radialGradient", "filter", "font", "font-face",
      "color-profile", "cursor", "view", "animate", "animateColor", "animateMotion",
      "animateTransform", "set", "altGlyphDef", "mpath"};
  return std::find(names.begin(), names.end(), name) != names.end();
}

using ShapeReader = void (*)(pugi::xml_node, Pen&);

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

// "path 'flight3'", or the tag alone when the element has no id.
std::string describe(pugi::xml_node n) {
  const std::string id = n.attribute("id").value();
  return std::string(n.name()) + (id.empty() ? "" : " '" + id + "'");
}

// What encloses an element: the map to the world and its group.
struct Scope {
  Affine to_world;
  std::optional<std::string> group;  // the nearest enclosing <g> with an id that is no layer
  std::string layer;                 // the nearest enclosing layer's id
  const std::string& group_id() const { return group ? *group : layer; }
};

class Reader {
 public:
  Reader(std::string path, std::string text, const SvgPlacement& placement)
      : path_(std::move(path)), text_(std::move(text)), placement_(placement), budget_(placement.tolerance) {}

  std::vector<SvgGroup> read() {
    if (text_.find('\0') != std::string::npos)
      throw InputError(Location{path_, 0, ""}, "is not UTF-8 text (it holds NUL bytes; UTF-16 is not read)");
    pugi::xml_document doc;
    const pugi::xml_parse_result parsed =
        doc.load_buffer(text_.data(), text_.size(), pugi::parse_default, pugi::encoding_utf8);
    if (!parsed) fail_at(parsed.offset, std::string("not well-formed XML: ") + parsed.description());
    const pugi::xml_node root = the_root(doc);
    if (!hidden(root)) read_children(root, Scope{placed(root), std::nullopt, ""}, 0);
    if (groups_.empty())
      throw InputError(Location{path_, 0, ""},
                       "holds no path, line, polyline, polygon, rect, circle or ellipse (none drawn, visible and "
                       "longer than a point)");
    return std::move(groups_);
  }

 private:
  [[noreturn]] void fail_at(ptrdiff_t offset, const std::string& message) const {
    const auto end = text_.begin() + std::clamp<ptrdiff_t>(offset, 0, static_cast<ptrdiff_t>(text_.size()));
    throw InputError(Location{path_, 1 + static_cast<int>(std::count(text_.begin(), end, '\n')), ""}, message);
  }
  [[noreturn]] void fail(pugi::xml_node n, const std::string& message) const {
    fail_at(n.offset_debug(), describe(n) + ": " + message);
  }

  pugi::xml_node the_root(const pugi::xml_document& doc) const {
    const pugi::xml_node root = doc.document_element();
    for (pugi::xml_node n = root.next_sibling(); n; n = n.next_sibling())
      if (n.type() == pugi::node_element) fail_at(n.offset_debug(), "not well-formed XML: a second root element");
    if (!in_svg_namespace(root) || local_of(root.name()) != "svg")
      fail(root, "the root element is not an <svg> of the SVG namespace (" + std::string(svg_namespace) + ")");
    if (root.attribute("transform")) fail(root, "a transform on the root <svg> is not read: put it on a <g>");
    return root;
  }

  // The map from the root's user units to the world (see read_svg_walls).
  Affine placed(pugi::xml_node root) const {
    double left = 0, bottom = 0;
    try {
      if (const pugi::xml_attribute box = root.attribute("viewBox")) {
        const std::vector<double> v = number_list(box.value());
        if (v.size() != 4) throw Malformed("viewBox needs 4 numbers, found " + std::to_string(v.size()));
        if (!(v[2] > 0 && v[3] > 0)) throw Malformed("viewBox width and height must be > 0");
        left = v[0];
        bottom = v[1] + v[3];
      } else {
        bottom = length_attribute(root, "height").value_or(0);
      }
    } catch (const Malformed& e) {
      fail(root, e.what());
    }
    const double s = placement_.scale;
    return {s, 0, 0, -s, placement_.offset.x - s * left, placement_.offset.y + s * bottom};
  }

  void read_children(pugi::xml_node parent, const Scope& scope, int depth) {
    for (const pugi::xml_node n : parent.children()) {
      if (n.type() != pugi::node_element || !in_svg_namespace(n) || hidden(n)) continue;
      const std::string_view name = local_of(n.name());
      if (draws_nothing(name)) continue;
      if (name == "g") {
        if (depth >= max_depth) fail(n, "groups are nested more than 1000 deep");
        read_children(n, inside(n, scope), depth + 1);
      } else if (const ShapeReader reader = shape_reader(name)) {
        read_shape(n, reader, scope);
      } else {
        fail(n, "is not read: only path, line, polyline, polygon, rect, circle and ellipse elements (in g groups) are");
      }
    }
  }

  Scope inside(pugi::xml_node g, const Scope& outer) const {
    Scope scope = outer;
    scope.to_world = with_transform(g, outer.to_world);
    const std::string id = g.attribute("id").value();
    if (is_layer(g))
      scope.layer = id;
    else if (!id.empty())
      scope.group = id;
    return scope;
  }

  Affine with_transform(pugi::xml_node n, const Affine& outer) const {
    const pugi::xml_attribute t = n.attribute("transform");
    if (!t) return outer;
    try {
      return composed(outer, t.value());
    } catch (const Malformed& e) {
      fail(n, "transform " + excerpt(t.value()) + ": " + e.what());
    }
  }

  void read_shape(pugi::xml_node n, ShapeReader reader, const Scope& scope) {
    Pen pen{with_transform(n, scope.to_world), Trace(budget_, placement_.tolerance), {}};
    try {
      reader(n, pen);
    } catch (const Malformed& e) {
      fail(n, e.what());
    }
    if (!pen.lines.empty()) add(scope.group_id(), std::move(pen.lines));
  }

  // A group is made when it first gets lines, so that every group returned has some.
  void add(const std::string& id, std::vector<SvgPolyline> lines) {
    const auto [at, fresh] = index_.try_emplace(id, groups_.size());
    if (fresh) groups_.push_back(SvgGroup{id, {}});
    std::vector<SvgPolyline>& all = groups_[at->second].lines;
    std::move(lines.begin(), lines.end(), std::back_inserter(all));
  }

  std::string path_;
  std::string text_;
  SvgPlacement placement_;
  Budget budget_;
  std::vector<SvgGroup> groups_;
  std::map<std::string, size_t> index_;
};

// A drawing is a regular file of at most 64 MiB: a device (/dev/zero) or a pipe would never end.
std::string read_file(const std::string& path) {
  std::error_code ec;
  const auto status = std::filesystem::status(path, ec);
  if (!ec && std::filesystem::exists(status) && !std::filesystem::is_regular_file(status))
    throw InputError(Location{path, 0, ""}, "is not a regular file");
  constexpr std::uintmax_t largest = std::uintmax_t{64} << 20;
  if (!ec && std::filesystem::is_regular_file(status) && std::filesystem::file_size(path, ec) > largest)
    throw InputError(Location{path, 0, ""}, "is larger than 64 MiB: not a drawing of walls");
  std::ifstream in(path, std::ios::binary);
  try {
    if (in) return std::string(std::istreambuf_iterator<char>(in), {});
  } catch (const std::ios_base::failure&) {
    // a directory opens but cannot be read; errno says why
  }
  throw InputError(Location{path, 0, ""}, std::string("cannot be read: ") + std::strerror(errno));
}

void check_placement(const std::string& path, const SvgPlacement& p) {
  const auto refuse = [&](const std::string& what) { throw InputError(Location{path, 0, ""}, what); };
  if (!(std::isfinite(p.scale) && p.scale > 0))
    refuse("the scale must be a finite number > 0 (metres per user unit), got " + message_number(p.scale));
  if (!(std::isfinite(p.tolerance) && p.tolerance > 0))
    refuse("the tolerance must be a finite number > 0 (metres), got " + message_number(p.tolerance));
  if (!(std::isfinite(p.offset.x) && std::isfinite(p.offset.y))) refuse("the offset must be finite");
}

}  // namespace

std::vector<SvgGroup> read_svg_walls(const std::string& path, const SvgPlacement& placement) {
  check_placement(path, placement);
  return Reader(path, read_file(path), placement).read();
}

}  // namespace kiln
