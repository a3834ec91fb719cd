// The walls (shapes flattened to segments, SVG drawings, temperatures; their motions are
// wall_motion.cpp's), the particles attached to them, and the periodic cell.
#include "src/scene/scene_parts.h"
#include "src/base/text_format.h"

#include <algorithm>
#include <cmath>
#include "src/scene/svg_geometry.h"
#include "src/scene/wall_geometry.h"

namespace kiln::scene_parts {

namespace {

// temperature: T (isothermal), {steps: [[t0, T0], [t1, T1], ...]} (T_k from t_k on), or
// {ramp: [[t0, T0], ...]} (linear between the points, held beyond them).
thermal::WallTemperature read_wall_temperature(const SceneNode& node) {
  thermal::WallTemperature wt;
  if (!node.is_map()) {
    wt.kind = thermal::WallTemperature::Kind::steps;
    wt.times = {0};
    wt.values = {node.temperature()};
    return wt;
  }
  node.allow();
  if (node.has("steps") == node.has("ramp")) node.fail("give one of 'steps' or 'ramp'");
  const bool steps = node.has("steps");
  wt.kind = steps ? thermal::WallTemperature::Kind::steps : thermal::WallTemperature::Kind::ramp;
  const SceneNode list = node[steps ? "steps" : "ramp"];
  for (const SceneNode& point : list.items()) {
    if (!point.is_sequence() || point.items().size() != 2) point.fail("expected a pair [time, temperature]");
    const double time = point.items()[0].number();
    if (!wt.times.empty() && time <= wt.times.back()) point.fail("times must increase");
    wt.times.push_back(time);
    wt.values.push_back(point.items()[1].temperature());
  }
  if (wt.times.empty()) list.fail("expected at least one [time, temperature] point");
  return wt;
}

// A circle or an arc as chords. Its tolerance is at least 1e-9 of its radius: the chords then
// number at most about 70,000 per turn (the sagitta R (1 - cos(dphi/2)) <= tolerance), and an arc
// turns at most once. It is at most half the radius, so that a circle has at least three chords: a
// tolerance of 1e300, or a radius of 1e-9 m under the default one, made chords of zero length,
// refused without naming either (issue 28's review).
std::vector<Vec2> read_arc(const SceneNode& node, double from, double to, double tolerance) {
  node.allow();
  const double radius = length(node["radius"]);
  if (tolerance < 1e-9 * radius)
    node.fail("the tolerance is below 1e-9 of the radius: the chords would be too many to hold");
  if (tolerance > 0.5 * radius)
    node.fail(format("the tolerance (%g m) is above half the radius (%g m): a circle would be fewer than three "
                     "chords; give a smaller tolerance or a larger radius",
                     tolerance, radius));
  return arc_points(point(node["centre"]), radius, from, to, tolerance);
}

void read_wall_shape(const SceneNode& w, int id, double tolerance, std::vector<Segment>& segments) {
  auto points = [](const SceneNode& list) {
    std::vector<Vec2> pts;
    for (const SceneNode& p : list.items()) pts.push_back(point(p));
    return pts;
  };
  if (auto s = w.optional("segment")) {
    const auto pts = points(*s);
    if (pts.size() != 2) s->fail("expected two points [[x0, y0], [x1, y1]]");
    add_polyline(segments, pts, false, id);
  } else if (auto p = w.optional("polyline")) {
    const auto pts = points(*p);
    if (pts.size() < 2) p->fail("expected at least two points");
    add_polyline(segments, pts, w.has("closed") && w["closed"].boolean(), id);
  } else if (auto b = w.optional("box")) {
    const auto v = b->items();
    if (v.size() != 4) b->fail("expected [x0, y0, x1, y1]");
    const Vec2 lo = point_of(v[0], v[1]), hi = point_of(v[2], v[3]);
    if (!(hi.x > lo.x && hi.y > lo.y)) b->fail("expected x1 > x0 and y1 > y0");
    add_polyline(segments, {lo, {hi.x, lo.y}, hi, {lo.x, hi.y}}, true, id);
  } else if (auto c = w.optional("circle")) {
    auto pts = read_arc(*c, 0, 2 * M_PI, tolerance);
    pts.pop_back();  // the last point closes onto the first
    add_polyline(segments, pts, true, id);
  } else {
    const SceneNode arc = w["arc"];
    const double from = arc["from_deg"].number() * M_PI / 180, to = arc["to_deg"].number() * M_PI / 180;
    if (!(to > from)) arc["to_deg"].fail("expected to_deg > from_deg (counter-clockwise)");
    if (to - from > 2 * M_PI) arc["to_deg"].fail("an arc turns at most 360 degrees");
    add_polyline(segments, read_arc(arc, from, to, tolerance), false, id);
  }
}

// svg: {file, scale, offset, tolerance, group}: the drawing's groups as walls (file relative to
// the scene file). Without `group` each group of the drawing becomes a wall named after its id
// (the entry's name, then the id, when it has a name); with it, only that group, named as the entry.
struct DrawnWall {
  std::string name;
  std::vector<SvgPolyline> lines;
};

std::vector<DrawnWall> read_svg_entry(const SceneNode& node, const std::string& scene_file, const std::string& name,
                                      double tolerance, std::vector<std::string>& inputs) {
  node.allow();
  const std::string file = beside_scene(node["file"].text(), scene_file);
  SvgPlacement placement;
  placement.scale = node.has("scale") ? node["scale"].positive() : 1.0;
  placement.offset = node.has("offset") ? point(node["offset"]) : Vec2{};
  placement.tolerance = node.has("tolerance") ? node["tolerance"].positive() : tolerance;
  std::vector<SvgGroup> groups;
  try {
    groups = read_svg_walls(file, placement);
  } catch (const InputError& e) {
    node["file"].fail(e.what());
  }
  inputs.push_back(node["file"].text() + "\t" + file_hash(file));  // as the scene names it
  // Lines outside any named group or layer form the group "drawing".
  auto id_of = [](const SvgGroup& group) { return group.id.empty() ? std::string("drawing") : group.id; };
  std::vector<DrawnWall> walls;
  if (auto g = node.optional("group")) {
    const std::string wanted = g->text();
    std::vector<std::string> ids;
    for (const SvgGroup& group : groups) {
      ids.push_back(id_of(group));
      if (id_of(group) == wanted) walls.push_back({name.empty() ? wanted : name, group.lines});
    }
    if (walls.empty()) g->fail("the drawing has no group '" + wanted + "'; its groups are " + choices_nearest_first(wanted, ids));
    return walls;
  }
  for (const SvgGroup& group : groups) walls.push_back({name.empty() ? id_of(group) : name + "." + id_of(group), group.lines});
  return walls;
}

// Circles, arcs and drawn curves are flattened by default to a hundredth of the smallest particle
// radius: a wall's chords then depart from the curve by less than the overlaps of its contacts
// (an absolute default made a drum of 100 um radius a heptagon).
double default_tolerance(const Scene& scene) {
  return 0.01 * *std::min_element(scene.radius.begin(), scene.radius.end());
}

}  // namespace

void read_walls(const SceneNode& root, Scene& scene, const MaterialIndex& index, MemoryClaim& claim) {
  const auto walls = root.optional("walls");
  if (!walls) return;
  for (const SceneNode& w : walls->items()) {
    w.allow();
    Wall wall;
    wall.material = index.find(w["material"]);
    if (auto m = w.optional("motion")) wall.motion = read_motion(*m);
    if (auto t = w.optional("temperature")) wall.temperature = read_wall_temperature(*t);
    const int shapes = w.has("segment") + w.has("polyline") + w.has("box") + w.has("circle") + w.has("arc") + w.has("svg");
    if (shapes != 1) w.fail("give exactly one shape: segment, polyline, box, circle, arc or svg");
    // Only curves are flattened: on straight shapes a tolerance is not read (and so refused).
    const bool curved = w.has("circle") || w.has("arc") || w.has("svg");
    if (w.has("svg") && w.has("tolerance") && w["svg"].has("tolerance"))
      w["tolerance"].fail("give the tolerance once: here or as svg.tolerance");
    const double tolerance = curved && w.has("tolerance") ? w["tolerance"].positive() : default_tolerance(scene);
    const std::string name = w.has("name") ? w["name"].text() : "";
    std::vector<DrawnWall> drawn;
    if (auto svg = w.optional("svg")) {
      drawn = read_svg_entry(*svg, scene.file, name, tolerance, scene.inputs);
    } else {
      drawn.push_back({name.empty() ? "wall" + std::to_string(scene.walls.size()) : name, {}});
    }
    // One body under one load: a drawing of several groups is several walls, each of which would
    // carry the whole mass and load.
    if (drawn.size() > 1 && wall.motion.free_along_load())
      w["motion"].fail("a load-controlled wall is one body: this drawing has " + std::to_string(drawn.size()) +
                       " groups; pick one with svg.group, or draw the wall as one group");
    for (const DrawnWall& d : drawn) {
      const int id = static_cast<int>(scene.walls.size());
      const size_t before = scene.segments.size();
      if (w.has("svg")) {
        for (const SvgPolyline& line : d.lines) {
          for (Vec2 p : line.points)
            if (!within_reach(p)) w["svg"].fail(std::string("the drawing, scaled and placed, has ") + out_of_reach);
          add_polyline(scene.segments, line.points, line.closed, id);
        }
      } else {
        read_wall_shape(w, id, tolerance, scene.segments);
      }
      claim.add_segments(w, scene.segments.size() - before);
      for (size_t s = before; s < scene.segments.size(); ++s)
        if (norm(scene.segments[s].b - scene.segments[s].a) == 0) w.fail("a wall segment has zero length");
      wall.name = d.name;
      for (const Wall& other : scene.walls)
        if (other.name == wall.name) (w.has("name") ? w["name"] : w).fail("a wall named '" + wall.name + "' exists already");
      scene.walls.push_back(wall);
    }
  }
}

void attach_particles(const std::vector<Attachment>& attachments, Scene& scene) {
  scene.attached.assign(scene.n_particles(), Scene::free_particle);
  for (const Attachment& a : attachments) {
    int to = Scene::fixed_particle;
    if (!a.fixed) {
      const std::string name = a.node.text();
      std::vector<std::string> names;
      to = -3;
      for (size_t w = 0; w < scene.walls.size(); ++w) {
        names.push_back(scene.walls[w].name);
        if (scene.walls[w].name == name) to = static_cast<int>(w);
      }
      if (to == -3) a.node.fail("no wall is named '" + name + "'; the walls are " + choices_nearest_first(name, names));
      if (scene.walls[to].motion.velocity_jumps())
        a.node.fail("particles cannot follow a wall that stops after a distance: their velocity would have to jump");
    }
    std::fill_n(scene.attached.begin() + a.first, a.count, to);
  }
}

// periodic: {x: [x0, x1], y: [y0, y1]}: the cell repeats along each axis given. Every particle
// starts inside it, and a period is at least four of the largest diameters, so that a particle
// meets each neighbour through one image only, with room for the neighbour skin.
void read_periodic(const SceneNode& root, Scene& scene, const ParticleSets& sets) {
  const auto cell = root.optional("periodic");
  if (!cell) return;
  cell->allow();
  const double largest = *std::max_element(scene.radius.begin(), scene.radius.end());
  auto axis = [&](const char* key, bool& on, double& lo, double& hi) {
    const auto range = cell->optional(key);
    if (!range) return;
    const auto v = range->items();
    if (v.size() != 2) range->fail("expected [low, high]");
    lo = point_of(v[0], v[1]).x;
    hi = point_of(v[1], v[0]).x;
    if (!(hi > lo)) range->fail("expected [low, high] with high > low");
    if (!(hi - lo >= 8 * largest))
      range->fail("the period is shorter than four of the largest particle diameters (8 x " + message_number(largest) +
                  " m): a particle would meet a neighbour through two images");
    on = true;
  };
  PeriodicCell& c = scene.periodic;
  axis("x", c.x, c.x0, c.x1);
  axis("y", c.y, c.y0, c.y1);
  if (!c.any()) cell->fail("give x: [x0, x1] and/or y: [y0, y1]");
  for (int i = 0; i < scene.n_particles(); ++i) {
    const Vec2 p = scene.position[i];
    if ((c.x && !(p.x >= c.x0 && p.x < c.x1)) || (c.y && !(p.y >= c.y0 && p.y < c.y1)))
      throw InputError(sets.location[sets.of[i]], sets.describe(i) + " starts outside the periodic cell");
  }
}

}  // namespace kiln::scene_parts
