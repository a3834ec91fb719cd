#include "src/scene_reader.h"

#include <cmath>

#include "src/nearest.h"

namespace kiln {

// A value replaced by --set (or inside one) is blamed on the command line, not the file.
bool SceneNode::from_command_line(const std::string& path) const {
  if (!overridden_) return false;
  for (const std::string& p : *overridden_)
    if (path == p || (path.size() > p.size() && path.compare(0, p.size(), p) == 0 && path[p.size()] == '.')) return true;
  return false;
}

Location SceneNode::location() const {
  const YAML::Mark mark = node_.Mark();
  if (from_command_line(path_) || mark.is_null() || mark.line < 0) return {"--set", 0, path_};
  return {file_, mark.line + 1, path_};
}

void SceneNode::fail(const std::string& message) const { throw InputError(location(), message); }

std::string SceneNode::child_path(const std::string& key) const {
  return path_.empty() ? key : path_ + "." + key;
}

const SceneNode& SceneNode::allow(std::initializer_list<const char*> allowed) const {
  if (!node_.IsMap()) fail("expected a map with keys " + choices_nearest_first("", {allowed.begin(), allowed.end()}));
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    bool known = false;
    for (const char* a : allowed) known = known || key == a;
    if (!known) {
      const YAML::Mark mark = kv.first.Mark();
      Location at{file_, mark.line + 1, child_path(key)};
      if (from_command_line(child_path(key)) || mark.is_null() || mark.line < 0) at = {"--set", 0, child_path(key)};
      throw InputError(at, "unknown key; valid keys here are " +
                               choices_nearest_first(key, {allowed.begin(), allowed.end()}));
    }
  }
  return *this;
}

bool SceneNode::has(const std::string& key) const { return node_.IsMap() && node_[key]; }

SceneNode SceneNode::operator[](const std::string& key) const {
  if (!node_.IsMap()) fail("expected a map containing '" + key + "'");
  YAML::Node child = node_[key];
  if (!child) fail("missing required key '" + key + "'");
  return this->child(child, key);
}

std::optional<SceneNode> SceneNode::optional(const std::string& key) const {
  if (!has(key)) return std::nullopt;
  return (*this)[key];
}

std::vector<SceneNode> SceneNode::items() const {
  if (!node_.IsSequence()) fail("expected a list");
  std::vector<SceneNode> out;
  for (size_t i = 0; i < node_.size(); ++i)
    out.push_back(child(node_[i], std::to_string(i)));
  return out;
}

std::vector<std::pair<std::string, SceneNode>> SceneNode::entries() const {
  if (!node_.IsMap()) fail("expected a map");
  std::vector<std::pair<std::string, SceneNode>> out;
  for (const auto& kv : node_) {
    const std::string key = kv.first.as<std::string>();
    out.emplace_back(key, child(kv.second, key));
  }
  return out;
}

double SceneNode::number(const char* expected) const {
  if (!node_.IsScalar()) fail(std::string("expected ") + expected);
  double v = 0;
  try {
    v = node_.as<double>();
  } catch (const YAML::Exception&) {
    fail(std::string("expected ") + expected + ", got '" + node_.Scalar() + "'");
  }
  if (!std::isfinite(v)) fail("expected a finite number, got '" + node_.Scalar() + "'");
  return v;
}

double SceneNode::positive() const {
  const double v = number("a positive number");
  if (!(v > 0)) fail("expected a positive number, got " + node_.Scalar());
  return v;
}

double SceneNode::non_negative() const {
  const double v = number("a number >= 0");
  if (v < 0) fail("expected a number >= 0, got " + node_.Scalar());
  return v;
}

double SceneNode::in_range(double lo, double hi, bool lo_open, bool hi_open) const {
  const double v = number();
  const bool ok = (lo_open ? v > lo : v >= lo) && (hi_open ? v < hi : v <= hi);
  if (!ok) {
    fail("expected a value in " + std::string(lo_open ? "(" : "[") + YAML::Node(lo).Scalar() + ", " +
         YAML::Node(hi).Scalar() + (hi_open ? ")" : "]") + ", got " + node_.Scalar());
  }
  return v;
}

long SceneNode::integer(long min_value) const {
  if (!node_.IsScalar()) fail("expected a whole number");
  long v = 0;
  try {
    v = node_.as<long>();
  } catch (const YAML::Exception&) {
    fail("expected a whole number, got '" + node_.Scalar() + "'");
  }
  if (v < min_value) fail("expected a whole number >= " + std::to_string(min_value) + ", got " + node_.Scalar());
  return v;
}

bool SceneNode::boolean() const {
  if (!node_.IsScalar()) fail("expected true or false");
  try {
    return node_.as<bool>();
  } catch (const YAML::Exception&) {
    fail("expected true or false, got '" + node_.Scalar() + "'");
  }
}

std::string SceneNode::text() const {
  if (!node_.IsScalar()) fail("expected a text value");
  return node_.Scalar();
}

std::string SceneNode::choice(std::initializer_list<const char*> valid) const {
  const std::string v = text();
  for (const char* c : valid)
    if (v == c) return v;
  fail("unknown value '" + v + "'; valid choices are " + choices_nearest_first(v, {valid.begin(), valid.end()}));
}

Vec2 SceneNode::vec2() const {
  if (!node_.IsSequence() || node_.size() != 2) fail("expected a pair [x, y]");
  const auto xy = items();
  return {xy[0].number(), xy[1].number()};
}

double SceneNode::number_or(const std::string& key, double fallback) const {
  const auto child = optional(key);
  return child ? child->number() : fallback;
}

}  // namespace kiln
