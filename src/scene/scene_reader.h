// Checked access to a YAML scene: every read knows its file, line and dotted key, so a wrong
// type, a missing value or an unknown key becomes an InputError that says exactly where it is.
#pragma once
#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <map>
#include <memory>
#include <set>
#include <optional>
#include <string>
#include <vector>

#include "src/base/error.h"
#include "src/base/vec2.h"

namespace kiln {

// The documented keys of a scene, for each map by its schema path: the dotted path with `*` for a
// list index or for a name the user chooses (a material). A map whose keys are such names has the
// single key "*".
using KeySchema = std::map<std::string, std::vector<std::string>>;

// The schema path of `key` inside the map or list whose schema path is `parent`.
std::string schema_child(const KeySchema& schema, const std::string& parent, const std::string& key, bool in_list);

// Whether `text` is valid UTF-8 (the JSON writer's own test, so that what passes here is written).
bool valid_utf8(const std::string& text);
// Fails naming the first line of `text` that is not valid UTF-8.
void check_utf8(const std::string& text, const std::string& file);

// What the YAML parser accepts but a scene must not be: a key given twice in a map (yaml-cpp would
// silently read the first), a key that is not a plain word, and aliases that expand the document to
// more than `max_values` values (a few lines of anchors can stand for billions), make a list or map
// that contains itself, or nest it more than 64 levels deep. `origin` is where
// the document comes from: a file (line 1: lines are reported) or a --set value (line 0, and the
// key it replaces).
void check_structure(const YAML::Node& doc, const Location& origin, size_t max_values);

// What every node of one scene shares.
struct SceneReading {
  std::string file;
  std::set<std::string> overridden;  // dotted paths that --set replaced: reported as "--set"
  const KeySchema* schema = nullptr;
  mutable std::set<std::string> read;  // dotted paths of every value the reader took
};

class SceneNode {
 public:
  SceneNode(YAML::Node root, std::shared_ptr<const SceneReading> source)
      : node_(std::move(root)), source_(std::move(source)) {}

  // Fails unless this is a map whose keys are all documented here (listing the valid ones).
  const SceneNode& allow() const;
  // The same for a variant that takes only some of the documented keys (a fixed wall's motion).
  const SceneNode& allow(std::initializer_list<const char*> allowed) const;
  bool has(const std::string& key) const;
  SceneNode operator[](const std::string& key) const;  // required key
  std::optional<SceneNode> optional(const std::string& key) const;
  std::vector<SceneNode> items() const;                 // a sequence
  std::vector<std::pair<std::string, SceneNode>> entries() const;  // a map, in file order
  bool is_map() const { return node_.IsMap(); }
  bool is_sequence() const { return node_.IsSequence(); }

  double number(const char* expected = "a number") const;  // finite
  double positive() const;      // > 0 and normal (a subnormal 1e-320 has lost its digits)
  double non_negative() const;  // >= 0
  double in_range(double lo, double hi, bool lo_open, bool hi_open) const;
  long long integer(long long min_value, long long max_value) const;
  double temperature() const;   // Celsius, not below absolute zero
  bool boolean() const;
  std::string text() const;     // at most max_text_length characters
  std::string choice(std::initializer_list<const char*> valid) const;
  std::string choice(const std::vector<std::string>& valid) const;
  Vec2 vec2() const;

  // Convenience: optional key with a default.
  double number_or(const std::string& key, double fallback) const;

  // Fails at the first key below this node that nothing read: a documented key that does not
  // apply where it is given (`closed` on a box) would otherwise pass silently. Call after reading.
  void check_all_read() const;

  Location location() const;
  const std::string& path() const { return path_; }
  [[noreturn]] void fail(const std::string& message) const;

  static constexpr size_t max_text_length = 1000;

 private:
  SceneNode(YAML::Node node, std::string path, std::string pattern, std::shared_ptr<const SceneReading> source)
      : node_(std::move(node)), path_(std::move(path)), pattern_(std::move(pattern)), source_(std::move(source)) {}
  std::string child_path(const std::string& key) const;
  SceneNode child(YAML::Node node, const std::string& key) const;
  bool from_command_line(const std::string& path) const;
  // What a scalar's tag lets it be: a number, a whole number or a truth value.
  enum class ScalarKind { number, whole, truth };
  void not_text(const char* expected, ScalarKind kind) const;
  [[noreturn]] void fail_unknown_key(const YAML::Node& key, const std::vector<std::string>& valid) const;
  YAML::Node node_;
  std::string path_;     // dotted path, e.g. particles.0.radius
  std::string pattern_;  // schema path, e.g. particles.*.radius
  std::shared_ptr<const SceneReading> source_;
};

}  // namespace kiln
