#include "src/studies/study_recommend.h"

#include <algorithm>
#include <cmath>

#include "integrators/integrator.h"
#include "src/base/error.h"
#include "src/base/nearest.h"
#include "src/scene/scene_yaml.h"
#include "src/studies/exact_solutions.h"
#include "src/studies/study_order.h"
#include "src/studies/study_report.h"
#include "src/studies/study_runs.h"

namespace kiln {

namespace {

struct Candidate {
  std::string name;
  StabilityEstimate start;  // the estimate at t = 0
  double limit = INFINITY;  // its stability limit: the smallest at t = 0 and on every probed run's end state (s)
  std::string limit_state = "the state at t = 0";
  bool conduction = false;  // conduction's limit binds
  double first = 0;         // the first step probed (s)
  double next = 0;          // the next step to probe (s)
  int probed = 0;
  int beyond = 0;           // of them, steps beyond 0.9 of the limit on their own end states
  bool met = false;         // some step met the tolerance (its half step may not have)
  int pending = -1;         // a probe that met the tolerance, waiting for its half step to confirm it
  bool live = true;
  std::string stopped;      // why its probe ended
};

// One probed step: its error (or bias) against the reference and its cost.
struct Probe {
  std::string integrator;
  double dt = 0, fraction = NAN;  // fraction: of the integrator's stability limit
  double error = NAN;             // |difference| (plus the reference's accuracy), or |bias|
  Bias bias;                      // chaotic scenes
  std::vector<double> values;     // chaotic scenes: each member's value
  double limit = INFINITY;        // the limit it is judged by: its candidate's, and on its own runs' end states
  std::string limit_state;
  bool meets = false, unstable = false, beyond = false;
  bool confirmed = false;  // it met the tolerance and so did its half step: it may be recommended
  std::string failure;
  double seconds = 0;  // one run's wall time (an ensemble's mean)
  int members = 1;
  double rhs = 0;
};

double mean_of(const std::vector<StudyRun>& runs, double StudyRun::*field) {
  double s = 0;
  for (const StudyRun& r : runs) s += r.*field / runs.size();
  return s;
}

double total_seconds(const std::vector<StudyRun>& runs) {
  double s = 0;
  for (const StudyRun& r : runs) s += r.seconds;
  return s;
}

// The method a name stands for (an alias's target): two names of one method are one candidate.
std::string method_of(const std::string& name) {
  const IntegratorInfo& info = integrator_info(name);
  return info.alias_of.empty() ? info.name : info.alias_of;
}

}  // namespace

nlohmann::json run_recommend(const RecommendOptions& o) {
  const Scene base = load_scene(o.scene, o.sets);
  if (o.quantity.empty())
    throw InputError("--quantity is required: the quantity the tolerance is about; available: " +
                     choices_nearest_first("", study_quantities(base)));
  check_quantity(base, o.quantity);
  const double tolerance = o.ensemble.tolerance;
  if (!(tolerance > 0))
    throw InputError("--tolerance is required: the error of " + o.quantity + " you accept, in its unit");
  if (o.integrators.empty()) throw InputError("--integrators: give at least one integrator");
  if (o.halvings < 1 || o.halvings > 20)
    throw InputError("--halvings: a whole number in [1, 20] is needed, got " + std::to_string(o.halvings));
  if (!(o.budget >= 0)) throw InputError("--budget: CPU seconds, 0 (none) or more");
  std::vector<std::string> methods;
  for (const std::string& name : o.integrators) {
    make_integrator(name);  // unknown names fail here
    const std::string method = method_of(name);
    for (size_t k = 0; k < methods.size(); ++k)
      if (methods[k] == method)
        throw InputError("--integrators: '" + name + "' is given twice" +
                         (o.integrators[k] == name ? "" : " ('" + o.integrators[k] + "' names the same method, " + method + ")"));
    methods.push_back(method);
  }
  if (o.ensemble.automatic)
    throw InputError("kiln recommend sizes its ensembles by its verdicts (8 members, grown where a verdict needs "
                     "them, up to --max-seeds): give --seeds N for a fixed size, or neither");
  const double t_end = o.t_end > 0 ? o.t_end : base.t_end;
  const bool chaotic = !base.random_sources.empty() || o.ensemble.on();
  const EnsembleOptions& ensemble = o.ensemble;
  if (chaotic) check_ensemble(base, o.quantity);
  // Ensembles start at 8 members (or --seeds N, fixed; or --max-seeds when smaller) and grow only
  // where a verdict needs them.
  const int first_members = ensemble.seeds > 0 ? ensemble.seeds : std::min(8, ensemble.max_seeds);
  const int max_members = ensemble.seeds > 0 ? ensemble.seeds : ensemble.max_seeds;

  std::vector<Candidate> candidates;
  for (const std::string& name : o.integrators) {
    Candidate c;
    c.name = name;
    c.start = estimate_stability(base, o.heat_stage ? "" : name);
    const StudyLimit limit = study_limit(c.start, base, name, o.heat_stage);
    c.limit = limit.dt;
    c.conduction = limit.conduction;
    // No limit (nothing touches, nothing conducts): from 16 of the scene's steps, and a run of 4 steps at least.
    c.first = std::min(std::isfinite(c.limit) ? 0.9 * c.limit : 16 * base.dt, t_end / 4);
    c.next = c.first;
    candidates.push_back(c);
  }
  auto run = [&](std::vector<StudyRun>& batch) {
    run_study(o.scene, o.sets, t_end, o.quantity, batch, o.threads, o.quiet, o.heat_stage);
  };
  double spent = 0;  // CPU seconds of the probe's runs
  // The budget is judged before each batch of runs from what such runs have cost (none known: the
  // first round runs): a batch that would end beyond it is not started.
  auto affordable = [&](double predicted) { return o.budget == 0 || spent + predicted <= o.budget; };

  // The reference.
  nlohmann::json reference_json;
  std::vector<double> reference;          // the value (no randomness), or each member's (chaotic)
  double reference_accuracy = 0;
  std::vector<StudyRun> reference_members;  // chaotic: the reference's members, grown with the probes'
  Members ensemble_members(o.scene, o.sets);
  StudyRun reference_point("", 0);
  double finest = INFINITY;  // the probe's finest step: every reference takes as long as a run of it
  for (const Candidate& c : candidates) finest = std::min(finest, c.first / std::pow(2.0, o.halvings));
  refuse_too_many_steps(base, finest, t_end, o.heat_stage, "the probe's finest step");
  if (chaotic) {
    const auto best = std::max_element(candidates.begin(), candidates.end(), [](const Candidate& a, const Candidate& b) {
      return nominal_order(a.name) < nominal_order(b.name);
    });
    // No candidate runs at or below this step (a half step that was the reference itself would
    // confirm nothing): the probe of a candidate ends above it.
    reference_point = StudyRun(best->name, best->first / std::pow(2.0, o.halvings));
    grow_ensembles({{&reference_members, reference_point, first_members}}, ensemble_members, run);
    for (const StudyRun& r : reference_members) spent += r.seconds;
    reference_json = {{"kind", "ensemble"}, {"integrator", best->name}, {"dt", reference_point.dt}};
  } else if (const auto exact = exact_quantity(base, o.quantity, t_end)) {
    reference = *exact;
    reference_json = {{"kind", "analytic"}};
  } else {
    const StudyReference ref =
        study_reference(base, o.scene, o.sets, o.quantity, t_end, "fine", finest, o.fine_rtol, o.heat_stage);
    reference = ref.value;
    reference_accuracy = ref.accuracy;
    reference_json = {{"kind", "fine"}, {"fine_rtol", o.fine_rtol}, {"accuracy", ref.accuracy}};
  }

  // Chaotic: a probe's bias against the reference's first members, as many as the probe has.
  auto bias_of = [&](const std::vector<StudyRun>& runs) {
    const std::vector<double> values = member_values(runs);
    std::vector<double> ref = member_values(reference_members);
    if (ref.empty())
      throw StudyError(format("the reference ensemble (%s at %g s): ", reference_point.integrator.c_str(),
                              reference_point.dt) +
                       member_problem(reference_members, o.quantity));
    ref.resize(values.size());
    return paired_bias(values, ref, ensemble.level, ensemble.power);
  };
  bool budget_stopped_growth = false;
  // A verdict is decided when the bias's interval lies within the tolerance or wholly beyond it;
  // otherwise the probe (and the reference, to pair with it) gets the members that would shrink the
  // interval to the margin between its estimate and the tolerance (the interval narrows as
  // 1 / sqrt(N)), a tenth more, four at least, up to the cap.
  // Points that cannot be recommended (`skip`: beyond the limit, or failed) are not grown.
  auto decide = [&](const std::vector<StudyRun>& points, std::vector<std::vector<StudyRun>>& results,
                    const std::vector<char>& skip) {
    for (;;) {
      std::vector<Growth> grow;
      int need = 0;
      for (size_t k = 0; k < points.size(); ++k) {
        if (skip[k] || member_values(results[k]).empty()) continue;
        const Bias b = bias_of(results[k]);
        if (!std::isfinite(b.low) || verdict_of(b, tolerance) == BiasVerdict::within_tolerance || b.low > tolerance ||
            b.high < -tolerance)
          continue;
        const int n = static_cast<int>(results[k].size());
        if (n >= max_members) continue;
        const double margin = std::max(std::abs(tolerance - std::abs(b.estimate)), 0.1 * tolerance);
        const double factor = std::pow((b.high - b.low) / 2 / margin, 2);
        const int wanted = std::min(max_members, std::max(n + 4, static_cast<int>(std::ceil(1.1 * n * factor))));
        need = std::max(need, wanted);
        grow.push_back({&results[k], points[k], wanted});
      }
      if (grow.empty()) return;
      if (static_cast<int>(reference_members.size()) < need) grow.push_back({&reference_members, reference_point, need});
      double predicted = 0;
      for (const Growth& g : grow) predicted += (g.to - g.members->size()) * total_seconds(*g.members) / g.members->size();
      if (!affordable(predicted)) {
        budget_stopped_growth = true;
        return;
      }
      std::vector<size_t> before;
      for (const Growth& g : grow) before.push_back(g.members->size());
      grow_ensembles(grow, ensemble_members, run);
      for (size_t g = 0; g < grow.size(); ++g)
        for (size_t m = before[g]; m < grow[g].members->size(); ++m) spent += (*grow[g].members)[m].seconds;
    }
  };

  // The limit a probe is judged by: its candidate's so far, and on each of its runs' end states
  // (a settled heap, a formed bed bind below t = 0's; the members' beds differ). The smallest is
  // the candidate's from then on.
  auto judge_limit = [&](Candidate& c, Probe& p, const std::vector<StudyRun>& runs) {
    for (size_t m = 0; m < runs.size(); ++m) {
      if (!runs[m].at_end.is_object()) continue;
      const StudyLimit joined = study_limit(with_state(c.start, limit_of_json(runs[m].at_end)), base, c.name, o.heat_stage);
      if (joined.dt < c.limit) {
        c.limit = joined.dt;
        c.conduction = joined.conduction;
        c.limit_state = format("the end of its run at dt = %g s", p.dt) +
                        (chaotic ? format(" (member %d)", ensemble_members.number(static_cast<int>(m))) : std::string());
      }
    }
    p.limit = c.limit;
    p.limit_state = c.limit_state;
    p.fraction = p.dt / p.limit;
    p.beyond = p.fraction > 0.9 * (1 + 1e-9);
  };

  // The staged probe: a round per step.
  std::vector<Probe> probes;
  double best_cost = INFINITY;
  bool budget_spent = false;
  for (;;) {
    std::vector<size_t> who;
    std::vector<StudyRun> points;
    double predicted = 0;  // the round's cost, from each candidate's last step (a halving doubles it)
    for (size_t c = 0; c < candidates.size(); ++c)
      if (candidates[c].live) {
        who.push_back(c);
        points.emplace_back(candidates[c].name, candidates[c].next);
        points.back().limit_at_end = !o.heat_stage;
      }
    if (points.empty()) break;
    for (size_t k = 0; k < who.size(); ++k)
      for (auto p = probes.rbegin(); p != probes.rend(); ++p)
        if (p->integrator == candidates[who[k]].name) {
          predicted += p->seconds * (p->dt / points[k].dt) * (chaotic ? first_members : 1);
          break;
        }
    if (!affordable(predicted)) {
      budget_spent = true;
      for (size_t c : who) {
        candidates[c].live = false;
        candidates[c].stopped = format("its next step would go beyond the budget of %g CPU seconds (%.3g spent, the "
                                       "round predicted at %.3g)",
                                       o.budget, spent, predicted);
      }
      break;
    }
    std::vector<std::vector<StudyRun>> results(points.size());
    if (chaotic) {
      std::vector<Growth> batch;
      for (size_t k = 0; k < points.size(); ++k) batch.push_back({&results[k], points[k], first_members});
      grow_ensembles(batch, ensemble_members, run);
    } else {
      run(points);
      for (size_t k = 0; k < points.size(); ++k) results[k] = {points[k]};
    }
    for (const std::vector<StudyRun>& runs : results) spent += total_seconds(runs);
    std::vector<Probe> round(who.size());
    std::vector<char> skip(who.size());
    for (size_t k = 0; k < who.size(); ++k) {
      Probe& p = round[k];
      p.integrator = candidates[who[k]].name;
      p.dt = points[k].dt;
      judge_limit(candidates[who[k]], p, results[k]);
      p.failure = member_failure(results[k], &p.unstable);
      skip[k] = p.beyond || !p.failure.empty();
    }
    if (chaotic) decide(points, results, skip);
    for (size_t k = 0; k < who.size(); ++k) {
      Candidate& c = candidates[who[k]];
      const std::vector<StudyRun>& runs = results[k];
      Probe& p = round[k];
      ++c.probed;
      if (p.failure.empty() && p.beyond)
        p.failure = format("beyond 0.9 of the stability limit on %s, %.4g s: never recommended", p.limit_state.c_str(),
                           p.limit);
      else if (p.failure.empty() && member_values(runs).empty())
        p.failure = member_unmeasured(runs, o.quantity);
      c.beyond += p.beyond;
      // Past the limit the probe goes on from 0.8 of it: the limit on the end states varies by some
      // per cent between members and steps (measured on T3: 4.5e-5 to 6.3e-5 s), and a step at
      // 0.9 of the smallest limit found so far was mostly beyond 0.9 of its own runs' smallest.
      // Within the limit, it halves.
      c.next = p.beyond ? 0.8 * c.limit : p.dt / 2;
      p.seconds = mean_of(runs, &StudyRun::seconds);
      p.members = static_cast<int>(runs.size());
      for (const StudyRun& r : runs) p.rhs += static_cast<double>(r.rhs_evals) / runs.size();
      if (p.failure.empty()) {
        if (chaotic) {
          p.values = member_values(runs);
          p.bias = bias_of(runs);
          p.error = std::abs(p.bias.estimate);
          p.meets = verdict_of(p.bias, tolerance) == BiasVerdict::within_tolerance;
        } else {
          p.error = max_abs_difference(runs.front().value, reference) + reference_accuracy;
          p.meets = p.error <= tolerance;
        }
      }
      c.met = c.met || p.meets;
      probes.push_back(p);
      // A step is recommended only when its half step meets the tolerance too: an error that
      // happens to be small at t_end (a harmonic contact's phase) is no error that falls with dt.
      if (p.meets && c.pending >= 0) {
        probes[c.pending].confirmed = true;
        best_cost = std::min(best_cost, probes[c.pending].seconds);
        c.live = false;
        c.stopped = format("met the tolerance at %g s and at its half (smaller steps cost more)", probes[c.pending].dt);
      } else if (p.meets) {
        c.pending = static_cast<int>(probes.size()) - 1;
      } else {
        c.pending = -1;
        if (!p.failure.empty() && !p.unstable && !p.beyond) {
          c.live = false;  // an error, not the step: halving would not cure it
          c.stopped = p.failure;
        }
      }
      if (!c.live) continue;
      const std::string probed =
          format("%d steps probed", c.probed) + (c.beyond ? format(" (%d beyond 0.9 of the limit)", c.beyond) : "");
      const std::string missed = c.met ? "a step met the tolerance but its half step did not" : "none met the tolerance";
      // A halving doubles a run's cost: a candidate whose next step costs more than the best found
      // stops (a pending one runs its confirmation whatever it costs).
      if (chaotic && c.next <= reference_point.dt * (1 + 1e-9)) {
        c.live = false;
        c.stopped = probed + ", down to the reference's step: " + missed;
      } else if (c.pending < 0 && c.probed >= o.halvings) {
        c.live = false;
        c.stopped = probed + ": " + missed;
      } else if (c.pending >= 0 && c.probed > o.halvings) {
        c.live = false;
        c.stopped = "met the tolerance at its finest step, which its half step could not confirm: more --halvings";
      } else if (c.pending < 0 && 2 * p.seconds > best_cost) {
        c.live = false;
        c.stopped = "its next step would cost more than the cheapest step that meets the tolerance";
      }
    }
  }

  // The recommendation: the cheapest step that meets the tolerance.
  // Costs within a tenth of each other are a tie (one wall-time sample each): fewer forces win it.
  const Probe* chosen = nullptr;
  // Runs of a few milliseconds are timed mostly by the clock's noise: there too, forces decide.
  auto cheaper = [](const Probe& a, const Probe& b) {
    const bool tie = std::abs(a.seconds - b.seconds) <= 0.1 * std::max(a.seconds, b.seconds) ||
                     std::max(a.seconds, b.seconds) < 0.01;
    return tie ? a.rhs < b.rhs : a.seconds < b.seconds;
  };
  for (const Probe& p : probes)
    if (p.confirmed && (!chosen || cheaper(p, *chosen))) chosen = &p;
  const Probe* closest = nullptr;  // the smallest error reached, for the answer when none met
  for (const Probe& p : probes)
    if (p.failure.empty() && (!closest || p.error < closest->error)) closest = &p;

  if (chaotic) {
    reference_json["statistics"] = ensemble_json(member_values(reference_members), ensemble.level);
    reference_json["members_first"] = first_members;
    reference_json["members_cap"] = max_members;
  }
  StudyReport report("recommend", study_header(base, o.quantity, reference_json["kind"].get<std::string>(), t_end));
  nlohmann::json& out = report.json();
  out["tolerance"] = tolerance;
  out["reference_point"] = reference_json;
  out["cpu_seconds"] = spent;
  out["budget"] = o.budget > 0 ? nlohmann::json(o.budget) : nlohmann::json(nullptr);
  out["budget_spent"] = budget_spent;
  out["budget_stopped_growth"] = budget_stopped_growth;
  report.csv_row({"integrator", "dt", "fraction_of_limit", "error", "meets", "seconds", "rhs_evals"});
  report.table("  integrator            dt        of limit   %-30s  meets   s per run   rhs evals\n",
               chaotic ? "bias (interval)" : "error");
  nlohmann::json probes_json = nlohmann::json::array();
  for (const Probe& p : probes) {
    nlohmann::json j = {{"integrator", p.integrator}, {"dt", p.dt}, {"members", p.members},
                        {"fraction_of_limit", std::isfinite(p.fraction) ? nlohmann::json(p.fraction) : nlohmann::json(nullptr)},
                        {"stability_limit", std::isfinite(p.limit) ? nlohmann::json(p.limit) : nlohmann::json(nullptr)},
                        {"limit_state", p.limit_state}, {"meets", p.meets}, {"confirmed", p.confirmed},
                        {"seconds", p.seconds},
                        {"rhs_evals", p.failure.empty() ? nlohmann::json(std::lround(p.rhs)) : nlohmann::json(nullptr)}};
    if (chaotic && !p.values.empty()) j["member_values"] = p.values;
    std::string error;
    if (!p.failure.empty()) {
      j["failure"] = p.failure;
      j["unstable"] = p.unstable;
      error = p.unstable                          ? "unstable"
              : p.beyond                          ? "beyond 0.9 of the limit"
              : p.failure.find("not measured") != std::string::npos ? "not measured"
                                                                       : "failed";
    } else {
      j["error"] = p.error;
      if (chaotic) {
        j["bias"] = bias_json(p.bias, tolerance);
        error = format("%.3g [%.3g, %.3g]", p.bias.estimate, p.bias.low, p.bias.high);
      } else {
        error = format("%.4g", p.error);
      }
    }
    probes_json.push_back(j);
    const std::string rhs = p.failure.empty() ? std::to_string(std::lround(p.rhs)) : "";
    report.table("  %-18s  %10.4e  %8.3f   %-30s  %-5s   %9.4g   %9s\n", p.integrator.c_str(), p.dt, p.fraction,
                 error.c_str(), p.confirmed ? "yes" : p.meets ? "yes*" : "no", p.seconds, rhs.c_str());
    report.csv_row({p.integrator, csv_number(p.dt), csv_number(p.fraction), p.failure.empty() ? csv_number(p.error) : "",
                    p.meets ? "1" : "0", csv_number(p.seconds), rhs});
  }
  out["probes"] = probes_json;
  nlohmann::json stops = nlohmann::json::object();
  std::string ends;
  for (const Candidate& c : candidates) {
    stops[c.name] = {{"stability_limit", std::isfinite(c.limit) ? nlohmann::json(c.limit) : nlohmann::json(nullptr)},
                     {"limit_state", c.limit_state}, {"limit_is_conduction", c.conduction}, {"first_dt", c.first},
                     {"stopped", c.stopped}};
    ends += format("  %s: %s\n", c.name.c_str(), c.stopped.c_str());
  }
  out["candidates"] = stops;
  // What it did not try: the catalogue's other fixed-step schemes, adaptive stepping, steps below the last probed.
  std::vector<std::string> others;
  for (const IntegratorInfo& info : integrator_catalogue())
    if (info.alias_of.empty() && info.integrates_contacts &&
        std::find(methods.begin(), methods.end(), info.name) == methods.end())
      others.push_back(info.name);
  out["integrators"] = o.integrators;
  out["not_tried"] = {{"integrators", others}, {"adaptive_stepping", true},
                      {"steps", "below each candidate's last probed step, and above 0.9 of its stability limit"}};
  std::string verdict;
  if (chosen) {
    out["recommendation"] = {{"integrator", chosen->integrator}, {"dt", chosen->dt},
                             {"fraction_of_limit", chosen->fraction}, {"error", chosen->error},
                             {"seconds_per_run", chosen->seconds}};
    const Candidate& c = *std::find_if(candidates.begin(), candidates.end(),
                                       [&](const Candidate& k) { return k.name == chosen->integrator; });
    verdict = format("recommended: %s at dt = %.4g s (%.2f of its stability limit on %s): %s %.3g within %.3g, and at "
                     "its half step; %.3g s per run\n",
                     chosen->integrator.c_str(), chosen->dt, chosen->fraction, c.limit_state.c_str(),
                     chaotic ? "|bias|" : "error", chosen->error, tolerance, chosen->seconds);
  } else {
    out["recommendation"] = nullptr;
    verdict = format("no probed step met %.3g at itself and at its half step%s: raise --halvings%s, or try other "
                     "--integrators",
                     tolerance, budget_spent || budget_stopped_growth ? " within the budget" : "",
                     budget_spent || budget_stopped_growth ? " or --budget" : "");
    if (closest)
      verdict += format(" (the smallest error reached: %.3g, %s at %.4g s%s)", closest->error,
                        closest->integrator.c_str(), closest->dt,
                        chaotic ? "" : format("; the reference is good to %.2g", std::max(reference_accuracy, 1e-16)).c_str());
    verdict += "\n";
  }
  report.publish(format("%s on %s at t = %g s: the cheapest step within %.3g, reference %s\n%s\n", o.quantity.c_str(),
                        base.name.c_str(), t_end, tolerance, reference_json["kind"].get<std::string>().c_str(),
                        chaotic ? format("%s (ensemble_member = 0, 1, ...); bias against %s at %.4g s (the finest "
                                         "step of the highest-order candidate; its own bias is not measured), paired "
                                         "seed by seed (paired t test), %g %% intervals; meets: the whole interval "
                                         "within the tolerance\n",
                                         first_members == max_members
                                             ? format("ensembles of %d members", first_members).c_str()
                                             : format("ensembles of %d members, grown where a verdict needed them (up "
                                                      "to %d)",
                                                      first_members, max_members)
                                                   .c_str(),
                                         reference_point.integrator.c_str(), reference_point.dt, 100 * ensemble.level)
                                      .c_str()
                                : ""),
                 "\nyes*: met the tolerance, but its half step did not (or was not run): not recommended\n" + ends +
                     verdict +
                     (budget_stopped_growth ? "the budget stopped an ensemble's growth: a verdict it needed stays open\n"
                                            : "") +
                     format("probe cost: %.3g CPU seconds of runs; not tried: %zu other integrators, adaptive stepping, "
                            "steps below each candidate's last\n",
                            spent, others.size()),
                 o.out_dir, o.quiet);
  return out;
}

}  // namespace kiln
