// Nothing a user does loses finished work: signals, full disks, kills, checkpoints and restarts,
// earlier results in the same directory, exit codes.
#include <catch2/catch.hpp>
#include <fcntl.h>
#include <hdf5.h>
#include <sys/resource.h>
#include <sys/wait.h>
#include <unistd.h>

#include <chrono>
#include <csignal>
#include <cstring>
#include <filesystem>
#include <fstream>
#include <functional>
#include <nlohmann/json.hpp>
#include <thread>

#include "src/base/error.h"
#include "src/output/outputs.h"
#include "src/scene/overrides.h"
#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "src/base/snapshot.h"
#include "tests/support.h"

using namespace kiln;
namespace fs = std::filesystem;

namespace {

struct Outcome {
  int exit_code = -1;  // -1 when ended by a signal
  int signal = 0;      // the signal that ended it
  std::string err;     // its standard error
};

// Runs the kiln binary. file_limit > 0 caps every file it writes at that many bytes (RLIMIT_FSIZE
// with SIGXFSZ ignored: a write past it fails with EFBIG, as a write to a full disk fails with
// ENOSPC). With `send`, the signal goes to kiln once `ready()` holds.
Outcome run_kiln(const std::vector<std::string>& args, long file_limit = 0, int send = 0,
                 const std::function<bool()>& ready = {}, int times = 1) {
  static int calls = 0;  // one file per call: a call may run inside another's wait
  const fs::path err_file =
      fs::temp_directory_path() / ("kiln_stderr_" + std::to_string(::getpid()) + "_" + std::to_string(++calls));
  const pid_t pid = fork();
  if (pid == 0) {
    const int err = open(err_file.c_str(), O_WRONLY | O_CREAT | O_TRUNC, 0644);
    const int null = open("/dev/null", O_WRONLY);
    dup2(err, 2);
    dup2(null, 1);
    if (file_limit > 0) {
      std::signal(SIGXFSZ, SIG_IGN);
      const rlimit limit{static_cast<rlim_t>(file_limit), static_cast<rlim_t>(file_limit)};
      setrlimit(RLIMIT_FSIZE, &limit);
    }
    std::vector<char*> argv;
    std::string binary = KILN_BINARY;
    argv.push_back(binary.data());
    std::vector<std::string> copies = args;
    for (std::string& a : copies) argv.push_back(a.data());
    argv.push_back(nullptr);
    execv(binary.c_str(), argv.data());
    _exit(127);
  }
  int status = 0;
  if (send) {
    const auto give_up = std::chrono::steady_clock::now() + std::chrono::seconds(60);
    while (waitpid(pid, &status, WNOHANG) == 0) {
      if (ready() || std::chrono::steady_clock::now() > give_up) {
        for (int k = 0; k < times; ++k) kill(pid, send);  // `times` at once: as GNU timeout signals
        break;
      }
      std::this_thread::sleep_for(std::chrono::milliseconds(5));
    }
  }
  waitpid(pid, &status, 0);
  Outcome o;
  if (WIFEXITED(status)) o.exit_code = WEXITSTATUS(status);
  if (WIFSIGNALED(status)) o.signal = WTERMSIG(status);
  std::ifstream in(err_file);
  std::stringstream text;
  text << in.rdbuf();
  o.err = text.str();
  fs::remove(err_file);
  return o;
}

// Every dataset of frames in a result file, concatenated: equal vectors are equal bits.
std::vector<double> frames_of(const fs::path& file) {
  std::vector<double> all;
  for (const char* name : {"time", "position", "velocity", "angle", "angular_velocity", "temperature"}) {
    const auto d = testing::read_dataset(file, name);
    all.insert(all.end(), d.begin(), d.end());
  }
  return all;
}

bool same_bits(const std::vector<double>& a, const std::vector<double>& b) {
  return a.size() == b.size() && std::memcmp(a.data(), b.data(), a.size() * sizeof(double)) == 0;
}

nlohmann::json summary_of(const fs::path& dir) {
  std::ifstream in(dir / "summary.json");
  return nlohmann::json::parse(in);
}

// The drum (T6): rotating walls, friction and rolling history, heat; 214 discs, 0.04 s.
const std::vector<std::string> drum_sets = {"output_interval=0.004"};
const std::string drum = testing::case_path("t6_drum.yaml");

// A scene run uninterrupted to t_end into dir, in this process.
void run_whole(const std::vector<std::string>& sets, const fs::path& dir, const std::string& file = drum) {
  const Scene scene = load_scene(file, sets);
  RunOptions o;
  o.out_dir = dir.string();
  o.quiet = true;
  std::ifstream in(file);
  std::stringstream text;
  text << in.rdbuf();
  o.source = {file, text.str(), sets};
  run_scene(scene, o);
}

// The same run from its checkpoint in dir, to `t_end`.
nlohmann::json resume(const fs::path& dir, double t_end) {
  const Snapshot checkpoint = Snapshot::read((dir / "checkpoint.h5").string());
  RunOptions o;
  o.out_dir = dir.string();
  o.quiet = true;
  o.resume = &checkpoint;
  const Scene scene = scene_of_checkpoint(checkpoint, {assignment("t_end", t_end)}, o.source);
  return run_scene(scene, o);
}

}  // namespace

TEST_CASE("a run stopped at half its time and resumed gives frames bit-identical to an uninterrupted one",
          "[checkpoint][heavy]") {
  // Verlet schemes and fixed-step ARKODE tables, on a drum whose walls turn (time enters the
  // right-hand side) with contact history, rotation and heat.
  for (const std::string integrator : {"velocity-verlet", "verlet", "velocity-verlet-predicted", "erk4"}) {
    const double t_end = integrator == "erk4" ? 0.012 : 0.04;
    std::vector<std::string> sets = drum_sets;
    sets.push_back("integrator=" + integrator);
    const fs::path whole = testing::fresh_dir("whole"), halves = testing::fresh_dir("halves");
    std::vector<std::string> whole_sets = sets, half_sets = sets;
    whole_sets.push_back(assignment("t_end", t_end));
    half_sets.push_back(assignment("t_end", t_end / 2));
    run_whole(whole_sets, whole);
    run_whole(half_sets, halves);
    REQUIRE(fs::exists(halves / "checkpoint.h5"));
    const nlohmann::json s = resume(halves, t_end);
    INFO(integrator);
    CHECK(same_bits(frames_of(whole / "result.h5"), frames_of(halves / "result.h5")));
    const nlohmann::json w = summary_of(whole);
    CHECK(s["steps"] == w["steps"]);
    CHECK(s["energy"]["balance_error"] == w["energy"]["balance_error"]);
    CHECK(s["run_id"] != w["run_id"]);
    CHECK(s["resumed_at"].size() == 1);
    fs::remove_all(whole);
    fs::remove_all(halves);
  }
}

TEST_CASE("a frictional impact stopped mid-contact resumes bit for bit under each Verlet scheme, its friction heat "
          "included",
          "[checkpoint]") {
  // A disc grazing a floor with friction heating it, stopped at 1.1e-4 s (its contact runs from
  // 3e-5 to 2.4e-4 s). The Verlet schemes book each contact's heat from its rows at the previous
  // and the latest evaluation (src/dem/contact_works.cpp): without the latest rows in the
  // checkpoint the resumed temperature ended 4.4e-9 K off.
  const fs::path scene_dir = testing::fresh_dir("grazing_scene");
  fs::create_directories(scene_dir);
  const std::string file = (scene_dir / "grazing.yaml").string();
  std::ofstream(file) << testing::grazing_impact();
  for (const std::string integrator : {"velocity-verlet", "verlet", "velocity-verlet-predicted"}) {
    const fs::path whole = testing::fresh_dir("whole"), halves = testing::fresh_dir("halves");
    const std::vector<std::string> sets = {"integrator=" + integrator, "dt=1e-6", "heat_from_dissipation=all"};
    run_whole(sets, whole, file);
    std::vector<std::string> half = sets;
    half.push_back("t_end=1.1e-4");
    run_whole(half, halves, file);
    resume(halves, 0.002);
    INFO(integrator);
    CHECK(same_bits(frames_of(whole / "result.h5"), frames_of(halves / "result.h5")));
    CHECK(summary_of(halves)["energy"]["thermal_change"] == summary_of(whole)["energy"]["thermal_change"]);
    fs::remove_all(whole);
    fs::remove_all(halves);
  }
  fs::remove_all(scene_dir);
}

TEST_CASE("a fixed-step run that ended off its grid resumes with whole steps from its own time", "[checkpoint]") {
  // The sticking pair under erk4 with contact events: the located onset moves the grid of steps
  // off 2e-5 s, so the first run's last step is shortened onto it. The resumed run must step on
  // from 2e-5 s; it stamped its first step on the old grid instead (5.8e-7 s past the stop for a
  // step of 5e-7 s), and ended 4.9e-8 m from the uninterrupted run. It is not the same bits (the
  // uninterrupted run has no step boundary at 2e-5 s), but the same trajectory to round-off.
  const std::string file = testing::case_path("pair_stick.yaml");
  const std::vector<std::string> sets = {"integrator=erk4", "contact_events=true"};
  const fs::path whole = testing::fresh_dir("whole"), halves = testing::fresh_dir("halves");
  std::vector<std::string> whole_sets = sets, half_sets = sets;
  whole_sets.push_back("t_end=8e-5");
  half_sets.push_back("t_end=2e-5");
  run_whole(whole_sets, whole, file);
  run_whole(half_sets, halves, file);
  resume(halves, 8e-5);
  const std::vector<double> a = testing::read_dataset(whole / "result.h5", "position");
  const std::vector<double> b = testing::read_dataset(halves / "result.h5", "position");
  const std::vector<double> ta = testing::read_dataset(whole / "result.h5", "time");
  const std::vector<double> tb = testing::read_dataset(halves / "result.h5", "time");
  REQUIRE(ta.back() == Approx(8e-5).epsilon(1e-12));
  REQUIRE(tb.back() == Approx(8e-5).epsilon(1e-12));
  double worst = 0;
  for (std::size_t k = 1; k <= 4; ++k) worst = std::max(worst, std::abs(a[a.size() - k] - b[b.size() - k]));
  CHECK(worst < 1e-12);  // m; discs of 2.5 mm moving at 1 m/s
  fs::remove_all(whole);
  fs::remove_all(halves);
}

// A rough wall under load, driven over a row of discs in a cell periodic in x: the wall body's
// coordinate, the attached discs and the periodic images all go through the checkpoint.
TEST_CASE("a sheared periodic row under a load-controlled rough wall resumes bit for bit", "[checkpoint]") {
  const fs::path dir = testing::fresh_dir("sheared_scene");
  fs::create_directories(dir);
  const std::string file = (dir / "sheared.yaml").string();
  std::ofstream(file) << R"(name: sheared
materials:
  glass: {density: 2500, stiffness: 5.0e4, restitution: 0.3, friction: 0.4}
particles:
  - {material: glass, radius: 0.001, velocity: [0.3, 0], lattice: {kind: square, origin: [0.001, 0.001], spacing: 0.002, rows: 1, columns: 10}}
  - {material: glass, radius: 0.001, attach: top, lattice: {kind: square, origin: [0.0, 0.003], spacing: 0.002, rows: 1, columns: 10}}
walls:
  - {name: floor, material: glass, polyline: [[0, 0], [0.01, 0], [0.02, 0]]}
  - name: top
    material: glass
    segment: [[0, 0.004], [0.02, 0.004]]
    motion: {type: load_controlled, velocity: [0.05, 0], load: [0, -2.0], mass: 0.01, damping: 2.0}
periodic: {x: [0, 0.02]}
allow_overlap: true
dt: 1.0e-6
t_end: 0.06
output_interval: 0.005
)";
  const fs::path whole = testing::fresh_dir("sheared_whole"), halves = testing::fresh_dir("sheared_halves");
  run_whole({}, whole, file);
  run_whole({assignment("t_end", 0.03)}, halves, file);
  const nlohmann::json s = resume(halves, 0.06);
  std::vector<double> a, b;
  for (const char* name : {"time", "position", "velocity", "angle", "angular_velocity", "wall_segments", "wall_force",
                           "wall_power"}) {
    const auto da = testing::read_dataset(whole / "result.h5", name), db = testing::read_dataset(halves / "result.h5", name);
    a.insert(a.end(), da.begin(), da.end());
    b.insert(b.end(), db.begin(), db.end());
  }
  CHECK(same_bits(a, b));
  CHECK(s["energy"]["balance_error"] == summary_of(whole)["energy"]["balance_error"]);
  fs::remove_all(whole);
  fs::remove_all(halves);
  fs::remove_all(dir);
}

TEST_CASE("SIGTERM stops a run with its frames, summary and checkpoint, exit 143; the restart continues bit for bit",
          "[checkpoint][signal][heavy]") {
  const fs::path whole = testing::fresh_dir("term_whole"), dir = testing::fresh_dir("term");
  run_whole({"output_interval=0.004", "t_end=0.06"}, whole);
  // Signalled once its first checkpoint exists, somewhere in the middle of the run.
  const Outcome o = run_kiln({"run", drum, "--set", "output_interval=0.004", "--t-end", "0.06", "--checkpoint-every",
                              "0.01", "--quiet", "--out", dir.string()},
                             0, SIGTERM, [&] { return fs::exists(dir / "checkpoint.h5"); });
  REQUIRE(o.exit_code == 143);
  CHECK(o.err.find("stopped by SIGTERM at t = ") != std::string::npos);
  CHECK(o.err.find("kiln run --restart") != std::string::npos);
  const nlohmann::json s = summary_of(dir);
  CHECK(s["stopped_early"] == "signal");
  const double stopped = s["t_end"].get<double>();
  CHECK(stopped < 0.06);
  // The published result holds every frame up to the stop, the last one at the stop.
  const auto time = testing::read_dataset(dir / "result.h5", "time");
  REQUIRE(!time.empty());
  CHECK(time.back() == stopped);
  for (const auto& entry : fs::directory_iterator(dir)) CHECK(entry.path().extension() != ".tmp");
  // Going on: the frames of the uninterrupted run, bit for bit (the stop's extra frame is dropped).
  const Outcome r = run_kiln({"run", "--restart", (dir / "checkpoint.h5").string(), "--quiet"});
  REQUIRE(r.exit_code == 0);
  CHECK(same_bits(frames_of(whole / "result.h5"), frames_of(dir / "result.h5")));
  fs::remove_all(whole);
  fs::remove_all(dir);
}

// Issue 28's review: GNU timeout sends SIGTERM to kiln and then to its process group, microseconds
// apart; that was taken as a second signal, and the run ended unpublished in 2 of 4 tries.
TEST_CASE("two SIGTERMs within a second are one request: the run still publishes, exit 143", "[signal]") {
  const fs::path dir = testing::fresh_dir("term_twice");
  const Outcome o = run_kiln({"run", drum, "--t-end", "0.5", "--quiet", "--out", dir.string()}, 0, SIGTERM,
                             [&] { return fs::exists(dir / "result.h5.tmp"); }, 2);
  REQUIRE(o.exit_code == 143);
  CHECK(summary_of(dir)["stopped_early"] == "signal");
  CHECK(fs::exists(dir / "checkpoint.h5"));
  fs::remove_all(dir);
}

TEST_CASE("SIGINT (Ctrl-C) stops a run the same way with exit 130", "[signal]") {
  const fs::path dir = testing::fresh_dir("int");
  const Outcome o = run_kiln({"run", drum, "--t-end", "0.5", "--quiet", "--out", dir.string()}, 0, SIGINT,
                             [&] { return fs::exists(dir / "result.h5.tmp"); });
  REQUIRE(o.exit_code == 130);
  CHECK(summary_of(dir)["stopped_early"] == "signal");
  CHECK(!testing::read_dataset(dir / "result.h5", "time").empty());
  CHECK(fs::exists(dir / "checkpoint.h5"));
  fs::remove_all(dir);
}

TEST_CASE("a run killed outright leaves its finished frames readable and resumes from its last checkpoint",
          "[checkpoint][signal][heavy]") {
  const fs::path whole = testing::fresh_dir("kill_whole"), dir = testing::fresh_dir("kill");
  run_whole({"output_interval=0.004", "t_end=0.06"}, whole);
  const auto start = std::chrono::steady_clock::now();
  const Outcome o = run_kiln({"run", drum, "--set", "output_interval=0.004", "--t-end", "0.06", "--checkpoint-every",
                              "0.01", "--quiet", "--out", dir.string()},
                             0, SIGKILL, [&] {
                               return fs::exists(dir / "checkpoint.h5") &&
                                      std::chrono::steady_clock::now() - start > std::chrono::milliseconds(400);
                             });
  REQUIRE(o.signal == SIGKILL);
  CHECK_FALSE(fs::exists(dir / "result.h5"));  // nothing under a final name but the checkpoint
  CHECK_FALSE(fs::exists(dir / "summary.json"));
  const auto time = testing::read_dataset(dir / "result.h5.tmp", "time");
  CHECK(!time.empty());  // readable, with the frames flushed before the kill
  const Outcome r = run_kiln({"run", "--restart", (dir / "checkpoint.h5").string(), "--quiet"});
  REQUIRE(r.exit_code == 0);
  CHECK(same_bits(frames_of(whole / "result.h5"), frames_of(dir / "result.h5")));
  fs::remove_all(whole);
  fs::remove_all(dir);
}

TEST_CASE("a full disk ends the run with one message naming the file and what it kept; with room, the restart "
          "finishes it bit for bit", "[outputs]") {
  // A full disk removed the whole run, every checkpoint included, even when every step had
  // finished. Now it keeps the frames (result.h5.unfinished, readable) and the last checkpoint.
  // Files capped (as a disk fills) early (only the start's checkpoint), mid-run, and at the close,
  // when every frame is written and the tables and views are not.
  const fs::path whole = testing::fresh_dir("full_whole");
  const std::vector<std::string> sets = {"output_interval=0.001", "t_end=0.06"};
  run_whole(sets, whole);
  // At the close: every frame fits, and the 0.6 MB the close reserves does not (its views take
  // about 0.3 MB of the whole 2.0 MB).
  const long closing = static_cast<long>(fs::file_size(whole / "result.h5")) - 300 * 1024;
  for (const long limit : {200L * 1024, 700L * 1024, closing}) {
    CAPTURE(limit);
    const fs::path dir = testing::fresh_dir("full");
    const Outcome o = run_kiln({"run", drum, "--t-end", "0.06", "--set", "output_interval=0.001", "--checkpoint-every",
                                "0.01", "--quiet", "--out", dir.string()},
                               limit);
    CHECK(o.signal == 0);  // no SIGSEGV in HDF5's exit handler
    CHECK(o.exit_code == 4);
    CHECK(o.err.find("result.h5.tmp") != std::string::npos);
    CHECK(o.err.find("kept: ") != std::string::npos);
    CHECK(std::count(o.err.begin(), o.err.end(), '\n') == 1);  // one message, not HDF5's error stack
    for (const char* name : {"result.h5", "summary.json", "picture.png", "result.xdmf"}) CHECK_FALSE(fs::exists(dir / name));
    for (const auto& entry : fs::directory_iterator(dir)) CHECK(entry.path().extension() != ".tmp");
    REQUIRE(fs::exists(dir / "checkpoint.h5"));
    CHECK_FALSE(testing::read_dataset(dir / "result.h5.unfinished", "time").empty());  // readable
    REQUIRE(run_kiln({"run", "--restart", (dir / "checkpoint.h5").string(), "--quiet"}).exit_code == 0);
    CHECK(same_bits(frames_of(whole / "result.h5"), frames_of(dir / "result.h5")));
    CHECK_FALSE(fs::exists(dir / "result.h5.unfinished"));
    fs::remove_all(dir);
  }
  fs::remove_all(whole);
}

TEST_CASE("a run killed while publishing resumes to publish; a published run is not resumed at its end",
          "[outputs][checkpoint]") {
  // A kill during the final publication left frames that --restart refused ("give a later
  // --t-end"). The states a kill can leave there: nothing renamed yet (result.h5.tmp, complete),
  // or result.h5 renamed and summary.json (published last) not.
  const fs::path whole = testing::fresh_dir("publish_whole"), dir = testing::fresh_dir("publish");
  const std::vector<std::string> sets = {"output_interval=0.004", "t_end=0.02"};
  run_whole(sets, whole);
  for (const bool renamed : {false, true}) {
    CAPTURE(renamed);
    fs::remove_all(dir);
    run_whole(sets, dir);
    for (const char* name : {"summary.json", "result.xdmf", "picture.png", "units.csv", "wall_loads.csv"})
      fs::remove(dir / name);
    if (!renamed) fs::rename(dir / "result.h5", dir / "result.h5.tmp");
    const Outcome r = run_kiln({"run", "--restart", (dir / "checkpoint.h5").string(), "--quiet"});
    INFO(r.err);
    REQUIRE(r.exit_code == 0);
    CHECK(same_bits(frames_of(whole / "result.h5"), frames_of(dir / "result.h5")));
    CHECK(fs::exists(dir / "summary.json"));
    CHECK(fs::exists(dir / "result.xdmf"));
  }
  const Outcome again = run_kiln({"run", "--restart", (dir / "checkpoint.h5").string(), "--quiet"});
  CHECK(again.exit_code == 2);
  CHECK(again.err.find("give a later --t-end") != std::string::npos);
  fs::remove_all(dir);
  fs::remove_all(whole);
}

TEST_CASE("a run stopped at rest whose publication failed resumes to publish and does not step on past its rest",
          "[outputs][checkpoint]") {
  // Its last checkpoint is at its rest, before t_end: resumed, it stepped on to t_end, writing
  // frames and a summary the run it finishes never had.
  const fs::path whole = testing::fresh_dir("rest_whole"), dir = testing::fresh_dir("rest");
  const std::vector<std::string> sets = {"output_interval=0.004", "t_end=0.02", "stop.kinetic_energy_below=1e9",
                                         "stop.not_before=0.008"};
  run_whole(sets, whole);
  run_whole(sets, dir);
  for (const char* name : {"summary.json", "result.xdmf", "picture.png", "units.csv", "wall_loads.csv"})
    fs::remove(dir / name);
  const Outcome r = run_kiln({"run", "--restart", (dir / "checkpoint.h5").string(), "--quiet"});
  INFO(r.err);
  REQUIRE(r.exit_code == 0);
  CHECK(same_bits(frames_of(whole / "result.h5"), frames_of(dir / "result.h5")));
  const nlohmann::json summary = summary_of(dir);
  CHECK(summary["stopped_early"] == "at_rest");
  CHECK(summary["t_end"].get<double>() == Approx(0.008));
  fs::remove_all(dir);
  fs::remove_all(whole);
}

TEST_CASE("a text output that cannot be written is an OutputError naming the file and its partial file is removed",
          "[outputs]") {
  // In a child whose files may not exceed 4 KiB, as on a disk that fills up while writing.
  const fs::path file = testing::fresh_dir("text_output");
  const pid_t pid = fork();
  if (pid == 0) {
    std::signal(SIGXFSZ, SIG_IGN);
    const rlimit limit{4096, 4096};
    setrlimit(RLIMIT_FSIZE, &limit);
    try {
      write_file(file.string(), std::string(1 << 16, 'x'));
    } catch (const OutputError& e) {
      const std::string message = e.what();
      _exit(message.find(file.string()) != std::string::npos && message.find("File too large") != std::string::npos
                ? 0
                : 2);
    }
    _exit(1);
  }
  int status = 0;
  waitpid(pid, &status, 0);
  CHECK(WIFEXITED(status));
  CHECK(WEXITSTATUS(status) == 0);  // 1: the write "succeeded"; 2: the message lacks the file or the cause
  CHECK_FALSE(fs::exists(file));
}

TEST_CASE("a new run moves an earlier run's results into previous/ and records its own run id and start time",
          "[outputs]") {
  const fs::path dir = testing::fresh_dir("previous");
  const std::vector<std::string> run = {"run", testing::case_path("t1_free_fall.yaml"), "--t-end", "0.01", "--quiet",
                                        "--out", dir.string()};
  REQUIRE(run_kiln(run).exit_code == 0);
  const nlohmann::json first = summary_of(dir);
  REQUIRE(run_kiln(run).exit_code == 0);
  const nlohmann::json second = summary_of(dir);
  CHECK(first["run_id"] != second["run_id"]);
  CHECK(second["start_time"].get<std::string>().size() == 20);  // 2026-11-30T15:04:05Z
  CHECK(summary_of(dir / "previous")["run_id"] == first["run_id"]);
  // A failed run leaves the earlier results in previous/ and nothing beside them.
  const std::vector<std::string> unstable = {"run", testing::case_path("t1_free_fall.yaml"), "--dt", "5e-4", "--t-end",
                                             "0.2", "--force", "--quiet", "--out", dir.string()};
  CHECK(run_kiln(unstable).exit_code == 3);
  CHECK_FALSE(fs::exists(dir / "summary.json"));
  CHECK(summary_of(dir / "previous")["run_id"] == second["run_id"]);
  fs::remove_all(dir);
}

TEST_CASE("a restart refuses a checkpoint of another kiln version, another scene, or a result of another run",
          "[checkpoint]") {
  const fs::path dir = testing::fresh_dir("refuse");
  run_whole({"t_end=0.002"}, dir);
  Snapshot s = Snapshot::read((dir / "checkpoint.h5").string());
  SceneRecord source;
  CHECK_NOTHROW(scene_of_checkpoint(s, {"t_end=0.004"}, source));
  s.put_text("kiln_version", "0.0.1");
  CHECK_THROWS_AS(scene_of_checkpoint(s, {}, source), InputError);
  // The scene given beside --restart must be the one the checkpoint records.
  const Outcome other = run_kiln({"run", testing::case_path("t1_free_fall.yaml"), "--restart",
                                  (dir / "checkpoint.h5").string(), "--t-end", "0.004"});
  CHECK(other.exit_code == 2);
  CHECK(other.err.find("is a checkpoint of scene file") != std::string::npos);
  // Its frames must be the run's own: another run's result.h5 is refused.
  const fs::path elsewhere = testing::fresh_dir("refuse_other");
  run_whole({"t_end=0.002"}, elsewhere);
  fs::copy_file(elsewhere / "result.h5", dir / "result.h5", fs::copy_options::overwrite_existing);
  const Outcome mixed = run_kiln({"run", "--restart", (dir / "checkpoint.h5").string(), "--t-end", "0.004"});
  CHECK(mixed.exit_code == 2);
  CHECK(mixed.err.find("holds the") != std::string::npos);
  fs::remove_all(dir);
  fs::remove_all(elsewhere);
}

TEST_CASE("an output interval far below the step gives one frame per step and ends", "[outputs]") {
  // (1e-300 s, tried here first, is now refused: more than a million frames; 1e-9 s is a thousandth
  // of T1's step.)
  const Scene scene = load_scene(testing::case_path("t1_free_fall.yaml"), {"t_end=0.001", "output_interval=1e-9"});
  const fs::path dir = testing::fresh_dir("tiny_interval");
  RunOptions o;
  o.out_dir = dir.string();
  o.quiet = true;
  const nlohmann::json s = run_scene(scene, o);
  CHECK(testing::read_dataset(dir / "result.h5", "time").size() == s["steps"].get<size_t>() + 1);
  fs::remove_all(dir);
}

TEST_CASE("a disc that moves more than its radius in one step stops the run with that reason", "[stability]") {
  // 100 m/s towards the floor at dt = 1e-4 s: 10 mm a step, five radii (kiln check refuses it;
  // this is the run's own check, for what the estimate cannot foresee).
  const Scene scene = load_scene(testing::case_path("t1_free_fall.yaml"),
                                 {"particles.0.velocity=[0, -100]", "dt=1e-4", "t_end=0.01"});
  try {
    run_scene(scene, {"", true});
    FAIL("the disc went through");
  } catch (const InstabilityError& e) {
    CHECK(std::string(e.what()).find("more than its radius") != std::string::npos);
  }
}

TEST_CASE("exit codes: a NaN or zero argument is bad input with a short message; a study with no result is 5",
          "[outputs]") {
  const std::string scene = testing::case_path("t1_free_fall.yaml");
  for (const char* bad : {"nan", "0", "-1", "inf"}) {
    const Outcome o = run_kiln({"check", scene, "--dt", bad});
    INFO(bad);
    CHECK(o.exit_code == 2);
    CHECK(o.err.find("must be a positive finite number") != std::string::npos);
    CHECK(o.err.size() < 300);
  }
  CHECK(run_kiln({"run", scene, "--no-such-option"}).exit_code == 2);
  const fs::path dir = testing::fresh_dir("study_failed");
  const Outcome study = run_kiln({"sweep", scene, "--integrator", "velocity-verlet", "--dt-min", "1e-3", "--dt-max",
                                  "2e-3", "--points", "2", "--t-end", "0.2", "--quiet", "--out", dir.string()});
  CHECK(study.exit_code == 5);
  CHECK(study.err.find("every run of the study failed") != std::string::npos);
  fs::remove_all(dir);
}

TEST_CASE("energies that overflow stop a forced run instead of ending it with exit 0", "[stability]") {
  // A speed of 1e155 m/s is finite, its kinetic energy is not: the check used to compare inf - inf.
  // (The step is short enough that the disc moves less than its radius.) A scene file can no longer
  // give that speed (faster than light): the state is set here, as a blown-up run would reach it.
  Scene scene = load_scene(testing::case_path("t1_free_fall.yaml"), {"dt=1e-160", "t_end=1e-160"});
  scene.velocity[0] = {1e155, 0};
  try {
    run_scene(scene, {"", true});
    FAIL("the run ended normally");
  } catch (const InstabilityError& e) {
    CHECK(std::string(e.what()).find("energy overflow") != std::string::npos);
  }
}

TEST_CASE("a resumed run that fails keeps the earlier frames and the checkpoint, and resumes again once the cause "
          "is gone", "[checkpoint][heavy]") {
  const fs::path dir = testing::fresh_dir("resume_fails"), whole = testing::fresh_dir("resume_fails_whole");
  run_whole({"output_interval=0.004", "t_end=0.008"}, dir);
  run_whole({"output_interval=0.004", "t_end=0.04"}, whole);
  const std::vector<double> time_before = testing::read_dataset(dir / "result.h5", "time");
  const std::vector<double> position_before = testing::read_dataset(dir / "result.h5", "position");
  // Resumed on a disk that fills up after one more frame (a frame of the drum is 12 KiB).
  const long limit = static_cast<long>(fs::file_size(dir / "result.h5")) + 20 * 1024;
  const Outcome o = run_kiln({"run", "--restart", (dir / "checkpoint.h5").string(), "--t-end", "0.04", "--quiet"}, limit);
  CHECK(o.exit_code == 4);
  CHECK(fs::exists(dir / "checkpoint.h5"));
  // The frames it resumed after are still there (under the temporary name: the run did not end).
  const fs::path left = fs::exists(dir / "result.h5") ? dir / "result.h5" : dir / "result.h5.tmp";
  const std::vector<double> time_after = testing::read_dataset(left, "time");
  const std::vector<double> position_after = testing::read_dataset(left, "position");
  REQUIRE(time_after.size() >= time_before.size());
  CHECK(std::equal(time_before.begin(), time_before.end(), time_after.begin()));
  CHECK(std::equal(position_before.begin(), position_before.end(), position_after.begin()));
  // With room again, the restart goes on and ends as the uninterrupted run.
  REQUIRE(run_kiln({"run", "--restart", (dir / "checkpoint.h5").string(), "--t-end", "0.04", "--quiet"}).exit_code == 0);
  CHECK(same_bits(frames_of(whole / "result.h5"), frames_of(dir / "result.h5")));
  fs::remove_all(dir);
  fs::remove_all(whole);
}

TEST_CASE("a second run into a directory in use is refused; a killed resumed run resumes from its own frames",
          "[checkpoint][heavy]") {
  const fs::path dir = testing::fresh_dir("in_use"), whole = testing::fresh_dir("in_use_whole");
  // While a run writes, a second one into the same directory is refused (they used to publish a mix).
  const std::vector<std::string> long_run = {"run", drum, "--t-end", "0.5", "--quiet", "--out", dir.string()};
  Outcome second;
  const Outcome first = run_kiln(long_run, 0, SIGTERM, [&] {
    if (!fs::exists(dir / "checkpoint.h5")) return false;
    second = run_kiln({"run", testing::case_path("t1_free_fall.yaml"), "--t-end", "0.01", "--quiet", "--out",
                       dir.string()});
    return true;
  });
  CHECK(first.exit_code == 143);
  CHECK(second.exit_code == 2);
  CHECK(second.err.find("is in use by another kiln run") != std::string::npos);
  // A resumed run killed outright, then resumed again: from the frames the killed one extended.
  fs::remove_all(dir);
  run_whole({"output_interval=0.004", "t_end=0.02"}, dir);
  run_whole({"output_interval=0.004", "t_end=0.08"}, whole);
  const auto start = std::chrono::steady_clock::now();
  const Outcome killed = run_kiln({"run", "--restart", (dir / "checkpoint.h5").string(), "--t-end", "0.08",
                                   "--checkpoint-every", "0.004", "--quiet"},
                                  0, SIGKILL,
                                  [&] { return std::chrono::steady_clock::now() - start > std::chrono::milliseconds(700); });
  REQUIRE(killed.signal == SIGKILL);
  REQUIRE(run_kiln({"run", "--restart", (dir / "checkpoint.h5").string(), "--t-end", "0.08", "--quiet"}).exit_code == 0);
  CHECK(same_bits(frames_of(whole / "result.h5"), frames_of(dir / "result.h5")));
  CHECK_FALSE(fs::exists(dir / "result.h5.unfinished"));
  fs::remove_all(dir);
  fs::remove_all(whole);
}

// The scene's text is in the checkpoint, its drawings are not: a drawing changed since is refused,
// where it used to move the walls silently.
TEST_CASE("a restart refuses a scene whose SVG drawing changed since the checkpoint", "[checkpoint][svg]") {
  const fs::path dir = testing::fresh_dir("svg_restart");
  fs::create_directories(dir);
  const std::string svg = R"svg(<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 100 100"><g id="box"><rect x="10" y="10" width="80" height="80" transform="rotate(0 50 50)"/></g></svg>)svg";
  std::ofstream(dir / "box.svg") << svg;
  const std::string file = (dir / "box.yaml").string();
  std::ofstream(file) << R"(name: svg_box
materials:
  glass: {density: 2500, stiffness: 1.0e4, restitution: 0.5}
particles:
  - {material: glass, radius: 0.002, at: [[0.05, 0.05]]}
walls:
  - {material: glass, svg: {file: box.svg, scale: 0.001}}
dt: 1.0e-5
t_end: 0.02
)";
  const fs::path out = testing::fresh_dir("svg_restart_out");
  run_whole({assignment("t_end", 0.01)}, out, file);
  std::ofstream(dir / "box.svg") << testing::replaced(svg, "rotate(0 50 50)", "rotate(5 50 50)");
  std::string message;
  try {
    resume(out, 0.02);
  } catch (const InputError& e) {
    message = e.what();
  }
  CHECK(message.find("box.svg") != std::string::npos);
  CHECK(message.find("changed since the checkpoint") != std::string::npos);
  fs::remove_all(dir);
  fs::remove_all(out);
}

TEST_CASE("a shear cell resumed with a later t_end reports the profile and stresses of an uninterrupted run",
          "[checkpoint][shear]") {
  // The shear observer averages over the second half of the run: resumed at 0.02 s with t_end
  // 0.04 s, its window is 0.02 .. 0.04 s, and what the checkpoint carries of the first run's
  // window (0.01 .. 0.02 s) must not enter it.
  const std::string file = testing::case_path("n3_shear_cell.yaml");
  const fs::path whole = testing::fresh_dir("shear_whole"), halves = testing::fresh_dir("shear_halves");
  run_whole({"t_end=0.04"}, whole, file);
  run_whole({"t_end=0.02"}, halves, file);
  const nlohmann::json resumed = resume(halves, 0.04), straight = summary_of(whole);
  for (const char* key : {"shear_stress", "normal_stress", "effective_friction", "inertial_number"})
    CHECK(resumed[key] == straight[key]);
  CHECK(resumed["shear_profile"] == straight["shear_profile"]);
  fs::remove_all(whole);
  fs::remove_all(halves);
}
