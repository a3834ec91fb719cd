// `--set KEY=VALUE`: replace one value of a loaded scene by its dotted path before it is checked.
#pragma once
#include <yaml-cpp/yaml.h>

#include <set>
#include <string>
#include <vector>

#include "src/scene/scene_reader.h"

namespace kiln {

// Applies each "dotted.path=value" to `root`. The value is read as YAML, so numbers, words and
// [x, y] lists all work. Every key of the path must be documented in `schema` (else the error
// lists the nearest valid keys); a documented map the scene lacks is added, so that any
// documented key can be set (`--set checks.max_overlap_fraction=0.1` on a scene without checks).
// Names (materials) and list indices must exist. KEY=null removes an optional key.
// Returns the dotted paths it replaced.
std::set<std::string> apply_overrides(YAML::Node& root, const std::vector<std::string>& assignments,
                                      const KeySchema& schema);

// "key=value" for a number, printed with all 17 significant digits (std::to_string keeps six
// decimals, which turns a 1e-7 s step into 0).
std::string assignment(const std::string& key, double value);

}  // namespace kiln
