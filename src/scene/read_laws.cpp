// The materials and the contact law of every pair of them: defaults mixed from the materials,
// each `contacts:` entry over them, and the checks that a law in use has what its model needs.
#include "src/scene/scene_parts.h"

#include <algorithm>
#include <cmath>

namespace kiln::scene_parts {

namespace {

// Every pair of materials gets a contact law whose damping is solved for when a run starts (up to
// 0.2 s each, n (n + 1) / 2 of them): 16 materials cost half a minute at worst.
constexpr int max_materials = 16;

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

}  // namespace

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

}  // namespace kiln::scene_parts
