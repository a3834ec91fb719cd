// Path data (chapter 8): M L H V C S Q T A Z, absolute and relative, implicit repeats; arcs in
// endpoint form converted to centre form (appendix F.6).
#include "src/scene/svg_parts.h"

#include <algorithm>
#include <cctype>
#include <numbers>

namespace kiln::svg {

namespace {

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

}  // namespace

void read_path(pugi::xml_node n, Pen& pen) {
  const char* d = n.attribute("d").value();
  try {
    PathReader(d, pen).read();
  } catch (const Malformed& e) {
    throw Malformed(std::string("d ") + excerpt(d) + ": " + e.what());
  }
}

}  // namespace kiln::svg
