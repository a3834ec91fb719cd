// What observers look for in a scene, found one way for both the check that the scene has it
// (the observer catalogue's needs) and the observer that measures it.
#pragma once
#include <cmath>
#include <set>
#include <vector>

#include "src/scene/scene.h"

namespace kiln {

// The floor's plane (the lowest wall vertex) and the orifice in it: the widest gap between the wall
// segments lying in that plane (none: width NaN). The discharge observer's plane and window.
struct Orifice {
  double plane = INFINITY, width = NAN, centre = 0;
};
Orifice find_orifice(const std::vector<Segment>& segments);

// The wall driven under a load (the first load-controlled one), or -1: the shear cell's moving wall.
int driven_wall(const Scene& scene);

// The materials particles are made of (the species), leaving out walls' materials and the particles
// of walls.
std::set<int> particle_materials(const Scene& scene);

}  // namespace kiln
