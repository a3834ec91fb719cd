// `kiln bench`: particle-steps per second on the benchmark pile (src/app/bench.h).
#include "src/app/bench.h"
#include "src/app/command.h"
#include "src/app/command_options.h"

namespace kiln {

namespace {

class BenchCommand final : public Command {
 public:
  explicit BenchCommand(CLI::App& app)
      : Command(app.add_subcommand("bench", "particle-steps per second on the benchmark pile (README: Performance)")) {
    // The period must hold four of the largest diameters (2.4 mm): 4 columns of 2.5 mm.
    cli_->add_option("--columns", bench_.columns, "lattice columns: 50 rows x columns discs (20: 1,000; 200: 10,000)")
        ->check(CLI::Range(4, 4000));
    cli_->add_option("--pile", bench_.pile,
                     "time this settled pile (LAMMPS data file, atom_style sphere) instead of settling one")
        ->check(CLI::ExistingFile)
        ->excludes("--columns");
    CLI::Option* write_pile =
        cli_->add_option("--write-pile", bench_.write_pile,
                         "settle the pile of --columns and write it here (LAMMPS data file); no timing")
            ->excludes("--pile");
    // What times a pile does not apply to writing one.
    for (CLI::Option* timing :
         {cli_->add_option("--steps", bench_.steps, "timed steps")->check(CLI::Range(1, 100000000)),
          cli_->add_option("--warmup", bench_.warmup, "untimed steps before them")->check(CLI::Range(0, 100000000)),
          cli_->add_flag("--flowing", bench_.flowing, "tilt gravity 30 degrees toward +x"),
          cli_->add_flag("--thermal", bench_.thermal, "a hot and a cold half, heat conducted through the contacts"),
          cli_->add_option("--integrator", bench_.integrator,
                           "integrator (see 'kiln integrators'; ARKODE at the fixed dt)")
              ->check(integrator_name)})
      timing->excludes(write_pile);
  }
  int run() override { return run_bench(bench_); }

 private:
  BenchOptions bench_;
};

}  // namespace

std::unique_ptr<Command> add_bench_command(CLI::App& app) { return std::make_unique<BenchCommand>(app); }

}  // namespace kiln
