#include "src/app/bench.h"

#include <malloc.h>
#include <sys/resource.h>
#include <unistd.h>

#include <nlohmann/json.hpp>

#include <chrono>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "integrators/integrator.h"
#include "src/base/wall_clock.h"
#include "src/dem/dem_system.h"
#include "src/base/error.h"
#include "src/scene/particle_file.h"
#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "src/run/stability.h"

namespace kiln {

namespace {

constexpr double spacing = 0.0025;    // lattice spacing (m)
constexpr int rows = 50;
constexpr double lattice_y0 = 0.0015;  // the lowest row's centres, clear of the floor (largest radius 1.2 mm)
constexpr double density = 2500;
constexpr double settle_time = 0.24;   // s, BENCH.md

// The scene of BENCH.md around a particle set (a YAML list entry) in a cell periodic over [x0, x1].
// The thermal variant gives the discs LIGGGHTS' conduction law (heat/gran/conduction: the
// conductance of the contact area, batchelor_obrien here) and glass-like properties.
std::string bench_scene(const std::string& particles, double x0, double x1, const BenchOptions& o) {
  const double g = 9.81, tilt = o.flowing ? 30 * M_PI / 180 : 0;
  std::ostringstream s;
  s.precision(17);
  s << "name: bench_pile\n"
    << "gravity: [" << g * std::sin(tilt) << ", " << -g * std::cos(tilt) << "]\n"
    << "materials:\n  grain: {density: " << density
    << (o.thermal ? ", specific_heat: 840, conductivity: 1.0" : "") << "}\n"
    << "contacts:\n  - between: [grain, grain]\n    stiffness: 1.0e4\n    damping_rate: 1.9e4\n"
    << "    friction: 0.5\n    tangential_stiffness_ratio: 0.2857142857142857\n    tangential_damping_ratio: 0.5\n"
    << (o.thermal ? "    conduction: batchelor_obrien\n" : "") << "particles:\n" << particles
    << "walls:\n  - {name: floor, material: grain, segment: [[" << x0 << ", 0], [" << x1 << ", 0]]}\n"
    << "periodic: {x: [" << x0 << ", " << x1 << "]}\n"
    << "allow_overlap: true\n"  // a settled pile is in contact
    << "integrator: " << nlohmann::json(o.integrator).dump() << "\ndt: 2.0e-6\nt_end: 1.0\nskin: 0.0004\n";
  return s.str();
}

// The process's peak resident size since it began (MB): what /usr/bin/time reports of a peer.
double peak_rss_mb() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss / 1024.0;
}

// The resident high-water mark (VmHWM of /proc/self/status, MB), which, unlike ru_maxrss, can be
// started again: restart_resident_peak() sets it to the resident size now (Linux 4.0 and later:
// "5" written to /proc/self/clear_refs), after giving the heap's free pages back (malloc_trim),
// so that what the stability estimate freed is not counted as the run's. A run's own peak is then
// read apart from the estimate's, which comes first and holds several times the step's memory.
// Negative where /proc does not give it (run_rss_mb=-1 in the machine line). Starting the mark again starts ru_maxrss again too, and
// so what /usr/bin/time reports of this process: its peak is the larger of the two parts'.
double resident_peak_mb() {
  std::ifstream status("/proc/self/status");
  for (std::string line; std::getline(status, line);)
    if (line.rfind("VmHWM:", 0) == 0) return std::stod(line.substr(6)) / 1024.0;  // "VmHWM:  1234 kB"
  return -1;
}
bool restart_resident_peak() {
  malloc_trim(0);
  std::ofstream clear("/proc/self/clear_refs");
  clear << "5";
  clear.close();
  return clear.good() && resident_peak_mb() >= 0;
}

// The lattice dropped onto the floor and settled for 0.24 s under velocity Verlet: the pile as a
// particle file (positions wrapped into the cell, ids in lattice order, box y from 0 to above
// the lattice's top).
ParticleFile settle_pile(int columns) {
  const double width = columns * spacing, top = lattice_y0 + (rows - 1) * spacing * std::sqrt(3.0) / 2;
  std::ostringstream lattice;
  lattice.precision(17);
  // A quarter spacing in: the half-offset rows end a quarter spacing short of the cell's edge,
  // so the lattice is periodic with the cell.
  lattice << "  - material: grain\n    radius: {uniform: [0.0008, 0.0012]}\n"
          << "    lattice: {kind: hexagonal, origin: [" << spacing / 4 << ", " << lattice_y0 << "], spacing: " << spacing
          << ", rows: " << rows << ", columns: " << columns << ", jitter: 0.00002, seed: 7}\n";
  BenchOptions settling;
  const Scene scene = parse_scene(bench_scene(lattice.str(), 0, width, settling), "bench_pile");
  DemSystem system(scene);
  std::vector<double> y = system.initial_state();
  auto integrator = make_integrator(scene.integrator, scene.control);
  integrator->start(system, 0, y.data(), scene.dt);
  const long steps = std::lround(settle_time / scene.dt);
  for (long k = 0; k < steps; ++k) integrator->step();

  ParticleFile pile;
  const int n = system.particles();
  for (int i = 0; i < n; ++i) {
    pile.id.push_back(i + 1);
    pile.position.push_back(system.cell().wrap({y[system.x_at() + i], y[system.y_at() + i]}));
    pile.radius.push_back(system.radius(i));
    pile.density.push_back(density);
    pile.velocity.push_back({y[system.vx_at() + i], y[system.vy_at() + i]});
    pile.angular_velocity.push_back(system.rotates() ? y[system.omega_at() + i] : 0.0);
  }
  pile.has_velocity = pile.has_angular_velocity = pile.has_box = true;
  pile.xlo = 0;
  pile.xhi = width;
  pile.ylo = 0;
  pile.yhi = top + 10 * spacing;
  return pile;
}

// A pile settled by this command for its own timing: a file in the temporary directory, removed
// when the command ends.
class TemporaryPile {
 public:
  explicit TemporaryPile(int columns)
      : path_((std::filesystem::temp_directory_path() / ("kiln_bench_pile_" + std::to_string(::getpid()) + ".data")).string()) {
    write_lammps_data(path_, settle_pile(columns), "kiln bench pile");
  }
  ~TemporaryPile() {
    std::error_code ignored;
    std::filesystem::remove(path_, ignored);
  }
  TemporaryPile(const TemporaryPile&) = delete;
  TemporaryPile& operator=(const TemporaryPile&) = delete;
  const std::string& path() const { return path_; }

 private:
  std::string path_;
};

// The x range of a pile file's box, over which the cell is periodic (the file is read again as
// the scene's particle set; this copy is gone before the run, so as not to count in its memory).
std::pair<double, double> periodic_range(const std::string& path) {
  const ParticleFile pile = read_particle_file(path, ParticleFileFormat::lammps, {INT_MAX, density});
  if (!pile.has_box)
    throw InputError({path, 0, ""}, "--pile needs the box ('xlo xhi' and 'ylo yhi' header lines): the cell is periodic over xlo..xhi");
  return {pile.xlo, pile.xhi};
}

// The timed run is a run of the scene as `kiln run` makes it, without files: the guard's checks
// after every step, a finite-state check every 64 steps, and a frame (energy check, ledger,
// contact count) every 1,000 steps. Only what users trust a run for counts toward a figure.
int time_pile(const std::string& path, const BenchOptions& o) {
  const auto [x0, x1] = periodic_range(path);
  std::ostringstream entry;
  entry << "  - material: grain\n    file: " << nlohmann::json(std::filesystem::absolute(path).string()).dump() << "\n";
  if (o.thermal) {
    entry.precision(17);
    entry << "    temperature: {x_split: " << (x0 + x1) / 2 << ", left: 100, right: 0}\n";
  }
  const long frame_every = 1000;
  Scene scene = parse_scene(bench_scene(entry.str(), x0, x1, o), "bench_pile");
  scene.t_end = static_cast<double>(o.warmup + o.steps) * scene.dt;
  scene.output_interval = static_cast<double>(frame_every) * scene.dt;
  RunOptions run;
  run.quiet = true;
  run.time_from_step = o.warmup;
  const StabilityEstimate estimate = estimate_stability(scene);
  const double start_rss = peak_rss_mb();
  const bool apart = restart_resident_peak();
  run.estimate = &estimate;
  const nlohmann::json summary = run_scene(scene, run);
  const double run_rss = apart ? resident_peak_mb() : -1;
  const double rss = apart ? std::max(start_rss, run_rss) : peak_rss_mb();
  const nlohmann::json& timed = summary.at("timed");
  const long steps = timed.at("steps"), rhs = timed.at("rhs_evals"), rebuilds = timed.at("neighbour_rebuilds");
  const double loop = timed.at("seconds");
  const int n = summary.at("particles");
  const double rate = n * static_cast<double>(steps) / loop;
  // At the end of the timed steps, as LAMMPS' contact/atom counts them: disc-disc contacts at both
  // ends; the floor's apart.
  const double per_disc = 2.0 * timed.at("particle_contacts").get<double>() / n;
  const double floor_per_disc = timed.at("wall_contacts").get<double>() / n;
  // A neighbour rebuild's cost per disc: of the rebuilds while timed, or when there were none, of
  // the run's (the first one, which builds Box2D's tree, included).
  const long all_rebuilds = summary.at("neighbour_rebuilds");
  const double rebuild_seconds = rebuilds > 0 ? timed.at("neighbour_update_seconds").get<double>()
                                              : summary.at("profile").at("seconds").at("neighbour_update").get<double>();
  const double rebuild_ns = 1e9 * rebuild_seconds / (static_cast<double>(std::max(1L, rebuilds > 0 ? rebuilds : all_rebuilds)) * n);
  const char* model = o.thermal ? (o.flowing ? "flowing+thermal" : "thermal") : (o.flowing ? "flowing" : "resting");
  std::printf("bench_pile (%s, %s): %d discs from %s, periodic in x over [%g, %g] m; %ld timed steps of %g s after %ld warm-up steps, "
              "run with its checks (every step), ledger and a frame every %ld steps\n",
              model, o.integrator.c_str(), n, path.c_str(), x0, x1, steps, scene.dt, o.warmup, frame_every);
  std::printf("  loop time %.3f s, %.3g particle-steps/s (%.1f ns per particle-step), %.2f right-hand sides per step\n",
              loop, rate, 1e9 / rate, double(rhs) / steps);
  char run_peak[64] = "not measured here (no /proc/self/clear_refs)";
  if (apart) std::snprintf(run_peak, sizeof run_peak, "%.1f MB (its system, lists and steps)", run_rss);
  std::printf("  peak RSS %.1f MB: %.1f MB up to the end of the stability estimate before the run, the run itself %s\n", rss,
              start_rss, run_peak);
  const long reorders = summary.at("curve_reorders");
  std::printf("  %.3f contacts per disc (particle-particle, at both ends, at the end), %.3f with the floor; %ld neighbour rebuilds while timed, %.0f ns per disc each; "
              "particle order ranked along the curve %ld times in the run\n",
              per_disc, floor_per_disc, rebuilds, rebuild_ns, reorders);
  std::printf("kiln-bench: n=%d steps=%ld warmup=%ld integrator=%s model=%s loop_s=%.6f particle_steps_per_s=%.6g "
              "ns_per_particle_step=%.4f rhs_evals=%ld s_per_rhs=%.6g s_per_step=%.6g peak_rss_mb=%.2f run_rss_mb=%.2f "
              "contacts_per_disc=%.4f wall_contacts_per_disc=%.4f rebuilds=%ld rebuild_ns_per_disc=%.1f curve_reorders=%ld\n",
              n, steps, o.warmup, o.integrator.c_str(), model, loop, rate, 1e9 / rate, rhs, rhs > 0 ? loop / rhs : 0.0,
              loop / steps, rss, run_rss, per_disc, floor_per_disc, rebuilds, rebuild_ns, reorders);
  return exit_success;
}

}  // namespace

int run_bench(const BenchOptions& o) {
  make_integrator(o.integrator);  // an unknown name fails here, naming the valid ones
  if (!o.write_pile.empty()) {
    const auto start = std::chrono::steady_clock::now();
    const ParticleFile pile = settle_pile(o.columns);
    write_lammps_data(o.write_pile, pile, "kiln bench pile: " + std::to_string(rows) + " rows x " +
                                              std::to_string(o.columns) + " columns, settled 0.24 s");
    std::printf("settled %d discs for %g s in %.1f s (velocity Verlet); wrote %s (box x [%g, %g] m, y [%g, %g] m)\n",
                pile.size(), settle_time, seconds_since(start), o.write_pile.c_str(), pile.xlo, pile.xhi, pile.ylo, pile.yhi);
    return exit_success;
  }
  if (!o.pile.empty()) return time_pile(o.pile, o);
  const TemporaryPile pile(o.columns);
  return time_pile(pile.path(), o);
}

}  // namespace kiln
