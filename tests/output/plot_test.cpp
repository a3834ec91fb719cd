// kiln plot DIR (scripts/plot_case.py): the case quantities of a run over time in DIR/plots.png,
// found generically, so a case that reports a new history appears without a change to the script.
// The script lists its panels' titles in the PNG's text (its Description), which these tests read.
#include <cairo.h>
#include <fcntl.h>
#include <sys/file.h>
#include <unistd.h>

#include <algorithm>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>

#include "src/base/figure_script.h"
#include "src/run/simulation.h"
#include "tests/support.h"

using namespace kiln;
namespace fs = std::filesystem;

namespace {

std::string read_all(const fs::path& file) {
  std::ifstream in(file, std::ios::binary);
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// `kiln plot DIR`: its exit status and what it printed.
std::pair<int, std::string> plot(const fs::path& dir) {
  const fs::path log = dir.string() + ".log";
  const std::string cmd = std::string(KILN_BINARY) + " plot " + dir.string() + " --quiet > " + log.string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  std::pair<int, std::string> result = {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_all(log)};
  fs::remove(log);
  return result;
}

bool is_png(const fs::path& file) {
  cairo_surface_t* image = cairo_image_surface_create_from_png(file.c_str());
  const bool ok = cairo_surface_status(image) == CAIRO_STATUS_SUCCESS && cairo_image_surface_get_width(image) > 100;
  cairo_surface_destroy(image);
  return ok;
}

}  // namespace

TEST_CASE("kiln plot draws a drum run's mixing, temperatures, wall loads and energy ledger into plots.png",
          "[plot]") {
  const fs::path dir = testing::fresh_dir("plot_drum");
  run_scene(load_scene(testing::case_path("t6_drum.yaml"), {"t_end=0.03"}), {dir.string(), true});
  const auto [status, output] = plot(dir);
  INFO(output);
  REQUIRE(status == 0);
  REQUIRE(is_png(dir / "plots.png"));
  CHECK_FALSE(fs::exists(dir / "plots.png.tmp"));
  const std::string png = read_all(dir / "plots.png");
  for (const char* panel : {"mixing_history: lacey_index", "mixing_history: temperature_std",
                            "energy.history: balance_error", "temperatures (result.h5)",
                            "wall_torque per frame (result.h5)", "wall_power per frame (result.h5)", "energy ledger"})
    CHECK_THAT(png, Catch::Contains(panel));
  fs::remove_all(dir);
}

TEST_CASE("a history that a new case writes into summary.json appears in kiln plot without a change to it",
          "[plot]") {
  const fs::path dir = testing::fresh_dir("plot_new_history");
  fs::create_directories(dir);
  std::ofstream(dir / "summary.json") << R"({"scene": "silo", "integrator": "velocity-verlet", "t_end": 2,
    "discharge_history": {"time": [0, 1, 2], "mass_discharged": [0, 0.1, null]},
    "velocity_profile": {"y": [0, 0.01, 0.02], "vx": [0, 0.3, 0.5]}})";
  const auto [status, output] = plot(dir);
  INFO(output);
  REQUIRE(status == 0);
  const std::string png = read_all(dir / "plots.png");
  CHECK_THAT(png, Catch::Contains("discharge_history: mass_discharged"));
  CHECK_THAT(png, Catch::Contains("velocity_profile: vx"));
  fs::remove_all(dir);
}

TEST_CASE("kiln plot labels the case quantities by the observer catalogue and lists their figures", "[plot]") {
  const fs::path dir = testing::fresh_dir("plot_catalogue");
  fs::create_directories(dir);
  std::ofstream(dir / "summary.json") << R"({"scene": "pile", "integrator": "velocity-verlet", "t_end": 1,
    "heap_angle_deg": 31.5, "packing_fraction": null,
    "mixing_history": {"time": [0, 1], "lacey_index": [0.1, 0.4]}})";
  const auto [status, output] = plot(dir);
  INFO(output);
  REQUIRE(status == 0);
  const std::string png = read_all(dir / "plots.png");
  CHECK_THAT(png, Catch::Contains("mixing_history: lacey_index: Lacey's mixing index"));  // its meaning
  CHECK_THAT(png, Catch::Contains("case figures: heap_angle_deg, packing_fraction"));      // null: not measured
  fs::remove_all(dir);
}

// Issue 28's review: on a run still writing, kiln plot said "summary.json not found"; it shares
// kiln movie's reading of a directory now (RunOutputs::require_published).
TEST_CASE("kiln plot without summary.json says whether the run is missing, killed or still running, and writes nothing",
          "[plot]") {
  const fs::path dir = testing::fresh_dir("plot_empty");
  fs::create_directories(dir);
  auto refused_with = [&](const std::string& why) {
    const auto [status, output] = plot(dir);
    CHECK(status == 2);
    CHECK_THAT(output, Catch::Contains((dir / "summary.json").string() + " is missing") && Catch::Contains(why));
  };
  refused_with("give the directory of a run");
  CHECK(fs::is_empty(dir));
  std::ofstream(dir / "result.h5.tmp") << "frames so far";
  refused_with("it was killed");
  const int lock = ::open((dir / ".kiln.lock").c_str(), O_CREAT | O_RDWR, 0644);
  REQUIRE(::flock(lock, LOCK_EX | LOCK_NB) == 0);  // as a run holds it
  refused_with("is still running");
  ::close(lock);
  CHECK_FALSE(fs::exists(dir / "plots.png"));
  fs::remove_all(dir);
}

TEST_CASE("kiln plot on a full disk says it could not write plots.png in one line, exit 4, no traceback", "[plot]") {
  // Issue 28's campaign: with no room for plots.png, kiln plot printed the Python traceback of the
  // failed write, then a hint to install matplotlib. (ulimit -f stands in for a full disk: Python
  // ignores SIGXFSZ, so the write fails with EFBIG.)
  const fs::path dir = testing::fresh_dir("plot_full");
  fs::create_directories(dir);
  std::ofstream(dir / "summary.json") << R"({"scene": "pile", "integrator": "velocity-verlet", "t_end": 1,
    "mixing_history": {"time": [0, 1], "lacey_index": [0.1, 0.4]}})";
  const fs::path log = dir.string() + ".log";
  const std::string cmd = "ulimit -f 8 && " + std::string(KILN_BINARY) + " plot " + dir.string() + " --quiet > " +
                          log.string() + " 2>&1";
  const int status = std::system(("sh -c '" + cmd + "'").c_str());
  const std::string output = read_all(log);
  fs::remove(log);
  INFO(output);
  CHECK((WIFEXITED(status) ? WEXITSTATUS(status) : -1) == 4);
  CHECK_THAT(output, Catch::Contains("cannot write " + (dir / "plots.png.tmp").string()));
  CHECK_THAT(output, !Catch::Contains("Traceback"));
  CHECK_THAT(output, !Catch::Contains("apt-get"));
  CHECK_FALSE(fs::exists(dir / "plots.png"));
  CHECK_FALSE(fs::exists(dir / "plots.png.tmp"));
  fs::remove_all(dir);
}

namespace {

// `kiln order` of T1 (free fall) to 0.01 s from --dt 1e-4 over 3 levels: velocity Verlet is exact
// there but for round-off (errors 0, 3.5e-18, 0), so it has no fitted order; erk2 has one.
std::pair<int, std::string> null_order_study(const fs::path& out, const std::string& shell_prefix = "") {
  const fs::path log = out.string() + ".log";
  const std::string cmd = shell_prefix + std::string(KILN_BINARY) + " order " + testing::case_path("t1_free_fall.yaml") +
                          " --integrators velocity-verlet,erk2 --dt 1e-4 --levels 3 --t-end 0.01 --quiet --out " +
                          out.string() + " > " + log.string() + " 2>&1";
  const int status = std::system(("sh -c '" + cmd + "'").c_str());
  std::pair<int, std::string> result = {WIFEXITED(status) ? WEXITSTATUS(status) : -1, read_all(log)};
  fs::remove(log);
  return result;
}

}  // namespace

TEST_CASE("kiln order draws an integrator whose fitted order is null and notes why under the plot, exit 0, no "
          "traceback",
          "[plot][study]") {
  // Issue 28's campaign (F11): the plot script formatted the null order as a number, printed its
  // TypeError traceback and "order.png not written (needs matplotlib)", and kiln order exited 0.
  const fs::path dir = testing::fresh_dir("order_null_fit");
  const auto [status, output] = null_order_study(dir);
  INFO(output);
  CHECK(status == 0);
  CHECK_THAT(output, !Catch::Contains("Traceback"));
  CHECK_THAT(output, !Catch::Contains("matplotlib"));
  REQUIRE(is_png(dir / "order.png"));
  const std::string png = read_all(dir / "order.png");  // its notes are in the PNG's Description
  CHECK_THAT(png, Catch::Contains("velocity-verlet: no fitted order: not settled (an error of zero gives no order"));
  CHECK_THAT(png, Catch::Contains("velocity-verlet: not drawn at dt = 0.0001, 2.5e-05 (error 0, NaN or failed)"));
  CHECK_FALSE(fs::exists(dir / "order.png.tmp"));
  fs::remove_all(dir);
}

TEST_CASE("kiln order on a full disk says in one line that order.png could not be written, exit 4, its JSON and CSV "
          "kept",
          "[plot][study]") {
  // Issue 28's campaign (F11): with no room for order.png kiln order printed the Python traceback of
  // the failed write and "needs matplotlib", and exited 0. kiln plot's fix (exit 4, one line) is
  // now every figure's (src/base/figure_script.h, scripts/kiln_figure.py).
  const fs::path dir = testing::fresh_dir("order_full");
  const auto [status, output] = null_order_study(dir, "ulimit -f 8 && ");
  INFO(output);
  CHECK(status == 4);
  CHECK_THAT(output, Catch::Contains("error: cannot write " + (dir / "order.png.tmp").string() +
                                     ": File too large (order.json and order.csv are written)"));
  CHECK(std::count(output.begin(), output.end(), '\n') == 1);  // that line alone
  CHECK_THAT(output, !Catch::Contains("Traceback"));
  CHECK_THAT(output, !Catch::Contains("matplotlib"));
  CHECK(fs::exists(dir / "order.json"));
  CHECK(fs::exists(dir / "order.csv"));
  CHECK_FALSE(fs::exists(dir / "order.png"));
  CHECK_FALSE(fs::exists(dir / "order.png.tmp"));
  fs::remove_all(dir);
}

TEST_CASE("a figure script that fails on what it is given ends in one line naming the exception, exit 6, never a "
          "traceback",
          "[plot]") {
  // What any figure script lets out (an unforeseen null, a field of the wrong kind) is a defect of
  // kiln's: reported as one, with the script's line, not as a traceback or a missing matplotlib.
  const fs::path dir = testing::fresh_dir("figure_defect");
  fs::create_directories(dir);
  std::ofstream(dir / "order.json") << R"({"scene": "s", "quantity": "position", "reference": "analytic",
    "t_end": 1, "integrators": 3})";
  const std::string figure = (dir / "order.png").string();
  try {
    draw_figure("plot_study.py", {"order", (dir / "order.json").string(), figure}, figure);
    FAIL("the figure was drawn");
  } catch (const FigureError& e) {
    CHECK(e.status == 6);
    CHECK_THAT(e.what(), Catch::StartsWith("cannot draw " + figure + ": TypeError"));
    CHECK_THAT(e.what(), Catch::Contains("plot_study.py:") && Catch::Contains("please report it"));
    CHECK_THAT(e.what(), !Catch::Contains("Traceback") && !Catch::Contains("\n"));
  }
  CHECK_FALSE(fs::exists(figure));
  fs::remove_all(dir);
}
