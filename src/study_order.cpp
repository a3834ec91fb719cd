#include "src/study_order.h"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <sstream>
#include <thread>

#include "integrators/integrator.h"
#include "src/error.h"
#include "src/exact_solutions.h"
#include "src/nearest.h"
#include "src/outputs.h"
#include "src/overrides.h"
#include "src/scene_yaml.h"
#include "src/simulation.h"

namespace kiln {

namespace {

// The quantities a scene can be studied on: its state fields, and the scalars its case
// quantities (report:) put in the summary.
std::vector<std::string> available_quantities(const Scene& scene) {
  std::vector<std::string> q = {"position", "velocity"};
  if (scene.thermal) q.push_back("temperature");
  for (const std::string& r : scene.report) {
    if (r == "heap") q.insert(q.end(), {"heap_angle_deg", "packing_fraction"});
    if (r == "incline_motion") q.insert(q.end(), {"incline_acceleration", "slip_ratio"});
    if (r == "temperatures") q.insert(q.end(), {"temperature_mean", "temperature_min", "temperature_max", "heat_content"});
  }
  return q;
}

// The studied quantity of one run: a state field, or a scalar the summary reports.
std::vector<double> quantity_of(const std::string& q, const FinalFields& f, const nlohmann::json& summary) {
  if (q == "position") return f.position;
  if (q == "velocity") return f.velocity;
  if (q == "temperature") return f.temperature;
  return {summary.at(q).get<double>()};
}

double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b) {
  double worst = 0;
  for (size_t k = 0; k < a.size(); ++k) worst = std::max(worst, std::abs(a[k] - b[k]));
  return worst;
}

struct Job {
  Job(std::string name, double step) : integrator(std::move(name)), dt(step) {}
  std::string integrator;
  double dt;
  std::vector<double> value;
  long rhs_evals = 0;
  double seconds = 0;
  std::string failure;
};

// Runs every job on `threads` workers; each job writes only its own slot.
void run_jobs(const OrderOptions& o, std::vector<Job>& jobs, double t_end) {
  std::atomic<size_t> next{0};
  auto work = [&] {
    for (size_t k = next++; k < jobs.size(); k = next++) {
      Job& job = jobs[k];
      std::vector<std::string> sets = o.sets;
      sets.push_back("integrator=" + job.integrator);
      sets.push_back(assignment("dt", job.dt));
      sets.push_back(assignment("t_end", t_end));
      sets.push_back(assignment("output_interval", t_end));
      try {
        const Scene scene = load_scene(o.scene, sets);
        FinalFields fields;
        const nlohmann::json s = run_scene(scene, {"", true, &fields});
        job.value = quantity_of(o.quantity, fields, s);
        job.rhs_evals = s["rhs_evals"].get<long>();
        job.seconds = s["wall_seconds"].get<double>();
      } catch (const std::exception& e) {
        job.failure = e.what();
      }
    }
  };
  const int threads = o.threads > 0 ? o.threads : std::max(1u, std::thread::hardware_concurrency());
  std::vector<std::thread> pool;
  for (int k = 0; k < threads; ++k) pool.emplace_back(work);
  for (auto& th : pool) th.join();
}

int nominal_order(const std::string& name) {
  for (const auto& info : integrator_catalogue())
    if (info.name == name) return info.order;
  return 0;
}

}  // namespace

nlohmann::json run_order_study(const OrderOptions& o) {
  const Scene base = load_scene(o.scene, o.sets);
  const double t_end = o.t_end > 0 ? o.t_end : base.t_end;
  if (o.levels < (o.reference == "richardson" ? 3 : 2))
    throw InputError("--levels must be at least " + std::string(o.reference == "richardson" ? "3" : "2"));
  if (!(o.ratio > 1)) throw InputError("--ratio must be above 1");
  if (o.reference != "analytic" && o.reference != "richardson" && o.reference != "fine")
    throw InputError("unknown --reference '" + o.reference + "'; valid choices are " +
                     choices_nearest_first(o.reference, {"analytic", "richardson", "fine"}));
  const auto available = available_quantities(base);
  if (std::find(available.begin(), available.end(), o.quantity) == available.end())
    throw InputError("unknown --quantity '" + o.quantity + "' for scene '" + base.name + "'; available: " +
                     choices_nearest_first(o.quantity, available));
  for (const std::string& name : o.integrators) make_integrator(name);  // unknown names fail here

  // The reference.
  std::vector<double> reference;
  if (o.reference == "analytic") {
    const auto exact = exact_quantity(base, o.quantity, t_end);
    if (!exact)
      throw InputError("no exact solution is registered for scene '" + base.name + "' and quantity '" + o.quantity +
                       "'; registered: " + exact_solutions_known() + ". Use --reference fine or richardson");
    reference = *exact;
  } else if (o.reference == "fine") {
    // The same scene with Dormand-Prince, adaptive at a tight tolerance, from the finest step.
    std::vector<Job> fine = {Job("erk5", o.dt / std::pow(o.ratio, o.levels))};
    OrderOptions tight = o;
    tight.sets.push_back("rtol=1e-11");
    tight.sets.push_back("atol=1e-15");
    run_jobs(tight, fine, t_end);
    if (!fine[0].failure.empty()) throw std::runtime_error("the fine reference run failed: " + fine[0].failure);
    reference = fine[0].value;
  }

  std::vector<Job> jobs;
  for (const std::string& name : o.integrators)
    for (int level = 0; level < o.levels; ++level) jobs.emplace_back(name, o.dt / std::pow(o.ratio, level));
  run_jobs(o, jobs, t_end);

  nlohmann::json out;
  out["scene"] = base.name;
  out["quantity"] = o.quantity;
  out["norm"] = "max abs over components";
  out["reference"] = o.reference;
  out["t_end"] = t_end;
  out["ratio"] = o.ratio;
  out["integrators"] = nlohmann::json::array();
  std::ostringstream table, csv;
  csv << "integrator,dt,error,observed_order,rhs_evals,wall_seconds\n";
  for (size_t i = 0; i < o.integrators.size(); ++i) {
    const std::string& name = o.integrators[i];
    const Job* row = &jobs[i * o.levels];
    nlohmann::json entry;
    entry["name"] = name;
    entry["nominal_order"] = nominal_order(name);
    std::vector<double> dts, errors;
    std::string failure;
    for (int k = 0; k < o.levels; ++k) {
      if (!row[k].failure.empty()) failure = row[k].failure;
      dts.push_back(row[k].dt);
    }
    if (!failure.empty()) {
      entry["failure"] = failure;
      out["integrators"].push_back(entry);
      table << name << ": failed: " << failure << "\n";
      continue;
    }
    // Errors against the reference, or (Richardson) differences of successive levels.
    const int count = o.reference == "richardson" ? o.levels - 1 : o.levels;
    for (int k = 0; k < count; ++k)
      errors.push_back(o.reference == "richardson" ? max_abs_difference(row[k].value, row[k + 1].value)
                                                   : max_abs_difference(row[k].value, reference));
    std::vector<double> orders;
    for (int k = 0; k + 1 < count; ++k)
      orders.push_back(errors[k + 1] > 0 && errors[k] > 0 ? std::log(errors[k] / errors[k + 1]) / std::log(o.ratio)
                                                          : NAN);
    // Least-squares slope over the asymptotic range: the finer half of the levels (at least
    // three points, or all there are).
    const int from = std::max(0, std::min(count - 3, count / 2));
    double sx = 0, sy = 0, sxx = 0, sxy = 0, n = 0;
    for (int k = from; k < count; ++k) {
      if (!(errors[k] > 0)) continue;
      const double x = std::log(dts[k]), y = std::log(errors[k]);
      sx += x;
      sy += y;
      sxx += x * x;
      sxy += x * y;
      n += 1;
    }
    const double slope = n >= 2 ? (n * sxy - sx * sy) / (n * sxx - sx * sx) : NAN;
    const int nominal = nominal_order(name);
    // High orders approach their asymptote from above: a little above nominal still matches.
    const std::string verdict = !(slope > 0.5)                                          ? "not converging"
                                : (slope >= nominal - 0.2 && slope <= nominal + 0.35) ? "matches"
                                : slope < nominal                                       ? "reduced"
                                                                                        : "above nominal (pre-asymptotic?)";
    entry["dt"] = std::vector<double>(dts.begin(), dts.begin() + count);
    entry["error"] = errors;
    entry["observed_orders"] = orders;
    entry["fitted_order"] = slope;
    entry["verdict"] = verdict;
    std::vector<long> evals;
    std::vector<double> seconds;
    for (int k = 0; k < o.levels; ++k) {
      evals.push_back(row[k].rhs_evals);
      seconds.push_back(row[k].seconds);
    }
    entry["rhs_evals"] = evals;
    entry["wall_seconds"] = seconds;
    out["integrators"].push_back(entry);

    char line[256];
    table << name << " (nominal order " << nominal << ")\n";
    table << "        dt           " << (o.reference == "richardson" ? "difference" : "error     ") << "   order\n";
    for (int k = 0; k < count; ++k) {
      std::snprintf(line, sizeof line, "  %12.4e   %12.4e   %s\n", dts[k], errors[k],
                    k == 0 ? "" : std::to_string(orders[k - 1]).substr(0, 5).c_str());
      table << line;
      csv << name << "," << dts[k] << "," << errors[k] << "," << (k == 0 ? "" : std::to_string(orders[k - 1])) << ","
          << evals[k] << "," << seconds[k] << "\n";
    }
    std::snprintf(line, sizeof line, "  fitted order %.3f over the finer levels: %s\n\n", slope, verdict.c_str());
    table << line;
  }
  if (!o.quiet) std::printf("%s on %s, %s at t = %g s, reference %s\n\n%s", o.quantity.c_str(), base.name.c_str(),
                            "max abs error", t_end, o.reference.c_str(), table.str().c_str());
  if (!o.out_dir.empty()) {
    std::filesystem::create_directories(o.out_dir);
    const std::string dir = o.out_dir + "/";
    write_file_atomically(dir + "order.json", out.dump(2) + "\n");
    write_file_atomically(dir + "order.csv", csv.str());
    // The plot is matplotlib's, run by Debian's python3 on the JSON just written.
    const std::string script = std::string(KILN_SCRIPTS_DIR) + "/plot_order.py";
    const std::string cmd = "/usr/bin/python3 " + script + " " + dir + "order.json " + dir + "order.png";
    if (std::system(cmd.c_str()) != 0)
      std::fprintf(stderr, "warning: order.png not written (needs /usr/bin/python3 with matplotlib: apt-get install "
                           "python3-matplotlib)\n");
  }
  return out;
}

}  // namespace kiln
