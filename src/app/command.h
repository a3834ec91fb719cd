// The subcommands of kiln, a file each (command_*.cpp; the three studies, which share their
// options, one file): each adds itself and its options to the command line, and runs when the
// command line names it. main.cpp registers them, parses and maps kiln's errors to exit statuses.
#pragma once
#include <CLI/CLI.hpp>

#include <memory>
#include <string>

#include "src/app/movie.h"
#include "src/scene/scene.h"

namespace kiln {

class Command {
 public:
  explicit Command(CLI::App* cli) : cli_(cli) {}
  virtual ~Command() = default;
  bool chosen() const { return cli_->parsed(); }
  // The exit status (src/base/error.h); bad input and failures throw kiln's errors.
  virtual int run() = 0;

 protected:
  CLI::App* cli_;
};

std::unique_ptr<Command> add_run_command(CLI::App& app);          // command_run.cpp
std::unique_ptr<Command> add_movie_command(CLI::App& app);        // command_movie.cpp
std::unique_ptr<Command> add_plot_command(CLI::App& app);         // command_plot.cpp
std::unique_ptr<Command> add_check_command(CLI::App& app);        // command_check.cpp
std::unique_ptr<Command> add_cases_command(CLI::App& app);        // command_lists.cpp
std::unique_ptr<Command> add_integrators_command(CLI::App& app);  // command_lists.cpp
std::unique_ptr<Command> add_bench_command(CLI::App& app);        // command_bench.cpp
std::unique_ptr<Command> add_order_command(CLI::App& app);        // command_studies.cpp
std::unique_ptr<Command> add_sweep_command(CLI::App& app);        // command_studies.cpp
std::unique_ptr<Command> add_wp_command(CLI::App& app);           // command_studies.cpp
std::unique_ptr<Command> add_recommend_command(CLI::App& app);    // command_studies.cpp

// What `kiln movie` does, which `kiln run --movie` does too when the run ends: draws the movie of
// the run in `dir` (src/app/movie.h) and says where it is. Returns the exit status.
int make_movie(const std::string& dir, const Scene& scene, MovieOptions options);

}  // namespace kiln
