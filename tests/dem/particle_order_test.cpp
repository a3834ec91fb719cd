// The contact loop walks the particles in an order of its own (DemSystem's slots): the index
// order while the pairs' particles lie close in it, ranked along a Hilbert curve once they do
// not (a pile numbered at random, or one that has flowed and mixed). That order must change
// nothing but the last bits of sums: a pile numbered at random runs as the same pile numbered
// along its lattice, on any number of threads in the same bits, and resumes from a checkpoint
// bit for bit; and a rebuild after the order changed keeps every contact's history.
#include <omp.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <cstring>
#include <numeric>
#include <random>

#include "src/base/snapshot.h"
#include "src/dem/contact_list.h"
#include "tests/support.h"

namespace kiln {
namespace {

// The scene with its particles numbered anew: particle k of `s` is particle label[k] of the result.
Scene renumbered(Scene s, const std::vector<int>& label) {
  auto permute = [&](auto& v) {
    if (v.empty()) return;
    auto out = v;
    for (size_t k = 0; k < v.size(); ++k) out[label[k]] = v[k];
    v = out;
  };
  permute(s.position);
  permute(s.velocity);
  permute(s.radius);
  permute(s.angular_velocity);
  permute(s.material);
  permute(s.temperature);
  permute(s.attached);
  return s;
}

std::vector<int> random_labels(int n) {
  std::vector<int> label(n);
  std::iota(label.begin(), label.end(), 0);
  std::shuffle(label.begin(), label.end(), std::mt19937(11));
  return label;
}

struct Stepped {
  std::vector<double> y;
  long reorders = 0, rebuilds = 0;
};

Stepped stepped(const Scene& scene, const std::string& integrator, int threads, int steps) {
  DemSystem system(scene);
  Stepped out{system.initial_state(), 0};
  const int before = omp_get_max_threads();
  omp_set_num_threads(threads);
  auto stepper = make_integrator(integrator);
  stepper->start(system, 0, out.y.data(), scene.dt);
  for (int k = 0; k < steps; ++k) stepper->step();
  omp_set_num_threads(before);
  out.reorders = system.reorders();
  out.rebuilds = system.rebuilds();
  return out;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

}  // namespace

TEST_CASE("a pile numbered at random is ranked along a Hilbert curve and runs as the pile numbered in order",
          "[order]") {
  for (const bool hot : {true, false}) {
    INFO((hot ? "hot" : "cold"));
    const Scene lattice = parse_scene(testing::pressed_pile(hot), "pressed_pile");
    const int n = lattice.n_particles();
    const std::vector<int> label = random_labels(n);
    const Scene shuffled = renumbered(lattice, label);
    const Stepped a = stepped(lattice, "velocity-verlet", 1, 60), b = stepped(shuffled, "velocity-verlet", 1, 60);
    CHECK(a.reorders == 0);  // the lattice's numbering is local already
    CHECK(b.reorders == 1);  // at the first rebuild, and not again: the curve's order stays local
    // Field by field, particle k of the lattice against particle label[k] of the shuffled pile:
    // the same forces summed in another order differ in their last bits. Most spins (up to 1,500
    // rad/s here) end 1e-14 of themselves apart, a few 1e-11: contacts at their friction or rolling
    // caps amplify the last bits (the lattice pile with every vx moved by one ulp ends with a spin
    // 1.5e-12 of itself off in the same 60 steps). Positions end 2.6e-15 m apart (5e-16 while the
    // friction cap reset every sliding spring to the cap, erasing its last bits; now a spring
    // within the cap keeps them). A contact missed or
    // met twice would change a disc's velocity by its force times dt / m, 1e-4 m/s or more.
    // Velocities and spins are compared relative to themselves above 1 (m/s, rad/s).
    const DemSystem sa(lattice), sb(shuffled);
    double position = 0, velocity = 0, temperature = 0;
    for (int k = 0; k < n; ++k) {
      const int m = label[k];
      for (const auto& [at_a, at_b] : {std::pair{sa.x_at(), sb.x_at()}, std::pair{sa.y_at(), sb.y_at()},
                                       std::pair{sa.angle_at(), sb.angle_at()}})
        position = std::max(position, std::abs(a.y[at_a + k] - b.y[at_b + m]));
      for (const auto& [at_a, at_b] : {std::pair{sa.vx_at(), sb.vx_at()}, std::pair{sa.vy_at(), sb.vy_at()},
                                       std::pair{sa.omega_at(), sb.omega_at()}})
        velocity = std::max(velocity, std::abs(a.y[at_a + k] - b.y[at_b + m]) / std::max(1.0, std::abs(a.y[at_a + k])));
      if (hot) temperature = std::max(temperature, std::abs(a.y[sa.temperature_at() + k] - b.y[sb.temperature_at() + m]));
    }
    INFO("position " << position << ", velocity " << velocity << ", temperature " << temperature);
    CHECK(position < 1e-14);  // a missed contact: its force times dt^2 / m, > 1e-10 m
    CHECK(velocity < 1e-10);
    CHECK(temperature < 1e-12);  // kelvin, of a 100 K spread
    // The ledger sums the same works in another order.
    for (int e = 0; e < sa.ledger_count(); ++e)
      CHECK(b.y[sb.ledger_at() + e] == Approx(a.y[sa.ledger_at() + e]).epsilon(1e-9).margin(1e-20));
  }
}

TEST_CASE("a pile in curve order ends in the same bits on 1 and 2 threads", "[order][threads]") {
  const Scene lattice = parse_scene(testing::pressed_pile(true), "pressed_pile");
  const Scene shuffled = renumbered(lattice, random_labels(lattice.n_particles()));
  for (const char* integrator : {"velocity-verlet", "erk2"}) {
    INFO(integrator);
    const Stepped one = stepped(shuffled, integrator, 1, 40), two = stepped(shuffled, integrator, 2, 40);
    CHECK(one.reorders == 1);
    CHECK(same_bits(one.y, two.y));
  }
}

TEST_CASE("a ranking that cannot bring the pairs together is not repeated at every rebuild", "[order]") {
  // One fixed disc 100 km above the pile sets the curve's extent: its cells are 3 m wide and the
  // whole pile lies in one, so the ranking keeps the random numbering. A skin of 0.1 um makes
  // nearly every step a rebuild.
  std::string text = testing::pressed_pile(false);
  text.insert(text.find("periodic:"), "  - {material: grain, radius: 0.001, fixed: true, at: [[0.1, 100000]]}\n");
  text += "skin: 1.0e-7\n";
  const Scene lattice = parse_scene(text, "pressed_pile_and_far_disc");
  const Stepped run = stepped(renumbered(lattice, random_labels(lattice.n_particles())), "velocity-verlet", 1, 30);
  CHECK(run.rebuilds >= 10);
  CHECK(run.reorders == 1);
}

TEST_CASE("a run in curve order resumes from its checkpoint bit for bit, its particle order with it",
          "[order][checkpoint]") {
  const Scene lattice = parse_scene(testing::pressed_pile(false), "pressed_pile");
  const Scene shuffled = renumbered(lattice, random_labels(lattice.n_particles()));
  const Stepped whole = stepped(shuffled, "velocity-verlet", 1, 40);
  DemSystem first(shuffled);
  std::vector<double> y = first.initial_state();
  auto stepper = make_integrator("velocity-verlet");
  stepper->start(first, 0, y.data(), shuffled.dt);
  for (int k = 0; k < 20; ++k) stepper->step();
  Snapshot saved;
  SnapshotFields system_out(saved, "system."), integrator_out(saved, "integrator.");
  first.state(system_out);
  stepper->state(integrator_out);
  DemSystem second(shuffled);
  SnapshotFields system_in(static_cast<const Snapshot&>(saved), "system.");
  second.state(system_in);
  CHECK(second.reorders() == 1);
  auto resumed = make_integrator("velocity-verlet");
  resumed->resume(second, y.data(), shuffled.dt, saved, "integrator.");
  for (int k = 0; k < 20; ++k) resumed->step();
  CHECK(same_bits(y, whole.y));
}

TEST_CASE("a rebuild after the particle order changed keeps each contact's spring and frame", "[order]") {
  // Four particles, slots 0..3 then reversed: the same three pairs, found as pairs of slots, must
  // come back with the history each had, whatever order the list holds them in.
  ContactList list;
  list.history = true;
  const std::vector<int> identity = {0, 1, 2, 3}, reversed = {3, 2, 1, 0};  // particle at slot s, and its inverse
  list.replace({{0, 1}, {1, 2}, {2, 3}}, 4, true, identity.data(), identity.data());
  for (int p = 0; p < list.size(); ++p) {
    list.spring[p] = 10.0 * list.i[p] + list.j[p];
    list.frame[p] = {1.0, 0.0, 0.0, -(10.0 * list.i[p] + list.j[p])};
  }
  // Slot s now holds particle 3 - s: the pairs (0, 1), (1, 2), (2, 3) are the slot pairs
  // (2, 3), (1, 2), (0, 1), found in that sorted order, and a new pair (0, 3) = slots (0, 3).
  list.replace({{0, 1}, {0, 3}, {1, 2}, {2, 3}}, 4, true, reversed.data(), reversed.data());
  REQUIRE(list.size() == 4);
  for (int p = 0; p < list.size(); ++p) {
    INFO("pair " << list.i[p] << ", " << list.j[p]);
    CHECK(list.i[p] < list.j[p]);  // particles in index order, whatever their slots
    CHECK(list.si[p] == reversed[list.i[p]]);
    CHECK(list.sj[p] == reversed[list.j[p]]);
    const double expected = list.i[p] == 0 && list.j[p] == 3 ? 0.0 : 10.0 * list.i[p] + list.j[p];
    CHECK(list.spring[p] == expected);
    CHECK(list.frame[p].rho_n == -expected);
  }
  // Sorted by slots: lower, then higher.
  for (int p = 1; p < list.size(); ++p) {
    const auto key = [&](int q) { return std::pair{std::min(list.si[q], list.sj[q]), std::max(list.si[q], list.sj[q])}; };
    CHECK(key(p - 1) < key(p));
  }
}

}  // namespace kiln
