// P1: a 20 um copper powder compacted on a hot floor, the case where conduction, not contact
// mechanics, limits an explicit step. IMEX (conduction implicit) must run stably at a step where
// every explicit scheme is stopped, and agree with a converged explicit run.
#include <catch2/catch.hpp>

#include "src/base/error.h"
#include "src/scene/overrides.h"
#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "tests/support.h"

using namespace kiln;

namespace {

nlohmann::json run_powder(const std::string& integrator, double dt, FinalFields* fields) {
  return run_scene(load_scene(testing::case_path("p1_fine_powder_compaction.yaml"),
                              {"integrator=" + integrator, assignment("dt", dt)}),
                   {"", true, fields});
}

}  // namespace

TEST_CASE("P1 fine powder: IMEX runs at 6x the step where explicit conduction blows up, to the same temperatures",
          "[heat][powder][heavy]") {
  // The measured explicit boundary is 7.6e-6 s (erk4); IMEX's mechanical one 6.2e-5 s.
  const double big = 4.5e-5;
  CHECK_THROWS_AS(run_powder("erk4", big, nullptr), InstabilityError);
  FinalFields implicit, converged;
  const nlohmann::json s = run_powder("imex4", big, &implicit);
  run_powder("erk4", 2.5e-6, &converged);
  double worst = 0;
  for (size_t i = 0; i < implicit.temperature.size(); ++i)
    worst = std::max(worst, std::abs(implicit.temperature[i] - converged.temperature[i]));
  INFO("largest temperature difference " << worst << " K");
  CHECK(worst < 2e-3);  // first order in dt (contact onsets at the side walls): 7e-4 K at this step
  // All heat came through the floor, and the bed approaches its temperature.
  CHECK(s["energy"]["heat_from_walls"].get<double>() ==
        Approx(s["energy"]["thermal_change"].get<double>()).epsilon(1e-9));
  CHECK(s["temperature_min"].get<double>() > 99);
}

// Issue 28 (F13): a fixed step's Newton test weighed 1e-12 of a temperature in Celsius plus
// 1e-14 K, so particles at 0 C asked the iteration for 1e-14 K, below the heat flows' round-off:
// P1 started at 0 C failed at t = 0 with ARK_CONV_FAILURE and blamed dt. Conduction depends on
// temperature differences alone, so the same bed 20 K warmer must give the same temperatures + 20 K.
TEST_CASE("P1 started at 0 C runs under fixed-step IMEX, and 20 K warmer gives the same temperatures plus 20 K",
          "[heat][powder]") {
  const auto bed = [](double particles, double floor, FinalFields* fields) {
    return run_scene(load_scene(testing::case_path("p1_fine_powder_compaction.yaml"),
                                {"t_end=0.001", assignment("particles.0.temperature", particles),
                                 "walls.0.temperature={steps: [[0, " + std::to_string(floor) + "], [0.008, 100]]}"}),
                     {"", true, fields});
  };
  FinalFields cold, warm;
  const nlohmann::json s = bed(0, 20, &cold);
  bed(20, 40, &warm);
  CHECK(s["integrator"] == "imex4");
  REQUIRE(cold.temperature.size() == warm.temperature.size());
  double largest = 0, furthest = 0;
  for (size_t i = 0; i < cold.temperature.size(); ++i) {
    largest = std::max(largest, cold.temperature[i]);
    furthest = std::max(furthest, std::abs(warm.temperature[i] - 20 - cold.temperature[i]));
  }
  CHECK(largest > 1e-3);  // heat came in from the floor
  // The iteration stops within 1e-12 of the absolute temperature (3e-10 K): ten times that.
  CHECK(furthest < 3e-9);
}
