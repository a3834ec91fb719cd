// kiln: the command-line program. Each subcommand is a few lines over the library.
#include <CLI/CLI.hpp>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <fstream>
#include <iostream>

#include "integrators/integrator.h"
#include "src/bench.h"
#include "src/error.h"
#include "src/overrides.h"
#include "src/scene_yaml.h"
#include "src/simulation.h"
#include "src/stability.h"
#include "src/study_order.h"
#include "src/study_sweep.h"
#include "src/study_wp.h"

namespace {

struct SceneArgs {
  std::string path;
  std::string integrator;
  double dt = 0, t_end = 0, rtol = 0, atol = 0;
  bool contact_events = false;
  std::vector<std::string> sets;
};

// Command-line options become --set overrides, so they pass through the same checks as the file.
kiln::Scene load(const SceneArgs& a) {
  std::vector<std::string> sets = a.sets;
  if (!a.integrator.empty()) sets.push_back("integrator=" + a.integrator);
  if (a.dt > 0) sets.push_back(kiln::assignment("dt", a.dt));
  if (a.t_end > 0) sets.push_back(kiln::assignment("t_end", a.t_end));
  if (a.rtol > 0) sets.push_back(kiln::assignment("rtol", a.rtol));
  if (a.atol > 0) sets.push_back(kiln::assignment("atol", a.atol));
  if (a.contact_events) sets.push_back("contact_events=true");
  kiln::Scene scene = kiln::load_scene(a.path, sets);
  kiln::make_integrator(scene.integrator, scene.control);  // an unknown name fails before anything runs
  return scene;
}

void add_scene_options(CLI::App* cmd, SceneArgs& a) {
  cmd->add_option("scene", a.path, "scene file (YAML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--integrator", a.integrator, "integrator name (see 'kiln integrators')");
  cmd->add_option("--dt", a.dt, "time step (s)")->check(CLI::PositiveNumber);
  cmd->add_option("--t-end", a.t_end, "end time (s)")->check(CLI::PositiveNumber);
  cmd->add_option("--rtol", a.rtol, "relative tolerance: adaptive steps from --dt (erk:/imex: methods)")
      ->check(CLI::PositiveNumber);
  cmd->add_option("--atol", a.atol, "absolute tolerance (per field: --set atol.temperature=...)")
      ->check(CLI::PositiveNumber);
  cmd->add_flag("--contact-events", a.contact_events,
                "lock the acting contacts within a step, locate onsets and releases, restart there (ARKODE)");
  cmd->add_option("--set", a.sets, "override a scene value by dotted path: KEY=VALUE")->take_all();
}

// The options every study command shares: the scene, its overrides, end time, output, threads.
template <class Options>
CLI::App* add_study(CLI::App& app, const char* name, const char* summary, Options& o) {
  CLI::App* cmd = app.add_subcommand(name, summary);
  cmd->add_option("scene", o.scene, "scene file (YAML)")->required()->check(CLI::ExistingFile);
  cmd->add_option("--t-end", o.t_end, "end time (s); default the scene's")->check(CLI::PositiveNumber);
  cmd->add_option("--out", o.out_dir, std::string("output directory (default out/<scene name>/") + name + ")");
  cmd->add_option("--threads", o.threads, "worker threads")->check(CLI::PositiveNumber);
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
  return verdict.unstable ? 1 : 0;
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

int run(const SceneArgs& a, std::string out, bool quiet, bool force) {
  const kiln::Scene scene = load(a);
  const kiln::DtVerdict verdict = kiln::judge_dt(kiln::estimate_stability(scene), scene.dt, scene);
  for (const std::string& w : verdict.warnings)
    std::fprintf(stderr, "%s: %s\n", verdict.unstable && !force ? "error" : "warning", w.c_str());
  if (verdict.unstable && !force) return 1;
  if (out.empty()) out = "out/" + scene.name;
  const nlohmann::json s = kiln::run_scene(scene, {out, quiet});
  if (!quiet) {
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
                scene.name.c_str(), steps.c_str(), integrators.c_str(),
                s["wall_seconds"].get<double>(), s["particle_steps_per_second"].get<double>(),
                s["energy"]["balance_error"].get<double>(), out.c_str());
  }
  return 0;
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
  std::string out;
  bool quiet = false, force = false;
  CLI::App* run_cmd = app.add_subcommand("run", "run a scene and write result.h5, result.xdmf, summary.json, picture.png");
  add_scene_options(run_cmd, run_args);
  run_cmd->add_option("--out", out, "output directory (default out/<scene name>)");
  run_cmd->add_flag("--quiet", quiet, "no progress or summary line");
  run_cmd->add_flag("--force", force, "run even when dt is beyond the estimated limit (to probe where it goes unstable)");
  CLI::App* check_cmd = app.add_subcommand("check", "validate a scene and print its time-step estimates");
  add_scene_options(check_cmd, check_args);
  CLI::App* cases_cmd = app.add_subcommand("cases", "list the shipped cases");
  CLI::App* integrators_cmd = app.add_subcommand("integrators", "list the integrators with their orders");
  kiln::BenchOptions bench;
  CLI::App* bench_cmd = app.add_subcommand("bench", "particle-steps per second on the benchmark pile (../shared/BENCH.md)");
  bench_cmd->add_option("--columns", bench.columns, "lattice columns: 50 rows x columns discs (20: 1,000; 200: 10,000)")
      ->check(CLI::PositiveNumber);
  bench_cmd->add_option("--steps", bench.steps, "timed steps")->check(CLI::PositiveNumber);
  bench_cmd->add_flag("--flowing", bench.flowing, "tilt gravity 30 degrees toward +x");
  kiln::OrderOptions order;
  CLI::App* order_cmd = add_study(app, "order", "observed orders of integrators on a scene (order.json, .csv, .png)", order);
  order_cmd->add_option("--integrators", order.integrators, "comma-separated names (see 'kiln integrators')")
      ->required()
      ->delimiter(',');
  order_cmd->add_option("--dt", order.dt, "the coarsest step (s)")->required()->check(CLI::PositiveNumber);
  order_cmd->add_option("--levels", order.levels, "number of step sizes")->check(CLI::Range(2, 30));
  order_cmd->add_option("--ratio", order.ratio, "dt_{k+1} = dt_k / ratio (default 2)");
  order_cmd->add_option("--quantity", order.quantity,
                        "position, velocity, temperature or a case quantity (default: temperature on a frozen scene, "
                        "else position)");
  order_cmd->add_option("--reference", order.reference, "analytic | richardson | fine");
  order_cmd->add_option("--fine-rtol", order.fine_rtol, "tolerance of the fine reference (default 1e-11)")
      ->check(CLI::PositiveNumber);
  kiln::SweepOptions sweep;
  CLI::App* sweep_cmd =
      add_study(app, "sweep", "time-step sensitivity and stability boundary (sweep.json, .csv, .png)", sweep);
  sweep_cmd->add_option("--integrator", sweep.integrator, "integrator name")->required();
  sweep_cmd->add_option("--dt-min", sweep.dt_min, "smallest step (s)")->required()->check(CLI::PositiveNumber);
  sweep_cmd->add_option("--dt-max", sweep.dt_max, "largest step (s)")->required()->check(CLI::PositiveNumber);
  sweep_cmd->add_option("--points", sweep.points, "steps, log-spaced")->check(CLI::Range(2, 200));
  sweep_cmd->add_option("--quantity", sweep.quantities, "quantities (default: the case's)")->take_all();
  kiln::WorkPrecisionOptions wp;
  CLI::App* wp_cmd = add_study(app, "wp", "work-precision: error against cost (wp.json, .csv, .png)", wp);
  wp_cmd->add_option("--integrators", wp.integrators, "comma-separated names")->required()->delimiter(',');
  wp_cmd->add_option("--dts", wp.dts, "fixed steps (s)")->delimiter(',');
  wp_cmd->add_option("--rtols", wp.rtols, "tolerances (adaptive)")->delimiter(',');
  wp_cmd->add_option("--quantity", wp.quantity,
                     "position, velocity, temperature or a case quantity (default: temperature on a frozen scene, "
                     "else position)");
  wp_cmd->add_option("--reference", wp.reference, "analytic | fine");
  wp_cmd->add_option("--fine-rtol", wp.fine_rtol, "tolerance of the fine reference (default 1e-11)")
      ->check(CLI::PositiveNumber);
  wp_cmd->add_option("--seeds", wp.seeds, "chaotic scenes: average a scalar over this many fills (noise floor shown)");
  wp_cmd->add_option("--seed-key", wp.seed_key, "the key --seeds varies (default particles.0.fill.seed)");
  wp_cmd->add_option("--repeats", wp.repeats, "timed runs after a warm-up")->check(CLI::PositiveNumber);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    // --help and --version exit 0; a bad argument is bad input: the documented exit code 2.
    return app.exit(e) == 0 ? 0 : 2;
  }
  try {
    if (*run_cmd) return run(run_args, out, quiet, force);
    if (*check_cmd) return check(check_args);
    if (*cases_cmd) return list_cases();
    if (*integrators_cmd) return list_integrators();
    if (*bench_cmd) return kiln::run_bench(bench);
    // A study writes into out/<scene name>/<study> unless --out says otherwise.
    auto out_dir = [](std::string& dir, const std::string& scene, const std::vector<std::string>& sets,
                      const char* study) {
      if (dir.empty()) dir = "out/" + kiln::load_scene(scene, sets).name + "/" + study;
    };
    if (*order_cmd) {
      out_dir(order.out_dir, order.scene, order.sets, "order");
      kiln::run_order_study(order);
      return 0;
    }
    if (*sweep_cmd) {
      out_dir(sweep.out_dir, sweep.scene, sweep.sets, "sweep");
      kiln::run_sweep_study(sweep);
      return 0;
    }
    if (*wp_cmd) {
      out_dir(wp.out_dir, wp.scene, wp.sets, "wp");
      kiln::run_work_precision(wp);
      return 0;
    }
  } catch (const kiln::InputError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 2;
  } catch (const kiln::InstabilityError& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 3;
  } catch (const std::exception& e) {
    std::fprintf(stderr, "error: %s\n", e.what());
    return 1;
  }
  return 0;
}
