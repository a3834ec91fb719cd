// Friction heat (Nguyen et al. 2009 [nguyen2009-friction-heat-dem.txt]): a sliding contact turns
// mu F_n |u_t| into heat, shared by beta = (rho_i/(rho_i + rho_j) + lambda_i/(lambda_i + lambda_j))/2.
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>

#include "src/scene/overrides.h"
#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "thermal/conductance.h"

using namespace kiln;

namespace {

// A copper cylinder launched at v0 without spin along an adiabatic steel floor. It slides until
// friction has spun it up to rolling; the slip speed falls as v0 - 3 mu g t, so friction turns
// mu m g * v0^2 / (6 mu g) = m v0^2 / 6 into heat, which is also the kinetic energy lost
// (1/2 m v0^2 before, 1/3 m v0^2 when rolling at 2/3 v0).
std::string sliding_disc(double v0) {
  const double r = 0.002, m = M_PI * r * r * 0.002 * 8900, k = 1e5;
  std::ostringstream s;
  s.precision(17);
  s << "name: sliding\nmass_model: cylinder\nthickness: 0.002\nheat_from_dissipation: friction\n"
    << "materials:\n"
    << "  copper: {density: 8900, stiffness: 1.0e5, restitution: 0.5, friction: 0.4, specific_heat: 385,\n"
    << "           conductivity: 385, electrical_resistivity: 1.7e-8}\n"
    << "  steel: {stiffness: 1.0e5, restitution: 0.5, friction: 0.4, conductivity: 16, electrical_resistivity: 7.0e-7}\n"
    << "particles:\n  - material: copper\n    radius: " << r << "\n    temperature: 20\n"
    << "    velocity: [" << v0 << ", 0]\n    at: [[0, " << r - m * 9.81 / k << "]]\n"
    << "walls:\n  - {material: steel, segment: [[-0.01, 0], [1.0, 0]]}\n"
    << "allow_overlap: true\nintegrator: velocity-verlet-predicted\ndt: 2.0e-7\nt_end: 0.2\n"
    << "output_interval: 0.01\nreport: [temperatures]\n";
  return s.str();
}

}  // namespace

TEST_CASE("a sliding disc turns mu F_n |u_t| into heat, shared with the floor by beta", "[friction-heat][heavy]") {
  const double v0 = 1.0, r = 0.002, m = M_PI * r * r * 0.002 * 8900;
  const Scene scene = parse_scene(sliding_disc(v0), "sliding.yaml");
  const auto s = run_scene(scene, {"", true});
  const double friction_heat = m * v0 * v0 / 6;
  const double beta = thermal::heat_partition(1.7e-8, 7.0e-7, 385, 16);
  CHECK(beta == Approx(0.5 * (1.7e-8 / 7.17e-7 + 385.0 / 401)));
  // All of the slip work is dissipated by friction; the disc keeps beta of it.
  CHECK(s["energy"]["dissipated_friction"].get<double>() == Approx(friction_heat).epsilon(0.01));
  CHECK(s["energy"]["thermal_change"].get<double>() == Approx(beta * friction_heat).epsilon(0.01));
  CHECK(s["energy"]["heat_from_dissipation"].get<double>() == Approx(s["energy"]["thermal_change"].get<double>()).epsilon(1e-6));  // round-off of 1e6 small increments to 20 C
  const double temperature_rise = beta * friction_heat / (m * 385);
  CHECK(s["temperature_max"].get<double>() - 20 == Approx(temperature_rise).epsilon(0.01));
  // The ledger closes: the floor's share stays dissipated, the disc's share is heat.
  CHECK(std::abs(s["energy"]["balance_error"].get<double>()) < 1e-3 * 0.5 * m * v0 * v0);
}

TEST_CASE("without conversion the same slide dissipates as much but heats nothing", "[friction-heat][heavy]") {
  const Scene scene = parse_scene(sliding_disc(1.0), "sliding.yaml", {"heat_from_dissipation=none"});
  const auto s = run_scene(scene, {"", true});
  CHECK(s["energy"]["dissipated_friction"].get<double>() > 0);
  CHECK(s["energy"]["thermal_change"].get<double>() == 0.0);
}
