// Conductance laws as pure functions, against values computed by hand (independently, in Python,
// from the formulas of the seeds), with unlike radii and materials.
#include <catch2/catch.hpp>
#include <cmath>

#include "thermal/conductance.h"
#include "thermal/wall_temperature.h"

using namespace kiln::thermal;

TEST_CASE("lens law: T4's lens radius is sqrt(0.39) mm and H = 2 k r_c", "[conduction]") {
  CHECK(lens_radius(0.002, 0.002, 0.0038) == Approx(std::sqrt(0.39) * 1e-3));
  CHECK(lens_conductance(385, lens_radius(0.002, 0.002, 0.0038)) == Approx(2 * 385 * std::sqrt(0.39) * 1e-3));
  // Unlike radii 1 and 2 mm, centres 2.9 mm apart: r_c = 0.36050 mm (thesis Annex A geometry).
  CHECK(lens_radius(0.001, 0.002, 0.0029) == Approx(3.6050153332424566e-4));
  CHECK(lens_radius(0.002, 0.001, 0.0029) == Approx(3.6050153332424566e-4));  // symmetric
  // Against a flat wall at 0.9 mm from a 1 mm disc: half chord sqrt(1 - 0.81) mm.
  CHECK(lens_radius(0.001, INFINITY, 0.0009) == Approx(std::sqrt(0.19) * 1e-3));
  CHECK(lens_radius(0.001, 0.001, 0.0021) == 0.0);  // apart
  // Unlike materials use the harmonic mean conductivity.
  const ConductionLaw law{ConductionModel::lens, 385, 36};
  CHECK(conductance(law, 0.002, 0.002, 0.0038, 0) == Approx(2 * (2 * 385.0 * 36 / 421) * std::sqrt(0.39) * 1e-3));
}

TEST_CASE("Batchelor-O'Brien: 4 k1 k2/(k1+k2) sqrt(A/pi), with the softened-modulus correction", "[conduction]") {
  const double rc = lens_radius(0.001, 0.002, 0.0029);
  CHECK(batchelor_obrien_conductance(harmonic_mean(385, 36), rc, 1.0) == Approx(4 * 385.0 * 36 / 421 * rc));
  CHECK(batchelor_obrien_conductance(harmonic_mean(385, 36), rc, 1e-3) == Approx(0.1 * 4 * 385.0 * 36 / 421 * rc));
}

TEST_CASE("Hertz conductance (Nguyen): H = 2 lambda (3 F a* / (4 E*))^(1/3)", "[conduction]") {
  // Stainless steel (E 193 GPa, nu 0.29): E* = 1.0536e11 Pa; 10 N between two 1 mm discs.
  const double e_star = 1 / (2 * (1 - 0.29 * 0.29) / 193e9);
  CHECK(e_star == Approx(105360847254.06703));
  const ConductionLaw law{ConductionModel::hertz, 15, 15, 0, 1, e_star};
  CHECK(conductance(law, 0.001, 0.001, 0.00199, 10.0) == Approx(0.000986821476307254));
  CHECK(conductance(law, 0.001, 0.001, 0.00199, 0.0) == 0.0);
  // Against a wall a* = r_i: the same force through twice the radius of curvature.
  CHECK(conductance(law, 0.001, INFINITY, 0.00099, 10.0) == Approx(0.000986821476307254 * std::cbrt(2.0)));
}

TEST_CASE("pipe network (Feng): H = w / (R_A + R_B + R_c) for cylinders of unlike radii", "[conduction]") {
  // F2's pair: radii 10 and 15 mm, centres 24.5 mm apart, k = 16 W/mK, w = 10 mm.
  const ConductionLaw law{ConductionModel::pipe_network, 16, 16, 0, 1, 0, 0.01, 0};
  CHECK(lens_radius(0.010, 0.015, 0.0245) == Approx(0.0024351170150804886));
  CHECK(conductance(law, 0.010, 0.015, 0.0245, 0) == Approx(0.08083184930575046));
  const ConductionLaw resisted{ConductionModel::pipe_network, 16, 16, 0, 1, 0, 0.01, 0.1};
  CHECK(conductance(resisted, 0.010, 0.015, 0.0245, 0) == Approx(0.01 / (0.01 / 0.08083184930575046 + 0.1)));
}

TEST_CASE("constant conductance and the friction-heat partition beta", "[conduction]") {
  CHECK(conductance({ConductionModel::constant, 0, 0, 0.5}, 1, 1, 1, 0) == 0.5);
  CHECK(conductance({ConductionModel::none, 1, 1}, 0.001, 0.001, 0.0019, 1) == 0.0);
  CHECK(heat_partition(0, 0, 15, 15) == 0.5);        // one material: 1/2
  CHECK(heat_partition(1, 3, 15, 15) == Approx(0.375));  // (1/4 + 1/2) / 2
  CHECK(heat_partition(1, 3, 15, 15) + heat_partition(3, 1, 15, 15) == Approx(1.0));
}

TEST_CASE("wall temperature schedules: steps hold, ramps interpolate", "[conduction]") {
  WallTemperature steps{WallTemperature::Kind::steps, {0, 8}, {0, 50}};
  CHECK(steps.at(7.999) == 0);
  CHECK(steps.at(8.0) == 50);
  CHECK(steps.at(100) == 50);
  WallTemperature ramp{WallTemperature::Kind::ramp, {1, 3}, {0, 100}};
  CHECK(ramp.at(0) == 0);
  CHECK(ramp.at(2) == Approx(50));
  CHECK(ramp.at(5) == 100);
  CHECK_FALSE(WallTemperature{}.isothermal());
}
