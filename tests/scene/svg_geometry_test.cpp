// Walls from SVG drawings: world placement, transforms, path commands, curve flattening within the
// tolerance, groups and layers, and the errors a user can act on.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <functional>
#include <numbers>
#include <string>
#include <system_error>
#include <vector>

#include <unistd.h>

#include "src/base/error.h"
#include "src/scene/svg_geometry.h"
#include "src/scene/wall_geometry.h"

using namespace kiln;

namespace {

constexpr double pi = std::numbers::pi;

// A directory of this test process (ctest runs test cases in parallel), removed when it exits.
struct TempDir {
  std::filesystem::path path =
      std::filesystem::temp_directory_path() / ("kiln_svg_test_" + std::to_string(::getpid()));
  TempDir() { std::filesystem::create_directories(path); }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
};

// Writes `text` as a file of this test run and returns its path.
std::string svg_file(const std::string& name, const std::string& text) {
  static const TempDir dir;
  const std::filesystem::path file = dir.path / name;
  std::ofstream(file, std::ios::binary) << text;
  return file.string();
}

// A document holding `body`; the first line is the <svg> tag, so `body` starts on line 2.
std::string svg(const std::string& body, const std::string& root_attributes = R"(viewBox="0 0 100 100")") {
  return R"(<svg xmlns="http://www.w3.org/2000/svg" )" + root_attributes + ">\n" + body + "\n</svg>\n";
}

std::vector<SvgGroup> read(const std::string& name, const std::string& text, const SvgPlacement& placement) {
  return read_svg_walls(svg_file(name, text), placement);
}

// The lines of a document without a viewBox at unit scale: world = (x, -y).
std::vector<SvgPolyline> lines_of(const std::string& name, const std::string& body, double tolerance = 1e-3) {
  const auto groups = read(name, svg(body, ""), {1, {0, 0}, tolerance});
  REQUIRE(groups.size() == 1);
  return groups[0].lines;
}

std::string error_of(const std::string& name, const std::string& text,
                     const SvgPlacement& placement = {1, {0, 0}, 1e-3}) {
  try {
    read(name, text, placement);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

void check_same(const std::vector<SvgPolyline>& a, const std::vector<SvgPolyline>& b) {
  REQUIRE(a.size() == b.size());
  for (size_t i = 0; i < a.size(); ++i) {
    CHECK(a[i].closed == b[i].closed);
    REQUIRE(a[i].points.size() == b[i].points.size());
    for (size_t k = 0; k < a[i].points.size(); ++k) CHECK(norm(a[i].points[k] - b[i].points[k]) < 1e-12);
  }
}

void check_points(const SvgPolyline& line, const std::vector<Vec2>& expected, double within = 1e-12) {
  REQUIRE(line.points.size() == expected.size());
  for (size_t k = 0; k < expected.size(); ++k) {
    INFO("point " << k);
    CHECK(norm(line.points[k] - expected[k]) < within);
  }
}

// Largest distance from the curve c(t), t in [t0, t1], to the chord from a to b (dense sampling).
double chord_deviation(const std::function<Vec2(double)>& c, double t0, double t1, Vec2 a, Vec2 b) {
  double worst = 0;
  for (int k = 0; k <= 200; ++k) worst = std::max(worst, distance_to_segment(c(t0 + (t1 - t0) * k / 200), a, b));
  return worst;
}

bool contains(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

}  // namespace

TEST_CASE("a square of relative commands in a translated, rotated group lands on its 4 world corners", "[svg]") {
  const SvgPlacement placement{0.01, {1, 2}, 1e-6};
  const std::string body =
      R"svg(<g id="box" transform="translate(50,20) rotate(30)"><path d="m 10,10 h 20 v 20 h -20 z"/></g>)svg";
  const auto groups = read("square.svg", svg(body, R"(viewBox="0 0 200 100")"), placement);
  REQUIRE(groups.size() == 1);
  CHECK(groups[0].id == "box");
  REQUIRE(groups[0].lines.size() == 1);
  const SvgPolyline& square = groups[0].lines[0];
  CHECK(square.closed);
  std::vector<Vec2> expected;
  const double c = std::cos(pi / 6), s = std::sin(pi / 6);
  for (Vec2 q : {Vec2{10, 10}, Vec2{30, 10}, Vec2{30, 30}, Vec2{10, 30}}) {
    const Vec2 user{50 + c * q.x - s * q.y, 20 + s * q.x + c * q.y};
    expected.push_back({1 + 0.01 * (user.x - 0), 2 + 0.01 * (100 - user.y)});
  }
  check_points(square, expected);
}

TEST_CASE("a circle is flattened to the sagitta optimum with every chord within the tolerance", "[svg]") {
  const double T = 1e-6;
  const auto groups = read("circle.svg", svg(R"(<circle cx="40" cy="30" r="20"/>)"), {1e-3, {0.5, -0.25}, T});
  const SvgPolyline& circle = groups.at(0).lines.at(0);
  CHECK(circle.closed);
  const Vec2 centre{0.5 + 0.04, -0.25 + 1e-3 * (100 - 30)};
  const double R = 0.02;
  const size_t n = circle.points.size();
  for (size_t k = 0; k < n; ++k) {
    CHECK(std::abs(norm(circle.points[k] - centre) - R) < 1e-12 * R);
    const double deviation = R - norm(0.5 * (circle.points[k] + circle.points[(k + 1) % n]) - centre);
    CHECK(deviation >= 0);
    CHECK(deviation <= T * (1 + 1e-9));
  }
  const double optimum = std::ceil(2 * pi / (2 * std::acos(1 - T / R)));
  CHECK(std::abs(static_cast<double>(n) - optimum) <= 1);
}

TEST_CASE("an ellipse under skew and scale stays on its transformed ellipse with chords within the tolerance", "[svg]") {
  const double T = 1e-5, scale = 2e-3;
  const auto groups = read("ellipse.svg",
                           svg(R"svg(<ellipse cx="30" cy="40" rx="20" ry="8" transform="skewX(30) scale(1.5,0.8)"/>)svg"),
                           {scale, {0, 0}, T});
  const SvgPolyline& ellipse = groups.at(0).lines.at(0);
  CHECK(ellipse.closed);
  const double tan30 = std::tan(pi / 6);
  // World from the ellipse's own frame, and the parameter of a world point.
  const auto world = [&](double t) {
    const Vec2 q{30 + 20 * std::cos(t), 40 + 8 * std::sin(t)};
    const Vec2 user{1.5 * q.x + 0.8 * tan30 * q.y, 0.8 * q.y};
    return Vec2{scale * user.x, scale * (100 - user.y)};
  };
  const auto own = [&](Vec2 w) {
    const Vec2 user{w.x / scale, 100 - w.y / scale};
    const double y = user.y / 0.8;
    return Vec2{(user.x - tan30 * user.y) / 1.5, y};
  };
  const auto implicit = [&](Vec2 w) {
    const Vec2 q = own(w);
    return std::pow((q.x - 30) / 20, 2) + std::pow((q.y - 40) / 8, 2);
  };
  const size_t n = ellipse.points.size();
  for (size_t k = 0; k < n; ++k) {
    const Vec2 a = ellipse.points[k], b = ellipse.points[(k + 1) % n];
    CHECK(std::abs(implicit(a) - 1) < 1e-9);
    CHECK(implicit(0.5 * (a + b)) <= 1);  // chords run inside the convex curve
    const Vec2 qa = own(a), qb = own(b);
    const double ta = std::atan2((qa.y - 40) / 8, (qa.x - 30) / 20);
    const double dt = std::remainder(std::atan2((qb.y - 40) / 8, (qb.x - 30) / 20) - ta, 2 * pi);
    CHECK(dt > 0);
    CHECK(chord_deviation(world, ta, ta + dt, a, b) <= T * (1 + 1e-9));
  }
  // Not absurdly many: no more than twice the count for a circle of radius `reach`, the sum of two
  // conjugate semi-diameters (at least the semi-major axis).
  const double reach = norm(world(0) - world(pi)) / 2 + norm(world(pi / 2) - world(-pi / 2)) / 2;
  CHECK(static_cast<double>(n) <= 2 * std::ceil(2 * pi / (2 * std::acos(1 - T / reach))));
}

TEST_CASE("a cubic Bezier is flattened to points on the exact curve with every chord within the tolerance", "[svg]") {
  const double T = 1e-6, scale = 1e-3;
  const auto groups = read("cubic.svg", svg(R"(<path d="M 10 80 C 40 10, 65 10, 95 80"/>)"), {scale, {0, 0}, T});
  const SvgPolyline& curve = groups.at(0).lines.at(0);
  CHECK_FALSE(curve.closed);
  const std::array<Vec2, 4> p{{{10, 80}, {40, 10}, {65, 10}, {95, 80}}};
  const auto at = [&](double t) {
    const double s = 1 - t;
    const Vec2 user = s * s * s * p[0] + 3 * s * s * t * p[1] + 3 * s * t * t * p[2] + t * t * t * p[3];
    return Vec2{scale * user.x, scale * (100 - user.y)};
  };
  const auto tangent = [&](double t) { return (1 / 2e-7) * (at(t + 1e-7) - at(t - 1e-7)); };
  // The parameter of each point: the nearest of a dense sampling, polished by Newton steps.
  std::vector<double> ts;
  for (const Vec2& q : curve.points) {
    double t = 0;
    for (int k = 0; k <= 4000; ++k)
      if (norm(at(k / 4000.0) - q) < norm(at(t) - q)) t = k / 4000.0;
    for (int step = 0; step < 20; ++step) {
      const Vec2 d = tangent(t);
      t = std::clamp(t - dot(at(t) - q, d) / dot(d, d), 0.0, 1.0);
    }
    CHECK(norm(at(t) - q) < 1e-12);
    ts.push_back(t);
  }
  CHECK(ts.front() < 1e-9);
  CHECK(ts.back() > 1 - 1e-9);
  double worst = 0;
  for (size_t k = 0; k + 1 < ts.size(); ++k) {
    CHECK(ts[k + 1] > ts[k]);
    worst = std::max(worst, chord_deviation(at, ts[k], ts[k + 1], curve.points[k], curve.points[k + 1]));
  }
  CHECK(worst <= T * (1 + 1e-9));
  CHECK(worst >= T / 4);  // the chords use the tolerance: not absurdly many points
}

TEST_CASE("an arc command follows the circle its large-arc and sweep flags select", "[svg]") {
  struct Case {
    const char* flags;
    Vec2 centre;   // user units
    double sweep;  // user-space angle, radians (positive: the positive angle direction)
  };
  for (const Case& c : {Case{"0 1", {0, 0}, pi / 2}, Case{"1 1", {10, 10}, 3 * pi / 2}, Case{"0 0", {10, 10}, -pi / 2},
                        Case{"1 0", {0, 0}, -3 * pi / 2}}) {
    INFO("flags " << c.flags);
    const auto lines = lines_of("arc.svg", std::string(R"(<path d="M 10 0 A 10 10 0 )") + c.flags + R"( 0 10"/>)", 1e-4);
    const SvgPolyline& arc = lines.at(0);
    const Vec2 centre{c.centre.x, -c.centre.y};
    double swept = 0;
    for (size_t k = 0; k < arc.points.size(); ++k) {
      CHECK(std::abs(norm(arc.points[k] - centre) - 10) < 1e-12);
      if (k > 0) {
        const Vec2 a = arc.points[k - 1] - centre, b = arc.points[k] - centre;
        swept += std::atan2(cross(a, b), dot(a, b));
      }
    }
    CHECK(swept == Approx(-c.sweep).margin(1e-12));  // the world's y is flipped
    check_points({{arc.points.front(), arc.points.back()}}, {{10, 0}, {0, -10}});
  }
}

TEST_CASE("an arc whose radii cannot reach its end point is scaled up to a half ellipse (F.6.6)", "[svg]") {
  const SvgPolyline arc = lines_of("small_arc.svg", R"(<path d="M 0 0 A 1 1 0 0 1 10 0"/>)", 1e-4).at(0);
  for (const Vec2& q : arc.points) CHECK(std::abs(norm(q - Vec2{5, 0}) - 5) < 1e-12);
  CHECK(arc.points.size() > 10);
}

TEST_CASE("H V S T shorthands and relative forms draw what their explicit forms draw", "[svg]") {
  const auto path = [](const std::string& d) {
    static int count = 0;
    return lines_of("shorthand" + std::to_string(++count) + ".svg", R"(<path d=")" + d + R"("/>)");
  };
  check_same(path("M0 0 H 10 V 10 h -5 v -5"), path("M0 0 L10 0 L10 10 L5 10 L5 5"));
  check_same(path("M0 0 C 0 10 10 10 10 0 S 20 -10 20 0"), path("M0 0 C 0 10 10 10 10 0 C 10 -10 20 -10 20 0"));
  check_same(path("m0 0 c 0 10 10 10 10 0 s 10 -10 10 0"), path("M0 0 C 0 10 10 10 10 0 C 10 -10 20 -10 20 0"));
  check_same(path("M0 0 Q 5 10 10 0 T 20 0"), path("M0 0 Q 5 10 10 0 Q 15 -10 20 0"));
  check_same(path("m0 0 q 5 10 10 0 t 10 0"), path("M0 0 Q 5 10 10 0 Q 15 -10 20 0"));
  // After a command of another kind, S and T start their curve at the current point.
  check_same(path("M0 0 L 5 5 S 10 10 15 5"), path("M0 0 L 5 5 C 5 5 10 10 15 5"));
  check_same(path("M0 0 L 5 5 T 15 5"), path("M0 0 L 5 5 Q 5 5 15 5"));
}

TEST_CASE("numbers after a moveto are linetos and every subpath is a polyline of its own", "[svg]") {
  check_points(lines_of("implicit_abs.svg", R"(<path d="M 0 0 10 0 10 10"/>)").at(0), {{0, 0}, {10, 0}, {10, -10}});
  check_points(lines_of("implicit_rel.svg", R"(<path d="m 1 1 2 0 0 2"/>)").at(0), {{1, -1}, {3, -1}, {3, -3}});
  const auto lines =
      lines_of("subpaths.svg", R"(<path d="M0 0 L1 0 L1 1 Z M 5 5 l 1 0 l 0 1 z m 2 2 l 1 0 l 0 1 z l 0 2"/>)");
  REQUIRE(lines.size() == 4);
  check_points(lines[0], {{0, 0}, {1, 0}, {1, -1}});
  check_points(lines[1], {{5, -5}, {6, -5}, {6, -6}});
  check_points(lines[2], {{7, -7}, {8, -7}, {8, -8}});  // m after z is relative to the closed subpath's start
  check_points(lines[3], {{7, -7}, {7, -9}});            // a line after z starts at that start too
  CHECK(lines[0].closed);
  CHECK(lines[1].closed);
  CHECK(lines[2].closed);
  CHECK_FALSE(lines[3].closed);
}

TEST_CASE("repeated points are dropped and a closed outline does not repeat its first point", "[svg]") {
  const auto lines = lines_of("repeats.svg", R"(<path d="M 0 0 L 0 0 L 1 0 1 0 L 1 1 L 0 0 Z M 5 0 L 6 0 Z"/>
<polygon points="0 0 2 0 2 2 0 0"/>)");
  REQUIRE(lines.size() == 3);
  check_points(lines[0], {{0, 0}, {1, 0}, {1, -1}});
  CHECK(lines[0].closed);
  check_points(lines[1], {{5, 0}, {6, 0}});  // closing two points would only retrace their segment
  CHECK_FALSE(lines[1].closed);
  check_points(lines[2], {{0, 0}, {2, 0}, {2, -2}});
  CHECK(lines[2].closed);
}

TEST_CASE("path numbers may run together: exponents, .5.5, -1-2 and arc flags without separators", "[svg]") {
  check_points(lines_of("numbers.svg", R"(<path d="M.5.5L1e-3-2l-1-2.5E1+1,+2"/>)").at(0),
               {{0.5, -0.5}, {0.001, 2}, {-0.999, 27}, {0.001, 25}});
  // "a1 1 0 011 1": rx ry rotation, then the flags 0 and 1 and the end point 1 1.
  const SvgPolyline arc = lines_of("flags.svg", R"(<path d="M0 0a1 1 0 011 1"/>)", 1e-4).at(0);
  for (const Vec2& q : arc.points) CHECK(std::abs(norm(q - Vec2{0, -1}) - 1) < 1e-12);
  check_points({{arc.points.front(), arc.points.back()}}, {{0, 0}, {1, -1}});
}

TEST_CASE("line, polyline, polygon and rect come back as drawn, rounded corners within the tolerance", "[svg]") {
  const auto lines = lines_of("shapes.svg", R"(<line x1="1" y1="2" x2="3" y2="4"/>
<polyline points="0,0 1,0 1,1"/>
<polygon points="0 0 1 0 1 1"/>
<rect x="1" y="2" width="3" height="4"/>)");
  REQUIRE(lines.size() == 4);
  check_points(lines[0], {{1, -2}, {3, -4}});
  check_points(lines[1], {{0, 0}, {1, 0}, {1, -1}});
  check_points(lines[2], {{0, 0}, {1, 0}, {1, -1}});
  check_points(lines[3], {{1, -2}, {4, -2}, {4, -6}, {1, -6}});
  CHECK_FALSE(lines[0].closed);
  CHECK_FALSE(lines[1].closed);
  CHECK(lines[2].closed);
  CHECK(lines[3].closed);

  const double T = 1e-4;
  const SvgPolyline round = lines_of("rounded.svg", R"(<rect width="10" height="6" rx="2"/>)", T).at(0);
  CHECK(round.closed);
  CHECK(norm(round.points.front() - Vec2{2, 0}) == 0);
  // Signed distance to the rounded rectangle (centre (5, -3), half sides 5 x 3, corner radius 2).
  const auto signed_distance = [](Vec2 p) {
    const Vec2 q{std::abs(p.x - 5) - 3, std::abs(p.y + 3) - 1};
    return norm({std::max(q.x, 0.0), std::max(q.y, 0.0)}) + std::min(std::max(q.x, q.y), 0.0) - 2;
  };
  const size_t n = round.points.size();
  for (size_t k = 0; k < n; ++k) {
    const Vec2 a = round.points[k], b = round.points[(k + 1) % n];
    CHECK(std::abs(signed_distance(a)) < 1e-12);
    CHECK(signed_distance(0.5 * (a + b)) <= 1e-12);
    CHECK(signed_distance(0.5 * (a + b)) >= -T * (1 + 1e-9));
  }
}

TEST_CASE("an Inkscape drawing gives one group per id'd group, else per layer, in document order", "[svg]") {
  const std::string file = std::string(KILN_CASES_DIR) + "/../tests/data/svg/inkscape_layers.svg";
  const auto groups = read_svg_walls(file, {1e-3, {0, 0}, 1e-6});
  std::vector<std::string> ids;
  for (const SvgGroup& g : groups) ids.push_back(g.id);
  // The hidden layer (text and path) and the path in defs draw nothing; the sublayer's path
  // belongs to the enclosing group "baffles", the drum (in a group without id) to its layer.
  CHECK(ids == std::vector<std::string>{"hopper", "layer1", "layer3", "baffles", ""});
  REQUIRE(groups.size() == 5);
  check_points(groups[0].lines.at(0), {{0.010, 0.045}, {0.020, 0.015}, {0.040, 0.015}, {0.050, 0.045}});
  check_points(groups[1].lines.at(0), {{0, 0.005}, {0.1, 0.005}});
  const SvgPolyline& drum = groups[2].lines.at(0);
  CHECK(drum.closed);
  for (const Vec2& q : drum.points) CHECK(std::abs(norm(q - Vec2{0.08, 0.025}) - 0.01) < 1e-12);
  check_points(groups[3].lines.at(0), {{0.070, 0.045}, {0.070, 0.040}});
  check_points(groups[4].lines.at(0), {{0, 0.05}, {0.005, 0.05}});
}

TEST_CASE("definitions, descriptions, hidden elements, comments and other namespaces draw nothing", "[svg]") {
  const auto lines = lines_of("ignored.svg", R"(<title>t</title><desc>d</desc><style>path { stroke: red }</style>
<!-- <text>a comment</text> -->
<defs><text id="label">in defs</text><path d="M 0 0 L 1 1"/></defs>
<metadata><text>metadata</text></metadata>
<foo:bar xmlns:foo="urn:example"><path d="M 0 0 L 1 1"/></foo:bar>
<path display="none" d="M 0 0 L 1 1"/>
<text style="fill:red; Display : none !important">hidden</text>
<g style="display:none"><image href="x.png"/></g>
<path d="M 0 0 L 2 0"/>)");
  REQUIRE(lines.size() == 1);
  check_points(lines[0], {{0, 0}, {2, 0}});
}

TEST_CASE("the root's height stands for a missing viewBox and units convert at 96 px per inch", "[svg]") {
  const auto groups = read("height.svg", svg(R"(<path d="M 0 0 L 96 0"/>)", R"(width="2in" height="1in")"),
                           {1e-3, {0, 0}, 1e-6});
  check_points(groups.at(0).lines.at(0), {{0, 0.096}, {0.096, 0.096}});
}

TEST_CASE("malformed XML is refused with the parser's description and its line", "[svg]") {
  const std::string text = svg(R"(<path d="M 0 0 L 1 1">)");
  const std::string error = error_of("malformed.svg", text);
  CHECK(contains(error, "malformed.svg:3: "));
  CHECK(contains(error, "not well-formed XML"));
  CHECK(contains(error, "mismatch"));
  CHECK(contains(error_of("empty.svg", ""), "No document element"));
  CHECK(contains(error_of("html.svg", "<html/>"), "root element is not an <svg> of the SVG namespace"));
}

TEST_CASE("an element that draws but is not read is refused by its tag, id and line", "[svg]") {
  const std::string error = error_of("text.svg", svg("<path d=\"M 0 0 L 1 1\"/>\n<text id=\"label1\">hello</text>"));
  CHECK(contains(error, "text.svg:3: "));
  CHECK(contains(error, "text 'label1'"));
  CHECK(contains(error, "only path, line, polyline, polygon, rect, circle and ellipse"));
  const std::string image = error_of("image.svg", svg("<g><image href=\"x.png\"/></g>"));
  CHECK(contains(image, "image.svg:2: image: is not read"));
}

TEST_CASE("broken path data is refused naming the path, the command and what is wrong", "[svg]") {
  const auto error_in = [](const std::string& d) {
    return error_of("path.svg", svg("\n<path id=\"flight3\" d=\"" + d + "\"/>"));
  };
  const std::string missing = error_in("M 0 0 C 1 2 3 4");
  CHECK(contains(missing, "path.svg:3: "));
  CHECK(contains(missing, "path 'flight3'"));
  CHECK(contains(missing, "command 'C' needs 6 numbers, found 4"));
  CHECK(contains(error_in("M 0 0 C 1 2 3 4 5 6 7 8"), "command 'C' needs a multiple of 6 numbers, found 8"));
  CHECK(contains(error_in("M 0 0 L 1 # 2"), "expected a number, found '#' at character 11"));
  CHECK(contains(error_in("L 0 0"), "must start with a moveto"));
  CHECK(contains(error_in("M 0 0 Z 1 2"), "expected a command letter"));
  CHECK(contains(error_in("M 0 0 A 1 1 0 2 1 5 5"), "arc flag must be 0 or 1, found '2'"));
  CHECK(contains(error_in("M 1e 2"), "exponent without digits"));
  CHECK(contains(error_in("M 0,,0"), "not followed by a number"));
  CHECK(contains(error_in("M 0 0 L 1e999 0"), "'1e999' is beyond the range of double precision"));
  CHECK(contains(error_of("points.svg", svg(R"(<polygon id="p" points="0 0 1 0 1"/>)")), "pairs of numbers, found 5"));
}

TEST_CASE("a malformed or singular transform is refused naming the element and the fault", "[svg]") {
  const auto error_in = [](const std::string& t) {
    return error_of("transform.svg", svg("<g id=\"frame\" transform=\"" + t + "\"><path d=\"M 0 0 L 1 1\"/></g>"));
  };
  CHECK(contains(error_in("rotate(1 2)"),
                 "transform.svg:2: g 'frame': transform \"rotate(1 2)\": transform 'rotate' takes 1 or 3 numbers, found 2"));
  CHECK(contains(error_in("translate(1,2"), "expected ')'"));
  CHECK(contains(error_in("spin(3)"), "unknown transform 'spin'"));
  CHECK(contains(error_in("skewX(90)"), "undefined"));
  CHECK(contains(error_in("scale(0)"), "singular"));
}

TEST_CASE("zero or negative sizes and a file that draws nothing are refused", "[svg]") {
  const std::string zero = error_of("zero.svg", svg(R"(<circle id="c0" cx="5" cy="5" r="0"/>)"));
  CHECK(contains(zero, "zero.svg:2: circle 'c0': r must be > 0, found 0"));
  CHECK(contains(error_of("rect.svg", svg(R"(<rect width="-1" height="2"/>)")), "width must be > 0"));
  CHECK(contains(error_of("ellipse.svg", svg(R"(<ellipse rx="2"/>)")), "attribute ry is missing"));
  const std::string nothing = error_of("nothing.svg", svg("<defs><path d=\"M 0 0 L 1 1\"/></defs>"));
  CHECK(contains(nothing, "nothing.svg: holds no path, line, polyline, polygon, rect, circle or ellipse"));
}

TEST_CASE("an unreadable file, a bad placement and a tolerance too fine for the budget are refused", "[svg]") {
  const std::string missing = "/nonexistent/kiln/walls.svg";
  try {
    read_svg_walls(missing, {1, {0, 0}, 1e-3});
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(contains(e.what(), missing + ": cannot be read: No such file or directory"));
  }
  const std::string text = svg(R"(<circle r="10"/>)");
  CHECK(contains(error_of("tolerance.svg", text, {1, {0, 0}, 0}), "the tolerance must be a finite number > 0"));
  CHECK(contains(error_of("scale.svg", text, {-1, {0, 0}, 1e-3}), "the scale must be a finite number > 0"));
  const std::string budget = error_of("budget.svg", text, {1, {0, 0}, 1e-12});
  CHECK(contains(budget, "more than 1,000,000 points"));
  CHECK(contains(budget, "use a larger tolerance"));
}

TEST_CASE("a device or a directory given as the drawing is refused instead of read without end", "[svg]") {
  for (const char* path : {"/dev/zero", "/tmp"}) {
    std::string message;
    try {
      kiln::read_svg_walls(path, {1.0, {0, 0}, 1e-3});
    } catch (const kiln::InputError& e) {
      message = e.what();
    }
    INFO(path);
    CHECK(message.find(path) != std::string::npos);
  }
}
