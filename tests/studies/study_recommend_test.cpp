// kiln recommend (src/studies/study_recommend.h) on the harmonic contact, whose exact solution is
// known: the cheapest scheme at a tight tolerance is the fourth-order one, as theory says, it is
// never asked to step beyond a stability limit, and it says when nothing meets the tolerance.
#include <catch2/catch.hpp>

#include <string>

#include "src/run/stability.h"
#include "src/scene/scene_yaml.h"
#include "src/studies/study_recommend.h"
#include "tests/support.h"

using namespace kiln;

namespace {

RecommendOptions harmonic(double tolerance) {
  RecommendOptions o;
  o.scene = testing::case_path("harmonic_contact_pair.yaml");
  o.quantity = "position";
  o.ensemble.tolerance = tolerance;
  o.quiet = true;
  o.threads = 1;
  return o;
}

}  // namespace

TEST_CASE("recommend finds the fourth-order scheme cheapest at a tight tolerance on the harmonic contact, as theory says",
          "[study]") {
  // Theory: a p-th order scheme's error at t_end falls as dt^p, so at 1e-10 m velocity Verlet
  // (p = 2, one force per step) needs dt ~ 4e-6 s (about 2,500 forces) and erk4 (p = 4, four
  // per step) dt ~ 7e-5 s (about 850); Heun's table has no imaginary interval, so its limit on
  // the undamped contact is 1.2e-5 s (about 1,900 forces at that step alone).
  const nlohmann::json r = run_recommend(harmonic(1e-10));
  REQUIRE(r["recommendation"].is_object());
  CHECK(r["recommendation"]["integrator"] == "erk4");
  CHECK(r["recommendation"]["error"].get<double>() <= 1e-10);
  CHECK(r["reference"] == "analytic");
  for (const auto& p : r["probes"]) {
    INFO(p.dump());
    CHECK(p["fraction_of_limit"].get<double>() <= 0.9 + 1e-12);  // never beyond a stability limit
  }
}

TEST_CASE("recommend takes a step only when its half step meets the tolerance too, and one force per step wins a loose one",
          "[study]") {
  // At 1e-7 m velocity Verlet's 4.0e-4 s ends 1.4e-8 m off (the phase at t_end happens to match),
  // its half step 3.5e-7 m: the coarse step was recommended before, by chance.
  const nlohmann::json r = run_recommend(harmonic(1e-7));
  REQUIRE(r["recommendation"].is_object());
  CHECK(r["recommendation"]["integrator"] == "velocity-verlet");
  CHECK(r["recommendation"]["dt"].get<double>() == Approx(1.0033e-4).epsilon(1e-3));
  bool lucky_step_left = false;
  for (const auto& p : r["probes"])
    if (p["integrator"] == "velocity-verlet" && p["dt"].get<double>() > 4e-4)
      lucky_step_left = p["meets"] == true && p["confirmed"] == false;
  CHECK(lucky_step_left);
  // Loose: velocity Verlet at 0.9 of its limit meets 1e-6 m, and so does its half step.
  const nlohmann::json loose = run_recommend(harmonic(1e-6));
  REQUIRE(loose["recommendation"].is_object());
  CHECK(loose["recommendation"]["integrator"] == "velocity-verlet");
  CHECK(loose["recommendation"]["fraction_of_limit"].get<double>() == Approx(0.9));
}

TEST_CASE("recommend says so when no probed scheme meets the tolerance, or the budget ends the probe", "[study]") {
  const nlohmann::json none = run_recommend(harmonic(1e-30));
  CHECK(none["recommendation"].is_null());
  for (const auto& [name, c] : none["candidates"].items())
    CHECK(c["stopped"].get<std::string>().find("steps probed: none met the tolerance") != std::string::npos);
  RecommendOptions o = harmonic(1e-14);
  o.budget = 1e-9;
  const nlohmann::json broke = run_recommend(o);
  CHECK(broke["budget_spent"] == true);
  CHECK(broke["recommendation"].is_null());
  CHECK(broke["probes"].size() == 3);  // one round, then the next was predicted beyond the budget
  CHECK(broke["not_tried"]["integrators"].size() > 10);
  // The budget is judged before a round from what the last one cost: the probe stops near it, off
  // by that prediction's error (runs of milliseconds: their clock's noise, a few per cent here),
  // where it overran by the whole of its last round before, and says what it spent.
  // (20 rounds of the first: a loaded machine makes one round cost several times another.)
  o.budget = 20 * broke["cpu_seconds"].get<double>();
  const nlohmann::json some = run_recommend(o);
  CHECK(some["cpu_seconds"].get<double>() <= 1.5 * o.budget);
  CHECK(some["probes"].size() > 3);
}

TEST_CASE("recommend's list of what it did not try names no method it tried, under any of its names", "[study]") {
  RecommendOptions o = harmonic(1e-6);
  o.integrators = {"erk2", "erk4"};
  const nlohmann::json r = run_recommend(o);
  CHECK(r["integrators"] == nlohmann::json({"erk2", "erk4"}));
  for (const auto& name : r["not_tried"]["integrators"]) {
    INFO(name);
    CHECK(name != "erk:HEUN_EULER_2_1_2");
    CHECK(name != "erk:ZONNEVELD_5_3_4");
  }
  // Two names of one method are one candidate: refused, naming both.
  o.integrators = {"erk4", "erk:ZONNEVELD_5_3_4"};
  CHECK_THROWS_WITH(run_recommend(o), Catch::Contains("'erk:ZONNEVELD_5_3_4' is given twice ('erk4' names the same"));
}

TEST_CASE("recommend judges each step by the limit on every member's end state, never recommending beyond 0.9 of it",
          "[study][heavy]") {
  // A small drum (40 discs, 50 ms): its members' beds differ, and so do their limits at the end.
  // The limit was taken on member 0's end state of the first run alone (itself past the limit),
  // and a step was recommended at 0.91 of another member's.
  RecommendOptions o;
  o.scene = testing::case_path("t6_drum.yaml");
  o.sets = {"particles.0.fill.count=40"};
  o.quantity = "temperature_std";
  o.integrators = {"velocity-verlet"};
  o.ensemble.seeds = 3;
  o.ensemble.tolerance = 1;  // loose: the first step within the limit meets it
  o.halvings = 3;
  o.t_end = 0.05;
  o.quiet = true;
  o.threads = 2;
  const nlohmann::json r = run_recommend(o);
  const Scene base = load_scene(o.scene, o.sets);
  const StabilityEstimate start = estimate_stability(base, "velocity-verlet");
  for (const auto& p : r["probes"]) {
    if (p.contains("failure")) continue;
    INFO(p.dump());
    const double dt = p["dt"].get<double>();
    CHECK(dt <= 0.9 * p["stability_limit"].get<double>() * (1 + 1e-9));
    // Each member's end state at that step, by hand.
    for (int m = 0; m < 3; ++m) {
      std::vector<StudyRun> run = {StudyRun("velocity-verlet", dt, {member_set(m)})};
      run[0].limit_at_end = true;
      run_study(o.scene, o.sets, o.t_end, o.quantity, run, 1, true);
      REQUIRE(run[0].at_end.is_object());
      const double limit = study_limit(with_state(start, limit_of_json(run[0].at_end)), base, "velocity-verlet", false).dt;
      CHECK(dt <= 0.9 * limit * (1 + 1e-9));
    }
  }
}

TEST_CASE("recommend refuses a question it cannot answer", "[study]") {
  RecommendOptions o = harmonic(0);
  CHECK_THROWS_WITH(run_recommend(o), Catch::Contains("--tolerance is required"));
  CHECK_THROWS_WITH(ensemble_options("", 0, 64, false, 0.95, 0, true), Catch::Contains("a number above 0"));
  CHECK_THROWS_WITH(ensemble_options("4", 0, 6, true, 0.95, 0, false), Catch::Contains("--max-seeds caps --seeds auto"));
  CHECK_THROWS_WITH(require_seeds_for_statistics(ensemble_options("", 0, 6, true, 0.95, 0, false)),
                    Catch::Contains("--max-seeds caps --seeds auto"));
  o = harmonic(1e-6);
  o.quantity = "heap_angle_deg";
  CHECK_THROWS_WITH(run_recommend(o), Catch::Contains("unknown quantity"));
  o = harmonic(1e-6);
  o.integrators = {"erk9"};
  CHECK_THROWS(run_recommend(o));
}
