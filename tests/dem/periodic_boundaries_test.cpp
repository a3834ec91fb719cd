// Periodic cells: the minimum image everywhere, places wrapped into the cell, contact history kept
// across a wrap, and no wall effects.
#include <algorithm>
#include <numeric>

#include "tests/support.h"

namespace {

using kiln::testing::Run;

// Sum of m v over the particles, and the particles' energy (kinetic plus elastic).
struct GasState {
  double px = 0, py = 0, momentum_scale = 0, energy = 0;
};
GasState gas_state(const Run& r) {
  GasState g;
  for (int i = 0; i < r.system->particles(); ++i) {
    const double m = r.system->mass(i);
    g.px += m * r.vx(i);
    g.py += m * r.vy(i);
    g.momentum_scale += m * std::hypot(r.vx(i), r.vy(i));
  }
  const kiln::EnergyLedger e = r.system->energy(r.t(), r.y.data());
  g.energy = e.kinetic + e.elastic;
  return g;
}

// 64 discs in a cell periodic along x and y, elastic contacts, no gravity, no walls.
const std::string periodic_gas = R"(name: periodic_gas
gravity: [0, 0]
materials:
  glass: {density: 2500, stiffness: 1.0e4, restitution: 1.0}
particles:
  - material: glass
    radius: 0.001
    lattice: {kind: square, origin: [0.0015, 0.0015], spacing: 0.004, rows: 8, columns: 8}
    random_velocity: {max: 0.5, seed: 3}
periodic: {x: [0, 0.032], y: [0, 0.032]}
dt: 2.0e-6
t_end: 0.06
)";

}  // namespace

// Velocity Verlet keeps the energy of an elastic gas to O(dt^2) (a contact takes 36 steps here:
// about 1e-3 of the kinetic energy at the peaks of the collisions, none drifting) and the momentum
// to round-off: each contact's force acts on both discs, wherever the pair sits in the cell.
TEST_CASE("an elastic gas in a periodic cell keeps its energy and its momentum", "[periodic]") {
  Run r(periodic_gas);
  const GasState start = gas_state(r);
  double worst_energy = 0;
  long collisions_seen = 0;
  while (r.t() < r.scene.t_end) {
    r.step();
    const GasState now = gas_state(r);
    worst_energy = std::max(worst_energy, std::abs(now.energy - start.energy) / start.energy);
    collisions_seen += r.system->count_contacts(r.t(), r.y.data()).particle_particle > 0;
    CHECK(std::abs(now.px - start.px) < 1e-12 * start.momentum_scale);
    CHECK(std::abs(now.py - start.py) < 1e-12 * start.momentum_scale);
    CHECK(r.system->count_contacts(r.t(), r.y.data()).particle_wall == 0);
  }
  CHECK(worst_energy < 2e-3);
  // The test means something: discs collided, and discs left the cell's first image.
  CHECK(collisions_seen > 1000);
  int crossed = 0;
  for (int i = 0; i < r.system->particles(); ++i) crossed += r.x(i) < 0 || r.x(i) >= 0.032 || r.yy(i) < 0 || r.yy(i) >= 0.032;
  CHECK(crossed > 10);
}

// The same pair of discs, pressed and sheared with friction while one crosses the periodic edge,
// and again in the middle of the cell: the minimum image makes the two runs the same motion
// (translation invariance), so the contact and its tangential spring survive the crossing.
TEST_CASE("a pair in contact keeps its contact and its tangential history across the periodic edge", "[periodic]") {
  const std::string pair = R"(name: pair_across
gravity: [0, 0]
materials:
  steel: {density: 7800, stiffness: 2.0e4, restitution: 0.7, friction: 0.4}
particles:
  - {material: steel, radius: 0.001, velocity: [2.0, 0.05], at: [[X0, 0.005]]}
  - {material: steel, radius: 0.001, velocity: [2.0, -0.05], at: [[X1, 0.0058]]}
periodic: {x: [0, 0.02]}
allow_overlap: true
dt: 5.0e-7
t_end: 2.0e-4
)";
  // Across: the first disc 0.01 mm before the edge, its neighbour's centre 1.79 mm further (the
  // other side of the edge, wrapped); in the middle: both 10 mm to the left.
  const double x0 = 0.01999, x1 = x0 + 0.0017 - 0.02;
  Run across(kiln::testing::replaced(kiln::testing::replaced(pair, "X0", std::to_string(x0)), "X1", std::to_string(x1)));
  Run middle(kiln::testing::replaced(kiln::testing::replaced(pair, "X0", std::to_string(x0 - 0.01)), "X1",
                                     std::to_string(x1 + 0.01)));
  bool touching_after_crossing = false;
  while (across.t() < across.scene.t_end) {
    across.step();
    middle.step();
    const bool crossed = across.x(0) >= 0.02;
    if (crossed && across.system->count_contacts(across.t(), across.y.data()).particle_particle == 1) {
      touching_after_crossing = true;
      // The spring of the contact is the one the middle run has.
      REQUIRE(across.system->particle_contacts().size() >= 1);
      REQUIRE(middle.system->particle_contacts().size() >= 1);
      CHECK(across.system->particle_contacts().spring[0] ==
            Approx(middle.system->particle_contacts().spring[0]).margin(1e-15));
    }
  }
  CHECK(touching_after_crossing);
  for (int i = 0; i < 2; ++i) {
    CHECK(across.vx(i) == Approx(middle.vx(i)).epsilon(1e-9));
    CHECK(across.vy(i) == Approx(middle.vy(i)).margin(1e-9));
    CHECK(across.omega(i) == Approx(middle.omega(i)).margin(1e-6));
  }
  CHECK(std::abs(across.omega(0)) > 1);  // friction turned the discs
}

// A disc sliding with friction on a floor of two segments crosses the periodic edge while its
// friction spring is loaded: it rolls on as it would on a long floor.
TEST_CASE("a disc sliding on a periodic floor keeps its wall contact history across the edge", "[periodic]") {
  const std::string slide = R"(name: slide_across
materials:
  steel: {density: 7800, stiffness: 2.0e4, restitution: 0.5, friction: 0.3}
particles:
  - {material: steel, radius: 0.001, velocity: [0.4, 0], angular_velocity: 0, at: [[X0, 0.00099]]}
walls:
  - {name: floor, material: steel, polyline: [[FA, 0], [FM, 0], [FB, 0]]}
PERIODIC
allow_overlap: true
dt: 1.0e-6
t_end: 0.05
)";
  auto scene = [&](double x0, double a, double b, const std::string& periodic) {
    std::string s = kiln::testing::replaced(slide, "X0", std::to_string(x0));
    s = kiln::testing::replaced(s, "FA", std::to_string(a));
    s = kiln::testing::replaced(s, "FM", std::to_string(0.5 * (a + b)));
    s = kiln::testing::replaced(s, "FB", std::to_string(b));
    return kiln::testing::replaced(s, "PERIODIC", periodic);
  };
  Run across(scene(0.019, 0, 0.02, "periodic: {x: [0, 0.02]}"));
  Run long_floor(scene(0.019, -0.1, 0.1, ""));
  while (across.t() < across.scene.t_end) {
    across.step();
    long_floor.step();
  }
  CHECK(across.x(0) > 0.021);  // it crossed the edge, onto the floor's other segment
  CHECK(across.vx(0) == Approx(long_floor.vx(0)).epsilon(1e-9));
  CHECK(across.omega(0) == Approx(long_floor.omega(0)).epsilon(1e-9));
  CHECK(across.yy(0) == Approx(long_floor.yy(0)).epsilon(1e-9));
  // Friction was at work: it spun the disc up to a rim speed of half its sliding speed and more.
  CHECK(-across.omega(0) * 0.001 > 0.5 * across.vx(0));
}

namespace {

// Mean contacts per disc among the discs near the cell's edges (a tenth of it on each side), and
// over the whole pile.
std::pair<double, double> edge_and_pile_coordination(const Run& r, double x0, double x1) {
  const kiln::DemSystem& sys = *r.system;
  const int n = sys.particles();
  std::vector<int> z(n, 0);
  const double *px = r.y.data() + sys.x_at(), *py = r.y.data() + sys.y_at();
  const kiln::ContactList& pp = sys.particle_contacts();
  for (int p = 0; p < pp.size(); ++p) {
    const int i = pp.i[p], j = pp.j[p];
    const kiln::Vec2 d = sys.separation(px, py, i, j);
    if (std::hypot(d.x, d.y) < sys.radius(i) + sys.radius(j)) {
      ++z[i];
      ++z[j];
    }
  }
  double edge = 0, all = 0;
  int n_edge = 0;
  const double band = 0.1 * (x1 - x0);
  for (int i = 0; i < n; ++i) {
    const double x = sys.cell().wrap({px[i], py[i]}).x;
    all += z[i];
    if (x < x0 + band || x > x1 - band) {
      edge += z[i];
      ++n_edge;
    }
  }
  return {edge / n_edge, all / n};
}

}  // namespace

// A hexagonal pile with friction settles under gravity on a floor. Periodic in x, the discs at the
// cell's edges have the neighbours the middle ones have; the same pile without the period has free
// edges whose discs miss neighbours and slump (the contrast shows the test can tell). Friction
// keeps the lattice: without it the exactly packed pile is an unstable equilibrium that round-off
// rearranges, differently from run to run, and the comparison becomes one of noise.
TEST_CASE("a periodic pile has no wall effects: the coordination number at its edges is the pile's", "[periodic]") {
  const std::string pile = R"(name: periodic_pile
materials:
  glass: {density: 2500, stiffness: 2.0e4, restitution: 0.3, friction: 0.5}
particles:
  - material: glass
    radius: 0.001
    lattice: {kind: hexagonal, origin: [0.0005, 0.00101], spacing: 0.002, rows: 8, columns: 20}
walls:
  - {name: floor, material: glass, segment: [[-0.05, 0], [0.09, 0]]}
PERIODIC
allow_overlap: true  # the lattice's neighbours touch exactly
dt: 2.0e-6
t_end: 0.05
)";
  Run periodic(kiln::testing::replaced(pile, "PERIODIC", "periodic: {x: [0, 0.04]}"));
  Run open(kiln::testing::replaced(pile, "PERIODIC", ""));
  while (periodic.t() < periodic.scene.t_end) {
    periodic.step();
    open.step();
  }
  const auto [edge, all] = edge_and_pile_coordination(periodic, 0, 0.04);
  const auto [open_edge, open_all] = edge_and_pile_coordination(open, 0, 0.04);
  INFO("periodic: edge " << edge << ", pile " << all << "; open: edge " << open_edge << ", pile " << open_all);
  CHECK(all > 4);
  // Columns of the settled lattice differ by up to half a contact from one another (contacts at
  // the threshold of touching); the edge bands, 32 discs, within a tenth of the pile's mean.
  CHECK(std::abs(edge - all) < 0.1 * all);
  CHECK(open_edge < 0.5 * open_all);
}

// A particle's wrap is a view: the state stays continuous, so every integrator, fixed-step or
// adaptive, carries a disc across the edge without a rejected step (a first version rebuilt the
// neighbour lists at every wrap, which ARKODE took for a step too long, and failed).
TEST_CASE("every integrator carries discs across a periodic edge", "[periodic]") {
  const std::string crossing = R"(name: crossing
gravity: [0, 0]
materials:
  glass: {density: 2500, stiffness: 1.0e4, restitution: 0.9}
particles:
  - {material: glass, radius: 0.001, velocity: [1.0, -0.3], at: [[0.015, 0.005]]}
periodic: {x: [0, 0.02], y: [0, 0.02]}
dt: 1.0e-5
t_end: 0.05
)";
  for (const std::vector<std::string>& sets : std::vector<std::vector<std::string>>{
           {"integrator=erk4"}, {"integrator=erk4", "rtol=1e-6"}, {"integrator=velocity-verlet"}}) {
    Run r(crossing, sets);
    r.integrator->set_stop_time(r.scene.t_end);
    while (r.t() < r.scene.t_end - 1e-12) r.step();
    INFO(sets.back());
    CHECK(r.x(0) == Approx(0.015 + 0.05).epsilon(1e-9));  // two and a half periods, free flight
    CHECK(r.yy(0) == Approx(0.005 - 0.015).epsilon(1e-9));
    if (sets.size() == 1) CHECK(r.integrator->stats().steps == 5000);
  }
}
