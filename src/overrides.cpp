#include "src/overrides.h"

#include <cstdio>

#include "src/error.h"
#include "src/nearest.h"

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
  for (const auto& kv : map) keys.push_back(kv.first.as<std::string>());
  return keys;
}

}  // namespace

std::set<std::string> apply_overrides(YAML::Node& root, const std::vector<std::string>& assignments) {
  std::set<std::string> replaced;
  for (const std::string& assignment : assignments) {
    const size_t eq = assignment.find('=');
    if (eq == std::string::npos || eq == 0)
      throw InputError({"--set", 0, assignment}, "expected KEY=VALUE, e.g. --set dt=1e-6");
    const std::string path = assignment.substr(0, eq);
    YAML::Node value;
    try {
      value = YAML::Load(assignment.substr(eq + 1));
    } catch (const YAML::Exception& e) {
      throw InputError({"--set", 0, path}, std::string("cannot read the value: ") + e.what());
    }
    const std::vector<std::string> parts = split_path(path);
    replaced.insert(path);
    YAML::Node node = root;
    std::string walked;
    for (size_t i = 0; i < parts.size(); ++i) {
      const std::string& part = parts[i];
      const bool last = i + 1 == parts.size();
      walked += (walked.empty() ? "" : ".") + part;
      if (node.IsSequence()) {
        size_t index = 0;
        try {
          index = std::stoul(part);
        } catch (const std::exception&) {
          index = node.size();
        }
        if (index >= node.size())
          throw InputError({"--set", 0, walked}, "'" + part + "' is not an index of this list (0.." +
                                                     std::to_string(node.size() - 1) + ")");
        if (last) {
          node[index] = value;
        } else {
          node.reset(node[index]);
        }
        continue;
      }
      if (!node.IsMap())
        throw InputError({"--set", 0, walked}, "the value above this key is not a map");
      if (last) {
        if (value.IsNull()) {
          node.remove(part);  // KEY=null takes an optional key out
        } else {
          node[part] = value;
        }
      } else {
        YAML::Node child = node[part];
        if (!child)
          throw InputError({"--set", 0, walked},
                           "no such key; valid keys here are " + choices_nearest_first(part, keys_of(node)));
        node.reset(child);
      }
    }
  }
  return replaced;
}

std::string assignment(const std::string& key, double value) {
  char text[40];
  std::snprintf(text, sizeof text, "%.17g", value);
  return key + "=" + text;
}

}  // namespace kiln
