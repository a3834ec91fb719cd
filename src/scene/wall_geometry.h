// Walls as straight segments: flattening of boxes, polylines, circles and arcs, and a disc's
// contact with a segment. How walls move is src/scene/wall_motion.h.
#pragma once
#include <algorithm>
#include <cmath>
#include <vector>

#include "src/scene/scene.h"

namespace kiln {

// Appends the segments of an open or closed polyline to `out`, linking neighbours so that a
// shared vertex belongs to exactly one segment.
void add_polyline(std::vector<Segment>& out, const std::vector<Vec2>& points, bool closed, int wall);

// Points of a circular arc from angle `from` to `to` (radians, counter-clockwise) whose chords
// deviate from the true arc by at most `tolerance` (sagitta R (1 - cos(dphi/2)) <= tolerance).
std::vector<Vec2> arc_points(Vec2 centre, double radius, double from, double to, double tolerance);

// Distance from point p to the segment from a to b (its end points included).
inline double distance_to_segment(Vec2 p, Vec2 a, Vec2 b) {
  const Vec2 ab = b - a;
  const double len2 = dot(ab, ab);
  const double s = len2 > 0 ? std::clamp(dot(p - a, ab) / len2, 0.0, 1.0) : 0.0;
  return norm(p - (a + s * ab));
}

// Contact of a disc (centre c, radius r) with segment `s` whose current endpoints are a[s], b[s].
// A vertex shared by two segments belongs to one of them: the later segment (its end a), and only
// when the disc lies beyond the neighbour's face too; otherwise the neighbour's face carries the
// contact. So a disc resting on a polyline joint feels one force, not two [thesis Annex A:
// segment walls with their end points]. Returns false when this segment carries no contact; with
// `apart_too`, a disc clear of the face still gets its hit (negative overlap), for contact events.
struct WallHit {
  Vec2 closest;      // contact point on the wall
  Vec2 normal;       // unit, from the disc centre towards the wall
  double overlap = 0;
};
inline bool disc_segment_contact(const std::vector<Segment>& segments, const std::vector<Vec2>& a,
                          const std::vector<Vec2>& b, int s, Vec2 c, double r, WallHit& hit,
                          bool apart_too = false) {
  const Segment& seg = segments[s];
  const Vec2 ab = b[s] - a[s];
  const double along = dot(c - a[s], ab) / dot(ab, ab);
  if (along >= 1 && seg.next_shared) return false;  // the vertex itself belongs to the next segment
  if (along < 0 && seg.prev >= 0 && dot(c - a[s], b[seg.prev] - a[seg.prev]) < 0) return false;
  hit.closest = a[s] + std::clamp(along, 0.0, 1.0) * ab;
  const Vec2 d = hit.closest - c;
  const double dist2 = dot(d, d);
  if (dist2 >= r * r && !apart_too) return false;
  const double dist = std::sqrt(dist2);
  hit.normal = (1 / dist) * d;
  hit.overlap = r - dist;
  return true;
}

}  // namespace kiln
