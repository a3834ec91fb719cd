#include "src/studies/study_wp.h"

#include <algorithm>
#include <cmath>

#include "src/base/error.h"
#include "src/base/nearest.h"
#include "src/scene/overrides.h"
#include "src/scene/scene_yaml.h"
#include "src/studies/study_report.h"
#include "src/studies/study_runs.h"

namespace kiln {

namespace {

// Mean and standard error of the mean of the first values of runs[first], runs[first + 1], ...
// (count of them); failed runs make the mean NaN.
std::pair<double, double> ensemble_mean(const std::vector<StudyRun>& runs, size_t first, size_t count) {
  double mean = 0;
  for (size_t k = first; k < first + count; ++k) {
    if (!runs[k].failure.empty()) return {NAN, NAN};
    mean += runs[k].value.front() / count;
  }
  double deviations = 0;  // two passes: a mean far above the spread would cancel in sum x^2 - n mean^2
  for (size_t k = first; k < first + count; ++k) deviations += std::pow(runs[k].value.front() - mean, 2);
  return {mean, count > 1 ? std::sqrt(deviations / (count - 1) / count) : 0.0};
}

}  // namespace

nlohmann::json run_work_precision(const WorkPrecisionOptions& o_in) {
  WorkPrecisionOptions o = o_in;
  const Scene base = load_scene(o.scene, o.sets);
  if (o.quantity.empty()) o.quantity = default_quantity(base, o.heat_stage);
  check_quantity(base, o.quantity);
  if (o.dts.empty() == o.rtols.empty()) throw InputError("give either --dts or --rtols");
  const bool ensemble = o.seeds > 0;
  if (ensemble) {
    if (o.seeds < 2) throw InputError("--seeds needs at least 2 fills to estimate the noise floor");
    if (const QuantityShape shape = shape_of(base, o.quantity); shape != QuantityShape::number)
      throw InputError("--seeds compares ensemble means of a scalar; '" + o.quantity + "' is a " +
                       (shape == QuantityShape::field ? "field" : "list") + "; available: " +
                       choices_nearest_first(o.quantity, study_quantities(base)));
    o.reference = "ensemble";
    load_scene(o.scene, [&] { auto s = o.sets; s.push_back(o.seed_key + "=1"); return s; }());  // the key exists
  } else if (o.reference != "analytic" && o.reference != "fine") {
    throw InputError("unknown --reference '" + o.reference + "'; valid choices are " +
                     choices_nearest_first(o.reference, {"analytic", "fine"}) + " (or --seeds N for chaotic scenes)");
  }
  const double t_end = o.t_end > 0 ? o.t_end : base.t_end;
  const bool adaptive = !o.rtols.empty();
  const std::vector<double>& settings = adaptive ? o.rtols : o.dts;
  const int members = ensemble ? o.seeds : 1;
  auto make_run = [&](const std::string& name, double v, int member) {
    StudyRun run(name, adaptive ? base.dt : v, adaptive ? std::vector<std::string>{assignment("rtol", v)}
                                                         : std::vector<std::string>{});
    if (ensemble) run.sets.push_back(o.seed_key + "=" + std::to_string(member + 1));
    return run;
  };
  std::vector<StudyRun> runs;
  for (const std::string& name : o.integrators)
    for (double v : settings)
      for (int m = 0; m < members; ++m) {
        runs.push_back(make_run(name, v, m));
        runs.back().repeats = o.repeats;
      }
  std::vector<double> reference;
  double reference_se = 0;
  if (ensemble) {
    const double finest = *std::min_element(settings.begin(), settings.end()) / (adaptive ? 10 : 2);
    std::vector<StudyRun> ref;
    for (int m = 0; m < members; ++m) ref.push_back(make_run(o.integrators.front(), finest, m));
    run_study(o.scene, o.sets, t_end, o.quantity, ref, o.threads, o.quiet, o.heat_stage);
    for (const StudyRun& r : ref)
      if (!r.failure.empty()) throw StudyError("an ensemble reference run failed: " + r.failure);
    const auto [mean, se] = ensemble_mean(ref, 0, members);
    reference = {mean};
    reference_se = se;
  } else {
    reference = study_reference(base, o.scene, o.sets, o.quantity, t_end, o.reference, base.dt, o.fine_rtol, o.heat_stage)
                    .value;
  }
  run_study(o.scene, o.sets, t_end, o.quantity, runs, o.threads, o.quiet, o.heat_stage);

  StudyReport report("wp", study_header(base, o.quantity, o.reference, t_end));
  nlohmann::json& out = report.json();
  out["setting"] = adaptive ? "rtol" : "dt";
  out["repeats"] = o.repeats;
  if (o.reference == "fine") out["fine_rtol"] = o.fine_rtol;
  if (ensemble) {
    out["seeds"] = o.seeds;
    out["reference_value"] = reference.front();
    out["reference_standard_error"] = reference_se;
  }
  std::vector<std::string> header = {"integrator", adaptive ? "rtol" : "dt", "error", "wall_seconds", "rhs_evals"};
  if (ensemble) header.insert(header.begin() + 3, "noise");
  report.csv_row(header);
  for (size_t i = 0; i < o.integrators.size(); ++i) {
    nlohmann::json entry;
    entry["name"] = o.integrators[i];
    entry[adaptive ? "rtol" : "dt"] = settings;
    nlohmann::json errors = nlohmann::json::array(), noise = nlohmann::json::array(),
                   seconds = nlohmann::json::array(), evals = nlohmann::json::array();
    report.table("%s\n   %s          error%s          seconds     rhs evals\n", o.integrators[i].c_str(),
                 adaptive ? "rtol" : "dt  ", ensemble ? "      +- noise" : "");
    for (size_t k = 0; k < settings.size(); ++k) {
      const size_t first = (i * settings.size() + k) * members;
      bool failed = false, unstable = false;
      double wall = 0, rhs = 0;
      for (int m = 0; m < members; ++m) {
        const StudyRun& r = runs[first + m];
        failed = failed || !r.failure.empty();
        unstable = unstable || r.unstable;
        wall += r.seconds / members;  // cost of one run
        rhs += static_cast<double>(r.rhs_evals) / members;
      }
      if (failed) {
        errors.push_back(nullptr);
        noise.push_back(nullptr);
        seconds.push_back(nullptr);
        evals.push_back(nullptr);
        report.table("  %12.4e   failed (%s)\n", settings[k], unstable ? "unstable" : "error");
      } else {
        double e, n = 0;
        if (ensemble) {
          const auto [mean, se] = ensemble_mean(runs, first, members);
          e = std::abs(mean - reference.front());
          n = std::hypot(se, reference_se);
        } else {
          e = max_abs_difference(runs[first].value, reference);
        }
        errors.push_back(e);
        noise.push_back(n);
        seconds.push_back(wall);
        evals.push_back(std::lround(rhs));
        const std::string noise_cell = ensemble ? format("   %10.3e", n) : "";
        report.table("  %12.4e   %12.4e%s   %10.4g   %10ld\n", settings[k], e, noise_cell.c_str(), wall,
                     std::lround(rhs));
        std::vector<std::string> row = {o.integrators[i], csv_number(settings[k]), csv_number(e), csv_number(wall),
                                        std::to_string(std::lround(rhs))};
        if (ensemble) row.insert(row.begin() + 3, csv_number(n));
        report.csv_row(row);
      }
    }
    entry["error"] = errors;
    if (ensemble) entry["noise"] = noise;
    entry["wall_seconds"] = seconds;
    entry["rhs_evals"] = evals;
    out["integrators"].push_back(entry);
  }
  std::string heading = format("%s on %s at t = %g s, reference %s; cost: minimum wall time of %d runs after a warm-up\n",
                               o.quantity.c_str(), base.name.c_str(), t_end, o.reference.c_str(), o.repeats);
  if (ensemble)
    heading += format("ensemble of %d fills (%s = 1..%d): error of the mean, reference %.6g +- %.3g (%s at "
                      "%s); noise: standard error of the difference\n",
                      o.seeds, o.seed_key.c_str(), o.seeds, reference.front(), reference_se,
                      o.integrators.front().c_str(), adaptive ? "a tenth of the smallest rtol" : "half the smallest dt");
  report.publish(heading + "\n", "", o.out_dir, o.quiet);
  require_a_result(runs);
  return out;
}

}  // namespace kiln
