#include "src/dem/stage_profile.h"

#include <cstdio>

namespace kiln {

const char* stage_name(Stage s) {
  switch (s) {
    case Stage::neighbour_update: return "neighbour_update";
    case Stage::particle_contacts: return "particle_contacts";
    case Stage::wall_contacts: return "wall_contacts";
    case Stage::conduction: return "conduction";
    case Stage::integration: return "integration";
    case Stage::checks: return "checks";
    case Stage::observers: return "observers";
    case Stage::output: return "output";
    case Stage::count: break;
  }
  return "?";
}

nlohmann::json StageProfile::json(long steps) const {
  nlohmann::json seconds = nlohmann::json::object(), per_step = nlohmann::json::object();
  for (int k = 0; k < static_cast<int>(Stage::count); ++k) {
    const char* name = stage_name(static_cast<Stage>(k));
    seconds[name] = seconds_[k];
    per_step[name] = steps > 0 ? seconds_[k] / steps : 0.0;
  }
  return {{"seconds", seconds}, {"per_step", per_step}, {"steps", steps}};
}

std::string profile_table(const nlohmann::json& profile) {
  double total = 0;
  for (const auto& [name, seconds] : profile["seconds"].items()) total += seconds.get<double>();
  const long steps = profile["steps"].get<long>();
  std::string out = "stage                  seconds   share   per step (s)\n";
  char line[128];
  for (int k = 0; k < static_cast<int>(Stage::count); ++k) {
    const char* name = stage_name(static_cast<Stage>(k));
    const double sec = profile["seconds"].value(name, 0.0);
    std::snprintf(line, sizeof line, "%-20s %9.3f %6.1f %%   %.3e\n", name, sec,
                  total > 0 ? 100 * sec / total : 0.0, steps > 0 ? sec / steps : 0.0);
    out += line;
  }
  std::snprintf(line, sizeof line, "%-20s %9.3f  (%ld steps)\n", "total", total, steps);
  return out + line;
}

}  // namespace kiln
