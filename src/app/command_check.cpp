// `kiln check`: a scene validated, and its time-step estimates (src/run/stability.h).
#include <cmath>
#include <cstdio>

#include "integrators/integrator.h"
#include "src/app/command.h"
#include "src/app/command_options.h"
#include "src/base/error.h"
#include "src/run/stability.h"

namespace kiln {

namespace {

class CheckCommand final : public Command {
 public:
  explicit CheckCommand(CLI::App& app)
      : Command(app.add_subcommand("check", "validate a scene and print its time-step estimates")) {
    add_scene_options(cli_, scene_args_);
    cli_->get_option("scene")->required();
    cli_->add_flag("--json", json_, "write the estimates and the verdict as JSON on standard output");
    cli_->add_flag("--quiet")->description("no progress line (on a terminal, scenes of 131,072 particles or more show one)");
  }

  int run() override {
    const SceneArgs& a = scene_args_;
    const Scene scene = load(a);
    const StabilityEstimate est = estimate_stability(scene);
    const DtVerdict verdict = judge_dt(est, scene.dt, scene);
    if (json_) {
      nlohmann::json j = {{"scene", scene.name}, {"dt", scene.dt}, {"estimate", estimate_json(est)},
                          {"refused", verdict.unstable}, {"warnings", verdict.warnings}};
      // What binds dt: the contacts' limit or explicit conduction's on the network at t = 0 (a
      // frozen scene's only limit); limit_fraction is dt over it.
      const bool conduction = scene.frozen || est.conduction_dt_limit < est.dt_limit;
      const double binding = conduction ? est.conduction_dt_limit : est.dt_limit;
      j["estimate"]["binding_kind"] = conduction ? "conduction" : "contacts";
      j["estimate"]["binding_limit"] = std::isfinite(binding) ? nlohmann::json(binding) : nlohmann::json(nullptr);
      j["estimate"]["limit_fraction"] = std::isfinite(binding) && binding > 0 ? nlohmann::json(scene.dt / binding) : nlohmann::json(nullptr);
      std::printf("%s\n", j.dump(2).c_str());
      return verdict.unstable ? exit_refused : exit_success;
    }
    std::printf("scene %s: %d particle%s, %zu wall segment%s, integrator %s, dt %.4g s\n", scene.name.c_str(),
                scene.n_particles(), scene.n_particles() == 1 ? "" : "s", scene.segments.size(),
                scene.segments.size() == 1 ? "" : "s", scene.integrator.c_str(), scene.dt);
    if (scene.frozen) {
      std::printf("  mechanics frozen: no mechanical time step\n");
    } else {
      if (std::isfinite(est.contact_duration) && scene.dt <= est.contact_duration)
        std::printf("  shortest contact duration  %.4g s (%s); dt is 1/%.4g of it\n", est.contact_duration,
                    est.shortest_pair.c_str(), est.contact_duration / scene.dt);
      else if (std::isfinite(est.contact_duration))  // "1/0.5 of it" read as a fraction
        std::printf("  shortest contact duration  %.4g s (%s); dt is %.3g times it\n", est.contact_duration,
                    est.shortest_pair.c_str(), scene.dt / est.contact_duration);
      const MechanicalLimit& l = est.limit;
      if (!std::isfinite(est.contact_duration))
        std::printf("  stability limit of dt      none: no contact can form (%s)\n",
                    scene.n_particles() > 1 ? "no walls, no particles approaching" : "one particle, no walls");
      else if (std::isinf(l.dt))
        std::printf("  stability limit of dt      none from the contacts analysed (%s)\n", l.state.c_str());
      else if (std::isnan(l.dt))
        std::printf("  stability limit of dt      not a number: a spring over a mass on %s overflows double precision\n",
                    l.state.c_str());
      else if (l.dt == 0)
        std::printf("  stability limit of dt      none: %s\n", describe_limit(est).c_str());
      else
        std::printf("  stability limit of dt      %.4g s for %s (dt is %.3g of it): the %s mode of %s, on %s\n"
                    "                             (%d coordinates, %d contacts; stiffest mode %.4g rad/s)\n",
                    l.dt, est.integrator.c_str(), scene.dt / l.dt, l.mode.c_str(), l.where.c_str(), l.state.c_str(),
                    l.coordinates, l.contacts, l.omega_max);
      if (l.blow_up_dt > l.dt && std::isfinite(l.blow_up_dt))
        std::printf("  blow-up limit of dt        %.4g s (the normal and wall-body modes): between the two, the %s mode grows\n"
                    "                             only to its %s cap, and sticking contacts creep or chatter there with the\n"
                    "                             energy balanced: no check can stop such a run (kiln sweep shows the drift)\n",
                    l.blow_up_dt, l.mode.c_str(), l.mode == "rolling" ? "rolling" : "Coulomb");
      if (std::isfinite(est.rayleigh))
        std::printf("  Rayleigh time step         %.4g s (smallest particle); dt is %.4g %% of it\n", est.rayleigh,
                    100 * scene.dt / est.rayleigh);
      else
        std::printf("  Rayleigh time step         n/a (no youngs_modulus given)\n");
      if (std::isfinite(est.recommended_dt) && est.recommended_dt < est.contact_duration / 50)
        std::printf("  recommended dt             %.4g s (the stability limit, below contact duration / 50 = %.4g s)\n",
                    est.recommended_dt, est.contact_duration / 50);
      else if (std::isfinite(est.recommended_dt))
        std::printf("  recommended dt             %.4g s (contact duration / 50; %.3g of the limit)\n", est.recommended_dt,
                    est.recommended_dt / est.dt_limit);
    }
    if (scene.thermal) {
      if (std::isfinite(est.thermal_dt_limit_network))
        std::printf("  explicit conduction limit  %.4g s (2 / lambda_max, contact network at t = 0)",
                    est.thermal_dt_limit_network);
      else
        std::printf("  explicit conduction limit  none at t = 0 (no conducting contact)");
      if (!scene.frozen && std::isfinite(est.thermal_dt_limit))
        std::printf(", %.4g s (dense packing at 1 %% overlap)", est.thermal_dt_limit);
      const double reach = real_stability_of(scene.integrator);
      if (std::isinf(reach))
        std::printf("\n  %-26s none (conduction implicit)", (scene.integrator + "'s limit").c_str());
      else if (reach != 2 && std::isfinite(est.thermal_dt_limit_network))
        std::printf("\n  %-26s %.4g s (%.4g / lambda_max: the table's reach on the negative real axis)",
                    (scene.integrator + "'s limit").c_str(), reach / 2 * est.thermal_dt_limit_network, reach);
      if (std::isfinite(est.thermal_relaxation_time))
        std::printf("\n  thermal relaxation time    %.4g s (fastest mode, 1 / lambda_max)\n", est.thermal_relaxation_time);
      else
        std::printf("\n  thermal relaxation time    none (no conducting contact)\n");
    }
    std::fflush(stdout);  // the verdict goes to stderr, after the table
    for (const std::string& w : verdict.warnings)
      std::fprintf(stderr, "%s: %s\n", verdict.unstable ? "error" : "warning", w.c_str());
    return verdict.unstable ? exit_refused : exit_success;
  }

 private:
  SceneArgs scene_args_;
  bool json_ = false;
};

}  // namespace

std::unique_ptr<Command> add_check_command(CLI::App& app) { return std::make_unique<CheckCommand>(app); }

}  // namespace kiln
