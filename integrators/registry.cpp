// Integrators by name: the names a user types (`--integrator`, the scene's `integrator:` key).
#include <cstdio>  // arkode_butcher.h uses FILE without including it

#include <arkode/arkode_butcher_erk.h>

#include <algorithm>
#include <cmath>
#include <memory>
#include <stdexcept>
#include <vector>

#include "integrators/arkode.h"
#include "integrators/integrator.h"
#include "integrators/stability_region.h"
#include "integrators/velocity_verlet.h"
#include "integrators/verlet.h"
#include "src/base/error.h"
#include "src/base/nearest.h"

namespace kiln {

namespace {

// SUNDIALS 6.4.1's built-in explicit tables (KNOTH_WOLKE_3_3 has no embedding: fixed step only)
// and its IMEX pairs, each an explicit and a diagonally implicit table.
const char* const erk_tables[] = {"HEUN_EULER_2_1_2",     "BOGACKI_SHAMPINE_4_2_3", "ARK324L2SA_ERK_4_2_3",
                                  "ZONNEVELD_5_3_4",      "ARK436L2SA_ERK_6_3_4",   "SAYFY_ABURUB_6_3_4",
                                  "CASH_KARP_6_4_5",      "FEHLBERG_6_4_5",         "DORMAND_PRINCE_7_4_5",
                                  "ARK548L2SA_ERK_8_4_5", "VERNER_8_5_6",           "FEHLBERG_13_7_8",
                                  "KNOTH_WOLKE_3_3",      "ARK437L2SA_ERK_7_3_4",   "ARK548L2SAb_ERK_8_4_5"};
struct Pair {
  const char* name;
  const char* erk;
  const char* dirk;
};
const Pair imex_pairs[] = {{"ARK324L2SA", "ARK324L2SA_ERK_4_2_3", "ARK324L2SA_DIRK_4_2_3"},
                           {"ARK436L2SA", "ARK436L2SA_ERK_6_3_4", "ARK436L2SA_DIRK_6_3_4"},
                           {"ARK437L2SA", "ARK437L2SA_ERK_7_3_4", "ARK437L2SA_DIRK_7_3_4"},
                           {"ARK548L2SA", "ARK548L2SA_ERK_8_4_5", "ARK548L2SA_DIRK_8_4_5"},
                           {"ARK548L2SAb", "ARK548L2SAb_ERK_8_4_5", "ARK548L2SAb_DIRK_8_4_5"}};
const std::pair<const char*, const char*> aliases[] = {
    {"erk2", "erk:HEUN_EULER_2_1_2"}, {"erk3", "erk:BOGACKI_SHAMPINE_4_2_3"}, {"erk4", "erk:ZONNEVELD_5_3_4"},
    {"erk5", "erk:DORMAND_PRINCE_7_4_5"}, {"erk6", "erk:VERNER_8_5_6"},       {"erk8", "erk:FEHLBERG_13_7_8"},
    {"imex3", "imex:ARK324L2SA"},        {"imex4", "imex:ARK436L2SA"},       {"imex5", "imex:ARK548L2SA"}};

// An ARKODE method's entry, its orders and reach read from its own Butcher table(s): the method
// order q and the embedding's p (0: none) as SUNDIALS defines them.
IntegratorInfo arkode_entry(std::string name, const char* erk, const char* dirk, std::string summary) {
  IntegratorInfo info;
  info.name = std::move(name);
  info.scheme = IntegratorScheme::arkode;
  info.erk_table = erk;
  info.dirk_table = dirk ? dirk : "";
  info.implicit = dirk != nullptr;
  info.locates_contact_events = true;
  ARKodeButcherTable t = load_butcher_table(erk, false);
  info.order = info.order_with_dashpot = t->q;
  info.embedding = t->p;
  // ARKODE adds the stages' slopes to y_n one at a time (N_VLinearCombination): each nonzero
  // weight of b rounds every position once.
  info.position_roundings = static_cast<int>(std::count_if(t->b, t->b + t->stages, [](double b) { return b != 0; }));
  ARKodeButcherTable_Free(t);
  info.real_stability = info.implicit ? INFINITY : reach_along(StabilityFunction(erk), {-1, 0});
  info.summary = std::move(summary);
  return info;
}

IntegratorInfo verlet_entry(const char* name, IntegratorScheme scheme, int order_with_dashpot, const char* summary) {
  IntegratorInfo info;
  info.name = name;
  info.scheme = scheme;
  info.order = 2;
  info.order_with_dashpot = order_with_dashpot;
  info.summary = summary;
  return info;
}

std::vector<IntegratorInfo> build_catalogue() {
  std::vector<IntegratorInfo> c = {
      verlet_entry("verlet", IntegratorScheme::basic_verlet, 1,
                   "basic Stormer-Verlet (thesis II.16, II.20, II.21); backward-difference velocity in forces"),
      verlet_entry("velocity-verlet", IntegratorScheme::velocity_verlet, 1,
                   "velocity Verlet (thesis II.25-II.27); half-step velocity in forces, as LAMMPS"),
      verlet_entry("velocity-verlet-predicted", IntegratorScheme::velocity_verlet_predicted, 2,
                   "velocity Verlet with the predicted v_n + a_n dt in forces"),
  };
  for (const char* table : erk_tables)
    c.push_back(arkode_entry(std::string("erk:") + table, table, nullptr, "ARKODE explicit table (ARKStep)"));
  for (const Pair& p : imex_pairs)
    c.push_back(arkode_entry(std::string("imex:") + p.name, p.erk, p.dirk,
                             "ARKODE IMEX pair: mechanics explicit, conduction implicit (linear_solver: cholesky)"));
  IntegratorInfo euler = arkode_entry("imex1", imex_euler_table, imex_euler_table,
                                      "IMEX Euler: backward Euler on conduction keeps the maximum principle at any "
                                      "step (heat on frozen networks only)");
  // Its explicit half is forward Euler, which grows every undamped contact oscillation.
  euler.integrates_contacts = false;
  c.push_back(euler);
  for (const auto& [alias, target] : aliases)
    for (const IntegratorInfo& info : std::vector<IntegratorInfo>(c))
      if (info.name == target) {
        IntegratorInfo a = info;
        a.name = alias;
        a.alias_of = target;
        a.summary = std::string("alias of ") + target;
        c.push_back(a);
      }
  return c;
}

}  // namespace

const std::vector<IntegratorInfo>& integrator_catalogue() {
  static const std::vector<IntegratorInfo> catalogue = build_catalogue();
  return catalogue;
}

const IntegratorInfo& integrator_info(const std::string& name) {
  // Names are short words: a longer text is no misspelling of one, and is not echoed whole.
  if (name.size() > 100)
    throw InputError("an integrator name of " + std::to_string(name.size()) +
                     " characters; the names are short words (see 'kiln integrators')");
  for (const IntegratorInfo& info : integrator_catalogue())
    if (info.name == name) return info;
  std::vector<std::string> names;
  for (const auto& i : integrator_catalogue()) names.push_back(i.name);
  throw InputError("unknown integrator '" + name + "'; valid names are " + choices_nearest_first(name, names));
}

double real_stability_of(const std::string& name) {
  for (const IntegratorInfo& info : integrator_catalogue())
    if (info.name == name) return info.real_stability;
  return 2;
}

std::unique_ptr<Integrator> make_integrator(const std::string& name, const StepControl& control) {
  const IntegratorInfo& info = integrator_info(name);
  if (control.contact_events && !info.locates_contact_events)
    throw InputError("contact events need an ARKODE integrator (erk:..., imex:...), not '" + name + "'");
  if (control.rtol > 0 && info.embedding == 0)
    throw InputError("integrator '" + name + "' has no error estimate and cannot adapt: give no rtol, or pick an "
                     "erk: or imex: method with an embedding (see 'kiln integrators')");
  switch (info.scheme) {
    case IntegratorScheme::basic_verlet: return std::make_unique<BasicVerlet>();
    case IntegratorScheme::velocity_verlet: return std::make_unique<VelocityVerlet>(false);
    case IntegratorScheme::velocity_verlet_predicted: return std::make_unique<VelocityVerlet>(true);
    case IntegratorScheme::arkode:
      return std::make_unique<ArkodeIntegrator>(ArkodeMethod{info.erk_table, info.dirk_table}, control);
  }
  throw std::logic_error("make_integrator: a scheme without a constructor");
}

}  // namespace kiln
