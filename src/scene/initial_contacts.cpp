// The start state's contacts: no centre on another or on a wall, no overlap unless allowed.
#include "src/scene/scene_parts.h"

#include <algorithm>
#include <sstream>
#include "src/geometry/broadphase.h"
#include "src/scene/wall_geometry.h"

namespace kiln::scene_parts {

// Initial contacts. A centre on a wall or on another centre is always an error: the contact normal
// runs from the one to the other and is undefined there. Other overlaps are errors unless
// allow_overlap, and then when deeper than checks.max_overlap_fraction.
void check_initial_contacts(const SceneNode& root, const Scene& scene, const ParticleSets& sets) {
  const bool overlap_allowed = root.has("allow_overlap") && root["allow_overlap"].boolean();
  std::vector<double> x, y;
  for (Vec2 p : scene.position) {
    x.push_back(p.x);
    y.push_back(p.y);
  }
  const double rmin = *std::min_element(scene.radius.begin(), scene.radius.end());
  Broadphase bp(1e-3 * rmin);
  auto part_of_a_wall = [&](int i) { return !scene.attached.empty() && scene.attached[i] != Scene::free_particle; };
  // Streamed, stopping at the first fault: a typo that puts a million discs on one point must be
  // told at once, not after listing its half a trillion pairs. Allowed overlaps are bounded by
  // the run's own overlap check, which would stop the run at its first step.
  // Millions of discs take seconds to a minute (`kiln check` said nothing meanwhile): shown on a
  // terminal.
  Progress progress("checking the start's overlaps", scene.n_particles() < progress_min_items);
  bp.scan_particle_pairs(x.data(), y.data(), scene.radius.data(), scene.n_particles(), scene.periodic, [&](int i, int j) {
    if (part_of_a_wall(i) && part_of_a_wall(j)) return true;  // walls do not touch walls
    const Location& at = sets.location[sets.of[j]];
    const Vec2 d = scene.position[j] - scene.position[i];
    const double distance = norm(scene.periodic.minimum_image(d.x, d.y));
    if (distance == 0)
      throw InputError(at, sets.describe(i) + " and " + sets.describe(j) +
                               " share a centre: their contact normal is undefined, even with allow_overlap");
    const double overlap = scene.radius[i] + scene.radius[j] - distance;
    if (overlap <= 0) return true;
    std::ostringstream msg;
    msg << "particles " << i << " and " << j << " overlap by " << overlap << " m at the start (sets "
        << sets.location[sets.of[i]].key << " and " << at.key << ")";
    if (!overlap_allowed) {
      msg << "; move them apart or set allow_overlap: true";
      throw InputError(at, msg.str());
    }
    const double fraction = overlap / std::min(scene.radius[i], scene.radius[j]);
    if (fraction > scene.max_overlap_fraction) {
      msg << ", " << fraction << " of the smaller radius: more than checks.max_overlap_fraction ("
          << scene.max_overlap_fraction << "), so the run's overlap check would stop it at its first step";
      throw InputError(at, msg.str());
    }
    return true;
  }, &progress);
  progress.finish();
  std::vector<CandidatePair> pairs;
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
    const double overlap = scene.radius[p.i] - distance;
    if (overlap <= 0) continue;
    std::ostringstream msg;
    msg << sets.describe(p.i) << " overlaps " << wall << " by " << overlap << " m at the start";
    if (!overlap_allowed) {
      msg << "; move it or set allow_overlap: true";
      throw InputError(at, msg.str());
    }
    if (overlap / scene.radius[p.i] > scene.max_overlap_fraction) {
      msg << ", " << overlap / scene.radius[p.i] << " of its radius: more than checks.max_overlap_fraction ("
          << scene.max_overlap_fraction << "), so the run's overlap check would stop it at its first step";
      throw InputError(at, msg.str());
    }
  }
}

}  // namespace kiln::scene_parts
