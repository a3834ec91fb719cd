#include "src/scene/overrides.h"

#include <algorithm>
#include <cstdio>

#include "src/base/error.h"
#include "src/base/nearest.h"

namespace kiln {

namespace {

std::vector<std::string> split_path(const std::string& path) {
  std::vector<std::string> parts;
  size_t start = 0;
  while (true) {
    const size_t dot = path.find('.', start);
    parts.push_back(path.substr(start, dot - start));
    if (dot == std::string::npos) break;
    start = dot + 1;
  }
  return parts;
}

std::vector<std::string> keys_of(const YAML::Node& map) {
  std::vector<std::string> keys;
  for (const auto& kv : map) keys.push_back(kv.first.Scalar());
  return keys;
}

// The value of "path=value", read as YAML and held to the same rules as the scene file.
YAML::Node read_value(const std::string& path, const std::string& text) {
  YAML::Node value;
  try {
    // Every document is read: `--set 'dt=2e-6\n---\nx: 1'` was read as 2e-6, the rest dropped unread.
    const std::vector<YAML::Node> documents = YAML::LoadAll(text);
    if (documents.size() > 1)
      throw InputError({"--set", 0, path}, "the value holds a second YAML document (after '---'): give one value");
    if (!documents.empty()) value = documents.front();
  } catch (const YAML::Exception& e) {
    throw InputError({"--set", 0, path}, std::string("cannot read the value: ") + e.what());
  }
  check_structure(value, {"--set", 0, path}, 2 * text.size() + 1000);
  return value;
}

// One step of a path through a list: the index must exist.
YAML::Node list_item(const YAML::Node& list, const std::string& part, const std::string& walked) {
  if (list.size() == 0) throw InputError({"--set", 0, walked}, "the list is empty: there is no item '" + part + "'");
  size_t index = list.size();
  if (part.find_first_not_of("0123456789") == std::string::npos && part.size() < 10) index = std::stoul(part);
  if (index >= list.size())
    throw InputError({"--set", 0, walked}, "'" + part + "' is not an index of this list (0.." +
                                               std::to_string(list.size() - 1) + ")");
  return list[index];
}

// Fails unless `key` may stand in the map whose schema path is `pattern`: a documented key; where
// the keys are names (materials) or nothing is documented, an existing key (or a new last one).
// Returns whether the key is documented, and so may be added.
bool check_key(const YAML::Node& map, const std::string& key, const std::string& pattern, const KeySchema& schema,
               const std::string& walked, bool last) {
  const auto documented = schema.find(pattern);
  const bool named = documented != schema.end() && documented->second == std::vector<std::string>{"*"};
  if (documented != schema.end() && !named) {
    const auto& keys = documented->second;
    if (std::find(keys.begin(), keys.end(), key) != keys.end()) return true;
    throw InputError({"--set", 0, walked}, "no such key; valid keys here are " + choices_nearest_first(key, keys));
  }
  if (!last && !map[key])
    throw InputError({"--set", 0, walked},
                     "no such key; valid keys here are " + choices_nearest_first(key, keys_of(map)));
  return false;
}

void set_value(YAML::Node& root, const std::string& path, const YAML::Node& value, const KeySchema& schema) {
  const std::vector<std::string> parts = split_path(path);
  YAML::Node node = root;
  std::string walked, pattern;
  for (size_t i = 0; i < parts.size(); ++i) {
    const std::string& part = parts[i];
    const bool last = i + 1 == parts.size();
    walked += (walked.empty() ? "" : ".") + part;
    const bool in_list = node.IsSequence();
    const std::string child_pattern = schema_child(schema, pattern, part, in_list);
    if (in_list) {
      YAML::Node item = list_item(node, part, walked);
      if (last) {
        item = value;
      } else {
        node.reset(item);
      }
    } else {
      if (!node.IsMap()) throw InputError({"--set", 0, walked}, "the value above this key is not a map");
      const bool documented = check_key(node, part, pattern, schema, walked, last);
      if (last && value.IsNull()) {
        node.remove(part);  // KEY=null takes an optional key out
      } else if (last) {
        node[part] = value;
      } else {
        if (!node[part]) {
          if (!documented || !schema.count(child_pattern))
            throw InputError({"--set", 0, walked}, "'" + part + "' takes a value here, not keys");
          node[part] = YAML::Node(YAML::NodeType::Map);  // a documented map the scene lacks
        }
        node.reset(node[part]);
      }
    }
    pattern = child_pattern;
  }
}

}  // namespace

std::set<std::string> apply_overrides(YAML::Node& root, const std::vector<std::string>& assignments,
                                      const KeySchema& schema) {
  std::set<std::string> replaced;
  for (const std::string& assignment : assignments) {
    const size_t eq = assignment.find('=');
    const std::string path = assignment.substr(0, eq);
    // Names and texts end up in summary.json: what the JSON writer would refuse is refused here.
    if (!valid_utf8(path)) throw InputError({"--set", 0, ""}, "the key is not valid UTF-8");
    if (!valid_utf8(assignment)) throw InputError({"--set", 0, path}, "not valid UTF-8");
    if (eq == std::string::npos || eq == 0)
      throw InputError({"--set", 0, path.substr(0, 100)}, "expected KEY=VALUE, e.g. --set dt=1e-6");
    set_value(root, path, read_value(path, assignment.substr(eq + 1)), schema);
    replaced.insert(path);
  }
  return replaced;
}

std::string assignment(const std::string& key, double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", value);
  return key + "=" + text;
}

}  // namespace kiln
