// `--set KEY=VALUE`: replace one value of a loaded scene by its dotted path before it is checked.
#pragma once
#include <yaml-cpp/yaml.h>

#include <set>
#include <string>
#include <vector>

namespace kiln {

// Applies each "dotted.path=value" to `root`. The value is read as YAML, so numbers, words and
// [x, y] lists all work. A path through a key that does not exist fails with the nearest valid
// keys; the last key may be new (the scene checker then decides whether it is a valid key).
// KEY=null removes an optional key.
// Returns the dotted paths it replaced.
std::set<std::string> apply_overrides(YAML::Node& root, const std::vector<std::string>& assignments);

// "key=value" for a number, printed with all 17 significant digits (std::to_string keeps six
// decimals, which turns a 1e-7 s step into 0).
std::string assignment(const std::string& key, double value);

}  // namespace kiln
