// T2 and C1: a disc against inclined surfaces.
#include <catch2/catch.hpp>
#include <cmath>

#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "src/scene/overrides.h"
#include "tests/support.h"

using namespace kiln;

TEST_CASE("T2: the rebound from an inclined wall mirrors the normal velocity and keeps the tangential one", "[t2]") {
  const Scene scene = load_scene(testing::case_path("t2_inclined_wall.yaml"));
  testing::Run run(testing::case_text("t2_inclined_wall.yaml"));
  const Vec2 along = (1 / std::hypot(0.05, -0.01)) * Vec2{0.05, -0.01};  // incline direction
  const Vec2 normal = perp(along);                                       // points up, away from the wall
  const double r = scene.radius[0];
  auto gap = [&] { return dot(Vec2{run.x(0), run.yy(0)} - Vec2{0.0, 0.015}, normal) - r; };
  // Free flight before the impact: no horizontal force, so x does not move at all.
  double x0 = run.x(0);
  while (gap() > 0) {
    run.step();
    CHECK(run.x(0) == x0);
  }
  // The step before contact began: reconstruct the incoming velocity at the onset.
  const Vec2 v_in{run.vx(0), run.vy(0)};
  const double t_on = run.t();
  while (gap() <= 0) run.step();
  const Vec2 v_out{run.vx(0), run.vy(0)};
  const double t_contact = run.t() - t_on;
  // Frictionless elastic contact: the normal speed reverses exactly (gravity's normal part acts
  // symmetrically), the tangential speed only gains gravity's tangential pull during the contact.
  CHECK(dot(v_out, normal) == Approx(-dot(v_in, normal)).epsilon(0.005));
  CHECK(dot(v_out, along) == Approx(dot(v_in, along) + dot(scene.gravity, along) * t_contact).epsilon(0.005));
  // After the impact x moves linearly: constant vx during the next flight.
  const double vx_after = run.vx(0);
  for (int k = 0; k < 20000 && gap() > 0; ++k) {
    run.step();
    CHECK(run.vx(0) == Approx(vx_after).epsilon(1e-12));
  }
  CHECK(vx_after > 0.05);  // the incline throws it toward +x, down the slope
}

namespace {

nlohmann::json c1(double theta_deg, double mu, const std::string& mass_model) {
  const double th = theta_deg * M_PI / 180;
  std::vector<std::string> sets = {assignment("gravity.0", 9.81 * std::sin(th)), assignment("gravity.1", -9.81 * std::cos(th)),
                                   assignment("materials.copper.friction", mu),
                                   assignment("materials.wall.friction", mu), "mass_model=" + mass_model};
  if (mass_model == "sphere") sets.push_back("thickness=null");
  return run_scene(load_scene(testing::case_path("c1_incline_roll_slide.yaml"), sets), {"", true});
}

}  // namespace

TEST_CASE("C1: below the friction limit a cylinder rolls without slip at 2/3 g sin(theta)", "[c1]") {
  const auto s = c1(20, 0.3, "cylinder");
  CHECK(s["incline_acceleration"].get<double>() == Approx(2.0 / 3.0 * 9.81 * std::sin(20 * M_PI / 180)).epsilon(0.01));
  CHECK(std::abs(s["slip_ratio"].get<double>()) < 0.01);
}

TEST_CASE("C1: below the friction limit a sphere rolls without slip at 5/7 g sin(theta)", "[c1]") {
  const auto s = c1(20, 0.3, "sphere");
  CHECK(s["incline_acceleration"].get<double>() == Approx(5.0 / 7.0 * 9.81 * std::sin(20 * M_PI / 180)).epsilon(0.01));
  CHECK(std::abs(s["slip_ratio"].get<double>()) < 0.01);
}

TEST_CASE("C1: above the friction limit the disc slides at g (sin(theta) - mu cos(theta))", "[c1]") {
  const double th = 45 * M_PI / 180, mu = 0.1;
  const auto s = c1(45, mu, "cylinder");
  CHECK(s["incline_acceleration"].get<double>() == Approx(9.81 * (std::sin(th) - mu * std::cos(th))).epsilon(0.01));
  CHECK(s["slip_ratio"].get<double>() > 0.5);
  // Sliding friction dissipates mu N v per unit time: the ledger must have it and close.
  CHECK(s["energy"]["dissipated_friction"].get<double>() > 0);
  CHECK(std::abs(s["energy"]["balance_error"].get<double>()) < 1e-3 * std::abs(s["energy"]["kinetic"].get<double>()));
}
