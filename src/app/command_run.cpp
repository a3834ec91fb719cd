// `kiln run`: a scene to its end (or from a checkpoint on), with its outputs, and its movie.
#include <csignal>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "src/app/command.h"
#include "src/app/command_options.h"
#include "src/base/error.h"
#include "src/base/snapshot.h"
#include "src/base/stop_signal.h"
#include "src/base/text_format.h"
#include "src/dem/stage_profile.h"
#include "src/run/simulation.h"
#include "src/run/stability.h"
#include "src/scene/overrides.h"
#include "src/scene/scene_yaml.h"

namespace kiln {

namespace {

// "N steps of dt s" for each stage the run took, saying where a step differed from dt: adaptive
// steps, and a last step shortened to end on t_end.
std::string describe_steps(const nlohmann::json& stage, double dt, bool adaptive) {
  const nlohmann::json& h = stage["step_size"];
  const long n = h["steps"].get<long>();
  char text[200];
  if (n == 0) return "no steps";
  if (adaptive) {
    std::snprintf(text, sizeof text, "%ld adaptive steps (%.3g to %.3g s, mean %.3g s)", n, h["min"].get<double>(),
                  h["max"].get<double>(), h["mean"].get<double>());
  } else if (h["last"].get<double>() < dt * (1 - 1e-4)) {  // closer: dt less ARKODE's summed round-off
    std::snprintf(text, sizeof text, "%ld steps of %g s (the last %.3g s, to end on t_end)", n, dt,
                  h["last"].get<double>());
  } else {
    std::snprintf(text, sizeof text, "%ld steps of %g s", n, dt);
  }
  std::string described = text;
  if (stage.contains("steps_capped_by_skin") && stage["steps_capped_by_skin"].get<long>() > 0) {
    // Then the step follows the skin, not the tolerance: a study of rtol would measure the skin.
    std::snprintf(text, sizeof text, "; %ld of them capped by the neighbour skin (skin / (8 x fastest speed))",
                  stage["steps_capped_by_skin"].get<long>());
    described += text;
  }
  if (stage.contains("contact_events") && stage["contact_events"].get<long>() > 0) {
    std::snprintf(text, sizeof text, "; %ld contact events cut a step and restarted the steps there (smallest %.3g s)",
                  stage["contact_events"].get<long>(), h["min"].get<double>());
    described += text;
  }
  return described;
}

struct RunArgs {
  std::string out;
  bool quiet = false, force = false, profile = false;
  double checkpoint_every = 0;
  std::string restart;  // a checkpoint to go on from
  std::string movie;    // a field to draw the movie by when the run ends, or ""
};

std::string read_text(const std::string& path) { return read_scene_text(path); }

// The summary line of a run that ended, or where a stopped one stopped and how to go on.
void report_run(const Scene& scene, const nlohmann::json& s, const std::string& out, bool quiet) {
  if (s["stopped_early"] == "signal") {
    std::fprintf(stderr, "%s: stopped by %s at t = %.6g s after %ld steps; frames, wall loads, summary and picture in %s/; "
                 "go on with: kiln run --restart %s\n", scene.name.c_str(), s["stopped_by"].get<std::string>().c_str(),
                 s["t_end"].get<double>(), s["steps"].get<long>(), out.c_str(), s["checkpoint"].get<std::string>().c_str());
    return;
  }
  if (quiet) return;
  const bool adaptive = scene.control.rtol > 0;
  const nlohmann::json& stats = s["integrator_stats"];
  std::string steps = describe_steps(stats, scene.dt, adaptive);
  std::string integrators = scene.integrator;
  if (stats.contains("heat_stage")) {
    const std::string heat = stats["heat_stage"]["integrator"].get<std::string>();
    steps += ", then " + describe_steps(stats["heat_stage"], scene.freeze.dt, adaptive) + " of frozen heating";
    if (heat != scene.integrator) integrators += " (heating: " + heat + ")";
  }
  std::printf("%s: %s with %s, %.3g s wall (%.3g particle-steps/s); energy balance error %.3g J; "
              "outputs in %s/\n",
              scene.name.c_str(), steps.c_str(), integrators.c_str(), s["wall_seconds"].get<double>(),
              s["particle_steps_per_second"].get<double>(), s["energy"]["balance_error"].get<double>(), out.c_str());
}

class RunCommand final : public Command {
 public:
  explicit RunCommand(CLI::App& app)
      : Command(app.add_subcommand(
            "run", "run a scene and write result.h5, result.xdmf, summary.json, picture.png, checkpoint.h5")) {
    add_scene_options(cli_, scene_args_);
    cli_->add_option("--out", run_args_.out, "output directory (default out/<scene name>)");
    cli_->add_flag("--quiet", run_args_.quiet, "no progress or summary line");
    cli_->add_flag("--profile", run_args_.profile,
                   "print the wall time of each stage of the step (also in summary.json as `profile`)");
    cli_->add_flag("--force", run_args_.force,
                   "run even when dt is beyond the estimated limit or the step count beyond its limit");
    cli_->add_option("--checkpoint-every", run_args_.checkpoint_every,
                     "write checkpoint.h5 every this many seconds of simulated time (always at the end and on "
                     "SIGINT/SIGTERM)")
        ->check(positive_finite);
    cli_->add_option("--restart", run_args_.restart, "go on from DIR/checkpoint.h5, appending to DIR/result.h5")
        ->check(CLI::ExistingFile);
    cli_->add_option("--movie", run_args_.movie,
                     "when the run ends, draw its frames coloured by this field into OUT/movie/ and OUT/movie.mp4 "
                     "(as 'kiln movie')")
        ->check(CLI::IsMember(movie_fields()));
  }

  int run() override {
    const SceneArgs& a = scene_args_;
    const RunArgs& r = run_args_;
    RunOptions options;
    options.quiet = r.quiet;
    options.checkpoint_every = r.checkpoint_every;
    options.stop_on_signal = true;
    Scene scene;
    Snapshot checkpoint;
    std::string out = r.out;
    if (!r.restart.empty()) {
      // The scene is the checkpoint's; only the end time may change (and the output options).
      if (!a.integrator.empty() || a.dt > 0 || a.rtol > 0 || a.atol > 0 || a.contact_events || !a.sets.empty() ||
          !out.empty())
        throw InputError("--restart: the scene, its steps and its output directory are the checkpoint's; only "
                         "--t-end, --checkpoint-every, --quiet and --movie may be given with it");
      checkpoint = Snapshot::read(r.restart);
      std::vector<std::string> sets;
      if (a.t_end > 0) sets.push_back(assignment("t_end", a.t_end));
      scene = scene_of_checkpoint(checkpoint, sets, options.source);
      if (!a.path.empty() && read_text(a.path) != options.source.text)
        throw InputError(r.restart + " is a checkpoint of scene file '" + options.source.file + "', not of '" +
                         a.path + "' as it now reads: run the scene from the start, or restart without it");
      out = std::filesystem::path(r.restart).parent_path().string();
      if (out.empty()) out = ".";
      options.resume = &checkpoint;
    } else {
      if (a.path.empty()) throw InputError("kiln run: give a scene file (or --restart CHECKPOINT)");
      scene = load(a);
      // Recorded with its absolute path: a restart from another directory finds the files the
      // scene names relative to itself (drawings).
      options.source = {std::filesystem::absolute(a.path).string(), read_text(a.path), overrides_of(a)};
      if (out.empty()) out = "out/" + scene.name;
    }
    if (!r.movie.empty()) check_movie_field(scene, r.movie, "--movie");  // before the run, not after
    // A checkpoint below an ulp of the time never advanced the next one: 1e-300 s looped for ever.
    if (r.checkpoint_every > 0 && scene.t_end / r.checkpoint_every > max_frames)
      throw InputError(format("--checkpoint-every %g s: t_end / it = %g s / %g s = %.3g checkpoints, more than the "
                                      "limit of %.0e; give at least %g s",
                                      r.checkpoint_every, scene.t_end, r.checkpoint_every,
                                      scene.t_end / r.checkpoint_every, max_frames, scene.t_end / max_frames));
    const StabilityEstimate estimate = estimate_stability(scene);
    options.estimate = &estimate;
    const DtVerdict verdict = judge_dt(estimate, scene.dt, scene);
    for (const std::string& w : verdict.warnings)
      std::fprintf(stderr, "%s: %s\n", verdict.unstable && !r.force ? "error" : "warning", w.c_str());
    if (verdict.unstable && !r.force) return exit_refused;
    options.out_dir = out;
    catch_stop_signals();
    const nlohmann::json s = run_scene(scene, options);
    report_run(scene, s, out, r.quiet);
    if (r.profile) std::printf("%s", profile_table(s["profile"]).c_str());
    int status = exit_success;
    if (s["stopped_early"] == "signal") status = stop_signal() == SIGINT ? exit_sigint : exit_sigterm;
    if (r.movie.empty()) return status;
    // A run stopped by a signal gets its movie too, of the frames it finished.
    std::fflush(stdout);  // the run's line before the movie's messages
    MovieOptions movie;
    movie.field = r.movie;
    movie.quiet = r.quiet;
    const int movie_status = make_movie(out, scene, movie);
    return status != exit_success ? status : movie_status;
  }

 private:
  SceneArgs scene_args_;
  RunArgs run_args_;
};

}  // namespace

std::unique_ptr<Command> add_run_command(CLI::App& app) { return std::make_unique<RunCommand>(app); }

}  // namespace kiln
