// Step control: a run takes exactly the steps it reports, frames never cut a step, and every
// integrator ends on t_end the same way (a last step shortened to land there, and reported).
#include <catch2/catch.hpp>

#include <filesystem>

#include "src/base/error.h"
#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "src/run/stability.h"
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

TEST_CASE("an adaptive step never outruns the neighbour lists: T1 damped under erk5 at rtol 1e-6 bounces to the end",
          "[step_control]") {
  // In free flight the error estimate lets the step grow without bound; it used to grow until one
  // step moved the disc beyond the skin (exit 3 at 0.041 s). Steps are now capped at an eighth of
  // the skin over the fastest speed, and a step that still outruns the lists is halved.
  const Scene scene = load_scene(testing::case_path("t1_free_fall_damped.yaml"), {"integrator=erk5", "rtol=1e-6"});
  const auto s = run_scene(scene, {"", true});
  CHECK(s["t_end"].get<double>() == Approx(scene.t_end));
  // The ledger closes to the tolerance asked for (measured 1.0e-6 of the largest exchange).
  CHECK(std::abs(s["energy"]["balance_error"].get<double>()) < 1e-5 * s["checks"]["energy_balance"]["largest_exchange"].get<double>());
}

TEST_CASE("a disc striking a floor at 70 degrees with mu = 1 finishes under erk5 at rtol 1e-6", "[step_control]") {
  const Scene scene = load_scene(testing::case_path("t1_free_fall_damped.yaml"),
                                 {"integrator=erk5", "rtol=1e-6", "particles.0.velocity=[1.8793852415718166, -0.6840402866513374]",
                                  "contacts.0.friction=1.0", "t_end=0.1"});
  const auto s = run_scene(scene, {"", true});
  CHECK(s["t_end"].get<double>() == Approx(0.1));
}

TEST_CASE("a fixed step longer than the skin allows gets lists that cover it: free flight at 1.5 m/s under erk4 "
          "at dt 1e-3", "[step_control]") {
  // 1.5 mm per step against a 0.8 mm skin (and below the 2 mm radius, beyond which the run stops:
  // the disc could pass through a wall): the run used to stop at t = 0 ("velocities are running
  // away"). The lists are now built with a skin that covers the step; erk4 is exact on the
  // parabola of free flight.
  const Scene scene = load_scene(testing::case_path("t1_free_fall.yaml"),
                                 {"integrator=erk4", "dt=1e-3", "t_end=0.01", "particles.0.velocity=[0, -1.5]"});
  FinalFields f;
  const auto s = run_scene(scene, {"", true, &f});
  CHECK(s["steps"].get<long>() == 10);
  CHECK(f.position[1] == Approx(scene.position[0].y - 1.5 * 0.01 - 0.5 * 9.81 * 0.01 * 0.01).epsilon(1e-12));
}

TEST_CASE("when a step outruns the lists the message names the step, the speed and the skin", "[step_control]") {
  const Scene scene = load_scene(testing::case_path("t1_free_fall.yaml"));
  DemSystem system(scene);
  std::vector<double> from = system.initial_state(), to = from;
  from[system.vy_at()] = -2;
  to[system.y_at()] -= 2e-3;
  const std::string text = system.describe_travel(from.data(), to.data(), 1e-3);
  INFO(text);
  CHECK(text.find("particle 0 by 0.002 m") != std::string::npos);
  CHECK(text.find("step x speed = 0.002 m") != std::string::npos);
  CHECK(text.find("neighbour skin of 0.0008 m") != std::string::npos);
}

TEST_CASE("adaptive runs of the shipped exact cases finish from rtol 1e-4 to 1e-8", "[step_control]") {
  for (const char* file : {"harmonic_contact_pair.yaml", "t1_free_fall.yaml", "t1_free_fall_damped.yaml",
                           "c1_incline_roll_slide.yaml", "oblique_sliding_impact.yaml", "slide_to_roll.yaml",
                           "stick_two_sevenths.yaml", "t4_two_particle_conduction.yaml", "f1_chain_slab.yaml",
                           "n1_triangle_conduction.yaml"})
    for (const char* rtol : {"1e-4", "1e-6", "1e-8"}) {
      INFO(file << " rtol " << rtol);
      const Scene scene = load_scene(testing::case_path(file), {"integrator=erk5", std::string("rtol=") + rtol});
      const auto s = run_scene(scene, {"", true});
      CHECK(s["t_end"].get<double>() == Approx(scene.t_end));
    }
}

TEST_CASE("fixed ARKODE steps end exactly on t_end however many there are (no step of 1e-12 s after them)",
          "[step_control]") {
  // ARKODE sums its steps into t: after 300,000 steps of 1e-6 s it stood 1.1e-12 s short of 0.3 and
  // took one more step of that length.
  const auto s = run_scene(load_scene(testing::case_path("t1_free_fall.yaml"), {"integrator=erk4", "t_end=0.3"}),
                           {"", true});
  CHECK(s["steps"].get<long>() == 300000);
  CHECK(s["t_end"].get<double>() == 0.3);
  CHECK(s["step_size"]["min"].get<double>() == Approx(1e-6).epsilon(1e-4));
}

TEST_CASE("a frozen heating stage reports the integrator and step it ran with", "[step_control][heavy]") {
  const auto s = run_scene(load_scene(testing::case_path("n2_heated_steel_bed.yaml"),
                                      {"freeze.integrator=imex4", "freeze.dt=450"}),
                           {"", true});
  const auto& heat = s["integrator_stats"]["heat_stage"];
  CHECK(heat["integrator"] == "imex4");
  CHECK(heat["dt"].get<double>() == 450);
  CHECK(heat["step_size"]["max"].get<double>() == Approx(450));
}

TEST_CASE("a step that carries a disc past a wall's overlap band is refused: 100 m/s at dt 1e-4 s", "[step_control]") {
  // A 2 mm disc at 100 m/s towards a floor: one step moves it 10 mm, more than its diameter, and it
  // jumped over the floor without ever touching it (exit 0). dt x impact speed must stay below the
  // smallest radius.
  const Scene scene = parse_scene(R"(name: fast_disc_tunnel
mass_model: sphere
gravity: [0, -9.81]
materials:
  glass: {density: 2500, stiffness: 2.0e4, restitution: 0.5}
  plate: {stiffness: 2.0e4, restitution: 0.5}
particles:
  - material: glass
    radius: 0.002
    at: [[0.0, 0.0131]]
    velocity: [0.0, -100.0]
walls:
  - {name: floor, material: plate, segment: [[-0.01, 0.0], [0.01, 0.0]]}
dt: 1.0e-4
t_end: 0.0005
)",
                                  "tunnel.yaml");
  const DtVerdict verdict = judge_dt(estimate_stability(scene), scene.dt, scene);
  REQUIRE(verdict.unstable);
  CHECK(verdict.warnings.front().find("dt x impact speed") != std::string::npos);
  CHECK(verdict.warnings.front().find("smallest radius (0.002 m)") != std::string::npos);
  CHECK_FALSE(judge_dt(estimate_stability(scene), 1e-6, scene).unstable);
}
