// The scene reader's parts, one file each (read_laws, read_particles, read_walls,
// read_run_settings, read_reports, initial_contacts, scene_values, scene_schema), and what they share: the
// checked readers of values, the memory claim, where each particle came from. scene_yaml.cpp calls
// them in order. Internal to src/scene/.
#pragma once
#include <algorithm>
#include <climits>
#include <cstdint>
#include <map>
#include <sstream>
#include <string>
#include <vector>

#include "src/base/nearest.h"
#include "src/scene/scene.h"
#include "src/scene/scene_reader.h"

namespace kiln::scene_parts {

// Every documented key, by the schema path of its map (scene_schema.cpp).
const KeySchema& scene_schema();
// The keys of a `contacts:` entry: those every law reads and those of each model (read_laws.cpp).
std::vector<std::string> contact_entry_keys();
// The keys of a wall's motion, of every kind (wall_motion.cpp).
std::vector<std::string> wall_motion_keys();

// Checked values (scene_values.cpp).
double length(const SceneNode& node);  // in [1e-9, 1e6] m
bool within_reach(Vec2 p);
extern const char* const out_of_reach;
Vec2 point(const SceneNode& node);
Vec2 point_of(const SceneNode& x, const SceneNode& y);  // [x, y] given as two numbers of a longer list
double restitution(const SceneNode& node);
std::string read_name(const SceneNode& node);
std::string file_hash(const std::string& path);
std::string beside_scene(const std::string& file, const std::string& scene_file);

// A scene's claim on memory, counted before anything is allocated for it. A run needs about
// 0.5 kB per disc (measured on a 40,000-disc lattice: state, neighbour lists, frames), counted as
// 1 kB to leave room for the contacts of dense packings; a wall segment about 256 bytes (its
// geometry, its moved copies, its proxy in the neighbour tree).
class MemoryClaim {
 public:
  explicit MemoryClaim(uint64_t budget) : budget_(budget) {}
  long long max_particles() const {
    return static_cast<long long>(std::min<uint64_t>({budget_ / per_particle, INT_MAX, max_tree_proxies}));
  }
  void add_particles(const SceneNode& at, long long count, const std::string& what) {
    const std::string before = particles_ > 0 ? " after " + std::to_string(particles_) + " in earlier sets" : "";
    if (count > max_particles() - particles_)
      at.fail(what + " particles" + before + ": more than the " + std::to_string(max_particles()) + " " +
              (budget_ / per_particle < max_tree_proxies
                   ? "that fit in this machine's memory (" + gigabytes() + " at about 1 kB per particle in a run)"
                   : std::string("that Box2D's tree holds (its node array's size in bytes is an int: it crashed at "
                                 "about 17.6 million proxies)")));
    particles_ += count;
  }
  void add_segments(const SceneNode& at, size_t count) {
    segments_ += count;
    if (particles_ + segments_ > max_tree_proxies)
      at.fail("the walls come to " + std::to_string(segments_) + " segments, which with " + std::to_string(particles_) +
              " particles are more proxies than Box2D's tree holds (" + std::to_string(max_tree_proxies) + ")");
    if (particles_ * per_particle + segments_ * per_segment > budget_)
      at.fail("the walls come to " + std::to_string(segments_) + " segments, which with " +
              std::to_string(particles_) + " particles exceed this machine's memory (" + gigabytes() +
              "; about 256 bytes a segment): raise the tolerance of circles and arcs");
  }

 private:
  static constexpr uint64_t per_particle = 1024, per_segment = 256;
  // Box2D 2.4's b2DynamicTree doubles an array of 2 n nodes of 40 bytes, sized by an int: beyond
  // 2^24 proxies the doubling overflows (a segfault at about 17.6 million particles, measured on a
  // 24 GB machine whose memory allowed 24.7 million). Particles and wall segments are its proxies.
  static constexpr uint64_t max_tree_proxies = uint64_t{1} << 24;
  std::string gigabytes() const {
    std::ostringstream s;
    s.precision(3);
    s << budget_ / 1e9 << " GB";
    return s.str();
  }
  uint64_t budget_;
  long long particles_ = 0;
  uint64_t segments_ = 0;
};

// Where each particle came from, for messages.
struct ParticleSets {
  std::vector<Location> location;  // of each set
  std::vector<int> first;          // index of each set's first particle
  std::vector<int> of;             // each particle's set
  std::string describe(int i) const {
    return "particle " + std::to_string(i) + " (number " + std::to_string(i - first[of[i]]) + " of set " +
           location[of[i]].key + ")";
  }
};

struct MaterialIndex {
  std::map<std::string, int> by_name;
  int find(const SceneNode& node) const {
    const std::string name = node.text();
    const auto it = by_name.find(name);
    if (it == by_name.end()) {
      std::vector<std::string> names;
      for (const auto& kv : by_name) names.push_back(kv.first);
      node.fail("unknown material '" + name + "'; defined materials are " + choices_nearest_first(name, names));
    }
    return it->second;
  }
};

// attach: WALL or fixed: true on a particle set, resolved once the walls are read.
struct Attachment {
  SceneNode node;
  bool fixed = false;
  int first = 0, count = 0;
};

// The parts, in the order read_scene calls them.
void read_materials(const SceneNode& root, Scene& scene, MaterialIndex& index);             // read_laws.cpp
void read_contacts(const SceneNode& root, Scene& scene, const MaterialIndex& index,
                   std::vector<Location>& law_location);                                      // read_laws.cpp
void read_particles(const SceneNode& root, Scene& scene, const MaterialIndex& index, ParticleSets& sets,
                    MemoryClaim& claim, std::vector<Attachment>& attachments);               // read_particles.cpp
void read_walls(const SceneNode& root, Scene& scene, const MaterialIndex& index, MemoryClaim& claim);  // read_walls.cpp
WallMotion read_motion(const SceneNode& m);                                                   // wall_motion.cpp
void attach_particles(const std::vector<Attachment>& attachments, Scene& scene);              // read_walls.cpp
void read_periodic(const SceneNode& root, Scene& scene, const ParticleSets& sets);            // read_walls.cpp
void read_heat(const SceneNode& root, Scene& scene);                                          // read_run_settings.cpp
void check_laws(const Scene& scene, const std::vector<Location>& law_location);              // read_laws.cpp
void check_initial_contacts(const SceneNode& root, const Scene& scene, const ParticleSets& sets);  // initial_contacts.cpp
void read_stepping(const SceneNode& root, Scene& scene);                                      // read_run_settings.cpp
void read_checks(const SceneNode& root, Scene& scene);                                        // read_run_settings.cpp
void read_reports(const SceneNode& root, Scene& scene);                                       // read_reports.cpp

}  // namespace kiln::scene_parts
