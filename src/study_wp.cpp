#include "src/study_wp.h"

#include <cmath>
#include <cstdio>
#include <sstream>

#include "src/error.h"
#include "src/exact_solutions.h"
#include "src/nearest.h"
#include "src/overrides.h"
#include "src/scene_yaml.h"
#include "src/study_runs.h"

namespace kiln {

nlohmann::json run_work_precision(const WorkPrecisionOptions& o) {
  const Scene base = load_scene(o.scene, o.sets);
  check_quantity(base, o.quantity);
  if (o.dts.empty() == o.rtols.empty()) throw InputError("give either --dts or --rtols");
  if (o.reference != "analytic" && o.reference != "fine")
    throw InputError("unknown --reference '" + o.reference + "'; valid choices are " +
                     choices_nearest_first(o.reference, {"analytic", "fine"}));
  const double t_end = o.t_end > 0 ? o.t_end : base.t_end;
  const std::vector<double> reference = study_reference(base, o.scene, o.sets, o.quantity, t_end, o.reference, base.dt);
  const bool adaptive = !o.rtols.empty();
  const std::vector<double>& settings = adaptive ? o.rtols : o.dts;
  std::vector<StudyRun> runs;
  for (const std::string& name : o.integrators)
    for (double v : settings) {
      runs.emplace_back(name, adaptive ? base.dt : v, adaptive ? std::vector<std::string>{assignment("rtol", v)}
                                                               : std::vector<std::string>{});
      runs.back().repeats = o.repeats;
    }
  run_study(o.scene, o.sets, t_end, o.quantity, runs, o.threads);

  nlohmann::json out = study_header(base, o.quantity, o.reference, t_end);
  out["setting"] = adaptive ? "rtol" : "dt";
  out["repeats"] = o.repeats;
  std::ostringstream csv, table;
  csv << "integrator," << (adaptive ? "rtol" : "dt") << ",error,wall_seconds,rhs_evals\n";
  for (size_t i = 0; i < o.integrators.size(); ++i) {
    nlohmann::json entry;
    entry["name"] = o.integrators[i];
    entry[adaptive ? "rtol" : "dt"] = settings;
    nlohmann::json errors = nlohmann::json::array(), seconds = nlohmann::json::array(), evals = nlohmann::json::array();
    table << o.integrators[i] << "\n   " << (adaptive ? "rtol" : "dt  ") << "          error          seconds     rhs evals\n";
    for (size_t k = 0; k < settings.size(); ++k) {
      const StudyRun& r = runs[i * settings.size() + k];
      char line[160];
      if (!r.failure.empty()) {
        errors.push_back(nullptr);
        seconds.push_back(nullptr);
        evals.push_back(nullptr);
        std::snprintf(line, sizeof line, "  %12.4e   failed (%s)\n", settings[k], r.unstable ? "unstable" : "error");
      } else {
        const double e = max_abs_difference(r.value, reference);
        errors.push_back(e);
        seconds.push_back(r.seconds);
        evals.push_back(r.rhs_evals);
        std::snprintf(line, sizeof line, "  %12.4e   %12.4e   %10.4g   %10ld\n", settings[k], e, r.seconds, r.rhs_evals);
        csv << o.integrators[i] << "," << settings[k] << "," << e << "," << r.seconds << "," << r.rhs_evals << "\n";
      }
      table << line;
    }
    entry["error"] = errors;
    entry["wall_seconds"] = seconds;
    entry["rhs_evals"] = evals;
    out["integrators"].push_back(entry);
  }
  if (!o.quiet)
    std::printf("%s on %s at t = %g s, reference %s; cost: minimum wall time of %d runs after a warm-up\n\n%s",
                o.quantity.c_str(), base.name.c_str(), t_end, o.reference.c_str(), o.repeats, table.str().c_str());
  if (!o.out_dir.empty()) write_study(o.out_dir, "wp", out, csv.str());
  return out;
}

}  // namespace kiln
