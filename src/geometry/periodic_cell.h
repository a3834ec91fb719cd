// A periodic cell: along x and/or y the scene repeats with period L = x1 - x0 (y1 - y0).
//
// The state keeps each particle's continuous (unwrapped) position, as LAMMPS keeps image flags:
// the integrators see a smooth state, and everything that compares two positions goes through
// minimum_image(). Positions are wrapped into the cell where a place matters: the neighbour tree,
// wall contacts, outputs and observers.
#pragma once
#include <cmath>

#include "src/base/vec2.h"

namespace kiln {

struct PeriodicCell {
  bool x = false, y = false;
  double x0 = 0, x1 = 0, y0 = 0, y1 = 0;  // m
  bool any() const { return x || y; }
  bool operator==(const PeriodicCell&) const = default;
  double length_x() const { return x1 - x0; }
  double length_y() const { return y1 - y0; }
  // The separation d = p_j - p_i of the nearest images (exact when |d| < 3/2 L along a periodic axis).
  // Within half a period nothing is shifted (nearbyint would give 0): the division and the call
  // are skipped for nearly every pair of the contact loop.
  Vec2 minimum_image(double dx, double dy) const {
    if (x && std::abs(dx) > 0.5 * length_x()) dx -= length_x() * std::nearbyint(dx / length_x());
    if (y && std::abs(dy) > 0.5 * length_y()) dy -= length_y() * std::nearbyint(dy / length_y());
    return {dx, dy};
  }
  // The image of p nearest the point `near`: where p meets a wall segment (near its middle).
  Vec2 image_near(Vec2 p, Vec2 near) const {
    if (!any()) return p;
    const Vec2 d = minimum_image(p.x - near.x, p.y - near.y);
    return {near.x + d.x, near.y + d.y};
  }
  // The image of a point inside the cell, [x0, x1) x [y0, y1) along the periodic axes.
  Vec2 wrap(Vec2 p) const {
    if (x) p.x -= length_x() * std::floor((p.x - x0) / length_x());
    if (y) p.y -= length_y() * std::floor((p.y - y0) / length_y());
    return p;
  }
};

}  // namespace kiln
