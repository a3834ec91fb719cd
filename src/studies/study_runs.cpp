#include "src/studies/study_runs.h"

#include <algorithm>
#include <atomic>
#include <chrono>
#include <cmath>
#include <cstdint>
#include <numeric>
#include <string_view>
#include <thread>
#ifdef _OPENMP
#include <omp.h>
#endif

#include <sched.h>

#include "contact/normal_force.h"
#include "integrators/integrator.h"
#include "src/base/error.h"
#include "src/run/stability.h"
#include "src/studies/exact_solutions.h"
#include "src/base/nearest.h"
#include "src/scene/observer_catalogue.h"
#include "src/scene/overrides.h"
#include "src/base/progress.h"
#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "src/studies/study_ranks.h"

namespace kiln {

namespace {

// The catalogue's key `quantity` among the observers `scene` reports, or nullptr.
const ObserverKey* reported_key(const Scene& scene, const std::string& quantity) {
  for (const std::string& r : scene.report)
    for (const ObserverKey& k : find_observer(r)->keys)
      if (k.path == quantity && k.kind != ObserverKey::Kind::text && k.written_in(scene)) return &k;
  return nullptr;
}

// The values at `path` below `node` (src/scene/observer_catalogue.h): a member of an object, or
// of every element of an array of objects (one per wall); null (not measured) is NaN.
void collect(const nlohmann::json& node, std::string_view path, std::vector<double>& out) {
  if (node.is_null()) {
    out.push_back(NAN);
  } else if (path.empty() && node.is_array()) {
    for (const nlohmann::json& v : node) out.push_back(v.is_null() ? NAN : v.get<double>());
  } else if (path.empty()) {
    out.push_back(node.get<double>());
  } else if (node.is_array()) {
    for (const nlohmann::json& element : node) collect(element, path, out);
  } else {
    const size_t dot = path.find('.');
    collect(node.at(std::string(path.substr(0, dot))), dot == path.npos ? "" : path.substr(dot + 1), out);
  }
}

// Every run's own figures in summary.json, whatever its report: the mean contacts per particle
// (sampled at the frames) and each wall's mean loads over the run (force: a list of x and y).
std::vector<std::string> run_quantities(const Scene& scene) {
  std::vector<std::string> q = {"mean_contacts"};
  for (const Wall& w : scene.walls)
    for (const char* load : {"mean_torque", "mean_power", "mean_force"}) q.push_back("walls." + w.name + "." + load);
  return q;
}

bool is_run_quantity(const Scene& scene, const std::string& quantity) {
  const auto q = run_quantities(scene);
  return std::find(q.begin(), q.end(), quantity) != q.end();
}

}  // namespace

std::vector<std::string> study_quantities(const Scene& scene) {
  std::vector<std::string> q = {"position", "velocity"};
  if (scene.thermal) q.push_back("temperature");
  for (const std::string& r : scene.report)
    for (const ObserverKey& k : find_observer(r)->keys)
      if (k.kind != ObserverKey::Kind::text && k.written_in(scene)) q.push_back(k.path);
  for (const std::string& r : run_quantities(scene)) q.push_back(r);
  return q;
}

std::vector<std::string> headline_quantities(const Scene& scene) {
  std::vector<std::string> q;
  for (const std::string& r : scene.report)
    for (const ObserverKey& k : find_observer(r)->keys)
      if (k.headline && k.written_in(scene)) q.push_back(k.path);
  return q;
}

QuantityShape shape_of(const Scene& scene, const std::string& quantity) {
  const ObserverKey* k = reported_key(scene, quantity);
  if (!k && is_run_quantity(scene, quantity))
    return quantity.size() > 10 && quantity.substr(quantity.size() - 10) == "mean_force" ? QuantityShape::list
                                                                                         : QuantityShape::number;
  if (!k) return QuantityShape::field;
  return k->kind == ObserverKey::Kind::number ? QuantityShape::number : QuantityShape::list;
}

std::string default_quantity(const Scene& scene, bool heat_stage) {
  return scene.frozen || heat_stage ? "temperature" : "position";
}

void check_quantity(const Scene& scene, const std::string& quantity) {
  const auto available = study_quantities(scene);
  if (std::find(available.begin(), available.end(), quantity) != available.end()) return;
  std::string reported_by;  // a case quantity of an observer the scene does not ask for
  for (const ObserverEntry& e : observer_catalogue())
    for (const ObserverKey& k : e.keys)
      if (reported_by.empty() && k.path == quantity && k.kind != ObserverKey::Kind::text)
        reported_by = " ('" + quantity + "' is reported by '" + e.name + "', which the scene's report: does not name)";
  throw InputError("unknown quantity '" + quantity + "' for scene '" + scene.name + "'; available: " +
                   choices_nearest_first(quantity, available) + reported_by);
}

double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b) {
  const size_t n = std::min(a.size(), b.size());
  if (n == 0) return NAN;
  double worst = 0;
  for (size_t k = 0; k < n; ++k) {
    const double d = std::abs(a[k] - b[k]);
    if (std::isnan(d)) return NAN;
    worst = std::max(worst, d);
  }
  return worst;
}

std::vector<double> quantity_value(const std::string& quantity, const FinalFields& fields, const nlohmann::json& summary) {
  if (quantity == "position") return fields.position;
  if (quantity == "velocity") return fields.velocity;
  if (quantity == "temperature") return fields.temperature;
  std::vector<double> values;
  if (quantity.rfind("walls.", 0) == 0) {  // walls.<name>.<load>: the wall of that name (a name may hold dots)
    const size_t load = quantity.rfind('.');
    const std::string name = quantity.substr(6, load - 6);
    for (const nlohmann::json& w : summary.at("walls"))
      if (w.at("name") == name) collect(w, quantity.substr(load + 1), values);
    return values;
  }
  collect(summary, quantity, values);
  return values;
}

namespace {

void run_one(const std::string& path, const std::vector<std::string>& base_sets, double t_end, const std::string& q,
             bool heat_stage, StudyRun& run) {
  std::vector<std::string> sets = base_sets;
  sets.push_back((heat_stage ? "freeze.integrator=" : "integrator=") + run.integrator);
  sets.push_back(assignment(heat_stage ? "freeze.dt" : "dt", run.dt));
  sets.push_back(assignment("t_end", t_end));
  sets.insert(sets.end(), run.sets.begin(), run.sets.end());
  const auto started = std::chrono::steady_clock::now();
  try {
    // One frame at the end (no steps shortened to land on frames), unless the scene freezes or
    // stops by its kinetic energy (checked at its frames), or the quantity is a report's: the
    // observers sample at the frames, and a discharge rate, a dynamic angle of repose or an
    // effective friction over a window of the run was not measured from two samples.
    Scene scene = load_scene(path, sets);
    if (!scene.freeze.enabled && scene.stop_kinetic_energy == 0 && !reported_key(scene, q) && q != "mean_contacts")
      scene.output_interval = t_end;
    const int runs = run.repeats > 1 ? run.repeats + 1 : 1;  // a warm-up first when timing
    const StabilityEstimate estimate = estimate_stability(scene);  // once for the repeats
    double best = INFINITY;
    for (int k = 0; k < runs; ++k) {
      FinalFields fields;
      RunOptions options{"", true, &fields};
      options.limit_at_end = run.limit_at_end;
      options.estimate = &estimate;
      const nlohmann::json s = run_scene(scene, options);
      if (s["stability"].contains("at_end")) run.at_end = s["stability"]["at_end"];
      // A study of the heating stage counts that stage's cost alone (the settling is the same in
      // every run).
      const nlohmann::json& cost = heat_stage ? s["integrator_stats"]["heat_stage"] : s;
      if (runs == 1 || k > 0) best = std::min(best, cost["wall_seconds"].get<double>());
      run.value = quantity_value(q, fields, s);
      run.rhs_evals = cost["rhs_evals"].get<long>();
    }
    run.seconds = best;
  } catch (const InstabilityError& e) {
    run.unstable = true;
    run.failure = e.what();
  } catch (const std::exception& e) {
    run.failure = e.what();
  }
  // A failed run cost its time too (a study's budget counts it): timed here, as the summary that
  // times a run is not written for one that fails.
  if (!run.failure.empty())
    run.seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - started).count();
}

// What one run of `runs` costs, relative to the others: its steps, times its timed repeats.
double cost_of(const StudyRun& run) { return (run.repeats > 1 ? run.repeats + 1 : 1) / run.dt; }

// The runs this rank runs, costliest first: each run, costliest first, goes to the rank with the
// least work so far (ties: the lower rank), so the levels of an order study, each twice the work of
// the last, balance. Every rank computes the same assignment from the same runs.
std::vector<size_t> runs_of_this_rank(const std::vector<StudyRun>& runs) {
  std::vector<size_t> order(runs.size());
  std::iota(order.begin(), order.end(), size_t{0});
  std::stable_sort(order.begin(), order.end(),
                   [&](size_t a, size_t b) { return cost_of(runs[a]) > cost_of(runs[b]); });
  const int rank = this_rank();
  std::vector<double> load(rank_count(), 0.0);
  std::vector<size_t> mine;
  for (size_t k : order) {
    const auto least = std::min_element(load.begin(), load.end());
    *least += cost_of(runs[k]);
    if (least - load.begin() == rank) mine.push_back(k);
  }
  return mine;
}

// Worker threads: `threads`, or (0) every core this process may run on (its CPU affinity, which
// mpirun sets when it binds a rank), and no more than there are runs.
size_t worker_count(int threads, size_t runs) {
  cpu_set_t cpus;
  const int cores = sched_getaffinity(0, sizeof cpus, &cpus) == 0 ? CPU_COUNT(&cpus)
                                                                   : static_cast<int>(std::thread::hardware_concurrency());
  return std::min(runs, static_cast<size_t>(std::max(1, threads > 0 ? threads : cores)));
}

// Sends the results of this rank's runs to every rank and fills in everyone's (src/studies/study_ranks.h),
// as CBOR: doubles exactly, NaN included. Without MPI the results go through the same encoding.
void share_results(std::vector<StudyRun>& runs, const std::vector<size_t>& mine) {
  nlohmann::json block = nlohmann::json::array();
  for (size_t k : mine) {
    const StudyRun& r = runs[k];
    block.push_back({{"run", k}, {"value", r.value}, {"rhs_evals", r.rhs_evals}, {"seconds", r.seconds},
                     {"unstable", r.unstable}, {"failure", r.failure},
                     {"at_end", r.at_end}});
  }
  const std::vector<std::uint8_t> bytes = nlohmann::json::to_cbor(block);
  std::vector<int> received(runs.size(), 0);
  for (const std::string& from_rank : gather_on_every_rank(std::string(bytes.begin(), bytes.end()))) {
    for (const nlohmann::json& r : nlohmann::json::from_cbor(from_rank)) {
      const size_t k = r["run"].get<size_t>();
      StudyRun& run = runs.at(k);
      run.value = r["value"].get<std::vector<double>>();
      run.rhs_evals = r["rhs_evals"].get<long>();
      run.seconds = r["seconds"].get<double>();
      run.unstable = r["unstable"].get<bool>();
      run.failure = r["failure"].get<std::string>();
      run.at_end = r["at_end"];
      ++received[k];
    }
  }
  // Every run exactly once: no rank dropped one, no two ranks reported the same.
  if (std::any_of(received.begin(), received.end(), [](int n) { return n != 1; }))
    throw std::logic_error("the ranks' results do not cover the study's runs exactly once");
}

}  // namespace

void run_study(const std::string& scene, const std::vector<std::string>& sets, double t_end, const std::string& quantity,
               std::vector<StudyRun>& runs, int threads, bool quiet, bool heat_stage) {
  const Scene base = load_scene(scene, sets);
  if (heat_stage && !base.freeze.enabled)
    throw InputError("--heat-stage needs a scene that freezes (a 'freeze:' block): '" + scene + "' has none");
  // The step-count limit of kiln run, before any run starts (a study of 1e-12 s steps never ended).
  for (const StudyRun& run : runs) {
    const bool adaptive = std::any_of(run.sets.begin(), run.sets.end(),
                                      [](const std::string& s) { return s.rfind("rtol=", 0) == 0; });
    if (!adaptive) refuse_too_many_steps(base, run.dt, t_end, heat_stage, "a run of the study with " + run.integrator);
  }
  // This rank's share (all of them without MPI), on its threads.
  const std::vector<size_t> mine = runs_of_this_rank(runs);
  std::atomic<size_t> next{0}, finished{0};
  auto work = [&] {
    // The study's threads are its runs: each run's own loops stay on its worker (OpenMP would
    // put a team of every core's threads under each of them). Results do not depend on it.
#ifdef _OPENMP
    omp_set_num_threads(1);
#endif
    for (size_t k = next++; k < mine.size(); k = next++) {
      run_one(scene, sets, t_end, quantity, heat_stage, runs[mine[k]]);
      ++finished;
    }
  };
  std::vector<std::thread> pool(worker_count(threads, mine.size()));
  for (std::thread& worker : pool) worker = std::thread(work);
  Progress progress("study", quiet);
  while (finished < mine.size()) {
    progress.update_runs(static_cast<long>(finished), static_cast<long>(mine.size()));
    std::this_thread::sleep_for(std::chrono::milliseconds(100));
  }
  progress.finish();
  for (auto& th : pool) th.join();
  share_results(runs, mine);
}

void refuse_too_many_steps(const Scene& base, double dt, double t_end, bool heat_stage, const std::string& what) {
  if (const auto refusal = heat_stage ? too_many_steps("freeze.dt", dt, t_end) : too_many_moving_steps(base, dt, t_end))
    throw InputError(what + ": " + refusal->substr(0, refusal->rfind(", or run it anyway")));
}

StudyReference study_reference(const Scene& scene, const std::string& path, const std::vector<std::string>& sets,
                               const std::string& quantity, double t_end, const std::string& kind, double fine_dt,
                               double fine_rtol, bool heat_stage) {
  // Before the reference, whose exact solution (a bounce at a time) or fine run would take as long
  // as the study's finest run: `kiln order --t-end 1e10` computed bounces silently for ever (issue
  // 28's last review) before run_study refused its runs.
  refuse_too_many_steps(scene, fine_dt, t_end, heat_stage, "the study's finest step");
  if (kind == "analytic") {
    const auto exact = exact_quantity(scene, quantity, t_end);
    if (!exact)
      throw InputError("no exact solution is registered for scene '" + scene.name + "' and quantity '" + quantity +
                       "'; registered: " + exact_solutions_known() + ". Use --reference fine (or richardson)");
    return {*exact, 0};
  }
  if (heat_stage)
    throw InputError("--heat-stage compares with the exact solution of the settled network (--reference analytic): "
                     "a fine adaptive run would adapt the settling stage too");
  // A force that jumps at a contact's onset (the linear dashpot's): without events an adaptive step
  // fails to pass it at this tolerance. Hertz forces (Tsuji's dashpot ~ delta^(1/4)) are continuous
  // there. A Coulomb or rolling cap kinks the force where a spring starts or stops slipping: located,
  // the reference keeps erk5's order through it.
  const bool kinks = std::any_of(scene.laws.begin(), scene.laws.end(), [](const PairLaw& l) {
    return contact::force_jumps_at_touch(l.contact.model) || l.contact.friction > 0 || l.contact.rolling_friction > 0;
  });
  std::vector<StudyRun> fine;
  for (double rtol : {fine_rtol, 0.1 * fine_rtol}) {
    std::vector<std::string> tight = {assignment("rtol", rtol), "atol=1e-15"};
    if (!scene.frozen && kinks) tight.push_back("contact_events=true");
    fine.emplace_back("erk5", fine_dt, tight);
  }
  run_study(path, sets, t_end, quantity, fine, 1);
  for (const StudyRun& r : fine)
    if (!r.failure.empty()) throw StudyError("the fine reference run failed: " + r.failure);
  return {fine[0].value, max_abs_difference(fine[0].value, fine[1].value)};
}

StudyLimit study_limit(const StabilityEstimate& est, const Scene& scene, const std::string& integrator, bool heat_stage) {
  const double conduction =
      real_stability_of(integrator) / 2 * (heat_stage ? est.thermal_dt_limit : est.thermal_dt_limit_network);
  const bool binds = scene.thermal && (scene.frozen || heat_stage || conduction < est.dt_limit);
  return {binds ? conduction : est.dt_limit, binds};
}

void require_a_result(const std::vector<StudyRun>& runs) {
  if (runs.empty() || std::any_of(runs.begin(), runs.end(), [](const StudyRun& r) { return r.failure.empty(); }))
    return;
  throw StudyError("every run of the study failed (" + std::to_string(runs.size()) + " runs); the first: " +
                   runs.front().failure);
}

}  // namespace kiln
