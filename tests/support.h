// Helpers shared by the tests: build a scene from YAML text and step it directly.
#pragma once
#include <cmath>
#include <fstream>
#include <memory>
#include <sstream>
#include <string>
#include <vector>

#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <hdf5.h>

#include <filesystem>

#include "integrators/integrator.h"
#include "src/dem/dem_system.h"
#include "src/base/error.h"
#include "src/scene/scene_yaml.h"

namespace kiln::testing {

// A scene, its system, its state and an integrator, stepped by hand.
struct Run {
  Scene scene;
  std::unique_ptr<DemSystem> system;
  std::vector<double> y;
  std::unique_ptr<Integrator> integrator;

  explicit Run(const std::string& yaml, const std::vector<std::string>& sets = {})
      : scene(parse_scene(yaml, "test.yaml", sets)) {
    system = std::make_unique<DemSystem>(scene);
    y = system->initial_state();
    integrator = make_integrator(scene.integrator, scene.control);
    integrator->start(*system, 0, y.data(), scene.dt);
  }
  double t() const { return integrator->time(); }
  void step() { integrator->step(); }
  double x(int i) const { return y[system->x_at() + i]; }
  double yy(int i) const { return y[system->y_at() + i]; }
  double vx(int i) const { return y[system->vx_at() + i]; }
  double vy(int i) const { return y[system->vy_at() + i]; }
  double omega(int i) const { return system->rotates() ? y[system->omega_at() + i] : 0.0; }
};

// A disc hitting a floor at 70 degrees from the normal, mu 1, restitution 0.5 (linear), made
// thermal so that friction heat can be checked against the ledger: the disc keeps beta = 1/2.
inline std::string grazing_impact() {
  return R"(name: grazing
mass_model: sphere
gravity: [0, 0]
heat_from_dissipation: friction
conduction_model: none
materials:
  glass: {density: 2500, stiffness: 2.0e4, restitution: 0.5, friction: 1.0, specific_heat: 800, conductivity: 1}
  plate: {stiffness: 2.0e4, restitution: 0.5, friction: 1.0, conductivity: 1}
particles:
  - material: glass
    radius: 0.002
    temperature: 20
    at: [[0.0, 0.00201]]
    velocity: [0.9396926, -0.3420201]
walls:
  - {name: floor, material: plate, segment: [[-0.05, 0.0], [0.05, 0.0]]}
integrator: erk2
dt: 2.5e-7
t_end: 0.002
output_interval: 1.0e-4
)";
}

// A small valid scene: two copper discs above a floor (the base of the bad-input tests).
inline const std::string two_discs_on_a_floor = R"(name: ok
materials:
  copper: {density: 8900, stiffness: 6000, restitution: 0.8}
particles:
  - material: copper
    radius: 0.002
    at: [[0.0, 0.01], [0.01, 0.01]]
walls:
  - {name: floor, material: copper, segment: [[-0.1, 0], [0.1, 0]]}
dt: 1.0e-6
t_end: 0.01
)";

// An empty directory of the system's temporary directory, unique to this test process.
inline std::filesystem::path fresh_dir(const std::string& name) {
  const std::filesystem::path dir =
      std::filesystem::temp_directory_path() / ("kiln_test_" + name + "_" + std::to_string(::getpid()));
  std::filesystem::remove_all(dir);
  return dir;
}

// The message a scene text gives when it cannot be loaded (named bad.yaml), or "" when it loads.
inline std::string error_of(const std::string& text, const std::vector<std::string>& sets = {},
                            uint64_t memory = physical_memory()) {
  try {
    parse_scene(text, "bad.yaml", sets, memory);
  } catch (const InputError& e) {
    return e.what();
  }
  return "";
}

// `text` with the first `from` replaced by `to` (which must be there).
inline std::string replaced(std::string text, const std::string& from, const std::string& to) {
  const size_t at = text.find(from);
  REQUIRE(at != std::string::npos);
  return text.replace(at, from.size(), to);
}

inline std::string case_path(const std::string& name) { return std::string(KILN_CASES_DIR) + "/" + name; }
inline std::string case_text(const std::string& name) {
  std::ifstream in(case_path(name));
  std::stringstream text;
  text << in.rdbuf();
  return text.str();
}

// A whole dataset of result.h5, flattened.
inline std::vector<double> read_dataset(const std::filesystem::path& file, const char* name) {
  const hid_t f = H5Fopen(file.c_str(), H5F_ACC_RDONLY, H5P_DEFAULT);
  if (f < 0) return {};
  const hid_t ds = H5Dopen2(f, name, H5P_DEFAULT);
  const hid_t space = H5Dget_space(ds);
  std::vector<double> data(H5Sget_simple_extent_npoints(space));
  H5Dread(ds, H5T_NATIVE_DOUBLE, H5S_ALL, H5S_ALL, H5P_DEFAULT, data.data());
  H5Sclose(space);
  H5Dclose(ds);
  H5Fclose(f);
  return data;
}

// The Verlet schemes (the catalogue also lists ARKODE methods and aliases).
// 9,000 rough, pressed discs in a cell periodic in x on a floor with friction and rolling
// resistance, moving a little; hot (a hot and a cold half, dashpot and friction heat, conduction)
// or cold. Large enough that every threaded loop runs in parallel and that the contact loop's
// particle order matters (more than 4,096 discs: DemSystem::reorder_slots()).
inline std::string pressed_pile(bool hot) {
  std::ostringstream s;
  s << "name: pressed_pile\nmass_model: sphere\ngravity: [0, -9.81]\nallow_overlap: true\n"
    << (hot ? "heat_from_dissipation: all\n" : "")
    << "materials:\n  grain: {density: 2500, stiffness: 10000, restitution: 0.5, friction: 0.5, "
       "rolling_friction: 0.1" << (hot ? ", specific_heat: 840, conductivity: 2" : "") << "}\n"
    << "particles:\n  - material: grain\n    radius: {uniform: [0.00095, 0.00105]}\n"
    << (hot ? "    temperature: {left: 100, right: 0, x_split: 0.146}\n" : "")
    << "    random_velocity: {max: 0.05, seed: 4}\n"
    << "    lattice: {kind: hexagonal, origin: [0.0005, 0.0012], spacing: 0.00195, rows: 60, columns: 150, "
       "jitter: 0.00002, seed: 3}\n"
    << "periodic: {x: [0, 0.2925]}\n"
    << "walls:\n  - {material: grain, polyline: [[-1, 0], [1.3, 0]]}\n"
    << "integrator: velocity-verlet\ndt: 1.0e-6\nt_end: 1\n";
  return s.str();
}

inline std::vector<std::string> verlet_family() { return {"verlet", "velocity-verlet", "velocity-verlet-predicted"}; }

// Observed order from errors at step sizes h and h/2.
inline double order(double e_coarse, double e_fine) { return std::log(e_coarse / e_fine) / std::log(2.0); }

// The kiln binary run by the shell with `arguments`, its standard output and error into `log`:
// the exit status (-1 when a signal ended it) and what it printed.
struct CommandOutcome {
  int status = -1;
  std::string output;
};
inline CommandOutcome run_kiln_command(const std::string& arguments, const std::filesystem::path& log) {
  const std::string cmd = std::string(KILN_BINARY) + " " + arguments + " > " + log.string() + " 2>&1";
  const int status = std::system(cmd.c_str());
  std::ifstream in(log);
  std::stringstream text;
  text << in.rdbuf();
  return {WIFEXITED(status) ? WEXITSTATUS(status) : -1, text.str()};
}

}  // namespace kiln::testing
