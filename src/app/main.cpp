// kiln: the command-line program. Each subcommand is a file over the library (src/app/command.h);
// here they are registered, the line parsed and kiln's errors mapped to exit statuses.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <csignal>
#include <cstdio>
#include <memory>
#include <string>
#include <vector>

#include "src/app/command.h"
#include "src/base/error.h"
#include "src/base/nearest.h"
#include "src/base/progress.h"
#include "src/studies/study_ranks.h"

int main(int argc, char** argv) {
  // A file-size limit (ulimit -f) is a full disk by another name: with SIGXFSZ ignored the write
  // fails with EFBIG and the run keeps its finished work and says so (exit 4); by default the
  // signal killed the process without a word (issue 28's review).
  std::signal(SIGXFSZ, SIG_IGN);
  CLI::App app{"kiln: 2D thermo-mechanical discrete element engine with swappable integrators"};
  app.require_subcommand(1);
  std::vector<std::unique_ptr<kiln::Command>> commands;
  for (auto add : {kiln::add_run_command, kiln::add_movie_command, kiln::add_plot_command, kiln::add_check_command,
                   kiln::add_cases_command, kiln::add_integrators_command, kiln::add_bench_command,
                   kiln::add_order_command, kiln::add_sweep_command, kiln::add_wp_command,
                   kiln::add_recommend_command})
    commands.push_back(add(app));
  // A first word that is no command ("kiln chek"): CLI11 answers "A subcommand is required", which
  // does not say that the word was read, nor what the commands are.
  if (argc > 1 && argv[1][0] != '-') {
    std::vector<std::string> names;
    for (const CLI::App* sub : app.get_subcommands({})) names.push_back(sub->get_name());
    if (std::find(names.begin(), names.end(), argv[1]) == names.end()) {
      std::fprintf(stderr, "error: '%s' is not a kiln command; the commands are %s (kiln --help says what each does)\n",
                   std::string(argv[1]).substr(0, 100).c_str(), kiln::choices_nearest_first(argv[1], names).c_str());
      return kiln::exit_bad_input;
    }
  }
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; a bad argument is bad input.
    return app.exit(e) == 0 ? kiln::exit_success : kiln::exit_bad_input;
  }
  // --quiet silences every progress line, those of a scene's loading and checks included.
  for (const CLI::App* sub : app.get_subcommands())
    if (const CLI::Option* quiet = sub->get_option_no_throw("--quiet"); quiet && quiet->count() > 0)
      kiln::silence_progress();
  // Every error ends through finish_ranks: a study under mpirun (src/studies/study_ranks.h) tells
  // the other ranks, which would otherwise wait for this one; elsewhere it prints the message.
  try {
    const auto chosen = std::find_if(commands.begin(), commands.end(), [](const auto& c) { return c->chosen(); });
    return (*chosen)->run();
  } catch (const kiln::InputError& e) {
    return kiln::finish_ranks(kiln::exit_bad_input, std::string("error: ") + e.what());
  } catch (const kiln::InstabilityError& e) {
    return kiln::finish_ranks(kiln::exit_unstable, std::string("error: ") + e.what());
  } catch (const kiln::OutputError& e) {
    return kiln::finish_ranks(kiln::exit_output_failed,
                              std::string("error: ") + e.what() + " (nothing was published under a final name)");
  } catch (const kiln::StudyError& e) {
    return kiln::finish_ranks(kiln::exit_study_failed, std::string("error: ") + e.what());
  } catch (const std::exception& e) {
    return kiln::finish_ranks(kiln::exit_internal, std::string("error (internal, please report it): ") + e.what());
  }
}
