// The checked readers of values a scene's parts share: lengths, points, restitutions, names, files.
#include "src/scene/scene_parts.h"

#include <cmath>
#include <fstream>

namespace kiln::scene_parts {

namespace {

// The spring-dashpot laws reach a restitution e -> 0 only as the dashpot approaches its overdamped
// limit (critical damping for the linear law with tension; without bound for Hertz and clamped
// laws), where e hangs on the third digit of the damping and the contact barely ends: below 0.01
// the impact is plastic, which a viscoelastic dashpot does not describe. A stronger damping is
// given directly as a contact's damping_rate.
constexpr double least_restitution = 0.01;

}  // namespace

double length(const SceneNode& node) {
  const double v = node.positive();
  if (v < shortest_length || v > farthest_coordinate)
    node.fail("expected a length in [1e-9, 1e6] m, got " + node.text() +
              " (below a nanometre a disc is a few atoms; beyond 1000 km the neighbour search loses its cells)");
  return v;
}

bool within_reach(Vec2 p) { return std::abs(p.x) <= farthest_coordinate && std::abs(p.y) <= farthest_coordinate; }
extern const char* const out_of_reach;
const char* const out_of_reach = "a coordinate beyond 1e6 m (1000 km) from the origin, where kiln's neighbour search "
                                 "cannot resolve nanometre discs";

Vec2 point(const SceneNode& node) {
  const Vec2 p = node.vec2();
  if (!within_reach(p)) node.fail(out_of_reach);
  return p;
}

// [x, y] given as two numbers of a longer list (a rectangle's corners).
Vec2 point_of(const SceneNode& x, const SceneNode& y) {
  const Vec2 p{x.number(), y.number()};
  if (!within_reach(p)) (std::abs(p.x) > farthest_coordinate ? x : y).fail(out_of_reach);
  return p;
}

double restitution(const SceneNode& node) {
  const double e = node.number();
  // Each end has its own reason; a value beyond one is told that end's.
  if (e > 1)
    node.fail("expected a restitution in [0.01, 1], got " + node.text() +
              ": above 1 an impact would give back more energy than it took, which needs a dashpot of negative "
              "damping (1 is an elastic contact, no dashpot)");
  if (!(e >= least_restitution))
    node.fail("expected a restitution in [0.01, 1], got " + node.text() +
              ": below 0.01 a spring-dashpot contact is at the edge of overdamping, where the restitution hangs on "
              "the third digit of the damping and the impact is plastic, which the model does not describe (give a "
              "contact's damping_rate for a stronger damping)");
  return e;
}

// The scene name becomes the output directory out/<name>: a plain directory name, nothing that
// climbs out of out/, hides, or is empty.
std::string read_name(const SceneNode& node) {
  const std::string name = node.text();
  const bool safe = !name.empty() && name.size() <= 100 && name.front() != '.' &&
                    name.find_first_not_of("ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789_.-") ==
                        std::string::npos;
  if (!safe)
    node.fail("the name '" + name + "' cannot be a directory name: use 1 to 100 of A-Z a-z 0-9 _ . -, not "
              "starting with '.'");
  return name;
}

// 64-bit FNV-1a of a file's bytes ("" when it cannot be read: its reader reports that).
std::string file_hash(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  uint64_t h = 14695981039346656037ull;
  for (char c; in.get(c);) h = (h ^ static_cast<unsigned char>(c)) * 1099511628211ull;
  std::ostringstream s;
  s << std::hex << h;
  return s.str();
}

// A file a scene names (a drawing, a particle file): relative paths are relative to the scene file.
std::string beside_scene(const std::string& file, const std::string& scene_file) {
  if (file.empty() || file.front() == '/') return file;
  const size_t slash = scene_file.rfind('/');
  return slash == std::string::npos ? file : scene_file.substr(0, slash + 1) + file;
}

}  // namespace kiln::scene_parts
