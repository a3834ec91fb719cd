#include "src/scene/scene_yaml.h"

#include <unistd.h>
#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>

#include <fstream>
#include <sstream>

#include "src/scene/overrides.h"
#include "src/scene/scene_parts.h"

namespace kiln {

namespace {

using namespace scene_parts;

// The table of contents of a scene: each part reads its keys, in an order where each finds what
// it depends on already read.
Scene read_scene(const SceneNode& root, const std::string& file, uint64_t memory) {
  root.allow();
  Scene scene;
  scene.file = file;
  scene.name = read_name(root["name"]);
  if (auto d = root.optional("description")) scene.description = d->text();
  if (auto m = root.optional("mass_model")) {
    if (m->choice({"sphere", "cylinder"}) == "cylinder") {
      scene.mass_model = MassModel::cylinder;
      scene.thickness = length(root["thickness"]);
    }
  }
  if (root.has("thickness") && scene.mass_model != MassModel::cylinder)
    root["thickness"].fail("thickness applies only to mass_model: cylinder");
  if (auto g = root.optional("gravity")) scene.gravity = g->vec2();
  MaterialIndex index;
  read_materials(root, scene, index);
  std::vector<Location> law_location;
  read_contacts(root, scene, index, law_location);
  MemoryClaim claim(memory);
  ParticleSets sets;
  std::vector<Attachment> attachments;
  read_particles(root, scene, index, sets, claim, attachments);
  read_walls(root, scene, index, claim);
  attach_particles(attachments, scene);
  read_periodic(root, scene, sets);
  read_heat(root, scene);
  check_laws(scene, law_location);
  check_initial_contacts(root, scene, sets);
  read_stepping(root, scene);
  read_checks(root, scene);
  read_reports(root, scene);
  return scene;
}

}  // namespace

uint64_t physical_memory() {
  const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return uint64_t{4} << 30;  // not told: assume a small machine, 4 GB
  return static_cast<uint64_t>(pages) * static_cast<uint64_t>(page_size);
}

Scene parse_scene(const std::string& text, const std::string& file, const std::vector<std::string>& overrides,
                  uint64_t memory) {
  // Names and texts end up in summary.json: text the JSON writer would refuse is refused here.
  check_utf8(text, file);
  YAML::Node doc;
  try {
    doc = YAML::Load(text);
  } catch (const YAML::DeepRecursion& e) {
    throw InputError({file, e.mark.line + 1, ""},
                     "lists or maps nested " + std::to_string(e.depth()) + " levels deep: not a scene");
  } catch (const YAML::ParserException& e) {
    throw InputError({file, e.mark.line + 1, ""}, "not valid YAML: " + e.msg);
  }
  if (!doc.IsMap()) throw InputError({file, 1, ""}, "a scene is a map of keys (name, materials, particles, ...)");
  // Without aliases a document has fewer values than characters (each takes one at least).
  check_structure(doc, {file, 1, ""}, 2 * text.size() + 1000);
  auto source = std::make_shared<SceneReading>();
  source->file = file;
  source->schema = &scene_schema();
  source->overridden = apply_overrides(doc, overrides, scene_schema());
  const SceneNode root(doc, source);
  Scene scene = read_scene(root, file, memory);
  root.check_all_read();
  return scene;
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides, uint64_t memory) {
  std::ifstream in(path);
  if (!in) throw InputError({path, 0, ""}, "cannot open the scene file");
  std::stringstream text;
  text << in.rdbuf();
  return parse_scene(text.str(), path, overrides, memory);
}

}  // namespace kiln
