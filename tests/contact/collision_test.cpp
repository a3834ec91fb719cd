// Head-on collisions of two discs: the restitution the contact law was asked for comes out, for
// the linear and the Hertz law, several e and size ratios ([csiro-dem-spring-dashpot.txt] normal
// spring-dashpot; Hertz with the Tsuji dashpot of contact/normal_force.h).
#include <catch2/catch.hpp>
#include <cmath>
#include <sstream>

#include "contact/model_table.h"
#include "src/run/stability.h"
#include "src/scene/overrides.h"
#include "tests/support.h"

using namespace kiln;

namespace {

std::string pair_scene(const std::string& model, double e, double r1, double r2, bool tension) {
  const double v = 0.5, gap = 1e-5;
  std::ostringstream s;
  s << "name: pair\ngravity: [0, 0]\n"
    << "materials:\n  glass: {density: 2500, stiffness: 1.0e4, youngs_modulus: 1.0e8, poisson_ratio: 0.3}\n"
    << "contacts:\n  - between: [glass, glass]\n    model: " << model << "\n    restitution: " << e
    << "\n    tension: " << (tension ? "true" : "false") << "\n"
    << "particles:\n  - material: glass\n    radius: " << r1 << "\n    at: [[0, 0]]\n    velocity: [" << v << ", 0]\n"
    << "  - material: glass\n    radius: " << r2 << "\n    at: [[" << r1 + r2 + gap << ", 0]]\n    velocity: [" << -v
    << ", 0]\n"
    << "integrator: velocity-verlet\ndt: 1.0e-7\nt_end: 1.0\n";
  return s.str();
}

// Steps through the collision with dt = contact duration / 2000 and returns the measured e.
double measured_restitution(const std::string& model, double e, double r1, double r2, bool tension,
                            const std::string& integrator) {
  const std::string yaml = pair_scene(model, e, r1, r2, tension);
  const Scene probe = parse_scene(yaml, "pair.yaml");
  const double tc = estimate_stability(probe).contact_duration;
  testing::Run run(yaml, {assignment("dt", tc / 2000), "integrator=" + integrator});
  const double approach = run.vx(0) - run.vx(1);
  bool touched = false;
  for (long step = 0; step < 10000000; ++step) {
    run.step();
    const double gap = run.x(1) - run.x(0) - r1 - r2;
    if (gap < 0) touched = true;
    if (touched && gap > 0) break;
  }
  REQUIRE(touched);
  return (run.vx(1) - run.vx(0)) / approach;
}

}  // namespace

TEST_CASE("linear spring-dashpot collision returns the requested restitution within 0.5 %", "[collision]") {
  for (double e : {0.3, 0.5, 0.8, 0.95})
    for (double ratio : {1.0, 2.0, 4.0})
      for (bool tension : {true, false}) {
        INFO("e = " << e << ", size ratio " << ratio << ", tension " << tension);
        CHECK(measured_restitution("linear", e, 1e-3, ratio * 1e-3, tension, "velocity-verlet") ==
              Approx(e).epsilon(0.005));
      }
}

TEST_CASE("Hertz collision with the Tsuji dashpot returns the requested restitution within 0.5 %", "[collision]") {
  for (double e : {0.3, 0.5, 0.8, 0.95})
    for (double ratio : {1.0, 2.0, 4.0}) {
      INFO("e = " << e << ", size ratio " << ratio);
      CHECK(measured_restitution("hertz", e, 1e-3, ratio * 1e-3, true, "velocity-verlet") == Approx(e).epsilon(0.005));
      CHECK(measured_restitution("hertz", e, 1e-3, ratio * 1e-3, false, "verlet") == Approx(e).epsilon(0.005));
    }
}

TEST_CASE("every normal model of the table, collided head-on, returns the restitution its dashpot was solved for",
          "[collision]") {
  for (const auto& m : contact::normal_models())
    for (bool tension : {true, false}) {
      INFO(m.name << ", tension " << tension);
      CHECK(measured_restitution(m.name, 0.6, 1e-3, 2e-3, tension, "velocity-verlet") == Approx(0.6).epsilon(0.005));
    }
}
