#include "src/studies/study_sweep.h"

#include <algorithm>
#include <cmath>

#include "integrators/integrator.h"
#include "src/base/error.h"
#include "src/scene/scene_yaml.h"
#include "src/run/stability.h"
#include "src/studies/study_ranks.h"
#include "src/studies/study_report.h"
#include "src/studies/study_runs.h"

namespace kiln {

namespace {

// The ensembles' statistics of a sweep: per quantity and step the mean with its interval and the
// bias against the smallest step's ensemble (paired seed by seed), and, with a tolerance, the
// largest step whose bias lies within it at that step and at every smaller one (the evidence: its
// interval). Writes them into the study's JSON and returns the text that follows the table.
std::string ensemble_sweep(const SweepOptions& o, const std::vector<double>& dts,
                           const std::vector<std::string>& quantities, const std::vector<EnsembleRuns>& ensembles,
                           const Members& members, nlohmann::json& out) {
  const EnsembleOptions& e = o.ensemble;
  out["ensemble"] = ensemble_settings_json(e, ensembles.front(), members);
  std::string text(1, '\n');
  text += ensemble_heading(e, ensembles.front(), members, format("the smallest step, %.4g s", dts.front()));
  for (size_t qi = 0; qi < quantities.size(); ++qi) {
    const EnsembleRuns& runs = ensembles[qi];
    if (qi > 0 && runs.members != ensembles.front().members)
      text += format("(%s: %d members)\n", quantities[qi].c_str(), runs.members);
    const std::vector<double> reference = member_values(runs.points.front());
    nlohmann::json rows = nlohmann::json::array();
    text += format("%s\n        dt            mean   +- interval     bias and verdict\n", quantities[qi].c_str());
    double largest = 0;
    bool within_so_far = !reference.empty() && e.tolerance > 0;
    for (size_t k = 0; k < dts.size(); ++k) {
      const std::vector<double> values = member_values(runs.points[k]);
      if (values.empty()) {
        const std::string why = member_problem(runs.points[k], quantities[qi]);
        rows.push_back({{"dt", dts[k]}, {"failure", why}});
        text += format("  %12.4e   %s\n", dts[k], why.c_str());
        within_so_far = false;
        continue;
      }
      const Ensemble stats = ensemble_of(values, e.level);
      nlohmann::json row = {{"dt", dts[k]}, {"ensemble", ensemble_json(values, e.level)}};
      std::string says = k == 0 ? "(the reference)" : "(no reference: the smallest step has no values)";
      if (k > 0 && !reference.empty()) {
        const Bias bias = paired_bias(values, reference, e.level, e.power);
        row["bias"] = bias_json(bias, e.tolerance);
        says = format("%+.3g: ", bias.estimate) + describe(bias, e.tolerance);
        within_so_far = within_so_far && verdict_of(bias, e.tolerance) == BiasVerdict::within_tolerance;
        if (within_so_far) largest = dts[k];
      }
      rows.push_back(row);
      text += format("  %12.4e  %12.6g  %10.2g     %s\n", dts[k], stats.mean, (stats.high - stats.low) / 2, says.c_str());
    }
    out["statistics"][quantities[qi]] = rows;
    if (e.tolerance > 0) {
      out["largest_dt_within_tolerance"][quantities[qi]] = largest > 0 ? nlohmann::json(largest) : nlohmann::json(nullptr);
      text += largest > 0 ? format("largest dt whose bias lies within %.3g (its %g %% interval inside +-%.3g, and at "
                                   "every smaller step): %.4g s\n",
                                   e.tolerance, 100 * e.level, e.tolerance, largest)
                          : format("no step above the smallest shows its bias within %.3g at this ensemble size: more "
                                   "seeds, or a smaller --dt-min\n",
                                   e.tolerance);
    }
  }
  return text;
}

}  // namespace

nlohmann::json run_sweep_study(const SweepOptions& o) {
  const Scene base = load_scene(o.scene, o.sets);
  if (!(o.dt_min > 0 && o.dt_max > o.dt_min)) throw InputError("need 0 < --dt-min < --dt-max");
  if (o.points < 2) throw InputError("--points must be at least 2");
  const double t_end = o.t_end > 0 ? o.t_end : base.t_end;
  std::vector<std::string> quantities = o.quantities;
  if (quantities.empty()) {  // defaults: the case's figures of merit, else the final positions
    quantities = headline_quantities(base);
    if (quantities.empty()) quantities.push_back(base.thermal ? "temperature" : "position");
  }
  for (const std::string& q : quantities) check_quantity(base, q);
  const bool ensemble = o.ensemble.on();
  if (ensemble)
    for (const std::string& q : quantities) check_ensemble(base, q);
  require_seeds_for_statistics(o.ensemble);

  // One run per (dt, quantity); field quantities are reported as their difference from the
  // run at the smallest dt (the sensitivity of the result to the step).
  std::vector<double> dts;
  for (int k = 0; k < o.points; ++k) dts.push_back(o.dt_min * std::pow(o.dt_max / o.dt_min, k / (o.points - 1.0)));
  std::vector<std::vector<StudyRun>> per_quantity;
  std::vector<EnsembleRuns> ensembles;  // with --seeds: per quantity, the members of each step
  Members members(o.scene, o.sets);
  for (const std::string& q : quantities) {
    std::vector<StudyRun> runs;
    for (double dt : dts) runs.emplace_back(o.integrator, dt);
    // The runs' end states: settled ones, whose contact network may bind below the start's (the
    // finest run that reached its end is used).
    for (StudyRun& r : runs) r.limit_at_end = per_quantity.empty() && !o.heat_stage;
    auto run = [&](std::vector<StudyRun>& batch) {
      run_study(o.scene, o.sets, t_end, q, batch, o.threads, o.quiet, o.heat_stage);
    };
    if (ensemble) {
      // A step stands for its members: member 0's run (and limit at the end), failed if any failed.
      ensembles.push_back(run_ensembles(runs, o.ensemble, members, run));
      for (size_t k = 0; k < runs.size(); ++k) {
        runs[k] = ensembles.back().points[k].front();
        bool unstable = false;
        runs[k].failure = member_failure(ensembles.back().points[k], &unstable);
        runs[k].unstable = unstable;
        if (!runs[k].failure.empty()) runs[k].value.clear();
      }
    } else {
      run(runs);
    }
    per_quantity.push_back(runs);
  }

  // The stability boundary: the first failure. Bisect (in log dt) between the smallest unstable
  // step and the largest stable one below it; stable runs above it (a window of instability, as
  // beyond a Verlet scheme's tangential-rotational limit, where the dissipation check fires and
  // further out the contacts only creep) are reported, not taken for the boundary.
  const std::vector<StudyRun>& first = per_quantity.front();
  double stable = 0, unstable = 0, stable_above = 0;
  for (const StudyRun& r : first)
    if (r.unstable && (unstable == 0 || r.dt < unstable)) unstable = r.dt;
  for (const StudyRun& r : first) {
    if (!r.unstable && r.failure.empty() && (unstable == 0 || r.dt < unstable)) stable = std::max(stable, r.dt);
    if (!r.unstable && r.failure.empty() && unstable > 0 && r.dt > unstable) stable_above = std::max(stable_above, r.dt);
  }
  if (stable > 0 && unstable > stable) {
    for (int k = 0; k < o.bisections; ++k) {
      std::vector<StudyRun> probe = {StudyRun(o.integrator, std::sqrt(stable * unstable))};
      run_study(o.scene, o.sets, t_end, quantities.front(), probe, 1, true, o.heat_stage);
      (probe[0].unstable ? unstable : stable) = probe[0].dt;
    }
  }
  // The prediction for the integrator swept (its mechanics: a heat-stage sweep varies freeze.dt):
  // the start's, joined with the limit on the finest run's end state.
  StabilityEstimate est = estimate_stability(base, o.heat_stage ? "" : o.integrator);
  const StabilityEstimate at_start = est;
  const auto settled = std::find_if(first.begin(), first.end(), [](const StudyRun& r) { return r.at_end.is_object(); });
  if (settled != first.end()) {
    MechanicalLimit end = limit_of_json(settled->at_end);
    end.state += format(" (the end of the run at dt = %.4g s)", settled->dt);
    est = with_state(est, end);
  }

  StudyReport report("sweep", {{"scene", base.name}});
  nlohmann::json& out = report.json();
  out["integrator"] = o.integrator;
  out["t_end"] = t_end;
  out["ranks"] = rank_count();  // how it ran: the MPI processes (src/studies/study_ranks.h)
  out["quantities"] = quantities;
  out["dt"] = dts;
  out["largest_stable_dt"] = stable > 0 ? nlohmann::json(stable) : nlohmann::json(nullptr);
  out["smallest_unstable_dt"] = unstable > 0 ? nlohmann::json(unstable) : nlohmann::json(nullptr);
  out["estimate"] = estimate_json(est);
  out["estimate_at_start"] = estimate_json(at_start);
  out["limit_at_end"] = settled != first.end() ? settled->at_end : nlohmann::json(nullptr);
  const StudyLimit binding = study_limit(est, base, o.integrator, o.heat_stage);
  const bool conduction_binds = binding.conduction;
  const double limit = binding.dt;
  out["estimate"]["binding_limit"] = limit;
  std::vector<std::string> header = {"dt", "stable"};
  header.insert(header.end(), quantities.begin(), quantities.end());
  report.csv_row(header);
  report.table("     dt          stable");
  for (const std::string& q : quantities) report.table("  %s", q.c_str());
  report.table("\n");
  nlohmann::json values = nlohmann::json::object();
  for (size_t qi = 0; qi < quantities.size(); ++qi) {
    const std::vector<StudyRun>& runs = per_quantity[qi];
    const bool field = shape_of(base, quantities[qi]) != QuantityShape::number;  // or a list
    nlohmann::json column = nlohmann::json::array();
    for (const StudyRun& r : runs) {
      if (!r.failure.empty()) {
        column.push_back(nullptr);
      } else if (ensemble) {
        column.push_back(ensemble_of(member_values(ensembles[qi].points[&r - runs.data()]), o.ensemble.level).mean);
      } else {
        column.push_back(field ? max_abs_difference(r.value, runs.front().value) : r.value.front());
      }
    }
    values[quantities[qi]] = column;
  }
  out["values"] = values;
  out["stable"] = nlohmann::json::array();
  out["failure"] = nlohmann::json::array();  // why a run stopped (an instability check, or an error)
  for (const StudyRun& r : first) out["failure"].push_back(r.failure.empty() ? nlohmann::json(nullptr) : nlohmann::json(r.failure));
  for (size_t k = 0; k < dts.size(); ++k) {
    const bool ok = first[k].failure.empty();
    out["stable"].push_back(ok);
    report.table("  %12.4e  %-6s", dts[k], ok ? "yes" : first[k].unstable ? "no" : "error");
    std::vector<std::string> row = {csv_number(dts[k]), ok ? "1" : "0"};
    for (const std::string& q : quantities) {
      const auto& v = values[q][k];
      report.table("  %12.5g", v.is_null() ? NAN : v.get<double>());
      row.push_back(v.is_null() ? "" : csv_exact(v.get<double>()));
    }
    report.table("\n");
    report.csv_row(row);
  }
  const std::string predicted =
      conduction_binds ? format("%.5g s (explicit conduction, %.4g / lambda_max)", limit, real_stability_of(o.integrator))
                       : format("%.5g s: %s", limit, describe_limit(est).c_str());
  const std::string recommended = std::isfinite(est.recommended_dt) && limit > 0 && std::isfinite(limit)
                                      ? format("; recommended dt %.3g s, %.3g of the limit", est.recommended_dt,
                                               est.recommended_dt / limit)
                                      : std::string();
  // A tangential-rotational or rolling limit bounds a mode that grows only to its cap: the run
  // goes on, wrong (contacts creep), and may blow up only at the normal modes' limit.
  const double blow_up = conduction_binds ? limit : est.limit.blow_up_dt;
  const std::string also = blow_up > limit && std::isfinite(blow_up)
                               ? format("; blow-up limit %.5g s (normal and wall-body modes: between the two, sticking "
                                        "contacts creep within their cap with the energy balanced, no check stops them: "
                                        "the fields above drift instead)",
                                        blow_up)
                               : std::string();
  std::string boundary;
  if (stable > 0 && unstable > 0) {
    const double measured = std::sqrt(stable * unstable);
    out["measured_over_predicted"] = limit > 0 && std::isfinite(limit) ? nlohmann::json(measured / limit) : nlohmann::json(nullptr);
    out["measured_over_blow_up"] = blow_up > 0 && std::isfinite(blow_up) ? nlohmann::json(measured / blow_up) : nlohmann::json(nullptr);
    boundary = format("stability boundary between %.5g and %.5g s, predicted %s%s; measured / predicted %.3f%s%s\n",
                      stable, unstable, predicted.c_str(), also.c_str(), measured / limit,
                      blow_up > limit && std::isfinite(blow_up) ? format(", / blow-up limit %.3f", measured / blow_up).c_str() : "",
                      recommended.c_str());
  } else {
    boundary = format("no stability boundary inside the sweep; predicted %s%s%s\n", predicted.c_str(), also.c_str(),
                      recommended.c_str());
  }
  out["stable_above_boundary"] = stable_above > 0 ? nlohmann::json(stable_above) : nlohmann::json(nullptr);
  if (stable_above > 0)
    boundary += format("runs above the boundary were stable again, up to %.5g s: a window of instability (the "
                       "first failure is the boundary)\n",
                       stable_above);
  if (ensemble) boundary += ensemble_sweep(o, dts, quantities, ensembles, members, out);
  report.publish(format("%s with %s to t = %g s (%s)\n\n", base.name.c_str(), o.integrator.c_str(), t_end,
                        ensemble ? "numbers: ensemble means" : "fields: difference from the smallest dt"),
                 "\n" + boundary, o.out_dir, o.quiet);
  require_a_result(first);
  return out;
}

}  // namespace kiln
