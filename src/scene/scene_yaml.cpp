#include "src/scene/scene_yaml.h"

#include <unistd.h>
#include <yaml-cpp/depthguard.h>
#include <yaml-cpp/yaml.h>

#include <algorithm>
#include <cctype>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <vector>

#include "src/base/text_format.h"
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
  if (auto m = root.optional("ensemble_member")) scene.ensemble_member = m->integer(0, 1000000000);
  read_particles(root, scene, index, sets, claim, attachments);
  read_walls(root, scene, index, claim);
  attach_particles(attachments, scene);
  read_periodic(root, scene, sets);
  read_heat(root, scene);
  check_laws(scene, law_location);
  read_checks(root, scene);  // the start check bounds allowed overlaps by the run's overlap check
  check_initial_contacts(root, scene, sets);
  read_stepping(root, scene);
  read_reports(root, scene);
  return scene;
}

// The top-level key whose value holds line `line` (0-based) of `text`, for nesting too deep, which
// yaml-cpp refuses before there is a tree to name a key in:
// the nearest line at or above it that starts with a key in the first column. "" if none.
std::string top_level_key_at(const std::string& text, int line) {
  std::vector<size_t> starts = {0};
  for (size_t k = 0; k < text.size() && static_cast<int>(starts.size()) <= line; ++k)
    if (text[k] == '\n') starts.push_back(k + 1);
  for (int l = std::min<int>(line, static_cast<int>(starts.size()) - 1); l >= 0; --l) {
    const size_t from = starts[l];
    const size_t end = std::min(text.find('\n', from), text.size());
    const std::string row = text.substr(from, std::min<size_t>(end - from, 200));
    const bool top = !row.empty() && !std::isspace(static_cast<unsigned char>(row[0])) && row[0] != '#' && row[0] != '-';
    const size_t colon = row.find(':');
    if (top && colon != std::string::npos && colon > 0) return row.substr(0, colon);
    if (top && l == line) return "";  // the line at fault is a top-level line, and holds no key

  }
  return "";
}

}  // namespace

uint64_t physical_memory() {
  const long pages = sysconf(_SC_PHYS_PAGES), page_size = sysconf(_SC_PAGE_SIZE);
  if (pages <= 0 || page_size <= 0) return uint64_t{4} << 30;  // not told: assume a small machine, 4 GB
  return static_cast<uint64_t>(pages) * static_cast<uint64_t>(page_size);
}

Scene parse_scene(const std::string& written, const std::string& file, const std::vector<std::string>& overrides,
                  uint64_t memory) {
  // YAML (1.2, 5.4) and PyYAML read a lone CR as a line break; yaml-cpp 0.7 reads it as a character
  // of its line, so a lone CR inside a comment hid the key after it (output_interval dropped). Lone
  // CRs become line feeds, and the scene is read as the YAML it is; CR LF is the parser's.
  std::string text = written;
  for (size_t k = 0; k < text.size(); ++k)
    if (text[k] == '\r' && (k + 1 == text.size() || text[k + 1] != '\n')) text[k] = '\n';
  // Names and texts end up in summary.json: text the JSON writer would refuse is refused here.
  check_utf8(text, file);
  // YAML allows no control character but tab, line feed and carriage return, comments included
  // (PyYAML refuses them; yaml-cpp read a NUL byte in a comment as part of the comment).
  for (size_t k = 0, line = 1, line_start = 0; k < text.size(); ++k) {
    const unsigned char c = static_cast<unsigned char>(text[k]);
    if (c == '\n') {
      ++line;
      line_start = k + 1;
    } else if ((c < 0x20 && c != '\t' && c != '\r') || c == 0x7f) {
      throw InputError({file, static_cast<int>(line), ""},
                       format("a control character (byte 0x%02x) at column %zu: YAML allows none but tab, line feed "
                              "and carriage return",
                              c, k - line_start + 1));
    }
  }
  YAML::Node doc;
  try {
    // Every document is read, so that a second one is refused rather than dropped unread.
    const std::vector<YAML::Node> documents = YAML::LoadAll(text);
    if (documents.size() > 1) {
      const YAML::Mark at = documents[1].Mark();
      throw InputError({file, at.is_null() || at.line < 0 ? 0 : at.line + 1, ""},
                       "a second YAML document (after '---'): a scene is one document, and kiln would read only the "
                       "first; remove the marker or put the second scene in a file of its own");
    }
    if (!documents.empty()) doc = documents.front();
  } catch (const YAML::DeepRecursion& e) {
    throw InputError({file, e.mark.line + 1, top_level_key_at(text, e.mark.line)},
                     "lists or maps nested " + std::to_string(e.depth()) + " levels deep: not a scene");
  } catch (const YAML::ParserException& e) {
    // No key: a parser's mark is where it noticed, often the line after the fault (an unclosed list
    // is reported at the next key).
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

std::string read_scene_text(const std::string& path) {
  // The largest drawing kiln reads is 64 MiB too (svg_geometry.cpp). A device that never ends
  // (/dev/zero, /dev/urandom) is refused once that much is read: it used to be read whole, until
  // the kernel's out-of-memory killer ended kiln (24 GB, SIGKILL).
  constexpr size_t largest = size_t{64} << 20;
  std::error_code error;
  if (std::filesystem::is_directory(path, error)) throw InputError({path, 0, ""}, "is a directory, not a scene file");
  std::ifstream in(path, std::ios::binary);
  if (!in) throw InputError({path, 0, ""}, "cannot open the scene file");
  std::string text;
  std::vector<char> piece(size_t{1} << 16);
  while (in.read(piece.data(), static_cast<std::streamsize>(piece.size())) || in.gcount() > 0) {
    text.append(piece.data(), static_cast<size_t>(in.gcount()));
    if (text.size() > largest)
      throw InputError({path, 0, ""}, "is larger than 64 MiB: not a scene (a scene's text takes kB; give many "
                                      "particles in a particle file, particles: - file:)");
  }
  if (in.bad()) throw InputError({path, 0, ""}, "cannot read the scene file");
  return text;
}

Scene load_scene(const std::string& path, const std::vector<std::string>& overrides, uint64_t memory) {
  return parse_scene(read_scene_text(path), path, overrides, memory);
}

}  // namespace kiln
