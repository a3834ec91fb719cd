// Checked access to a YAML scene: every read knows its file, line and dotted key, so a wrong
// type, a missing value or an unknown key becomes an InputError that says exactly where it is.
#pragma once
#include <yaml-cpp/yaml.h>

#include <initializer_list>
#include <memory>
#include <set>
#include <optional>
#include <string>
#include <vector>

#include "src/error.h"
#include "src/vec2.h"

namespace kiln {

class SceneNode {
 public:
  // `overridden` holds the dotted paths that --set replaced: they are reported as "--set".
  SceneNode(YAML::Node node, std::string path, std::string file,
            std::shared_ptr<const std::set<std::string>> overridden = nullptr)
      : node_(std::move(node)), path_(std::move(path)), file_(std::move(file)), overridden_(std::move(overridden)) {}

  // Fails unless this is a map whose keys are all among `allowed` (listing the valid ones).
  const SceneNode& allow(std::initializer_list<const char*> allowed) const;
  bool has(const std::string& key) const;
  SceneNode operator[](const std::string& key) const;  // required key
  std::optional<SceneNode> optional(const std::string& key) const;
  std::vector<SceneNode> items() const;                 // a sequence
  std::vector<std::pair<std::string, SceneNode>> entries() const;  // a map, in file order
  bool is_map() const { return node_.IsMap(); }
  bool is_sequence() const { return node_.IsSequence(); }
  bool is_scalar() const { return node_.IsScalar(); }

  double number(const char* expected = "a number") const;
  double positive() const;      // > 0
  double non_negative() const;  // >= 0
  double in_range(double lo, double hi, bool lo_open, bool hi_open) const;
  long integer(long min_value) const;
  bool boolean() const;
  std::string text() const;
  std::string choice(std::initializer_list<const char*> valid) const;
  Vec2 vec2() const;

  // Convenience: optional key with a default.
  double number_or(const std::string& key, double fallback) const;

  Location location() const;
  const std::string& path() const { return path_; }
  [[noreturn]] void fail(const std::string& message) const;

 private:
  std::string child_path(const std::string& key) const;
  SceneNode child(YAML::Node node, const std::string& key) const {
    return SceneNode(std::move(node), child_path(key), file_, overridden_);
  }
  bool from_command_line(const std::string& path) const;
  YAML::Node node_;
  std::string path_;
  std::string file_;
  std::shared_ptr<const std::set<std::string>> overridden_;
};

}  // namespace kiln
