// Boundaries as a scene gives them: keys nothing reads (or that belong to another law) refused,
// SVG drawings as walls, the default flattening of curves, periodic cells, particles attached to
// walls or fixed, and load-controlled walls. Everything goes through parse_scene / load_scene.
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "src/base/error.h"
#include "src/scene/scene_yaml.h"
#include "tests/support.h"

using namespace kiln;
using testing::error_of;
using testing::fresh_dir;
using testing::replaced;

namespace {

const std::string& good = testing::two_discs_on_a_floor;

// tests/data/boundaries: the drawing drum_flights.svg and the scene drum_flights.yaml next to it.
std::string boundaries_dir() { return std::string(KILN_CASES_DIR) + "/../tests/data/boundaries"; }

std::string file_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// The 1-based line of the first occurrence of `needle` in `text` (which must hold it).
int line_of(const std::string& text, const std::string& needle) {
  const size_t at = text.find(needle);
  REQUIRE(at != std::string::npos);
  return 1 + static_cast<int>(std::count(text.begin(), text.begin() + static_cast<std::ptrdiff_t>(at), '\n'));
}

// "bad.yaml:LINE: key 'KEY'", the head of every message about a key of a scene named bad.yaml.
std::string at(int line, const std::string& key) { return "bad.yaml:" + std::to_string(line) + ": key '" + key + "'"; }

// The message of a scene read as `file` (an SVG path in it is relative to that file's directory).
std::string error_in(const std::string& text, const std::string& file, const std::vector<std::string>& sets = {}) {
  try {
    parse_scene(text, file, sets);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

bool has(const std::string& text, const std::string& part) { return text.find(part) != std::string::npos; }

// The part of a message after `marker` (the list of valid keys, say), or "" when it is not there.
std::string after(const std::string& text, const std::string& marker) {
  const size_t at = text.find(marker);
  return at == std::string::npos ? "" : text.substr(at + marker.size());
}

// The segments of wall `w`, in order.
std::vector<Segment> segments_of(const Scene& scene, int w) {
  std::vector<Segment> out;
  for (const Segment& s : scene.segments)
    if (s.wall == w) out.push_back(s);
  return out;
}

std::vector<std::string> wall_names(const Scene& scene) {
  std::vector<std::string> names;
  for (const Wall& w : scene.walls) names.push_back(w.name);
  return names;
}

// The largest sagitta of the chords of wall `w` about a circle (centre c, radius r): r minus the
// distance of a chord's midpoint from the centre.
double largest_sagitta(const Scene& scene, int w, Vec2 c, double r) {
  double largest = 0;
  for (const Segment& s : segments_of(scene, w)) largest = std::max(largest, r - norm(0.5 * (s.a + s.b) - c));
  return largest;
}

// ---- Scenes ---------------------------------------------------------------------------------

// A thermal version of the two discs (for the conduction keys of a contact entry).
std::string thermal_discs() {
  return replaced(
    replaced(good, "restitution: 0.8}", "restitution: 0.8, specific_heat: 385, conductivity: 400, youngs_modulus: 1.2e11}"),
    "    radius: 0.002\n", "    radius: 0.002\n    temperature: 20\n");
}

// The two discs with a Young's modulus (a Hertz contact can be valid).
std::string hertz_discs() { return replaced(good, "restitution: 0.8}", "restitution: 0.8, youngs_modulus: 1.2e11}"); }

// A contact entry, in block style so that each key has a line of its own, added before particles:.
std::string with_contact(const std::string& scene, const std::string& entry_lines) {
  return replaced(scene, "particles:", "contacts:\n  - between: [copper, copper]\n" + entry_lines + "particles:");
}

// Two free discs on a floor, two more under a lid that moves down; `set` is added to the second set.
std::string lid_scene(const std::string& set, const std::string& lid_motion = "{type: translate, velocity: [0, -0.01]}") {
  const std::string second_set = "  - material: copper\n    radius: 0.002\n    at: [[0.0, 0.03], [0.01, 0.03]]\n" + set;
  const std::string lid = "  - name: top\n    material: copper\n    segment: [[-0.1, 0.035], [0.1, 0.035]]\n    motion: " +
                          lid_motion + "\n";
  return replaced(replaced(good, "walls:\n", second_set + "walls:\n"), "dt: ", lid + "dt: ");
}

// The drum of tests/data/boundaries/drum_flights.yaml with its wall entry replaced by `entry`.
std::string drum_scene(const std::string& entry) {
  return R"(name: drum
materials:
  steel: {density: 7800, stiffness: 1.0e5, restitution: 0.5, friction: 0.3}
particles:
  - material: steel
    radius: 0.002
    at: [[0.0, 0.0], [0.01, 0.0]]
walls:
  - )" + entry + R"(
dt: 1.0e-5
t_end: 0.01
)";
}
const std::string drum_svg = "file: drum_flights.svg, scale: 0.001, offset: [-0.06, -0.06], tolerance: 1.0e-4";

// Where a point of the drawing (user units, y down) lands: offset + scale (x - 0, 120 - y).
Vec2 world(double x, double y) { return {-0.06 + 0.001 * x, -0.06 + 0.001 * (120 - y)}; }

}  // namespace

// ---- 1. Keys nothing reads, and keys of another law ------------------------------------------

TEST_CASE("closed on a box is refused at its line and key: a box is always closed", "[boundary-input]") {
  const std::string text = replaced(good, "  - {name: floor, material: copper, segment: [[-0.1, 0], [0.1, 0]]}\n",
                                    "  - name: bin\n    material: copper\n    box: [-0.1, 0, 0.1, 0.1]\n"
                                    "    closed: true\n");
  const std::string msg = error_of(text);
  CHECK(has(msg, at(line_of(text, "closed:"), "walls.0.closed")));
  CHECK(has(msg, "does not apply"));
  // Without it the box loads, and closed is read on a polyline.
  CHECK(error_of(replaced(text, "    closed: true\n", "")).empty());
  CHECK(error_of(replaced(text, "box: [-0.1, 0, 0.1, 0.1]", "polyline: [[-0.1, 0.1], [-0.1, 0], [0.1, 0], [0.1, 0.1]]"))
            .empty());
}

TEST_CASE("closed on a box given through --set is refused as --set", "[boundary-input]") {
  const std::string text = replaced(good, "segment: [[-0.1, 0], [0.1, 0]]", "box: [-0.1, 0, 0.1, 0.1]");
  REQUIRE(error_of(text).empty());
  const std::string msg = error_of(text, {"walls.0.closed=true"});
  CHECK(has(msg, "--set: key 'walls.0.closed'"));
  CHECK(has(msg, "does not apply"));
}

TEST_CASE("conductance on a lens contact of a thermal scene is refused naming line, key and conduction: constant",
          "[boundary-input]") {
  REQUIRE(error_of(thermal_discs()).empty());
  const std::string text = with_contact(thermal_discs(), "    conductance: 0.5\n");
  const std::string msg = error_of(text);
  CHECK(has(msg, at(line_of(text, "conductance:"), "contacts.0.conductance")));
  CHECK(has(msg, "conduction: constant"));
  // With conduction: constant the same key is the law's parameter.
  CHECK(error_of(with_contact(thermal_discs(), "    conduction: constant\n    conductance: 0.5\n")).empty());
  // Through --set it is blamed on the command line.
  const std::string set = error_of(with_contact(thermal_discs(), "    friction: 0.3\n"), {"contacts.0.conductance=0.5"});
  CHECK(has(set, "--set: key 'contacts.0.conductance'"));
}

TEST_CASE("damping_rate with model: hertz is refused naming the key, its line, and the keys of the Hertz law",
          "[boundary-input]") {
  REQUIRE(error_of(with_contact(hertz_discs(), "    model: hertz\n")).empty());
  const std::string text = with_contact(hertz_discs(), "    model: hertz\n    damping_rate: 50\n");
  const std::string msg = error_of(text);
  CHECK(has(msg, at(line_of(text, "damping_rate:"), "contacts.0.damping_rate")));
  CHECK(has(msg, "model: linear"));
  const std::string valid = after(msg, "the keys of this pair's law are");
  REQUIRE(!valid.empty());
  for (const char* key : {"'between'", "'model'", "'restitution'", "'tension'", "'friction'", "'conduction'",
                          "'rolling_model'", "'tangential_stiffness_ratio'"})
    CHECK(has(valid, key));
  CHECK(!has(valid, "'damping_rate'"));
  CHECK(!has(valid, "'stiffness'"));
  const std::string set = error_of(with_contact(hertz_discs(), "    model: hertz\n"), {"contacts.0.damping_rate=50"});
  CHECK(has(set, "--set: key 'contacts.0.damping_rate'"));
  CHECK(has(set, "model: linear"));
}

TEST_CASE("stiffness with a Hertz contact is refused at its line, from the entry's model or the scene's",
          "[boundary-input]") {
  const std::string text = with_contact(hertz_discs(), "    model: hertz\n    stiffness: 1.0e4\n");
  const std::string msg = error_of(text);
  CHECK(has(msg, at(line_of(text, "stiffness: 1.0e4"), "contacts.0.stiffness")));
  CHECK(has(msg, "youngs_modulus"));
  const std::string scene_model = with_contact(replaced(hertz_discs(), "dt:", "contact_model: hertz\ndt:"),
                                               "    stiffness: 1.0e4\n");
  CHECK(has(error_of(scene_model), at(line_of(scene_model, "stiffness: 1.0e4"), "contacts.0.stiffness")));
  // A linear contact takes it.
  CHECK(error_of(with_contact(hertz_discs(), "    stiffness: 1.0e4\n")).empty());
}

TEST_CASE("softened_modulus_ratio with lens conduction is refused at its line and key", "[boundary-input]") {
  const std::string text = with_contact(thermal_discs(), "    softened_modulus_ratio: 0.01\n");
  const std::string msg = error_of(text);
  CHECK(has(msg, at(line_of(text, "softened_modulus_ratio:"), "contacts.0.softened_modulus_ratio")));
  CHECK(has(msg, "conduction: batchelor_obrien"));
  CHECK(error_of(with_contact(thermal_discs(), "    conduction: batchelor_obrien\n    softened_modulus_ratio: 0.01\n"))
            .empty());
}

TEST_CASE("contact_resistance without pipe_network conduction is refused at its line and key", "[boundary-input]") {
  const std::string text = with_contact(thermal_discs(), "    conduction: hertz\n    contact_resistance: 0.1\n");
  const std::string msg = error_of(text);
  CHECK(has(msg, at(line_of(text, "contact_resistance:"), "contacts.0.contact_resistance")));
  CHECK(has(msg, "conduction: pipe_network"));
  const std::string cylinders =
      replaced(thermal_discs(), "particles:", "mass_model: cylinder\nthickness: 0.001\nparticles:");
  CHECK(error_of(with_contact(cylinders, "    conduction: pipe_network\n    contact_resistance: 0.1\n")).empty());
}

TEST_CASE("rolling_damping_ratio with rolling_model constant is refused at its line and key", "[boundary-input]") {
  const std::string text = with_contact(good, "    rolling_model: constant\n    rolling_damping_ratio: 0.3\n");
  const std::string msg = error_of(text);
  CHECK(has(msg, at(line_of(text, "rolling_damping_ratio:"), "contacts.0.rolling_damping_ratio")));
  CHECK(has(msg, "rolling_model: epsd"));
  CHECK(error_of(with_contact(good, "    rolling_model: epsd\n    rolling_damping_ratio: 0.3\n")).empty());
}

TEST_CASE("every shipped case still loads", "[boundary-input]") {
  int loaded = 0;
  for (const auto& entry : std::filesystem::directory_iterator(KILN_CASES_DIR)) {
    if (entry.path().extension() != ".yaml") continue;
    INFO(entry.path().string());
    CHECK_NOTHROW(load_scene(entry.path().string()));
    ++loaded;
  }
  CHECK(loaded >= 19);
}

// ---- 2. SVG walls -------------------------------------------------------------------------------

TEST_CASE("an SVG drawing beside the scene file gives one wall per group, named after the groups",
          "[boundary-input]") {
  const Scene scene = load_scene(boundaries_dir() + "/drum_flights.yaml");
  CHECK(wall_names(scene) == std::vector<std::string>{"shell", "flights"});
  // The entry's motion and material belong to every wall it draws.
  for (const Wall& w : scene.walls) {
    CHECK(w.motion.kind == WallMotion::Kind::rotate);
    CHECK(w.material == 0);
  }
  CHECK(segments_of(scene, 0).size() + segments_of(scene, 1).size() == scene.segments.size());
}

TEST_CASE("the drum shell lands on a circle of radius R x scale within the tolerance", "[boundary-input]") {
  const Scene scene = load_scene(boundaries_dir() + "/drum_flights.yaml");
  REQUIRE(scene.walls.size() == 2);
  const double r = 50 * 0.001, tolerance = 1e-4;
  const Vec2 centre = world(60, 60);
  CHECK(norm(centre) < 1e-15);
  const auto shell = segments_of(scene, 0);
  // Every chord within the tolerance (sagitta r (1 - cos(pi / n)) <= tolerance: n >= 50).
  CHECK(shell.size() >= 50);
  CHECK(shell.size() < 200);
  for (const Segment& s : shell) {
    CHECK(std::abs(norm(s.a - centre) - r) <= 1e-12);
    CHECK(r - norm(0.5 * (s.a + s.b) - centre) <= tolerance);
  }
  // The tolerance given is the one used, not the (finer) default of a hundredth of the radius.
  CHECK(largest_sagitta(scene, 0, centre, r) > tolerance / 4);
  // A closed ring: each segment starts where the one before ends.
  for (size_t k = 0; k < shell.size(); ++k) CHECK(norm(shell[k].a - shell[(k + 1) % shell.size()].a) > 0);
  for (size_t k = 0; k < shell.size(); ++k) CHECK(norm(shell[k].b - shell[(k + 1) % shell.size()].a) == 0);
}

TEST_CASE("each flight's corners land exactly where its rotate transform puts them", "[boundary-input]") {
  const Scene scene = load_scene(boundaries_dir() + "/drum_flights.yaml");
  REQUIRE(scene.walls.size() == 2);
  const auto flights = segments_of(scene, 1);
  REQUIRE(flights.size() == 8);  // four L's of two segments each
  // The corners of "m 60,12 v 10 h 6" under rotate(0), rotate(90,60,60), rotate(180 60 60) and
  // rotate(-90,60,60), in user units, worked out by hand.
  const double corners[4][3][2] = {{{60, 12}, {60, 22}, {66, 22}},
                                   {{108, 60}, {98, 60}, {98, 66}},
                                   {{60, 108}, {60, 98}, {54, 98}},
                                   {{12, 60}, {22, 60}, {22, 54}}};
  for (int f = 0; f < 4; ++f) {
    INFO("flight " << f);
    const Segment& leg = flights[2 * f];
    const Segment& foot = flights[2 * f + 1];
    CHECK(norm(leg.a - world(corners[f][0][0], corners[f][0][1])) <= 1e-12);
    CHECK(norm(leg.b - world(corners[f][1][0], corners[f][1][1])) <= 1e-12);
    CHECK(norm(foot.a - world(corners[f][1][0], corners[f][1][1])) <= 1e-12);
    CHECK(norm(foot.b - world(corners[f][2][0], corners[f][2][1])) <= 1e-12);
  }
  // The first flight hangs from the top of the shell: 48 mm up, its foot 6 mm to the right.
  CHECK(norm(flights[0].a - Vec2{0, 0.048}) <= 1e-12);
  CHECK(norm(flights[1].b - Vec2{0.006, 0.038}) <= 1e-12);
}

TEST_CASE("the scene's SVG file is found next to the scene file wherever that is", "[boundary-input]") {
  const auto dir = fresh_dir("boundary_svg");
  std::filesystem::create_directories(dir);
  std::filesystem::copy_file(boundaries_dir() + "/drum_flights.svg", dir / "drum_flights.svg");
  std::ofstream(dir / "drum.yaml") << file_text(boundaries_dir() + "/drum_flights.yaml");
  const Scene scene = load_scene((dir / "drum.yaml").string());
  CHECK(wall_names(scene) == std::vector<std::string>{"shell", "flights"});
  // Without the drawing next to it, the scene names its key.
  std::filesystem::remove(dir / "drum_flights.svg");
  try {
    load_scene((dir / "drum.yaml").string());
    FAIL("no error");
  } catch (const InputError& e) {
    CHECK(has(e.what(), "key 'walls.0.svg.file'"));
    CHECK(has(e.what(), "drum_flights.svg"));
  }
  std::filesystem::remove_all(dir);
}

TEST_CASE("an SVG entry's name prefixes its groups' names; with group it selects one group named as the entry",
          "[boundary-input]") {
  const std::string scene_file = boundaries_dir() + "/inline.yaml";
  const Scene named = parse_scene(drum_scene("{name: drum, material: steel, svg: {" + drum_svg + "}}"), scene_file);
  CHECK(wall_names(named) == std::vector<std::string>{"drum.shell", "drum.flights"});

  const Scene one =
      parse_scene(drum_scene("{name: paddles, material: steel, svg: {" + drum_svg + ", group: flights}}"), scene_file);
  CHECK(wall_names(one) == std::vector<std::string>{"paddles"});
  CHECK(one.segments.size() == 8);
  for (const Segment& s : one.segments) CHECK(s.wall == 0);

  // The composed names are what attach and messages use.
  const Scene attached = parse_scene(
      replaced(drum_scene("{name: drum, material: steel, svg: {" + drum_svg + "}}"), "at: [[0.0, 0.0], [0.01, 0.0]]",
               "at: [[0.0, 0.0], [0.01, 0.0]]\n    attach: drum.flights"),
      scene_file);
  CHECK(attached.attached == std::vector<int>{1, 1});
}

TEST_CASE("two SVG entries selecting one group each without a name get distinct, non-empty wall names",
          "[boundary-input]") {
  // Each entry could be named after the group it selects; an empty name makes the second entry
  // collide with the first ("a wall named '' exists already") and cannot be attached to.
  const std::string scene_file = boundaries_dir() + "/inline.yaml";
  const std::string text = replaced(drum_scene("{material: steel, svg: {" + drum_svg + ", group: shell}}"),
                                    "\ndt:", "\n  - {material: steel, svg: {" + drum_svg + ", group: flights}}\ndt:");
  const std::string msg = error_in(text, scene_file);
  INFO(msg);
  CHECK(msg.empty());
  if (msg.empty()) {
    const Scene scene = parse_scene(text, scene_file);
    REQUIRE(scene.walls.size() == 2);
    CHECK(!scene.walls[0].name.empty());
    CHECK(!scene.walls[1].name.empty());
    CHECK(scene.walls[0].name != scene.walls[1].name);
  }
  const Scene single = parse_scene(drum_scene("{material: steel, svg: {" + drum_svg + ", group: flights}}"), scene_file);
  REQUIRE(single.walls.size() == 1);
  CHECK(!single.walls[0].name.empty());
  CHECK(single.walls[0].name == "flights");  // the natural name: the group's id
}

TEST_CASE("a group the drawing lacks is refused at walls.N.svg.group, listing the groups", "[boundary-input]") {
  const std::string text = drum_scene("{material: steel, svg: {" + drum_svg + ", group: paddles}}");
  const std::string msg = error_in(text, boundaries_dir() + "/inline.yaml");
  CHECK(has(msg, "inline.yaml:" + std::to_string(line_of(text, "group: paddles")) + ": key 'walls.0.svg.group'"));
  CHECK(has(msg, "'paddles'"));
  CHECK(has(msg, "'shell'"));
  CHECK(has(msg, "'flights'"));
  // A layer is no group.
  CHECK(!has(after(msg, "its groups are"), "layer1"));
}

TEST_CASE("a malformed SVG is refused naming the scene key walls.N.svg.file and the SVG's line", "[boundary-input]") {
  const auto dir = fresh_dir("boundary_bad_svg");
  std::filesystem::create_directories(dir);
  // The third flight loses the length of its foot.
  const std::string drawing =
      replaced(file_text(boundaries_dir() + "/drum_flights.svg"), "d=\"m 60,12 l 0,10 l 6,0\"", "d=\"m 60,12 l 0,10 l 6\"");
  std::ofstream(dir / "drum_flights.svg") << drawing;
  // The element's line: where its <path starts.
  const size_t d = drawing.find("l 6\"");
  const size_t element = drawing.rfind("<path", d);
  const int svg_line = 1 + static_cast<int>(std::count(drawing.begin(), drawing.begin() + element, '\n'));
  const std::string text = drum_scene("{material: steel, svg: {" + drum_svg + "}}");
  const std::string scene_file = (dir / "drum.yaml").string();
  const std::string msg = error_in(text, scene_file);
  CHECK(has(msg, scene_file + ":" + std::to_string(line_of(text, "svg:")) + ": key 'walls.0.svg.file'"));
  CHECK(has(msg, "drum_flights.svg:" + std::to_string(svg_line) + ":"));
  CHECK(has(msg, "path4"));
  // Not XML at all: the parser's line.
  std::ofstream(dir / "drum_flights.svg") << "<svg xmlns=\"http://www.w3.org/2000/svg\">\n<g id=\"a\">\n<path d=\"M 0 0 L 1 1\">\n</svg>\n";
  const std::string xml = error_in(text, scene_file);
  CHECK(has(xml, "key 'walls.0.svg.file'"));
  CHECK(has(xml, "not well-formed XML"));
  CHECK(has(xml, "drum_flights.svg:"));
  std::filesystem::remove_all(dir);
}

TEST_CASE("lines in no group make a wall named drawing, which group: drawing selects", "[boundary-input]") {
  // An element in no group (and no layer with an id) belongs to the group "" (svg_geometry.h),
  // and its wall is named "drawing": that name should also select it, and a missing group's
  // message should offer it under that name rather than as ''.
  const auto dir = fresh_dir("boundary_ungrouped");
  std::filesystem::create_directories(dir);
  std::ofstream(dir / "loose.svg") << "<svg xmlns=\"http://www.w3.org/2000/svg\" viewBox=\"0 0 100 100\">\n"
                                      "<path d=\"M 0 0 L 10 0\"/>\n<g id=\"flights\"><path d=\"M 0 5 L 10 5\"/></g>\n</svg>\n";
  const std::string scene_file = (dir / "scene.yaml").string();
  const std::string placed = "file: loose.svg, scale: 0.001, offset: [-0.05, -0.2]";
  const Scene all = parse_scene(drum_scene("{material: steel, svg: {" + placed + "}}"), scene_file);
  CHECK(wall_names(all) == std::vector<std::string>{"drawing", "flights"});
  const std::string msg = error_in(drum_scene("{material: steel, svg: {" + placed + ", group: drawing}}"), scene_file);
  INFO(msg);
  CHECK(msg.empty());
  CHECK(!has(error_in(drum_scene("{material: steel, svg: {" + placed + ", group: paddles}}"), scene_file), "''"));
  std::filesystem::remove_all(dir);
}

// ---- 3. The default flattening -----------------------------------------------------------------

TEST_CASE("a circle wall without a tolerance is flattened to a hundredth of the smallest radius", "[boundary-input]") {
  // 100 um discs in a drum of 1 mm radius: chords within 1 um, about 71 of them (a heptagon was
  // the old absolute default).
  const std::string text = R"(name: small_drum
materials:
  glass: {density: 2500, stiffness: 100, restitution: 0.9}
particles:
  - material: glass
    radius: 1.0e-4
    at: [[0, 0], [3.0e-4, 0]]
walls:
  - {name: drum, material: glass, circle: {centre: [0, 0], radius: 0.001}}
dt: 1.0e-7
t_end: 1.0e-4
)";
  const Scene scene = parse_scene(text, "small_drum.yaml");
  const auto drum = segments_of(scene, 0);
  CHECK(drum.size() >= 71);
  CHECK(drum.size() > 7 * 5);
  for (const Segment& s : drum) CHECK(std::abs(norm(s.a) - 0.001) < 1e-15);
  CHECK(largest_sagitta(scene, 0, {0, 0}, 0.001) <= 1e-6 * (1 + 1e-9));
  CHECK(largest_sagitta(scene, 0, {0, 0}, 0.001) > 0.25e-6);  // not needlessly finer
  // A smaller disc in another set sets the default.
  const Scene finer = parse_scene(
      replaced(text, "walls:", "  - material: glass\n    radius: 5.0e-5\n    at: [[0, 5.0e-4]]\nwalls:"), "small_drum.yaml");
  CHECK(largest_sagitta(finer, 0, {0, 0}, 0.001) <= 0.5e-6 * (1 + 1e-9));
  CHECK(segments_of(finer, 0).size() > drum.size());
  // An arc likewise.
  const Scene arc = parse_scene(
      replaced(text, "circle: {centre: [0, 0], radius: 0.001}", "arc: {centre: [0, 0], radius: 0.001, from_deg: 180, to_deg: 360}"),
      "small_drum.yaml");
  CHECK(largest_sagitta(arc, 0, {0, 0}, 0.001) <= 1e-6 * (1 + 1e-9));
  CHECK(segments_of(arc, 0).size() >= 35);
}

TEST_CASE("an SVG circle without a tolerance is flattened to a hundredth of the smallest radius", "[boundary-input]") {
  const std::string text = drum_scene("{material: steel, svg: {file: drum_flights.svg, scale: 0.001, offset: [-0.06, -0.06]}}");
  const Scene scene = parse_scene(text, boundaries_dir() + "/inline.yaml");
  REQUIRE(scene.walls.size() == 2);
  const double tolerance = 0.01 * 0.002;
  CHECK(largest_sagitta(scene, 0, {0, 0}, 0.05) <= tolerance * (1 + 1e-9));
  CHECK(largest_sagitta(scene, 0, {0, 0}, 0.05) > tolerance / 4);
  // A wall-level tolerance stands for the drawing's when it gives none.
  const Scene coarse = parse_scene(
      drum_scene("{material: steel, tolerance: 1.0e-4, svg: {file: drum_flights.svg, scale: 0.001, offset: [-0.06, -0.06]}}"),
      boundaries_dir() + "/inline.yaml");
  CHECK(largest_sagitta(coarse, 0, {0, 0}, 0.05) <= 1e-4 * (1 + 1e-9));
  CHECK(largest_sagitta(coarse, 0, {0, 0}, 0.05) > 1e-4 / 4);
}

// ---- 4. Periodic cells ---------------------------------------------------------------------------

TEST_CASE("periodic: {x: [0, L]} loads into scene.periodic", "[boundary-input]") {
  const Scene x = parse_scene(good + "periodic: {x: [0, 0.1]}\n", "ok.yaml");
  CHECK(x.periodic.x);
  CHECK(!x.periodic.y);
  CHECK(x.periodic.x0 == 0);
  CHECK(x.periodic.x1 == 0.1);
  const Scene y = parse_scene(good + "periodic: {y: [-0.05, 0.15]}\n", "ok.yaml");
  CHECK(!y.periodic.x);
  CHECK(y.periodic.y);
  CHECK(y.periodic.y0 == -0.05);
  CHECK(y.periodic.y1 == 0.15);
  const Scene none = parse_scene(good, "ok.yaml");
  CHECK(!none.periodic.any());
}

TEST_CASE("a particle starting outside the periodic cell is refused, naming it", "[boundary-input]") {
  const std::string msg = error_of(good + "periodic: {x: [0.005, 0.1]}\n");
  CHECK(has(msg, at(5, "particles.0")));
  CHECK(has(msg, "particle 0 (number 0 of set particles.0)"));
  CHECK(has(msg, "outside the periodic cell"));
  // The cell is [x0, x1): a particle on x1 is outside.
  const std::string edge = error_of(good + "periodic: {x: [-0.05, 0.01]}\n");
  CHECK(has(edge, "particle 1 (number 1 of set particles.0)"));
  CHECK(has(edge, "outside the periodic cell"));
  CHECK(has(error_of(good + "periodic: {y: [0.02, 0.1]}\n"), "outside the periodic cell"));
}

TEST_CASE("a period shorter than 8 of the largest radii is refused; 8 radii exactly loads", "[boundary-input]") {
  const std::string text = good + "periodic:\n  x: [0, 0.0159]\n";
  const std::string msg = error_of(text);
  CHECK(has(msg, at(line_of(text, "x: [0, 0.0159]"), "periodic.x")));
  CHECK(has(msg, "shorter"));
  CHECK(error_of(good + "periodic: {x: [0, 0.016]}\n").empty());
  CHECK(!error_of(good + "periodic: {x: [0.1, 0]}\n").empty());
  CHECK(!error_of(good + "periodic: {y: [0, 0.0159]}\n").empty());
}

TEST_CASE("a short period's message gives the largest radius readably, also for sub-micrometre discs",
          "[boundary-input]") {
  // Radii down to 1e-9 m are valid; the bound 8 r must not print as "8 x 0.000000 m".
  const std::string tiny = replaced(replaced(good, "radius: 0.002", "radius: 1.0e-7"), "at: [[0.0, 0.01], [0.01, 0.01]]",
                                    "at: [[0.0, 0.01], [1.0e-6, 0.01]]");
  REQUIRE(error_of(tiny + "periodic: {x: [0, 2.0e-6]}\n").empty());
  const std::string msg = error_of(tiny + "periodic: {x: [0, 5.0e-7]}\n");
  INFO(msg);
  CHECK(has(msg, "key 'periodic.x'"));
  CHECK(!has(msg, "0.000000"));
  CHECK((has(msg, "1e-07") || has(msg, "8e-07")));
}

TEST_CASE("periodic: {} is refused at its key", "[boundary-input]") {
  const std::string text = good + "periodic: {}\n";
  const std::string msg = error_of(text);
  CHECK(has(msg, at(line_of(text, "periodic:"), "periodic")));
  CHECK(has(msg, "x: [x0, x1]"));
}

TEST_CASE("an unknown key under periodic is refused, listing x and y", "[boundary-input]") {
  const std::string text = good + "periodic:\n  x: [0, 0.1]\n  z: [0, 0.1]\n";
  const std::string msg = error_of(text);
  CHECK(has(msg, at(line_of(text, "z:"), "periodic.z")));
  CHECK(has(msg, "'x'"));
  CHECK(has(msg, "'y'"));
}

TEST_CASE("two particles overlapping across the periodic boundary are refused as overlapping (minimum image)",
          "[boundary-input]") {
  // 0.0034 m apart across the boundary: an overlap of 0.3 of a radius, which allow_overlap allows
  // (0.75 of one, as here before, is beyond the run's overlap check, and refused at the start).
  const std::string across = replaced(good, "at: [[0.0, 0.01], [0.01, 0.01]]", "at: [[0.001, 0.01], [0.0976, 0.01]]");
  REQUIRE(error_of(across).empty());  // 0.0966 m apart without the cell
  const std::string msg = error_of(across + "periodic: {x: [0, 0.1]}\n");
  CHECK(has(msg, "particles 0 and 1 overlap by"));
  CHECK(has(msg, "allow_overlap"));
  CHECK(has(msg, "bad.yaml:5"));
  CHECK(error_of(across + "periodic: {x: [0, 0.1]}\nallow_overlap: true\n").empty());
  // Just apart across the boundary (0.0041 m between centres of radius 0.002) is fine.
  CHECK(error_of(replaced(good, "at: [[0.0, 0.01], [0.01, 0.01]]", "at: [[0.001, 0.01], [0.0969, 0.01]]") +
                 "periodic: {x: [0, 0.1]}\n")
            .empty());
  // Along y too.
  const std::string stacked = replaced(good, "at: [[0.0, 0.01], [0.01, 0.01]]", "at: [[0.0, 0.011], [0.0, 0.0485]]");
  REQUIRE(error_of(stacked).empty());
  CHECK(has(error_of(stacked + "periodic: {y: [0.01, 0.05]}\n"), "overlap"));
}

// ---- 5. Particles attached to walls, or fixed ----------------------------------------------------

TEST_CASE("attach: WALL gives the particles of that set the wall's index", "[boundary-input]") {
  const Scene scene = parse_scene(lid_scene("    attach: top\n"), "lid.yaml");
  CHECK(scene.attached == std::vector<int>{Scene::free_particle, Scene::free_particle, 1, 1});
  // A wall without a name is found by its default name.
  const Scene unnamed = parse_scene(replaced(lid_scene("    attach: wall1\n"), "  - name: top\n    material", "  - material"),
                                    "lid.yaml");
  CHECK(unnamed.attached == std::vector<int>{-1, -1, 1, 1});
  // A rotating wall can carry particles.
  const Scene rotating =
      parse_scene(lid_scene("    attach: top\n", "{type: rotate, centre: [0, 0], rpm: 10}"), "lid.yaml");
  CHECK(rotating.attached == std::vector<int>{-1, -1, 1, 1});
  // No attach, no fixed: all free.
  CHECK(parse_scene(lid_scene(""), "lid.yaml").attached == std::vector<int>(4, Scene::free_particle));
}

TEST_CASE("attach to an unknown wall is refused at its key, listing the walls", "[boundary-input]") {
  const std::string text = lid_scene("    attach: lid\n");
  const std::string msg = error_of(text);
  CHECK(has(msg, at(line_of(text, "attach: lid"), "particles.1.attach")));
  CHECK(has(msg, "'lid'"));
  CHECK(has(msg, "'top'"));
  CHECK(has(msg, "'floor'"));
}

TEST_CASE("attach together with fixed is refused at the particle set", "[boundary-input]") {
  const std::string text = lid_scene("    attach: top\n    fixed: true\n");
  const std::string msg = error_of(text);
  CHECK(has(msg, "key 'particles.1'"));
  CHECK(has(msg, "bad.yaml:" + std::to_string(line_of(text, "  - material: copper\n    radius: 0.002\n    at: [[0.0, 0.03]"))));
  CHECK(has(msg, "attach"));
  CHECK(has(msg, "fixed"));
}

TEST_CASE("fixed: true gives Scene::fixed_particle; fixed: false leaves the set free", "[boundary-input]") {
  CHECK(parse_scene(lid_scene("    fixed: true\n"), "lid.yaml").attached ==
        std::vector<int>{-1, -1, Scene::fixed_particle, Scene::fixed_particle});
  CHECK(parse_scene(lid_scene("    fixed: false\n"), "lid.yaml").attached == std::vector<int>(4, Scene::free_particle));
}

TEST_CASE("attaching to a translating wall that stops after a distance is refused", "[boundary-input]") {
  const std::string text = lid_scene("    attach: top\n", "{type: translate, velocity: [0, -0.01], distance: 0.005}");
  const std::string msg = error_of(text);
  CHECK(has(msg, at(line_of(text, "attach: top"), "particles.1.attach")));
  CHECK(has(msg, "distance"));
  // Without the attachment the stopping wall is fine.
  CHECK(error_of(lid_scene("", "{type: translate, velocity: [0, -0.01], distance: 0.005}")).empty());
}

// ---- 6. Load-controlled walls -----------------------------------------------------------------

TEST_CASE("a load_controlled motion parses into the wall's motion", "[boundary-input]") {
  const Scene scene = parse_scene(
      lid_scene("", "{type: load_controlled, velocity: [0.1, 0], load: [0, -50], mass: 0.2, damping: 1}"), "lid.yaml");
  REQUIRE(scene.walls.size() == 2);
  const WallMotion& m = scene.walls[1].motion;
  CHECK(m.kind == WallMotion::Kind::load_controlled);
  CHECK(m.velocity.x == 0.1);
  CHECK(m.velocity.y == 0);
  CHECK(m.load.x == 0);
  CHECK(m.load.y == -50);
  CHECK(m.mass == 0.2);
  CHECK(m.damping == 1);
  CHECK(scene.walls[0].motion.kind == WallMotion::Kind::fixed);
  // The velocity may be left out (a wall under load alone); the damping is stated, 0 allowed.
  const Scene bare = parse_scene(lid_scene("", "{type: load_controlled, load: [0, -50], mass: 0.2, damping: 0}"), "lid.yaml");
  CHECK(bare.walls[1].motion.kind == WallMotion::Kind::load_controlled);
  CHECK(bare.walls[1].motion.velocity.x == 0);
  CHECK(bare.walls[1].motion.velocity.y == 0);
  CHECK(bare.walls[1].motion.damping == 0);
  CHECK(has(error_of(lid_scene("", "{type: load_controlled, load: [0, -50], mass: 0.2}")), "'damping'"));
}

TEST_CASE("a load_controlled velocity not perpendicular to the load is refused at the velocity", "[boundary-input]") {
  const std::string text = lid_scene("", "{type: load_controlled, velocity: [0.1, 0.01], load: [0, -50], mass: 0.2, damping: 1}");
  const std::string msg = error_of(text);
  CHECK(has(msg, at(line_of(text, "load_controlled"), "walls.1.motion.velocity")));
  CHECK(has(msg, "perpendicular"));
  // A load along x with the velocity along y is fine.
  CHECK(error_of(lid_scene("", "{type: load_controlled, velocity: [0, 0.1], load: [20, 0], mass: 0.2, damping: 1}")).empty());
}

TEST_CASE("a zero load or a missing mass of a load_controlled wall is refused at its key", "[boundary-input]") {
  const std::string zero = lid_scene("", "{type: load_controlled, velocity: [0.1, 0], load: [0, 0], mass: 0.2, damping: 1}");
  const std::string z = error_of(zero);
  CHECK(has(z, at(line_of(zero, "load_controlled"), "walls.1.motion.load")));
  CHECK(has(z, "non-zero load"));
  const std::string massless = lid_scene("", "{type: load_controlled, velocity: [0.1, 0], load: [0, -50]}");
  const std::string m = error_of(massless);
  CHECK(has(m, at(line_of(massless, "load_controlled"), "walls.1.motion")));
  CHECK(has(m, "'mass'"));
  CHECK(has(error_of(lid_scene("", "{type: load_controlled, load: [0, -50], mass: -0.2, damping: 1}")), "walls.1.motion.mass"));
  CHECK(has(error_of(lid_scene("", "{type: load_controlled, load: [0, -50], mass: 0.2, damping: -1}")),
            "walls.1.motion.damping"));
  CHECK(has(error_of(lid_scene("", "{type: load_controlled, velocity: [0.1, 0], mass: 0.2, damping: 1}")), "'load'"));
}

TEST_CASE("unknown keys of a load_controlled motion are refused, listing its keys", "[boundary-input]") {
  for (const std::string key : {"rpm: 10", "distance: 0.01", "centre: [0, 0]", "force: [0, -50]"}) {
    INFO(key);
    const std::string text =
        lid_scene("", "{type: load_controlled, velocity: [0.1, 0], load: [0, -50], mass: 0.2, " + key + "}");
    const std::string msg = error_of(text);
    CHECK(has(msg, at(line_of(text, "load_controlled"), "walls.1.motion." + key.substr(0, key.find(':')))));
    CHECK(has(msg, "unknown key"));
    for (const char* valid : {"'type'", "'velocity'", "'load'", "'mass'", "'damping'"}) CHECK(has(msg, valid));
  }
}
