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
