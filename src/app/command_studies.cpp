// `kiln order`, `kiln sweep` and `kiln wp`: the studies of integrators on a scene
// (src/studies/), which share their options, their output directory and the ranks of mpirun.
#include "src/app/command.h"
#include "src/app/command_options.h"
#include "src/base/atomic_write.h"
#include "src/base/error.h"
#include "src/base/figure_script.h"
#include "src/base/progress.h"
#include "src/scene/scene_yaml.h"
#include "src/studies/study_order.h"
#include "src/studies/study_ranks.h"
#include "src/studies/study_recommend.h"
#include "src/studies/study_sweep.h"
#include "src/studies/study_wp.h"

namespace kiln {

namespace {

template <class Options>
class StudyCommand final : public Command {
 public:
  using Study = nlohmann::json (*)(const Options&);
  // The options every study shares: the scene, its overrides, end time, output, threads.
  StudyCommand(CLI::App& app, const char* name, const char* summary, Study study)
      : Command(app.add_subcommand(name, summary)), name_(name), study_(study) {
    cli_->add_option("scene", o_.scene, "scene file (YAML)")->required()->check(CLI::ExistingFile);
    cli_->add_option("--t-end", o_.t_end, "end time (s); default the scene's")->check(positive_finite);
    cli_->add_option("--out", o_.out_dir, std::string("output directory (default out/<scene name>/") + name + ")");
    cli_->add_option("--threads", o_.threads, "worker threads")->check(CLI::Range(1, 1024));
    cli_->add_option("--set", o_.sets, "override a scene value: KEY=VALUE")->take_all();
    cli_->add_flag("--quiet", o_.quiet, "no table and no progress");
    cli_->add_flag("--heat-stage", o_.heat_stage,
                   "vary the frozen heating stage (freeze.integrator, freeze.dt); the settling keeps the scene's");
    cli_->add_option("--seeds", seeds_,
                     "chaotic scenes: run each point as an ensemble of N members (ensemble_member = 0..N-1), or 'auto' "
                     "(with --se)");
    cli_->add_option("--se", se_, "with --seeds auto: add members until each mean's standard error is below this")
        ->check(positive_finite);
    cli_->add_option("--max-seeds", max_seeds_, "the cap of --seeds auto, and of recommend's grown ensembles (default 64)");
    cli_->add_option("--level", level_, "confidence level of intervals and tests (default 0.95)");
    cli_->add_option("--tolerance", tolerance_, "the bias you accept, in the quantity's unit (ensembles)");
  }
  CLI::App* cli() { return cli_; }
  Options& options() { return o_; }

  // Under mpirun the study's runs are spread over the ranks (src/studies/study_ranks.h), and rank 0
  // alone prints and writes, into out/<scene name>/<study> unless --out says otherwise. Every exit
  // from here on goes through finish_ranks (main's too), so that no rank waits for one that has failed.
  int run() override {
    o_.ensemble = ensemble_options(seeds_, se_, max_seeds_, cli_->count("--max-seeds") > 0, level_, tolerance_,
                                   cli_->count("--tolerance") > 0);
    o_.ensemble.level_given = cli_->count("--level") > 0;
    start_ranks();
    if (o_.out_dir.empty()) o_.out_dir = "out/" + load_scene(o_.scene, o_.sets).name + "/" + name_;
    if (this_rank() != 0) {
      o_.out_dir.clear();
      o_.quiet = true;
      silence_progress();
    } else {
      require_writable_directory(o_.out_dir, "--out");
    }
    try {
      study_(o_);
    } catch (const FigureError& e) {  // the JSON and CSV are written, the plot not: one line, its exit code
      return finish_ranks(e.status, std::string("error: ") + e.what());
    }
    return finish_ranks(exit_success, "");
  }

 private:
  std::string name_;
  Study study_;
  Options o_;
  std::string seeds_;
  double se_ = 0, level_ = 0.95, tolerance_ = 0;
  int max_seeds_ = 64;
};

// What order and wp compare: the quantity, and the reference with its tolerance when it is a fine run.
template <class Options>
void add_reference_options(CLI::App* cli, Options& o, const char* references) {
  cli->add_option("--quantity", o.quantity,
                  "position, velocity, temperature or a case quantity (default: temperature on a frozen scene, "
                  "else position)");
  cli->add_option("--reference", o.reference, references);
  cli->add_option("--fine-rtol", o.fine_rtol, "tolerance of the fine reference (default 1e-11)")
      ->check(relative_tolerance);
}

}  // namespace

std::unique_ptr<Command> add_order_command(CLI::App& app) {
  auto command = std::make_unique<StudyCommand<OrderOptions>>(
      app, "order", "observed orders of integrators on a scene (order.json, .csv, .png)", run_order_study);
  CLI::App* cli = command->cli();
  OrderOptions& o = command->options();
  cli->add_option("--integrators", o.integrators, "comma-separated names (see 'kiln integrators')")
      ->required()
      ->delimiter(',')
      ->check(integrator_name);
  cli->add_option("--dt", o.dt, "the coarsest step (s)")->required()->check(positive_finite);
  cli->add_option("--levels", o.levels, "number of step sizes")->check(CLI::Range(2, 30));
  cli->add_option("--ratio", o.ratio, "dt_{k+1} = dt_k / ratio (default 2)")->check(CLI::Range(1.01, 1000.0));
  add_reference_options(cli, o, "analytic | richardson | fine");
  return command;
}

std::unique_ptr<Command> add_sweep_command(CLI::App& app) {
  auto command = std::make_unique<StudyCommand<SweepOptions>>(
      app, "sweep", "time-step sensitivity and stability boundary (sweep.json, .csv, .png)", run_sweep_study);
  CLI::App* cli = command->cli();
  SweepOptions& o = command->options();
  cli->add_option("--integrator", o.integrator, "integrator name")->required()->check(integrator_name);
  cli->add_option("--dt-min", o.dt_min, "smallest step (s)")->required()->check(positive_finite);
  cli->add_option("--dt-max", o.dt_max, "largest step (s)")->required()->check(positive_finite);
  cli->add_option("--points", o.points, "steps, log-spaced")->check(CLI::Range(2, 200));
  cli->add_option("--quantity", o.quantities, "quantities (default: the case's)")->take_all();
  return command;
}

std::unique_ptr<Command> add_wp_command(CLI::App& app) {
  auto command = std::make_unique<StudyCommand<WorkPrecisionOptions>>(
      app, "wp", "work-precision: error against cost (wp.json, .csv, .png)", run_work_precision);
  CLI::App* cli = command->cli();
  WorkPrecisionOptions& o = command->options();
  cli->add_option("--integrators", o.integrators, "comma-separated names")->required()->delimiter(',')->check(integrator_name);
  cli->add_option("--dts", o.dts, "fixed steps (s)")->delimiter(',')->check(positive_finite);
  cli->add_option("--rtols", o.rtols, "tolerances (adaptive)")->delimiter(',')->check(relative_tolerance);
  add_reference_options(cli, o, "analytic | fine");
  cli->add_option("--repeats", o.repeats, "timed runs after a warm-up")->check(CLI::Range(1, 1000));
  return command;
}

std::unique_ptr<Command> add_recommend_command(CLI::App& app) {
  auto command = std::make_unique<StudyCommand<RecommendOptions>>(
      app, "recommend", "the cheapest integrator and step that meet --tolerance on a quantity (recommend.json, .csv, .png)",
      run_recommend);
  CLI::App* cli = command->cli();
  RecommendOptions& o = command->options();
  cli->add_option("--quantity", o.quantity, "the quantity (a case number, or position, velocity, temperature)")
      ->required();
  cli->add_option("--integrators", o.integrators, "candidates (default velocity-verlet,erk2,erk4)")
      ->delimiter(',')
      ->check(integrator_name);
  cli->add_option("--budget", o.budget, "CPU seconds for the probe's runs (default: none)")->check(positive_finite);
  cli->add_option("--halvings", o.halvings, "steps probed per candidate, from 0.9 of its limit (default 6)")
      ->check(CLI::Range(1, 20));
  cli->add_option("--fine-rtol", o.fine_rtol, "tolerance of the fine reference (scenes without randomness)")
      ->check(relative_tolerance);
  return command;
}

}  // namespace kiln
