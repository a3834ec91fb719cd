#include "src/scene_yaml.h"

#include <unistd.h>
#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <climits>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "src/broadphase.h"
#include "src/nearest.h"
#include "src/observers.h"
#include "src/overrides.h"
#include "src/particle_file.h"
#include "src/particle_fill.h"
#include "src/scene_reader.h"
#include "src/svg_geometry.h"
#include "src/wall_geometry.h"

namespace kiln {

namespace {

// Every documented key, by the schema path of its map (see KeySchema). allow() checks a map
// against it, and --set may add any key it lists.
const KeySchema scene_schema = {
    {"", {"name", "description", "mass_model", "thickness", "gravity", "materials", "contact_model", "contacts",
          "conduction_model", "rolling_model", "heat_from_dissipation", "mechanics", "freeze", "particles", "walls",
          "integrator", "rtol", "atol", "contact_events", "linear_solver", "dt", "t_end", "output_interval", "skin",
          "allow_overlap", "checks", "stop", "report", "periodic"}},
    {"periodic", {"x", "y"}},
    {"materials", {"*"}},
    {"materials.*", {"density", "youngs_modulus", "poisson_ratio", "stiffness", "restitution", "friction",
                     "rolling_friction", "specific_heat", "conductivity", "electrical_resistivity"}},
    {"contacts.*", {"between", "model", "stiffness", "restitution", "damping_rate", "tension", "friction",
                    "rolling_friction", "rolling_model", "rolling_damping_ratio", "tangential_stiffness_ratio",
                    "tangential_damping_ratio", "conduction", "conductance", "softened_modulus_ratio",
                    "contact_resistance"}},
    {"particles.*", {"material", "radius", "velocity", "random_velocity", "angular_velocity", "temperature", "at",
                     "fill", "lattice", "file", "format", "attach", "fixed"}},
    {"particles.*.radius", {"uniform"}},
    {"particles.*.random_velocity", {"max", "seed"}},
    {"particles.*.temperature", {"x_split", "left", "right"}},
    {"particles.*.fill", {"rectangle", "polygon", "count", "seed", "attempts"}},
    {"particles.*.lattice", {"kind", "origin", "spacing", "rows", "columns", "jitter", "seed"}},
    {"walls.*", {"name", "material", "motion", "temperature", "segment", "polyline", "box", "circle", "arc", "closed",
                 "tolerance", "svg"}},
    {"walls.*.svg", {"file", "scale", "offset", "tolerance", "group"}},
    {"walls.*.motion", {"type", "velocity", "distance", "centre", "rpm", "load", "mass", "damping"}},
    {"walls.*.temperature", {"steps", "ramp"}},
    {"walls.*.circle", {"centre", "radius"}},
    {"walls.*.arc", {"centre", "radius", "from_deg", "to_deg"}},
    {"freeze", {"kinetic_energy_below", "not_before", "latest", "dt", "output_interval", "integrator"}},
    {"atol", {"position", "velocity", "angle", "temperature", "other"}},
    {"checks", {"max_overlap_fraction"}},
    {"stop", {"kinetic_energy_below", "not_before"}},
};

// The spring-dashpot laws reach a restitution e -> 0 only as the dashpot approaches its overdamped
// limit (critical damping for the linear law with tension; without bound for Hertz and clamped
// laws), where e hangs on the third digit of the damping and the contact barely ends: below 0.01
// the impact is plastic, which a viscoelastic dashpot does not describe. A stronger damping is
// given directly as a contact's damping_rate.
constexpr double least_restitution = 0.01;
// Every pair of materials gets a contact law whose damping is solved for when a run starts (up to
// 0.2 s each, n (n + 1) / 2 of them): 16 materials cost half a minute at worst.
constexpr int max_materials = 16;

// A scene's claim on memory, counted before anything is allocated for it. A run needs about
// 0.5 kB per disc (measured on a 40,000-disc lattice: state, neighbour lists, frames), counted as
// 1 kB to leave room for the contacts of dense packings; a wall segment about 256 bytes (its
// geometry, its moved copies, its proxy in the neighbour tree).
class MemoryClaim {
 public:
  explicit MemoryClaim(uint64_t budget) : budget_(budget) {}
  long long max_particles() const {
    return static_cast<long long>(std::min<uint64_t>(budget_ / per_particle, INT_MAX));  // n_particles() is an int
  }
  void add_particles(const SceneNode& at, long long count, const std::string& what) {
    const std::string before = particles_ > 0 ? " after " + std::to_string(particles_) + " in earlier sets" : "";
    if (count > max_particles() - particles_)
      at.fail(what + " particles" + before + ": more than the " + std::to_string(max_particles()) + " that fit in this machine's memory (" +
              gigabytes() + " at about 1 kB per particle in a run)");
    particles_ += count;
  }
  void add_segments(const SceneNode& at, size_t count) {
    segments_ += count;
    if (particles_ * per_particle + segments_ * per_segment > budget_)
      at.fail("the walls come to " + std::to_string(segments_) + " segments, which with " +
              std::to_string(particles_) + " particles exceed this machine's memory (" + gigabytes() +
              "; about 256 bytes a segment): raise the tolerance of circles and arcs");
  }

 private:
  static constexpr uint64_t per_particle = 1024, per_segment = 256;
  std::string gigabytes() const {
    std::ostringstream s;
    s.precision(3);
    s << budget_ / 1e9 << " GB";
    return s.str();
  }
  uint64_t budget_;
  long long particles_ = 0;
  uint64_t segments_ = 0;
};

double length(const SceneNode& node) {
  const double v = node.positive();
  if (v < shortest_length || v > farthest_coordinate)
    node.fail("expected a length in [1e-9, 1e6] m, got " + node.text() +
              " (below a nanometre a disc is a few atoms; beyond 1000 km the neighbour search loses its cells)");
  return v;
}

bool within_reach(Vec2 p) { return std::abs(p.x) <= farthest_coordinate && std::abs(p.y) <= farthest_coordinate; }
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
  if (!(e >= least_restitution && e <= 1))
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

// Where each particle came from, for messages.
struct ParticleSets {
  std::vector<Location> location;  // of each set
  std::vector<int> first;          // index of each set's first particle
  std::vector<int> of;             // each particle's set
  std::string describe(int i) const {
    return "particle " + std::to_string(i) + " (number " + std::to_string(i - first[of[i]]) + " of set " +
           location[of[i]].key + ")";
  }
};

struct MaterialIndex {
  std::map<std::string, int> by_name;
  int find(const SceneNode& node) const {
    const std::string name = node.text();
    const auto it = by_name.find(name);
    if (it == by_name.end()) {
      std::vector<std::string> names;
      for (const auto& kv : by_name) names.push_back(kv.first);
      node.fail("unknown material '" + name + "'; defined materials are " + choices_nearest_first(name, names));
    }
    return it->second;
  }
};

Material read_material(const std::string& name, const SceneNode& m) {
  m.allow();
  Material mat;
  mat.name = name;
  // Up to 1e12 kg/m^3: osmium's 22,590 scaled up by 1e7 or more (density scaling, to lengthen the
  // step); beyond, masses of large particles overflow (1e300 made an infinite mass that blamed dt).
  if (auto v = m.optional("density")) mat.density = v->in_range(0, 1e12, true, false);
  if (auto v = m.optional("youngs_modulus")) mat.youngs_modulus = v->positive();
  if (auto v = m.optional("poisson_ratio")) mat.poisson_ratio = v->in_range(-1, 0.5, true, false);
  if (auto v = m.optional("stiffness")) mat.stiffness = v->positive();
  if (auto v = m.optional("restitution")) mat.restitution = restitution(*v);
  if (auto v = m.optional("friction")) mat.friction = v->non_negative();
  if (auto v = m.optional("rolling_friction")) mat.rolling_friction = v->non_negative();
  if (auto v = m.optional("specific_heat")) mat.specific_heat = v->positive();
  if (auto v = m.optional("conductivity")) mat.conductivity = v->positive();
  if (auto v = m.optional("electrical_resistivity")) mat.electrical_resistivity = v->positive();
  return mat;
}

double effective_modulus(const Material& a, const Material& b) {
  if (a.youngs_modulus <= 0 || b.youngs_modulus <= 0) return 0;
  return 1.0 / ((1 - a.poisson_ratio * a.poisson_ratio) / a.youngs_modulus +
                (1 - b.poisson_ratio * b.poisson_ratio) / b.youngs_modulus);
}

// Default law of an unlisted pair: springs in series scaled to give k for like materials
// (2 k1 k2 / (k1 + k2)), the geometric mean of the restitutions, the smaller friction.
PairLaw combined_law(const Material& a, const Material& b, NormalModel model) {
  PairLaw law;
  law.model = model;
  law.stiffness = (a.stiffness > 0 && b.stiffness > 0) ? 2 * a.stiffness * b.stiffness / (a.stiffness + b.stiffness)
                                                       : std::max(a.stiffness, b.stiffness);
  law.effective_modulus = effective_modulus(a, b);
  law.restitution = std::sqrt(a.restitution * b.restitution);
  law.friction = std::min(a.friction, b.friction);
  law.rolling_friction = std::min(a.rolling_friction, b.rolling_friction);
  return law;
}

contact::RollingModel read_rolling_model(const SceneNode& node) {
  return node.choice({"constant", "epsd"}) == "epsd" ? contact::RollingModel::epsd : contact::RollingModel::constant;
}

NormalModel read_model(const SceneNode& node) {
  return node.choice({"linear", "hertz"}) == "hertz" ? NormalModel::hertz : NormalModel::linear;
}

thermal::ConductionModel read_conduction(const SceneNode& node) {
  using M = thermal::ConductionModel;
  const std::string c = node.choice({"lens", "hertz", "batchelor_obrien", "pipe_network", "constant", "none"});
  if (c == "lens") return M::lens;
  if (c == "hertz") return M::hertz;
  if (c == "batchelor_obrien") return M::batchelor_obrien;
  if (c == "pipe_network") return M::pipe_network;
  if (c == "constant") return M::constant;
  return M::none;
}

// A contact entry's keys that belong to one law, refused with another: the Hertz law takes its
// stiffness from the materials' moduli, and its dashpot (N s/m^1.25) from the restitution, so a
// linear damping rate has no meaning there; each conduction and rolling law has its own parameter.
void check_law_keys(const SceneNode& c, const PairLaw& law) {
  using M = thermal::ConductionModel;
  const bool hertz = law.model == NormalModel::hertz;
  struct Owned {
    const char* key;
    bool applies;
    const char* law;
  };
  const Owned owned[] = {
      {"stiffness", !hertz, "model: linear (Hertz takes its stiffness from youngs_modulus and poisson_ratio)"},
      {"damping_rate", !hertz, "model: linear (a Hertz contact is damped through its restitution)"},
      {"conductance", law.conduction == M::constant, "conduction: constant"},
      {"softened_modulus_ratio", law.conduction == M::batchelor_obrien, "conduction: batchelor_obrien"},
      {"contact_resistance", law.conduction == M::pipe_network, "conduction: pipe_network"},
      {"rolling_damping_ratio", law.rolling_model == contact::RollingModel::epsd, "rolling_model: epsd"}};
  std::vector<std::string> valid = {"between", "model", "restitution", "tension", "friction", "rolling_friction",
                                    "rolling_model", "tangential_stiffness_ratio", "tangential_damping_ratio",
                                    "conduction"};
  for (const Owned& o : owned)
    if (o.applies) valid.push_back(o.key);
  for (const Owned& o : owned)
    if (c.has(o.key) && !o.applies)
      c[o.key].fail(std::string("applies to ") + o.law + " only; the keys of this pair's law are " +
                    choices_nearest_first(o.key, valid));
}

void read_contacts(const SceneNode& root, Scene& scene, const MaterialIndex& index,
                   std::vector<Location>& law_location) {
  const int nm = scene.n_materials();
  NormalModel model = NormalModel::linear;
  if (auto m = root.optional("contact_model")) model = read_model(*m);
  thermal::ConductionModel conduction = thermal::ConductionModel::lens;
  if (auto c = root.optional("conduction_model")) conduction = read_conduction(*c);
  contact::RollingModel rolling = contact::RollingModel::constant;
  if (auto r = root.optional("rolling_model")) rolling = read_rolling_model(*r);
  scene.laws.resize(nm * nm);
  law_location.assign(nm * nm, root.location());
  for (int a = 0; a < nm; ++a)
    for (int b = 0; b < nm; ++b) {
      scene.laws[a * nm + b] = combined_law(scene.materials[a], scene.materials[b], model);
      scene.laws[a * nm + b].conduction = conduction;
      scene.laws[a * nm + b].rolling_model = rolling;
    }
  if (auto contacts = root.optional("contacts")) {
    for (const SceneNode& c : contacts->items()) {
      c.allow();
      const auto pair = c["between"].items();
      if (pair.size() != 2) c["between"].fail("expected two material names [a, b]");
      const int a = index.find(pair[0]), b = index.find(pair[1]);
      PairLaw law = scene.laws[a * nm + b];
      if (auto v = c.optional("model")) law.model = read_model(*v);
      if (auto v = c.optional("stiffness")) law.stiffness = v->positive();
      if (auto v = c.optional("restitution")) law.restitution = restitution(*v);
      if (auto v = c.optional("damping_rate")) law.damping_rate = v->non_negative();
      if (c.has("restitution") && c.has("damping_rate"))
        c["damping_rate"].fail("give either restitution or damping_rate, not both");
      if (auto v = c.optional("tension")) law.tension = v->boolean();
      if (auto v = c.optional("friction")) law.friction = v->non_negative();
      if (auto v = c.optional("rolling_friction")) law.rolling_friction = v->non_negative();
      if (auto v = c.optional("rolling_model")) law.rolling_model = read_rolling_model(*v);
      if (auto v = c.optional("rolling_damping_ratio")) law.rolling_damping_ratio = v->non_negative();
      if (auto v = c.optional("tangential_stiffness_ratio")) law.tangential_stiffness_ratio = v->positive();
      if (auto v = c.optional("tangential_damping_ratio")) law.tangential_damping_ratio = v->non_negative();
      if (auto v = c.optional("conduction")) law.conduction = read_conduction(*v);
      if (law.conduction == thermal::ConductionModel::constant) law.conductance = c["conductance"].positive();
      if (auto v = c.optional("softened_modulus_ratio")) law.modulus_ratio = v->in_range(0, 1, true, false);
      if (auto v = c.optional("contact_resistance")) law.contact_resistance = v->non_negative();
      check_law_keys(c, law);
      scene.laws[a * nm + b] = scene.laws[b * nm + a] = law;
      law_location[a * nm + b] = law_location[b * nm + a] = c.location();
    }
  }
}

RadiusDistribution read_radius(const SceneNode& node) {
  if (node.is_map()) {
    node.allow();
    const auto range = node["uniform"].items();
    if (range.size() != 2) node["uniform"].fail("expected [min, max]");
    const double lo = length(range[0]), hi = length(range[1]);
    if (hi < lo) node["uniform"].fail("expected min <= max");
    return {lo, hi};
  }
  const double r = length(node);
  return {r, r};
}

Region read_region(const SceneNode& fill) {
  Region region;
  if (auto rect = fill.optional("rectangle")) {
    const auto v = rect->items();
    if (v.size() != 4) rect->fail("expected [x0, y0, x1, y1]");
    region.corners = {point_of(v[0], v[1]), point_of(v[2], v[1]), point_of(v[2], v[3]), point_of(v[0], v[3])};
    if (!(region.corners[2].x > region.corners[0].x && region.corners[2].y > region.corners[0].y))
      rect->fail("expected x1 > x0 and y1 > y0");
  } else if (auto poly = fill.optional("polygon")) {
    for (const SceneNode& p : poly->items()) region.corners.push_back(point(p));
    if (region.corners.size() < 3) poly->fail("expected at least three corners");
  } else {
    fill.fail("expected a region: 'rectangle' or 'polygon'");
  }
  return region;
}

// fill: random discs in a region, counted against the memory before any is placed.
Placement read_fill(const SceneNode& fill, const SceneNode& radius, const Scene& scene, MemoryClaim& claim) {
  fill.allow();
  const Region region = read_region(fill);
  const long long count = fill["count"].integer(1, LLONG_MAX);
  claim.add_particles(fill["count"], count, std::to_string(count));
  const long long seed = fill.has("seed") ? fill["seed"].integer(0, LLONG_MAX) : 1;
  // A disc that finds no place in a million tries will not find one: the region is full.
  const long long attempts = fill.has("attempts") ? fill["attempts"].integer(1, 1000000) : 10000;
  try {
    return random_fill(region, static_cast<int>(count), read_radius(radius), static_cast<uint64_t>(seed), attempts,
                       scene.position, scene.radius);
  } catch (const std::runtime_error& e) {
    fill.fail(e.what());
  }
}

// lattice: rows x columns discs, their number computed in 64 bits and counted against the memory.
Placement read_lattice(const SceneNode& lat, const SceneNode& radius, MemoryClaim& claim) {
  lat.allow();
  const bool hex = lat.has("kind") && lat["kind"].choice({"hexagonal", "square"}) == "hexagonal";
  const long long rows = lat["rows"].integer(1, LLONG_MAX), columns = lat["columns"].integer(1, LLONG_MAX);
  const bool huge = rows > LLONG_MAX / columns;  // the product itself would not fit in 64 bits
  const long long count = huge ? LLONG_MAX : rows * columns;
  claim.add_particles(lat, count, "rows x columns = " + std::to_string(rows) + " x " + std::to_string(columns) +
                                      (huge ? "" : " = " + std::to_string(count)));
  const Vec2 origin = point(lat["origin"]);
  const double spacing = length(lat["spacing"]);
  const double jitter = lat.has("jitter") ? lat["jitter"].non_negative() : 0.0;
  const long long seed = lat.has("seed") ? lat["seed"].integer(0, LLONG_MAX) : 1;
  return lattice(hex, origin, spacing, static_cast<int>(rows), static_cast<int>(columns), read_radius(radius), jitter,
                 static_cast<uint64_t>(seed));
}

// file: a particle file (src/particle_file.h) beside the scene, in the format of its extension or
// of `format`; its densities must be the material's, which gives every mass.
// A checkpoint records the file's hash with the scene's other inputs (Scene::inputs).
ParticleFile read_particle_set_file(const SceneNode& ps, Scene& scene, const Material& material, MemoryClaim& claim) {
  if (ps.has("radius")) ps["radius"].fail("the particle file gives every radius: remove this key");
  const SceneNode file_node = ps["file"];
  const std::string file = beside_scene(file_node.text(), scene.file);
  std::optional<ParticleFileFormat> format = particle_file_format_of(file);
  if (auto f = ps.optional("format"))
    format = f->choice({"lammps", "csv"}) == "csv" ? ParticleFileFormat::csv : ParticleFileFormat::lammps;
  if (!format)
    file_node.fail("the extension does not say the file's format (.data or .lmp: a LAMMPS data file, .csv: CSV); "
                   "give format: lammps or format: csv");
  ParticleFile read;
  try {
    read = read_particle_file(file, *format, {claim.max_particles(), material.density});
  } catch (const InputError& e) {
    file_node.fail(e.what());
  }
  claim.add_particles(file_node, read.size(), std::to_string(read.size()));
  scene.inputs.push_back(file_node.text() + "\t" + file_hash(file));  // as the scene names it
  return read;
}

Placement read_placement(const SceneNode& ps, const Scene& scene, MemoryClaim& claim, const ParticleFile* file) {
  const int ways = ps.has("at") + ps.has("fill") + ps.has("lattice") + ps.has("file");
  if (ways != 1) ps.fail("give exactly one of 'at' (a list of positions), 'fill', 'lattice' or 'file'");
  if (file) return {file->position, file->radius};
  if (auto fill = ps.optional("fill")) return read_fill(*fill, ps["radius"], scene, claim);
  if (auto lat = ps.optional("lattice")) return read_lattice(*lat, ps["radius"], claim);
  const auto at = ps["at"].items();
  claim.add_particles(ps["at"], static_cast<long long>(at.size()), std::to_string(at.size()));
  const RadiusDistribution radii = read_radius(ps["radius"]);
  Placement placed;
  Random rng(0);
  for (const SceneNode& p : at) {
    placed.position.push_back(point(p));
    placed.radius.push_back(radii.draw(rng));
  }
  return placed;
}

// attach: WALL or fixed: true on a particle set, resolved once the walls are read.
struct Attachment {
  SceneNode node;
  bool fixed = false;
  int first = 0, count = 0;
};

void read_particles(const SceneNode& root, Scene& scene, const MaterialIndex& index, ParticleSets& sets,
                    MemoryClaim& claim, std::vector<Attachment>& attachments) {
  for (const SceneNode& ps : root["particles"].items()) {
    ps.allow();
    const int mat = index.find(ps["material"]);
    if (!(scene.materials[mat].density > 0)) ps["material"].fail("this material needs a density to make particles");
    std::optional<ParticleFile> file;
    if (ps.has("file")) file = read_particle_set_file(ps, scene, scene.materials[mat], claim);
    // What a file gives for each particle, a key would give again for all of them.
    const bool file_temperatures = file && !file->temperature.empty();
    for (const auto& [key, given] : {std::pair{"velocity", file && file->has_velocity},
                                     std::pair{"angular_velocity", file && file->has_angular_velocity},
                                     std::pair{"temperature", file_temperatures}})
      if (given && ps.has(key)) ps[key].fail("the particle file gives every particle's " + std::string(key) + ": remove this key");
    const Vec2 velocity = ps.optional("velocity") ? ps["velocity"].vec2() : Vec2{};
    const double spin = ps.number_or("angular_velocity", 0);
    const Placement placed = read_placement(ps, scene, claim, file ? &*file : nullptr);
    for (size_t k = 0; k < placed.position.size(); ++k)
      if (!within_reach(placed.position[k]))
        ps.fail("particle " + std::to_string(k) + " of this set lies at " + out_of_reach);
    // random_velocity: {max: V, seed: S} adds to each velocity component a uniform draw in [-V, V].
    double jitter = 0;
    Random velocity_rng(1);
    if (auto rv = ps.optional("random_velocity")) {
      rv->allow();
      jitter = (*rv)["max"].positive();
      velocity_rng = Random(static_cast<uint64_t>(rv->has("seed") ? (*rv)["seed"].integer(0, LLONG_MAX) : 1));
    }
    // temperature: T, or {x_split: x, left: T1, right: T2} (a hot half and a cold half).
    const auto temp = ps.optional("temperature");
    double t_left = NAN, t_right = NAN, x_split = INFINITY;
    if (temp && temp->is_map()) {
      temp->allow();
      x_split = (*temp)["x_split"].number();
      t_left = (*temp)["left"].temperature();
      t_right = (*temp)["right"].temperature();
    } else if (temp) {
      t_left = t_right = temp->temperature();
    }
    const bool thermal_set = temp || file_temperatures;
    if (scene.thermal != thermal_set && !scene.position.empty())
      ps.fail("either every particle set gives a temperature (a thermal scene) or none does");
    scene.thermal = thermal_set;
    sets.first.push_back(scene.n_particles());
    if (ps.has("attach") && ps.has("fixed")) ps.fail("give one of 'attach' (a wall's name) or 'fixed', not both");
    // An attached or fixed particle moves with its wall: a velocity of its own would not be read.
    if (ps.has("attach") || (ps.has("fixed") && ps["fixed"].boolean()))
    {
      for (const char* key : {"velocity", "angular_velocity", "random_velocity"})
        if (ps.has(key)) ps[key].fail("attached and fixed particles move with their wall: remove it");
      // A file's velocities would be dropped as silently: only zeros (a settled pile's) are taken.
      const bool moving = file && (std::any_of(file->velocity.begin(), file->velocity.end(),
                                               [](Vec2 v) { return v.x != 0 || v.y != 0; }) ||
                                   std::any_of(file->angular_velocity.begin(), file->angular_velocity.end(),
                                               [](double w) { return w != 0; }));
      if (moving)
        ps["file"].fail("attached and fixed particles move with their wall, but the file gives some of them a "
                        "velocity or spin: set those to 0");
    }
    const int count = static_cast<int>(placed.radius.size());
    if (auto a = ps.optional("attach")) attachments.push_back({*a, false, scene.n_particles(), count});
    if (auto f = ps.optional("fixed"); f && f->boolean()) attachments.push_back({*f, true, scene.n_particles(), count});
    for (size_t k = 0; k < placed.radius.size(); ++k) {
      if (file_temperatures) scene.temperature.push_back(file->temperature[k]);
      else if (temp) scene.temperature.push_back(placed.position[k].x < x_split ? t_left : t_right);
      scene.position.push_back(placed.position[k]);
      scene.radius.push_back(placed.radius[k]);
      Vec2 v = file && file->has_velocity ? file->velocity[k] : velocity;
      if (jitter > 0) v = v + Vec2{velocity_rng.uniform(-jitter, jitter), velocity_rng.uniform(-jitter, jitter)};
      if (!std::isfinite(v.x) || !std::isfinite(v.y))
        ps.fail("the velocities overflow double precision (random_velocity.max near 1.8e308)");
      scene.velocity.push_back(v);
      scene.angular_velocity.push_back(file && file->has_angular_velocity ? file->angular_velocity[k] : spin);
      scene.material.push_back(mat);
      sets.of.push_back(static_cast<int>(sets.location.size()));
    }
    sets.location.push_back(ps.location());
  }
  if (scene.radius.empty()) root["particles"].fail("the scene has no particles");
}

WallMotion read_motion(const SceneNode& m) {
  WallMotion motion;
  const std::string kind = m["type"].choice({"fixed", "translate", "rotate", "load_controlled"});
  if (kind == "fixed") {
    m.allow({"type"});
  } else if (kind == "load_controlled") {
    m.allow({"type", "velocity", "load", "mass", "damping"});
    motion.kind = WallMotion::Kind::load_controlled;
    motion.velocity = m.has("velocity") ? m["velocity"].vec2() : Vec2{};
    motion.load = m["load"].vec2();
    motion.mass = m["mass"].positive();
    motion.damping = m["damping"].non_negative();  // stated, as the load and mass are (0 allowed)
    if (norm(motion.load) == 0) m["load"].fail("a load-controlled wall needs a non-zero load (N)");
    // The body is driven along the velocity and free along the load: the two must not share a direction.
    if (std::abs(dot(motion.velocity, motion.load)) > 1e-12 * norm(motion.velocity) * norm(motion.load))
      m["velocity"].fail("the driven velocity must be perpendicular to the load: the wall is free along the load");
  } else if (kind == "translate") {
    m.allow({"type", "velocity", "distance"});
    motion.kind = WallMotion::Kind::translate;
    motion.velocity = m["velocity"].vec2();
    motion.distance = m.has("distance") ? m["distance"].non_negative() : INFINITY;
  } else {
    m.allow({"type", "centre", "rpm"});
    motion.kind = WallMotion::Kind::rotate;
    motion.centre = point(m["centre"]);
    motion.omega = m["rpm"].number() * 2 * M_PI / 60;
    if (!std::isfinite(motion.omega)) m["rpm"].fail("the angular speed overflows double precision");
  }
  return motion;
}

// temperature: T (isothermal), {steps: [[t0, T0], [t1, T1], ...]} (T_k from t_k on), or
// {ramp: [[t0, T0], ...]} (linear between the points, held beyond them).
thermal::WallTemperature read_wall_temperature(const SceneNode& node) {
  thermal::WallTemperature wt;
  if (!node.is_map()) {
    wt.kind = thermal::WallTemperature::Kind::steps;
    wt.times = {0};
    wt.values = {node.temperature()};
    return wt;
  }
  node.allow();
  if (node.has("steps") == node.has("ramp")) node.fail("give one of 'steps' or 'ramp'");
  const bool steps = node.has("steps");
  wt.kind = steps ? thermal::WallTemperature::Kind::steps : thermal::WallTemperature::Kind::ramp;
  const SceneNode list = node[steps ? "steps" : "ramp"];
  for (const SceneNode& point : list.items()) {
    if (!point.is_sequence() || point.items().size() != 2) point.fail("expected a pair [time, temperature]");
    const double time = point.items()[0].number();
    if (!wt.times.empty() && time <= wt.times.back()) point.fail("times must increase");
    wt.times.push_back(time);
    wt.values.push_back(point.items()[1].temperature());
  }
  if (wt.times.empty()) list.fail("expected at least one [time, temperature] point");
  return wt;
}

// A circle or an arc as chords. Its tolerance is at least 1e-9 of its radius: the chords then
// number at most about 70,000 per turn (the sagitta R (1 - cos(dphi/2)) <= tolerance), and an arc
// turns at most once.
std::vector<Vec2> read_arc(const SceneNode& node, double from, double to, double tolerance) {
  node.allow();
  const double radius = length(node["radius"]);
  if (tolerance < 1e-9 * radius)
    node.fail("the tolerance is below 1e-9 of the radius: the chords would be too many to hold");
  return arc_points(point(node["centre"]), radius, from, to, tolerance);
}

void read_wall_shape(const SceneNode& w, int id, double tolerance, std::vector<Segment>& segments) {
  auto points = [](const SceneNode& list) {
    std::vector<Vec2> pts;
    for (const SceneNode& p : list.items()) pts.push_back(point(p));
    return pts;
  };
  if (auto s = w.optional("segment")) {
    const auto pts = points(*s);
    if (pts.size() != 2) s->fail("expected two points [[x0, y0], [x1, y1]]");
    add_polyline(segments, pts, false, id);
  } else if (auto p = w.optional("polyline")) {
    const auto pts = points(*p);
    if (pts.size() < 2) p->fail("expected at least two points");
    add_polyline(segments, pts, w.has("closed") && w["closed"].boolean(), id);
  } else if (auto b = w.optional("box")) {
    const auto v = b->items();
    if (v.size() != 4) b->fail("expected [x0, y0, x1, y1]");
    const Vec2 lo = point_of(v[0], v[1]), hi = point_of(v[2], v[3]);
    if (!(hi.x > lo.x && hi.y > lo.y)) b->fail("expected x1 > x0 and y1 > y0");
    add_polyline(segments, {lo, {hi.x, lo.y}, hi, {lo.x, hi.y}}, true, id);
  } else if (auto c = w.optional("circle")) {
    auto pts = read_arc(*c, 0, 2 * M_PI, tolerance);
    pts.pop_back();  // the last point closes onto the first
    add_polyline(segments, pts, true, id);
  } else {
    const SceneNode arc = w["arc"];
    const double from = arc["from_deg"].number() * M_PI / 180, to = arc["to_deg"].number() * M_PI / 180;
    if (!(to > from)) arc["to_deg"].fail("expected to_deg > from_deg (counter-clockwise)");
    if (to - from > 2 * M_PI) arc["to_deg"].fail("an arc turns at most 360 degrees");
    add_polyline(segments, read_arc(arc, from, to, tolerance), false, id);
  }
}

// svg: {file, scale, offset, tolerance, group}: the drawing's groups as walls (file relative to
// the scene file). Without `group` each group of the drawing becomes a wall named after its id
// (the entry's name, then the id, when it has a name); with it, only that group, named as the entry.
struct DrawnWall {
  std::string name;
  std::vector<SvgPolyline> lines;
};

std::vector<DrawnWall> read_svg_entry(const SceneNode& node, const std::string& scene_file, const std::string& name,
                                      double tolerance, std::vector<std::string>& inputs) {
  node.allow();
  const std::string file = beside_scene(node["file"].text(), scene_file);
  SvgPlacement placement;
  placement.scale = node.has("scale") ? node["scale"].positive() : 1.0;
  placement.offset = node.has("offset") ? point(node["offset"]) : Vec2{};
  placement.tolerance = node.has("tolerance") ? node["tolerance"].positive() : tolerance;
  std::vector<SvgGroup> groups;
  try {
    groups = read_svg_walls(file, placement);
  } catch (const InputError& e) {
    node["file"].fail(e.what());
  }
  inputs.push_back(node["file"].text() + "\t" + file_hash(file));  // as the scene names it
  // Lines outside any named group or layer form the group "drawing".
  auto id_of = [](const SvgGroup& group) { return group.id.empty() ? std::string("drawing") : group.id; };
  std::vector<DrawnWall> walls;
  if (auto g = node.optional("group")) {
    const std::string wanted = g->text();
    std::vector<std::string> ids;
    for (const SvgGroup& group : groups) {
      ids.push_back(id_of(group));
      if (id_of(group) == wanted) walls.push_back({name.empty() ? wanted : name, group.lines});
    }
    if (walls.empty()) g->fail("the drawing has no group '" + wanted + "'; its groups are " + choices_nearest_first(wanted, ids));
    return walls;
  }
  for (const SvgGroup& group : groups) walls.push_back({name.empty() ? id_of(group) : name + "." + id_of(group), group.lines});
  return walls;
}

// Circles, arcs and drawn curves are flattened by default to a hundredth of the smallest particle
// radius: a wall's chords then depart from the curve by less than the overlaps of its contacts
// (an absolute default made a drum of 100 um radius a heptagon).
double default_tolerance(const Scene& scene) {
  return 0.01 * *std::min_element(scene.radius.begin(), scene.radius.end());
}

void read_walls(const SceneNode& root, Scene& scene, const MaterialIndex& index, MemoryClaim& claim) {
  const auto walls = root.optional("walls");
  if (!walls) return;
  for (const SceneNode& w : walls->items()) {
    w.allow();
    Wall wall;
    wall.material = index.find(w["material"]);
    if (auto m = w.optional("motion")) wall.motion = read_motion(*m);
    if (auto t = w.optional("temperature")) wall.temperature = read_wall_temperature(*t);
    const int shapes = w.has("segment") + w.has("polyline") + w.has("box") + w.has("circle") + w.has("arc") + w.has("svg");
    if (shapes != 1) w.fail("give exactly one shape: segment, polyline, box, circle, arc or svg");
    // Only curves are flattened: on straight shapes a tolerance is not read (and so refused).
    const bool curved = w.has("circle") || w.has("arc") || w.has("svg");
    if (w.has("svg") && w.has("tolerance") && w["svg"].has("tolerance"))
      w["tolerance"].fail("give the tolerance once: here or as svg.tolerance");
    const double tolerance = curved && w.has("tolerance") ? w["tolerance"].positive() : default_tolerance(scene);
    const std::string name = w.has("name") ? w["name"].text() : "";
    std::vector<DrawnWall> drawn;
    if (auto svg = w.optional("svg")) {
      drawn = read_svg_entry(*svg, scene.file, name, tolerance, scene.inputs);
    } else {
      drawn.push_back({name.empty() ? "wall" + std::to_string(scene.walls.size()) : name, {}});
    }
    // One body under one load: a drawing of several groups is several walls, each of which would
    // carry the whole mass and load.
    if (drawn.size() > 1 && wall.motion.kind == WallMotion::Kind::load_controlled)
      w["motion"].fail("a load-controlled wall is one body: this drawing has " + std::to_string(drawn.size()) +
                       " groups; pick one with svg.group, or draw the wall as one group");
    for (const DrawnWall& d : drawn) {
      const int id = static_cast<int>(scene.walls.size());
      const size_t before = scene.segments.size();
      if (w.has("svg")) {
        for (const SvgPolyline& line : d.lines) {
          for (Vec2 p : line.points)
            if (!within_reach(p)) w["svg"].fail(std::string("the drawing, scaled and placed, has ") + out_of_reach);
          add_polyline(scene.segments, line.points, line.closed, id);
        }
      } else {
        read_wall_shape(w, id, tolerance, scene.segments);
      }
      claim.add_segments(w, scene.segments.size() - before);
      for (size_t s = before; s < scene.segments.size(); ++s)
        if (norm(scene.segments[s].b - scene.segments[s].a) == 0) w.fail("a wall segment has zero length");
      wall.name = d.name;
      for (const Wall& other : scene.walls)
        if (other.name == wall.name) (w.has("name") ? w["name"] : w).fail("a wall named '" + wall.name + "' exists already");
      scene.walls.push_back(wall);
    }
  }
}

void attach_particles(const std::vector<Attachment>& attachments, Scene& scene) {
  scene.attached.assign(scene.n_particles(), Scene::free_particle);
  for (const Attachment& a : attachments) {
    int to = Scene::fixed_particle;
    if (!a.fixed) {
      const std::string name = a.node.text();
      std::vector<std::string> names;
      to = -3;
      for (size_t w = 0; w < scene.walls.size(); ++w) {
        names.push_back(scene.walls[w].name);
        if (scene.walls[w].name == name) to = static_cast<int>(w);
      }
      if (to == -3) a.node.fail("no wall is named '" + name + "'; the walls are " + choices_nearest_first(name, names));
      const WallMotion& m = scene.walls[to].motion;
      if (m.kind == WallMotion::Kind::translate && std::isfinite(m.distance))
        a.node.fail("particles cannot follow a wall that stops after a distance: their velocity would have to jump");
    }
    std::fill_n(scene.attached.begin() + a.first, a.count, to);
  }
}

// periodic: {x: [x0, x1], y: [y0, y1]}: the cell repeats along each axis given. Every particle
// starts inside it, and a period is at least four of the largest diameters, so that a particle
// meets each neighbour through one image only, with room for the neighbour skin.
void read_periodic(const SceneNode& root, Scene& scene, const ParticleSets& sets) {
  const auto cell = root.optional("periodic");
  if (!cell) return;
  cell->allow();
  const double largest = *std::max_element(scene.radius.begin(), scene.radius.end());
  auto axis = [&](const char* key, bool& on, double& lo, double& hi) {
    const auto range = cell->optional(key);
    if (!range) return;
    const auto v = range->items();
    if (v.size() != 2) range->fail("expected [low, high]");
    lo = point_of(v[0], v[1]).x;
    hi = point_of(v[1], v[0]).x;
    if (!(hi > lo)) range->fail("expected [low, high] with high > low");
    if (!(hi - lo >= 8 * largest))
      range->fail("the period is shorter than four of the largest particle diameters (8 x " + message_number(largest) +
                  " m): a particle would meet a neighbour through two images");
    on = true;
  };
  PeriodicCell& c = scene.periodic;
  axis("x", c.x, c.x0, c.x1);
  axis("y", c.y, c.y0, c.y1);
  if (!c.any()) cell->fail("give x: [x0, x1] and/or y: [y0, y1]");
  for (int i = 0; i < scene.n_particles(); ++i) {
    const Vec2 p = scene.position[i];
    if ((c.x && !(p.x >= c.x0 && p.x < c.x1)) || (c.y && !(p.y >= c.y0 && p.y < c.y1)))
      throw InputError(sets.location[sets.of[i]], sets.describe(i) + " starts outside the periodic cell");
  }
}

// A pair law that will be used must have what its model needs.
void check_laws(const Scene& scene, const std::vector<Location>& law_location) {
  const int nm = scene.n_materials();
  std::vector<bool> used(nm, false), wall_used(nm, false), wall_conducts(nm, false);
  for (int m : scene.material) used[m] = true;
  for (const Wall& w : scene.walls) {
    wall_used[w.material] = true;
    wall_conducts[w.material] = wall_conducts[w.material] || w.temperature.isothermal();
  }
  for (int a = 0; a < nm; ++a)
    for (int b = 0; b < nm; ++b) {
      if (!used[a] || !(used[b] || wall_used[b])) continue;
      const PairLaw& law = scene.law(a, b);
      const std::string pair = "'" + scene.materials[a].name + "' and '" + scene.materials[b].name + "'";
      if (law.model == NormalModel::linear && !(law.stiffness > 0))
        throw InputError(law_location[a * nm + b], "the linear contact between " + pair +
                                                       " needs a stiffness (materials' or the contact's 'stiffness')");
      if (law.model == NormalModel::hertz && !(law.effective_modulus > 0))
        throw InputError(law_location[a * nm + b],
                         "the Hertz contact between " + pair + " needs youngs_modulus on both materials");
      if (!scene.thermal || law.conduction == thermal::ConductionModel::none ||
          law.conduction == thermal::ConductionModel::constant)
        continue;
      if (!used[b] && !wall_conducts[b]) continue;
      if (!(scene.materials[a].conductivity > 0 && scene.materials[b].conductivity > 0))
        throw InputError(law_location[a * nm + b], "conduction between " + pair + " needs 'conductivity' on both materials");
      if (law.conduction == thermal::ConductionModel::hertz && !(law.effective_modulus > 0))
        throw InputError(law_location[a * nm + b],
                         "Hertz conduction between " + pair + " needs youngs_modulus on both materials");
      if (law.conduction == thermal::ConductionModel::pipe_network && scene.mass_model != MassModel::cylinder)
        throw InputError(law_location[a * nm + b], "pipe_network conduction is for cylinders: set mass_model: cylinder");
    }
}

// Initial contacts. A centre on a wall or on another centre is always an error: the contact normal
// runs from the one to the other and is undefined there. Other overlaps are errors unless
// allow_overlap.
void check_initial_contacts(const SceneNode& root, const Scene& scene, const ParticleSets& sets) {
  const bool overlap_allowed = root.has("allow_overlap") && root["allow_overlap"].boolean();
  std::vector<double> x, y;
  for (Vec2 p : scene.position) {
    x.push_back(p.x);
    y.push_back(p.y);
  }
  const double rmin = *std::min_element(scene.radius.begin(), scene.radius.end());
  Broadphase bp(1e-3 * rmin);
  std::vector<CandidatePair> pairs;
  bp.particle_pairs(x.data(), y.data(), scene.radius.data(), scene.n_particles(), scene.periodic, pairs);
  auto part_of_a_wall = [&](int i) { return !scene.attached.empty() && scene.attached[i] != Scene::free_particle; };
  for (const CandidatePair& p : pairs) {
    if (part_of_a_wall(p.i) && part_of_a_wall(p.j)) continue;  // walls do not touch walls
    const Location& at = sets.location[sets.of[p.j]];
    const Vec2 d = scene.position[p.j] - scene.position[p.i];
    const double distance = norm(scene.periodic.minimum_image(d.x, d.y));
    if (distance == 0)
      throw InputError(at, sets.describe(p.i) + " and " + sets.describe(p.j) +
                               " share a centre: their contact normal is undefined, even with allow_overlap");
    const double overlap = scene.radius[p.i] + scene.radius[p.j] - distance;
    if (overlap > 0 && !overlap_allowed) {
      std::ostringstream msg;
      msg << "particles " << p.i << " and " << p.j << " overlap by " << overlap << " m at the start (sets "
          << sets.location[sets.of[p.i]].key << " and " << at.key << "); move them apart or set allow_overlap: true";
      throw InputError(at, msg.str());
    }
  }
  std::vector<Vec2> a, b;
  for (const Segment& s : scene.segments) {
    a.push_back(s.a);
    b.push_back(s.b);
  }
  bp.wall_pairs(x.data(), y.data(), scene.radius.data(), scene.n_particles(), a, b, scene.periodic, pairs);
  for (const CandidatePair& p : pairs) {
    const Segment& s = scene.segments[p.j];
    const std::string wall = "wall '" + scene.walls[s.wall].name + "' (walls." + std::to_string(s.wall) + ")";
    const Location& at = sets.location[sets.of[p.i]];
    const double distance = distance_to_segment(scene.periodic.image_near(scene.position[p.i], 0.5 * (s.a + s.b)), s.a, s.b);
    if (distance == 0)
      throw InputError(at, sets.describe(p.i) + " has its centre on " + wall +
                               ": the contact normal is undefined, even with allow_overlap; move it off the wall");
    if (distance < scene.radius[p.i] && !overlap_allowed) {
      std::ostringstream msg;
      msg << sets.describe(p.i) << " overlaps " << wall << " by " << scene.radius[p.i] - distance
          << " m at the start; move it or set allow_overlap: true";
      throw InputError(at, msg.str());
    }
  }
}

void read_heat(const SceneNode& root, Scene& scene) {
  if (auto h = root.optional("heat_from_dissipation")) {
    const std::string mode = h->choice({"none", "friction", "all"});
    scene.heat_from_dissipation = mode == "all"        ? HeatFromDissipation::all
                                  : mode == "friction" ? HeatFromDissipation::friction
                                                       : HeatFromDissipation::none;
  }
  if (auto m = root.optional("mechanics")) scene.frozen = m->choice({"dynamic", "frozen"}) == "frozen";
  if (auto f = root.optional("freeze")) {
    f->allow();
    scene.freeze.enabled = true;
    scene.freeze.kinetic_energy_below = (*f)["kinetic_energy_below"].positive();
    if (auto n = f->optional("not_before")) scene.freeze.not_before = n->non_negative();
    if (auto l = f->optional("latest")) scene.freeze.latest = l->positive();
    scene.freeze.dt = (*f)["dt"].positive();
    if (auto o = f->optional("output_interval")) scene.freeze.output_interval = o->positive();
    if (auto i = f->optional("integrator")) scene.freeze.integrator = i->text();
  }
  if (scene.thermal) {
    for (int i = 0; i < scene.n_particles(); ++i) {
      const Material& m = scene.materials[scene.material[i]];
      if (!(m.specific_heat > 0 && m.conductivity > 0))
        root["materials"][m.name].fail("particles of a thermal scene need specific_heat and conductivity");
    }
    return;
  }
  const char* needs_heat = root.has("heat_from_dissipation") ? "heat_from_dissipation"
                           : root.has("freeze")              ? "freeze"
                                                             : nullptr;
  if (needs_heat) root[needs_heat].fail("this scene carries no temperatures (give particle sets a 'temperature')");
  if (scene.frozen) root["mechanics"].fail("mechanics: frozen leaves nothing to integrate without temperatures");
  for (size_t w = 0; w < scene.walls.size(); ++w)
    if (scene.walls[w].temperature.isothermal())
      root["walls"].items()[w]["temperature"].fail("this scene carries no temperatures (give particle sets a 'temperature')");
}

// The integrators a scene names exist and suit their stages: made once here (an unknown name is
// reported at its key; rtol and contact events are checked where the run makes it, since studies
// override the integrator after loading), and IMEX Euler only where no contact is integrated (its
// forward Euler grows every undamped contact oscillation).
void check_integrators(const SceneNode& root, const Scene& scene) {
  auto check = [&](const SceneNode* node, const std::string& name, bool mechanics) {
    try {
      make_integrator(name);
    } catch (const InputError& e) {
      if (node) node->fail(e.what());
      throw;
    }
    if (mechanics && name == "imex1") {
      const std::string why =
          "imex1 integrates heat on frozen networks only: its explicit Euler part is unstable on undamped contacts. Use "
          "it with 'mechanics: frozen' or as 'freeze.integrator'; for moving grains pick imex3, imex4 or imex5";
      if (node) node->fail(why);
      throw InputError(why);
    }
  };
  const auto integrator_node = root.optional("integrator");
  check(integrator_node ? &*integrator_node : nullptr, scene.integrator, !scene.frozen);
  if (const auto freeze = root.optional("freeze"))
    if (const auto i = freeze->optional("integrator")) check(&*i, scene.freeze.integrator, false);
}

// The steps: integrator, tolerances, dt, t_end and frames.
void read_stepping(const SceneNode& root, Scene& scene) {
  if (auto i = root.optional("integrator")) scene.integrator = i->text();
  // Below 1e-14 no integrator can meet the tolerance in double precision: ARKODE fails its steps.
  if (auto r = root.optional("rtol")) scene.control.rtol = r->in_range(1e-14, 1, false, true);
  // atol: a number for every component, or per field {position, velocity, angle, temperature, other}.
  if (auto a = root.optional("atol")) {
    if (a->is_map()) {
      a->allow();
      auto field = [&](const char* key, double fallback) { return a->has(key) ? (*a)[key].positive() : fallback; };
      scene.control.atol = field("other", 0);
      scene.control.atol_position = field("position", NAN);
      scene.control.atol_velocity = field("velocity", NAN);
      scene.control.atol_angle = field("angle", NAN);
      scene.control.atol_temperature = field("temperature", NAN);
    } else {
      scene.control.atol = a->positive();
    }
  }
  // Whether the integrator can adapt or locate events is checked where it is made (make_integrator).
  if (auto e = root.optional("contact_events")) scene.control.contact_events = e->boolean();
  if (auto l = root.optional("linear_solver")) {
    scene.control.linear_solver =
        l->choice({"cholesky", "cg"}) == "cg" ? LinearSolverKind::cg : LinearSolverKind::cholesky;
  }
  check_integrators(root, scene);
  // How many steps that makes is judged with the other limits of dt (judge_dt), which --force overrides.
  scene.dt = root["dt"].positive();
  scene.t_end = root["t_end"].positive();
  if (scene.dt > scene.t_end) root["dt"].fail("dt is longer than t_end");
  scene.output_interval = root.has("output_interval") ? root["output_interval"].positive() : scene.t_end / 100;
}

// The run's own checks, its early stop, and the quantities it reports.
void read_checks(const SceneNode& root, Scene& scene) {
  if (auto s = root.optional("skin")) scene.skin = length(*s);
  if (auto checks = root.optional("checks")) {
    checks->allow();
    if (auto f = checks->optional("max_overlap_fraction")) scene.max_overlap_fraction = f->in_range(0, 1, true, false);
  }
  if (auto stop = root.optional("stop")) {
    stop->allow();
    scene.stop_kinetic_energy = (*stop)["kinetic_energy_below"].positive();
    if (auto n = stop->optional("not_before")) scene.stop_not_before = n->non_negative();
  }
  if (auto report = root.optional("report")) {
    for (const SceneNode& q : report->items()) {
      const std::string name = q.text();
      const auto& known = observer_names();
      if (std::find(known.begin(), known.end(), name) == known.end())
        q.fail("unknown quantity '" + name + "'; available: " + choices_nearest_first(name, known));
      if (const std::string need = observer_needs(name, scene); !need.empty()) q.fail("'" + name + "' needs " + need);
      scene.report.push_back(name);
    }
  }
}

void read_materials(const SceneNode& root, Scene& scene, MaterialIndex& index) {
  const auto materials = root["materials"].entries();
  if (materials.size() > max_materials)
    root["materials"].fail(std::to_string(materials.size()) + " materials; at most " + std::to_string(max_materials) +
                           " (every pair of them gets a contact law, solved for when a run starts)");
  for (const auto& [name, node] : materials) {
    index.by_name[name] = scene.n_materials();
    scene.materials.push_back(read_material(name, node));
  }
}

Scene read_scene(const SceneNode& root, const std::string& file, uint64_t memory) {
  root.allow();
  Scene scene;
  scene.file = file;
  scene.name = read_name(root["name"]);
  if (auto d = root.optional("description")) scene.description = d->text();
  if (auto m = root.optional("mass_model")) {
    if (m->choice({"sphere", "cylinder"}) == "cylinder") {
      scene.mass_model = MassModel::cylinder;
      scene.thickness = length(root["thickness"]);
    }
  }
  if (root.has("thickness") && scene.mass_model != MassModel::cylinder)
    root["thickness"].fail("thickness applies only to mass_model: cylinder");
  if (auto g = root.optional("gravity")) scene.gravity = g->vec2();
  MaterialIndex index;
  read_materials(root, scene, index);
  std::vector<Location> law_location;
  read_contacts(root, scene, index, law_location);
  MemoryClaim claim(memory);
  ParticleSets sets;
  std::vector<Attachment> attachments;
  read_particles(root, scene, index, sets, claim, attachments);
  read_walls(root, scene, index, claim);
  attach_particles(attachments, scene);
  read_periodic(root, scene, sets);
  read_heat(root, scene);
  check_laws(scene, law_location);
  check_initial_contacts(root, scene, sets);
  read_stepping(root, scene);
  read_checks(root, scene);
  return scene;
}

}  // namespace

uint64_t physical_memory() {
  const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return uint64_t{4} << 30;  // not told: assume a small machine, 4 GB
  return static_cast<uint64_t>(pages) * static_cast<uint64_t>(page_size);
}

Scene parse_scene(const std::string& text, const std::string& file, const std::vector<std::string>& overrides,
                  uint64_t memory) {
  // Names and texts end up in summary.json: text the JSON writer would refuse is refused here.
  check_utf8(text, file);
  YAML::Node doc;
  try {
    doc = YAML::Load(text);
  } catch (const YAML::DeepRecursion& e) {
    throw InputError({file, e.mark.line + 1, ""},
                     "lists or maps nested " + std::to_string(e.depth()) + " levels deep: not a scene");
  } catch (const YAML::ParserException& e) {
    throw InputError({file, e.mark.line + 1, ""}, "not valid YAML: " + e.msg);
  }
  if (!doc.IsMap()) throw InputError({file, 1, ""}, "a scene is a map of keys (name, materials, particles, ...)");
  // Without aliases a document has fewer values than characters (each takes one at least).
  check_structure(doc, {file, 1, ""}, 2 * text.size() + 1000);
  auto source = std::make_shared<SceneReading>();
  source->file = file;
  source->schema = &scene_schema;
  source->overridden = apply_overrides(doc, overrides, scene_schema);
  const SceneNode root(doc, source);
  Scene scene = read_scene(root, file, memory);
  root.check_all_read();
  return scene;
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides, uint64_t memory) {
  std::ifstream in(path);
  if (!in) throw InputError({path, 0, ""}, "cannot open the scene file");
  std::stringstream text;
  text << in.rdbuf();
  return parse_scene(text.str(), path, overrides, memory);
}

}  // namespace kiln
