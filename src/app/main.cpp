// kiln: the command-line program. Each subcommand is a few lines over the library.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <csignal>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>
#include <sstream>

#include "integrators/integrator.h"
#include "src/app/bench.h"
#include "src/base/error.h"
#include "src/app/movie.h"
#include "src/scene/overrides.h"
#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "src/dem/stage_profile.h"
#include "src/base/snapshot.h"
#include "src/run/stability.h"
#include "src/base/stop_signal.h"
#include "src/studies/study_order.h"
#include "src/studies/study_ranks.h"
#include "src/studies/study_sweep.h"
#include "src/studies/study_wp.h"
#include "src/base/subprocess.h"

namespace {

// A time, a step or a tolerance: a positive finite number. CLI11's PositiveNumber accepts "nan"
// (which then was ignored) and states its range as 300 digits.
const CLI::Validator positive_finite(
    [](std::string& text) {
      try {
        size_t used = 0;
        const double v = std::stod(text, &used);
        if (used == text.size() && std::isfinite(v) && v > 0) return std::string();
      } catch (const std::exception&) {
      }
      return "must be a positive finite number, got '" + text + "'";
    },
    "POSITIVE");

struct SceneArgs {
  std::string path;
  std::string integrator;
  double dt = 0, t_end = 0, rtol = 0, atol = 0;
  bool contact_events = false;
  std::vector<std::string> sets;
};

// Command-line options become --set overrides, so they pass through the same checks as the file.
std::vector<std::string> overrides_of(const SceneArgs& a) {
  std::vector<std::string> sets = a.sets;
  if (!a.integrator.empty()) sets.push_back("integrator=" + a.integrator);
  if (a.dt > 0) sets.push_back(kiln::assignment("dt", a.dt));
  if (a.t_end > 0) sets.push_back(kiln::assignment("t_end", a.t_end));
  if (a.rtol > 0) sets.push_back(kiln::assignment("rtol", a.rtol));
  if (a.atol > 0) sets.push_back(kiln::assignment("atol", a.atol));
  if (a.contact_events) sets.push_back("contact_events=true");
  return sets;
}

kiln::Scene load(const SceneArgs& a) {
  kiln::Scene scene = kiln::load_scene(a.path, overrides_of(a));
  kiln::make_integrator(scene.integrator, scene.control);  // an unknown name fails before anything runs
  return scene;
}

void add_scene_options(CLI::App* cmd, SceneArgs& a) {
  cmd->add_option("scene", a.path, "scene file (YAML)")->check(CLI::ExistingFile);
  cmd->add_option("--integrator", a.integrator, "integrator name (see 'kiln integrators')");
  cmd->add_option("--dt", a.dt, "time step (s)")->check(positive_finite);
  cmd->add_option("--t-end", a.t_end, "end time (s)")->check(positive_finite);
  cmd->add_option("--rtol", a.rtol, "relative tolerance: adaptive steps from --dt (erk:/imex: methods)")
      ->check(positive_finite);
  cmd->add_option("--atol", a.atol, "absolute tolerance (per field: --set atol.temperature=...)")
      ->check(positive_finite);
  cmd->add_flag("--contact-events", a.contact_events,
                "lock the acting contacts within a step, locate onsets and releases, restart there (ARKODE)");
  cmd->add_option("--set", a.sets, "override a scene value by dotted path: KEY=VALUE")->take_all();
}

// The options every study command shares: the scene, its overrides, end time, output, threads.
template <class Options>
CLI::App* add_study(CLI::App& app, const char* name, const char* summary, Options& o) {
  CLI::App* cmd = app.add_subcommand(name, summary);
  cmd->add_option("scene", o.scene, "scene file (YAML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--t-end", o.t_end, "end time (s); default the scene's")->check(positive_finite);
  cmd->add_option("--out", o.out_dir, std::string("output directory (default out/<scene name>/") + name + ")");
  cmd->add_option("--threads", o.threads, "worker threads")->check(CLI::Range(1, 1024));
  cmd->add_option("--set", o.sets, "override a scene value: KEY=VALUE")->take_all();
  cmd->add_flag("--quiet", o.quiet, "no table and no progress");
  cmd->add_flag("--heat-stage", o.heat_stage,
                "vary the frozen heating stage (freeze.integrator, freeze.dt); the settling keeps the scene's");
  return cmd;
}

int check(const SceneArgs& a) {
  const kiln::Scene scene = load(a);
  const kiln::StabilityEstimate est = kiln::estimate_stability(scene);
  std::printf("scene %s: %d particles, %zu wall segments, integrator %s, dt %.4g s\n", scene.name.c_str(),
              scene.n_particles(), scene.segments.size(), scene.integrator.c_str(), scene.dt);
  if (scene.frozen) {
    std::printf("  mechanics frozen: no mechanical time step\n");
  } else {
    std::printf("  shortest contact duration  %.4g s (%s); dt is 1/%.1f of it\n", est.contact_duration,
                est.shortest_pair.c_str(), est.contact_duration / scene.dt);
    std::printf("  stability limit of dt      %.4g s (central difference on the stiffest contact%s)\n", est.dt_limit,
                scene.n_particles() >= 2 ? ", a disc between two: / sqrt 2" : "");
    if (std::isfinite(est.rayleigh))
      std::printf("  Rayleigh time step         %.4g s (smallest particle); dt is %.1f %% of it\n", est.rayleigh,
                  100 * scene.dt / est.rayleigh);
    else
      std::printf("  Rayleigh time step         n/a (no youngs_modulus given)\n");
    std::printf("  recommended dt             %.4g s (contact duration / 50)\n", est.recommended_dt);
  }
  if (scene.thermal) {
    std::printf("  explicit conduction limit  %.4g s (2 / lambda_max, contact network at t = 0)",
                est.thermal_dt_limit_network);
    if (!scene.frozen) std::printf(", %.4g s (dense packing at 1 %% overlap)", est.thermal_dt_limit);
    const double reach = kiln::real_stability_of(scene.integrator);
    if (std::isinf(reach))
      std::printf("\n  %-26s none (conduction implicit)", (scene.integrator + "'s limit").c_str());
    else if (reach != 2)
      std::printf("\n  %-26s %.4g s (%.4g / lambda_max: the table's reach on the negative real axis)",
                  (scene.integrator + "'s limit").c_str(), reach / 2 * est.thermal_dt_limit_network, reach);
    std::printf("\n  thermal relaxation time    %.4g s (fastest mode, 1 / lambda_max)\n", est.thermal_relaxation_time);
  }
  std::fflush(stdout);  // the verdict goes to stderr, after the table
  const kiln::DtVerdict verdict = kiln::judge_dt(est, scene.dt, scene);
  for (const std::string& w : verdict.warnings)
    std::fprintf(stderr, "%s: %s\n", verdict.unstable ? "error" : "warning", w.c_str());
  return verdict.unstable ? kiln::exit_refused : kiln::exit_success;
}

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

// Draws the movie of the run in `dir` (src/app/movie.h) and says where it is. Returns the exit status.
int make_movie(const std::string& dir, const kiln::Scene& scene, kiln::MovieOptions options) {
  options.ffmpeg = kiln::find_program("ffmpeg");
  kiln::Movie movie;
  try {
    movie = kiln::write_movie(dir, scene, options);
  } catch (const kiln::OutputError& e) {
    std::fprintf(stderr, "error: %s (no movie was published)\n", e.what());
    return kiln::exit_output_failed;
  }
  if (movie.stopped_by != 0) {
    std::fprintf(stderr, "movie of %s: stopped by %s; no frames were published\n", dir.c_str(),
                 kiln::signal_name(movie.stopped_by));
    return movie.stopped_by == SIGINT ? kiln::exit_sigint : kiln::exit_sigterm;
  }
  if (!movie.failure.empty()) {
    std::fprintf(stderr, "error: %s could not encode %s/movie.mp4 (%s); the %d frames are in %s/\n",
                 options.ffmpeg.c_str(), dir.c_str(), movie.failure.c_str(), movie.frames, movie.frames_dir.c_str());
    return kiln::exit_output_failed;
  }
  if (options.quiet) return kiln::exit_success;
  if (movie.mp4.empty())
    std::printf("movie: %d frames in %s/; installing Debian's ffmpeg (apt-get install ffmpeg) also gives "
                "%s/movie.mp4\n",
                movie.frames, movie.frames_dir.c_str(), dir.c_str());
  else
    std::printf("movie: %s (%d frames at %d per second; the frames are in %s/)\n", movie.mp4.c_str(), movie.frames,
                options.fps, movie.frames_dir.c_str());
  return kiln::exit_success;
}

// DIR/plots.png: the case quantities of the run in DIR over time (scripts/plot_case.py).
int plot(const std::string& dir, bool quiet) {
  const std::string summary = (std::filesystem::path(dir) / "summary.json").string();
  if (!std::filesystem::exists(summary))
    throw kiln::InputError("kiln plot: " + summary + " not found: give the output directory of a run (kiln run "
                           "SCENE --out DIR)");
  const kiln::ProgramResult r =
      kiln::run_program({"/usr/bin/python3", std::string(KILN_SCRIPTS_DIR) + "/plot_case.py", dir});
  std::fprintf(stderr, "%s", r.errors.c_str());  // the script's warnings and errors
  if (r.status != 0) {
    std::fprintf(stderr, "error: %s/plots.png not written (it needs Debian's /usr/bin/python3 with matplotlib and "
                         "h5py: apt-get install python3-matplotlib python3-h5py)\n", dir.c_str());
    return kiln::exit_output_failed;
  }
  if (!quiet) std::printf("plots: %s/plots.png\n", dir.c_str());
  return kiln::exit_success;
}

std::string read_text(const std::string& path) {
  std::ifstream in(path, std::ios::binary);
  std::ostringstream text;
  text << in.rdbuf();
  if (!in) throw kiln::InputError(path + ": cannot read the scene file");
  return text.str();
}

// The summary line of a run that ended, or where a stopped one stopped and how to go on.
void report_run(const kiln::Scene& scene, const nlohmann::json& s, const std::string& out, bool quiet) {
  if (s["stopped_early"] == "signal") {
    std::fprintf(stderr, "%s: stopped by %s at t = %.6g s after %ld steps; frames, summary and picture in %s/; "
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

int run(const SceneArgs& a, const RunArgs& r) {
  kiln::RunOptions options;
  options.quiet = r.quiet;
  options.checkpoint_every = r.checkpoint_every;
  options.stop_on_signal = true;
  kiln::Scene scene;
  kiln::Snapshot checkpoint;
  std::string out = r.out;
  if (!r.restart.empty()) {
    // The scene is the checkpoint's; only the end time may change (and the output options).
    if (!a.integrator.empty() || a.dt > 0 || a.rtol > 0 || a.atol > 0 || a.contact_events || !a.sets.empty() || !out.empty())
      throw kiln::InputError("--restart: the scene, its steps and its output directory are the checkpoint's; only "
                             "--t-end, --checkpoint-every, --quiet and --movie may be given with it");
    checkpoint = kiln::Snapshot::read(r.restart);
    std::vector<std::string> sets;
    if (a.t_end > 0) sets.push_back(kiln::assignment("t_end", a.t_end));
    scene = kiln::scene_of_checkpoint(checkpoint, sets, options.source);
    if (!a.path.empty() && read_text(a.path) != options.source.text)
      throw kiln::InputError(r.restart + " is a checkpoint of scene file '" + options.source.file + "', not of '" +
                             a.path + "' as it now reads: run the scene from the start, or restart without it");
    out = std::filesystem::path(r.restart).parent_path().string();
    if (out.empty()) out = ".";
    options.resume = &checkpoint;
  } else {
    if (a.path.empty()) throw kiln::InputError("kiln run: give a scene file (or --restart CHECKPOINT)");
    scene = load(a);
    // Recorded with its absolute path: a restart from another directory finds the files the
    // scene names relative to itself (drawings).
    options.source = {std::filesystem::absolute(a.path).string(), read_text(a.path), overrides_of(a)};
    if (out.empty()) out = "out/" + scene.name;
  }
  if (!r.movie.empty()) kiln::check_movie_field(scene, r.movie, "--movie");  // before the run, not after
  const kiln::DtVerdict verdict = kiln::judge_dt(kiln::estimate_stability(scene), scene.dt, scene);
  for (const std::string& w : verdict.warnings)
    std::fprintf(stderr, "%s: %s\n", verdict.unstable && !r.force ? "error" : "warning", w.c_str());
  if (verdict.unstable && !r.force) return kiln::exit_refused;
  options.out_dir = out;
  kiln::catch_stop_signals();
  const nlohmann::json s = kiln::run_scene(scene, options);
  report_run(scene, s, out, r.quiet);
  if (r.profile) std::printf("%s", kiln::profile_table(s["profile"]).c_str());
  int status = kiln::exit_success;
  if (s["stopped_early"] == "signal") status = kiln::stop_signal() == SIGINT ? kiln::exit_sigint : kiln::exit_sigterm;
  if (r.movie.empty()) return status;
  // A run stopped by a signal gets its movie too, of the frames it finished.
  std::fflush(stdout);  // the run's line before the movie's messages
  kiln::MovieOptions movie;
  movie.field = r.movie;
  movie.quiet = r.quiet;
  const int movie_status = make_movie(out, scene, movie);
  return status != kiln::exit_success ? status : movie_status;
}

int list_cases() {
  std::vector<std::filesystem::path> files;
  for (const auto& entry : std::filesystem::directory_iterator(KILN_CASES_DIR))
    if (entry.path().extension() == ".yaml") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  for (const auto& f : files) {
    const kiln::Scene scene = kiln::load_scene(f.string());
    std::printf("%-30s %s\n", f.filename().c_str(), scene.description.c_str());
  }
  std::printf("(in %s)\n", KILN_CASES_DIR);
  return 0;
}

int list_integrators() {
  std::printf("%-30s %5s %9s %9s %6s  %s\n", "name", "order", "dashpot", "embedded", "adapts", "scheme");
  for (const auto& info : kiln::integrator_catalogue())
    std::printf("%-30s %5d %9d %9s %6s  %s\n", info.name.c_str(), info.order, info.order_with_dashpot,
                info.embedding ? std::to_string(info.embedding).c_str() : "-", info.embedding ? "yes" : "no",
                info.summary.c_str());
  std::printf("(order: nominal order on smooth forces; dashpot: order when forces depend on velocity)\n");
  return 0;
}

}  // namespace

int main(int argc, char** argv) {
  CLI::App app{"kiln: 2D thermo-mechanical discrete element engine with swappable integrators"};
  app.require_subcommand(1);
  SceneArgs run_args, check_args;
  RunArgs run_opts;
  CLI::App* run_cmd = app.add_subcommand(
      "run", "run a scene and write result.h5, result.xdmf, summary.json, picture.png, checkpoint.h5");
  add_scene_options(run_cmd, run_args);
  run_cmd->add_option("--out", run_opts.out, "output directory (default out/<scene name>)");
  run_cmd->add_flag("--quiet", run_opts.quiet, "no progress or summary line");
  run_cmd->add_flag("--profile", run_opts.profile,
                    "print the wall time of each stage of the step (also in summary.json as `profile`)");
  run_cmd->add_flag("--force", run_opts.force,
                    "run even when dt is beyond the estimated limit or the step count beyond its limit");
  run_cmd->add_option("--checkpoint-every", run_opts.checkpoint_every,
                      "write checkpoint.h5 every this many seconds of simulated time (always at the end and on "
                      "SIGINT/SIGTERM)")
      ->check(positive_finite);
  run_cmd->add_option("--restart", run_opts.restart, "go on from DIR/checkpoint.h5, appending to DIR/result.h5")
      ->check(CLI::ExistingFile);
  run_cmd->add_option("--movie", run_opts.movie,
                      "when the run ends, draw its frames coloured by this field into OUT/movie/ and OUT/movie.mp4 "
                      "(as 'kiln movie')")
      ->check(CLI::IsMember(kiln::movie_fields()));
  std::string movie_dir;
  kiln::MovieOptions movie_opts;
  CLI::App* movie_cmd = app.add_subcommand(
      "movie", "draw a run's frames (DIR/result.h5) into DIR/movie/ and, with ffmpeg, DIR/movie.mp4");
  movie_cmd->add_option("dir", movie_dir, "the output directory of a run")->required()->check(CLI::ExistingDirectory);
  movie_cmd->add_option("--field", movie_opts.field, "colour the discs by speed, temperature or species (material)")
      ->check(CLI::IsMember(kiln::movie_fields()));
  movie_cmd->add_option("--fps", movie_opts.fps, "frames per second of movie.mp4 (default 25)")
      ->check(CLI::Range(1, 240));
  movie_cmd->add_flag("--quiet", movie_opts.quiet, "no progress and no closing line");
  std::string plot_dir;
  bool plot_quiet = false;
  CLI::App* plot_cmd = app.add_subcommand(
      "plot", "plot a run's case quantities over time (DIR/summary.json, DIR/result.h5) into DIR/plots.png");
  plot_cmd->add_option("dir", plot_dir, "the output directory of a run")->required()->check(CLI::ExistingDirectory);
  plot_cmd->add_flag("--quiet", plot_quiet, "no closing line");
  CLI::App* check_cmd = app.add_subcommand("check", "validate a scene and print its time-step estimates");
  add_scene_options(check_cmd, check_args);
  check_cmd->get_option("scene")->required();
  CLI::App* cases_cmd = app.add_subcommand("cases", "list the shipped cases");
  CLI::App* integrators_cmd = app.add_subcommand("integrators", "list the integrators with their orders");
  kiln::BenchOptions bench;
  CLI::App* bench_cmd = app.add_subcommand("bench", "particle-steps per second on the benchmark pile (README: Performance)");
  // The period must hold four of the largest diameters (2.4 mm): 4 columns of 2.5 mm.
  bench_cmd->add_option("--columns", bench.columns, "lattice columns: 50 rows x columns discs (20: 1,000; 200: 10,000)")
      ->check(CLI::Range(4, 4000));
  bench_cmd->add_option("--pile", bench.pile, "time this settled pile (LAMMPS data file, atom_style sphere) instead of settling one")
      ->check(CLI::ExistingFile)
      ->excludes("--columns");
  CLI::Option* write_pile =
      bench_cmd->add_option("--write-pile", bench.write_pile, "settle the pile of --columns and write it here (LAMMPS data file); no timing")
          ->excludes("--pile");
  // What times a pile does not apply to writing one.
  for (CLI::Option* timing :
       {bench_cmd->add_option("--steps", bench.steps, "timed steps")->check(CLI::Range(1, 100000000)),
        bench_cmd->add_option("--warmup", bench.warmup, "untimed steps before them")->check(CLI::Range(0, 100000000)),
        bench_cmd->add_flag("--flowing", bench.flowing, "tilt gravity 30 degrees toward +x"),
        bench_cmd->add_flag("--thermal", bench.thermal, "a hot and a cold half, heat conducted through the contacts"),
        bench_cmd->add_option("--integrator", bench.integrator, "integrator (see 'kiln integrators'; ARKODE at the fixed dt)")})
    timing->excludes(write_pile);
  kiln::OrderOptions order;
  CLI::App* order_cmd = add_study(app, "order", "observed orders of integrators on a scene (order.json, .csv, .png)", order);
  order_cmd->add_option("--integrators", order.integrators, "comma-separated names (see 'kiln integrators')")
      ->required()
      ->delimiter(',');
  order_cmd->add_option("--dt", order.dt, "the coarsest step (s)")->required()->check(positive_finite);
  order_cmd->add_option("--levels", order.levels, "number of step sizes")->check(CLI::Range(2, 30));
  order_cmd->add_option("--ratio", order.ratio, "dt_{k+1} = dt_k / ratio (default 2)")->check(CLI::Range(1.01, 1000.0));
  order_cmd->add_option("--quantity", order.quantity,
                        "position, velocity, temperature or a case quantity (default: temperature on a frozen scene, "
                        "else position)");
  order_cmd->add_option("--reference", order.reference, "analytic | richardson | fine");
  order_cmd->add_option("--fine-rtol", order.fine_rtol, "tolerance of the fine reference (default 1e-11)")
      ->check(positive_finite);
  kiln::SweepOptions sweep;
  CLI::App* sweep_cmd =
      add_study(app, "sweep", "time-step sensitivity and stability boundary (sweep.json, .csv, .png)", sweep);
  sweep_cmd->add_option("--integrator", sweep.integrator, "integrator name")->required();
  sweep_cmd->add_option("--dt-min", sweep.dt_min, "smallest step (s)")->required()->check(positive_finite);
  sweep_cmd->add_option("--dt-max", sweep.dt_max, "largest step (s)")->required()->check(positive_finite);
  sweep_cmd->add_option("--points", sweep.points, "steps, log-spaced")->check(CLI::Range(2, 200));
  sweep_cmd->add_option("--quantity", sweep.quantities, "quantities (default: the case's)")->take_all();
  kiln::WorkPrecisionOptions wp;
  CLI::App* wp_cmd = add_study(app, "wp", "work-precision: error against cost (wp.json, .csv, .png)", wp);
  wp_cmd->add_option("--integrators", wp.integrators, "comma-separated names")->required()->delimiter(',');
  wp_cmd->add_option("--dts", wp.dts, "fixed steps (s)")->delimiter(',')->check(positive_finite);
  wp_cmd->add_option("--rtols", wp.rtols, "tolerances (adaptive)")->delimiter(',')->check(positive_finite);
  wp_cmd->add_option("--quantity", wp.quantity,
                     "position, velocity, temperature or a case quantity (default: temperature on a frozen scene, "
                     "else position)");
  wp_cmd->add_option("--reference", wp.reference, "analytic | fine");
  wp_cmd->add_option("--fine-rtol", wp.fine_rtol, "tolerance of the fine reference (default 1e-11)")
      ->check(positive_finite);
  wp_cmd->add_option("--seeds", wp.seeds, "chaotic scenes: average a scalar over this many fills (noise floor shown)");
  wp_cmd->add_option("--seed-key", wp.seed_key, "the key --seeds varies (default particles.0.fill.seed)");
  wp_cmd->add_option("--repeats", wp.repeats, "timed runs after a warm-up")->check(CLI::Range(1, 1000));
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; a bad argument is bad input.
    return app.exit(e) == 0 ? kiln::exit_success : kiln::exit_bad_input;
  }
  try {
    if (*run_cmd) return run(run_args, run_opts);
    if (*movie_cmd) {
      return make_movie(movie_dir, kiln::scene_of_run(movie_dir), movie_opts);
    }
    if (*plot_cmd) return plot(plot_dir, plot_quiet);
    if (*check_cmd) return check(check_args);
    if (*cases_cmd) return list_cases();
    if (*integrators_cmd) return list_integrators();
    if (*bench_cmd) return kiln::run_bench(bench);
    // A study: under mpirun its runs are spread over the ranks (src/studies/study_ranks.h), and rank 0
    // alone prints and writes, into out/<scene name>/<study> unless --out says otherwise. Every
    // exit from here on goes through finish_ranks, so that no rank waits for one that has failed.
    kiln::start_ranks();
    auto prepare = [](auto& study, const char* name) {
      if (study.out_dir.empty()) study.out_dir = "out/" + kiln::load_scene(study.scene, study.sets).name + "/" + name;
      if (kiln::this_rank() != 0) {
        study.out_dir.clear();
        study.quiet = true;
      }
    };
    if (*order_cmd) {
      prepare(order, "order");
      kiln::run_order_study(order);
    } else if (*sweep_cmd) {
      prepare(sweep, "sweep");
      kiln::run_sweep_study(sweep);
    } else if (*wp_cmd) {
      prepare(wp, "wp");
      kiln::run_work_precision(wp);
    }
    return kiln::finish_ranks(kiln::exit_success, "");
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
