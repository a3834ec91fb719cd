#include "src/scene/scene_features.h"

#include <algorithm>
#include <utility>

namespace kiln {

Orifice find_orifice(const std::vector<Segment>& segments) {
  Orifice o;
  for (const Segment& s : segments) o.plane = std::min({o.plane, s.a.y, s.b.y});
  std::vector<std::pair<double, double>> floor;
  for (const Segment& s : segments)
    if (s.a.y == o.plane && s.b.y == o.plane) floor.push_back(std::minmax(s.a.x, s.b.x));
  std::sort(floor.begin(), floor.end());
  double reach = floor.empty() ? 0 : floor.front().second;
  for (const auto& [lo, hi] : floor) {
    if (lo > reach && (std::isnan(o.width) || lo - reach > o.width)) {
      o.width = lo - reach;
      o.centre = 0.5 * (lo + reach);
    }
    reach = std::max(reach, hi);
  }
  return o;
}

int driven_wall(const Scene& scene) {
  for (size_t w = 0; w < scene.walls.size(); ++w)
    if (scene.walls[w].motion.free_along_load()) return static_cast<int>(w);
  return -1;
}

std::set<int> particle_materials(const Scene& scene) {
  std::set<int> used;
  for (int i = 0; i < scene.n_particles(); ++i)
    if (scene.attached.empty() || scene.attached[i] == Scene::free_particle) used.insert(scene.material[i]);
  return used;
}

}  // namespace kiln
