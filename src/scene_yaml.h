// Reading a scene file into a validated Scene. Nothing runs on a bad scene: every problem is an
// InputError naming the file, line and key, and what was expected.
#pragma once
#include <string>
#include <vector>

#include "src/scene.h"

namespace kiln {

// Reads `path`, applies the `--set` assignments, then checks and expands everything.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {});
// The same from text already in memory; `file` is the name used in messages.
Scene parse_scene(const std::string& text, const std::string& file, const std::vector<std::string>& overrides = {});

}  // namespace kiln
