// N3: plane shear between rough walls (cases/n3_shear_cell.yaml). The dynamic regime runs in the
// default suite; the quasi-static regime (2 s of a slow wall) under `long`.
#include <catch2/catch.hpp>

#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "tests/support.h"

using namespace kiln;

namespace {

std::vector<double> numbers(const nlohmann::json& values) {
  std::vector<double> v;
  for (const auto& x : values) v.push_back(x.is_null() ? NAN : x.get<double>());
  return v;
}

// The layers free grains pass through: a wall's own layer holds only its glued grains.
std::vector<double> flowing(const std::vector<double>& v, const std::vector<double>& speed) {
  std::vector<double> out;
  for (size_t k = 0; k < v.size(); ++k)
    if (std::isfinite(speed[k])) out.push_back(v[k]);
  return out;
}

// Monotone up to the noise of a time mean: no layer slower than the one below by more than
// 2 % of the wall's speed.
bool rises(const std::vector<double>& v) {
  for (size_t k = 1; k < v.size(); ++k)
    if (v[k] < v[k - 1] - 0.02) return false;
  return true;
}

nlohmann::json shear(const std::vector<std::string>& sets = {}) {
  return run_scene(load_scene(testing::case_path("n3_shear_cell.yaml"), sets), {"", true});
}

}  // namespace

TEST_CASE("N3 dynamic shear: the velocity rises monotonically across the layer, friction heat peaks inside it and "
          "equals the frictional work, the effective friction is a dense flow's",
          "[shear][heavy]") {
  const nlohmann::json s = shear();
  const nlohmann::json& p = s["shear_profile"];
  const std::vector<double> speed = numbers(p["velocity_over_wall"]);
  const std::vector<double> v = flowing(speed, speed);
  const std::vector<double> heat = numbers(p["heat_power"]);
  INFO("velocity / V: " << p["velocity_over_wall"] << "\nheat share: " << p["heat_share"]
                        << "\neffective friction " << s["effective_friction"] << ", I " << s["inertial_number"]);
  // The bottom grains stay at rest and the top wall drags its neighbours at nearly its speed.
  REQUIRE(v.size() >= 15);
  CHECK(rises(v));
  CHECK(v.front() < 0.15);
  CHECK(v.back() > 0.85);
  // Dense inertial flow (GDR MiDi 2004: 1e-3 < I < 0.3).
  CHECK(s["inertial_number"].get<double>() > 0.03);
  CHECK(s["inertial_number"].get<double>() < 0.3);
  // The hottest layer is inside the flow: neither a wall's own layer nor the layer touching it.
  const size_t hottest = std::max_element(heat.begin(), heat.end()) - heat.begin();
  CHECK(hottest >= 2);
  CHECK(hottest + 2 < heat.size());
  // The heat in the grains is what friction dissipated. Velocity Verlet integrates the heat from
  // the friction power at each step's predicted velocities, which is first order in dt where
  // contacts stick, slip, start and end: 1.47 % above the ledger's friction work at the case's
  // step (1/26 of a contact) and 0.74 % at half of it (the ledger's work is Verlet's own, exact
  // for its discrete motion). Tolerance: twice the measured gap.
  const nlohmann::json& e = s["energy"];
  const double friction = e["dissipated_friction"].get<double>();
  CHECK(e["thermal_change"].get<double>() == Approx(friction).epsilon(1e-9));
  CHECK(e["thermal_change"].get<double>() == Approx(e["heat_from_dissipation"].get<double>()).epsilon(1e-9));
  // The window's heat is the heat of that half of the run: less than all of it, more than a third.
  CHECK(p["heat_total"].get<double>() < e["thermal_change"].get<double>());
  CHECK(p["heat_total"].get<double>() > 0.33 * e["thermal_change"].get<double>());
  // 2D DEM of frictional discs (da Cruz et al. 2005): mu(I) from about 0.25 at rest to 0.6.
  CHECK(s["effective_friction"].get<double>() > 0.25);
  CHECK(s["effective_friction"].get<double>() < 0.7);
  CHECK(std::abs(e["balance_error"].get<double>()) < 1e-3 * e["work_by_walls"].get<double>());
}

TEST_CASE("N3 quasi-static shear: the profile stays monotone and the effective friction is lower than in the "
          "dynamic regime (mu rises with I)",
          "[shear][long]") {
  const nlohmann::json slow = shear({"walls.1.motion.velocity=[0.05,0]", "t_end=2"});
  const nlohmann::json fast = shear();
  const std::vector<double> speed = numbers(slow["shear_profile"]["velocity_over_wall"]);
  INFO("quasi-static velocity / V: " << slow["shear_profile"]["velocity_over_wall"] << "\nmu " << slow["effective_friction"]
                                     << " at I " << slow["inertial_number"] << ", dynamic mu "
                                     << fast["effective_friction"] << " at I " << fast["inertial_number"]);
  CHECK(rises(flowing(speed, speed)));
  CHECK(slow["inertial_number"].get<double>() < 3e-3);
  CHECK(slow["effective_friction"].get<double>() > 0.2);
  CHECK(slow["effective_friction"].get<double>() < fast["effective_friction"].get<double>());
}
