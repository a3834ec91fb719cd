// C3: a flat-bottomed bin discharging through an orifice, against Beverloo's law
// W = C rho_b sqrt(g) (D - k d)^(3/2) (src/observers/beverloo_fit.h, cases/c3_hopper.yaml).
#include <catch2/catch.hpp>
#include <cmath>
#include <cstdio>
#include <iostream>

#include "src/observers/beverloo_fit.h"
#include "src/scene/overrides.h"
#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "tests/support.h"

using namespace kiln;

namespace {

// The case with an orifice of width D (m), run to t_end (s).
nlohmann::json discharge(double D, double t_end) {
  char left[80], right[80];
  std::snprintf(left, sizeof left, "walls.0.polyline.2=[%.17g,0.0]", -D / 2);
  std::snprintf(right, sizeof right, "walls.1.polyline.0=[%.17g,0.0]", D / 2);
  const Scene scene = load_scene(testing::case_path("c3_hopper.yaml"), {left, right, assignment("t_end", t_end)});
  nlohmann::json s = run_scene(scene, {"", true});
  REQUIRE(s["orifice_width"].get<double>() == Approx(D));
  INFO("D = " << D << " m: W = " << s["discharge_rate"] << " +- " << s["discharge_rate_error"] << " kg/s");
  // A steady window with a rate known to a few per cent, and a bed at rest in the bin's corners
  // packed as a random packing of polydisperse discs, well below the hexagonal 0.907 (measured
  // 0.81-0.84).
  CHECK(s["discharge_rate_error"].get<double>() < 0.05 * s["discharge_rate"].get<double>());
  CHECK(s["bed_packing_fraction"].get<double>() > 0.76);
  CHECK(s["bed_packing_fraction"].get<double>() < 0.88);
  // The ledger closes to velocity Verlet's first-order error with dashpots, against the potential
  // energy the flow has released (the potential counts from the continuous positions, which fall
  // by one period each time a disc goes round).
  CHECK(std::abs(s["energy"]["balance_error"].get<double>()) < 0.01 * -s["energy"]["potential"].get<double>());
  return s;
}

// One disc falls freely through a 20 mm orifice in a floor at y = 0. In a cell periodic along y
// (period 0.1 m) it comes back in at the top and passes again: by t = 0.3 s its continuous height
// 0.04 - g t^2 / 2 = -0.401 m has crossed the plane's images at 0, -0.1, ..., -0.4.
const std::string falling_disc = R"(name: pass
materials:
  glass: {density: 2500, stiffness: 2000, restitution: 0.5}
particles:
  - {material: glass, radius: 0.002, at: [[0.0, 0.04]]}
walls:
  - {name: left, material: glass, segment: [[-0.05, 0.0], [-0.01, 0.0]]}
  - {name: right, material: glass, segment: [[0.01, 0.0], [0.05, 0.0]]}
periodic: {y: [-0.05, 0.05]}
dt: 1.0e-4
t_end: 0.3
output_interval: 0.01
report: [discharge]
)";

}  // namespace

TEST_CASE("Beverloo fit recovers C, k and n of synthetic rates", "[hopper]") {
  const double rho_b = 5.4, g = 9.81, d = 0.004;
  const std::vector<double> D = {0.020, 0.024, 0.030, 0.036, 0.042};
  for (const double n : {1.5, 2.5}) {
    std::vector<double> W;
    for (double w : D) W.push_back(0.9 * rho_b * std::sqrt(g) * std::pow(w - 1.4 * d, n));
    const BeverlooFit fit = fit_beverloo(D, W, rho_b, g, d);
    CHECK(fit.n == Approx(n).epsilon(1e-6));
    CHECK(fit.k == Approx(1.4).epsilon(1e-6));
    CHECK(fit.C == Approx(0.9).epsilon(1e-6));
    CHECK(fit.rms_log_residual < 1e-9);
    const BeverlooFit fixed = fit_beverloo_fixed_exponent(D, W, rho_b, g, d, n);
    CHECK(fixed.k == Approx(1.4).epsilon(1e-9));
    CHECK(fixed.C == Approx(0.9).epsilon(1e-9));
  }
  // Rates scattered by +-2 % (as a run's are): the exponent stays near its value, the scatter
  // shows in the residual.
  std::vector<double> W;
  const double scatter[] = {1.02, 0.98, 1.0, 1.02, 0.98};
  for (size_t i = 0; i < D.size(); ++i)
    W.push_back(scatter[i] * 0.9 * rho_b * std::sqrt(g) * std::pow(D[i] - 1.4 * d, 1.5));
  const BeverlooFit fit = fit_beverloo(D, W, rho_b, g, d);
  CHECK(fit.n == Approx(1.5).margin(0.2));
  CHECK(fit.rms_log_residual == Approx(0.015).margin(0.01));
}

TEST_CASE("discharge observer counts every pass of a disc through the floor's plane", "[hopper]") {
  const Scene periodic = parse_scene(falling_disc, "pass.yaml");
  const double mass = 4.0 / 3 * M_PI * std::pow(0.002, 3) * 2500;
  nlohmann::json s = run_scene(periodic, {"", true});
  CHECK(s["discharged_count"] == 5);
  CHECK(s["discharged_mass"].get<double>() == Approx(5 * mass));
  CHECK(s["discharge_history"]["discharged_count"].back() == 5);
  CHECK(s["orifice_width"].get<double>() == Approx(0.02));
  CHECK(s["discharge_plane"] == 0.0);
  // Without the period it passes once and keeps falling.
  s = run_scene(parse_scene(falling_disc, "pass.yaml", {"periodic=null"}), {"", true});
  CHECK(s["discharged_count"] == 1);
  // A scene without walls has no floor to pass, a drum no orifice: both refused when read.
  CHECK_THROWS_WITH(parse_scene(falling_disc, "pass.yaml", {"walls=null"}),
                    Catch::Contains("'discharge' needs a floor with an orifice"));
  const std::string drum = testing::case_text("t6_drum.yaml") + "\nreport: [discharge]\n";
  CHECK_THROWS_WITH(parse_scene(testing::replaced(drum, "report: [temperatures, mixing]\n", ""), "drum.yaml"),
                    Catch::Contains("'discharge' needs a floor with an orifice"));
}

TEST_CASE("discharge observer goes on from a checkpoint as if never stopped", "[hopper][checkpoint]") {
  auto options = [](const std::filesystem::path& dir) {
    RunOptions o;
    o.out_dir = dir.string();
    o.quiet = true;
    o.source = {"pass.yaml", falling_disc, {}};
    return o;
  };
  const std::filesystem::path whole = testing::fresh_dir("pass_whole"), halves = testing::fresh_dir("pass_halves");
  const nlohmann::json w = run_scene(parse_scene(falling_disc, "pass.yaml"), options(whole));
  run_scene(parse_scene(falling_disc, "pass.yaml", {"t_end=0.15"}), options(halves));
  const Snapshot checkpoint = Snapshot::read((halves / "checkpoint.h5").string());
  RunOptions o = options(halves);
  o.resume = &checkpoint;
  const nlohmann::json s = run_scene(scene_of_checkpoint(checkpoint, {"t_end=0.3"}, o.source), o);
  CHECK(s["discharged_count"] == 5);
  for (const char* key : {"time", "discharged_mass", "discharged_count"})
    CHECK(s["discharge_history"][key] == w["discharge_history"][key]);
  std::filesystem::remove_all(whole);
  std::filesystem::remove_all(halves);
}

TEST_CASE("C3: the discharge rate rises from 6 d to 12 d as (D - k d)^(3/2) with a plausible k", "[hopper][heavy]") {
  // Two widths, 0.8 s each (the flow is steady from about 0.3 s). With the exponent fixed at 3/2
  // two rates give k (fit_beverloo_fixed_exponent): Beverloo's k is 1 to 3 (0.5 to 3 here: the
  // rates' few per cent move k by about 0.2), while rates growing as D (k = 0, n = 1) would give
  // k = -4.2 and the 3D law's D^(5/2) k = 3.2.
  const double d = 0.004;
  const nlohmann::json narrow = discharge(6 * d, 0.8), wide = discharge(12 * d, 0.8);
  const double w6 = narrow["discharge_rate"].get<double>(), w12 = wide["discharge_rate"].get<double>();
  const BeverlooFit fit = fit_beverloo_fixed_exponent({6 * d, 12 * d}, {w6, w12}, narrow["bulk_density"].get<double>(),
                                                       9.81, narrow["mean_diameter"].get<double>(), 1.5);
  INFO("W(6 d) = " << w6 << " kg/s, W(12 d) = " << w12 << " kg/s: k = " << fit.k << ", C = " << fit.C);
  CHECK(w12 > 3 * w6);
  CHECK(fit.k > 0.5);
  CHECK(fit.k < 3);
}

TEST_CASE("C3: Beverloo's law fitted over five orifice widths has the exponent 3/2", "[hopper][long]") {
  const double d = 0.004;
  const std::vector<double> widths = {6 * d, 7 * d, 8.5 * d, 10 * d, 12 * d};
  std::vector<double> rates;
  double rho_b = 0, mean_d = 0;
  std::cout << "C3 Beverloo fit (cases/c3_hopper.yaml, t_end 1.5 s)\n D (m)    W (kg/s)   +- (kg/s)  rho_b (kg/m^2)\n";
  for (double D : widths) {
    const nlohmann::json s = discharge(D, 1.5);
    rates.push_back(s["discharge_rate"].get<double>());
    rho_b += s["bulk_density"].get<double>() / static_cast<double>(widths.size());
    mean_d = s["mean_diameter"].get<double>();
    std::printf(" %.4f   %.5f    %.5f    %.3f\n", D, rates.back(), s["discharge_rate_error"].get<double>(),
                s["bulk_density"].get<double>());
  }
  for (size_t i = 1; i < rates.size(); ++i) CHECK(rates[i] > rates[i - 1]);
  const BeverlooFit fit = fit_beverloo(widths, rates, rho_b, 9.81, mean_d);
  const BeverlooFit fixed = fit_beverloo_fixed_exponent(widths, rates, rho_b, 9.81, mean_d, 1.5);
  std::printf(" d = %.5f m, rho_b = %.3f kg/m^2\n free:  C = %.3f, k = %.2f, n = %.3f (rms ln residual %.3f)\n"
              " n=3/2: C = %.3f, k = %.2f (rms ln residual %.3f)\n",
              mean_d, rho_b, fit.C, fit.k, fit.n, fit.rms_log_residual, fixed.C, fixed.k, fixed.rms_log_residual);
  // The exponent: the rates' standard errors (1-2.4 %) scatter a three-parameter fit over a factor
  // of 2 in D widely: a Monte-Carlo of this fit with the rates scattered by their errors gives n
  // in 1.17-1.89 (95 %; sigma 0.19) around the measured 1.45, so the band is 1.5 +- 0.4, two sigma.
  // Beverloo's 3/2 lies well inside; rates set by the head (n = 1) or the 3D law (5/2) do not.
  // In the free fit k trades against n (1.2-2.9 at one sigma): it is held to 1-3 with the exponent
  // fixed at 3/2, where the same Monte-Carlo gives 1.94 +- 0.09.
  CHECK(fit.n > 1.1);
  CHECK(fit.n < 1.9);
  CHECK(fit.k < 3.5);
  CHECK(fixed.k > 1);
  CHECK(fixed.k < 3);
}
