#include "src/scene/scene_reader.h"

#include <nlohmann/json.hpp>

#include <algorithm>
#include <charconv>
#include <climits>
#include <cfloat>
#include <cmath>

#include "src/base/nearest.h"
#include "src/scene/scene.h"

namespace kiln {

namespace {

// Keys are words (documented keys, material names): a longer one is garbage, and echoing it in
// every message would bury the message.
constexpr size_t max_key_length = 100;

std::string join(const std::string& path, const std::string& key) { return path.empty() ? key : path + "." + key; }

// Walks the whole document once, as it will be read (aliases expanded), counting the values.
class StructureWalk {
 public:
  StructureWalk(const Location& origin, size_t max_values) : origin_(origin), max_values_(max_values) {}

  void visit(const YAML::Node& node, const std::string& path) {
    if (++seen_ > max_values_)
      throw InputError(at(node, path), "the scene expands to more than " + std::to_string(max_values_) +
                                           " values: aliases (*name) repeat a part of it too often");
    check_tag(node, path);
    if (!node.IsSequence() && !node.IsMap()) return;
    // An alias inside its own anchor ({<<: *base} in &base) makes a list or map that contains
    // itself: the walk would descend until the count above stopped it, thousands of levels down
    // on a large scene, and the stack ran out first (SIGSEGV on N3 with one such line).
    for (const YAML::Node& outer : open_)
      if (outer.is(node))
        throw InputError(at(node, path), "an alias (*name) here stands for a list or map that contains it: the scene "
                                         "would never end");
    // Chains of aliases, each anchor holding the one before, nest as deep as there are anchors.
    if (open_.size() >= max_nesting)
      throw InputError(at(node, path), "lists or maps nested more than " + std::to_string(max_nesting) +
                                           " levels deep (aliases (*name) expanded): not a scene");
    open_.push_back(node);
    if (node.IsSequence()) {
      size_t index = 0;
      for (const YAML::Node& item : node) visit(item, join(path, std::to_string(index++)));
    } else {
      visit_map(node, path);
    }
    open_.pop_back();
  }

 private:
  void visit_map(const YAML::Node& map, const std::string& path) {
    std::map<std::string, Location> first;
    for (const auto& kv : map) {
      if (!kv.first.IsScalar()) throw InputError(at(kv.first, path), "a key must be a plain word, not a list or a map");
      const std::string& key = kv.first.Scalar();
      if (key.size() > max_key_length)
        throw InputError(at(kv.first, path), "a key of " + std::to_string(key.size()) +
                                                 " characters; keys are words of at most " +
                                                 std::to_string(max_key_length));
      const Location here = at(kv.first, join(path, key));
      const auto [earlier, fresh] = first.emplace(key, here);
      if (!fresh)
        throw InputError(here, "given twice (also " + describe_line(earlier->second) +
                                   "); YAML would keep only the first: remove one of them");
      visit(kv.second, join(path, key));  // the path below the origin: at() adds the origin's key once
    }
  }
  // Tags are honoured or refused, never ignored: the YAML core schema's own (a plain or quoted
  // scalar has "?" or "!") are read as they say (a !!str or quoted number is text, which a number's
  // key refuses); any other (!!binary, !!timestamp, !custom) is refused here, at its key.
  void check_tag(const YAML::Node& node, const std::string& path) const {
    static const char* const core[] = {"?", "!", "tag:yaml.org,2002:str", "tag:yaml.org,2002:int",
                                       "tag:yaml.org,2002:float", "tag:yaml.org,2002:bool", "tag:yaml.org,2002:null",
                                       "tag:yaml.org,2002:map", "tag:yaml.org,2002:seq"};
    const std::string& tag = node.Tag();
    if (tag.empty() || tag == "?" || tag == "!") return;
    if (std::find(std::begin(core), std::end(core), tag) != std::end(core)) {
      // A core tag names a kind of node: !!seq on a map was read as the map (issue 28's campaign).
      const bool fits = tag == "tag:yaml.org,2002:map"   ? node.IsMap()
                        : tag == "tag:yaml.org,2002:seq" ? node.IsSequence()
                                                         : node.IsScalar() || node.IsNull();
      if (fits) return;
      throw InputError(at(node, path), "the tag '" + tag + "' stands for a " +
                                           (tag == "tag:yaml.org,2002:map"   ? "map"
                                            : tag == "tag:yaml.org,2002:seq" ? "list"
                                                                             : "single value") +
                                           ", and it is given to a " + (node.IsMap() ? "map" : node.IsSequence() ? "list" : "value") +
                                           ": remove the tag");
    }
    throw InputError(at(node, path), "the tag '" + tag.substr(0, 60) +
                                         "' is not read by kiln (a scene uses YAML's plain numbers, words, "
                                         "lists and maps; !!str, !!int, !!float, !!bool and !!null are read as they say)");
  }
  Location at(const YAML::Node& node, const std::string& path) const {
    const YAML::Mark mark = node.Mark();
    const bool has_line = origin_.line > 0 && !mark.is_null() && mark.line >= 0;
    return {origin_.file, has_line ? mark.line + 1 : 0, join(origin_.key, path)};
  }
  static std::string describe_line(const Location& l) {
    return l.line > 0 ? "at line " + std::to_string(l.line) : "before";
  }
  // A scene nests a few levels (particles, a set, its lattice); 64 leaves room and keeps the walk
  // and the key paths in its messages short.
  static constexpr size_t max_nesting = 64;
  Location origin_;
  size_t max_values_;
  size_t seen_ = 0;
  std::vector<YAML::Node> open_;  // the lists and maps from the root to the node being visited
};

}  // namespace

std::string schema_child(const KeySchema& schema, const std::string& parent, const std::string& key, bool in_list) {
  const auto keys = schema.find(parent);
  const bool named = keys != schema.end() && keys->second.size() == 1 && keys->second.front() == "*";
  return join(parent, in_list || named ? "*" : key);
}

bool valid_utf8(const std::string& text) {
  try {
    (void)nlohmann::json(text).dump();
  } catch (const nlohmann::json::type_error&) {
    return false;
  }
  return true;
}

void check_utf8(const std::string& text, const std::string& file) {
  if (valid_utf8(text)) return;
  // The newline byte never occurs inside a multi-byte character: lines can be checked one by one.
  int line = 1;
  for (size_t start = 0; start <= text.size(); ++line) {
    const size_t end = std::min(text.find('\n', start), text.size());
    if (!valid_utf8(text.substr(start, end - start)))
      throw InputError({file, line, ""}, "not valid UTF-8 (a byte of another encoding, such as Latin-1): save the "
                                         "file as UTF-8");
    start = end + 1;
  }
}

void check_structure(const YAML::Node& doc, const Location& origin, size_t max_values) {
  StructureWalk(origin, max_values).visit(doc, "");
}

// A value replaced by --set (or inside one) is blamed on the command line, not the file.
bool SceneNode::from_command_line(const std::string& path) const {
  for (const std::string& p : source_->overridden)
    if (path == p || (path.size() > p.size() && path.compare(0, p.size(), p) == 0 && path[p.size()] == '.')) return true;
  return false;
}

Location SceneNode::location() const {
  const YAML::Mark mark = node_.Mark();
  if (from_command_line(path_) || mark.is_null() || mark.line < 0) return {"--set", 0, path_};
  return {source_->file, mark.line + 1, path_};
}

void SceneNode::fail(const std::string& message) const { throw InputError(location(), message); }

std::string SceneNode::child_path(const std::string& key) const { return join(path_, key); }

SceneNode SceneNode::child(YAML::Node node, const std::string& key) const {
  const std::string pattern = schema_child(*source_->schema, pattern_, key, node_.IsSequence());
  std::string path = child_path(key);
  source_->read.insert(path);
  return SceneNode(std::move(node), std::move(path), pattern, source_);
}

void SceneNode::check_all_read() const {
  if (node_.IsMap()) {
    for (const auto& kv : node_) {
      const std::string path = child_path(kv.first.Scalar());
      if (!source_->read.count(path)) {
        const YAML::Mark mark = kv.first.Mark();
        Location at{source_->file, mark.line + 1, path};
        if (from_command_line(path) || mark.is_null() || mark.line < 0) at = {"--set", 0, path};
        std::vector<std::string> used;
        for (const auto& other : node_)
          if (source_->read.count(child_path(other.first.Scalar()))) used.push_back(other.first.Scalar());
        throw InputError(at, "'" + kv.first.Scalar() + "' does not apply here: nothing reads it with the other keys "
                             "of this entry (read here: " + (used.empty() ? std::string("none") : choices_nearest_first(kv.first.Scalar(), used)) +
                             "); remove it");
      }
      child(kv.second, kv.first.Scalar()).check_all_read();
    }
  } else if (node_.IsSequence()) {
    for (size_t i = 0; i < node_.size(); ++i)
      if (source_->read.count(child_path(std::to_string(i)))) child(node_[i], std::to_string(i)).check_all_read();
  }
}

void SceneNode::fail_unknown_key(const YAML::Node& key, const std::vector<std::string>& valid) const {
  const YAML::Mark mark = key.Mark();
  const std::string path = child_path(key.Scalar());
  Location at{source_->file, mark.line + 1, path};
  if (from_command_line(path) || mark.is_null() || mark.line < 0) at = {"--set", 0, path};
  throw InputError(at, "unknown key; valid keys here are " + choices_nearest_first(key.Scalar(), valid));
}

const SceneNode& SceneNode::allow() const {
  const auto keys = source_->schema->find(pattern_);
  if (keys == source_->schema->end()) fail("no keys are documented here (" + pattern_ + ")");
  if (!node_.IsMap()) fail("expected a map with keys " + choices_nearest_first("", keys->second));
  for (const auto& kv : node_)
    if (std::find(keys->second.begin(), keys->second.end(), kv.first.Scalar()) == keys->second.end())
      fail_unknown_key(kv.first, keys->second);
  return *this;
}

const SceneNode& SceneNode::allow(std::initializer_list<const char*> allowed) const {
  const std::vector<std::string> valid(allowed.begin(), allowed.end());
  if (!node_.IsMap()) fail("expected a map with keys " + choices_nearest_first("", valid));
  for (const auto& kv : node_)
    if (std::find(valid.begin(), valid.end(), kv.first.Scalar()) == valid.end()) fail_unknown_key(kv.first, valid);
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
    const std::string key = kv.first.Scalar();
    out.emplace_back(key, child(kv.second, key));
  }
  return out;
}

// A number, a count or a truth value is a plain scalar or one tagged as such: YAML reads a quoted
// "8900" and !!str 8900 as text, which yaml-cpp would convert silently (PyYAML keeps text). The
// core schema's other tags are held to what they say too: yaml-cpp read `!!int 0.5` as 0.5,
// `!!null 2.0e-6` as 2e-6 and `!!bool 1` as a number (issue 28's campaign).
void SceneNode::not_text(const char* expected, ScalarKind kind) const {
  const std::string& tag = node_.Tag();
  if (tag == "!" || tag == "tag:yaml.org,2002:str")
    // yaml-cpp gives a quoted scalar and a block one (| or >) the same tag and no style: the
    // advice names both.
    fail(std::string("expected ") + expected + ", got the text '" + node_.Scalar().substr(0, 60) + "' (" +
         (tag == "!" ? "quoted, or a | or > block" : "tagged !!str") + ": YAML reads it as text; " +
         (tag == "!" ? "write it plain, without quotes or block indicator" : "remove the tag") + ")");
  const auto refuse = [&](const std::string& tagged, const std::string& reads_as) {
    fail(std::string("expected ") + expected + ", got '" + node_.Scalar().substr(0, 60) + "' tagged " + tagged +
         ": YAML reads it as " + reads_as + "; remove the tag");
  };
  const bool is_int = tag == "tag:yaml.org,2002:int", is_float = tag == "tag:yaml.org,2002:float";
  if (tag == "tag:yaml.org,2002:null") refuse("!!null", "null (no value)");
  if (tag == "tag:yaml.org,2002:bool" && kind != ScalarKind::truth) refuse("!!bool", "a truth value");
  if ((is_int || is_float) && kind == ScalarKind::truth) refuse(is_int ? "!!int" : "!!float", "a number");
  if (is_int && kind == ScalarKind::number) {
    // The core schema's integers: decimal, 0o octal, 0x hexadecimal.
    const std::string& s = node_.Scalar();
    const size_t sign = !s.empty() && (s[0] == '-' || s[0] == '+') ? 1 : 0;
    const bool whole = (s.size() > sign && s.find_first_not_of("0123456789", sign) == std::string::npos) ||
                       (s.size() > 2 && s.rfind("0o", 0) == 0 && s.find_first_not_of("01234567", 2) == std::string::npos) ||
                       (s.size() > 2 && s.rfind("0x", 0) == 0 &&
                        s.find_first_not_of("0123456789abcdefABCDEF", 2) == std::string::npos);
    if (!whole) refuse("!!int", "a whole number, which it is not");
  }
}

double SceneNode::number(const char* expected) const {
  if (!node_.IsScalar()) fail(std::string("expected ") + expected);
  not_text(expected, ScalarKind::number);
  double v = 0;
  try {
    v = node_.as<double>();
  } catch (const YAML::Exception&) {
    fail(std::string("expected ") + expected + ", got '" + text() + "'");
  }
  if (!std::isfinite(v)) fail("expected a finite number, got '" + node_.Scalar() + "'");
  return v;
}

double SceneNode::positive() const {
  const double v = number("a positive number");
  if (!(v > 0)) fail("expected a positive number, got " + node_.Scalar());
  if (v < DBL_MIN)
    fail("expected a positive number of at least 2.2e-308, got " + node_.Scalar() +
         " (a subnormal number has lost its significant digits)");
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
    fail("expected a value in " + std::string(lo_open ? "(" : "[") + message_number(lo) + ", " + message_number(hi) +
         (hi_open ? ")" : "]") + ", got " + node_.Scalar());
  }
  return v;
}

// Every whole number of a scene is read here, in 64 bits and checked against its range, so that
// no count wraps around when it is narrowed (4294967298 columns are not 2).
long long SceneNode::integer(long long min_value, long long max_value) const {
  const std::string range = "a whole number in [" + std::to_string(min_value) + ", " + std::to_string(max_value) + "]";
  if (!node_.IsScalar()) fail("expected " + range);
  not_text(range.c_str(), ScalarKind::whole);
  // YAML 1.2's core integers, read here: decimal (leading zeros included: 0100 is 100), 0o octal,
  // 0x hexadecimal. yaml-cpp's as<long long> read 0100 as octal 64, without a word, and refused 0090.
  const std::string& s = node_.Scalar();
  const size_t sign = !s.empty() && (s[0] == '-' || s[0] == '+') ? 1 : 0;
  int base = 10;
  size_t digits = sign;
  if (s.compare(sign, 2, "0o") == 0 || s.compare(sign, 2, "0x") == 0) {
    base = s[sign + 1] == 'o' ? 8 : 16;
    digits += 2;
  }
  unsigned long long magnitude = 0;
  const char *first = s.data() + digits, *last = s.data() + s.size();
  const auto [end, error] = std::from_chars(first, last, magnitude, base);
  if (first == last || end != last || error == std::errc::invalid_argument)
    fail("expected " + range + ", got '" + text() + "'");
  const unsigned long long limit = static_cast<unsigned long long>(LLONG_MAX) + (sign && s[0] == '-' ? 1 : 0);
  if (error == std::errc::result_out_of_range || magnitude > limit) fail("expected " + range + ", got " + s);
  const long long v = sign && s[0] == '-' ? static_cast<long long>(0ULL - magnitude) : static_cast<long long>(magnitude);
  if (v < min_value || v > max_value) fail("expected " + range + ", got " + s);
  return v;
}

double SceneNode::temperature() const {
  const double t = number("a temperature (degrees Celsius)");
  // Bounded below and above, as everywhere a temperature is read (src/scene/scene.h says why).
  if (const std::string why = temperature_refusal(t, node_.Scalar()); !why.empty())
    fail("a temperature of " + node_.Scalar() + " C " + why);
  return t;
}

bool SceneNode::boolean() const {
  if (!node_.IsScalar()) fail("expected true or false");
  not_text("true or false", ScalarKind::truth);
  try {
    return node_.as<bool>();
  } catch (const YAML::Exception&) {
    fail("expected true or false, got '" + text() + "'");
  }
}

std::string SceneNode::text() const {
  if (!node_.IsScalar()) fail("expected a text value");
  const std::string& s = node_.Scalar();
  if (s.size() > max_text_length)
    fail("a text of " + std::to_string(s.size()) + " characters; at most " + std::to_string(max_text_length) +
         " are read");
  return s;
}

std::string SceneNode::choice(std::initializer_list<const char*> valid) const {
  return choice(std::vector<std::string>(valid.begin(), valid.end()));
}

std::string SceneNode::choice(const std::vector<std::string>& valid) const {
  const std::string v = text();
  if (std::find(valid.begin(), valid.end(), v) != valid.end()) return v;
  fail("unknown value '" + v + "'; valid choices are " + choices_nearest_first(v, valid));
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
