// The stability estimate (src/run/stability.h) reads how fast walls move from the walls' motions
// (WallMotion::largest_speed): every moving wall pushes discs at its speed, a load-controlled one too.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "src/run/simulation.h"
#include "src/run/stability.h"
#include "src/scene/scene_yaml.h"
#include "tests/support.h"

using namespace kiln;

namespace {

// A Hertz disc at rest without gravity between a floor and a top wall moving as `motion` says:
// nothing but the wall sets its impact speed, and a Hertz contact's duration depends on it.
Scene disc_under_a_wall(const std::string& motion) {
  return parse_scene(R"(name: wall_speed
gravity: [0, 0]
contact_model: hertz
materials:
  glass: {density: 2500, youngs_modulus: 1.0e8, restitution: 0.5}
particles:
  - {material: glass, radius: 0.001, at: [[0, 0.002]]}
walls:
  - {name: floor, material: glass, segment: [[-0.05, 0], [0.05, 0]]}
  - {name: top, material: glass, segment: [[-0.05, 0.01], [0.05, 0.01]], motion: )" + motion + R"(}
dt: 1.0e-7
t_end: 0.01
)",
                     "wall_speed.yaml");
}

}  // namespace

TEST_CASE("the stability estimate counts a load-controlled wall's driven speed as a translating wall's", "[stability]") {
  // N3's top wall: driven at 4 m/s along x, free along its load. Before, its speed was left out:
  // the impact speed was the floor of 1 mm/s, and the Hertz contact (t ~ v^-1/5) 5.2 times longer.
  const StabilityEstimate driven = estimate_stability(
      disc_under_a_wall("{type: load_controlled, velocity: [4.0, 0], load: [0, -1.0], mass: 0.01, damping: 1.0}"));
  const StabilityEstimate sliding = estimate_stability(disc_under_a_wall("{type: translate, velocity: [4.0, 0]}"));
  const StabilityEstimate resting = estimate_stability(disc_under_a_wall("{type: fixed}"));
  CHECK(driven.impact_speed == Approx(2 * 4.0));  // two discs would meet at twice a disc's speed
  CHECK(driven.impact_speed == sliding.impact_speed);
  CHECK(driven.recommended_dt < resting.recommended_dt);
}

// A study compares runs by their wall seconds. The estimate at a run's start (a Lanczos iteration
// on 27,000 coordinates here, seconds) is start-up, reported apart; it was counted in the run's
// seconds, which made a two-step run cost as much as the estimate.
TEST_CASE("a run's wall seconds are its steps' and the stability estimate's seconds are reported apart", "[stability]") {
  std::string text = testing::pressed_pile(false);
  text += "output_interval: 1.0e-6\n";
  Scene scene = parse_scene(text, "pressed_pile");
  scene.t_end = 2 * scene.dt;
  RunOptions options;
  options.quiet = true;
  const nlohmann::json summary = run_scene(scene, options);
  const double estimate = summary.at("stability").at("estimate_seconds");
  const double run = summary.at("wall_seconds");
  INFO("estimate " << estimate << " s, run " << run << " s");
  CHECK(estimate > 0);
  CHECK(run < 0.5 * estimate);
}

TEST_CASE("a stiffness near double's range still names the binding mode in the estimate and its refusal", "[stability]") {
  // Issue 28's campaign (F6): at k = 1e300 N/m the step map's mode shape overflowed, and the
  // refusal read "(its  mode, ...)".
  const Scene scene = load_scene(testing::case_path("t3_heap.yaml"), {"materials.copper.stiffness=1e300"});
  const StabilityEstimate est = estimate_stability(scene);
  REQUIRE(std::isfinite(est.dt_limit));
  CHECK(!est.limit.mode.empty());
  const DtVerdict verdict = judge_dt(est, scene.dt, scene);
  CHECK(verdict.unstable);
  REQUIRE(!verdict.warnings.empty());
  for (const std::string& w : verdict.warnings) CHECK(w.find("its  mode") == std::string::npos);
}

TEST_CASE("a contact hundreds of orders faster than SI's scale gets its stability limit, not 'no stable step'",
          "[stability]") {
  // Issue 28's campaign (F8): at 1e-250 kg/m^3 a disc's contact rings at 1e131 rad/s; the step
  // map's entries spanned 1e-132 to 1e262 and every step was judged unstable ("no stable step",
  // a warning, exit 0), and the run died of NaN. The limit is found in units of 1/omega.
  const Scene scene = load_scene(testing::case_path("t3_heap.yaml"), {"materials.copper.density=1e-250"});
  const StabilityEstimate est = estimate_stability(scene);
  CHECK(est.dt_limit > 1e-133);
  CHECK(est.dt_limit < 1e-130);
  CHECK(judge_dt(est, scene.dt, scene).unstable);
}
