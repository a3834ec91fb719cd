// The stability limit kiln prints is the chosen integrator's, on the modes the scene has
// (src/run/stability.h, integrators/stability_region.h): each method's region from its own
// definition, each scene's modes from its linearised contacts, and what `kiln sweep` measures
// beside it. And no check fires on a healthy run (src/run/stability_guard.h).
#include <catch2/catch.hpp>

#include <cmath>
#include <complex>
#include <fstream>
#include <sstream>

#include "integrators/stability_region.h"
#include "src/base/error.h"
#include "src/base/symmetric_eigen.h"
#include "src/dem/contact_coefficients.h"
#include "src/run/simulation.h"
#include "src/run/stability.h"
#include "src/scene/overrides.h"
#include "src/scene/scene_yaml.h"
#include "src/studies/study_sweep.h"
#include "tests/support.h"

using namespace kiln;

namespace {

// The handed case rolling_incline_rest: a copper disc at rest on a 2 degree slope with friction 0.5
// and constant rolling friction 0.05, a linear contact of stiffness 6000 N/m, e = 0.5.
const std::string slope_disc = R"(name: slope_disc
mass_model: sphere
gravity: [0.342364, -9.804024]
materials:
  copper: {density: 8900, stiffness: 6000, restitution: 0.5, friction: 0.5, rolling_friction: 0.05}
  plate: {stiffness: 6000, restitution: 0.5, friction: 0.5, rolling_friction: 0.05}
particles:
  - {material: copper, radius: 0.002, at: [[0.0, 0.0019995]]}
walls:
  - {name: floor, material: plate, segment: [[-0.05, 0.0], [0.1, 0.0]]}
allow_overlap: true
integrator: velocity-verlet
dt: 1.0e-6
t_end: 0.3
output_interval: 1.0e-3
)";

// One disc falling with nothing to meet (a field report's scene).
const std::string lone_fall = R"(name: lone_fall
materials:
  steel: {density: 7800, stiffness: 1.0e5, restitution: 0.5, friction: 0.3}
particles:
  - {material: steel, radius: 0.01, at: [[0.0, 0.0]]}
integrator: velocity-verlet
dt: 1.0e-3
t_end: 1.0
output_interval: 0.01
)";

std::string written(const std::string& text, const std::string& name) {
  const std::filesystem::path dir = testing::fresh_dir("stability_limit");
  std::filesystem::create_directories(dir);
  const std::string path = (dir / name).string();
  std::ofstream(path) << text;
  return path;
}

StabilityEstimate slope_estimate(const std::string& integrator, const std::vector<std::string>& sets = {}) {
  return estimate_stability(parse_scene(slope_disc, "slope_disc.yaml", sets), integrator);
}

}  // namespace

TEST_CASE("a table's stability interval follows from its Butcher coefficients: Heun 0.053 and 2, RK3 sqrt 3 and 2.5127",
          "[stability]") {
  // Any s-stage method of order s (s <= 4) has R(z) = sum z^k / k!: Heun-Euler's 1 + z + z^2/2 never
  // reaches the imaginary axis (|R(iy)|^2 = 1 + y^4/4) and meets -2 on the real one; Bogacki and
  // Shampine's third-order solution (its fourth stage has b = 0) is RK3's, sqrt 3 and 2.5127
  // (Hairer and Wanner II, table IV.2.1).
  const StabilityIntervals heun = stability_intervals(integrator_info("erk2"));
  // Heun's grows at once; it counts as stable while it grows by at most growth_per_step a step:
  // |R(iy)|^2 = 1 + y^4/4 <= (1 + 1e-6)^2, y = (8e-6)^(1/4) = 0.0532.
  CHECK(heun.imaginary == Approx(std::pow(4 * ((1 + growth_per_step) * (1 + growth_per_step) - 1), 0.25)).epsilon(1e-3));
  CHECK(heun.negative_real == Approx(2).epsilon(1e-6));
  const StabilityIntervals rk3 = stability_intervals(integrator_info("erk3"));
  CHECK(rk3.imaginary == Approx(std::sqrt(3.0)).epsilon(1e-5));
  CHECK(rk3.negative_real == Approx(2.5127453266).epsilon(1e-5));
  // A fourth-order table agrees with exp(z) to z^4 (its fifth stage only adds c z^5).
  const StabilityFunction r(integrator_info("erk4").erk_table);
  const std::complex<double> z(-0.01, 0.02);
  const std::complex<double> taylor = 1.0 + z + z * z / 2.0 + z * z * z / 6.0 + z * z * z * z / 24.0;
  CHECK(std::abs(r(z) - taylor) < 1e-9);
  // The Verlet schemes are the central difference on an undamped spring: stable to omega dt = 2.
  for (const std::string& name : testing::verlet_family()) {
    INFO(name);
    CHECK(stability_intervals(integrator_info(name)).imaginary == Approx(2).epsilon(1e-6));
  }
}

TEST_CASE("a stiff undamped spring is stable to exactly 2/omega under velocity Verlet", "[stability]") {
  // k = 2.0e7 1/s^2, a disc's contact with the floor. The step map's columns mix 1e-12 and 2e7;
  // unbalanced, its eigenvalues came out 1e-5 off the unit circle and the limit printed was
  // 2.43e-6 s instead of 4.46e-4 s (T1 refused at its own dt).
  Eigen::MatrixXd k(1, 1), c = Eigen::MatrixXd::Zero(1, 1);
  k << 2.01179e7;
  for (const std::string& name : testing::verlet_family()) {
    INFO(name);
    CHECK(mechanical_step_limit(integrator_info(name), k, c).dt == Approx(2 / std::sqrt(k(0, 0))).epsilon(1e-6));
  }
}

TEST_CASE("the slope disc's limit is each integrator's own on its tangential-rotational and normal modes",
          "[stability]") {
  // The figures kiln sweep measures (scripts/stability_table.sh): erk4 unstable from 5.832e-4 s,
  // erk2 from 3.205e-4 s, erk3 from 5.336e-4 s. Before, every integrator was told 3.60e-4 s, the
  // central-difference bound of the normal spring.
  const StabilityEstimate vv = slope_estimate("velocity-verlet");
  CHECK(vv.dt_limit == Approx(2.5534e-4).epsilon(1e-3));
  CHECK(vv.limit.mode == "tangential-rotational");
  CHECK(vv.limit.where == "particle 0 on wall floor");
  const StabilityEstimate rk4 = slope_estimate("erk4");
  CHECK(rk4.dt_limit == Approx(5.834e-4).epsilon(1e-3));
  CHECK(rk4.limit.mode == "tangential-rotational");
  CHECK(slope_estimate("erk2").dt_limit == Approx(3.205e-4).epsilon(1e-3));
  CHECK(slope_estimate("erk2").limit.mode == "normal");
  CHECK(slope_estimate("erk3").dt_limit == Approx(5.336e-4).epsilon(1e-3));
  // An IMEX pair's explicit table takes the contacts.
  CHECK(slope_estimate("imex4").dt_limit == Approx(8.223e-4).epsilon(1e-3));
  // Without a tangential dashpot the tangential-rotational mode no longer binds velocity Verlet.
  const StabilityEstimate undamped =
      slope_estimate("velocity-verlet", {"contacts=[{between: [copper, plate], tangential_damping_ratio: 0}]"});
  CHECK(undamped.dt_limit > 1.3 * vv.dt_limit);
}

TEST_CASE("velocity Verlet just beyond the slope disc's tangential limit chatters at the caps, powered by creep, "
          "with its ledger balanced and friction dissipating",
          "[stability][checks]") {
  // At 2.6e-4 s (1.02 of the limit) the tangential-rotational mode grows until the Coulomb and
  // rolling caps hold it: the disc chatters and creeps down the slope, the energy it gains from
  // its descent. Before the cap stopped lengthening springs (contact/capped_spring.h), each slip
  // stored energy nothing had put in and the run was stopped because friction's ledger went
  // negative: the check caught the law's artifact, not the mode. `kiln run` refuses this dt
  // without --force (the next test: "sticking contacts creep or chatter").
  auto late_spin = [](const std::string& dt) {
    testing::Run run(slope_disc, {"dt=" + dt});
    run.integrator->set_stop_time(0.3);
    const EnergyLedger initial = run.system->energy(0, run.y.data());
    double spin = 0;
    while (run.t() < 0.3 * (1 - 1e-12)) {
      run.step();
      if (run.t() > 0.15) spin = std::max(spin, std::abs(run.omega(0)));
    }
    const EnergyLedger e = run.system->energy(run.t(), run.y.data());
    CHECK(e.dissipated_friction >= 0);
    CHECK(std::abs(balance_error(initial, e)) < 1e-3 * exchanged(initial, e));
    return spin;
  };
  // Below the limit the disc rests (5e-18 rad/s), beyond it it chatters (1.7e-2 rad/s measured).
  CHECK(late_spin("2.5e-4") < 1e-12);
  CHECK(late_spin("2.6e-4") > 1e-3);
  const auto healthy = run_scene(parse_scene(slope_disc, "slope_disc.yaml", {"dt=2.5e-4"}), {"", true});
  CHECK(healthy["t_end"].get<double>() == Approx(0.3));
}

TEST_CASE("between the slope disc's tangential-rotational limit and the normal modes' blow-up limit velocity Verlet "
          "creeps down the slope; beyond the second it blows up",
          "[stability][checks]") {
  // The tangential-rotational mode grows only until the rolling and Coulomb caps hold it, so the
  // run goes on, balanced and wrong: at 3e-4 s (1.17 of the limit) the disc slides 77 um down the
  // slope in 0.3 s (0.74 um, its settling into the floor, at any step below the limit). The
  // sweep's boundary, 3.61e-4 s (a 1.41 miss before), is the blow-up limit of the normal mode,
  // 2/omega_n shortened by the dashpot.
  const StabilityEstimate vv = slope_estimate("velocity-verlet");
  CHECK(vv.limit.mode == "tangential-rotational");
  CHECK(vv.limit.blow_up_dt == Approx(3.6006e-4).epsilon(1e-3));
  CHECK(slope_estimate("erk2").limit.blow_up_dt == slope_estimate("erk2").dt_limit);  // normal binds: one limit
  auto displacement = [](const std::string& dt) {
    FinalFields f;
    run_scene(parse_scene(slope_disc, "slope_disc.yaml", {"dt=" + dt}), {"", true, &f});
    return f.position[0];
  };
  CHECK(std::abs(displacement("2.5e-4")) < 1e-6);
  CHECK(std::abs(displacement("3e-4")) > 1e-5);
  CHECK_THROWS_AS(run_scene(parse_scene(slope_disc, "slope_disc.yaml", {"dt=3.7e-4"}), {"", true}), InstabilityError);
  // kiln check says both.
  const Scene at = parse_scene(slope_disc, "slope_disc.yaml", {"dt=3e-4"});
  const DtVerdict verdict = judge_dt(estimate_stability(at), at.dt, at);
  CHECK(verdict.unstable);
  REQUIRE_FALSE(verdict.warnings.empty());
  CHECK(verdict.warnings.front().find("sticking contacts creep or chatter") != std::string::npos);
  CHECK(verdict.warnings.front().find("blows up beyond 0.00036") != std::string::npos);
}

TEST_CASE("a disc on a fixed disc is limited by its own mass on the spring, not by a free pair that cannot form",
          "[stability]") {
  // A free copper disc resting on a fixed one, no dashpot: velocity Verlet's limit is 2 / omega,
  // omega = sqrt(k / m) (4485 rad/s; forced runs pass at 4.3e-4 s and fail at 4.6e-4 s). The
  // lone-pair probe took both discs free, omega sqrt 2 higher: 3.15e-4 s, refusing valid steps.
  const Scene scene = parse_scene(R"(name: on_fixed
mass_model: sphere
gravity: [0, -9.81]
materials:
  copper: {density: 8900, stiffness: 6000, restitution: 1.0}
particles:
  - {material: copper, radius: 0.002, at: [[0.0, 0.0]], fixed: true}
  - {material: copper, radius: 0.002, at: [[0.0, 0.003999269]]}
allow_overlap: true
integrator: velocity-verlet
dt: 1.0e-5
t_end: 0.01
)", "on_fixed.yaml");
  const StabilityEstimate est = estimate_stability(scene);
  const double m = 8900 * 4.0 / 3.0 * M_PI * std::pow(0.002, 3);
  const double k = contact_coefficients(scene, 0, 0).normal_stiffness(0.001);
  INFO("limit " << est.dt_limit << " s on " << est.limit.state);
  CHECK(est.dt_limit == Approx(2 / std::sqrt(k / m)).epsilon(1e-3));
}

TEST_CASE("kiln sweep on the slope disc under velocity Verlet: every run between the tangential-rotational and the "
          "blow-up limit drifts, the first failure is at the blow-up limit",
          "[stability][study]") {
  // Ten steps from 2.4e-4 to 3.7e-4 s. The runs beyond the tangential-rotational limit (2.55e-4 s)
  // go to the end with the disc creeping: the sweep's position column drifts from 7e-8 m
  // (2.64e-4 s) to 6e-4 m; 3.7e-4 s blows up, so the boundary is at the blow-up limit. Before the
  // cap stopped lengthening springs, 2.64e-4 s was stopped by the dissipation check (the cap's
  // stored energy, not the mode), and the sweep reported a window of stable runs above it.
  SweepOptions o;
  o.scene = written(slope_disc, "slope_disc.yaml");
  o.integrator = "velocity-verlet";
  o.dt_min = 2.4e-4;
  o.dt_max = 3.7e-4;
  o.points = 10;
  o.t_end = 0.3;
  o.quiet = true;
  const auto s = run_sweep_study(o);
  REQUIRE(s["largest_stable_dt"].is_number());
  REQUIRE(s["smallest_unstable_dt"].is_number());
  CHECK(s["largest_stable_dt"].get<double>() < s["smallest_unstable_dt"].get<double>());
  const double blow_up = s["estimate"]["blow_up_dt_limit"].get<double>();
  CHECK(blow_up == Approx(3.6006e-4).epsilon(1e-3));
  CHECK(s["smallest_unstable_dt"].get<double>() / blow_up == Approx(1).margin(0.03));
  CHECK(s["stable_above_boundary"].is_null());
  std::filesystem::remove_all(std::filesystem::path(o.scene).parent_path());
}

TEST_CASE("a thermal scene's conduction limit is judged on its network by check and sweep alike", "[stability][study]") {
  // Two touching 20 um copper discs: erk4's explicit limit on their network is 6.57e-5 s and the
  // sweep measures 6.65e-5 s; the sweep predicted 1.03e-5 s from the dense-packing guess, and
  // check's JSON named the contacts as binding (dt 0.875 of their limit) while refusing the dt.
  const std::string hot = R"(name: hotpair
mass_model: sphere
gravity: [0, 0]
conduction_model: lens
materials:
  copper: {density: 8900, stiffness: 0.2, restitution: 0.5, specific_heat: 172, conductivity: 385}
particles:
  - {material: copper, radius: 2.0e-5, temperature: 100, at: [[0.0, 0.0]]}
  - {material: copper, radius: 2.0e-5, temperature: 0, at: [[3.99e-5, 0.0]]}
allow_overlap: true
integrator: erk4
dt: 1.0e-6
t_end: 5.0e-4
)";
  const Scene scene = parse_scene(hot, "hotpair.yaml");
  const StabilityEstimate est = estimate_stability(scene);
  REQUIRE(est.conduction_dt_limit < est.dt_limit);
  SweepOptions o;
  o.scene = written(hot, "hotpair.yaml");
  o.integrator = "erk4";
  o.dt_min = 0.5 * est.conduction_dt_limit;
  o.dt_max = 2 * est.conduction_dt_limit;
  o.points = 4;
  o.quiet = true;
  const auto s = run_sweep_study(o);
  CHECK(s["estimate"]["binding_limit"].get<double>() == Approx(est.conduction_dt_limit));
  REQUIRE(s["measured_over_predicted"].is_number());
  CHECK(s["measured_over_predicted"].get<double>() == Approx(1).margin(0.05));
  std::filesystem::remove_all(std::filesystem::path(o.scene).parent_path());
}

namespace {

// Twelve frictionless discs 0.1 mm apart above a floor: no contact at t = 0, a column on the floor
// once they land. A fixed-free chain of N equal springs k and masses m has omega_max =
// 2 sqrt(k/m) sin((2N - 1) pi / (2 (2N + 1))), 1.4031 times a lone pair's sqrt(2 k/m) for N = 12.
std::string column() {
  std::string at;
  for (int i = 0; i < 12; ++i) at += (i ? ", [0.0, " : "[0.0, ") + std::to_string(0.0012 + 0.0021 * i) + "]";
  return "name: column\ngravity: [0, -9.81]\nmaterials:\n"
         "  glass: {density: 2500, stiffness: 1000, restitution: 0.5, friction: 0}\n"
         "particles:\n  - {material: glass, radius: 0.001, at: [" + at + "]}\n"
         "walls:\n  - {name: floor, material: glass, segment: [[-0.01, 0.0], [0.01, 0.0]]}\n"
         "integrator: velocity-verlet\ndt: 1.0e-5\nt_end: 0.5\n";
}

}  // namespace

TEST_CASE("the limit on a settled state is its network's: a landed column of 12 discs binds 1.40 times below its "
          "lone pair, and the guard recommends from the contacts it has when a check fires",
          "[stability][checks]") {
  const Scene scene = parse_scene(column(), "column.yaml");
  const StabilityEstimate start = estimate_stability(scene);
  CHECK(start.limit.state == "a lone glass-glass contact");
  // Named by what it probes: the probe's own "particles 0 and 1" named two steel balls in the C2 mill.
  CHECK(start.limit.where == "the smallest free glass and glass particles");
  RunOptions options{"", true};
  options.limit_at_end = true;
  const auto s = run_scene(scene, options);
  REQUIRE(s["stability"].contains("at_end"));
  const MechanicalLimit settled = limit_of_json(s["stability"]["at_end"]);
  CHECK(settled.contacts == 12);
  CHECK(settled.omega_max / start.limit.omega_max ==
        Approx(2 * std::sin(23 * M_PI / 50) / std::sqrt(2.0)).epsilon(1e-4));
  CHECK(settled.dt < 0.85 * start.dt_limit);
  const StabilityEstimate joined = with_state(start, settled);
  CHECK(joined.dt_limit == settled.dt);
  CHECK(joined.recommended_dt <= joined.dt_limit);
  // At 0.9 of the start's limit the column blows up as it lands (stopped at t = 0.015 s, its
  // contacts then bind at 8.4e-5 s); the message quoted the lone pair's limit, above the dt that
  // failed. (At 0.8 the growth is slower: the energy check fires at 0.14 s, when the column has
  // flown apart, and the message falls back to the start's contacts.)
  try {
    run_scene(parse_scene(column(), "column.yaml", {"dt=1.0521e-4"}), {"", true});
    FAIL("the column ran to the end");
  } catch (const InstabilityError& e) {
    const std::string m = e.what();
    INFO(m);
    const size_t at = m.find("velocity-verlet's limit ");
    REQUIRE(at != std::string::npos);
    CHECK(std::stod(m.substr(at + 24)) < 1.0521e-4);
    CHECK(m.find("s on the contacts at t = ", at) != std::string::npos);
  }
}

TEST_CASE("the guard's recommended dt says when it is the stability limit rather than contact duration / 50",
          "[stability][checks]") {
  // erk2 on the undamped harmonic pair: limit 1.19e-5 s, below t_c / 50 = 1.40e-5 s. The message
  // labelled the limit "contact duration 0.0007 s / 50".
  try {
    run_scene(load_scene(testing::case_path("harmonic_contact_pair.yaml"), {"integrator=erk2", "dt=5e-4"}), {"", true});
    FAIL("erk2 at 40 times its limit ran to the end");
  } catch (const InstabilityError& e) {
    const std::string m = e.what();
    CHECK(m.find("recommends dt <= 1.18") != std::string::npos);
    CHECK(m.find("(the stability limit; contact duration") != std::string::npos);
  }
}

TEST_CASE("an adaptive run's first step beyond the limit is warned of, not refused", "[stability]") {
  // erk5 with rtol 1e-6 from dt = 1e-3 s on T1 (limit 2.2e-4 s): the controller takes 691 steps and
  // keeps the energy to 1.7e-9 J; it was refused as "the run will blow up".
  const Scene scene = load_scene(testing::case_path("t1_free_fall.yaml"), {"integrator=erk5", "rtol=1e-6", "dt=1e-3"});
  const DtVerdict verdict = judge_dt(estimate_stability(scene), scene.dt, scene);
  CHECK_FALSE(verdict.unstable);
  REQUIRE_FALSE(verdict.warnings.empty());
  CHECK(verdict.warnings.front().find("the step controller will shorten it") != std::string::npos);
}

TEST_CASE("a disc falling with nothing to meet has no step limit and runs to the end at any step", "[stability][checks]") {
  // A field report: refused at 1e-3 s "can pass through a wall or another disc", and at 9.8e-4 s
  // stopped as unstable at t = 0.41 s because it keeps speeding up.
  const Scene scene = parse_scene(lone_fall, "lone_fall.yaml");
  const StabilityEstimate est = estimate_stability(scene);
  CHECK(std::isinf(est.dt_limit));
  const DtVerdict verdict = judge_dt(est, scene.dt, scene);
  CHECK_FALSE(verdict.unstable);
  CHECK(verdict.warnings.empty());
  for (const char* integrator : {"velocity-verlet", "erk4"}) {
    INFO(integrator);
    const auto s = run_scene(parse_scene(lone_fall, "lone_fall.yaml", {std::string("integrator=") + integrator}),
                             {"", true});
    CHECK(s["t_end"].get<double>() == Approx(1.0));
    CHECK_FALSE(s["stopped_early"].get<bool>());
  }
}

TEST_CASE("erk4 on T1 moved to y = 1e5 m keeps its energy within the round-off allowance", "[stability][checks]") {
  // Positions near 1e5 m round to 1.5e-11 m: the allowance counts the integrator's five stages,
  // each rounding the position (it counted one and missed by 0.8 %).
  std::string text = testing::case_text("t1_free_fall_damped.yaml");
  text = testing::replaced(text, "at: [[0.025, 0.03]]", "at: [[0.025, 100000.03]]");
  text = testing::replaced(text, "box: [0, 0, 0.05, 0.0375]", "box: [0, 100000, 0.05, 100000.0375]");
  const auto s = run_scene(parse_scene(text, "t1_far.yaml", {"integrator=erk4", "dt=1e-5"}), {"", true});
  CHECK(s["t_end"].get<double>() == Approx(0.3));
  CHECK(s["checks"]["energy_balance"]["worst_relative_error"].get<double>() < 0.25);
}

TEST_CASE("kiln sweep measures the slope disc's and F1's boundaries within 10 % of the printed limits",
          "[stability][study][long]") {
  struct Row {
    std::string scene, integrator;
    double t_end;
  };
  const std::string slope = written(slope_disc, "slope_disc.yaml");
  for (const Row& row : {Row{slope, "erk4", 0.3}, Row{slope, "erk2", 0.3}, Row{slope, "imex4", 0.3},
                         Row{testing::case_path("t1_free_fall_damped.yaml"), "erk4", 0.3},
                         Row{testing::case_path("f1_chain_slab.yaml"), "erk4", 0},
                         Row{testing::case_path("f1_chain_slab.yaml"), "velocity-verlet", 0}}) {
    INFO(row.scene << " under " << row.integrator);
    SweepOptions o;
    o.scene = row.scene;
    o.integrator = row.integrator;
    o.sets = {"integrator=" + row.integrator};
    const Scene scene = load_scene(row.scene, o.sets);
    const StabilityEstimate est = estimate_stability(scene);
    const double limit = scene.frozen ? est.conduction_dt_limit : est.dt_limit;
    o.dt_min = 0.5 * limit;
    o.dt_max = 2 * limit;
    o.points = 6;
    o.t_end = row.t_end;
    o.quiet = true;
    const auto s = run_sweep_study(o);
    REQUIRE(s["largest_stable_dt"].is_number());
    REQUIRE(s["smallest_unstable_dt"].is_number());
    const double measured =
        std::sqrt(s["largest_stable_dt"].get<double>() * s["smallest_unstable_dt"].get<double>());
    CHECK(measured / limit > 0.9);
    CHECK(measured / limit < 1.1);
  }
  std::filesystem::remove_all(std::filesystem::path(slope).parent_path());
}

TEST_CASE("a periodic ring of 200 touching discs, too many coordinates to decompose whole, binds at its chain's "
          "stiffest mode, omega = 2 sqrt(k/m)",
          "[stability]") {
  // The mode in which neighbours move against each other: the periodic chain Laplacian's largest
  // eigenvalue, 4 k/m. Found by Lanczos from the springs' rows, no operator stored.
  std::ostringstream text;
  text << "name: ring\nmaterials:\n  glass: {density: 2500, stiffness: 1.0e4, restitution: 1.0}\n"
       << "gravity: [0, 0]\nparticles:\n  - material: glass\n    radius: 0.001\n    at: [";
  const int discs = 200;
  const double spacing = 0.00199;
  for (int i = 0; i < discs; ++i) text << (i ? ", " : "") << "[" << (i + 0.5) * spacing << ", 0.0]";
  text << "]\nperiodic: {x: [0, " << discs * spacing << "]}\nallow_overlap: true\nintegrator: velocity-verlet\n"
       << "dt: 1.0e-6\nt_end: 1.0e-3\n";
  const Scene scene = parse_scene(text.str(), "ring.yaml");
  DemSystem system(scene);
  const std::vector<double> y = system.initial_state();
  system.prepare(0, y.data(), 0);
  const MechanicalLimit l = mechanical_limit(system, 0, y.data(), "velocity-verlet", "the ring");
  REQUIRE(l.coordinates > dense_limit);
  CHECK(l.contacts == discs);
  const double k = system.contact_springs(0, y.data()).front().kn, m = system.mass(0);
  CHECK(l.omega_max == Approx(2 * std::sqrt(k / m)).epsilon(1e-7));  // the Lanczos tolerance
  CHECK(l.dt == Approx(1 / std::sqrt(k / m)).epsilon(1e-6));
  CHECK(l.mode == "normal");
}

TEST_CASE("ARK437L2SA's limit holds on a contact that never opens, and a run stopped below it is told that its "
          "contacts open and close within a step",
          "[stability][checks]") {
  // The harmonic pair: a copper disc on a floor, oscillating between 2.4e-7 and 7.3e-7 m of overlap
  // about its rest overlap of 4.9e-7 m. kiln sweep measured 0.83 of ARK437L2SA's printed limit
  // (1.047e-3 s, its imaginary interval 4.695 / omega): at 0.86 of it the run gains energy. Not a
  // mode: a contact lasts 0.78 steps there, and the table's stages reach positions where the disc
  // has left the floor, so the force switches off inside the step. The message blamed "a state
  // already blown apart". Started 1e-9 m from its rest overlap, 500 times deeper in the contact
  // than its amplitude, the same disc runs at 0.99 of the limit and is stopped at 1.02.
  const std::string integrator = "integrator=erk:ARK437L2SA_ERK_7_3_4";
  const Scene shallow = load_scene(testing::case_path("harmonic_contact_pair.yaml"), {integrator});
  const StabilityEstimate estimate = estimate_stability(shallow);
  REQUIRE(estimate.dt_limit == Approx(1.047e-3).epsilon(1e-3));
  try {
    run_scene(load_scene(testing::case_path("harmonic_contact_pair.yaml"), {integrator, "dt=9e-4", "t_end=0.1"}),
              {"", true});
    FAIL("the shallow pair at 0.86 of the limit ran to the end");
  } catch (const InstabilityError& e) {
    const std::string m = e.what();
    CHECK(m.find("energy blow-up") != std::string::npos);
    CHECK(m.find("Or no linear mode grew: a contact lasts only 0.778 steps here") != std::string::npos);
  }
  // Another check at the same step (the overlap's, set tight: above the start's 0.000366 of the
  // radius, which a scene may not exceed, below what the growing oscillation reaches) is not
  // blamed on the energy that contact switching makes.
  try {
    run_scene(load_scene(testing::case_path("harmonic_contact_pair.yaml"),
                         {integrator, "dt=9e-4", "t_end=0.1", "checks.max_overlap_fraction=0.0004"}),
              {"", true});
    FAIL("the shallow pair with a tight overlap check ran to the end");
  } catch (const InstabilityError& e) {
    const std::string m = e.what();
    CHECK(m.find("energy blow-up") == std::string::npos);
    CHECK(m.find("no linear mode grew") == std::string::npos);
  }
  const double mass = 8900 * 4.0 / 3.0 * M_PI * std::pow(0.002, 3), rest_overlap = mass * 9.81 / 6000;
  std::ostringstream deep;
  deep.precision(17);
  deep << "name: deep_pair\nmass_model: sphere\ngravity: [0, -9.81]\n"
       << "materials:\n  copper: {density: 8900, stiffness: 6000, restitution: 1.0}\n"
       << "particles:\n  - {material: copper, radius: 0.002, at: [[0.0, " << 0.002 - rest_overlap - 1e-9 << "]]}\n"
       << "walls:\n  - {name: floor, material: copper, segment: [[-0.01, 0], [0.01, 0]]}\n"
       << "allow_overlap: true\nintegrator: erk:ARK437L2SA_ERK_7_3_4\ndt: 1.0e-5\nt_end: 1\noutput_interval: 0.01\n";
  const std::string path = written(deep.str(), "deep_pair.yaml");
  const StabilityEstimate deep_estimate = estimate_stability(load_scene(path));
  CHECK(deep_estimate.dt_limit == Approx(estimate.dt_limit).epsilon(1e-9));
  // 0.99: 960 steps; the mode's amplitude stays 1e-9 m (|R| < 1), far inside the contact.
  const nlohmann::json below = run_scene(load_scene(path, {assignment("dt", 0.99 * estimate.dt_limit)}), {"", true});
  CHECK(below["t_end"].get<double>() == Approx(1.0));
  CHECK_THROWS_WITH(run_scene(load_scene(path, {assignment("dt", 1.02 * estimate.dt_limit)}), {"", true}),
                    Catch::Contains("energy blow-up"));
}
