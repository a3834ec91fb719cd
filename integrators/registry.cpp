// Integrators by name: the names a user types (`--integrator`, the scene's `integrator:` key).
#include <cstdio>  // arkode_butcher.h uses FILE without including it

#include <arkode/arkode_butcher_erk.h>

#include <cmath>
#include <memory>
#include <vector>

#include "integrators/arkode.h"
#include "integrators/integrator.h"
#include "integrators/velocity_verlet.h"
#include "integrators/verlet.h"
#include "src/base/error.h"
#include "src/base/nearest.h"

namespace kiln {

namespace {

// SUNDIALS 6.4.1's built-in explicit tables, NAME_stages_embedding_order (KNOTH_WOLKE_3_3 has no
// embedding: fixed step only), and the IMEX pairs with their orders.
const char* const erk_tables[] = {"HEUN_EULER_2_1_2",     "BOGACKI_SHAMPINE_4_2_3", "ARK324L2SA_ERK_4_2_3",
                                  "ZONNEVELD_5_3_4",      "ARK436L2SA_ERK_6_3_4",   "SAYFY_ABURUB_6_3_4",
                                  "CASH_KARP_6_4_5",      "FEHLBERG_6_4_5",         "DORMAND_PRINCE_7_4_5",
                                  "ARK548L2SA_ERK_8_4_5", "VERNER_8_5_6",           "FEHLBERG_13_7_8",
                                  "KNOTH_WOLKE_3_3",      "ARK437L2SA_ERK_7_3_4",   "ARK548L2SAb_ERK_8_4_5"};
struct Pair {
  const char* name;
  const char* erk;
  const char* dirk;
  int order, embedding;
};
const Pair imex_pairs[] = {{"ARK324L2SA", "ARK324L2SA_ERK_4_2_3", "ARK324L2SA_DIRK_4_2_3", 3, 2},
                           {"ARK436L2SA", "ARK436L2SA_ERK_6_3_4", "ARK436L2SA_DIRK_6_3_4", 4, 3},
                           {"ARK437L2SA", "ARK437L2SA_ERK_7_3_4", "ARK437L2SA_DIRK_7_3_4", 4, 3},
                           {"ARK548L2SA", "ARK548L2SA_ERK_8_4_5", "ARK548L2SA_DIRK_8_4_5", 5, 4},
                           {"ARK548L2SAb", "ARK548L2SAb_ERK_8_4_5", "ARK548L2SAb_DIRK_8_4_5", 5, 4}};
const std::pair<const char*, const char*> aliases[] = {
    {"erk2", "erk:HEUN_EULER_2_1_2"}, {"erk3", "erk:BOGACKI_SHAMPINE_4_2_3"}, {"erk4", "erk:ZONNEVELD_5_3_4"},
    {"erk5", "erk:DORMAND_PRINCE_7_4_5"}, {"erk6", "erk:VERNER_8_5_6"},       {"erk8", "erk:FEHLBERG_13_7_8"},
    {"imex3", "imex:ARK324L2SA"},        {"imex4", "imex:ARK436L2SA"},       {"imex5", "imex:ARK548L2SA"}};

// Order and embedding from a table name's trailing numbers: stages_embedding_order, or
// stages_order for a table without an embedding.
std::pair<int, int> orders_of(const std::string& table) {
  std::vector<int> numbers;
  size_t end = table.size();
  while (end > 0) {
    const size_t start = table.rfind('_', end - 1);
    const std::string token = table.substr(start + 1, end - start - 1);
    if (token.empty() || token.find_first_not_of("0123456789") != std::string::npos) break;
    numbers.insert(numbers.begin(), std::stoi(token));
    end = start;
  }
  return numbers.size() == 3 ? std::pair{numbers[2], numbers[1]} : std::pair{numbers.back(), 0};
}

// The reach of an explicit table's stability region along the negative real axis: the first
// z < 0 with |R(z)| > 1, R(z) = 1 + z b^T (I - z A)^-1 1 evaluated stage by stage (A is strictly
// lower triangular). Scanned in steps of 0.01, then bisected.
double real_axis_reach(const char* table_name) {
  const std::string full = std::string("ARKODE_") + table_name;
  ARKodeButcherTable t = ARKodeButcherTable_LoadERKByName(full.c_str());
  if (!t) return 2;
  auto stable = [&](double z) {
    std::vector<double> stage(t->stages);
    double r = 1;
    for (int i = 0; i < t->stages; ++i) {
      double sum = 0;
      for (int j = 0; j < i; ++j) sum += t->A[i][j] * stage[j];
      stage[i] = 1 + z * sum;
      r += z * t->b[i] * stage[i];
    }
    return std::abs(r) <= 1 + 1e-12;
  };
  double lo = 0, hi = 0;
  for (double z = -0.01; z > -50; z -= 0.01) {
    if (!stable(z)) {
      hi = z;
      break;
    }
    lo = z;
  }
  if (hi == 0) hi = -50;
  for (int k = 0; k < 50; ++k) (stable(0.5 * (lo + hi)) ? lo : hi) = 0.5 * (lo + hi);
  ARKodeButcherTable_Free(t);
  return -lo;
}

std::vector<IntegratorInfo> build_catalogue() {
  std::vector<IntegratorInfo> c = {
      {"verlet", 2, 1, 0, false,
       "basic Stormer-Verlet (thesis II.16, II.20, II.21); backward-difference velocity in forces"},
      {"velocity-verlet", 2, 1, 0, false, "velocity Verlet (thesis II.25-II.27); half-step velocity in forces, as LAMMPS"},
      {"velocity-verlet-predicted", 2, 2, 0, false, "velocity Verlet with the predicted v_n + a_n dt in forces"},
  };
  for (const char* table : erk_tables) {
    const auto [order, embedding] = orders_of(table);
    c.push_back({std::string("erk:") + table, order, order, embedding, false, "ARKODE explicit table (ARKStep)",
                 real_axis_reach(table)});
  }
  for (const Pair& p : imex_pairs)
    c.push_back({std::string("imex:") + p.name, p.order, p.order, p.embedding, true,
                 "ARKODE IMEX pair: mechanics explicit, conduction implicit (linear_solver: cholesky)", INFINITY});
  c.push_back({"imex1", 1, 1, 0, true,
               "IMEX Euler: backward Euler on conduction keeps the maximum principle at any step (heat on frozen "
               "networks only)",
               INFINITY});
  for (const auto& [alias, target] : aliases)
    for (const IntegratorInfo& info : std::vector<IntegratorInfo>(c))
      if (info.name == target) {
        IntegratorInfo a = info;
        a.name = alias;
        a.summary = std::string("alias of ") + target;
        c.push_back(a);
      }
  return c;
}

}  // namespace

double real_stability_of(const std::string& name) {
  for (const IntegratorInfo& info : integrator_catalogue())
    if (info.name == name) return info.real_stability;
  return 2;
}

const std::vector<IntegratorInfo>& integrator_catalogue() {
  static const std::vector<IntegratorInfo> catalogue = build_catalogue();
  return catalogue;
}

std::unique_ptr<Integrator> make_integrator(const std::string& typed, const StepControl& control) {
  // Names are short words: a longer text is no misspelling of one, and is not echoed whole.
  if (typed.size() > 100)
    throw InputError("an integrator name of " + std::to_string(typed.size()) +
                     " characters; the names are short words (see 'kiln integrators')");
  std::string name = typed;
  for (const auto& [alias, target] : aliases)
    if (name == alias) name = target;
  const IntegratorInfo* info = nullptr;
  for (const auto& i : integrator_catalogue())
    if (i.name == name) info = &i;
  if (!info) {
    std::vector<std::string> names;
    for (const auto& i : integrator_catalogue()) names.push_back(i.name);
    throw InputError("unknown integrator '" + typed + "'; valid names are " + choices_nearest_first(typed, names));
  }
  if (control.contact_events && info->name.find(':') == std::string::npos)
    throw InputError("contact events need an ARKODE integrator (erk:..., imex:...), not '" + typed + "'");
  if (control.rtol > 0 && info->embedding == 0)
    throw InputError("integrator '" + typed + "' has no error estimate and cannot adapt: give no rtol, or pick an "
                     "erk: or imex: method with an embedding (see 'kiln integrators')");
  if (name == "verlet") return std::make_unique<BasicVerlet>();
  if (name == "velocity-verlet") return std::make_unique<VelocityVerlet>(false);
  if (name == "velocity-verlet-predicted") return std::make_unique<VelocityVerlet>(true);
  if (name.rfind("erk:", 0) == 0) return std::make_unique<ArkodeIntegrator>(ArkodeMethod{name.substr(4), ""}, control);
  if (name == "imex1") return std::make_unique<ArkodeIntegrator>(ArkodeMethod{imex_euler_table, imex_euler_table}, control);
  for (const Pair& p : imex_pairs)
    if (name == std::string("imex:") + p.name)
      return std::make_unique<ArkodeIntegrator>(ArkodeMethod{p.erk, p.dirk}, control);
  throw InputError("integrator '" + typed + "' is listed but not constructible");
}

}  // namespace kiln
