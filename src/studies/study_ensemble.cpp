#include "src/studies/study_ensemble.h"

#include <algorithm>
#include <cmath>

#include "src/base/error.h"
#include "src/base/nearest.h"
#include "src/scene/scene_yaml.h"
#include "src/studies/study_report.h"

namespace kiln {

EnsembleOptions ensemble_options(const std::string& seeds, double se, int max_seeds, bool max_seeds_given, double level,
                                 double tolerance, bool tolerance_given) {
  EnsembleOptions o;
  o.level = level;
  o.tolerance = tolerance;
  o.max_seeds = max_seeds;
  o.max_seeds_given = max_seeds_given;
  o.se_target = se;
  if (!(level >= 0.5 && level < 1))
    throw InputError("--level: a confidence level in [0.5, 1) is needed, got " + message_number(level));
  if (tolerance_given && (!(tolerance > 0) || !std::isfinite(tolerance)))
    throw InputError("--tolerance: the largest bias you accept, a number above 0 in the quantity's unit, is needed, got " +
                     message_number(tolerance));
  if (max_seeds_given && (max_seeds < 4 || max_seeds > 4096))
    throw InputError("--max-seeds: a whole number in [4, 4096] is needed, got " + std::to_string(max_seeds));
  if (seeds.empty()) {
    if (se > 0) throw InputError("--se is the target of --seeds auto: give --seeds auto");
    return o;
  }
  if (seeds == "auto") {
    o.automatic = true;
    if (!(se > 0) || !std::isfinite(se))
      throw InputError("--seeds auto adds members until the standard error of each mean is below --se: give --se, "
                       "a positive number in the quantity's unit");
    return o;
  }
  size_t used = 0;
  long long n = 0;
  try {
    n = std::stoll(seeds, &used);
  } catch (const std::exception&) {
    used = 0;
  }
  if (used != seeds.size() || n < 2 || n > 4096)
    throw InputError("--seeds: a whole number of members in [2, 4096] or 'auto' is needed, got '" + seeds + "'");
  if (se > 0) throw InputError("--se is the target of --seeds auto, not of --seeds " + seeds);
  if (max_seeds_given) throw InputError("--max-seeds caps --seeds auto, not --seeds " + seeds + " (a fixed size)");
  o.seeds = static_cast<int>(n);
  return o;
}

void require_seeds_for_statistics(const EnsembleOptions& o) {
  if (o.on()) return;
  if (o.level_given) throw InputError("--level is the confidence level of ensemble statistics: give --seeds N or --seeds auto");
  if (o.tolerance > 0)
    throw InputError("--tolerance judges the bias of ensemble means: give --seeds N or --seeds auto with it");
  if (o.max_seeds_given) throw InputError("--max-seeds caps --seeds auto: give --seeds auto with it");
}

void check_ensemble(const Scene& scene, const std::string& quantity) {
  if (scene.random_sources.empty())
    throw InputError("scene '" + scene.name +
                     "' declares nothing random (no fill, lattice jitter, random radius or random_velocity): every "
                     "member of an ensemble would be the same run");
  if (const QuantityShape shape = shape_of(scene, quantity); shape != QuantityShape::number) {
    std::vector<std::string> numbers;
    for (const std::string& q : study_quantities(scene))
      if (shape_of(scene, q) == QuantityShape::number) numbers.push_back(q);
    throw InputError("--seeds studies the ensemble mean of one number per run; '" + quantity + "' is a " +
                     (shape == QuantityShape::field ? "field" : "list") + "; the numbers of scene '" + scene.name +
                     "': " + (numbers.empty() ? std::string("none (its report: adds them)") : choices_nearest_first(quantity, numbers)));
  }
}

std::string member_set(int member) { return "ensemble_member=" + std::to_string(member); }

int Members::number(int slot) {
  while (static_cast<int>(numbers_.size()) <= slot) {
    const int n = next_++;
    try {
      std::vector<std::string> sets = sets_;
      sets.push_back(member_set(n));
      load_scene(scene_, sets);
      numbers_.push_back(n);
    } catch (const InputError& e) {
      skipped_.emplace_back(n, e.what());
      if (skipped_.size() > 10 + 2 * numbers_.size())
        throw StudyError(format("ensemble members cannot be built: %zu of the first %d fail, as member %d does: %s",
                                skipped_.size(), n + 1, n, e.what()));
    }
  }
  return numbers_[slot];
}

EnsembleRuns run_ensembles(const std::vector<StudyRun>& points, const EnsembleOptions& o, Members& numbers,
                           const std::function<void(std::vector<StudyRun>&)>& run) {
  EnsembleRuns r;
  r.points.assign(points.size(), {});
  int target = o.automatic ? std::min(4, o.max_seeds) : o.seeds;
  for (;;) {
    std::vector<Growth> grow;
    for (size_t p = 0; p < points.size(); ++p) grow.push_back({&r.points[p], points[p], target});
    grow_ensembles(grow, numbers, run);
    r.members = target;
    ++r.rounds;
    if (!o.automatic) return r;
    // The largest standard error over the points that ran, against the target.
    double worst = 0;
    for (const std::vector<StudyRun>& members : r.points) {
      const std::vector<double> v = member_values(members);
      if (!v.empty()) worst = std::max(worst, ensemble_of(v, o.level).se / o.se_target);
    }
    r.target_reached = worst <= 1;
    if (r.target_reached || r.members >= o.max_seeds) return r;
    // The standard error falls as 1 / sqrt(N): the size that reaches the target, a tenth more
    // for the estimate's own noise, and two members more at least.
    const int wanted = static_cast<int>(std::ceil(1.1 * r.members * worst * worst));
    target = std::min(o.max_seeds, std::max(wanted, r.members + 2));
  }
}

void grow_ensembles(const std::vector<Growth>& grow, Members& members,
                    const std::function<void(std::vector<StudyRun>&)>& run) {
  std::vector<StudyRun> batch;
  for (const Growth& g : grow)
    for (int m = static_cast<int>(g.members->size()); m < g.to; ++m) {
      batch.push_back(g.point);
      batch.back().sets.push_back(member_set(members.number(m)));
    }
  run(batch);
  size_t next = 0;
  for (const Growth& g : grow)
    while (static_cast<int>(g.members->size()) < g.to) g.members->push_back(batch[next++]);
}

std::vector<double> member_values(const std::vector<StudyRun>& members) {
  std::vector<double> v;
  for (const StudyRun& r : members) {
    if (!r.failure.empty() || r.value.empty() || !std::isfinite(r.value.front())) return {};
    v.push_back(r.value.front());
  }
  return v;
}

std::string member_failure(const std::vector<StudyRun>& members, bool* unstable) {
  if (unstable) *unstable = false;
  for (size_t m = 0; m < members.size(); ++m)
    if (!members[m].failure.empty()) {
      if (unstable) *unstable = members[m].unstable;
      return format("member %zu: %s", m, members[m].failure.c_str());
    }
  return "";
}

std::string member_unmeasured(const std::vector<StudyRun>& members, const std::string& quantity) {
  for (size_t m = 0; m < members.size(); ++m)
    if (members[m].failure.empty() && (members[m].value.empty() || !std::isfinite(members[m].value.front())))
      return format("%s not measured by member %zu (at dt = %g s; a longer --t-end may reach it)", quantity.c_str(), m,
                    members[m].dt);
  return "";
}

std::string member_problem(const std::vector<StudyRun>& members, const std::string& quantity) {
  const std::string failure = member_failure(members);
  return failure.empty() ? member_unmeasured(members, quantity) : failure;
}

namespace {
nlohmann::json number(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }
}  // namespace

nlohmann::json ensemble_json(const std::vector<double>& values, double level) {
  const Ensemble e = ensemble_of(values, level);
  return {{"members", e.n},
          {"mean", number(e.mean)},
          {"standard_deviation", number(e.sd)},
          {"standard_error", number(e.se)},
          {"interval", {number(e.low), number(e.high)}},
          {"member_values", values}};
}

nlohmann::json bias_json(const Bias& b, double tolerance) {
  const char* verdicts[] = {"within_tolerance", "biased", "no_bias_detectable"};
  return {{"test", b.test},
          {"estimate", number(b.estimate)},
          {"standard_error", number(b.se)},
          {"degrees_of_freedom", number(b.dof)},
          {"interval", {number(b.low), number(b.high)}},
          {"p_value", number(b.p_value)},
          {"smallest_detectable", number(b.detectable)},
          {"verdict", std::isfinite(b.low) ? nlohmann::json(verdicts[static_cast<int>(verdict_of(b, tolerance))])
                                           : nlohmann::json(nullptr)},
          {"says", describe(b, tolerance)}};
}

nlohmann::json ensemble_settings_json(const EnsembleOptions& o, const EnsembleRuns& runs, const Members& members) {
  nlohmann::json j = {{"members", runs.members}, {"level", o.level}, {"power", o.power},
                      {"member_key", "ensemble_member"}, {"tolerance", o.tolerance > 0 ? number(o.tolerance) : nullptr}};
  nlohmann::json skipped = nlohmann::json::array();
  for (const auto& [n, why] : members.skipped()) skipped.push_back({{"member", n}, {"reason", why}});
  j["skipped_members"] = skipped;
  if (o.automatic) {
    j["automatic"] = {{"standard_error_target", o.se_target}, {"max_seeds", o.max_seeds},
                      {"target_reached", runs.target_reached}, {"rounds", runs.rounds}};
  }
  return j;
}

std::string ensemble_heading(const EnsembleOptions& o, const EnsembleRuns& runs, const Members& members,
                             const std::string& reference) {
  std::string s = format("ensembles of %d members (ensemble_member = 0, 1, ...: every seed the scene declares varies)",
                         runs.members);
  if (!members.skipped().empty()) {
    s += format("; %zu member%s skipped, its scene could not be built (member %d: %s)", members.skipped().size(),
                members.skipped().size() == 1 ? "" : "s", members.skipped().front().first,
                members.skipped().front().second.c_str());
  }
  if (o.automatic)
    s += runs.target_reached ? format("; --seeds auto: every standard error <= %.3g after %d rounds", o.se_target, runs.rounds)
                             : format("; --seeds auto stopped at its cap of %d members with a standard error above "
                                      "%.3g: raise --max-seeds or --se",
                                      o.max_seeds, o.se_target);
  s += format("\nmean +- half the %g %% interval (Student t); bias against %s, paired seed by seed (paired t test)",
              100 * o.level, reference.c_str());
  if (o.tolerance > 0) s += format(", judged against the tolerance %.3g", o.tolerance);
  return s + "\n";
}

}  // namespace kiln
