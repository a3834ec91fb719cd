// The particle sets: placed at points, filled at random in a region, on a lattice, or read from a
// particle file; each with its material, velocities and temperatures.
#include "src/scene/scene_parts.h"

#include <algorithm>
#include <cfloat>
#include <cmath>
#include <optional>
#include "src/base/text_format.h"
#include "src/scene/particle_file.h"
#include "src/scene/particle_fill.h"

namespace kiln::scene_parts {

namespace {

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
  // Refused from the area before any placement: a million discs that cannot fit were placed one by
  // one until the first found no room, which took minutes.
  if (const std::string why = fill_cannot_fit(region, count, read_radius(radius)); !why.empty()) fill["count"].fail(why);
  const long long seed = fill.has("seed") ? fill["seed"].integer(0, LLONG_MAX) : 1;
  // A disc that finds no place in a million tries will not find one: the region is full.
  const long long attempts = fill.has("attempts") ? fill["attempts"].integer(1, 1000000) : 10000;
  try {
    return random_fill(region, static_cast<int>(count), read_radius(radius),
                       ensemble_seed(static_cast<uint64_t>(seed), scene.ensemble_member), attempts, scene.position,
                       scene.radius);
  } catch (const std::runtime_error& e) {
    fill.fail(e.what());
  }
}

// lattice: rows x columns discs, their number computed in 64 bits and counted against the memory.
Placement read_lattice(const SceneNode& lat, const SceneNode& radius, const Scene& scene, MemoryClaim& claim) {
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
                 ensemble_seed(static_cast<uint64_t>(seed), scene.ensemble_member));
}

// file: a particle file (src/scene/particle_file.h) beside the scene, in the format of its extension or
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
  if (auto lat = ps.optional("lattice")) return read_lattice(*lat, ps["radius"], scene, claim);
  const auto at = ps["at"].items();
  claim.add_particles(ps["at"], static_cast<long long>(at.size()), std::to_string(at.size()));
  const RadiusDistribution radii = read_radius(ps["radius"]);
  Placement placed;
  Random rng(ensemble_seed(0, scene.ensemble_member));
  for (const SceneNode& p : at) {
    placed.position.push_back(point(p));
    placed.radius.push_back(radii.draw(rng));
  }
  return placed;
}

// Whether a particle set's placement, radii or velocities are drawn from a seed (and so differ
// between the members of an ensemble).
bool declares_randomness(const SceneNode& ps) {
  const bool jitter = ps.has("lattice") && ps["lattice"].has("jitter") && ps["lattice"]["jitter"].non_negative() > 0;
  return ps.has("fill") || jitter || ps.has("random_velocity") || (ps.has("radius") && ps["radius"].is_map());
}

}  // namespace

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
    // The lightest disc's mass and moment of inertia must be normal numbers: a density of 1e-300
    // passed every range, and the run divided by a subnormal mass, died of NaN and blamed dt
    // (issue 28's campaign). Its heat capacity too, in a heated set: a mass of 1e-285 kg times a
    // specific heat of 1e-20 is subnormal, and the estimate said the scene's constants
    // "overflow", naming none (issue 28's review).
    if (!placed.radius.empty()) {
      const double r = *std::min_element(placed.radius.begin(), placed.radius.end());
      const Material& material = scene.materials[mat];
      const double density = material.density, m = disc_mass(scene, r, density);
      if (!(m >= DBL_MIN) || !(disc_inertia(scene, m, r) >= DBL_MIN))
        ps["material"].fail(format("this set's smallest disc (radius %g m, density %g kg/m^3) has a mass of %g kg: its "
                                   "mass and moment of inertia must be at least %g (the smallest normal double), or "
                                   "its accelerations overflow; raise the density",
                                   r, density, m, DBL_MIN));
      const double c = m * material.specific_heat;
      if ((ps.has("temperature") || file_temperatures) && material.specific_heat > 0 && !(c >= DBL_MIN))
        ps["material"].fail(format("this set's smallest disc (radius %g m) has a heat capacity of %g J/K (density %g "
                                   "kg/m^3 x specific heat %g J/(kg K)): it must be at least %g (the smallest normal "
                                   "double), or its heating rates overflow; raise the density or the specific heat",
                                   r, c, density, material.specific_heat, DBL_MIN));
    }
    for (size_t k = 0; k < placed.position.size(); ++k)
      if (!within_reach(placed.position[k]))
        ps.fail("particle " + std::to_string(k) + " of this set lies at " + out_of_reach);
    // random_velocity: {max: V, seed: S} adds to each velocity component a uniform draw in [-V, V].
    double jitter = 0;
    Random velocity_rng(1);
    if (auto rv = ps.optional("random_velocity")) {
      rv->allow();
      jitter = (*rv)["max"].positive();
      velocity_rng = Random(ensemble_seed(
          static_cast<uint64_t>(rv->has("seed") ? (*rv)["seed"].integer(0, LLONG_MAX) : 1), scene.ensemble_member));
    }
    if (declares_randomness(ps)) scene.random_sources.push_back(ps.path());
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
    // Room for the set at once, growing by at least twice as push_back would: 10^7 discs were
    // copied from one doubled vector to the next for seconds.
    auto make_room = [extra = placed.radius.size()](auto& v) {
      if (v.capacity() < v.size() + extra) v.reserve(std::max(v.size() + extra, 2 * v.capacity()));
    };
    make_room(scene.position);
    make_room(scene.radius);
    make_room(scene.velocity);
    make_room(scene.angular_velocity);
    make_room(scene.material);
    make_room(sets.of);
    if (thermal_set) make_room(scene.temperature);
    for (size_t k = 0; k < placed.radius.size(); ++k) {
      if (file_temperatures) scene.temperature.push_back(file->temperature[k]);
      else if (temp) scene.temperature.push_back(placed.position[k].x < x_split ? t_left : t_right);
      scene.position.push_back(placed.position[k]);
      scene.radius.push_back(placed.radius[k]);
      Vec2 v = file && file->has_velocity ? file->velocity[k] : velocity;
      if (jitter > 0) v = v + Vec2{velocity_rng.uniform(-jitter, jitter), velocity_rng.uniform(-jitter, jitter)};
      if (!std::isfinite(v.x) || !std::isfinite(v.y))
        ps.fail("the velocities overflow double precision (random_velocity.max near 1.8e308)");
      // No grain moves faster than light: a bound no physical scene meets, far below where a kinetic
      // energy overflows (an angular_velocity of 1e300 passed check and the run died of an
      // infinite I omega^2, blaming dt; issue 28's review).
      const double w = file && file->has_angular_velocity ? file->angular_velocity[k] : spin;
      const double speed = std::hypot(v.x, v.y), rim = std::abs(w) * placed.radius[k];
      if (!(speed <= speed_of_light) || !(rim <= speed_of_light)) {
        const bool moving = !(speed <= speed_of_light);
        const char* key = moving ? (file && file->has_velocity ? "file" : jitter > 0 ? "random_velocity" : "velocity")
                                 : (file && file->has_angular_velocity ? "file" : "angular_velocity");
        ps[key].fail(format("particle %zu of this set would move at %g m/s (%s): faster than light (299792458 m/s)",
                            k, moving ? speed : rim, moving ? "its velocity" : "its rim, angular velocity x radius"));
      }
      scene.velocity.push_back(v);
      scene.angular_velocity.push_back(w);
      scene.material.push_back(mat);
      sets.of.push_back(static_cast<int>(sets.location.size()));
    }
    sets.location.push_back(ps.location());
  }
  if (scene.radius.empty()) root["particles"].fail("the scene has no particles");
}

}  // namespace kiln::scene_parts
