#include "src/app/command_options.h"

#include <cmath>

#include "integrators/integrator.h"
#include "src/base/error.h"
#include "src/scene/overrides.h"
#include "src/scene/scene_yaml.h"

namespace kiln {

namespace {
// CLI11 gives a list option whose value holds no item (`--integrators ,`) the next argument, an
// option's name: it was called an unknown integrator (issue 28's review). Said as what it is.
std::string option_taken_as_value(const std::string& text) {
  return text.rfind("--", 0) == 0 ? "got the option '" + text.substr(0, 60) +
                                        "' as a value: the list before it holds no item (give comma-separated values)"
                                  : std::string();
}

// A number option: the whole text a number that `accepts` takes, else "must be <expected>".
CLI::Validator number_option(bool (*accepts)(double), const std::string& expected, const std::string& name) {
  return CLI::Validator(
      [accepts, expected](std::string& text) {
        if (std::string taken = option_taken_as_value(text); !taken.empty()) return taken;
        try {
          size_t used = 0;
          const double v = std::stod(text, &used);
          if (used == text.size() && accepts(v)) return std::string();
        } catch (const std::exception&) {
        }
        return "must be " + expected + ", got '" + text.substr(0, 60) + "'";
      },
      name);
}
}  // namespace

const CLI::Validator positive_finite =
    number_option([](double v) { return std::isfinite(v) && v > 0; }, "a positive finite number", "POSITIVE");

const CLI::Validator relative_tolerance = number_option(
    [](double v) { return v >= 1e-14 && v < 1; },
    "a relative tolerance in [1e-14, 1) (below 1e-14 ARKODE cannot take a step in double precision)", "RTOL");

const CLI::Validator integrator_name(
    [](std::string& text) {
      if (std::string taken = option_taken_as_value(text); !taken.empty()) return taken;
      try {
        integrator_info(text);
      } catch (const InputError& e) {
        return std::string(e.what());
      }
      return std::string();
    },
    "NAME");

std::vector<std::string> overrides_of(const SceneArgs& a) {
  std::vector<std::string> sets = a.sets;
  if (!a.integrator.empty()) sets.push_back("integrator=" + a.integrator);
  if (a.dt > 0) sets.push_back(assignment("dt", a.dt));
  if (a.t_end > 0) sets.push_back(assignment("t_end", a.t_end));
  if (a.rtol > 0) sets.push_back(assignment("rtol", a.rtol));
  if (a.atol > 0) sets.push_back(assignment("atol", a.atol));
  if (a.contact_events) sets.push_back("contact_events=true");
  return sets;
}

Scene load(const SceneArgs& a) {
  Scene scene = load_scene(a.path, overrides_of(a));
  make_integrator(scene.integrator, scene.control);
  return scene;
}

void add_scene_options(CLI::App* cmd, SceneArgs& a) {
  cmd->add_option("scene", a.path, "scene file (YAML)")->check(CLI::ExistingFile);
  cmd->add_option("--integrator", a.integrator, "integrator name (see 'kiln integrators')")->check(integrator_name);
  cmd->add_option("--dt", a.dt, "time step (s)")->check(positive_finite);
  cmd->add_option("--t-end", a.t_end, "end time (s)")->check(positive_finite);
  cmd->add_option("--rtol", a.rtol, "relative tolerance: adaptive steps from --dt (erk:/imex: methods)")
      ->check(relative_tolerance);
  cmd->add_option("--atol", a.atol, "absolute tolerance (per field: --set atol.temperature=...)")
      ->check(positive_finite);
  cmd->add_flag("--contact-events", a.contact_events,
                "lock the acting contacts within a step, locate onsets and releases, restart there (ARKODE)");
  cmd->add_option("--set", a.sets, "override a scene value by dotted path: KEY=VALUE")->take_all();
}

}  // namespace kiln
