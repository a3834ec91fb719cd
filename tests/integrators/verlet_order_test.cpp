// Orders of the Verlet integrators on a disc resting on a floor (a linear contact that never
// opens: a harmonic oscillator with an exact solution), with and without a dashpot. This is
// the check that would have caught Lethe's velocity Verlet silently turning into symplectic Euler.
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>

#include "contact/normal_force.h"
#include "src/scene/overrides.h"
#include "tests/support.h"

using namespace kiln;

namespace {

const double r = 0.002, k = 6000, g = 9.81;
const double m = 4.0 / 3.0 * M_PI * r * r * r * 8900;
const double w = std::sqrt(k / m);
const double d_eq = m * g / k, amplitude = 0.5 * d_eq;  // the overlap stays in (0.5, 1.5) d_eq

std::string resting_disc(double e) {
  std::ostringstream s;
  s.precision(17);
  s << "name: resting\n"
    << "materials:\n  copper: {density: 8900, stiffness: 6000, restitution: " << e << "}\n"
    << "particles:\n  - material: copper\n    radius: " << r << "\n    at: [[0, " << r - d_eq - amplitude << "]]\n"
    << "walls:\n  - {material: copper, segment: [[-0.01, 0], [0.01, 0]]}\n"
    << "allow_overlap: true\ndt: 1.0e-6\nt_end: 0.01\n";
  return s.str();
}

// Error at t_end (height scaled by omega, plus velocity) against the exact damped oscillation.
double error_at_end(const std::string& integrator, double e, double dt) {
  testing::Run run(resting_disc(e), {"integrator=" + integrator, assignment("dt", dt)});
  const double t_end = 0.01;
  const long steps = std::lround(t_end / dt);
  for (long s = 0; s < steps; ++s) run.step();
  const double zeta = contact::restitution_damping(e, contact::NormalModel::linear, true) / 2;
  const double wd = w * std::sqrt(1 - zeta * zeta);
  const double t = steps * dt;
  const double decay = std::exp(-zeta * w * t);
  const double offset = -amplitude * decay * (std::cos(wd * t) + zeta * w / wd * std::sin(wd * t));
  const double rate = amplitude * decay * (w * w / wd) * std::sin(wd * t);
  const double y_exact = r - d_eq + offset, v_exact = rate;
  return std::hypot(w * (run.yy(0) - y_exact), run.vy(0) - v_exact);
}

// Observed order over three halvings from dt = period / steps_per_period.
double measured_order(const std::string& integrator, double e, double steps_per_period = 100) {
  const double period = 2 * M_PI / w;
  const double h = period / steps_per_period;
  const double e1 = error_at_end(integrator, e, h), e2 = error_at_end(integrator, e, h / 2),
               e3 = error_at_end(integrator, e, h / 4);
  INFO(integrator << " e = " << e << ": errors " << e1 << " " << e2 << " " << e3);
  // In the asymptotic range both halvings agree (high orders approach it from above).
  CHECK(testing::order(e1, e2) == Approx(testing::order(e2, e3)).margin(0.35));
  return testing::order(e2, e3);
}

}  // namespace

TEST_CASE("every ARKODE explicit table reaches its nominal order on the harmonic contact", "[order][arkode]") {
  // Fixed steps through ARKStep's explicit mode. The step sizes keep each table's error above
  // round-off and in its asymptotic range: coarser for higher orders.
  for (const auto& info : integrator_catalogue()) {
    if (info.scheme != IntegratorScheme::arkode || info.implicit || !info.alias_of.empty()) continue;
    const double steps_per_period = info.order >= 7 ? 6 : info.order >= 5 ? 12 : info.order >= 4 ? 24 : 48;
    CHECK(measured_order(info.name, 1.0, steps_per_period) == Approx(info.order).margin(0.15));
  }
}

TEST_CASE("with a dashpot the ARKODE tables keep their order (the forces stay smooth)", "[order][arkode]") {
  for (const char* name : {"erk2", "erk4", "erk5"}) {
    const IntegratorInfo& info = integrator_info(name);
    CHECK(measured_order(name, 0.5, info.order >= 5 ? 6 : 24) == Approx(info.order).margin(0.15));
  }
}

TEST_CASE("all Verlet integrators are second order without a dashpot", "[order]") {
  for (const std::string& name : testing::verlet_family()) CHECK(measured_order(name, 1.0) == Approx(2).margin(0.15));
}

TEST_CASE("with a dashpot verlet and velocity-verlet are first order, velocity-verlet-predicted second", "[order]") {
  for (const auto& info : integrator_catalogue())
    if (info.scheme != IntegratorScheme::arkode)
      CHECK(measured_order(info.name, 0.5) == Approx(info.order_with_dashpot).margin(0.15));
}
