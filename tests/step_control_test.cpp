// Step control: a run takes exactly the steps it reports, frames never cut a step, and every
// integrator ends on t_end the same way (a last step shortened to land there, and reported).
#include <catch2/catch.hpp>

#include <filesystem>

#include "src/error.h"
#include "src/scene_yaml.h"
#include "src/simulation.h"
#include "tests/support.h"

using namespace kiln;
namespace fs = std::filesystem;

namespace {

nlohmann::json run_t4(const std::vector<std::string>& sets, const std::string& out = "") {
  return run_scene(load_scene(testing::case_path("t4_two_particle_conduction.yaml"), sets), {out, true});
}

}  // namespace

TEST_CASE("a fixed-step run takes exactly the steps of dt it reports, whatever the frame interval",
          "[step_control]") {
  // Frames every 0.01 s, steps of 0.04 s: fixed ARKODE steps used to be cut at every frame (80
  // steps reported as dt 0.04) while the Verlet schemes took 20.
  for (const char* integrator : {"erk4", "erk5", "imex4", "velocity-verlet", "verlet"}) {
    INFO(integrator);
    const auto s = run_t4({std::string("integrator=") + integrator, "dt=0.04", "t_end=0.8", "output_interval=0.01"});
    CHECK(s["steps"].get<long>() == 20);
    CHECK(s["t_end"].get<double>() == Approx(0.8).epsilon(1e-12));
    CHECK(s["step_size"]["min"].get<double>() == Approx(0.04).epsilon(1e-9));
    CHECK(s["step_size"]["max"].get<double>() == Approx(0.04).epsilon(1e-9));
  }
}

TEST_CASE("every integrator ends on t_end with one shorter last step when t_end is not a multiple of dt",
          "[step_control]") {
  // 0.8 = 26 x 0.03 + 0.02: the Verlet schemes used to overshoot to 0.81.
  for (const char* integrator : {"erk4", "imex3", "velocity-verlet", "verlet"}) {
    INFO(integrator);
    const auto s = run_t4({std::string("integrator=") + integrator, "dt=0.03", "t_end=0.8"});
    CHECK(s["steps"].get<long>() == 27);
    CHECK(s["t_end"].get<double>() == Approx(0.8).epsilon(1e-12));
    CHECK(s["step_size"]["max"].get<double>() == Approx(0.03).epsilon(1e-9));
    CHECK(s["step_size"]["last"].get<double>() == Approx(0.02).epsilon(1e-9));
  }
}

TEST_CASE("frames are the states of the steps that reach them, stamped with those steps' times", "[step_control]") {
  const fs::path dir = fs::temp_directory_path() / "kiln_step_control_frames";
  fs::remove_all(dir);
  run_t4({"integrator=erk4", "dt=0.04", "t_end=0.2", "output_interval=0.01"}, dir.string());
  const std::vector<double> times = testing::read_dataset(dir / "result.h5", "time");
  REQUIRE(times.size() == 6);
  for (size_t k = 0; k < times.size(); ++k) CHECK(times[k] == Approx(0.04 * k).margin(1e-12));
  fs::remove_all(dir);
}

TEST_CASE("explicit conduction beyond its limit goes unstable even with frames finer than the step",
          "[step_control]") {
  // Heun is stable to dt = 2 / lambda = 0.1064 s on T4. With frames every 0.01 s the cut steps
  // used to keep a run at dt 0.13 stable.
  const Scene scene = load_scene(testing::case_path("t4_two_particle_conduction.yaml"),
                                 {"integrator=erk2", "dt=0.13", "t_end=3", "output_interval=0.01"});
  CHECK_THROWS_AS(run_scene(scene, {"", true}), InstabilityError);
}

TEST_CASE("an adaptive run reports the smallest, largest and mean step it took", "[step_control]") {
  const auto s = run_t4({"integrator=erk4", "rtol=1e-6", "dt=1e-3", "t_end=0.8"});
  const auto& h = s["step_size"];
  CHECK(h["steps"].get<long>() == s["steps"].get<long>());
  CHECK(h["min"].get<double>() < h["max"].get<double>());
  CHECK(h["mean"].get<double>() == Approx(0.8 / s["steps"].get<double>()).epsilon(1e-9));
}
