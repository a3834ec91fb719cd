// Wall groups: turning and load-controlled walls, the loads the particles put on them (force,
// torque, power), and particles attached to walls or fixed.
#include <memory>
#include <numeric>

#include "src/scene/overrides.h"
#include "tests/support.h"

namespace {

using kiln::testing::Run;

// 45 discs in a drum of radius 20 mm turning counter-clockwise: the rolling regime.
const std::string slow_drum = R"(name: slow_drum
materials:
  glass: {density: 2500, stiffness: 2.0e4, restitution: 0.5, friction: 0.5}
  steel: {stiffness: 2.0e4, restitution: 0.5, friction: 0.5}
particles:
  - material: glass
    radius: {uniform: [0.001, 0.0013]}
    fill: {rectangle: [-0.011, -0.014, 0.011, 0.008], count: 45, seed: 4}
walls:
  - name: drum
    material: steel
    circle: {centre: [0, 0], radius: 0.02}
    motion: {type: rotate, centre: [0, 0], rpm: RPM}
dt: 1.0e-5
t_end: T_END
)";

std::string drum(double rpm, double t_end) {
  return kiln::testing::replaced(kiln::testing::replaced(slow_drum, "RPM", std::to_string(rpm)), "T_END",
                                 std::to_string(t_end));
}

}  // namespace

// The power a wall delivers is what the ledger's work_by_walls integrates: their time integrals
// agree to the trapezoidal rule's error over steps of 1e-5 s (the power is that of each step's
// latest force evaluation, at its end).
TEST_CASE("the time integral of a turning wall's power equals the ledger's work by walls", "[walls]") {
  Run r(drum(30, 0.3));
  double work = 0, before = r.system->wall_loads()[0].power, t0 = r.t();
  while (r.t() < r.scene.t_end) {
    r.step();
    const double power = r.system->wall_loads()[0].power;
    work += 0.5 * (before + power) * (r.t() - t0);
    before = power;
    t0 = r.t();
  }
  const double ledger = r.system->energy(r.t(), r.y.data()).work_by_walls;
  INFO("integral of power " << work << " J, ledger " << ledger << " J");
  CHECK(std::abs(ledger) > 1e-6);  // the wall did work
  CHECK(work == Approx(ledger).epsilon(0.01));
}

// In the rolling regime the bed turns with the drum as a whole and its centre of mass stays put:
// the walls hold the bed's weight, and the torque the particles put on the drum about its axis is
// the weight times the horizontal offset of the centre of mass, T = -M g x_c (g along -y): the
// drive has to hold the bed up on the rising side. Averaged over the second half of the run, where
// the bed's accelerations average out.
TEST_CASE("a slowly turning drum feels the bed's weight times the offset of its centre of mass as torque", "[walls]") {
  Run r(drum(10, 2.0));
  double mass = 0;
  for (int i = 0; i < r.system->particles(); ++i) mass += r.system->mass(i);
  double torque = 0, offset = 0;
  long samples = 0;
  while (r.t() < r.scene.t_end) {
    r.step();
    if (r.t() < 1.0) continue;
    double mx = 0;
    for (int i = 0; i < r.system->particles(); ++i) mx += r.system->mass(i) * r.x(i);
    offset += mx / mass;
    torque += r.system->wall_loads()[0].torque;
    ++samples;
  }
  torque /= samples;
  offset /= samples;
  const double expected = -mass * 9.81 * offset;
  INFO("torque " << torque << " N m, -M g x_c " << expected << " N m, x_c " << offset << " m");
  CHECK(offset > 1e-3);  // turning counter-clockwise, the bed leans to +x
  CHECK(torque == Approx(expected).epsilon(0.03));
}

namespace {

// A top wall resting on a row of discs on a floor, periodic in x: pressed down by its load and
// driven along x. Rough: a row of discs attached to it.
const std::string sheared_row = R"(name: sheared_row
gravity: [0, -9.81]
materials:
  glass: {density: 2500, stiffness: 5.0e4, restitution: 0.3, friction: 0.4}
particles:
  - material: glass
    radius: 0.001
    lattice: {kind: square, origin: [0.001, 0.001], spacing: 0.002, rows: 1, columns: 10}
  - material: glass
    radius: 0.001
    attach: top
    lattice: {kind: square, origin: [0.0, 0.003], spacing: 0.002, rows: 1, columns: 10}
walls:
  - {name: floor, material: glass, segment: [[0, 0], [0.02, 0]]}
  - name: top
    material: glass
    segment: [[0, 0.004], [0.02, 0.004]]
    motion: {type: load_controlled, velocity: [V, 0], load: [0, -2.0], mass: 0.01, damping: 2.0}
periodic: {x: [0, 0.02]}
allow_overlap: true
dt: 2.0e-6
t_end: 0.1
)";

}  // namespace

// A load-controlled wall comes to rest where the particles carry its load: the force they put on
// it (its attached discs included) balances the load, and the floor carries the load and the
// free discs' weight. Its attached discs keep their places on it exactly.
TEST_CASE("a load-controlled wall settles where the particles carry its load, its attached discs with it", "[walls]") {
  Run r(kiln::testing::replaced(sheared_row, "V", "0"));
  const int n = r.system->particles();
  std::vector<double> gap0;
  for (int i = 10; i < n; ++i) gap0.push_back(r.yy(i) - 0.004);
  while (r.t() < r.scene.t_end) r.step();
  const auto& loads = r.system->wall_loads();
  double free_weight = 0;
  for (int i = 0; i < 10; ++i) free_weight += r.system->mass(i) * 9.81;
  CHECK(loads[1].force.y == Approx(2.0).epsilon(1e-3));
  CHECK(loads[0].force.y == Approx(-(2.0 + free_weight)).epsilon(1e-3));
  // The wall moved down onto the discs (its coordinate runs along the load), and its discs moved
  // with it.
  CHECK(r.y[r.system->body_at()] > 1e-4);
  std::vector<kiln::Vec2> a, b;
  r.system->wall_geometry(r.t(), r.y.data(), a, b);
  CHECK(a[1].y < 0.004 - 1e-4);
  for (int i = 10; i < n; ++i) CHECK(r.yy(i) - a[1].y == Approx(gap0[i - 10]).margin(1e-12));
}

namespace {

struct DrivenRow {
  double power_integral = 0;  // trapezoidal rule over the steps
  kiln::EnergyLedger end, start;
};

DrivenRow drive_row(double dt, Run*& keep) {
  static std::unique_ptr<Run> run;
  run = std::make_unique<Run>(kiln::testing::replaced(sheared_row, "V", "0.05"),
                              std::vector<std::string>{kiln::assignment("dt", dt)});
  Run& r = *run;
  keep = run.get();
  DrivenRow out;
  out.start = r.system->energy(0, r.y.data());
  double before = 0, t0 = r.t();
  for (const auto& l : r.system->wall_loads()) before += l.power;
  while (r.t() < r.scene.t_end) {
    r.step();
    double power = 0;
    for (const auto& l : r.system->wall_loads()) power += l.power;
    out.power_integral += 0.5 * (before + power) * (r.t() - t0);
    before = power;
    t0 = r.t();
  }
  out.end = r.system->energy(r.t(), r.y.data());
  return out;
}

}  // namespace

// Driven along x at V, the wall and its discs move at V, and the row below is sheared. The ledger
// books the walls' work on their displacements (second order in dt, like the dashpots' and
// friction's): the balance closes with the wall body and its discs outside the particles'
// energy. The power a frame reports is that of the step's last force evaluation, whose dashpots
// see Verlet's predicted velocities: its time integral reaches the work at first order in dt.
TEST_CASE("a driven rough wall moves its attached discs at its velocity and its power is the walls' work", "[walls]") {
  Run* r = nullptr;
  const DrivenRow coarse = drive_row(1e-6, r);
  const DrivenRow fine = drive_row(5e-7, r);
  for (int i = 10; i < r->system->particles(); ++i) CHECK(r->vx(i) == Approx(0.05).epsilon(1e-12));
  std::vector<kiln::Vec2> a, b;
  r->system->wall_geometry(r->t(), r->y.data(), a, b);
  CHECK(a[1].x == Approx(0.05 * r->t()).margin(1e-12));
  CHECK(fine.end.work_by_walls > 0);
  const double balance = kiln::balance_error(fine.start, fine.end);
  INFO("balance error " << balance << " J of " << fine.end.work_by_walls << " J work; power integrals "
                        << coarse.power_integral << ", " << fine.power_integral << " J against "
                        << coarse.end.work_by_walls << ", " << fine.end.work_by_walls << " J");
  CHECK(std::abs(balance) < 1e-4 * fine.end.work_by_walls);
  const double gap_coarse = coarse.power_integral - coarse.end.work_by_walls;
  const double gap_fine = fine.power_integral - fine.end.work_by_walls;
  CHECK(std::abs(gap_fine) < 0.03 * fine.end.work_by_walls);
  CHECK(gap_coarse / gap_fine == Approx(2).epsilon(0.2));
}

// A fixed disc stays where it is and takes no force; a disc dropped on it bounces off, and with
// nothing moving the walls do no work.
TEST_CASE("a fixed particle does not move, takes no force, and does no work", "[walls]") {
  const std::string text = R"(name: fixed_grain
materials:
  glass: {density: 2500, stiffness: 2.0e4, restitution: 0.8}
particles:
  - {material: glass, radius: 0.001, fixed: true, at: [[0, 0]]}
  - {material: glass, radius: 0.001, at: [[0.0003, 0.004]]}
dt: 1.0e-6
t_end: 0.05
)";
  Run r(text);
  double highest_rebound = 0;
  bool touched = false;
  while (r.t() < r.scene.t_end) {
    r.step();
    touched = touched || r.system->count_contacts(r.t(), r.y.data()).particle_particle > 0;
    if (touched) highest_rebound = std::max(highest_rebound, r.vy(1));
  }
  CHECK(r.x(0) == 0);
  CHECK(r.yy(0) == 0);
  CHECK(r.vx(0) == 0);
  CHECK(r.vy(0) == 0);
  CHECK(touched);
  CHECK(highest_rebound > 0.1);
  const kiln::EnergyLedger e = r.system->energy(r.t(), r.y.data());
  CHECK(e.work_by_walls == 0);
  CHECK(std::abs(kiln::balance_error(r.system->energy(0, r.system->initial_state().data()), e)) < 1e-3 * e.dissipated_damping);
}

// A wall driven along a periodic axis leaves the cell; the particles meet it through their images,
// so after two and a half periods of travel it still rests on the row (a first version lost it
// after half a period, and the wall fell through the particles).
TEST_CASE("a wall driven along a periodic axis for periods on end still rests on the particles", "[walls][periodic]") {
  Run r(kiln::testing::replaced(sheared_row, "V", "0.5"));
  const kiln::EnergyLedger start = r.system->energy(0, r.y.data());
  while (r.t() < r.scene.t_end) r.step();
  std::vector<kiln::Vec2> a, b;
  r.system->wall_geometry(r.t(), r.y.data(), a, b);
  CHECK(a[1].x > 2.5 * 0.02 - 1e-9);
  CHECK(a[1].y > 0.0035);  // on the discs: the attached ones sit 1 mm below it on the free row
  const kiln::EnergyLedger e = r.system->energy(r.t(), r.y.data());
  CHECK(std::abs(kiln::balance_error(start, e)) < 1e-3 * e.work_by_walls);
}
