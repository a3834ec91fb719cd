// The benchmark pile of ../shared/BENCH.md: discs with diameters uniform in [1.6, 2.4] mm,
// density 2500, a jittered hexagonal lattice of 50 rows (spacing 2.5 mm) dropped onto a
// frictional floor and settled for 0.24 s (not timed); then 5,000 warm-up steps and the timed
// steps. Linear spring-dashpot kn = 1e4 N/m, gamma_n = 1.9e4 1/s (F = m_eff gamma_n v_n),
// k_t = 2/7 k_n, gamma_t = gamma_n / 2, mu = 0.5, dt = 2e-6 s, skin 0.4 mm.
// Difference from BENCH.md: kiln has no periodic boundaries yet, so the pile stands between two
// frictional side walls instead of being periodic in x.
#include "src/bench.h"

#include <sys/resource.h>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <sstream>

#include "integrators/integrator.h"
#include "src/dem_system.h"
#include "src/scene_yaml.h"

namespace kiln {

namespace {

std::string bench_scene(int columns, bool flowing) {
  const double spacing = 0.0025, width = columns * spacing + spacing;
  const double g = 9.81, tilt = flowing ? 30 * M_PI / 180 : 0;
  std::ostringstream s;
  s.precision(17);
  s << "name: bench_pile\n"
    << "gravity: [" << g * std::sin(tilt) << ", " << -g * std::cos(tilt) << "]\n"
    << "materials:\n  grain: {density: 2500}\n"
    << "contacts:\n  - between: [grain, grain]\n    stiffness: 1.0e4\n    damping_rate: 1.9e4\n"
    << "    friction: 0.5\n    tangential_stiffness_ratio: 0.2857142857142857\n    tangential_damping_ratio: 0.5\n"
    << "particles:\n  - material: grain\n    radius: {uniform: [0.0008, 0.0012]}\n"
    << "    lattice: {kind: hexagonal, origin: [" << spacing << ", 0.0015], spacing: " << spacing
    << ", rows: 50, columns: " << columns << ", jitter: 0.00002, seed: 7}\n"
    << "walls:\n  - {material: grain, polyline: [[0, 0.3], [0, 0], [" << width << ", 0], [" << width << ", 0.3]]}\n"
    << "integrator: velocity-verlet\ndt: 2.0e-6\nt_end: 1.0\nskin: 0.0004\n";
  return s.str();
}

double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;
}

}  // namespace

int run_bench(const BenchOptions& o) {
  const Scene scene = parse_scene(bench_scene(o.columns, o.flowing), "bench_pile");
  DemSystem system(scene);
  std::vector<double> y = system.initial_state();
  auto integrator = make_integrator(scene.integrator);
  integrator->start(system, 0, y.data(), scene.dt);
  const long settle = std::lround(0.24 / scene.dt), warm = 5000;
  using clock = std::chrono::steady_clock;
  const auto t0 = clock::now();
  for (long k = 0; k < settle + warm; ++k) integrator->step();
  const long rebuilds_before = system.rebuilds();
  const auto t1 = clock::now();
  for (long k = 0; k < o.steps; ++k) integrator->step();
  const auto t2 = clock::now();
  const double loop = std::chrono::duration<double>(t2 - t1).count();
  const auto contacts = system.count_contacts(integrator->time(), y.data());
  const int n = system.particles();
  std::printf("bench_pile (%s): %d discs, %ld timed steps of %g s after %ld settling + warm-up steps (%.1f s)\n",
              o.flowing ? "flowing, gravity tilted 30 deg" : "resting", n, o.steps, scene.dt, settle + warm,
              std::chrono::duration<double>(t1 - t0).count());
  std::printf("  loop time %.3f s, %.3g particle-steps/s, peak RSS %.1f MB\n", loop, n * o.steps / loop, peak_rss_mb());
  std::printf("  %.2f contacts per disc, %.2f candidate pairs per disc, %ld neighbour rebuilds while timed\n",
              (2.0 * contacts.particle_particle + contacts.particle_wall) / n,
              static_cast<double>(system.particle_contacts().size()) / n, system.rebuilds() - rebuilds_before);
  return 0;
}

}  // namespace kiln
