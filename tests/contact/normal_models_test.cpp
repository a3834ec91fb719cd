// The model tables of the laws (contact/model_table.h, thermal/conduction_model.h) and the one
// dispatch on the normal model (contact/normal_force.h): every model of a table is a consistent
// law, and a scene reads each model's keys through the table, refusing them for every other model.
#include <catch2/catch.hpp>

#include <cmath>
#include <set>
#include <span>
#include <sstream>
#include <string>

#include "contact/model_table.h"
#include "contact/normal_force.h"
#include "tests/support.h"
#include "thermal/conduction_model.h"

using namespace kiln;
using contact::NormalLaw;

namespace {

// Two discs whose material gives what every normal model needs, with one contact entry `entry`.
std::string scene_with_contact(const std::string& entry) {
  return testing::replaced(testing::two_discs_on_a_floor, "particles:",
                           "contacts:\n  - between: [copper, copper]\n" + entry + "particles:");
}
std::string with_modulus(const std::string& text) {
  return testing::replaced(text, "stiffness: 6000", "stiffness: 6000, youngs_modulus: 1.0e9");
}

// `key` in quotes, as a list of valid keys names it.
std::string quoted(const char* key) { return std::string("'").append(key).append("'"); }

// A value the key accepts.
double accepted_value(const Accepted& a) { return std::isfinite(a.hi) ? 0.5 * (a.lo + a.hi) : a.lo + 1; }

// The part of a message after `marker`, "" when it is not there.
std::string after(const std::string& text, const std::string& marker) {
  const size_t at = text.find(marker);
  return at == std::string::npos ? "" : text.substr(at + marker.size());
}

// For each model of a law's table (chosen in an entry by `selector`) and each key of another
// model: given with this model, the key is refused at its line, naming the models that read it,
// and the keys listed as this pair's are this model's, not that one; given with a model that owns
// it, it is read.
template <class Model, class Params>
void check_owned_keys(std::span<const ModelEntry<Model, Params>> table, const std::string& selector) {
  auto owns = [](const ModelEntry<Model, Params>& m, const std::string& key) {
    for (const auto& k : m.keys)
      if (key == k.key) return true;
    return false;
  };
  for (const auto& chosen : table)
    for (const auto& owner : table)
      for (const auto& k : owner.keys) {
        std::ostringstream entry;
        entry << "    " << selector << ": " << owner.name << "\n";
        for (const auto& needed : owner.keys)
          if (needed.required || needed.key == std::string(k.key))
            entry << "    " << needed.key << ": " << accepted_value(needed.accepts) << "\n";
        INFO(selector << ": " << owner.name << " with " << k.key);
        CHECK(testing::error_of(with_modulus(scene_with_contact(entry.str()))).empty());
        if (owns(chosen, k.key)) continue;
        const std::string given = "    " + std::string(k.key) + ": " + std::to_string(accepted_value(k.accepts)) + "\n";
        const std::string text = with_modulus(scene_with_contact("    " + selector + ": " + chosen.name + "\n" + given));
        const std::string msg = testing::error_of(text);
        INFO("refused with " << selector << ": " << chosen.name << ": " << msg);
        CHECK(msg.find("key 'contacts.0." + std::string(k.key) + "'") != std::string::npos);
        CHECK(msg.find(selector + ": " + owner.name) != std::string::npos);
        const std::string valid = after(msg, "the keys of this pair's law are");
        REQUIRE(!valid.empty());
        CHECK(valid.find(quoted(k.key)) == std::string::npos);
        CHECK(valid.find("'restitution'") != std::string::npos);
        for (const auto& own : chosen.keys) CHECK(valid.find(quoted(own.key)) != std::string::npos);
      }
}

}  // namespace

TEST_CASE("each normal model's keys are read with it and refused with every other, the pair's keys listed",
          "[contact]") {
  check_owned_keys(contact::normal_models(), "model");
}

TEST_CASE("each rolling and conduction model's keys are read with it and refused with every other",
          "[contact][conduction]") {
  check_owned_keys(contact::rolling_models(), "rolling_model");
  check_owned_keys(thermal::conduction_models(), "conduction");
}

TEST_CASE("a scene chooses among every model of a table by its name, and an unknown name lists them all",
          "[contact]") {
  std::set<std::string> names;
  for (const auto& m : contact::normal_models()) {
    CHECK(names.insert(m.name).second);
    const Scene scene = parse_scene(with_modulus(scene_with_contact(std::string("    model: ") + m.name + "\n")), "ok.yaml");
    CHECK(scene.law(0, 0).contact.model == m.model);
  }
  const std::string msg = testing::error_of(testing::two_discs_on_a_floor + "contact_model: hooke\n");
  for (const std::string& name : names) CHECK(msg.find("'" + name + "'") != std::string::npos);
}

TEST_CASE("a pair whose materials lack what its normal model needs is refused saying what that is", "[contact]") {
  for (const auto& m : contact::normal_models()) {
    if (!m.needed) continue;
    // The materials give nothing: no stiffness, no modulus.
    const std::string bare = testing::replaced(testing::two_discs_on_a_floor, "stiffness: 6000, ", "");
    const std::string msg = testing::error_of(bare + "contact_model: " + m.name + "\n");
    INFO(m.name << ": " << msg);
    CHECK(msg.find(std::string(m.title) + " contact between 'copper' and 'copper' needs " + m.needs) !=
          std::string::npos);
  }
}

TEST_CASE("for every normal model the spring force is d(energy)/d(overlap), its slope is d(force)/d(overlap), "
          "and the force beyond the spring is the dashpot's c delta^q v",
          "[contact]") {
  const double k = 3e6, c = 20, v = 0.3;
  for (const auto& m : contact::normal_models()) {
    const NormalLaw law{k, c, m.model, true}, spring{k, 0, m.model, true};
    for (double d : {1e-6, 1e-5, 1e-4}) {
      INFO(m.name << ", overlap " << d);
      const double h = 1e-4 * d;
      const double energy_slope =
          (normal_elastic_energy(law, d + h) - normal_elastic_energy(law, d - h)) / (2 * h);
      CHECK(energy_slope == Approx(normal_force(spring, d, 0)).epsilon(1e-7));
      const double force_slope = (normal_force(spring, d + h, 0) - normal_force(spring, d - h, 0)) / (2 * h);
      CHECK(stiffness_slope(law, d) == Approx(force_slope).epsilon(1e-7));
      const double f = normal_force(law, d, v);
      CHECK(dashpot_force(law, d, f) == Approx(c * dashpot_scale(law, d) * v).epsilon(1e-12));
      CHECK(normal_dissipation(law, d, v, f) == Approx(c * dashpot_scale(law, d) * v * v).epsilon(1e-12));
      // A dashpot that pushes at zero overlap makes the force jump at first touch.
      CHECK(contact::force_jumps_at_touch(m.model) == (dashpot_scale(law, 0.0) > 0));
    }
  }
}

TEST_CASE("every normal model is defined past separation, where contact events continue an acting contact's law",
          "[contact]") {
  // Within a step an acting contact keeps its law until the release is located: the stages see
  // small negative overlaps. Each function of the law stays finite there and agrees with the
  // force it continues (Hertz by 0: its delta^1/2 of a negative overlap was NaN, and a damped
  // Hertz bounce under erk4 with events stopped at its release).
  const double k = 3e6, c = 20, v = -0.3;
  for (const auto& m : contact::normal_models()) {
    const NormalLaw law{k, c, m.model, true};
    for (double d : {-1e-9, -1e-6}) {
      INFO(m.name << ", overlap " << d);
      const double f = normal_force(law, d, v);
      CHECK(std::isfinite(f));
      CHECK(std::isfinite(normal_elastic_energy(law, d)));
      CHECK(std::isfinite(stiffness_slope(law, d)));
      CHECK(std::isfinite(stiffness_slope_rate(law, d, v)));
      CHECK(dashpot_force(law, d, f) == Approx(c * dashpot_scale(law, d) * v).margin(1e-12));
    }
  }
}

TEST_CASE("for every normal model, with and without tension, the dashpot solved for a restitution gives it back",
          "[contact]") {
  for (const auto& m : contact::normal_models())
    for (bool tension : {false, true})
      for (double e : {0.2, 0.5, 0.9}) {
        INFO(m.name << ", tension " << tension << ", e = " << e);
        const double beta = contact::restitution_damping(e, m.model, tension);
        CHECK(contact::restitution_for_damping(beta, m.model, tension) == Approx(e).epsilon(1e-6));
      }
}

TEST_CASE("for every normal model the step limit's frequency is at least the contact's mean one, pi / duration",
          "[contact]") {
  // The frequency bounds the stiffest moment of the contact; over the whole contact the spring
  // is softer on average (linear: equal).
  for (const auto& m : contact::normal_models())
    for (double speed : {0.01, 1.0}) {
      const NormalLaw law{1e5, 0, m.model, true};
      INFO(m.name << " at " << speed << " m/s");
      CHECK(contact::limiting_frequency(law, 1e-3, speed) * contact::contact_duration(law, 1e-3, speed) >=
            Approx(M_PI).epsilon(1e-12));
    }
}
