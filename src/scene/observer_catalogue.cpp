#include "src/scene/observer_catalogue.h"

#include <cmath>
#include <utility>

#include "src/scene/scene.h"
#include "src/scene/scene_features.h"

namespace kiln {

bool ObserverKey::written_in(const Scene& scene) const { return !thermal_only || scene.thermal; }

namespace {

using Kind = ObserverKey::Kind;

ObserverKey key(Kind kind, std::string path, std::string unit, std::string meaning) {
  ObserverKey k;
  k.path = std::move(path);
  k.kind = kind;
  k.unit = std::move(unit);
  k.meaning = std::move(meaning);
  return k;
}
ObserverKey number(std::string path, std::string unit, std::string meaning) {
  return key(Kind::number, std::move(path), std::move(unit), std::move(meaning));
}
ObserverKey headline(std::string path, std::string unit, std::string meaning) {
  ObserverKey k = number(std::move(path), std::move(unit), std::move(meaning));
  k.headline = true;
  return k;
}
ObserverKey list(std::string path, std::string unit, std::string meaning, std::string against = "") {
  ObserverKey k = key(Kind::list, std::move(path), std::move(unit), std::move(meaning));
  k.against = std::move(against);
  return k;
}
ObserverKey text(std::string path, std::string meaning) { return key(Kind::text, std::move(path), "", std::move(meaning)); }
ObserverKey thermal(ObserverKey k) {
  k.thermal_only = true;
  return k;
}

std::string needs_nothing(const Scene&) { return ""; }
std::string needs_heat(const Scene& scene) { return scene.thermal ? "" : "a thermal scene"; }
std::string needs_walls(const Scene& scene) { return scene.walls.empty() ? "walls" : ""; }
std::string needs_species(const Scene& scene) {
  return particle_materials(scene).size() >= 2 ? "" : "particles of two materials (the species)";
}
std::string needs_orifice(const Scene& scene) {
  return std::isnan(find_orifice(scene.segments).width)
             ? "a floor with an orifice (a gap between wall segments at the lowest wall height)"
             : "";
}
std::string needs_driven_wall(const Scene& scene) {
  return driven_wall(scene) >= 0 ? "" : "a load-controlled wall (the driven wall of the shear cell)";
}

std::vector<ObserverKey> bounce_keys() {
  return {number("release_height", "m", "particle 0's height along -g at the start"),
          list("bounce_heights", "m", "particle 0's apex height after each bounce (from its first free flight)"),
          list("contact_durations", "s", "the length of each contact of particle 0 with a wall")};
}

std::vector<ObserverKey> discharge_keys() {
  const std::string t = "discharge_history.time";
  return {headline("discharge_rate", "kg/s", "steady discharge rate: the slope of the discharged mass over the steady window"),
          number("discharge_rate_error", "kg/s", "its standard error, from the rates of 8 blocks of the window"),
          number("discharge_rate_count", "1/s", "discs discharged per second over the steady window"),
          list("discharge_window", "s", "the steady window's first and last sample"),
          number("bulk_density", "kg/m^2", "mass per unit area of the discs at rest in the bin's bottom corners"),
          number("bed_packing_fraction", "1", "their area per unit area"),
          number("mean_diameter", "m", "the discs' mean diameter d"),
          number("orifice_width", "m", "the orifice's width D"),
          number("discharge_plane", "m", "the height of the floor's plane"),
          number("discharged_mass", "kg", "net mass passed down through the floor's plane"),
          number("discharged_count", "1", "net passes of discs down through the floor's plane"),
          list(t, "s", "sample times (every output interval)"),
          list("discharge_history.discharged_mass", "kg", "discharged mass", t),
          list("discharge_history.discharged_count", "1", "discharged discs", t),
          list("discharge_history.bulk_density", "kg/m^2", "bulk density in the bin's bottom corners", t)};
}

std::vector<ObserverKey> heap_keys() {
  return {headline("heap_angle_deg", "deg", "angle of repose: the mean of the two flanks' angles"),
          number("heap_angle_left_deg", "deg", "the left flank's angle"),
          number("heap_angle_right_deg", "deg", "the right flank's angle"),
          headline("packing_fraction", "1", "share of a window under the summit covered by discs")};
}

std::vector<ObserverKey> incline_keys() {
  return {headline("incline_acceleration", "m/s^2", "particle 0's acceleration along x over the run's second half"),
          headline("slip_ratio", "1", "1 + omega r / vx at the end: 0 rolling without slip, 1 sliding without spin")};
}

std::vector<ObserverKey> mixing_keys() {
  const std::string t = "mixing_history.time";
  return {headline("mixing_index", "1", "Lacey's mixing index at the end: 0 segregated, 1 random"),
          list(t, "s", "sample times (every output interval, and the end)"),
          list("mixing_history.lacey_index", "1", "Lacey's mixing index", t),
          list("mixing_history.bed_tilt_deg", "deg", "tilt of the bed's long axis", t),
          number("mixing_history.lacey_cell", "m", "width of the square cells of the index"),
          thermal(list("mixing_history.temperature_std", "C", "standard deviation of the temperatures", t)),
          list("bed_centre", "m", "the bed's centre of mass at the end, [x, y]"),
          headline("bed_tilt_deg", "deg", "tilt of the bed's long axis at the end, positive rising to the right"),
          number("dynamic_angle_of_repose_deg", "deg", "the mean tilt over the run's second half")};
}

std::vector<ObserverKey> shear_keys() {
  const std::string eta = "shear_profile.eta";
  return {list("shear_profile.window", "s", "first and last time of the averaging window (the run's second half)"),
          list(eta, "1", "relative height of each layer's centre across the gap"),
          list("shear_profile.velocity", "m/s", "mean velocity along the drive", eta),
          list("shear_profile.velocity_over_wall", "1", "mean velocity along the drive over the wall's", eta),
          number("shear_profile.wall_speed", "m/s", "the driven wall's speed V"),
          number("shear_profile.gap", "m", "mean gap H between the bed's bottom and the driven wall"),
          thermal(list("shear_profile.heat_power", "W", "heat gained by the particles of each layer per second", eta)),
          thermal(list("shear_profile.heat_share", "1", "each layer's share of the heat", eta)),
          thermal(number("shear_profile.heat_total", "J", "heat gained by the particles over the window")),
          number("shear_stress", "N/m", "mean shear force on the driven wall per unit cell length"),
          number("normal_stress", "N/m", "mean normal force on the driven wall per unit cell length"),
          headline("effective_friction", "1", "shear stress over normal stress"),
          number("shear_rate", "1/s", "V / H"),
          headline("inertial_number", "1", "I = shear rate x mean diameter x sqrt(density / normal stress)")};
}

std::vector<ObserverKey> temperature_keys() {
  return {list("temperatures", "C", "every particle's temperature at the end"),
          headline("temperature_mean", "C", "mean temperature"),
          headline("temperature_std", "C", "standard deviation of the temperatures"),
          headline("temperature_min", "C", "lowest temperature"),
          headline("temperature_max", "C", "highest temperature"),
          headline("heat_content", "J", "sum of heat capacity x temperature"),
          number("temperature_mean_left", "C", "mean temperature of the particles left of x = 0"),
          number("temperature_mean_right", "C", "mean temperature of the particles right of x = 0"),
          number("temperature_fit.slope", "C/m", "slope A of the least-squares line T = A x + B"),
          number("temperature_fit.intercept", "C", "its intercept B"),
          number("temperature_fit.rms_residual", "C", "its rms residual")};
}

std::vector<ObserverKey> temperature_profile_keys() {
  const std::string eta = "temperature_profile.eta";
  return {list(eta, "1", "relative height of each layer (one mean diameter thick) that holds discs"),
          list("temperature_profile.temperature", "C", "mean temperature of the layer", eta),
          number("temperature_profile.bed_height", "m", "height of the bed, lowest underside to highest top")};
}

std::vector<ObserverKey> impact_keys() {
  return {text("wall_impacts.name", "the wall's name"),
          list("wall_impacts.impacts", "1", "impacts on each wall"),
          list("wall_impacts.total_energy", "J", "their total energy m u_n^2 / 2, per wall"),
          list("wall_impacts.mean_energy", "J", "their mean energy, per wall"),
          list("wall_impacts.largest_energy", "J", "the largest impact's energy, per wall")};
}

}  // namespace

const std::vector<ObserverEntry>& observer_catalogue() {
  static const std::vector<ObserverEntry> catalogue = {
      {"bounce_heights", needs_nothing, bounce_keys()},
      {"discharge", needs_orifice, discharge_keys()},
      {"heap", needs_nothing, heap_keys()},
      {"incline_motion", needs_nothing, incline_keys()},
      {"mixing", needs_nothing, mixing_keys()},
      {"species_mixing", needs_species, mixing_keys()},
      {"shear_profile", needs_driven_wall, shear_keys()},
      {"temperatures", needs_heat, temperature_keys()},
      {"temperature_profile", needs_heat, temperature_profile_keys()},
      {"wall_impacts", needs_walls, impact_keys()},
  };
  return catalogue;
}

std::vector<std::string> observer_names() {
  std::vector<std::string> names;
  for (const ObserverEntry& e : observer_catalogue()) names.push_back(e.name);
  return names;
}

const ObserverEntry* find_observer(const std::string& name) {
  for (const ObserverEntry& e : observer_catalogue())
    if (e.name == name) return &e;
  return nullptr;
}

}  // namespace kiln
