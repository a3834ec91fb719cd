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

nlohmann::json run_work_precision(const WorkPrecisionOptions& o_in) {
  WorkPrecisionOptions o = o_in;
  const Scene base = load_scene(o.scene, o.sets);
  if (o.quantity.empty()) o.quantity = default_quantity(base, o.heat_stage);
  check_quantity(base, o.quantity);
  if (o.dts.empty() == o.rtols.empty()) throw InputError("give either --dts or --rtols");
  const bool ensemble = o.ensemble.on();
  require_seeds_for_statistics(o.ensemble);
  if (ensemble) {
    check_ensemble(base, o.quantity);
    o.reference = "ensemble";
  } else if (o.reference != "analytic" && o.reference != "fine") {
    throw InputError("unknown --reference '" + o.reference + "'; valid choices are " +
                     choices_nearest_first(o.reference, {"analytic", "fine"}) + " (or --seeds N for chaotic scenes)");
  }
  const double t_end = o.t_end > 0 ? o.t_end : base.t_end;
  const bool adaptive = !o.rtols.empty();
  const std::vector<double>& settings = adaptive ? o.rtols : o.dts;
  auto make_run = [&](const std::string& name, double v) {
    StudyRun run(name, adaptive ? base.dt : v, adaptive ? std::vector<std::string>{assignment("rtol", v)}
                                                         : std::vector<std::string>{});
    run.repeats = o.repeats;
    return run;
  };
  std::vector<StudyRun> runs;
  for (const std::string& name : o.integrators)
    for (double v : settings) runs.push_back(make_run(name, v));
  auto run = [&](std::vector<StudyRun>& batch) {
    run_study(o.scene, o.sets, t_end, o.quantity, batch, o.threads, o.quiet, o.heat_stage);
  };
  std::vector<double> reference;
  // Ensembles: the reference point (the first integrator at half the smallest step, or a tenth of
  // the smallest rtol) first, then every point, all of the same members.
  EnsembleRuns members;
  Members member_numbers(o.scene, o.sets);
  std::vector<double> reference_members;
  const double finest = *std::min_element(settings.begin(), settings.end()) / (adaptive ? 10 : 2);
  if (ensemble) {
    std::vector<StudyRun> points = {make_run(o.integrators.front(), finest)};
    points.front().repeats = 1;  // not timed
    points.insert(points.end(), runs.begin(), runs.end());
    members = run_ensembles(points, o.ensemble, member_numbers, run);
    reference_members = member_values(members.points.front());
    if (reference_members.empty())
      throw StudyError(format("the reference ensemble (%s at %g s): ", o.integrators.front().c_str(), finest) +
                       member_problem(members.points.front(), o.quantity));
    reference = {ensemble_of(reference_members, o.ensemble.level).mean};
  } else {
    reference = study_reference(base, o.scene, o.sets, o.quantity, t_end, o.reference, base.dt, o.fine_rtol, o.heat_stage)
                    .value;
    run(runs);
  }

  StudyReport report("wp", study_header(base, o.quantity, o.reference, t_end));
  nlohmann::json& out = report.json();
  out["setting"] = adaptive ? "rtol" : "dt";
  out["repeats"] = o.repeats;
  if (o.reference == "fine") out["fine_rtol"] = o.fine_rtol;
  if (ensemble) {
    out["ensemble"] = ensemble_settings_json(o.ensemble, members, member_numbers);
    out["reference_point"] = {{"integrator", o.integrators.front()}, {adaptive ? "rtol" : "dt", finest},
                              {"statistics", ensemble_json(reference_members, o.ensemble.level)}};
    out["reference_value"] = reference.front();
  }
  std::vector<std::string> header = {"integrator", adaptive ? "rtol" : "dt", "error", "wall_seconds", "rhs_evals"};
  if (ensemble) header.insert(header.begin() + 3, {"bias", "bias_low", "bias_high", "verdict"});
  report.csv_row(header);
  for (size_t i = 0; i < o.integrators.size(); ++i) {
    nlohmann::json entry;
    entry["name"] = o.integrators[i];
    entry[adaptive ? "rtol" : "dt"] = settings;
    nlohmann::json errors = nlohmann::json::array(), seconds = nlohmann::json::array(),
                   evals = nlohmann::json::array(), statistics = nlohmann::json::array();
    report.table("%s\n   %s          error%s          seconds     rhs evals%s\n", o.integrators[i].c_str(),
                 adaptive ? "rtol" : "dt  ", ensemble ? "      +- (interval)" : "", ensemble ? "   verdict" : "");
    for (size_t k = 0; k < settings.size(); ++k) {
      // A point's runs: one, or its ensemble's members (after the reference point).
      const std::vector<StudyRun> point =
          ensemble ? members.points[1 + i * settings.size() + k] : std::vector<StudyRun>{runs[i * settings.size() + k]};
      bool unstable = false;
      const std::string failure = member_failure(point, &unstable);
      const std::string unmeasured = ensemble && failure.empty() ? member_unmeasured(point, o.quantity) : "";
      double wall = 0, rhs = 0;
      for (const StudyRun& r : point) {
        wall += r.seconds / point.size();  // cost of one run
        rhs += static_cast<double>(r.rhs_evals) / point.size();
      }
      if (!failure.empty() || !unmeasured.empty()) {
        errors.push_back(nullptr);
        seconds.push_back(nullptr);
        evals.push_back(nullptr);
        statistics.push_back(nullptr);
        if (unmeasured.empty())
          report.table("  %12.4e   failed (%s: %s)\n", settings[k], unstable ? "unstable" : "error", failure.c_str());
        else
          report.table("  %12.4e   %s\n", settings[k], unmeasured.c_str());
        continue;
      }
      double e;
      std::string cells, verdict;
      std::vector<std::string> extra;
      if (ensemble) {
        const std::vector<double> values = member_values(point);
        const Bias bias = paired_bias(values, reference_members, o.ensemble.level, o.ensemble.power);
        e = std::abs(bias.estimate);
        statistics.push_back({{"ensemble", ensemble_json(values, o.ensemble.level)},
                              {"bias", bias_json(bias, o.ensemble.tolerance)}});
        cells = format("   %10.2e", (bias.high - bias.low) / 2);
        verdict = "   " + describe(bias, o.ensemble.tolerance);
        extra = {csv_number(bias.estimate), csv_number(bias.low), csv_number(bias.high),
                 statistics.back()["bias"]["verdict"].is_null() ? "" : statistics.back()["bias"]["verdict"].get<std::string>()};
      } else {
        e = max_abs_difference(point.front().value, reference);
      }
      errors.push_back(e);
      seconds.push_back(wall);
      evals.push_back(std::lround(rhs));
      report.table("  %12.4e   %12.4e%s   %10.4g   %10ld%s\n", settings[k], e, cells.c_str(), wall, std::lround(rhs),
                   verdict.c_str());
      std::vector<std::string> row = {o.integrators[i], csv_number(settings[k]), csv_number(e), csv_number(wall),
                                      std::to_string(std::lround(rhs))};
      row.insert(row.begin() + 3, extra.begin(), extra.end());
      report.csv_row(row);
    }
    entry["error"] = errors;
    if (ensemble) entry["statistics"] = statistics;
    entry["wall_seconds"] = seconds;
    entry["rhs_evals"] = evals;
    out["integrators"].push_back(entry);
  }
  std::string heading = format("%s on %s at t = %g s, reference %s; cost: minimum wall time of %d runs after a warm-up\n",
                               o.quantity.c_str(), base.name.c_str(), t_end, o.reference.c_str(), o.repeats);
  if (ensemble)
    heading += ensemble_heading(o.ensemble, members, member_numbers,
                                format("%s at %s (mean %.6g); error: |bias|", o.integrators.front().c_str(),
                                       format(adaptive ? "rtol %.3g" : "dt %.3g s", finest).c_str(), reference.front()));
  report.publish(heading + "\n", "", o.out_dir, o.quiet);
  if (!ensemble) require_a_result(runs);
  return out;
}

}  // namespace kiln
