// The verification matrix: every exact case against every integrator (the Verlet family, every
// ARKODE explicit table, every IMEX pair), with and without contact events where they matter.
//
// One checked-in table, tests/studies/verification_matrix.tsv, lists per row a case (scene, overrides,
// events), an integrator, the steps of a `kiln order` study (dt0, levels, ratio), the quantity
// compared with its exact reference at t_end, and what must come out: the least-squares order
// over the finer half of the levels (as `kiln order` fits it) within a tolerance, and the error at
// the finest level below a bound. A row whose order is below the integrator's nominal one says
// why. Rows labelled `default` run in the default suite (a Verlet scheme, a low- and a high-order
// table and, on thermal cases, an IMEX pair per case: about 5 s of CPU); the rest carry the tag
// [long] (CTest label `long`; about 20 s of CPU).
//
// Each row runs in a forked child, so a crash fails that row, with the signal, instead of the
// whole binary (IMEX pairs on scenes without temperatures did so before they ran their explicit
// tables). A row whose order is
// `fails` must fail: when it starts to run, the table is out of date.
//
// Tolerances (the table's header says the same): the studies are deterministic (bit-identical
// runs), so the tolerances only absorb round-off differences between compilers and platforms and
// changes that keep the numerics. Order: 0.15 where the per-halving orders of the fitted levels
// agree within 0.3 (the asymptotic range: the project's convention for measured orders, while a
// lost order costs at least 1), 0.5 where they do not (the order is erratic: kinks that fall
// anywhere in a step). Error bound: twice the measured finest error, so a change that costs one
// halving of the step fails.
//
// Regenerate the measured columns with scripts/verification_matrix.sh (it sets
// KILN_MATRIX_MEASURE: rows are then measured and written there, not asserted).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cerrno>
#include <cmath>
#include <csignal>
#include <cstdlib>
#include <cstring>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include "integrators/integrator.h"
#include "src/dem/dem_system.h"
#include "src/studies/exact_solutions.h"
#include "src/scene/scene_yaml.h"
#include "src/studies/study_order.h"
#include "tests/support.h"

using namespace kiln;

namespace {

// KILN_MATRIX_TABLE=FILE reads another table (a scratch one, e.g. to try other steps).
const std::string table_path = std::getenv("KILN_MATRIX_TABLE")
                                   ? std::string(std::getenv("KILN_MATRIX_TABLE"))
                                   : std::string(KILN_CASES_DIR) + "/../tests/studies/verification_matrix.tsv";

struct Row {
  int line = 0;
  std::string scene, sets, events, integrator;
  double dt0 = 0;
  int levels = 0;
  double ratio = 2;
  std::string quantity, t_end;
  int nominal = 0;
  std::string order;  // a number, "fails" (the run must fail) or "-" (not asserted: error at round-off)
  double order_tol = 0, bound = 0;
  std::string label, reason;

  std::string where() const {
    return "verification_matrix.tsv:" + std::to_string(line) + " (" + scene + (sets == "-" ? "" : " " + sets) +
           ", events " + events + ", " + integrator + ")";
  }
};

const char* const columns[] = {"scene", "sets",      "events", "integrator", "dt0",   "levels", "ratio", "quantity",
                               "t_end", "nominal",   "order",  "order_tol",  "bound", "label",  "reason"};
constexpr int column_count = sizeof(columns) / sizeof(columns[0]);

std::vector<std::string> split(const std::string& text, char by) {
  std::vector<std::string> parts;
  std::string part;
  std::istringstream in(text);
  while (std::getline(in, part, by)) parts.push_back(part);
  if (!text.empty() && text.back() == by) parts.emplace_back();
  return parts;
}

double number(const std::string& text, const std::string& where) {
  char* end = nullptr;
  const double v = std::strtod(text.c_str(), &end);
  if (text.empty() || *end != '\0') FAIL(where << ": '" << text << "' is not a number");
  return v;
}

const std::vector<Row>& table() {
  static const std::vector<Row> rows = [] {
    std::ifstream in(table_path);
    REQUIRE(in.good());
    std::vector<Row> out;
    std::string text;
    int line = 0;
    bool header = false;
    while (std::getline(in, text)) {
      ++line;
      if (text.empty() || text[0] == '#') continue;
      const auto f = split(text, '\t');
      const std::string where = "verification_matrix.tsv:" + std::to_string(line);
      REQUIRE(f.size() == column_count);
      if (!header) {  // the first non-comment line names the columns
        for (int c = 0; c < column_count; ++c) REQUIRE(f[c] == columns[c]);
        header = true;
        continue;
      }
      Row r;
      r.line = line;
      r.scene = f[0], r.sets = f[1], r.events = f[2], r.integrator = f[3];
      r.dt0 = number(f[4], where), r.levels = static_cast<int>(number(f[5], where)), r.ratio = number(f[6], where);
      r.quantity = f[7], r.t_end = f[8], r.nominal = static_cast<int>(number(f[9], where));
      r.order = f[10], r.order_tol = number(f[11], where), r.bound = number(f[12], where);
      r.label = f[13], r.reason = f[14];
      out.push_back(r);
    }
    return out;
  }();
  return rows;
}

// What one row measured.
struct Measured {
  std::string failure;  // empty when every level ran
  std::vector<double> dt, error, orders;
  double fitted = NAN;
};

Measured failed(const std::string& why) {
  Measured m;
  m.failure = why;
  return m;
}

Scene scene_of(const Row& r) {
  std::vector<std::string> sets;
  if (r.sets != "-") sets = split(r.sets, ';');
  return load_scene(testing::case_path(r.scene), sets);
}

double t_end_of(const Row& r, const Scene& scene) {
  return r.t_end == "-" ? scene.t_end : std::strtod(r.t_end.c_str(), nullptr);
}

// The pair cases have no closed form: their rows compare with a fine adaptive run (erk5 at rtol
// 1e-11 with contact events, src/studies/study_runs.cpp), the others with the exact solution.
bool has_exact_reference(const Row& r) {
  const Scene scene = scene_of(r);
  return exact_quantity(scene, r.quantity, t_end_of(r, scene)).has_value();
}

OrderOptions study_of(const Row& r) {
  OrderOptions o;
  o.scene = testing::case_path(r.scene);
  if (r.sets != "-") o.sets = split(r.sets, ';');
  o.sets.push_back(r.events == "on" ? "contact_events=true" : "contact_events=false");
  o.integrators = {r.integrator};
  o.dt = r.dt0;
  o.levels = r.levels;
  o.ratio = r.ratio;
  o.quantity = r.quantity;
  o.reference = has_exact_reference(r) ? "analytic" : "fine";
  o.t_end = r.t_end == "-" ? 0.0 : std::strtod(r.t_end.c_str(), nullptr);
  o.threads = 1;  // the machine is shared: one run at a time
  o.quiet = true;
  return o;
}

// Runs the row's study in a forked child, which sends order.json's entry back through a pipe: a
// crash or a hang (ten minutes) fails the row, not the test binary.
Measured measure(const Row& r) {
  int fd[2];
  if (pipe(fd) != 0) return failed(std::string("pipe: ") + std::strerror(errno));
  const pid_t pid = fork();
  if (pid < 0) return failed(std::string("fork: ") + std::strerror(errno));
  if (pid == 0) {
    close(fd[0]);
    // Catch2's handlers would report a crash as the parent's test failing: let signals kill the child.
    for (int sig : {SIGSEGV, SIGABRT, SIGFPE, SIGILL, SIGBUS, SIGTERM, SIGINT}) std::signal(sig, SIG_DFL);
    alarm(600);
    std::string out;
    try {
      out = run_order_study(study_of(r))["integrators"][0].dump();
    } catch (const std::exception& e) {
      out = nlohmann::json{{"failure", std::string("error: ") + e.what()}}.dump();
    }
    for (size_t done = 0; done < out.size();) {
      const ssize_t n = write(fd[1], out.data() + done, out.size() - done);
      if (n <= 0) break;
      done += static_cast<size_t>(n);
    }
    _exit(0);  // no atexit handlers, no Catch2 state: the parent reports
  }
  close(fd[1]);
  std::string text;
  char buffer[4096];
  for (ssize_t n; (n = read(fd[0], buffer, sizeof buffer)) > 0;) text.append(buffer, static_cast<size_t>(n));
  close(fd[0]);
  int status = 0;
  waitpid(pid, &status, 0);
  Measured m;
  if (WIFSIGNALED(status)) {
    m.failure = "crashed: signal " + std::to_string(WTERMSIG(status)) + " (" + strsignal(WTERMSIG(status)) + ")";
    return m;
  }
  const auto entry = nlohmann::json::parse(text, nullptr, false);
  if (entry.is_discarded()) return failed("no result from the child (exit status " + std::to_string(status) + ")");
  if (entry.contains("failure")) {
    m.failure = entry["failure"].get<std::string>();
    return m;
  }
  m.dt = entry["dt"].get<std::vector<double>>();
  m.error = entry["error"].get<std::vector<double>>();
  for (const auto& o : entry["observed_orders"]) m.orders.push_back(o.is_number() ? o.get<double>() : NAN);
  m.fitted = entry["fitted_order"].is_number() ? entry["fitted_order"].get<double>() : NAN;
  return m;
}

// What is wrong with a row's result against the table: nothing when empty.
std::vector<std::string> judge(const Row& r, const Measured& m) {
  std::vector<std::string> problems;
  if (r.order == "fails") {
    if (m.failure.empty())
      problems.push_back("listed as failing but every level ran (finest error " + std::to_string(m.error.back()) +
                         ", order " + std::to_string(m.fitted) +
                         "): the table is out of date, regenerate it with scripts/verification_matrix.sh");
    return problems;
  }
  if (!m.failure.empty()) {
    problems.push_back("failed: " + m.failure);
    return problems;
  }
  if (r.order != "-") {
    const double expected = std::strtod(r.order.c_str(), nullptr);
    if (!(std::abs(m.fitted - expected) <= r.order_tol)) {
      std::ostringstream s;
      s << "measured order " << m.fitted << ", the table expects " << expected << " +- " << r.order_tol;
      problems.push_back(s.str());
    }
  }
  if (!(m.error.back() <= r.bound)) {
    std::ostringstream s;
    s << "finest error " << m.error.back() << " at dt = " << m.dt.back() << " above the bound " << r.bound;
    problems.push_back(s.str());
  }
  return problems;
}

std::string describe(const Measured& m) {
  std::ostringstream s;
  s.precision(4);
  if (!m.failure.empty()) return m.failure;
  s << "errors";
  for (double e : m.error) s << " " << e;
  s << "; per-halving orders";
  for (double o : m.orders) s << " " << o;
  s << "; fitted " << m.fitted;
  return s.str();
}

// KILN_MATRIX_MEASURE=FILE: write what each row measured to FILE (appended, one line per row,
// tab-separated: the row's key, then fitted order, finest error, per-halving orders, failure)
// instead of asserting. scripts/verification_matrix.sh merges it into the table.
void record(const Row& r, const Measured& m, const char* file) {
  std::ofstream out(file, std::ios::app);
  out.precision(6);
  std::string orders;
  for (double o : m.orders) {
    if (!orders.empty()) orders += ',';
    orders += std::to_string(o);
  }
  out << r.scene << "\t" << r.sets << "\t" << r.events << "\t" << r.integrator << "\t" << r.quantity << "\t" << r.t_end
      << "\t" << (m.failure.empty() ? m.fitted : NAN) << "\t" << (m.failure.empty() ? m.error.back() : NAN) << "\t"
      << (orders.empty() ? "-" : orders) << "\t" << (m.failure.empty() ? "-" : m.failure) << "\n";
}

// Runs every row of one case (scene, events) with the given label.
void run_rows(const std::string& scene, const std::string& events, const std::string& label) {
  const char* measure_into = std::getenv("KILN_MATRIX_MEASURE");
  int ran = 0;
  for (const Row& r : table()) {
    if (r.scene != scene || r.events != events || r.label != label) continue;
    ++ran;
    const Measured m = measure(r);
    if (measure_into) {
      record(r, m, measure_into);
      continue;
    }
    INFO(r.where() << ": " << describe(m));
    const auto problems = judge(r, m);
    for (const std::string& p : problems) FAIL_CHECK(p);
    if (problems.empty()) SUCCEED();
  }
  CHECK(ran > 0);
}

bool is_alias(const IntegratorInfo& info) { return !info.alias_of.empty(); }

}  // namespace

// One test per case and label: the default subset, then [long] with every other integrator.
#define KILN_MATRIX_CASE(scene, events, what)                                                                  \
  TEST_CASE(what ": the fast subset (a Verlet scheme, a low- and a high-order table, on thermal cases an "  \
                 "IMEX pair) meets the order and error bound the matrix lists",                              \
            "[matrix][rows]") {                                                                              \
    run_rows(scene, events, "default");                                                                      \
  }                                                                                                          \
  TEST_CASE(what ": every integrator meets the order and error bound the matrix lists",                       \
            "[matrix][rows][long]") {                                                                        \
    run_rows(scene, events, "long");                                                                         \
  }

KILN_MATRIX_CASE("harmonic_contact_pair.yaml", "off", "harmonic contact")
KILN_MATRIX_CASE("t1_free_fall.yaml", "off", "T1 bounce without contact events")
KILN_MATRIX_CASE("t1_free_fall.yaml", "on", "T1 bounce with contact events")
KILN_MATRIX_CASE("t1_free_fall_damped.yaml", "off", "T1 damped bounce without contact events")
KILN_MATRIX_CASE("t1_free_fall_damped.yaml", "on", "T1 damped bounce with contact events")
KILN_MATRIX_CASE("t4_two_particle_conduction.yaml", "off", "T4 two-disc conduction")
KILN_MATRIX_CASE("f1_chain_slab.yaml", "off", "F1 conduction chain")
KILN_MATRIX_CASE("f2_pipe_network_pair.yaml", "off", "F2 pipe-network pair")
KILN_MATRIX_CASE("n1_triangle_conduction.yaml", "off", "N1 Hertz-conduction triangle")
KILN_MATRIX_CASE("c1_incline_roll_slide.yaml", "off", "C1 rolling from rest on the incline")
KILN_MATRIX_CASE("stick_two_sevenths.yaml", "off", "2/7 stick impact without contact events")
KILN_MATRIX_CASE("stick_two_sevenths.yaml", "on", "2/7 stick impact with contact events")
KILN_MATRIX_CASE("oblique_sliding_impact.yaml", "off", "oblique impact in gross sliding without contact events")
KILN_MATRIX_CASE("oblique_sliding_impact.yaml", "on", "oblique impact in gross sliding with contact events")
KILN_MATRIX_CASE("slide_to_roll.yaml", "off", "slide to roll")
KILN_MATRIX_CASE("pair_stick.yaml", "off", "pair stick and slide without contact events")
KILN_MATRIX_CASE("pair_stick.yaml", "on", "pair stick and slide with contact events")
KILN_MATRIX_CASE("pair_copper_glass.yaml", "off", "pair copper on glass without contact events")
KILN_MATRIX_CASE("pair_copper_glass.yaml", "on", "pair copper on glass with contact events")
KILN_MATRIX_CASE("pair_squeezed_disc.yaml", "off", "pair squeezed disc without contact events")
KILN_MATRIX_CASE("pair_squeezed_disc.yaml", "on", "pair squeezed disc with contact events")

TEST_CASE("the verification matrix lists every integrator on every case, and a reason wherever an order drops",
          "[matrix]") {
  const auto& rows = table();
  std::set<std::string> integrators;  // every scheme, aliases aside
  std::map<std::string, int> nominal;
  for (const auto& info : integrator_catalogue())
    if (!is_alias(info)) {
      integrators.insert(info.name);
      nominal[info.name] = info.order;
    }
  CHECK(integrators.size() == 24);  // 3 Verlet, 15 explicit tables, 5 IMEX pairs, IMEX Euler
  std::map<std::string, std::set<std::string>> listed;  // case -> integrators
  std::set<std::string> keys;
  std::set<std::string> frozen_groups;  // cases whose mechanics are frozen (only heat to integrate)
  int defaults = 0;
  for (const Row& r : rows) {
    INFO(r.where());
    CHECK(integrators.count(r.integrator) == 1);
    CHECK(r.nominal == nominal[r.integrator]);
    CHECK((r.events == "on" || r.events == "off"));
    CHECK((r.label == "default" || r.label == "long"));
    CHECK(keys.insert(r.scene + "|" + r.sets + "|" + r.events + "|" + r.integrator + "|" + r.quantity).second);
    listed[r.scene + " events " + r.events].insert(r.integrator);
    defaults += r.label == "default";
    CHECK(r.levels >= 3);
    CHECK(r.ratio > 1);
    CHECK(r.bound > 0);
    CHECK(r.order_tol > 0);
    CHECK(r.order_tol <= 0.5);
    // A dropped order (or a failing run) needs its reason; an order kept needs none.
    const bool drops =
        r.order == "fails" || (r.order != "-" && std::strtod(r.order.c_str(), nullptr) < r.nominal - 0.2);
    if (drops) CHECK((r.reason != "-" && !r.reason.empty() && r.reason.rfind("TODO", 0) != 0));
    // The exact reference exists for the row's scene, overrides and quantity; only the pair cases
    // (no closed form) compare with a fine run.
    const Scene scene = scene_of(r);
    if (scene.frozen) frozen_groups.insert(r.scene + " events " + r.events);
    CHECK((exact_quantity(scene, r.quantity, t_end_of(r, scene)) || r.scene.rfind("pair_", 0) == 0));
  }
  // Every case lists every integrator; with contact events the Verlet schemes (which refuse them)
  // are left out, and IMEX Euler is listed on frozen cases only (it refuses moving contacts).
  for (const auto& [group, names] : listed) {
    INFO(group);
    for (const std::string& name : integrators) {
      const bool verlet = name == "verlet" || name.rfind("velocity-verlet", 0) == 0;
      if (group.find("events on") != std::string::npos && verlet) continue;
      if (name == "imex1" && frozen_groups.count(group) == 0) continue;
      CHECK(names.count(name) == 1);
    }
  }
  CHECK(listed.size() == 21);
  CHECK(defaults <= 4 * 21);  // the default subset stays small
}

TEST_CASE("the matrix's check fails a row whose order or error is not what the table lists", "[matrix]") {
  // The cheapest row: velocity Verlet on the harmonic contact, run for real, then judged against a
  // table that is right, one that expects an order too high, and one whose bound is too tight.
  const auto& rows = table();
  const auto it = std::find_if(rows.begin(), rows.end(), [](const Row& r) {
    return r.scene == "harmonic_contact_pair.yaml" && r.integrator == "velocity-verlet";
  });
  REQUIRE(it != rows.end());
  const Measured m = measure(*it);
  INFO(describe(m));
  CHECK(judge(*it, m).empty());
  Row wrong_order = *it;
  wrong_order.order = std::to_string(std::strtod(it->order.c_str(), nullptr) + 1);
  CHECK(judge(wrong_order, m).size() == 1);
  Row tight = *it;
  tight.bound = m.error.back() / 2;
  CHECK(judge(tight, m).size() == 1);
  Row failing = *it;
  failing.order = "fails";
  CHECK(judge(failing, m).size() == 1);
  CHECK(judge(*it, failed("crashed: signal 11 (Segmentation fault)")).size() == 1);
}

TEST_CASE("the exact references give the textbook results: the 2/7 rule, e_t = 1 - mu (1 + e_n) cot(theta), "
          "slide to roll at 5/7 u0",
          "[matrix]") {
  // After the 2/7 stick impact: v_t = 3/7 v_t0, v_n reversed; the spin follows from the invariant.
  {
    const Scene s = load_scene(testing::case_path("stick_two_sevenths.yaml"));
    const auto v = exact_quantity(s, "velocity", s.t_end);
    REQUIRE(v);
    CHECK((*v)[0] == Approx(3.0 / 7.0 * 1.95).epsilon(1e-12));
    CHECK((*v)[1] == Approx(3.3774991).epsilon(1e-12));
  }
  // Gross sliding: e_t = 1 - mu (1 + e_n) cot(60 deg) with mu = 0.2, e_n = 1.
  {
    const Scene s = load_scene(testing::case_path("oblique_sliding_impact.yaml"));
    const auto v = exact_quantity(s, "velocity", s.t_end);
    REQUIRE(v);
    const double vt0 = std::sqrt(3.0), vn0 = 1.0;
    CHECK((*v)[0] / vt0 == Approx(1 - 0.2 * 2 / std::sqrt(3.0)).epsilon(1e-12));
    CHECK((*v)[1] == Approx(vn0).epsilon(1e-12));
  }
  // Slide to roll: v = u0 - mu g t while sliding, but the fresh spring first loads in stick for
  // t1 = asin(mu m g w_t / (k_t u0)) / w_t (18 us) with less than the full friction force, so the
  // model's disc is ahead of the rigid one by less than mu g t1. After t_s = 2 u0 / (7 mu g) the
  // centre rocks about 5/7 u0 with amplitude mu g / w_t.
  {
    const Scene s = load_scene(testing::case_path("slide_to_roll.yaml"));
    const double u0 = 0.1, mu = 0.5, g = 9.81, ts = 2 * u0 / (7 * mu * g), kt = 2.0 / 7.0 * 2500;
    const double m = 4.0 / 3.0 * M_PI * std::pow(0.0025, 3) * 4000, wt = std::sqrt(3.5 * kt / m);
    const double t1 = std::asin(mu * m * g * wt / (kt * u0)) / wt;
    const auto sliding = exact_quantity(s, "velocity", ts / 2);
    REQUIRE(sliding);
    const double ahead = (*sliding)[0] - (u0 - mu * g * ts / 2);
    INFO("t1 = " << t1 << " s, ahead by " << ahead << " m/s");
    CHECK(ahead > 0);
    CHECK(ahead < mu * g * t1);
    for (double t : {ts + 1e-4, s.t_end}) {
      const auto rolling = exact_quantity(s, "velocity", t);
      REQUIRE(rolling);
      CHECK(std::abs((*rolling)[0] - 5.0 / 7.0 * u0) <= mu * g / wt * 1.01);
      CHECK(std::abs((*rolling)[1]) < 1e-12);
    }
  }
}

TEST_CASE("a wall contact changes m r v_t - I omega by nothing: a velocity error measures the spin's too", "[matrix]") {
  // The matrix compares velocities only (a run reports no spin). On a flat wall the tangential force
  // F_t moves v_x by F_t / m and omega by r F_t / I, so m r v_x - I omega is a linear invariant, which
  // every Runge-Kutta and Verlet scheme keeps to round-off: the spin error is (m r / I) times the
  // v_x error. This guards that argument (it would fail if wall contacts got another lever arm).
  for (const char* integrator :
       {"velocity-verlet", "verlet", "velocity-verlet-predicted", "erk4", "erk:FEHLBERG_13_7_8"}) {
    testing::Run run(testing::case_text("stick_two_sevenths.yaml"),
                     {std::string("integrator=") + integrator, "dt=1e-6"});
    const double m = run.system->mass(0), inertia = run.system->inertia(0), r = run.system->radius(0);
    const double before = m * r * run.vx(0) - inertia * run.omega(0);
    while (run.t() < 8e-5 - 1e-12) run.step();
    INFO(integrator << ": v_x " << run.vx(0) << ", omega " << run.omega(0));
    CHECK(run.omega(0) < -1000);  // the impact spun it backwards (s = v_x + r omega)
    CHECK(m * r * run.vx(0) - inertia * run.omega(0) == Approx(before).epsilon(1e-12));
  }
}
