// The scene: everything a run needs, fully expanded and validated (particle sets already filled,
// walls already flattened to segments). Built by scene_yaml.cpp; read by the DEM system and outputs.
#pragma once
#include <cmath>
#include <string>
#include <vector>

#include "contact/contact_law.h"
#include "integrators/step_control.h"
#include "src/geometry/periodic_cell.h"
#include "src/base/error.h"
#include "src/base/vec2.h"
#include "src/scene/wall_motion.h"
#include "thermal/conduction_model.h"
#include "thermal/wall_temperature.h"

namespace kiln {

// Physical ranges of lengths (m). A disc below a nanometre is a few atoms, which the contact
// mechanics of continua does not describe. Coordinates stay within 1000 km of the origin: over
// nanometre discs, farther ones would overflow the 64-bit cell indices of the fill grid and the
// float boxes of the neighbour search.
inline constexpr double shortest_length = 1e-9;
inline constexpr double farthest_coordinate = 1e6;
// No grain or wall body moves faster than light (m/s): a bound no physical scene meets, far below
// where a kinetic energy overflows.
inline constexpr double speed_of_light = 299792458;
// Frames (output_interval) and checkpoints (--checkpoint-every) of one run, at most: an interval
// below an ulp of the time never advanced (1e-300 s looped for ever), and a million frames of even
// a small scene are gigabytes.
inline constexpr double max_frames = 1e6;

// Temperatures (degrees Celsius) lie in [absolute_zero, hottest_temperature], wherever they are
// read: particle sets, walls (and their steps and ramps), a particle file's column, --set. Above:
// kiln's laws are those of solid grains (elastic contacts, conduction through the contact spot, a
// solid's heat capacity), and no solid survives past about 4,000 C (tantalum hafnium carbide and
// hafnium carbonitride, the most refractory known, melt between 3,900 and 4,100 C); 1e5 C leaves
// room for walls that stand for hotter bodies (an electric arc's 6,000 to 20,000 C). Beyond it a
// temperature is a slip of digits or units, and soon more than double precision carries: the
// state holds temperatures beside the heat contents m c (T - T0) that the energy ledger sums with
// the motion's energies, so the spacing of doubles at T times a disc's heat capacity must stay far
// below those. At 1e5 C doubles are 1.5e-11 K apart; at 2e19 C, 4096 K, where imex4's Newton
// iteration could not converge and the run failed at t = 0 blaming dt (issue 28's campaign, F9).
inline constexpr double absolute_zero = -273.15;
inline constexpr double hottest_temperature = 1e5;

// Why `t` (written `text`) is no temperature, as words that follow the value in a message ("is
// below absolute zero ..."), naming the valid range; "" when it is one.
inline std::string temperature_refusal(double t, const std::string& text) {
  const std::string range = "temperatures lie in [-273.15, 1e5] C";
  if (!(t >= absolute_zero)) return "is below absolute zero (-273.15 C): " + range;
  if (!(t <= hottest_temperature)) {
    std::string why = "is above 1e5 C: " + range + ". kiln's laws are those of solid grains, and no solid survives "
                      "past about 4,000 C (the most refractory carbides melt there); 1e5 C leaves room for walls "
                      "that stand for hotter bodies";
    // Far beyond, double precision itself gives out: say so where a step's heat can no longer show.
    const double spacing = std::nextafter(t, INFINITY) - t;
    if (spacing >= 1e-3) why += " (at " + text + " C a double resolves only " + message_number(spacing) + " K)";
    return why;
  }
  return "";
}

enum class MassModel { sphere, cylinder };

struct Material {
  std::string name;
  double density = 0;                // kg/m^3; 0 for wall-only materials
  contact::ContactMaterial contact;  // moduli, stiffness, restitution, frictions
  double specific_heat = 0;          // J/(kg K)
  double conductivity = 0;           // W/(m K)
  double electrical_resistivity = 0; // Ohm m, shares frictional heat (0: not given)
};

// The laws of one unordered pair of materials: mechanics (contact/) and heat conduction (thermal/).
struct PairLaw {
  contact::ContactLaw contact;
  thermal::ConductionParams conduction;
};

// What mechanical dissipation becomes heat in the particles.
enum class HeatFromDissipation { none, friction, all };

// One straight wall piece. A particle touching a shared vertex is handled by exactly one of the
// two segments meeting there (disc_segment_contact, src/scene/wall_geometry.h).
struct Segment {
  Vec2 a, b;              // endpoints at t = 0
  int wall = 0;           // index of the wall it came from (motion, material)
  int prev = -1;          // segment whose end b is this segment's a (polyline neighbour), or -1
  bool next_shared = false;  // this segment's b is the next segment's a
};

struct Wall {
  std::string name;
  int material = 0;
  WallMotion motion;
  thermal::WallTemperature temperature;  // adiabatic unless given
};

// Settle, then freeze: once the kinetic energy falls below a threshold (not before `not_before`,
// at the latest at `latest`), positions and contact forces are fixed and only heat is integrated,
// with its own time step, until t_end.
struct FreezeStage {
  bool enabled = false;
  double kinetic_energy_below = 0;
  double not_before = 0;
  double latest = INFINITY;
  double dt = 0;
  Location dt_at;  // where freeze.dt was given, for refusals of the heating's length in steps
  double output_interval = 0;
  std::string integrator;  // of the frozen stage; empty: the scene's
};


struct Scene {
  std::string name;
  std::string file;        // scene file path, for messages and attributes
  std::string description;
  MassModel mass_model = MassModel::sphere;
  double thickness = 0;    // cylinder mass model
  Vec2 gravity{0, -9.81};

  std::vector<Material> materials;
  int n_materials() const { return static_cast<int>(materials.size()); }
  std::vector<PairLaw> laws;  // n_materials^2, symmetric
  const PairLaw& law(int a, int b) const { return laws[a * n_materials() + b]; }

  // Particles (structure of arrays).
  std::vector<Vec2> position, velocity;
  std::vector<double> radius, angular_velocity;
  std::vector<int> material;
  std::vector<double> temperature;  // thermal scenes only
  // Each particle free (-1), fixed in place (-2), or attached to wall w (w >= 0): an attached or
  // fixed particle moves with its wall and takes no forces; what pushes it pushes the wall.
  std::vector<int> attached;
  static constexpr int free_particle = -1, fixed_particle = -2;
  int n_particles() const { return static_cast<int>(radius.size()); }

  // Heat. A scene is thermal when its particles carry temperatures; otherwise no temperature is
  // integrated and nothing about heat is computed.
  bool thermal = false;
  HeatFromDissipation heat_from_dissipation = HeatFromDissipation::none;
  bool frozen = false;  // mechanics frozen from the start: a thermal-only scene
  FreezeStage freeze;

  // Ensembles (studies' --seeds): member k mixes k into every seed the scene declares (fills,
  // lattice jitter, random radii and velocities); 0 is the scene as written. random_sources names
  // the particle sets whose placement or velocities are drawn: none, and every member is the same.
  long long ensemble_member = 0;
  std::vector<std::string> random_sources;

  std::vector<Wall> walls;
  std::vector<Segment> segments;
  PeriodicCell periodic;  // no periodic axis unless given
  // The files the scene read besides itself (SVG drawings, particle files), each as "path<TAB>FNV-1a
  // hash of its bytes": a checkpoint records them, and a restart refuses files changed since.
  std::vector<std::string> inputs;

  // Integration and output.
  std::string integrator = "velocity-verlet";
  StepControl control;  // rtol/atol: adaptive stepping for integrators with an error estimate
  double dt = 0;
  double t_end = 0;
  Location t_end_at;  // where t_end was given (file, line, key), for refusals of the run's length
  Location dt_at;     // where dt was given: the run's length in steps is t_end's and dt's
  double output_interval = 0;
  double skin = 0;                    // neighbour skin (m); 0 = automatic
  double max_overlap_fraction = 0.5;  // instability check: overlap / smaller radius
  double stop_kinetic_energy = 0;     // stop early when kinetic energy falls below (J); 0 = never
  double stop_not_before = 0;         // ... but not before this time
  std::vector<std::string> report;    // case quantities to compute (observer_catalogue.h)
};

// A disc's mass (kg) and moment of inertia (kg m^2) under the scene's mass model: a sphere's,
// m = 4/3 pi r^3 rho and I = 2/5 m r^2, or a cylinder's of the scene's thickness t,
// m = pi r^2 t rho and I = 1/2 m r^2.
inline double disc_mass(const Scene& scene, double r, double density) {
  return scene.mass_model == MassModel::sphere ? 4.0 / 3.0 * M_PI * r * r * r * density
                                               : M_PI * r * r * scene.thickness * density;
}
inline double disc_inertia(const Scene& scene, double m, double r) {
  return (scene.mass_model == MassModel::sphere ? 0.4 : 0.5) * m * r * r;
}

}  // namespace kiln
