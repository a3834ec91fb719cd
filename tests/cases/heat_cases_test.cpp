// The thermal cases against their exact solutions: T4, F1 (chain and slab), F2, N1, L1, L2, T5,
// and the frozen-network stage.
#include <catch2/catch.hpp>
#include <hdf5.h>

#include <Eigen/Dense>
#include <cmath>
#include <filesystem>

#include "src/base/error.h"
#include "src/studies/exact_solutions.h"
#include "src/scene/overrides.h"
#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "src/run/stability.h"
#include "tests/support.h"

using namespace kiln;
namespace fs = std::filesystem;

namespace {

nlohmann::json run_case(const std::string& file, const std::vector<std::string>& sets = {}, const std::string& out = "") {
  return run_scene(load_scene(testing::case_path(file), sets), {out, true});
}

std::vector<double> temps(const nlohmann::json& s) { return s["temperatures"].get<std::vector<double>>(); }

// Rows of a (frames x n) dataset.
std::vector<std::vector<double>> read_frames(const fs::path& file, const char* name, int n) {
  const std::vector<double> flat = testing::read_dataset(file, name);
  std::vector<std::vector<double>> rows;
  for (size_t k = 0; k + n <= flat.size(); k += n) rows.emplace_back(flat.begin() + k, flat.begin() + k + n);
  return rows;
}

const double copper_capacity = 4.0 / 3.0 * M_PI * 8e-9 * 8900 * 172;  // T4's m c_p
const double t4_h = 2 * 385 * std::sqrt(0.39) * 1e-3;

double t4_error(const std::string& integrator, double dt) {
  const auto s = run_case("t4_two_particle_conduction.yaml", {"integrator=" + integrator, assignment("dt", dt),
                                                              "t_end=0.1"});
  const auto T = temps(s);
  const double exact = 100 * std::exp(-2 * t4_h * 0.1 / copper_capacity);
  return std::abs((T[0] - T[1]) - exact);
}

}  // namespace

TEST_CASE("T4: the temperature difference decays as exp(-2 H t / (m c_p)) and both reach 50 C", "[heat]") {
  const auto s = run_case("t4_two_particle_conduction.yaml");
  const auto T = temps(s);
  CHECK(T[0] == Approx(50).margin(0.01));
  CHECK(T[1] == Approx(50).margin(0.01));
  // Conduction alone keeps the heat to round-off.
  CHECK(std::abs(s["energy"]["thermal_change"].get<double>()) < 1e-12 * 100 * copper_capacity);
  CHECK(s["steps"].get<long>() == 500);
}

TEST_CASE("T4: the error shrinks at the integrator's order (forward Euler 1, Heun 2)", "[heat]") {
  for (const auto& [integrator, order] : std::vector<std::pair<std::string, double>>{{"verlet", 1}, {"velocity-verlet", 2}}) {
    const double e1 = t4_error(integrator, 2e-3), e2 = t4_error(integrator, 1e-3), e3 = t4_error(integrator, 5e-4);
    INFO(integrator << ": errors " << e1 << " " << e2 << " " << e3);
    CHECK(testing::order(e2, e3) == Approx(order).margin(0.1));
  }
}

TEST_CASE("F1: a 20-disc chain matches the matrix exponential of its conduction matrix", "[heat]") {
  // Independent reference: C dT/dt = -K T + b T_D with K the chain's Laplacian plus the wall.
  const int n = 20;
  const double H = 0.5, Hw = 1.0, TD = 100;
  const double C = 4.0 / 3.0 * M_PI * 1e-9 * 8900 * 385;
  Eigen::MatrixXd K = Eigen::MatrixXd::Zero(n, n);
  for (int i = 0; i + 1 < n; ++i) {
    K(i, i) += H;
    K(i + 1, i + 1) += H;
    K(i, i + 1) -= H;
    K(i + 1, i) -= H;
  }
  K(n - 1, n - 1) += Hw;
  // Symmetric: K / C = V diag(l) V^T; with T = TD + u, u(t) = V exp(-l t) V^T u(0).
  Eigen::SelfAdjointEigenSolver<Eigen::MatrixXd> eig(K / C);
  for (double t : {0.5, 2.0, 5.0}) {
    const auto s = run_case("f1_chain_slab.yaml", {assignment("t_end", t)});
    const auto T = temps(s);
    const Eigen::VectorXd u0 = Eigen::VectorXd::Constant(n, -TD);
    const Eigen::VectorXd u = eig.eigenvectors() *
                              (eig.eigenvalues().array() * -t).exp().matrix().asDiagonal() *
                              (eig.eigenvectors().transpose() * u0);
    for (int i = 0; i < n; ++i) CHECK(T[i] == Approx(TD + u(i)).margin(0.02));  // Heun at dt = 1 ms
    // The study registry's exact solution (built from the scene's own network) is the same.
    const auto exact = exact_quantity(load_scene(testing::case_path("f1_chain_slab.yaml")), "temperature", t);
    REQUIRE(exact);
    for (int i = 0; i < n; ++i) CHECK((*exact)[i] == Approx(TD + u(i)).margin(1e-9));
  }
}

TEST_CASE("F1: a long chain approaches the slab's Fourier series", "[heat]") {
  // 100 discs spaced 1.9 mm: a slab L = 0.19 m, alpha = H Delta^2 / C; at Fo = 0.1 and 0.3.
  const int n = 100;
  const double H = 0.5, delta = 0.0019, L = n * delta, C = 4.0 / 3.0 * M_PI * 1e-9 * 8900 * 385;
  const double alpha = H * delta * delta / C;
  const double wall_x = (n - 1) * delta + 0.00095;
  for (double fo : {0.1, 0.3}) {
    const double t = fo * L * L / alpha;
    const auto s = run_case("f1_chain_slab.yaml", {"particles.0.lattice.columns=100",
                                                   "walls.0.segment=[[" + std::to_string(wall_x) + ", -0.002], [" +
                                                       std::to_string(wall_x) + ", 0.002]]",
                                                   assignment("t_end", t), "dt=0.005"});
    const auto T = temps(s);
    double worst = 0;
    for (int i = 0; i < n; ++i) {
      const double X = (i + 0.5) * delta / L;  // the insulated end is half a spacing before disc 0
      double theta = 0;
      for (int m = 1; m <= 200; ++m) {
        const double l = (m - 0.5) * M_PI;
        theta += 4 * std::sin(l) / (2 * l + std::sin(2 * l)) * std::cos(l * X) * std::exp(-l * l * fo);
      }
      worst = std::max(worst, std::abs(T[i] - 100 * (1 - theta)));
    }
    INFO("Fo = " << fo << ": largest difference from the slab " << worst << " C");
    CHECK(worst < 0.5);  // the discrete chain differs from the continuum by O(1/N^2)
  }
}

TEST_CASE("F2: two cylinders with the pipe-network law follow the exact two-body exponential", "[heat]") {
  const double H = 0.08083184930575046;
  const double ca = M_PI * 1e-4 * 0.01 * 7800 * 460, cb = M_PI * 2.25e-4 * 0.01 * 7800 * 460;
  const double mean = (ca * 100) / (ca + cb);
  for (double t : {50.0, 150.0, 300.0}) {
    const auto T = temps(run_case("f2_pipe_network_pair.yaml", {assignment("t_end", t), "dt=0.25"}));
    const double diff = 100 * std::exp(-H * (1 / ca + 1 / cb) * t);
    CHECK(T[0] - T[1] == Approx(diff).epsilon(1e-4));
    CHECK((ca * T[0] + cb * T[1]) / (ca + cb) == Approx(mean).epsilon(1e-12));
  }
}

TEST_CASE("N1: heat is kept exactly and every temperature approaches the mean without overshoot", "[heat]") {
  const fs::path dir = fs::temp_directory_path() / ("kiln_n1_" + std::to_string(::getpid()));
  const auto s = run_case("n1_triangle_conduction.yaml", {}, dir.string());
  const auto frames = read_frames(dir / "result.h5", "temperature", 14);
  REQUIRE(frames.size() > 100);
  const double mean = (100 + 13 * 20.0) / 14;  // equal discs
  double previous_spread = INFINITY, previous_max = INFINITY, previous_min = -INFINITY;
  for (const auto& T : frames) {
    double sum = 0, spread = 0;
    for (double v : T) {
      sum += v;
      spread += (v - mean) * (v - mean);
    }
    CHECK(sum / 14 == Approx(mean).epsilon(1e-13));  // heat kept to round-off
    // Conduction dissipates sum (T - mean)^2 and obeys the maximum principle.
    CHECK(spread <= previous_spread * (1 + 1e-12));
    const double hi = *std::max_element(T.begin(), T.end()), lo = *std::min_element(T.begin(), T.end());
    CHECK(hi <= previous_max + 1e-12);
    CHECK(lo >= previous_min - 1e-12);
    previous_spread = spread;
    previous_max = hi;
    previous_min = lo;
  }
  // Disc 1 cools, discs 5 and 14 (the far corners) warm, all to the mean.
  const auto T = temps(s);
  for (int disc : {0, 4, 13}) CHECK(T[disc] == Approx(mean).margin(0.01));
  CHECK(frames[1][0] < 100);
  CHECK(frames[1][4] > 20);
  fs::remove_all(dir);
}

TEST_CASE("L1: the hot and cold halves of a pressed line both reach the mean, 0 C", "[heat][heavy]") {
  const auto s = run_case("l1_aligned_equilibrium.yaml");
  CHECK(s["temperature_mean_left"].get<double>() == Approx(0).margin(0.01));
  CHECK(s["temperature_mean_right"].get<double>() == Approx(0).margin(0.01));
  CHECK(std::abs(s["energy"]["thermal_change"].get<double>()) < 1e-9);  // adiabatic walls
}

TEST_CASE("L2: between walls at 0 C and 50 C the final temperatures are linear in x", "[heat][heavy]") {
  const auto s = run_case("l2_aligned_wall_heating.yaml");
  const auto fit = s["temperature_fit"];
  // Linear: the residual of the straight-line fit is nothing against the 50 C span.
  CHECK(fit["rms_residual"].get<double>() < 1e-3 * 50);
  // Through the middle at the mean of the walls, with the walls' slope 50 C / 0.09 m: the discrete
  // line is 6 % flatter because a wall contact conducts 1.26 times a particle contact, not twice
  // as a continuum end would (Hertz overlaps under one force: r_c,wall / r_c,pair = sqrt(2 * 2^(-1/3))).
  CHECK(fit["intercept"].get<double>() == Approx(25).margin(0.01));
  CHECK(fit["slope"].get<double>() == Approx(50 / 0.09).epsilon(0.08));
  // Heat entered through the walls and the ledger closes.
  CHECK(s["energy"]["heat_from_walls"].get<double>() > 0);
  CHECK(std::abs(s["energy"]["balance_error"].get<double>()) < 1e-6 * s["energy"]["heat_from_walls"].get<double>());
}

TEST_CASE("T5: a hot half and a cold half fall into a heap; heat is kept exactly while it spreads", "[heat]") {
  const auto s = run_case("t5_hot_heap.yaml", {"particles.0.fill.count=150"});
  CHECK(s["stopped_early"] == "at_rest");
  CHECK(s["heap_angle_deg"].get<double>() > 3);
  const double heat = s["heat_content"].get<double>();
  CHECK(std::abs(s["energy"]["thermal_change"].get<double>()) < 1e-12 * std::abs(heat));
  // Conduction through the contacts narrowed the spread of temperatures (a disc that touches only
  // the floor keeps its own). Diffusion over the half second of settling is slow: about 2 %.
  auto spread = [](const std::vector<double>& T) {
    double mean = 0, var = 0;
    for (double v : T) mean += v / T.size();
    for (double v : T) var += (v - mean) * (v - mean) / T.size();
    return std::sqrt(var);
  };
  const double before = spread(load_scene(testing::case_path("t5_hot_heap.yaml"), {"particles.0.fill.count=150"}).temperature);
  const double after = spread(temps(s));
  INFO("standard deviation " << before << " C at the start, " << after << " C at rest");
  CHECK(after < 0.99 * before);
  CHECK(s["temperature_max"].get<double>() <= 100);
  CHECK(s["temperature_min"].get<double>() >= 0);
}

TEST_CASE("freeze: a settled pile keeps its positions while heat moves with a large step", "[heat][heavy]") {
  const fs::path dir = fs::temp_directory_path() / ("kiln_freeze_" + std::to_string(::getpid()));
  const auto s = run_case("t5_hot_heap.yaml",
                          {"particles.0.fill.count=100", "stop=null",
                           "freeze={kinetic_energy_below: 1.0e-7, not_before: 0.3, dt: 1.0e-3, output_interval: 0.05}",
                           "t_end=3.0"},
                          dir.string());
  REQUIRE(s["frozen_at"].is_number());
  const double frozen_at = s["frozen_at"].get<double>();
  CHECK(frozen_at < 1.5);
  const auto positions = read_frames(dir / "result.h5", "position", 300);  // 100 x (x, y, 0)
  const auto times = read_frames(dir / "result.h5", "time", 1);
  size_t first_frozen = 0;
  while (times[first_frozen][0] < frozen_at) ++first_frozen;
  for (size_t k = first_frozen; k < positions.size(); ++k) CHECK(positions[k] == positions[first_frozen]);
  // Far fewer steps than the mechanical dt would need to reach 3 s.
  CHECK(s["steps"].get<long>() < frozen_at / 2e-6 + 3.0 / 1e-3 + 10);
  CHECK(std::abs(s["energy"]["thermal_change"].get<double>()) < 1e-12 * std::abs(s["heat_content"].get<double>()));
  fs::remove_all(dir);
}

TEST_CASE("explicit conduction beyond its limit is refused up front and stopped by the maximum principle", "[heat]") {
  const Scene scene = load_scene(testing::case_path("t4_two_particle_conduction.yaml"), {"dt=0.15", "t_end=3"});
  const StabilityEstimate est = estimate_stability(scene);
  CHECK(est.thermal_dt_limit_network == Approx(2 / (2 * t4_h / copper_capacity)));
  CHECK(judge_dt(est, scene.dt, scene).unstable);
  try {
    run_scene(scene, {"", true});
    FAIL("the run did not stop");
  } catch (const InstabilityError& e) {
    const std::string msg = e.what();
    CHECK(msg.find("maximum principle") != std::string::npos);
    CHECK(msg.find("explicit conduction of this network is stable below dt = 0.106") != std::string::npos);
  }
}

TEST_CASE("velocity Verlet's temperatures are stable to the conduction limit kiln check states, not half of it",
          "[heat]") {
  // The slope of each step was taken at the predictor, not the corrected temperatures: stable to
  // 0.56 of 2 / lambda (T4 went unstable at dt = 0.06 s with the limit at 0.107 s).
  const double limit = estimate_stability(load_scene(testing::case_path("t4_two_particle_conduction.yaml")))
                           .thermal_dt_limit_network;
  const auto stable = run_case("t4_two_particle_conduction.yaml",
                               {"dt=" + std::to_string(0.9 * limit), "t_end=" + std::to_string(300 * limit)});
  for (double temp : temps(stable)) CHECK(temp == Approx(50).margin(1e-6));
  const Scene beyond = load_scene(testing::case_path("t4_two_particle_conduction.yaml"),
                                  {"dt=" + std::to_string(1.1 * limit), "t_end=" + std::to_string(300 * limit)});
  CHECK_THROWS_AS(run_scene(beyond, {"", true}), InstabilityError);
}
