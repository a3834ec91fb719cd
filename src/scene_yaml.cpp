#include "src/scene_yaml.h"

#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cmath>
#include <fstream>
#include <map>
#include <sstream>

#include "src/broadphase.h"
#include "src/nearest.h"
#include "src/observers.h"
#include "src/overrides.h"
#include "src/particle_fill.h"
#include "src/scene_reader.h"
#include "src/wall_geometry.h"

namespace kiln {

namespace {

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
  m.allow({"density", "youngs_modulus", "poisson_ratio", "stiffness", "restitution", "friction", "rolling_friction",
           "specific_heat", "conductivity", "electrical_resistivity"});
  Material mat;
  mat.name = name;
  if (auto v = m.optional("density")) mat.density = v->positive();
  if (auto v = m.optional("youngs_modulus")) mat.youngs_modulus = v->positive();
  if (auto v = m.optional("poisson_ratio")) mat.poisson_ratio = v->in_range(-1, 0.5, true, false);
  if (auto v = m.optional("stiffness")) mat.stiffness = v->positive();
  if (auto v = m.optional("restitution")) mat.restitution = v->in_range(0, 1, true, false);
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
      c.allow({"between", "model", "stiffness", "restitution", "damping_rate", "tension", "friction",
               "rolling_friction", "rolling_model", "rolling_damping_ratio", "tangential_stiffness_ratio", "tangential_damping_ratio", "conduction", "conductance",
               "softened_modulus_ratio", "contact_resistance"});
      const auto pair = c["between"].items();
      if (pair.size() != 2) c["between"].fail("expected two material names [a, b]");
      const int a = index.find(pair[0]), b = index.find(pair[1]);
      PairLaw law = scene.laws[a * nm + b];
      if (auto v = c.optional("model")) law.model = read_model(*v);
      if (auto v = c.optional("stiffness")) law.stiffness = v->positive();
      if (auto v = c.optional("restitution")) law.restitution = v->in_range(0, 1, true, false);
      if (auto v = c.optional("damping_rate")) law.damping_rate = v->non_negative();
      if (c.has("restitution") && c.has("damping_rate"))
        c["damping_rate"].fail("give either restitution or damping_rate, not both");
      if (auto v = c.optional("tension")) law.tension = v->boolean();
      if (auto v = c.optional("friction")) law.friction = v->non_negative();
      if (auto v = c.optional("rolling_friction")) law.rolling_friction = v->non_negative();
      if (auto v = c.optional("rolling_model")) law.rolling_model = read_rolling_model(*v);
      if (auto v = c.optional("rolling_damping_ratio")) law.rolling_damping_ratio = v->non_negative();
      if (c.has("rolling_damping_ratio") && law.rolling_model != contact::RollingModel::epsd)
        c["rolling_damping_ratio"].fail("applies to rolling_model: epsd only; this pair's rolling model is constant");
      if (auto v = c.optional("tangential_stiffness_ratio")) law.tangential_stiffness_ratio = v->positive();
      if (auto v = c.optional("tangential_damping_ratio")) law.tangential_damping_ratio = v->non_negative();
      if (auto v = c.optional("conduction")) law.conduction = read_conduction(*v);
      if (law.conduction == thermal::ConductionModel::constant) law.conductance = c["conductance"].positive();
      if (auto v = c.optional("softened_modulus_ratio")) law.modulus_ratio = v->in_range(0, 1, true, false);
      if (auto v = c.optional("contact_resistance")) law.contact_resistance = v->non_negative();
      scene.laws[a * nm + b] = scene.laws[b * nm + a] = law;
      law_location[a * nm + b] = law_location[b * nm + a] = c.location();
    }
  }
}

RadiusDistribution read_radius(const SceneNode& node) {
  if (node.is_map()) {
    node.allow({"uniform"});
    const auto range = node["uniform"].items();
    if (range.size() != 2) node["uniform"].fail("expected [min, max]");
    const double lo = range[0].positive(), hi = range[1].positive();
    if (hi < lo) node["uniform"].fail("expected min <= max");
    return {lo, hi};
  }
  const double r = node.positive();
  return {r, r};
}

Region read_region(const SceneNode& fill) {
  Region region;
  if (auto rect = fill.optional("rectangle")) {
    const auto v = rect->items();
    if (v.size() != 4) rect->fail("expected [x0, y0, x1, y1]");
    const double x0 = v[0].number(), y0 = v[1].number(), x1 = v[2].number(), y1 = v[3].number();
    if (!(x1 > x0 && y1 > y0)) rect->fail("expected x1 > x0 and y1 > y0");
    region.corners = {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}};
  } else if (auto poly = fill.optional("polygon")) {
    for (const SceneNode& p : poly->items()) region.corners.push_back(p.vec2());
    if (region.corners.size() < 3) poly->fail("expected at least three corners");
  } else {
    fill.fail("expected a region: 'rectangle' or 'polygon'");
  }
  return region;
}

void read_particles(const SceneNode& root, Scene& scene, const MaterialIndex& index,
                    std::vector<Location>& set_location, std::vector<int>& set_of) {
  int set = 0;
  for (const SceneNode& ps : root["particles"].items()) {
    ps.allow({"material", "radius", "velocity", "random_velocity", "angular_velocity", "temperature", "at", "fill",
              "lattice"});
    const int mat = index.find(ps["material"]);
    if (!(scene.materials[mat].density > 0)) ps["material"].fail("this material needs a density to make particles");
    const int ways = ps.has("at") + ps.has("fill") + ps.has("lattice");
    if (ways != 1) ps.fail("give exactly one of 'at' (a list of positions), 'fill' or 'lattice'");
    const Vec2 velocity = ps.optional("velocity") ? ps["velocity"].vec2() : Vec2{};
    const double spin = ps.number_or("angular_velocity", 0);
    Placement placed;
    if (auto at = ps.optional("at")) {
      const RadiusDistribution radii = read_radius(ps["radius"]);
      Random rng(0);
      for (const SceneNode& p : at->items()) {
        placed.position.push_back(p.vec2());
        placed.radius.push_back(radii.draw(rng));
      }
    } else if (auto fill = ps.optional("fill")) {
      fill->allow({"rectangle", "polygon", "count", "seed", "attempts"});
      const Region region = read_region(*fill);
      const int count = static_cast<int>((*fill)["count"].integer(1));
      const long seed = fill->has("seed") ? (*fill)["seed"].integer(0) : 1;
      const long attempts = fill->has("attempts") ? (*fill)["attempts"].integer(1) : 10000;
      try {
        placed = random_fill(region, count, read_radius(ps["radius"]), static_cast<uint64_t>(seed), attempts,
                             scene.position, scene.radius);
      } catch (const std::runtime_error& e) {
        fill->fail(e.what());
      }
    } else {
      const SceneNode lat = ps["lattice"];
      lat.allow({"kind", "origin", "spacing", "rows", "columns", "jitter", "seed"});
      const bool hex = lat.has("kind") && lat["kind"].choice({"hexagonal", "square"}) == "hexagonal";
      placed = lattice(hex, lat["origin"].vec2(), lat["spacing"].positive(), static_cast<int>(lat["rows"].integer(1)),
                       static_cast<int>(lat["columns"].integer(1)), read_radius(ps["radius"]),
                       lat.has("jitter") ? lat["jitter"].non_negative() : 0.0,
                       static_cast<uint64_t>(lat.has("seed") ? lat["seed"].integer(0) : 1));
    }
    // random_velocity: {max: V, seed: S} adds to each velocity component a uniform draw in [-V, V].
    double jitter = 0;
    Random velocity_rng(1);
    if (auto rv = ps.optional("random_velocity")) {
      rv->allow({"max", "seed"});
      jitter = (*rv)["max"].positive();
      velocity_rng = Random(static_cast<uint64_t>(rv->has("seed") ? (*rv)["seed"].integer(0) : 1));
    }
    // temperature: T, or {x_split: x, left: T1, right: T2} (a hot half and a cold half).
    const auto temp = ps.optional("temperature");
    double t_left = NAN, t_right = NAN, x_split = INFINITY;
    if (temp && temp->is_map()) {
      temp->allow({"x_split", "left", "right"});
      x_split = (*temp)["x_split"].number();
      t_left = (*temp)["left"].number();
      t_right = (*temp)["right"].number();
    } else if (temp) {
      t_left = t_right = temp->number();
    }
    if (scene.thermal != static_cast<bool>(temp) && !scene.position.empty())
      ps.fail("either every particle set gives a temperature (a thermal scene) or none does");
    scene.thermal = static_cast<bool>(temp);
    for (size_t k = 0; k < placed.radius.size(); ++k) {
      if (temp) scene.temperature.push_back(placed.position[k].x < x_split ? t_left : t_right);
      scene.position.push_back(placed.position[k]);
      scene.radius.push_back(placed.radius[k]);
      Vec2 v = velocity;
      if (jitter > 0) v = v + Vec2{velocity_rng.uniform(-jitter, jitter), velocity_rng.uniform(-jitter, jitter)};
      scene.velocity.push_back(v);
      scene.angular_velocity.push_back(spin);
      scene.material.push_back(mat);
      set_of.push_back(set);
    }
    set_location.push_back(ps.location());
    ++set;
  }
  if (scene.radius.empty()) root["particles"].fail("the scene has no particles");
}

WallMotion read_motion(const SceneNode& m) {
  WallMotion motion;
  const std::string kind = m["type"].choice({"fixed", "translate", "rotate"});
  if (kind == "fixed") {
    m.allow({"type"});
  } else if (kind == "translate") {
    m.allow({"type", "velocity", "distance"});
    motion.kind = WallMotion::Kind::translate;
    motion.velocity = m["velocity"].vec2();
    motion.distance = m.has("distance") ? m["distance"].non_negative() : INFINITY;
  } else {
    m.allow({"type", "centre", "rpm"});
    motion.kind = WallMotion::Kind::rotate;
    motion.centre = m["centre"].vec2();
    motion.omega = m["rpm"].number() * 2 * M_PI / 60;
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
    wt.values = {node.number()};
    return wt;
  }
  node.allow({"steps", "ramp"});
  if (node.has("steps") == node.has("ramp")) node.fail("give one of 'steps' or 'ramp'");
  const bool steps = node.has("steps");
  wt.kind = steps ? thermal::WallTemperature::Kind::steps : thermal::WallTemperature::Kind::ramp;
  const SceneNode list = node[steps ? "steps" : "ramp"];
  for (const SceneNode& point : list.items()) {
    const Vec2 tv = point.vec2();
    if (!wt.times.empty() && tv.x <= wt.times.back()) point.fail("times must increase");
    wt.times.push_back(tv.x);
    wt.values.push_back(tv.y);
  }
  if (wt.times.empty()) list.fail("expected at least one [time, temperature] point");
  return wt;
}

void read_walls(const SceneNode& root, Scene& scene, const MaterialIndex& index) {
  const auto walls = root.optional("walls");
  if (!walls) return;
  for (const SceneNode& w : walls->items()) {
    w.allow({"name", "material", "motion", "temperature", "segment", "polyline", "box", "circle", "arc", "closed",
             "tolerance"});
    Wall wall;
    const int id = static_cast<int>(scene.walls.size());
    wall.name = w.has("name") ? w["name"].text() : "wall" + std::to_string(id);
    wall.material = index.find(w["material"]);
    if (auto m = w.optional("motion")) wall.motion = read_motion(*m);
    if (auto t = w.optional("temperature")) wall.temperature = read_wall_temperature(*t);
    const int shapes = w.has("segment") + w.has("polyline") + w.has("box") + w.has("circle") + w.has("arc");
    if (shapes != 1) w.fail("give exactly one shape: segment, polyline, box, circle or arc");
    const double tolerance = w.has("tolerance") ? w["tolerance"].positive() : 1e-5;
    const size_t before = scene.segments.size();
    auto points = [](const SceneNode& list) {
      std::vector<Vec2> pts;
      for (const SceneNode& p : list.items()) pts.push_back(p.vec2());
      return pts;
    };
    if (auto s = w.optional("segment")) {
      const auto pts = points(*s);
      if (pts.size() != 2) s->fail("expected two points [[x0, y0], [x1, y1]]");
      add_polyline(scene.segments, pts, false, id);
    } else if (auto p = w.optional("polyline")) {
      const auto pts = points(*p);
      if (pts.size() < 2) p->fail("expected at least two points");
      add_polyline(scene.segments, pts, w.has("closed") && w["closed"].boolean(), id);
    } else if (auto b = w.optional("box")) {
      const auto v = b->items();
      if (v.size() != 4) b->fail("expected [x0, y0, x1, y1]");
      const double x0 = v[0].number(), y0 = v[1].number(), x1 = v[2].number(), y1 = v[3].number();
      if (!(x1 > x0 && y1 > y0)) b->fail("expected x1 > x0 and y1 > y0");
      add_polyline(scene.segments, {{x0, y0}, {x1, y0}, {x1, y1}, {x0, y1}}, true, id);
    } else if (auto c = w.optional("circle")) {
      c->allow({"centre", "radius"});
      auto pts = arc_points((*c)["centre"].vec2(), (*c)["radius"].positive(), 0, 2 * M_PI, tolerance);
      pts.pop_back();  // the last point closes onto the first
      add_polyline(scene.segments, pts, true, id);
    } else {
      const SceneNode arc = w["arc"];
      arc.allow({"centre", "radius", "from_deg", "to_deg"});
      const double from = arc["from_deg"].number() * M_PI / 180, to = arc["to_deg"].number() * M_PI / 180;
      if (!(to > from)) arc["to_deg"].fail("expected to_deg > from_deg (counter-clockwise)");
      add_polyline(scene.segments, arc_points(arc["centre"].vec2(), arc["radius"].positive(), from, to, tolerance),
                   false, id);
    }
    for (size_t s = before; s < scene.segments.size(); ++s)
      if (norm(scene.segments[s].b - scene.segments[s].a) == 0) w.fail("a wall segment has zero length");
    scene.walls.push_back(wall);
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

void check_overlaps(const SceneNode& root, const Scene& scene, const std::vector<Location>& set_location,
                    const std::vector<int>& set_of) {
  if (root.has("allow_overlap") && root["allow_overlap"].boolean()) return;
  std::vector<double> x, y;
  for (Vec2 p : scene.position) {
    x.push_back(p.x);
    y.push_back(p.y);
  }
  double rmin = scene.radius.front();
  for (double r : scene.radius) rmin = std::min(rmin, r);
  Broadphase bp(1e-3 * rmin);
  std::vector<CandidatePair> pairs;
  bp.particle_pairs(x.data(), y.data(), scene.radius.data(), scene.n_particles(), pairs);
  for (const CandidatePair& p : pairs) {
    const double overlap = scene.radius[p.i] + scene.radius[p.j] - norm(scene.position[p.j] - scene.position[p.i]);
    if (overlap > 0) {
      std::ostringstream msg;
      msg << "particles " << p.i << " and " << p.j << " overlap by " << overlap << " m at the start (sets "
          << set_location[set_of[p.i]].key << " and " << set_location[set_of[p.j]].key
          << "); move them apart or set allow_overlap: true";
      throw InputError(set_location[set_of[p.j]], msg.str());
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
    f->allow({"kinetic_energy_below", "not_before", "latest", "dt", "output_interval", "integrator"});
    scene.freeze.enabled = true;
    scene.freeze.kinetic_energy_below = (*f)["kinetic_energy_below"].positive();
    scene.freeze.not_before = f->number_or("not_before", 0);
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

}  // namespace

Scene parse_scene(const std::string& text, const std::string& file, const std::vector<std::string>& overrides) {
  YAML::Node doc;
  try {
    doc = YAML::Load(text);
  } catch (const YAML::ParserException& e) {
    throw InputError({file, e.mark.line + 1, ""}, "not valid YAML: " + e.msg);
  }
  if (!doc.IsMap()) throw InputError({file, 1, ""}, "a scene is a map of keys (name, materials, particles, ...)");
  const auto overridden = std::make_shared<const std::set<std::string>>(apply_overrides(doc, overrides));
  const SceneNode root(doc, "", file, overridden);
  root.allow({"name", "description", "mass_model", "thickness", "gravity", "materials", "contact_model", "contacts",
              "conduction_model", "rolling_model", "heat_from_dissipation", "mechanics", "freeze", "particles", "walls", "integrator", "rtol", "atol", "contact_events", "linear_solver", "dt",
              "t_end", "output_interval", "skin", "allow_overlap", "checks", "stop", "report"});
  Scene scene;
  scene.file = file;
  scene.name = root["name"].text();
  if (auto d = root.optional("description")) scene.description = d->text();
  if (auto m = root.optional("mass_model")) {
    if (m->choice({"sphere", "cylinder"}) == "cylinder") {
      scene.mass_model = MassModel::cylinder;
      scene.thickness = root["thickness"].positive();
    }
  }
  if (root.has("thickness") && scene.mass_model != MassModel::cylinder)
    root["thickness"].fail("thickness applies only to mass_model: cylinder");
  if (auto g = root.optional("gravity")) scene.gravity = g->vec2();

  MaterialIndex index;
  for (const auto& [name, node] : root["materials"].entries()) {
    index.by_name[name] = scene.n_materials();
    scene.materials.push_back(read_material(name, node));
  }
  std::vector<Location> law_location;
  read_contacts(root, scene, index, law_location);
  std::vector<Location> set_location;
  std::vector<int> set_of;
  read_particles(root, scene, index, set_location, set_of);
  read_walls(root, scene, index);
  read_heat(root, scene);
  check_laws(scene, law_location);
  check_overlaps(root, scene, set_location, set_of);

  if (auto i = root.optional("integrator")) scene.integrator = i->text();
  if (auto r = root.optional("rtol")) scene.control.rtol = r->in_range(0, 1, true, true);
  // atol: a number for every component, or per field {position, velocity, angle, temperature, other}.
  if (auto a = root.optional("atol")) {
    if (a->is_map()) {
      a->allow({"position", "velocity", "angle", "temperature", "other"});
      scene.control.atol = a->number_or("other", 0);
      scene.control.atol_position = a->number_or("position", NAN);
      scene.control.atol_velocity = a->number_or("velocity", NAN);
      scene.control.atol_angle = a->number_or("angle", NAN);
      scene.control.atol_temperature = a->number_or("temperature", NAN);
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
  scene.dt = root["dt"].positive();
  scene.t_end = root["t_end"].positive();
  if (scene.dt > scene.t_end) root["dt"].fail("dt is longer than t_end");
  scene.output_interval = root.has("output_interval") ? root["output_interval"].positive() : scene.t_end / 100;
  if (auto s = root.optional("skin")) scene.skin = s->positive();
  if (auto checks = root.optional("checks")) {
    checks->allow({"max_overlap_fraction"});
    if (auto f = checks->optional("max_overlap_fraction")) scene.max_overlap_fraction = f->in_range(0, 1, true, false);
  }
  if (auto stop = root.optional("stop")) {
    stop->allow({"kinetic_energy_below", "not_before"});
    scene.stop_kinetic_energy = (*stop)["kinetic_energy_below"].positive();
    scene.stop_not_before = stop->number_or("not_before", 0);
  }
  if (auto report = root.optional("report")) {
    for (const SceneNode& q : report->items()) {
      const std::string name = q.text();
      const auto& known = observer_names();
      if (std::find(known.begin(), known.end(), name) == known.end())
        q.fail("unknown quantity '" + name + "'; available: " + choices_nearest_first(name, known));
      if ((name == "temperatures" || name == "temperature_profile") && !scene.thermal)
        q.fail("'" + name + "' needs a thermal scene");
      scene.report.push_back(name);
    }
  }
  return scene;
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides) {
  std::ifstream in(path);
  if (!in) throw InputError({path, 0, ""}, "cannot open the scene file");
  std::stringstream text;
  text << in.rdbuf();
  return parse_scene(text.str(), path, overrides);
}

}  // namespace kiln
