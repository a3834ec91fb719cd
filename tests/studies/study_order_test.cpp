// `kiln order`: it recovers known orders, Richardson agrees with the analytic reference, and the
// results do not depend on the number of threads.
#include <catch2/catch.hpp>
#include <cmath>
#include <filesystem>
#include <fstream>

#include "src/base/error.h"
#include "src/scene/overrides.h"
#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "src/studies/study_order.h"
#include "src/studies/study_sweep.h"
#include "src/studies/study_wp.h"
#include "tests/support.h"

using namespace kiln;

namespace {

OrderOptions harmonic(const std::string& integrator, double dt, int levels) {
  OrderOptions o;
  o.scene = testing::case_path("harmonic_contact_pair.yaml");
  o.integrators = {integrator};
  o.dt = dt;
  o.levels = levels;
  o.quiet = true;
  return o;
}

double fitted(const nlohmann::json& study) { return study["integrators"][0]["fitted_order"].get<double>(); }

// A pair case with contact events against the fine reference, velocity at the end.
OrderOptions pair_case(const std::string& scene, const std::string& integrator, double dt, int levels) {
  OrderOptions o;
  o.scene = testing::case_path(scene);
  o.integrators = {integrator};
  o.sets = {"contact_events=true"};
  o.reference = "fine";
  o.quantity = "velocity";
  o.dt = dt;
  o.levels = levels;
  o.quiet = true;
  return o;
}

}  // namespace

TEST_CASE("kiln order recovers velocity Verlet 2, Heun 2, Zonneveld 4 and Dormand-Prince 5 on the harmonic contact",
          "[study]") {
  // Coarsest steps in each scheme's asymptotic range (the period is 1.4 ms).
  CHECK(fitted(run_order_study(harmonic("velocity-verlet", 1e-4, 4))) == Approx(2).margin(0.15));
  CHECK(fitted(run_order_study(harmonic("erk2", 2.5e-5, 4))) == Approx(2).margin(0.15));
  CHECK(fitted(run_order_study(harmonic("erk4", 5e-5, 4))) == Approx(4).margin(0.15));
  const auto dp = run_order_study(harmonic("erk5", 1e-4, 4));
  CHECK(fitted(dp) == Approx(5).margin(0.25));
  CHECK(dp["integrators"][0]["verdict"] == "matches");
}

TEST_CASE("Richardson's estimate agrees with the analytic reference's order", "[study]") {
  OrderOptions o = harmonic("velocity-verlet", 1e-4, 5);
  const double analytic = fitted(run_order_study(o));
  o.reference = "richardson";
  const double richardson = fitted(run_order_study(o));
  CHECK(richardson == Approx(analytic).margin(0.15));
}

TEST_CASE("an order study gives the same JSON with 1 and 2 threads, timings aside", "[study]") {
  OrderOptions o = harmonic("velocity-verlet", 1e-4, 3);
  o.integrators = {"velocity-verlet", "erk4"};
  o.threads = 1;
  auto one = run_order_study(o);
  o.threads = 2;
  auto two = run_order_study(o);
  for (auto* s : {&one, &two})
    for (auto& entry : (*s)["integrators"]) entry.erase("wall_seconds");
  CHECK(one == two);
}

TEST_CASE("an unknown quantity or a case without an exact solution is refused with the choices", "[study]") {
  OrderOptions o = harmonic("velocity-verlet", 1e-4, 3);
  o.quantity = "positon";
  try {
    run_order_study(o);
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("'position'") != std::string::npos);
  }
  o.quantity = "position";
  o.scene = testing::case_path("t3_heap.yaml");
  try {
    run_order_study(o);
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("--reference fine") != std::string::npos);
  }
}

TEST_CASE("kiln sweep finds velocity Verlet's stability boundary within 10 % of 2/omega", "[study]") {
  SweepOptions o;
  o.scene = testing::case_path("harmonic_contact_pair.yaml");
  o.integrator = "velocity-verlet";
  o.dt_min = 1e-5;
  o.dt_max = 1e-3;
  o.points = 8;
  o.t_end = 0.05;
  o.quiet = true;
  const auto s = run_sweep_study(o);
  const double m = 4.0 / 3.0 * M_PI * 8e-9 * 8900, limit = 2 * std::sqrt(m / 6000);
  REQUIRE(s["largest_stable_dt"].is_number());
  CHECK(s["largest_stable_dt"].get<double>() == Approx(limit).epsilon(0.1));
  CHECK(s["smallest_unstable_dt"].get<double>() == Approx(limit).epsilon(0.1));
  CHECK(s["estimate"]["dt_limit"].get<double>() == Approx(limit).epsilon(1e-9));
  CHECK(s["stable"].front() == true);
  CHECK(s["stable"].back() == false);
}

TEST_CASE("kiln wp: the error falls monotonically with dt and the JSON has the documented fields", "[study]") {
  WorkPrecisionOptions o;
  o.scene = testing::case_path("t4_two_particle_conduction.yaml");
  o.integrators = {"velocity-verlet", "erk4"};
  o.dts = {4e-3, 2e-3, 1e-3};
  o.quantity = "temperature";
  o.repeats = 1;
  o.quiet = true;
  const auto s = run_work_precision(o);
  for (const char* key : {"scene", "quantity", "norm", "reference", "t_end", "setting", "repeats", "integrators"})
    CHECK(s.contains(key));
  for (const auto& entry : s["integrators"]) {
    for (const char* key : {"name", "dt", "error", "wall_seconds", "rhs_evals"}) CHECK(entry.contains(key));
    const auto err = entry["error"].get<std::vector<double>>();
    for (size_t k = 1; k < err.size(); ++k) CHECK(err[k] < err[k - 1]);
    const auto evals = entry["rhs_evals"].get<std::vector<long>>();
    CHECK(evals.back() > evals.front());
  }
}

TEST_CASE("kiln wp --seeds: the error is the ensemble's bias, paired seed by seed, with its interval and verdict",
          "[study][heavy]") {
  // A small drum (40 discs, 50 ms): chaotic, so compared over three members.
  WorkPrecisionOptions o;
  o.scene = testing::case_path("t6_drum.yaml");
  o.sets = {"particles.0.fill.count=40"};
  o.integrators = {"velocity-verlet"};
  o.dts = {4e-6};
  o.quantity = "temperature_std";
  o.ensemble.seeds = 3;
  o.t_end = 0.05;
  o.repeats = 1;
  o.quiet = true;
  const auto s = run_work_precision(o);
  // The same runs by hand: members 0..2 at 4e-6 s and at 2e-6 s, and their differences seed by seed.
  auto member_values = [&](double dt) {
    std::vector<double> v;
    for (int m = 0; m < 3; ++m) {
      const Scene scene = load_scene(o.scene, {"particles.0.fill.count=40", "ensemble_member=" + std::to_string(m),
                                               "t_end=0.05", "output_interval=0.05", assignment("dt", dt)});
      v.push_back(run_scene(scene, {"", true})["temperature_std"].get<double>());
    }
    return v;
  };
  const std::vector<double> run = member_values(4e-6), ref = member_values(2e-6);
  double mean = 0, dev = 0;
  for (int m = 0; m < 3; ++m) mean += (run[m] - ref[m]) / 3;
  for (int m = 0; m < 3; ++m) dev += std::pow(run[m] - ref[m] - mean, 2);
  const double se = std::sqrt(dev / 2 / 3);
  CHECK(s["reference"] == "ensemble");
  CHECK(s["ensemble"]["members"] == 3);
  CHECK(s["reference_value"].get<double>() == Approx((ref[0] + ref[1] + ref[2]) / 3).epsilon(1e-12));
  const auto& entry = s["integrators"][0];
  const auto& bias = entry["statistics"][0]["bias"];
  CHECK(entry["error"][0].get<double>() == Approx(std::abs(mean)).epsilon(1e-9));
  CHECK(bias["standard_error"].get<double>() == Approx(se).epsilon(1e-9));
  CHECK(bias["test"] == "paired t");
  // The 95 % interval of 2 degrees of freedom: the mean +- 4.303 standard errors.
  CHECK(bias["interval"][1].get<double>() - mean == Approx(4.302653 * se).epsilon(1e-5));
  CHECK(ref[0] != ref[1]);  // the members differ
  // A field cannot be averaged over different fills; a scene with nothing random has no ensemble.
  o.quantity = "temperature";
  CHECK_THROWS_WITH(run_work_precision(o), Catch::Contains("is a field"));
  o.scene = testing::case_path("t1_free_fall.yaml");
  o.sets = {};
  o.quantity = "velocity";
  CHECK_THROWS_WITH(run_work_precision(o), Catch::Contains("declares nothing random"));
}

TEST_CASE("on a frozen thermal scene the studies compare temperatures and the conduction limit by default",
          "[study]") {
  // Before, order and wp defaulted to positions (which never move there) and failed, and sweep
  // compared its boundary with the contacts' limit (2.3e-6 s on F1 against 2.2e-4 s).
  OrderOptions o;
  o.scene = testing::case_path("t4_two_particle_conduction.yaml");
  o.integrators = {"erk2"};
  o.dt = 0.02;
  o.levels = 3;
  o.quiet = true;
  const auto order = run_order_study(o);
  CHECK(order["quantity"] == "temperature");
  CHECK(fitted(order) == Approx(2).margin(0.3));
  SweepOptions s;
  s.scene = o.scene;
  s.integrator = "erk4";
  s.dt_min = 0.01;
  s.dt_max = 0.5;
  s.points = 4;
  s.quiet = true;
  const auto sweep = run_sweep_study(s);
  // RK4's real stability interval is 2.785 against forward Euler's 2: the limit that binds is the
  // explicit (Euler) conduction limit times 1.39, and the boundary found lies there.
  CHECK(sweep["estimate"]["binding_limit"].get<double>() ==
        Approx(2.785 / 2 * sweep["estimate"]["thermal_dt_limit"].get<double>()).epsilon(1e-3));
  CHECK(sweep["largest_stable_dt"].get<double>() ==
        Approx(sweep["estimate"]["binding_limit"].get<double>()).epsilon(0.1));
}

TEST_CASE("an order fit below nominal whose halvings still rise to it is called pre-asymptotic, not reduced",
          "[study]") {
  // The README's example: erk4 on the harmonic contact from 2e-4 s, per-halving orders 0.27,
  // 3.57, 3.85 (fit 3.71).
  const auto study = run_order_study(harmonic("erk4", 2e-4, 4));
  CHECK(fitted(study) < 3.8);
  CHECK(study["integrators"][0]["verdict"].get<std::string>().rfind("pre-asymptotic", 0) == 0);
}

TEST_CASE("an error at round-off is called the floor whatever its fit: erk5 on the harmonic contact from 3e-6 s",
          "[study]") {
  // Every level's error is 2e-14 to 4e-13 m/s (the velocity at t_end is small, so round-off of the
  // motion dominates): the fit, -0.81, is no order, and the study said "not converging" (and
  // erk6 on the 2/7 impact, at 2e-13, "reduced").
  auto o = harmonic("erk5", 3e-6, 6);
  o.quantity = "velocity";
  const auto entry = run_order_study(o)["integrators"][0];
  INFO(entry.dump());
  CHECK(entry["verdict"].get<std::string>().rfind("not settled", 0) == 0);
  CHECK(entry["verdict"].get<std::string>().find("reached the floor") != std::string::npos);
}

TEST_CASE("friction between discs keeps erk4's order with springs in the state and stick-slip located; a floor is called not settled", "[study]") {
  // Two equal spheres in an oblique impact, sticking throughout (mu 0.9 > (2/7) tan 30 deg), erk4
  // with contact events against a fine reference. With the elongation from the trapezoid between
  // contact frames and the Coulomb cap inside the stages, the per-halving orders wandered 0.68,
  // 1.00, 1.34, 2.17, 6.98 from dt 3e-6 s and the error stopped near 5.9e-9 (issue 25). With the
  // slip paths in the state and stick and slip locked per step they are 4.95 to 5.04 (erk4 meets
  // the harmonic contact at order 5, as on the frictionless pair) down to 7e-13.
  OrderOptions o = pair_case("pair_stick.yaml", "erk4", 3e-6, 6);
  const auto study = run_order_study(o);
  const auto& entry = study["integrators"][0];
  INFO(entry.dump());
  const auto& error = entry["error"];
  for (size_t k = 1; k < error.size(); ++k) {
    const double order = std::log2(error[k - 1].get<double>() / error[k].get<double>());
    CHECK(order > 4.5);
    CHECK(order < 5.5);
  }
  CHECK(error.back().get<double>() < 1e-11);
  // erk5 on the same ladder meets the fine reference's floor (9e-13) at its last level: not
  // settled, and the verdict names the floor instead of asking for more levels.
  o.integrators = {"erk5"};
  const auto floor = run_order_study(o)["integrators"][0];
  INFO(floor.dump());
  CHECK(floor["settled"] == false);
  CHECK(floor["verdict"].get<std::string>().rfind("not settled", 0) == 0);
  CHECK(floor["verdict"].get<std::string>().find("reached the floor") != std::string::npos);
  // Without events velocity Verlet's error stops falling near 8e-6, a million times above the
  // reference's accuracy: no floor (it was called one), but errors scattered by unlocated kinks.
  o.integrators = {"velocity-verlet"};
  o.sets = {"contact_events=false"};
  const auto kinks = run_order_study(o)["integrators"][0];
  INFO(kinks.dump());
  CHECK(kinks["verdict"].get<std::string>().find("far above the floor: the errors scatter") != std::string::npos);
  CHECK(kinks["verdict"].get<std::string>().find("reached the floor") == std::string::npos);
  // erk4 above nominal on a settled ladder is said to be settled, not "pre-asymptotic?".
  CHECK(entry["verdict"].get<std::string>().rfind("above nominal, settled", 0) == 0);
  // A free flight, exact under velocity Verlet: errors of zero give no order, and no verdict.
  const std::filesystem::path dir = testing::fresh_dir("free_flight");
  std::filesystem::create_directories(dir);
  const std::string fly = (dir / "fly.yaml").string();
  std::ofstream(fly) << R"(name: fly
materials:
  steel: {density: 7800, stiffness: 1.0e5, restitution: 0.5}
particles:
  - {material: steel, radius: 0.001, at: [[0.0, 0.0]], velocity: [1.0, 2.0]}
dt: 1.0e-3
t_end: 0.05
)";
  OrderOptions f;
  f.scene = fly;
  f.integrators = {"velocity-verlet"};
  f.reference = "richardson";
  f.quantity = "position";
  f.dt = 1e-3;
  f.levels = 4;
  f.quiet = true;
  const auto flight = run_order_study(f)["integrators"][0];
  INFO(flight.dump());
  CHECK(flight["settled"] == false);
  // A ladder that has settled keeps its verdict (the harmonic pair: 4.00, 4.00).
  const auto harmonic_study = run_order_study(harmonic("erk4", 5e-5, 4));
  CHECK(harmonic_study["integrators"][0]["settled"] == true);
  CHECK(harmonic_study["integrators"][0]["verdict"] == "matches");
  std::filesystem::remove_all(dir);
}

TEST_CASE("a study writes its JSON, CSV and plot into a directory whose path has a space and a quote", "[study]") {
  // The plot script runs without a shell: the path reaches it as it is.
  const std::filesystem::path dir = testing::fresh_dir("study with 'odd' path");
  OrderOptions o = harmonic("velocity-verlet", 1e-4, 2);
  o.out_dir = dir.string();
  run_order_study(o);
  for (const char* file : {"order.json", "order.csv", "order.png"}) CHECK(std::filesystem::exists(dir / file));
  std::filesystem::remove_all(dir);
}

TEST_CASE("a fine reference's accuracy is measured: an error far above it is not called its floor", "[study]") {
  // Sayfy-Aburub on the squeezed disc with events, from 4e-6 s: per halving 3.69 and 3.87 at the
  // finest levels, error 3.6e-9. The floor was assumed at 1000 x --fine-rtol (1e-8 here), so the
  // study said "reached the floor ... a larger --dt would settle it", a coarser ladder that only
  // lowers the halvings; the same ladder with --fine-rtol 1e-13 had identical errors. The
  // reference's own difference from a run at a tenth of its tolerance is far below that.
  const OrderOptions o = pair_case("pair_squeezed_disc.yaml", "erk:SAYFY_ABURUB_6_3_4", 4e-6, 5);
  const auto study = run_order_study(o);
  INFO(study.dump());
  const double accuracy = study["reference_accuracy"].get<double>();
  CHECK(accuracy > 0);
  CHECK(accuracy < 1e-10);
  const auto& entry = study["integrators"][0];
  CHECK(entry["error"].back().get<double>() > 1e3 * accuracy);
  CHECK(entry["verdict"].get<std::string>().find("reached the floor") == std::string::npos);
}

TEST_CASE("one halving is no verdict: two levels are not settled, whatever their order", "[study]") {
  // Two levels of erk2 on the sliding pair gave "matches" from one halving whose next was 3.23,
  // on a ladder that never settled; here erk4 on the harmonic contact, whose single halving is
  // 3.85, close to nominal and still no evidence.
  const auto study = run_order_study(harmonic("erk4", 5e-5, 2));
  const auto& entry = study["integrators"][0];
  INFO(entry.dump());
  CHECK(entry["settled"] == false);
  CHECK(entry["verdict"].get<std::string>().rfind("not settled (one halving", 0) == 0);
}

TEST_CASE("a coarse level beyond the stability limit is left out and named; the ladder is read from the rest",
          "[study]") {
  // erk4 on the sticking pair from 4e-5 s: that level blows up (the contact lasts about 4e-5 s),
  // and used to fail the whole ladder.
  const OrderOptions o = pair_case("pair_stick.yaml", "erk4", 4e-5, 4);
  const auto entry = run_order_study(o)["integrators"][0];
  INFO(entry.dump());
  CHECK(!entry.contains("failure"));
  REQUIRE(entry.contains("left_out_unstable"));
  CHECK(entry["left_out_unstable"]["dt"][0].get<double>() == Approx(4e-5));
  CHECK(entry["left_out_unstable"]["failure"][0].get<std::string>().find("unstable") != std::string::npos);
  CHECK(entry["error"].size() == 3u);
}

TEST_CASE("a ladder left with one halving after its unstable levels is not judged on it", "[study]") {
  // erk4 on the harmonic contact from 1.25e-3 s, three levels: the first blows up, the other two
  // give one halving of 0.25 (the second level sits just under erk4's limit), which was called
  // "not converging" with advice to turn contact events on.
  OrderOptions o = harmonic("erk4", 1.25e-3, 3);
  o.quantity = "velocity";
  const auto entry = run_order_study(o)["integrators"][0];
  INFO(entry.dump());
  CHECK(entry["left_out_unstable"]["dt"].size() == 1u);
  CHECK(entry["verdict"].get<std::string>().rfind("not settled (one halving", 0) == 0);
}

TEST_CASE("a study measures a report's quantity as a run of the scene does, its frames kept for the observers",
          "[study]") {
  // Studies ran with one frame at the end, and the observers sample at the frames: a dynamic angle
  // of repose (the mean tilt over the run's second half), a discharge rate or an effective
  // friction over a window came from two samples, or were not measured at all.
  const std::string scene = testing::case_path("t6_drum.yaml");
  const std::vector<std::string> sets = {"particles.0.fill.count=40", "output_interval=0.01"};
  std::vector<StudyRun> runs = {StudyRun("velocity-verlet", 2e-5)};
  run_study(scene, sets, 0.1, "dynamic_angle_of_repose_deg", runs, 1);
  REQUIRE(runs[0].failure.empty());
  const Scene direct = load_scene(scene, {"particles.0.fill.count=40", "output_interval=0.01", "t_end=0.1", "dt=2e-5"});
  const double expected = run_scene(direct, {"", true})["dynamic_angle_of_repose_deg"].get<double>();
  CHECK(runs[0].value.front() == expected);
}

TEST_CASE("every run's own figures can be studied: a wall's mean torque, power and force by its name, and the mean contacts",
          "[study]") {
  // The mill's torque and power draw were in summary.json only, out of the studies' reach.
  const std::string scene = testing::case_path("t6_drum.yaml");
  const std::vector<std::string> sets = {"particles.0.fill.count=40", "output_interval=0.01"};
  const Scene base = load_scene(scene, sets);
  for (const char* q : {"walls.drum.mean_torque", "walls.drum.mean_power", "mean_contacts"})
    CHECK(shape_of(base, q) == QuantityShape::number);
  CHECK(shape_of(base, "walls.drum.mean_force") == QuantityShape::list);
  CHECK_THROWS_WITH(check_quantity(base, "walls.drun.mean_torque"), Catch::Contains("'walls.drum.mean_torque'"));
  const Scene direct = load_scene(scene, {"particles.0.fill.count=40", "output_interval=0.01", "t_end=0.05", "dt=2e-5"});
  const nlohmann::json summary = run_scene(direct, {"", true});
  for (const char* q : {"walls.drum.mean_torque", "walls.drum.mean_force", "mean_contacts"}) {
    INFO(q);
    std::vector<StudyRun> runs = {StudyRun("velocity-verlet", 2e-5)};
    run_study(scene, sets, 0.05, q, runs, 1);
    REQUIRE(runs[0].failure.empty());
    const std::string key = std::string(q).substr(std::string(q).rfind('.') + 1);
    const nlohmann::json expected = key == "mean_contacts" ? summary["mean_contacts"] : summary["walls"][0][key];
    if (expected.is_array())
      CHECK(runs[0].value == expected.get<std::vector<double>>());
    else
      CHECK(runs[0].value == std::vector<double>{expected.get<double>()});
  }
}
