// What a run leaves behind and how it fails: outputs, determinism, instability messages, and a
// scene that models only what it needs.
#include <catch2/catch.hpp>
#include <hdf5.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "src/dem_system.h"
#include "src/error.h"
#include "src/overrides.h"
#include "src/scene_yaml.h"
#include "src/simulation.h"
#include "src/stability.h"
#include "tests/support.h"

using namespace kiln;
namespace fs = std::filesystem;

namespace {

}  // namespace

TEST_CASE("kiln run writes result.h5, result.xdmf, summary.json and picture.png, nothing temporary", "[outputs]") {
  const fs::path dir = testing::fresh_dir("outputs");
  const std::string cmd = std::string(KILN_BINARY) + " run " + testing::case_path("t1_free_fall.yaml") +
                          " --t-end 0.01 --quiet --out " + dir.string();
  REQUIRE(std::system(cmd.c_str()) == 0);
  for (const char* name : {"result.h5", "result.xdmf", "summary.json", "picture.png"}) CHECK(fs::exists(dir / name));
  for (const auto& entry : fs::directory_iterator(dir)) CHECK(entry.path().extension() != ".tmp");
  std::ifstream in(dir / "summary.json");
  const auto s = nlohmann::json::parse(in);
  for (const char* key : {"scene", "integrator", "dt", "t_end", "steps", "rhs_evals", "wall_seconds", "particles",
                          "mean_contacts"})
    CHECK(s.contains(key));
  for (const char* key : {"kinetic", "potential", "elastic", "dissipated_damping", "dissipated_friction",
                          "work_by_walls", "balance_error"})
    CHECK(s["energy"].contains(key));
  // 0.01 s at 1e-3 s per frame: the initial state, ten frames, the final state included.
  const auto time = testing::read_dataset(dir / "result.h5", "time");
  REQUIRE(time.size() == 11);
  CHECK(time.front() == 0.0);
  CHECK(time.back() == Approx(0.01));
  CHECK(testing::read_dataset(dir / "result.h5", "position").size() == 11 * 2);
  CHECK(testing::read_dataset(dir / "result.h5", "radius") == std::vector<double>{0.002});
  fs::remove_all(dir);
}

TEST_CASE("a bad --set on the command line fails with exit code 2 and writes nothing", "[outputs]") {
  const fs::path dir = testing::fresh_dir("bad");
  const std::string cmd = std::string(KILN_BINARY) + " run " + testing::case_path("t1_free_fall.yaml") +
                          " --set materials.copper.density=-1 --quiet --out " + dir.string() + " 2>/dev/null";
  CHECK(WEXITSTATUS(std::system(cmd.c_str())) == 2);
  CHECK_FALSE(fs::exists(dir));
}

TEST_CASE("the same scene and options give bit-identical result.h5 data", "[outputs]") {
  const Scene scene = load_scene(testing::case_path("t3_heap.yaml"), {"particles.0.fill.count=100", "t_end=0.05"});
  std::vector<std::vector<double>> runs;
  for (int k = 0; k < 2; ++k) {
    const fs::path dir = testing::fresh_dir("determinism" + std::to_string(k));
    run_scene(scene, {dir.string(), true});
    std::vector<double> all;
    for (const char* name : {"time", "position", "velocity", "angle", "angular_velocity"}) {
      const auto d = testing::read_dataset(dir / "result.h5", name);
      all.insert(all.end(), d.begin(), d.end());
    }
    runs.push_back(all);
    fs::remove_all(dir);
  }
  REQUIRE(runs[0].size() > 1000);
  CHECK(std::memcmp(runs[0].data(), runs[1].data(), runs[0].size() * sizeof(double)) == 0);
}

TEST_CASE("a step beyond the stability limit stops with the failed check, the time and the advised dt", "[stability]") {
  const Scene scene = load_scene(testing::case_path("t1_free_fall.yaml"), {"dt=5e-4", "t_end=0.2"});
  const StabilityEstimate est = estimate_stability(scene);
  CHECK(judge_dt(est, scene.dt, scene).unstable);  // kiln check and kiln run refuse it up front
  const fs::path dir = testing::fresh_dir("unstable");
  try {
    run_scene(scene, {dir.string(), true});
    FAIL("the run did not stop");
  } catch (const InstabilityError& e) {
    const std::string msg = e.what();
    CHECK(msg.find("unstable run at t = ") != std::string::npos);
    CHECK((msg.find("overlap") != std::string::npos || msg.find("energy blow-up") != std::string::npos ||
           msg.find("NaN") != std::string::npos));
    CHECK(msg.find("recommends dt <= 1.4") != std::string::npos);  // t_c / 50 = 1.40e-5 s
  }
  // Nothing half-written is left behind.
  for (const auto& entry : fs::directory_iterator(dir)) CHECK(entry.path().extension() != ".tmp");
  CHECK_FALSE(fs::exists(dir / "result.h5"));
  fs::remove_all(dir);
}

TEST_CASE("stability estimate: linear contact duration and the central-difference limit", "[stability]") {
  const Scene scene = load_scene(testing::case_path("t1_free_fall.yaml"));
  const StabilityEstimate est = estimate_stability(scene);
  const double m = 4.0 / 3.0 * M_PI * 8e-9 * 8900;
  CHECK(est.contact_duration == Approx(M_PI * std::sqrt(m / 6000)));
  CHECK(est.dt_limit == Approx(2 * std::sqrt(m / 6000)));
  CHECK(est.recommended_dt == Approx(est.contact_duration / 50));
  CHECK(judge_dt(est, 1e-6, scene).warnings.empty());
  CHECK_FALSE(judge_dt(est, 1e-4, scene).unstable);
  CHECK(judge_dt(est, 1e-4, scene).warnings.size() == 1);  // 7 steps per contact: warned, not refused
}

TEST_CASE("a frictionless scene integrates no rotation, while friction adds angles and spins", "[state]") {
  const Scene plain = load_scene(testing::case_path("t1_free_fall.yaml"));
  DemSystem without(plain);
  CHECK_FALSE(without.rotates());
  CHECK(without.layout().nq == 2 * plain.n_particles());
  const Scene rough = load_scene(testing::case_path("c1_incline_roll_slide.yaml"));
  DemSystem with(rough);
  CHECK(with.rotates());
  CHECK(with.layout().nq == 3 * rough.n_particles());
}
