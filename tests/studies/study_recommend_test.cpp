// kiln recommend (src/studies/study_recommend.h) on the harmonic contact, whose exact solution is
// known: the cheapest scheme at a tight tolerance is the fourth-order one, as theory says, it is
// never asked to step beyond a stability limit, and it says when nothing meets the tolerance.
#include <catch2/catch.hpp>

#include <string>

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
    CHECK(c["stopped"].get<std::string>().find("steps probed without meeting") != std::string::npos);
  RecommendOptions o = harmonic(1e-14);
  o.budget = 1e-9;
  const nlohmann::json broke = run_recommend(o);
  CHECK(broke["budget_spent"] == true);
  CHECK(broke["recommendation"].is_null());
  CHECK(broke["probes"].size() == 3);  // one round, then the budget was spent
  CHECK(broke["not_tried"]["integrators"].size() > 10);
}

TEST_CASE("recommend refuses a question it cannot answer", "[study]") {
  RecommendOptions o = harmonic(0);
  CHECK_THROWS_WITH(run_recommend(o), Catch::Contains("--tolerance is required"));
  o = harmonic(1e-6);
  o.quantity = "heap_angle_deg";
  CHECK_THROWS_WITH(run_recommend(o), Catch::Contains("unknown quantity"));
  o = harmonic(1e-6);
  o.integrators = {"erk9"};
  CHECK_THROWS(run_recommend(o));
}
