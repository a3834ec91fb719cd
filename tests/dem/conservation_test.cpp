// An undamped, frictionless gas of 500 discs in a box: the Verlet integrators keep the total
// energy (no drift over 10^5 steps), and the broadphase never misses a touching pair.
#include <catch2/catch.hpp>
#include <algorithm>
#include <cmath>

#include "src/scene/overrides.h"
#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "tests/support.h"

using namespace kiln;

namespace {

const char* gas = R"(name: gas
description: "500 elastic frictionless discs in a box"
gravity: [0, 0]
materials:
  glass: {density: 2500, stiffness: 1.0e4, restitution: 1.0}
particles:
  - material: glass
    radius: {uniform: [0.0008, 0.0012]}
    fill: {rectangle: [0, 0, 0.1, 0.1], count: 500, seed: 11}
    random_velocity: {max: 0.5, seed: 12}
walls:
  - {material: glass, box: [0, 0, 0.1, 0.1]}
integrator: velocity-verlet
dt: 1.0e-6
t_end: 0.1
output_interval: 0.001
)";

}  // namespace

TEST_CASE("an elastic gas of 500 discs keeps its energy over 10^5 steps with every Verlet integrator", "[conservation][heavy]") {
  // dt is 1/51 of the shortest contact (5.1e-5 s). Each collision leaves an O(dt^2) energy error
  // that depends on where its onset falls inside a step, so the total wanders like a random walk
  // (measured: at most 2.1e-5 of the energy over these 10^5 steps, 2e-3 at dt = 4e-6): it must
  // stay within 1e-4 at every frame, which a systematic drift of any size per collision breaks.
  for (const std::string& name : testing::verlet_family()) {
    const Scene scene = parse_scene(gas, "gas.yaml", {"integrator=" + name});
    const auto s = run_scene(scene, {"", true});
    REQUIRE(s["steps"].get<long>() == 100000);
    const double e0 = s["energy"]["initial_total"].get<double>();
    const auto err = s["energy"]["history"]["balance_error"].get<std::vector<double>>();
    double worst = 0;
    for (double e : err) worst = std::max(worst, std::abs(e));
    INFO(name << ": worst relative energy error " << worst / e0);
    CHECK(worst < 1e-4 * e0);
    CHECK(err.size() == 101);
    CHECK(s["mean_contacts"].get<double>() > 0.005);  // the gas really collides
  }
}

TEST_CASE("broadphase: every overlapping pair of a long random flow is a candidate pair", "[broadphase][heavy]") {
  // A small skin and fast particles force many rebuilds; after every step the candidate lists are
  // compared with a brute-force search over all pairs and all wall segments. Velocity Verlet
  // evaluates where it stands; Runge-Kutta stages run ahead of the step's start, and a step that
  // outruns the lists is redone.
  for (const char* integrator : {"velocity-verlet", "erk4"}) {
  INFO(integrator);
  testing::Run run(gas, {"particles.0.fill.count=120", "particles.0.random_velocity.max=3.0", "skin=0.0001",
                         "gravity=[0, -9.81]", std::string("integrator=") + integrator});
  const DemSystem& sys = *run.system;
  const int n = sys.particles();
  long checked_contacts = 0;
  for (int step = 0; step < 20000; ++step) {
    run.step();
    if (step % 10) continue;
    const ContactList& pp = sys.particle_contacts();
    for (int i = 0; i < n; ++i)
      for (int j = i + 1; j < n; ++j) {
        const double rs = sys.radius(i) + sys.radius(j);
        if (std::hypot(run.x(j) - run.x(i), run.yy(j) - run.yy(i)) >= rs) continue;
        ++checked_contacts;
        bool found = false;
        for (int p = 0; p < pp.size() && !found; ++p) found = pp.i[p] == i && pp.j[p] == j;
        CHECK(found);
      }
    std::vector<Vec2> a, b;
    sys.wall_geometry(run.t(), run.y.data(), a, b);
    const ContactList& pw = sys.wall_contacts();
    for (int i = 0; i < n; ++i)
      for (size_t s = 0; s < a.size(); ++s) {
        const Vec2 c{run.x(i), run.yy(i)}, ab = b[s] - a[s];
        const double along = std::clamp(dot(c - a[s], ab) / dot(ab, ab), 0.0, 1.0);
        if (norm(a[s] + along * ab - c) >= sys.radius(i)) continue;
        bool found = false;
        for (int p = 0; p < pw.size() && !found; ++p) found = pw.i[p] == i && pw.j[p] == static_cast<int>(s);
        CHECK(found);
      }
  }
  CHECK(checked_contacts > 1000);
  CHECK(sys.rebuilds() > 100);
  }
}
