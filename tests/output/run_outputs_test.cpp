// What a run leaves behind and how it fails: outputs, determinism, instability messages, and a
// scene that models only what it needs.
#include <cairo.h>
#include <catch2/catch.hpp>
#include <hdf5.h>

#include <algorithm>
#include <cstdint>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <nlohmann/json.hpp>
#include <sstream>

#include "src/dem/dem_system.h"
#include "src/base/error.h"
#include "src/output/output_h5.h"
#include "src/output/outputs.h"
#include "src/scene/overrides.h"
#include "src/scene/scene_yaml.h"
#include "src/run/simulation.h"
#include "src/base/snapshot.h"
#include "src/run/stability.h"
#include "tests/support.h"

using namespace kiln;
namespace fs = std::filesystem;

namespace {

// The dimensions of a dataset of an HDF5 file (empty when it is not there).
std::vector<hsize_t> dims_of(const fs::path& file, const std::string& name) {
  std::vector<hsize_t> dims;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return dims;
  if (H5Lexists(f, name.c_str(), H5P_DEFAULT) > 0) {
    const hid_t ds = H5Dopen2(f, name.c_str(), H5P_DEFAULT);
    const hid_t space = H5Dget_space(ds);
    dims.resize(H5Sget_simple_extent_ndims(space));
    H5Sget_simple_extent_dims(space, dims.data(), nullptr);
    H5Sclose(space);
    H5Dclose(ds);
  }
  H5Fclose(f);
  return dims;
}

// A text attribute of an object (a dataset, or "/" for the file), "" when absent.
std::string text_attribute(const fs::path& file, const std::string& object, const char* name) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return "";
  std::string value;
  const hid_t o = H5Oopen(f, object.c_str(), H5P_DEFAULT);
  if (o >= 0 && H5Aexists(o, name) > 0) {
    const hid_t attr = H5Aopen(o, name, H5P_DEFAULT);
    const hid_t type = H5Aget_type(attr);
    if (H5Tget_class(type) == H5T_STRING && !H5Tis_variable_str(type)) {
      value.assign(H5Tget_size(type), '\0');
      H5Aread(attr, type, value.data());
      value = value.substr(0, value.find('\0'));
    }
    H5Tclose(type);
    H5Aclose(attr);
  }
  if (o >= 0) H5Oclose(o);
  H5Fclose(f);
  return value;
}

// Every dataset of a file, found by visiting its links (not from a list of expected names).
std::vector<std::string> split(const std::string& text, char by) {
  std::vector<std::string> parts;
  std::stringstream in(text);
  for (std::string part; std::getline(in, part, by);) parts.push_back(part);
  return parts;
}

std::vector<std::string> datasets_of(const fs::path& file) {
  std::vector<std::string> names;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return names;
  auto visit = [](hid_t group, const char* name, const H5L_info_t*, void* data) -> herr_t {
    const hid_t o = H5Oopen(group, name, H5P_DEFAULT);
    if (o >= 0 && H5Iget_type(o) == H5I_DATASET) static_cast<std::vector<std::string>*>(data)->push_back(name);
    if (o >= 0) H5Oclose(o);
    return 0;
  };
  H5Lvisit(f, H5_INDEX_NAME, H5_ITER_INC, visit, &names);
  H5Fclose(f);
  return names;
}

// The file attribute wall_names (an array of variable-length strings).
std::vector<std::string> wall_names_of(const fs::path& file) {
  std::vector<std::string> names;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return names;
  if (H5Aexists(f, "wall_names") > 0) {
    const hid_t attr = H5Aopen(f, "wall_names", H5P_DEFAULT);
    const hid_t space = H5Aget_space(attr);
    std::vector<char*> text(H5Sget_simple_extent_npoints(space));
    const hid_t type = H5Tcopy(H5T_C_S1);
    H5Tset_size(type, H5T_VARIABLE);
    H5Tset_cset(type, H5T_CSET_UTF8);
    if (H5Aread(attr, type, text.data()) >= 0) {
      for (char* t : text) names.push_back(t ? t : "");
      H5Dvlen_reclaim(type, space, H5P_DEFAULT, text.data());
    }
    H5Tclose(type);
    H5Sclose(space);
    H5Aclose(attr);
  }
  H5Fclose(f);
  return names;
}

std::vector<int> read_ints(const fs::path& file, const char* name) {
  std::vector<int> data;
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return data;
  const hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
  const hid_t space = H5Dget_space(ds);
  data.resize(H5Sget_simple_extent_npoints(space));
  H5Dread(ds, H5T_NATIVE_INT, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
  H5Sclose(space);
  H5Dclose(ds);
  H5Fclose(f);
  return data;
}

// One disc at rest without gravity in a box of a floor and a ceiling, and a vertical wall
// (the pusher) from (0.02, 0.02) to (0.02, 0.08) that, with `moving`, translates at 0.6 m/s along x.
const double pusher_speed = 0.6;
std::string pusher_scene(bool moving) {
  return std::string(R"(name: pusher
gravity: [0, 0]
materials:
  copper: {density: 8900, stiffness: 6000, restitution: 0.8}
particles:
  - material: copper
    radius: 0.002
    at: [[0.05, 0.095]]
walls:
  - {name: floor, material: copper, segment: [[0, 0], [0.1, 0]]}
  - {name: ceiling, material: copper, segment: [[0, 0.1], [0.1, 0.1]]}
  - name: pusher
    material: copper
    segment: [[0.02, 0.02], [0.02, 0.08]]
)") + (moving ? "    motion: {type: translate, velocity: [0.6, 0]}\n" : "") +
         "dt: 1.0e-5\nt_end: 0.1\noutput_interval: 0.01\n";
}

// Runs the pusher scene into dir, recording its source (so that it can be resumed).
nlohmann::json run_pusher(const fs::path& dir, bool moving, const std::vector<std::string>& sets = {}) {
  const std::string text = pusher_scene(moving);
  RunOptions o;
  o.out_dir = dir.string();
  o.quiet = true;
  o.source = {"pusher.yaml", text, sets};
  return run_scene(parse_scene(text, "pusher.yaml", sets), o);
}

// The datasets of a result that are not frames: written once.
bool constant_dataset(const fs::path& file, const std::string& name) {
  return name == "radius" || name == "id" || name == "wall_of_segment" || name == "wall_connectivity" ||
         (name == "wall_segments" && dims_of(file, name).size() == 2);
}

}  // namespace

TEST_CASE("kiln run writes result.h5, result.xdmf, summary.json and picture.png, nothing temporary", "[outputs]") {
  const fs::path dir = testing::fresh_dir("outputs");
  const std::string cmd = std::string(KILN_BINARY) + " run " + testing::case_path("t1_free_fall.yaml") +
                          " --t-end 0.01 --quiet --out " + dir.string();
  REQUIRE(std::system(cmd.c_str()) == 0);
  for (const char* name : {"result.h5", "result.xdmf", "summary.json", "picture.png"}) CHECK(fs::exists(dir / name));
  for (const auto& entry : fs::directory_iterator(dir)) CHECK(entry.path().extension() != ".tmp");
  std::ifstream in(dir / "summary.json");
  const auto s = nlohmann::json::parse(in);
  for (const char* key : {"scene", "integrator", "dt", "t_end", "steps", "rhs_evals", "wall_seconds", "particles",
                          "mean_contacts"})
    CHECK(s.contains(key));
  for (const char* key : {"kinetic", "potential", "elastic", "dissipated_damping", "dissipated_friction",
                          "work_by_walls", "balance_error"})
    CHECK(s["energy"].contains(key));
  // 0.01 s at 1e-3 s per frame: the initial state, ten frames, the final state included.
  const auto time = testing::read_dataset(dir / "result.h5", "time");
  REQUIRE(time.size() == 11);
  CHECK(time.front() == 0.0);
  CHECK(time.back() == Approx(0.01));
  CHECK(testing::read_dataset(dir / "result.h5", "position").size() == 11 * 3);
  CHECK(testing::read_dataset(dir / "result.h5", "radius") == std::vector<double>{0.002});
  fs::remove_all(dir);
}

TEST_CASE("a published result.h5 ends where HDF5's contents end: the room reserved for frames is given back",
          "[outputs]") {
  // Issue 28's campaign: the last posix_fallocate reservation stayed in the published file as zeros
  // (T3 to 0.02 s: 185,252 bytes, 80,533 of them trailing zeros; 104,804 before the reservations).
  const fs::path dir = testing::fresh_dir("outputs_size");
  run_scene(load_scene(testing::case_path("t3_heap.yaml"), {"t_end=0.02"}), {dir.string(), true});
  std::ifstream in(dir / "result.h5", std::ios::binary);
  const std::string bytes((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  const size_t zeros = bytes.size() - (bytes.find_last_not_of('\0') + 1);
  CHECK(zeros < 1024);
  CHECK(bytes.size() < 120000);
  CHECK(testing::read_dataset(dir / "result.h5", "time").size() == 3);  // readable, every frame
  fs::remove_all(dir);
}

TEST_CASE("a quiet run of a frozen heat scene under an ARKODE method prints nothing", "[outputs]") {
  // The start's checkpoint asked the mechanics integrator, never started in a frozen scene, for its
  // statistics: ARKODE printed "arkode_mem = NULL illegal" five times on a healthy run.
  const fs::path dir = testing::fresh_dir("quiet_frozen");
  fs::create_directories(dir);
  const fs::path log = dir / "log.txt";
  const std::string cmd = std::string(KILN_BINARY) + " run " + testing::case_path("t4_two_particle_conduction.yaml") +
                          " --integrator erk4 --dt 0.04 --t-end 0.8 --quiet --out " + (dir / "run").string() + " > " +
                          log.string() + " 2>&1";
  REQUIRE(std::system(cmd.c_str()) == 0);
  std::ifstream in(log);
  const std::string printed((std::istreambuf_iterator<char>(in)), std::istreambuf_iterator<char>());
  CHECK(printed.empty());
  fs::remove_all(dir);
}

TEST_CASE("a bad --set on the command line fails with exit code 2 and writes nothing", "[outputs]") {
  const fs::path dir = testing::fresh_dir("bad");
  const std::string cmd = std::string(KILN_BINARY) + " run " + testing::case_path("t1_free_fall.yaml") +
                          " --set materials.copper.density=-1 --quiet --out " + dir.string() + " 2>/dev/null";
  CHECK(WEXITSTATUS(std::system(cmd.c_str())) == 2);
  CHECK_FALSE(fs::exists(dir));
}

TEST_CASE("the same scene and options give bit-identical result.h5 data", "[outputs]") {
  const Scene scene = load_scene(testing::case_path("t3_heap.yaml"), {"particles.0.fill.count=100", "t_end=0.05"});
  std::vector<std::vector<double>> runs;
  for (int k = 0; k < 2; ++k) {
    const fs::path dir = testing::fresh_dir("determinism" + std::to_string(k));
    run_scene(scene, {dir.string(), true});
    std::vector<double> all;
    for (const char* name : {"time", "position", "velocity", "angle", "angular_velocity"}) {
      const auto d = testing::read_dataset(dir / "result.h5", name);
      all.insert(all.end(), d.begin(), d.end());
    }
    runs.push_back(all);
    fs::remove_all(dir);
  }
  REQUIRE(runs[0].size() > 1000);
  CHECK(std::memcmp(runs[0].data(), runs[1].data(), runs[0].size() * sizeof(double)) == 0);
}

TEST_CASE("a step beyond the stability limit stops with the failed check, the time and the advised dt", "[stability]") {
  const Scene scene = load_scene(testing::case_path("t1_free_fall.yaml"), {"dt=5e-4", "t_end=0.2"});
  const StabilityEstimate est = estimate_stability(scene);
  CHECK(judge_dt(est, scene.dt, scene).unstable);  // kiln check and kiln run refuse it up front
  const fs::path dir = testing::fresh_dir("unstable");
  try {
    run_scene(scene, {dir.string(), true});
    FAIL("the run did not stop");
  } catch (const InstabilityError& e) {
    const std::string msg = e.what();
    CHECK(msg.find("unstable run at t = ") != std::string::npos);
    CHECK((msg.find("overlap") != std::string::npos || msg.find("energy blow-up") != std::string::npos ||
           msg.find("NaN") != std::string::npos));
    CHECK(msg.find("recommends dt <= 1.4") != std::string::npos);  // t_c / 50 = 1.40e-5 s
  }
  // Nothing half-written is left behind.
  for (const auto& entry : fs::directory_iterator(dir)) CHECK(entry.path().extension() != ".tmp");
  CHECK_FALSE(fs::exists(dir / "result.h5"));
  fs::remove_all(dir);
}

TEST_CASE("stability estimate: linear contact duration and the central-difference limit", "[stability]") {
  const Scene scene = load_scene(testing::case_path("t1_free_fall.yaml"));
  const StabilityEstimate est = estimate_stability(scene);
  const double m = 4.0 / 3.0 * M_PI * 8e-9 * 8900;
  CHECK(est.contact_duration == Approx(M_PI * std::sqrt(m / 6000)));
  CHECK(est.dt_limit == Approx(2 * std::sqrt(m / 6000)));
  CHECK(est.recommended_dt == Approx(est.contact_duration / 50));
  CHECK(judge_dt(est, 1e-6, scene).warnings.empty());
  CHECK_FALSE(judge_dt(est, 1e-4, scene).unstable);
  CHECK(judge_dt(est, 1e-4, scene).warnings.size() == 1);  // 7 steps per contact: warned, not refused
}

TEST_CASE("a frictionless scene integrates no rotation, while friction adds angles and spins", "[state]") {
  const Scene plain = load_scene(testing::case_path("t1_free_fall.yaml"));
  DemSystem without(plain);
  CHECK_FALSE(without.rotates());
  CHECK(without.layout().nq == 2 * plain.n_particles());
  const Scene rough = load_scene(testing::case_path("c1_incline_roll_slide.yaml"));
  DemSystem with(rough);
  CHECK(with.rotates());
  CHECK(with.layout().nq == 3 * rough.n_particles());
}

TEST_CASE("result.h5 writes position, velocity and wall forces as three-component vectors with z = 0", "[outputs]") {
  const fs::path dir = testing::fresh_dir("vectors");
  run_scene(load_scene(testing::case_path("t1_free_fall.yaml"), {"t_end=0.05"}), {dir.string(), true});
  const fs::path h5 = dir / "result.h5";
  const hsize_t frames = dims_of(h5, "time").at(0);
  REQUIRE(frames == 51);
  for (const char* name : {"position", "velocity", "wall_force"}) {
    INFO(name);
    CHECK(dims_of(h5, name) == std::vector<hsize_t>{frames, 1, 3});  // one disc, one wall (the box)
    const auto v = testing::read_dataset(h5, name);
    REQUIRE(v.size() == 3 * frames);
    for (size_t k = 2; k < v.size(); k += 3) CHECK(v[k] == 0.0);
  }
  // x and y are the disc's: released at rest at (0.025, 0.03), in free fall for 0.05 s.
  const auto p = testing::read_dataset(h5, "position"), v = testing::read_dataset(h5, "velocity");
  CHECK(p[0] == 0.025);
  CHECK(p[1] == 0.03);
  CHECK(p[3 * (frames - 1)] == Approx(0.025));
  CHECK(p[3 * (frames - 1) + 1] == Approx(0.03 - 0.5 * 9.81 * 0.05 * 0.05).epsilon(1e-4));
  CHECK(v[3 * (frames - 1) + 1] == Approx(-9.81 * 0.05).epsilon(1e-4));
  fs::remove_all(dir);
}

TEST_CASE("every dataset of a thermal run's result.h5 carries its units", "[outputs]") {
  // L2: a thermal scene with moving walls, so that every kind of dataset is written.
  const fs::path dir = testing::fresh_dir("units");
  run_scene(load_scene(testing::case_path("l2_aligned_wall_heating.yaml"), {"t_end=0.01"}), {dir.string(), true});
  const fs::path h5 = dir / "result.h5";
  const std::map<std::string, std::string> expected = {
      {"time", "s"},           {"position", "m"},       {"velocity", "m/s"},     {"angle", "rad"},
      {"angular_velocity", "rad/s"}, {"temperature", "degC"}, {"radius", "m"},   {"id", "1"},
      {"wall_segments", "m"},  {"wall_of_segment", "1"}, {"wall_connectivity", "1"}, {"wall_force", "N"},
      {"wall_torque", "N m"},  {"wall_power", "W"}};
  const std::vector<std::string> names = datasets_of(h5);
  for (const auto& [name, units] : expected) {
    INFO(name);
    CHECK(std::find(names.begin(), names.end(), name) != names.end());
  }
  for (const std::string& name : names) {
    INFO(name);
    const std::string units = text_attribute(h5, name, "units");
    CHECK_FALSE(units.empty());
    if (expected.count(name)) CHECK(units == expected.at(name));
  }
  fs::remove_all(dir);
}

TEST_CASE("wall_segments follow a translating wall frame by frame, with the walls' names and loads", "[outputs]") {
  const fs::path dir = testing::fresh_dir("moving_walls");
  run_pusher(dir, true);
  const fs::path h5 = dir / "result.h5";
  const Scene scene = parse_scene(pusher_scene(true), "pusher.yaml");
  const std::vector<double> time = testing::read_dataset(h5, "time");
  const hsize_t frames = time.size(), segments = scene.segments.size(), walls = scene.walls.size();
  REQUIRE(frames == 11);
  REQUIRE(segments == 3);
  REQUIRE(dims_of(h5, "wall_segments") == std::vector<hsize_t>{frames, segments, 4});
  CHECK(text_attribute(h5, "wall_segments", "units") == "m");
  CHECK(wall_names_of(h5) == std::vector<std::string>{"floor", "ceiling", "pusher"});
  const std::vector<int> wall_of = read_ints(h5, "wall_of_segment");
  REQUIRE(wall_of.size() == segments);
  const std::vector<double> seg = testing::read_dataset(h5, "wall_segments");
  for (hsize_t k = 0; k < frames; ++k)
    for (hsize_t s = 0; s < segments; ++s) {
      INFO("frame " << k << " (t = " << time[k] << "), segment " << s);
      const Segment& g = scene.segments[s];
      CHECK(wall_of[s] == g.wall);
      // The pusher's ends at a0 + v t, the others where they started.
      const double dx = scene.walls[g.wall].name == "pusher" ? pusher_speed * time[k] : 0.0;
      const double* row = &seg[4 * (k * segments + s)];
      CHECK(row[0] == Approx(g.a.x + dx).margin(1e-12));
      CHECK(row[1] == Approx(g.a.y).margin(1e-12));
      CHECK(row[2] == Approx(g.b.x + dx).margin(1e-12));
      CHECK(row[3] == Approx(g.b.y).margin(1e-12));
    }
  CHECK(seg[4 * ((frames - 1) * segments + 2)] == Approx(0.08));  // 0.02 + 0.6 m/s x 0.1 s
  // The loads: one row per frame and wall, in newtons, newton metres and watts.
  CHECK(dims_of(h5, "wall_force") == std::vector<hsize_t>{frames, walls, 3});
  CHECK(dims_of(h5, "wall_torque") == std::vector<hsize_t>{frames, walls});
  CHECK(dims_of(h5, "wall_power") == std::vector<hsize_t>{frames, walls});
  CHECK(text_attribute(h5, "wall_force", "units") == "N");
  CHECK(text_attribute(h5, "wall_torque", "units") == "N m");
  CHECK(text_attribute(h5, "wall_power", "units") == "W");
  // wall_loads.csv holds the same loads, a row per frame, its columns named by wall and unit.
  std::ifstream csv(dir / "wall_loads.csv");
  std::string header;
  REQUIRE(std::getline(csv, header));
  CHECK(header.rfind("\"time (s)\",\"floor force_x (N)\",\"floor force_y (N)\",\"floor torque (N m)\",\"floor power (W)\","
                     "\"ceiling force_x (N)\"", 0) == 0);
  const std::vector<double> force = testing::read_dataset(h5, "wall_force"),
                            torque = testing::read_dataset(h5, "wall_torque"),
                            power = testing::read_dataset(h5, "wall_power");
  hsize_t rows = 0;
  for (std::string line; std::getline(csv, line); ++rows) {
    INFO(line);
    const std::vector<std::string> cell = split(line, ',');
    REQUIRE(cell.size() == 1 + 4 * walls);
    CHECK(std::stod(cell[0]) == time[rows]);
    for (hsize_t w = 0; w < walls; ++w) {
      CHECK(std::stod(cell[1 + 4 * w]) == force[3 * (rows * walls + w)]);
      CHECK(std::stod(cell[2 + 4 * w]) == force[3 * (rows * walls + w) + 1]);
      CHECK(std::stod(cell[3 + 4 * w]) == torque[rows * walls + w]);
      CHECK(std::stod(cell[4 + 4 * w]) == power[rows * walls + w]);
    }
  }
  CHECK(rows == frames);
  // units.csv gives each array that result.xdmf shows the unit of the dataset it reads.
  std::ifstream units(dir / "units.csv");
  REQUIRE(std::getline(units, header));
  CHECK(header == "array,series,centre,unit,dataset");
  std::vector<std::string> arrays;
  for (std::string line; std::getline(units, line);) {
    INFO(line);
    const std::vector<std::string> cell = split(line, ',');
    REQUIRE(cell.size() == 5);
    CHECK(text_attribute(h5, cell[4].c_str(), "units") == cell[3]);
    arrays.push_back(cell[1] + "/" + cell[0]);
  }
  for (const char* a : {"particles/Points", "particles/radius", "particles/velocity", "particles/angle",
                        "particles/angular_velocity", "particles/id", "walls/Points", "walls/wall", "walls/wall_force",
                        "walls/wall_torque", "walls/wall_power", "both/time"})
    CHECK(std::count(arrays.begin(), arrays.end(), a) == 1);
  CHECK(arrays.size() == 12);  // no temperature: not a thermal scene
  fs::remove_all(dir);
}

TEST_CASE("wall_loads.csv names each wall's columns so that ParaView's CSV reader keeps them apart",
          "[outputs]") {
  // ParaView 5.11 reads no doubled quote back (a name 'say "hi"' lost its text), a line break
  // ends a row, and of two columns of one name it keeps the first: quotes become ', control
  // characters spaces, a repeated name its wall's index; commas and non-ASCII text stay.
  const fs::path dir = testing::fresh_dir("csv_names");
  run_scene(load_scene(testing::case_path("t1_free_fall.yaml"),
                       {"t_end=0.002", "walls=[{name: 'say \"hi\"', material: wall, segment: [[0, 0], [0.05, 0]]},"
                                        "{name: \"say 'hi'\", material: wall, segment: [[0, 0.04], [0.05, 0.04]]},"
                                        "{name: \"a, b\\nW\u00e4nde\", material: wall, segment: [[0, 0], [0, 0.04]]}]"}),
            {dir.string(), true});
  std::ifstream csv(dir / "wall_loads.csv");
  std::string header;
  REQUIRE(std::getline(csv, header));
  CHECK(header ==
        "\"time (s)\",\"say 'hi' force_x (N)\",\"say 'hi' force_y (N)\",\"say 'hi' torque (N m)\",\"say 'hi' power (W)\","
        "\"say 'hi' #1 force_x (N)\",\"say 'hi' #1 force_y (N)\",\"say 'hi' #1 torque (N m)\",\"say 'hi' #1 power (W)\","
        "\"a, b W\u00e4nde force_x (N)\",\"a, b W\u00e4nde force_y (N)\",\"a, b W\u00e4nde torque (N m)\","
        "\"a, b W\u00e4nde power (W)\"");
  fs::remove_all(dir);
}

TEST_CASE("a scene whose walls do not move writes wall_segments once", "[outputs]") {
  const fs::path dir = testing::fresh_dir("fixed_walls");
  run_pusher(dir, false);
  const fs::path h5 = dir / "result.h5";
  const Scene scene = parse_scene(pusher_scene(false), "pusher.yaml");
  const hsize_t frames = dims_of(h5, "time").at(0);
  REQUIRE(frames == 11);
  CHECK(dims_of(h5, "wall_segments") == std::vector<hsize_t>{3, 4});
  CHECK(text_attribute(h5, "wall_segments", "units") == "m");
  const std::vector<double> seg = testing::read_dataset(h5, "wall_segments");
  REQUIRE(seg.size() == 12);
  for (size_t s = 0; s < 3; ++s) {
    const Segment& g = scene.segments[s];
    CHECK(std::vector<double>(seg.begin() + 4 * s, seg.begin() + 4 * s + 4) ==
          std::vector<double>{g.a.x, g.a.y, g.b.x, g.b.y});
  }
  CHECK(read_ints(h5, "wall_of_segment") == std::vector<int>{0, 1, 2});
  CHECK(wall_names_of(h5) == std::vector<std::string>{"floor", "ceiling", "pusher"});
  CHECK(dims_of(h5, "wall_force") == std::vector<hsize_t>{frames, 3, 3});  // loads are frames all the same
  fs::remove_all(dir);
}

TEST_CASE("a resumed run cuts and extends every dataset of frames alike", "[outputs][checkpoint]") {
  const fs::path dir = testing::fresh_dir("resumed_walls"), whole = testing::fresh_dir("resumed_walls_whole");
  // Ending off the frame grid, the run's last frame (t = 0.055) follows its last checkpoint: the
  // resumed run drops it from every dataset of frames and goes on from t = 0.05.
  run_pusher(dir, true, {"t_end=0.055"});
  REQUIRE(dims_of(dir / "result.h5", "time").at(0) == 7);
  const Snapshot checkpoint = Snapshot::read((dir / "checkpoint.h5").string());
  REQUIRE(checkpoint.integer("frames") == 6);
  RunOptions o;
  o.out_dir = dir.string();
  o.quiet = true;
  o.resume = &checkpoint;
  run_scene(scene_of_checkpoint(checkpoint, {assignment("t_end", 0.1)}, o.source), o);
  run_pusher(whole, true);
  const fs::path h5 = dir / "result.h5";
  const hsize_t frames = dims_of(h5, "time").at(0);
  CHECK(frames == 11);
  std::vector<std::string> of_frames;
  int views = 0;  // /frames/k/<name>: those of frames the first run had were kept, of the others made anew
  for (const std::string& name : datasets_of(whole / "result.h5"))
    if (name.rfind("frames/", 0) == 0) {
      INFO(name);
      ++views;
      CHECK(testing::read_dataset(h5, name.c_str()) == testing::read_dataset(whole / "result.h5", name.c_str()));
    }
  CHECK(views == 11 * 8);  // position, velocity, angle, angular_velocity, wall_segments and the three loads
  CHECK(datasets_of(h5).size() == datasets_of(whole / "result.h5").size());
  for (const std::string& name : datasets_of(h5))
    if (!constant_dataset(h5, name) && name.rfind("frames/", 0) != 0) {
      INFO(name);
      of_frames.push_back(name);
      CHECK(dims_of(h5, name).at(0) == frames);
      CHECK(dims_of(h5, name) == dims_of(whole / "result.h5", name));
      CHECK(testing::read_dataset(h5, name.c_str()) == testing::read_dataset(whole / "result.h5", name.c_str()));
    }
  for (const char* name : {"time", "position", "velocity", "wall_segments", "wall_force", "wall_torque", "wall_power"})
    CHECK(std::find(of_frames.begin(), of_frames.end(), name) != of_frames.end());
  fs::remove_all(dir);
  fs::remove_all(whole);
}

TEST_CASE("reopening result.h5 to resume cuts every dataset of frames to the checkpoint's frames", "[outputs]") {
  const fs::path dir = testing::fresh_dir("reopen");
  fs::create_directories(dir);
  const fs::path file = dir / "result.h5";
  ResultLayout layout;
  layout.particles = 2;
  layout.thermal = true;
  layout.walls = 2;
  layout.segments = 3;
  layout.walls_move = true;
  const std::vector<double> two(2, 1.0), four(4, 1.0), twelve(12, 1.0);
  H5Frame f;
  f[FrameField::position] = f[FrameField::velocity] = four.data();
  f[FrameField::temperature] = two.data();
  f[FrameField::wall_segments] = twelve.data();
  f[FrameField::wall_force] = twelve.data();
  f[FrameField::wall_torque] = f[FrameField::wall_power] = two.data();
  {
    H5Frames h5(file.string(), layout);
    h5.write_constant({0.1, 0.2});
    h5.write_walls({0, 0, 1}, {"left", "right"}, nullptr);
    for (int k = 0; k < 5; ++k) {
      f.t = k;
      h5.append(f);
    }
    h5.write_frame_views();
    h5.close();
  }
  const std::vector<std::string> names = datasets_of(file);
  // 10 of frames, radius, id, wall_of_segment, wall_connectivity; the 9 views of each of 5 frames
  CHECK(names.size() == 14 + 5 * 9);
  // Issue 28's review: a checkpoint whose frame count disagrees with its time (3 frames at t = 4 s
  // here, or at 1.5 s) would cut finished frames or keep later ones: refused, nothing cut.
  CHECK_THROWS_WITH(H5Frames(file.string(), layout, 3, 3.5),
                    Catch::Contains("counts 3 frames, but this file's frame 3 is at t = 3 s"));
  CHECK_THROWS_WITH(H5Frames(file.string(), layout, 3, 1.5),
                    Catch::Contains("counts 3 frames, but this file's frame 2 is at t = 2 s"));
  {
    H5Frames h5(file.string(), layout, 3, 2.5);
    CHECK(h5.times() == std::vector<double>{0, 1, 2});
    h5.close();
  }
  CHECK(datasets_of(file).size() == 14 + 3 * 9);  // the views of the frames after the checkpoint are gone
  int of_frames = 0;
  for (const std::string& name : names)
    if (!constant_dataset(file, name) && name.rfind("frames/", 0) != 0) {
      INFO(name);
      ++of_frames;
      CHECK(dims_of(file, name).at(0) == 3);
    }
  CHECK(of_frames == 10);
  // A result without the datasets this run writes (an older kiln's, another scene's) is refused.
  layout.walls = 3;
  CHECK_THROWS_AS(H5Frames(file.string(), layout, 3, 2.5), InputError);
  fs::remove_all(dir);
}

namespace {

// What result.xdmf describes, as python3's XML parser reads it: one line per frame of each series
// (time|series|k|value), grid (grid|series|topology|elements|nodes per element|geometry type) and
// data item (hdf|k|file:/name|dims: a whole dataset, never a HyperSlab, which ParaView's Xdmf3
// readers cannot type).
const char* xdmf_reader = R"(import sys, xml.etree.ElementTree as ET
root = ET.parse(sys.argv[1]).getroot()
assert root.tag == 'Xdmf'
for series in root.find('Domain').findall('Grid'):
    assert series.get('CollectionType') == 'Temporal' and series.get('Name') in ('particles', 'walls')
    for k, grid in enumerate(series.findall('Grid')):
        assert grid.get('GridType') == 'Uniform' and grid.get('Name') == series.get('Name')
        print('time|%s|%d|%s' % (series.get('Name'), k, grid.find('Time').get('Value')))
        top, geo = grid.find('Topology'), grid.find('Geometry')
        print('grid|%s|%s|%s|%s|%s' % (grid.get('Name'), top.get('TopologyType'), top.get('NumberOfElements'),
                                       top.get('NodesPerElement'), geo.get('GeometryType')))
        for node in [top, geo] + grid.findall('Attribute'):
            for d in node.findall('DataItem'):
                assert d.get('ItemType') is None and d.get('Format') == 'HDF'
                print('hdf|%d|%s|%s' % (k, d.text.strip(), d.get('Dimensions')))
)";

std::vector<hsize_t> numbers(const std::string& text) {
  std::vector<hsize_t> v;
  std::istringstream in(text);
  for (hsize_t x; in >> x;) v.push_back(x);
  return v;
}

// Checks that dir/result.xdmf parses and that everything it refers to is in dir/result.h5 with
// the dimensions it states (frame k's items in /frames/k); returns the number of frames of the
// walls series.
int check_xdmf(const fs::path& dir) {
  const fs::path script = dir / "read_xdmf.py", listing = dir / "xdmf.txt", h5 = dir / "result.h5";
  std::ofstream(script) << xdmf_reader;
  const std::string cmd = "python3 " + script.string() + " " + (dir / "result.xdmf").string() + " > " + listing.string();
  REQUIRE(std::system(cmd.c_str()) == 0);
  std::ifstream in(listing);
  const std::vector<double> time = testing::read_dataset(h5, "time");
  std::map<std::string, size_t> frames;  // of each series
  for (std::string line; std::getline(in, line);) {
    INFO(line);
    const std::vector<std::string> f = split(line, '|');
    REQUIRE(!f.empty());
    if (f[0] == "time") {
      REQUIRE(f.size() == 4);
      const size_t k = frames[f[1]]++;
      CHECK(std::stoul(f[2]) == k);
      REQUIRE(k < time.size());
      CHECK(std::stod(f[3]) == time[k]);
    } else if (f[0] == "grid") {
      REQUIRE(f.size() == 6);
      const hsize_t elements = std::stoull(f[3]);
      if (f[1] == "particles") {
        CHECK(f[2] == "Polyvertex");
        CHECK(f[5] == "XYZ");
        CHECK(elements == dims_of(h5, "radius").at(0));
      } else {
        CHECK(f[2] == "Polyline");
        CHECK(f[4] == "2");
        CHECK(f[5] == "XY");
        CHECK(elements == dims_of(h5, "wall_of_segment").at(0));
      }
    } else {
      REQUIRE(f[0] == "hdf");
      REQUIRE(f.size() == 4);
      REQUIRE(f[2].rfind("result.h5:/", 0) == 0);
      const std::string name = f[2].substr(11);
      if (name.rfind("frames/", 0) == 0) CHECK(name.rfind("frames/" + f[1] + "/", 0) == 0);  // its own frame
      CHECK(dims_of(h5, name) == numbers(f[3]));
    }
  }
  CHECK(frames["particles"] == time.size());
  return static_cast<int>(frames["walls"]);
}

}  // namespace

TEST_CASE("result.xdmf parses and refers to datasets of result.h5 with their dimensions", "[outputs]") {
  SECTION("a translating wall: the walls grid reads a frame of wall_segments") {
    const fs::path dir = testing::fresh_dir("xdmf_moving");
    run_pusher(dir, true);
    CHECK(check_xdmf(dir) == 11);
    std::ifstream in(dir / "result.xdmf");
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    CHECK(text.find("result.h5:/frames/10/wall_segments") != std::string::npos);  // the last frame's
    fs::remove_all(dir);
  }
  SECTION("fixed walls: the walls grid reads the constant wall_segments") {
    const fs::path dir = testing::fresh_dir("xdmf_fixed");
    run_pusher(dir, false);
    CHECK(check_xdmf(dir) == 11);
    fs::remove_all(dir);
  }
  SECTION("a thermal scene") {
    const fs::path dir = testing::fresh_dir("xdmf_thermal");
    run_scene(load_scene(testing::case_path("t4_two_particle_conduction.yaml"), {"t_end=0.01"}), {dir.string(), true});
    check_xdmf(dir);
    std::ifstream in(dir / "result.xdmf");
    const std::string text{std::istreambuf_iterator<char>(in), std::istreambuf_iterator<char>()};
    CHECK(text.find("result.h5:/frames/0/temperature") != std::string::npos);
    fs::remove_all(dir);
  }
}

TEST_CASE("picture.png draws a translating wall where it is at the end of the run, not where it started",
          "[outputs]") {
  const fs::path dir = testing::fresh_dir("picture_walls");
  run_pusher(dir, true);
  // The pusher starts at x = 0.02 and ends at x = 0.08; the disc stays at rest at (0.05, 0.095).
  PictureInput drawn;
  drawn.centre = {{0.05, 0.095}};
  drawn.radius = {0.002};
  drawn.wall_a = {{0, 0}, {0, 0.1}, {0.08, 0.02}};
  drawn.wall_b = {{0.1, 0}, {0.1, 0.1}, {0.08, 0.08}};
  const PictureView view = picture_view(drawn);
  cairo_surface_t* png = cairo_image_surface_create_from_png((dir / "picture.png").c_str());
  REQUIRE(cairo_surface_status(png) == CAIRO_STATUS_SUCCESS);
  CHECK(cairo_image_surface_get_width(png) == view.width());
  CHECK(cairo_image_surface_get_height(png) == view.height());
  const unsigned char* data = cairo_image_surface_get_data(png);
  const int stride = cairo_image_surface_get_stride(png);
  // The darkest green value of the pixels around a point (0 black, 255 white).
  auto darkest = [&](Vec2 world) {
    const Vec2 p = view.pixel(world);
    int least = 255;
    for (int dy = -1; dy <= 1; ++dy)
      for (int dx = -1; dx <= 1; ++dx) {
        const int px = static_cast<int>(p.x) + dx, py = static_cast<int>(p.y) + dy;
        const uint32_t pixel = *reinterpret_cast<const uint32_t*>(data + py * stride + 4 * px);
        least = std::min<int>(least, (pixel >> 8) & 0xff);
      }
    return least;
  };
  CHECK(darkest({0.08, 0.05}) < 64);    // the pusher at t = 0.1
  CHECK(darkest({0.02, 0.05}) == 255);  // nothing where it was at t = 0
  CHECK(darkest({0.05, 0.0}) < 64);     // the floor
  cairo_surface_destroy(png);
  fs::remove_all(dir);
}

TEST_CASE("a wall driven along a periodic axis is written and drawn in the cell, however far it has travelled",
          "[outputs][periodic]") {
  const fs::path dir = testing::fresh_dir("driven_periodic");
  // A lid driven at 1 m/s across a 20 mm cell for 0.1 s travels five periods.
  const std::string scene = R"(name: driven
materials:
  glass: {density: 2500, stiffness: 5.0e4, restitution: 0.3}
particles:
  - {material: glass, radius: 0.001, at: [[0.005, 0.001], [0.015, 0.001]]}
walls:
  - {name: floor, material: glass, segment: [[0, 0], [0.02, 0]]}
  - {name: lid, material: glass, segment: [[0.0, 0.01], [0.02, 0.01]], motion: {type: translate, velocity: [1.0, 0]}}
periodic: {x: [0, 0.02]}
gravity: [0, 0]
dt: 1.0e-5
t_end: 0.1
output_interval: 0.01
)";
  run_scene(parse_scene(scene, "driven.yaml"), {dir.string(), true});
  // Each segment is written as 2 pieces (cut where it crosses x = 0 or 0.02), every piece inside
  // the cell and, per frame, the lid's pieces 0.02 long in all (before: one row, shifted by its
  // middle, which left half the lid outside the cell whenever it straddled the edge).
  const std::vector<double> segments = testing::read_dataset(dir / "result.h5", "wall_segments");
  REQUIRE(segments.size() == 11 * 4 * 4);
  CHECK(read_ints(dir / "result.h5", "wall_of_segment") == std::vector<int>{0, 0, 1, 1});
  int straddling = 0;
  for (size_t frame = 0; frame < 11; ++frame) {
    double lid = 0;
    for (size_t row = 0; row < 4; ++row) {
      const double* e = &segments[16 * frame + 4 * row];
      for (const double x : {e[0], e[2]}) {
        CHECK(x >= -1e-15);  // round-off of the shift
        CHECK(x <= 0.02 + 1e-15);
      }
      if (row >= 2) lid += std::hypot(e[2] - e[0], e[3] - e[1]);
      if (row == 3 && e[2] != e[0]) ++straddling;
    }
    CHECK(lid == Approx(0.02).margin(1e-15));
  }
  CHECK(straddling > 0);  // the test sees the lid cut at least once
  fs::remove_all(dir);
}
