// How a wall (all its segments, and the particles attached to it) moves as one rigid body, and
// everything that depends on the kind of motion: where a wall point is at time t, its velocity,
// spin and acceleration, the largest speed and displacement of the wall's points (which the
// neighbour lists and the stability estimate read), and how a scene gives it (read_motion, in
// wall_motion.cpp). Each answer is one switch on the kind, here or in wall_motion.cpp: a new kind
// of motion is its Kind and fields, and its case in each (-Wswitch names a switch that misses it).
#pragma once
#include <optional>
#include <vector>

#include "src/base/vec2.h"

namespace kiln {

struct Segment;

// load_controlled: a body of mass `mass` driven at `velocity` and free along the direction of the
// constant force `load` (perpendicular to it), where the particles push it and a dashpot
// `damping` slows it (Nguyen's shear cell: V along x, the normal load F along -y). Its weight is
// not added: give it in `load`. Its position along the load is part of the state (DemSystem), the
// only motion with a coordinate of its own: what is said here of it is its driven part.
struct WallMotion {
  enum class Kind { fixed, translate, rotate, load_controlled } kind = Kind::fixed;
  Vec2 velocity;        // translate, load_controlled: m/s
  double distance = 0;  // translate: the wall stops after travelling this far (m)
  Vec2 centre;          // rotate: centre of rotation
  double omega = 0;     // rotate: rad/s, counter-clockwise positive
  Vec2 load;            // load_controlled: N
  double mass = 0;      // load_controlled: kg
  double damping = 0;   // load_controlled: N s/m, along the load

  bool moves() const { return kind != Kind::fixed; }
  // Where the point at p0 at t = 0 is at time t, and the velocity of the wall's world point p.
  Vec2 point_at(Vec2 p0, double t) const;
  Vec2 velocity_at(Vec2 p, double t) const;
  // Its angular velocity (rad/s, counter-clockwise positive), which turns rolling springs and
  // attached particles. Inlined: every wall contact asks.
  double spin() const {
    switch (kind) {
      case Kind::fixed:
      case Kind::translate:
      case Kind::load_controlled:
        return 0;
      case Kind::rotate:
        return omega;
    }
    return 0;
  }
  // The acceleration of its world point p at time t (a turning wall's centripetal one).
  Vec2 acceleration_at(Vec2 p, double t) const;
  // The centre it turns about, if it turns.
  std::optional<Vec2> centre_of_rotation() const;
  // Whether its velocity jumps (a translation stopping after its distance): particles cannot follow it.
  bool velocity_jumps() const;
  // The largest speed any point of wall `wall`'s segments reaches during the run (m/s).
  double largest_speed(const std::vector<Segment>& segments, int wall) const;
  // The largest distance any point of wall `wall`'s segments can have moved between t0 and t1 (m).
  double max_displacement(const std::vector<Segment>& segments, int wall, double t0, double t1) const;

  // A wall body (the load-controlled wall) free along its load: whether it is one, a coordinate s
  // along the load as a displacement, a force's component along the load, and the body's
  // acceleration m s'' = (F_particles + F_load) . e - c s', e the load's direction.
  bool free_along_load() const { return kind == Kind::load_controlled; }
  Vec2 along_load(double s) const { return (s / norm(load)) * load; }
  double component_along_load(Vec2 f) const { return dot(f, (1 / norm(load)) * load); }
  double body_acceleration(Vec2 particles_force, double speed) const {
    const double along = component_along_load(particles_force) + norm(load);
    return (along - damping * speed) / mass;
  }
};

}  // namespace kiln
