// The start state's contacts: no centre on another or on a wall, no overlap unless allowed.
#include "src/scene/scene_parts.h"

#include <algorithm>
#include <sstream>
#include "src/geometry/broadphase.h"
#include "src/scene/wall_geometry.h"

namespace kiln::scene_parts {

// Initial contacts. A centre on a wall or on another centre is always an error: the contact normal
// runs from the one to the other and is undefined there. Other overlaps are errors unless
// allow_overlap.
void check_initial_contacts(const SceneNode& root, const Scene& scene, const ParticleSets& sets) {
  const bool overlap_allowed = root.has("allow_overlap") && root["allow_overlap"].boolean();
  std::vector<double> x, y;
  for (Vec2 p : scene.position) {
    x.push_back(p.x);
    y.push_back(p.y);
  }
  const double rmin = *std::min_element(scene.radius.begin(), scene.radius.end());
  Broadphase bp(1e-3 * rmin);
  std::vector<CandidatePair> pairs;
  bp.particle_pairs(x.data(), y.data(), scene.radius.data(), scene.n_particles(), scene.periodic, pairs);
  auto part_of_a_wall = [&](int i) { return !scene.attached.empty() && scene.attached[i] != Scene::free_particle; };
  for (const CandidatePair& p : pairs) {
    if (part_of_a_wall(p.i) && part_of_a_wall(p.j)) continue;  // walls do not touch walls
    const Location& at = sets.location[sets.of[p.j]];
    const Vec2 d = scene.position[p.j] - scene.position[p.i];
    const double distance = norm(scene.periodic.minimum_image(d.x, d.y));
    if (distance == 0)
      throw InputError(at, sets.describe(p.i) + " and " + sets.describe(p.j) +
                               " share a centre: their contact normal is undefined, even with allow_overlap");
    const double overlap = scene.radius[p.i] + scene.radius[p.j] - distance;
    if (overlap > 0 && !overlap_allowed) {
      std::ostringstream msg;
      msg << "particles " << p.i << " and " << p.j << " overlap by " << overlap << " m at the start (sets "
          << sets.location[sets.of[p.i]].key << " and " << at.key << "); move them apart or set allow_overlap: true";
      throw InputError(at, msg.str());
    }
  }
  std::vector<Vec2> a, b;
  for (const Segment& s : scene.segments) {
    a.push_back(s.a);
    b.push_back(s.b);
  }
  bp.wall_pairs(x.data(), y.data(), scene.radius.data(), scene.n_particles(), a, b, scene.periodic, pairs);
  for (const CandidatePair& p : pairs) {
    const Segment& s = scene.segments[p.j];
    const std::string wall = "wall '" + scene.walls[s.wall].name + "' (walls." + std::to_string(s.wall) + ")";
    const Location& at = sets.location[sets.of[p.i]];
    const double distance = distance_to_segment(scene.periodic.image_near(scene.position[p.i], 0.5 * (s.a + s.b)), s.a, s.b);
    if (distance == 0)
      throw InputError(at, sets.describe(p.i) + " has its centre on " + wall +
                               ": the contact normal is undefined, even with allow_overlap; move it off the wall");
    if (distance < scene.radius[p.i] && !overlap_allowed) {
      std::ostringstream msg;
      msg << sets.describe(p.i) << " overlaps " << wall << " by " << scene.radius[p.i] - distance
          << " m at the start; move it or set allow_overlap: true";
      throw InputError(at, msg.str());
    }
  }
}

}  // namespace kiln::scene_parts
