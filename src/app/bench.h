// `kiln bench`: particle-steps per second on the benchmark pile of ../shared/BENCH.md, the pile
// the peers (LAMMPS, LIGGGHTS) run in bench/run.sh.
//
// The pile: discs with diameters uniform in [1.6, 2.4] mm, density 2500 kg/m^3 (sphere masses),
// a jittered hexagonal lattice of 50 rows x `columns` (spacing 2.5 mm) in a cell periodic in x of
// columns x 2.5 mm, dropped onto a flat frictional floor at y = 0 and settled for 0.24 s. The
// timed scene: that pile, periodic in x over the file's box, the floor a wall along y = 0, linear
// spring-dashpot kn = 1e4 N/m, gamma_n = 1.9e4 1/s (F = m_eff gamma_n v_n), k_t = 2/7 k_n,
// gamma_t = gamma_n / 2, mu = 0.5, dt = 2e-6 s, skin 0.4 mm.
#pragma once
#include <string>

namespace kiln {

struct BenchOptions {
  int columns = 20;             // 50 rows x columns discs: 20 -> 1,000, 200 -> 10,000
  std::string pile;             // time this settled pile (a LAMMPS data file); empty: settle one first
  std::string write_pile;       // settle the pile and write it here (a LAMMPS data file); no timing
  long steps = 20000;           // timed steps after the warm-up
  long warmup = 5000;           // untimed steps before them
  bool flowing = false;         // gravity tilted 30 degrees toward +x
  bool thermal = false;         // a temperature on every disc (a hot and a cold half), contact conduction
  std::string integrator = "velocity-verlet";  // ARKODE tables run at the fixed dt
};

// Prints what it measured, ending with one line "kiln-bench: key=value ..." for scripts: n, steps,
// warmup, integrator, model, loop_s, particle_steps_per_s, ns_per_particle_step, rhs_evals,
// s_per_rhs, s_per_step, peak_rss_mb, contacts_per_disc (particle-particle, at both ends, at the
// end of the timed steps, as LAMMPS' contact/atom), wall_contacts_per_disc, rebuilds (while
// timed) and rebuild_ns_per_disc (a rebuild's wall time per disc: of those while timed, else of
// the run's, the first build included). The timed steps are those of a run of the scene with its
// checks, ledger and frames, as `kiln run` makes it without files (src/run/simulation.h).
// Returns the exit code; bad options and files throw InputError.
int run_bench(const BenchOptions& options);

}  // namespace kiln
