// Reading a scene file into a validated Scene. Nothing runs on a bad scene: every problem is an
// InputError naming the file, line and key, and what was expected. Nothing big is allocated for a
// scene before its size is checked against `memory` (bytes; by default the machine's physical
// memory): particles, lattice rows x columns, fill counts and wall segments.
#pragma once
#include <cstdint>
#include <string>
#include <vector>

#include "src/scene/scene.h"

namespace kiln {

// The machine's physical memory in bytes.
uint64_t physical_memory();

// The text of a scene file, read in pieces and refused past 64 MiB (a scene's text is a few kB to a
// few MB; /dev/zero or a mistaken file used to be read until the machine's memory ran out).
std::string read_scene_text(const std::string& path);

// Reads `path`, applies the `--set` assignments, then checks and expands everything.
Scene load_scene(const std::string& path, const std::vector<std::string>& overrides = {},
                 uint64_t memory = physical_memory());
// The same from text already in memory; `file` is the name used in messages.
Scene parse_scene(const std::string& text, const std::string& file, const std::vector<std::string>& overrides = {},
                  uint64_t memory = physical_memory());

}  // namespace kiln
