// The materials and the contact law of every pair of them: defaults mixed from the materials,
// each `contacts:` entry over them, and the checks that a law in use has what its model needs.
// The keys that only some models read are not named here: each law's table lists its models with
// their keys (contact/model_table.h, thermal/conduction_model.h), and an entry is read through it.
#include "src/scene/scene_parts.h"

#include <algorithm>
#include <iterator>

#include "contact/model_table.h"
#include "thermal/conduction_model.h"

namespace kiln::scene_parts {

namespace {

// Every pair of materials gets a contact law whose damping is solved for when a run starts (up to
// 0.2 s each, n (n + 1) / 2 of them): 16 materials cost half a minute at worst.
constexpr int max_materials = 16;

// The keys of a `contacts:` entry that every law reads; the others belong to some models of a law
// and are listed in its table.
const char* const common_keys[] = {"between", "model", "restitution", "tension", "friction", "rolling_friction",
                                   "rolling_model", "tangential_stiffness_ratio", "tangential_damping_ratio",
                                   "conduction"};

// The largest value of a material constant that the laws multiply with others, and why it is
// there: the largest in nature with room for a model's scalings, far below where a product in the
// laws overflows or its round-off outweighs the energies the ledger checks. Issue 28's campaign
// (F10): a conductivity of 1e300 passed, a pair's harmonic mean 2 k1 k2 / (k1 + k2) overflowed,
// check only warned (an explicit conduction limit of 0 s) and the run died of NaN; a specific heat
// of 1e12 passed and the round-off of the heat contents read as an energy blow-up (N2, T4); a
// Young's modulus of 1e60 to 1e100 passed as "no stability limit from the contacts" and the run
// died; two resistivities of 1e308 summed to infinity and shared friction heat wrongly.
// Not bounded: stiffness (two combine in series without overflow, contact/contact_law.cpp, and the
// step estimate refuses any that leaves no step), friction and rolling friction (a coefficient
// only caps a force: a huge one is a contact that never slides, as 1e300 ran on T3), density (its
// own range, below).
struct UpperBound {
  const char* what;  // "a conductivity"
  double most;
  const char* unit;
  const char* why;
};

constexpr UpperBound youngs_modulus_bound{
    "a Young's modulus", 1e13, "Pa",
    "the stiffest solid known, diamond, has 1.2e12 Pa, and a DEM model softens moduli (to lengthen the step), never "
    "stiffens them"};
constexpr UpperBound specific_heat_bound{
    "a specific heat", 1e6, "J/(kg K)",
    "the largest of any substance is hydrogen's 14,300; above, a disc's heat content m c (T - T0) is so large that "
    "its round-off outweighs the motion's energies in the energy ledger (1e12 read as an energy blow-up)"};
constexpr UpperBound conductivity_bound{
    "a conductivity", 1e6, "W/(m K)",
    "the largest of any solid is diamond's 2,200 (graphene's 5,000 in its plane), 1e6 leaves room for the "
    "correction of a softened modulus; 1e300 overflowed a pair's mean conductivity and the run died of NaN"};
constexpr UpperBound resistivity_bound{
    "an electrical resistivity", 1e30, "Ohm m",
    "the best insulators reach 1e25 Ohm m; the share of friction heat sums two resistivities, which overflows near "
    "1e308"};

double bounded(const SceneNode& node, const UpperBound& bound) {
  const double v = node.positive();
  if (v > bound.most)
    node.fail(std::string("expected ") + bound.what + " in (0, " + message_number(bound.most) + "]" +
              (*bound.unit ? std::string(" ") + bound.unit : std::string()) + ", got " + node.text() + ": " + bound.why);
  return v;
}

Material read_material(const std::string& name, const SceneNode& m) {
  m.allow();
  Material mat;
  mat.name = name;
  // Up to 1e12 kg/m^3: osmium's 22,590 scaled up by 1e7 or more (density scaling, to lengthen the
  // step); beyond, masses of large particles overflow (1e300 made an infinite mass that blamed dt).
  if (auto v = m.optional("density")) mat.density = v->in_range(0, 1e12, true, false);
  contact::ContactMaterial& c = mat.contact;
  if (auto v = m.optional("youngs_modulus")) c.youngs_modulus = bounded(*v, youngs_modulus_bound);
  if (auto v = m.optional("poisson_ratio")) c.poisson_ratio = v->in_range(-1, 0.5, true, false);
  if (auto v = m.optional("stiffness")) c.stiffness = v->positive();
  if (auto v = m.optional("restitution")) c.restitution = restitution(*v);
  if (auto v = m.optional("friction")) c.friction = v->non_negative();
  if (auto v = m.optional("rolling_friction")) c.rolling_friction = v->non_negative();
  if (auto v = m.optional("specific_heat")) mat.specific_heat = bounded(*v, specific_heat_bound);
  if (auto v = m.optional("conductivity")) mat.conductivity = bounded(*v, conductivity_bound);
  if (auto v = m.optional("electrical_resistivity")) mat.electrical_resistivity = bounded(*v, resistivity_bound);
  return mat;
}

// The model of a law that `node` names, from the law's table.
template <class Model, class Params>
Model read_model(const SceneNode& node, std::span<const ModelEntry<Model, Params>> table) {
  std::vector<std::string> names;
  for (const auto& e : table) names.push_back(e.name);
  const std::string name = node.choice(names);  // fails unless it is one of them
  return std::find_if(table.begin(), table.end(), [&](const auto& e) { return name == e.name; })->model;
}

template <class Model, class Params>
bool owns(const ModelEntry<Model, Params>& model, const std::string& key) {
  return std::any_of(model.keys.begin(), model.keys.end(), [&](const auto& k) { return key == k.key; });
}

template <class Model, class Params>
void add_keys(const ModelEntry<Model, Params>& model, std::vector<std::string>& keys) {
  for (const auto& k : model.keys)
    if (std::find(keys.begin(), keys.end(), k.key) == keys.end()) keys.push_back(k.key);
}

double read_value(const SceneNode& node, const Accepted& accepts) {
  if (accepts == positive_number) return node.positive();
  if (accepts == non_negative_number) return node.non_negative();
  return node.in_range(accepts.lo, accepts.hi, accepts.lo_open, accepts.hi_open);
}

// The keys that the models of one law own (its table), chosen by `selector`: a key of another
// model is refused naming the models that read it and `valid`, the keys of this pair's law; the
// chosen model's keys are read into `params`.
template <class Model, class Params>
void read_owned_keys(const SceneNode& c, const char* selector, std::span<const ModelEntry<Model, Params>> table,
                     Model chosen, Params& params, const std::vector<std::string>& valid) {
  const auto& mine = entry_of(table, chosen);
  for (const auto& other : table)
    for (const OwnedKey<Params>& k : other.keys) {
      if (!c.has(k.key) || owns(mine, k.key)) continue;
      std::string owners;
      for (const auto& m : table)
        if (owns(m, k.key)) owners += (owners.empty() ? "" : " or ") + std::string(selector) + ": " + m.name;
      const std::string instead = mine.instead ? std::string(" (") + mine.title + " " + mine.instead + ")" : "";
      c[k.key].fail(std::string(k.meaning) + " applies to " + owners + " only" + instead +
                    "; the keys of this pair's law are " + choices_nearest_first(k.key, valid));
    }
  for (const OwnedKey<Params>& k : mine.keys) {
    if (k.required || c.has(k.key)) params.*k.field = read_value(c[k.key], k.accepts);
    if (k.excludes && c.has(k.key) && c.has(k.excludes))
      c[k.key].fail(std::string("give either ") + k.excludes + " or " + k.key + ", not both");
  }
}

// One `contacts:` entry over the law its pair has so far.
void read_contact(const SceneNode& c, PairLaw& law) {
  contact::ContactLaw& m = law.contact;
  if (auto v = c.optional("model")) m.model = read_model(*v, contact::normal_models());
  if (auto v = c.optional("rolling_model")) m.rolling_model = read_model(*v, contact::rolling_models());
  if (auto v = c.optional("conduction")) law.conduction.model = read_model(*v, thermal::conduction_models());
  if (auto v = c.optional("restitution")) m.restitution = restitution(*v);
  if (auto v = c.optional("tension")) m.tension = v->boolean();
  if (auto v = c.optional("friction")) m.friction = v->non_negative();
  if (auto v = c.optional("rolling_friction")) m.rolling_friction = v->non_negative();
  if (auto v = c.optional("tangential_stiffness_ratio")) m.tangential_stiffness_ratio = v->positive();
  if (auto v = c.optional("tangential_damping_ratio")) m.tangential_damping_ratio = v->non_negative();
  std::vector<std::string> valid(std::begin(common_keys), std::end(common_keys));
  add_keys(entry_of(contact::normal_models(), m.model), valid);
  add_keys(entry_of(contact::rolling_models(), m.rolling_model), valid);
  add_keys(entry_of(thermal::conduction_models(), law.conduction.model), valid);
  read_owned_keys(c, "model", contact::normal_models(), m.model, m, valid);
  read_owned_keys(c, "rolling_model", contact::rolling_models(), m.rolling_model, m, valid);
  read_owned_keys(c, "conduction", thermal::conduction_models(), law.conduction.model, law.conduction, valid);
}

}  // namespace

std::vector<std::string> contact_entry_keys() {
  std::vector<std::string> keys(std::begin(common_keys), std::end(common_keys));
  for (const auto& m : contact::normal_models()) add_keys(m, keys);
  for (const auto& m : contact::rolling_models()) add_keys(m, keys);
  for (const auto& m : thermal::conduction_models()) add_keys(m, keys);
  return keys;
}

void read_contacts(const SceneNode& root, Scene& scene, const MaterialIndex& index,
                   std::vector<Location>& law_location) {
  const int nm = scene.n_materials();
  // The scene's models for every pair, unless given: the laws' own defaults.
  const PairLaw defaults;
  contact::NormalModel model = defaults.contact.model;
  if (auto m = root.optional("contact_model")) model = read_model(*m, contact::normal_models());
  thermal::ConductionModel conduction = defaults.conduction.model;
  if (auto c = root.optional("conduction_model")) conduction = read_model(*c, thermal::conduction_models());
  contact::RollingModel rolling = defaults.contact.rolling_model;
  if (auto r = root.optional("rolling_model")) rolling = read_model(*r, contact::rolling_models());
  scene.laws.resize(nm * nm);
  law_location.assign(nm * nm, root.location());
  for (int a = 0; a < nm; ++a)
    for (int b = 0; b < nm; ++b) {
      PairLaw& law = scene.laws[a * nm + b];
      law.contact = contact::mixed_law(scene.materials[a].contact, scene.materials[b].contact, model);
      law.contact.rolling_model = rolling;
      law.conduction.model = conduction;
    }
  if (auto contacts = root.optional("contacts")) {
    for (const SceneNode& c : contacts->items()) {
      c.allow();
      const auto pair = c["between"].items();
      if (pair.size() != 2) c["between"].fail("expected two material names [a, b]");
      const int a = index.find(pair[0]), b = index.find(pair[1]);
      PairLaw law = scene.laws[a * nm + b];
      read_contact(c, law);
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
      const contact::NormalModelEntry& model = entry_of(contact::normal_models(), law.contact.model);
      if (model.needed && !(law.contact.*model.needed > 0))
        throw InputError(law_location[a * nm + b],
                         std::string("the ") + model.title + " contact between " + pair + " needs " + model.needs);
      const thermal::ConductionModel conduction = law.conduction.model;
      if (!scene.thermal || conduction == thermal::ConductionModel::none ||
          conduction == thermal::ConductionModel::constant)
        continue;
      if (!used[b] && !wall_conducts[b]) continue;
      if (!(scene.materials[a].conductivity > 0 && scene.materials[b].conductivity > 0))
        throw InputError(law_location[a * nm + b], "conduction between " + pair + " needs 'conductivity' on both materials");
      if (conduction == thermal::ConductionModel::hertz && !(law.contact.effective_modulus > 0))
        throw InputError(law_location[a * nm + b],
                         "Hertz conduction between " + pair + " needs youngs_modulus on both materials");
      if (conduction == thermal::ConductionModel::pipe_network && scene.mass_model != MassModel::cylinder)
        throw InputError(law_location[a * nm + b], "pipe_network conduction is for cylinders: set mass_model: cylinder");
    }
}

}  // namespace kiln::scene_parts
