// ARKODE integrators on thermal and mechanical cases: IMEX orders, stiffness, adaptivity,
// aliases, and contact history across the stages of a step.
#include <catch2/catch.hpp>
#include <cmath>

#include "src/base/error.h"
#include "src/scene/overrides.h"
#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "src/run/stability.h"
#include "tests/support.h"

using namespace kiln;

namespace {

const double t4_capacity = 4.0 / 3.0 * M_PI * 8e-9 * 8900 * 172;
const double t4_h = 2 * 385 * std::sqrt(0.39) * 1e-3;

double t4_error(const std::vector<std::string>& sets) {
  std::vector<std::string> all = {"t_end=0.1"};
  all.insert(all.end(), sets.begin(), sets.end());
  const auto s = run_scene(load_scene(testing::case_path("t4_two_particle_conduction.yaml"), all), {"", true});
  const auto T = s["temperatures"].get<std::vector<double>>();
  return std::abs((T[0] - T[1]) - 100 * std::exp(-2 * t4_h * 0.1 / t4_capacity));
}

}  // namespace

TEST_CASE("every IMEX pair reaches its nominal order on T4's exact exponential", "[arkode]") {
  for (const auto& info : integrator_catalogue()) {
    if (info.scheme != IntegratorScheme::arkode || !info.implicit || !info.integrates_contacts || !info.alias_of.empty()) continue;
    const double h = info.order >= 5 ? 0.02 : 0.01;
    const double e1 = t4_error({"integrator=" + info.name, assignment("dt", h)});
    const double e2 = t4_error({"integrator=" + info.name, assignment("dt", h / 2)});
    const double e3 = t4_error({"integrator=" + info.name, assignment("dt", h / 4)});
    INFO(info.name << ": errors " << e1 << " " << e2 << " " << e3);
    CHECK(testing::order(e2, e3) == Approx(info.order).margin(0.15));
  }
}

TEST_CASE("adaptive runs of T4 meet the tolerance: the true error scales with rtol", "[arkode]") {
  double previous = 0;
  // One output frame, so that frames do not cap the step size.
  for (double rtol : {1e-4, 1e-6, 1e-8}) {
    const double err = t4_error({"integrator=erk5", assignment("rtol", rtol), "dt=1e-3", "output_interval=0.1"});
    INFO("rtol " << rtol << ": error " << err);
    CHECK(err < 100 * rtol * 10);  // within ten times the tolerance of the 100 C difference
    if (previous > 0) CHECK(previous / err > 10);  // two decades of rtol buy more than one of error
    previous = err;
  }
}

TEST_CASE("a stiff conduction network: IMEX runs at the mechanical step, explicit schemes are stopped", "[arkode]") {
  // Fine grains (r = 10 micrometres) of a soft, highly conductive material pressed in a line between
  // two walls (static: every overlap is 2 micrometres, so all forces balance). The explicit
  // conduction limit lies thousands of times below the step the contacts need.
  const char* scene = R"(name: stiff
gravity: [0, 0]
conduction_model: lens
materials:
  powder: {density: 8900, stiffness: 0.1, restitution: 0.5, specific_heat: 172, conductivity: 1.0e6}
particles:
  - material: powder
    radius: 1.0e-5
    temperature: {x_split: 4.0e-5, left: 100, right: 0}
    lattice: {kind: square, origin: [0, 0], spacing: 1.8e-5, rows: 1, columns: 6}
walls:
  - {material: powder, segment: [[-0.8e-5, -2.0e-5], [-0.8e-5, 2.0e-5]]}
  - {material: powder, segment: [[9.8e-5, 2.0e-5], [9.8e-5, -2.0e-5]]}
allow_overlap: true
integrator: imex:ARK324L2SA
dt: 5.0e-7
t_end: 2.0e-5
output_interval: 1.0e-6
report: [temperatures]
)";
  const Scene imex = parse_scene(scene, "stiff.yaml");
  const StabilityEstimate est = estimate_stability(imex);
  INFO("thermal limit " << est.thermal_dt_limit_network << " s, mechanical recommendation " << est.recommended_dt << " s");
  CHECK(est.thermal_dt_limit_network < imex.dt / 1000);
  CHECK(imex.dt < est.recommended_dt);
  const auto s = run_scene(imex, {"", true});
  CHECK(s["temperature_max"].get<double>() <= 100);
  CHECK(s["temperature_min"].get<double>() >= 0);
  CHECK(s["temperature_max"].get<double>() - s["temperature_min"].get<double>() < 1);  // equalised
  CHECK(s["integrator_stats"]["linear_solves"].get<long>() > 0);  // the implicit stages were solved
  for (const char* explicit_scheme : {"erk4", "velocity-verlet"}) {
    const Scene ex = parse_scene(scene, "stiff.yaml", {std::string("integrator=") + explicit_scheme});
    CHECK(judge_dt(estimate_stability(ex), ex.dt, ex).unstable);
    try {
      run_scene(ex, {"", true});
      FAIL(explicit_scheme << " was not stopped");
    } catch (const InstabilityError& e) {
      CHECK(std::string(e.what()).find("unstable run") != std::string::npos);
    }
  }
}

TEST_CASE("a table selected by alias and by name gives the same trajectory, bit for bit", "[arkode]") {
  for (const auto& [alias, name] : std::vector<std::pair<std::string, std::string>>{
           {"erk4", "erk:ZONNEVELD_5_3_4"}, {"erk5", "erk:DORMAND_PRINCE_7_4_5"}}) {
    std::vector<std::vector<double>> states;
    for (const std::string& n : {alias, name}) {
      testing::Run run(testing::case_text("t1_free_fall.yaml"), {"integrator=" + n, "dt=2e-6"});
      for (int k = 0; k < 20000; ++k) run.step();
      states.push_back(run.y);
    }
    CHECK(states[0] == states[1]);
  }
}

TEST_CASE("contact history is the same at every stage: C1 rolls at 2/3 g sin(theta) with Runge-Kutta", "[arkode]") {
  // Every stage of a step sees the elongation committed at the step's start plus v_t times its
  // own offset; the elongation is committed only from an evaluation at the accepted step's end.
  for (const char* integrator : {"erk2", "erk4", "erk5"}) {
    const auto s = run_scene(load_scene(testing::case_path("c1_incline_roll_slide.yaml"),
                                        {std::string("integrator=") + integrator, "dt=2e-6"}),
                             {"", true});
    INFO(integrator);
    CHECK(s["incline_acceleration"].get<double>() == Approx(2.0 / 3.0 * 9.81 * std::sin(20 * M_PI / 180)).epsilon(0.01));
    CHECK(std::abs(s["slip_ratio"].get<double>()) < 0.01);
    CHECK(s["integrator_stats"]["rhs_evals_history"].get<long>() == s["steps"].get<long>());
  }
}

TEST_CASE("evaluating a stage never changes the history another stage sees", "[arkode]") {
  // Mid-roll on the C1 incline the tangential spring is loaded. Stages at different offsets of one
  // step read the committed elongation; none of them writes it, and the elongation a stage sees
  // is a function of its state alone (the committed one plus the contact points' displacement
  // since; erk4 carries the springs in its state: the committed one plus the slip path since), not
  // of how far into the step it is.
  testing::Run run(testing::case_text("c1_incline_roll_slide.yaml"), {"integrator=erk4", "dt=2e-6"});
  for (int k = 0; k < 5000; ++k) run.step();
  DemSystem& sys = *run.system;
  const double t = run.t(), h = 2e-6;
  std::vector<double> y(sys.state_size());
  std::copy(run.y.begin(), run.y.end(), y.begin());
  sys.initial_history(y.data() + run.y.size());
  std::vector<double> a(y.size()), b(y.size()), c(y.size());
  sys.derivative(t + 0.3 * h, y.data(), a.data());
  sys.derivative(t + h, y.data(), b.data());
  sys.derivative(t + 0.3 * h, y.data(), c.data());
  CHECK(a == c);
  CHECK(a == b);
  CHECK(sys.wall_contacts().spring[0] != 0.0);
}

TEST_CASE("rtol with a scheme that cannot adapt is refused with the reason", "[arkode]") {
  try {
    const Scene scene = parse_scene(testing::case_text("t1_free_fall.yaml"), "t1.yaml", {"rtol=1e-6"});
    make_integrator(scene.integrator, scene.control);
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("cannot adapt") != std::string::npos);
  }
}

namespace {

// T1's state at t = 0.1 s, after one bounce, against the exact piecewise solution (free fall, a
// harmonic contact with gravity, free flight): sqrt((omega dy)^2 + dv^2).
double t1_error(const std::string& integrator, double dt, bool events) {
  const double g = 9.81, r = 0.002, k = 6000, m = 4.0 / 3.0 * M_PI * r * r * r * 8900, w = std::sqrt(k / m);
  const double v_in = std::sqrt(2 * g * 0.028), t_on = v_in / g, d_eq = m * g / k;
  const double t_off = t_on + (2 * M_PI - 2 * std::atan2(v_in / w, d_eq)) / w;
  const double T = 0.1, s = T - t_off;
  testing::Run run(testing::case_text("t1_free_fall.yaml"),
                   {"integrator=" + integrator, assignment("dt", dt), events ? "contact_events=true" : "contact_events=false"});
  run.integrator->set_stop_time(T);  // an event shifts the step grid: land on T exactly
  while (run.t() < T - 1e-12) run.step();
  return std::hypot(w * (run.yy(0) - (r + v_in * s - g / 2 * s * s)), run.vy(0) - (v_in - g * s));
}

// Least-squares slope of log(error) against log(dt) over dt = 4e-5 ... 5e-6.
double fitted_order(const std::string& integrator, bool events) {
  double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
  for (double dt : {4e-5, 2e-5, 1e-5, 5e-6}) {
    const double x = std::log(dt), y = std::log(t1_error(integrator, dt, events));
    sx += x;
    sy += y;
    sxx += x * x;
    sxy += x * y;
    n += 1;
  }
  return (n * sxy - sx * sy) / (n * sxx - sx * sx);
}

}  // namespace

TEST_CASE("T1 bounce: with contact events Zonneveld and Dormand-Prince keep order >= 3.8", "[arkode][events]") {
  for (const char* integrator : {"erk4", "erk5"}) {
    const double with = fitted_order(integrator, true), without = fitted_order(integrator, false);
    INFO(integrator << ": measured order " << with << " with contact events, " << without << " without");
    CHECK(with >= 3.8);
    // Integrating straight through the contact's kink the error depends on where the kink falls
    // in a step: erratic and far larger (measured orders per halving 4.2, 1.2, 6.2 for erk4 and
    // -0.5, 4.3, 0.9 for erk5; at dt = 5e-6 s the error is 1800 and 5e5 times that with events).
    CHECK(t1_error(integrator, 5e-6, false) > 100 * t1_error(integrator, 5e-6, true));
  }
}

TEST_CASE("contact events are refused for the Verlet schemes", "[arkode][events]") {
  try {
    const Scene scene = parse_scene(testing::case_text("t1_free_fall.yaml"), "t1.yaml", {"contact_events=true"});
    make_integrator(scene.integrator, scene.control);
    FAIL("accepted");
  } catch (const InputError& e) {
    CHECK(std::string(e.what()).find("need an ARKODE integrator") != std::string::npos);
  }
}

TEST_CASE("an IMEX pair on a scene without temperatures runs its explicit table, step for step", "[arkode]") {
  // With no stiff part, f = f_E + 0 and the additive method is its explicit table (before: a
  // segmentation fault in the implicit part).
  auto final_state = [](const std::string& integrator) {
    testing::Run run(testing::case_text("t1_free_fall.yaml"), {"integrator=" + integrator, "dt=1e-5", "t_end=0.01"});
    while (run.t() < 0.01 - 1e-12) run.step();
    return run.y;
  };
  CHECK(final_state("imex:ARK324L2SA") == final_state("erk:ARK324L2SA_ERK_4_2_3"));
  CHECK(final_state("imex5") == final_state("erk:ARK548L2SA_ERK_8_4_5"));
}

TEST_CASE("a damped Hertz bounce with contact events goes through its release: the state stays finite and the "
          "energy balanced",
          "[arkode][events]") {
  // A copper disc dropped 5 mm onto a floor, Hertz with Tsuji's dashpot (restitution 0.8 and 0.5),
  // erk4 with events. The acting contact is continued past separation until the release is
  // located; the Hertz spring's delta^1/2 of that negative overlap was NaN, and the run stopped at
  // the release (t = 0.0323 s) blaming the step.
  const Scene scene = parse_scene(R"(name: hertz_drop
mass_model: sphere
gravity: [0, -9.81]
materials:
  copper: {density: 8900, youngs_modulus: 1.0e8, restitution: 0.8}
  wall: {youngs_modulus: 1.0e8, restitution: 0.5}
contact_model: hertz
particles:
  - {material: copper, radius: 0.0015, at: [[0.0, 0.0065]]}
walls:
  - {name: floor, material: wall, segment: [[-0.1, 0.0], [0.1, 0.0]]}
integrator: erk4
contact_events: true
dt: 2.0e-6
t_end: 0.05
)",
                                  "hertz_drop.yaml");
  const auto s = run_scene(scene, {"", true});
  const auto& energy = s["energy"];
  CHECK(s["integrator_stats"]["contact_events"].get<long>() >= 2);  // touch and release
  CHECK(energy["dissipated_damping"].get<double>() > 0);
  // The ledger is integrated by the table too: measured 1.0e-7 of the largest exchange.
  CHECK(std::abs(energy["balance_error"].get<double>()) <
        1e-6 * s["checks"]["energy_balance"]["largest_exchange"].get<double>());
}

// Issue 28's review: at rtol 1e-13 the dashpot's onset on a wall (the velocity's local error falls
// only as h across a jump in force) shrank Fehlberg's step to 3e-19 s at t = 2.36e-3 s, and the run
// took 40 million steps without advancing. It stops now, saying why; rtol 1e-12 passes the same
// onset (a few steps of 1.7e-18 s), and located onsets pass it at 1e-13.
TEST_CASE("an adaptive step stalled at the time's round-off stops the run saying so; a looser rtol or located onsets "
          "pass the same onset",
          "[arkode]") {
  const std::string box = R"(name: b
materials:
  copper: {density: 8900, stiffness: 6000, restitution: 0.8}
  wall: {stiffness: 6000, restitution: 0.5}
particles:
  - material: copper
    radius: 0.002
    at: [[0.025, 0.0025], [0.01, 0.01]]
    velocity: [0.1, -0.2]
walls:
  - {name: box, material: wall, box: [0, 0, 0.05, 0.0375]}
integrator: erk:FEHLBERG_6_4_5
dt: 1.0e-5
t_end: 0.004
output_interval: 1.0e-3
contacts:
  - between: [copper, wall]
    stiffness: 6000
    restitution: 0.5
    friction: 0.3
    rolling_friction: 0.1
    rolling_model: epsd
    tangential_stiffness_ratio: 0.2857
    tangential_damping_ratio: 0.5
)";
  const auto run = [&](std::vector<std::string> sets) { return run_scene(parse_scene(box, "box.yaml", sets), {"", true}); };
  CHECK_THROWS_WITH(run({"rtol=1e-13"}), Catch::Contains("the adaptive step stalled at t = 0.002363") &&
                                             Catch::Contains("loosen rtol"));
  CHECK(run({"rtol=1e-12"})["integrator_stats"]["step_size"]["min"].get<double>() < 1e-16);  // the onset's steps
  CHECK_NOTHROW(run({"rtol=1e-13", "contact_events=true"}));
}
