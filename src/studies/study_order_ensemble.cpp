#include <cmath>

#include "integrators/integrator.h"
#include "src/studies/study_order.h"
#include "src/studies/study_ranks.h"
#include "src/studies/study_report.h"
#include "src/studies/study_runs.h"

namespace kiln {

nlohmann::json run_order_ensemble(const OrderOptions& o, const Scene& base, double t_end) {
  const EnsembleOptions& e = o.ensemble;
  check_ensemble(base, o.quantity);
  // The reference: the first integrator one level below the finest, run by the same members.
  const double finest = o.dt / std::pow(o.ratio, o.levels);
  std::vector<StudyRun> points = {StudyRun(o.integrators.front(), finest)};
  for (const std::string& name : o.integrators)
    for (int level = 0; level < o.levels; ++level) points.emplace_back(name, o.dt / std::pow(o.ratio, level));
  Members numbers(o.scene, o.sets);
  const EnsembleRuns runs = run_ensembles(points, e, numbers, [&](std::vector<StudyRun>& batch) {
    run_study(o.scene, o.sets, t_end, o.quantity, batch, o.threads, o.quiet, o.heat_stage);
  });
  const std::vector<double> reference = member_values(runs.points.front());
  if (reference.empty())
    throw StudyError(format("the reference ensemble (%s at %g s): ", o.integrators.front().c_str(), finest) +
                     member_problem(runs.points.front(), o.quantity));

  StudyReport report("order", study_header(base, o.quantity, "ensemble", t_end));
  nlohmann::json& out = report.json();
  out["ratio"] = o.ratio;
  out["ensemble"] = ensemble_settings_json(e, runs, numbers);
  out["reference_point"] = {{"integrator", o.integrators.front()}, {"dt", finest},
                            {"statistics", ensemble_json(reference, e.level)}};
  report.csv_row({"integrator", "dt", "mean", "bias", "bias_low", "bias_high", "observed_order", "order_se"});
  for (size_t i = 0; i < o.integrators.size(); ++i) {
    const std::string& name = o.integrators[i];
    nlohmann::json entry = {{"name", name}, {"nominal_order", nominal_order(name)}};
    // A level whose runs failed or did not measure the quantity is left out and named; the others
    // are read (one unmeasured member discarded the whole ladder).
    std::vector<double> dts, biases(o.levels, NAN), ses(o.levels, NAN);
    std::vector<bool> resolved(o.levels, false);
    std::vector<std::string> left_out(o.levels);
    nlohmann::json statistics = nlohmann::json::array(), left = nlohmann::json::array();
    report.table("%s (nominal order %d)\n        dt            mean          bias   +- interval   order\n",
                 name.c_str(), nominal_order(name));
    for (int level = 0; level < o.levels; ++level) {
      const std::vector<StudyRun>& members = runs.points[1 + i * o.levels + level];
      const std::vector<double> values = member_values(members);
      dts.push_back(members.front().dt);
      if (values.empty()) {
        left_out[level] = member_problem(members, o.quantity);
        left.push_back({{"dt", dts.back()}, {"reason", left_out[level]}});
        statistics.push_back(nullptr);
        continue;
      }
      const Bias bias = paired_bias(values, reference, e.level, e.power);
      biases[level] = bias.estimate;
      ses[level] = bias.se;
      resolved[level] = bias.detected();
      statistics.push_back({{"ensemble", ensemble_json(values, e.level)}, {"bias", bias_json(bias, 0)}});
    }
    if (!left.empty()) entry["left_out"] = left;
    // An order between two levels only where both biases are detected: the log of an interval
    // that holds zero is no number. Its standard error by the delta method (the two levels' biases
    // taken as independent, which overstates it where they share seeds' noise).
    nlohmann::json orders = nlohmann::json::array(), order_ses = nlohmann::json::array();
    double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
    for (int k = 0; k < o.levels; ++k) {
      if (resolved[k]) {
        const double x = std::log(dts[k]), y = std::log(std::abs(biases[k]));
        sx += x, sy += y, sxx += x * x, sxy += x * y, n += 1;
      }
      if (k == 0) continue;
      if (resolved[k - 1] && resolved[k]) {
        orders.push_back(std::log(std::abs(biases[k - 1] / biases[k])) / std::log(o.ratio));
        order_ses.push_back(std::hypot(ses[k - 1] / biases[k - 1], ses[k] / biases[k]) / std::log(o.ratio));
      } else {
        orders.push_back(nullptr);
        order_ses.push_back(nullptr);
      }
    }
    const double slope = n >= 2 ? (n * sxy - sx * sy) / (n * sxx - sx * sx) : NAN;
    const int detected = static_cast<int>(n);
    double smallest = NAN;  // at the finest level that was measured
    for (const auto& st : statistics)
      if (!st.is_null() && st["bias"]["smallest_detectable"].is_number())
        smallest = st["bias"]["smallest_detectable"].get<double>();
    const std::string verdict =
        detected >= 2
            ? format("fitted order %.2f over the %d levels whose bias is detected (nominal %d)", slope, detected,
                     nominal_order(name))
            : std::isfinite(smallest)
                ? format("not resolved: the bias is detected at %d of %d levels (the smallest this ensemble detects at "
                         "the finest: %.2g): more members (--seeds auto --se %.2g) or coarser steps",
                         detected, o.levels, smallest, smallest / 4)
                : std::string("no level measured the quantity: see the levels left out");
    entry["dt"] = dts;
    entry["statistics"] = statistics;
    entry["observed_orders"] = orders;
    entry["observed_order_standard_errors"] = order_ses;
    entry["fitted_order"] = std::isfinite(slope) ? nlohmann::json(slope) : nlohmann::json(nullptr);
    entry["levels_resolved"] = detected;
    entry["verdict"] = verdict;
    out["integrators"].push_back(entry);
    for (int k = 0; k < o.levels; ++k) {
      if (!left_out[k].empty()) {
        report.table("  %12.4e   left out: %s\n", dts[k], left_out[k].c_str());
        continue;
      }
      const auto& st = statistics[k];
      const auto& b = st["bias"];
      const double lo = b["interval"][0].get<double>(), hi = b["interval"][1].get<double>();
      const std::string order = k > 0 && orders[k - 1].is_number()
                                    ? format("%.2f +- %.2f", orders[k - 1].get<double>(), order_ses[k - 1].get<double>())
                                    : k > 0 ? "-" : "";
      report.table("  %12.4e  %12.6g  %+11.3e  %10.2e   %s%s\n", dts[k], st["ensemble"]["mean"].get<double>(),
                   biases[k], (hi - lo) / 2, order.c_str(), resolved[k] ? "" : "   (bias not detected)");
      report.csv_row({name, csv_number(dts[k]), csv_number(st["ensemble"]["mean"].get<double>()), csv_number(biases[k]),
                      csv_number(lo), csv_number(hi), k > 0 && orders[k - 1].is_number() ? csv_number(orders[k - 1].get<double>()) : "",
                      k > 0 && orders[k - 1].is_number() ? csv_number(order_ses[k - 1].get<double>()) : ""});
    }
    report.table("  %s\n\n", verdict.c_str());
  }
  report.publish(format("%s on %s at t = %g s: orders of the ensemble mean's bias\n", o.quantity.c_str(),
                        base.name.c_str(), t_end) +
                     ensemble_heading(e, runs, numbers, format("%s at %.4g s", o.integrators.front().c_str(), finest)) + "\n",
                 "", o.out_dir, o.quiet);
  return out;
}

}  // namespace kiln
