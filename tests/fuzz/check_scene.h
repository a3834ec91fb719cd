// What the scene fuzzer does with one input, shared with the test that replays its findings
// (tests/scene/hostile_input_test.cpp): the path `kiln check` takes up to its verdict (read and
// validate, make the integrator, estimate the time step, judge dt), without running. A bad scene
// ends in an InputError, which is caught; anything else escapes and is a finding, as is a scene
// that loads but breaks what it promises the run (a trap, below).
//
// Lines after a line "#--set" are --set assignments, so that overrides are fuzzed too (the scene
// above stays valid YAML: the marker is a comment).
#pragma once
#include <cmath>
#include <cstdint>
#include <sstream>
#include <string>
#include <vector>

#include "integrators/integrator.h"
#include "src/base/error.h"
#include "src/scene/scene_yaml.h"
#include "src/run/stability.h"

namespace kiln::fuzz {

// Scenes may claim 64 MB here, not the machine's memory: the fuzzer stops at -rss_limit_mb=2048,
// and the time a big legal scene takes to fill is no finding.
constexpr uint64_t memory = uint64_t{64} << 20;

inline void check_scene(const std::string& input) {
  const std::string marker = "\n#--set\n";
  const size_t at = input.find(marker);
  std::vector<std::string> sets;
  if (at != std::string::npos) {
    std::istringstream lines(input.substr(at + marker.size()));
    for (std::string line; std::getline(lines, line);) sets.push_back(line);
  }
  try {
    const Scene scene = parse_scene(input.substr(0, at), "fuzz.yaml", sets, memory);
    // What a scene that passed promises the run: finite positive steps and times, and particles
    // with finite positive radii at finite positions. A scene that breaks it is a finding.
    bool sound = std::isfinite(scene.dt) && scene.dt > 0 && std::isfinite(scene.t_end) && scene.t_end > 0 &&
                 std::isfinite(scene.output_interval) && scene.output_interval > 0 &&
                 scene.radius.size() == scene.position.size();
    for (size_t i = 0; sound && i < scene.radius.size(); ++i)
      sound = std::isfinite(scene.radius[i]) && scene.radius[i] > 0 && std::isfinite(scene.position[i].x) &&
              std::isfinite(scene.position[i].y);
    if (!sound) __builtin_trap();
    make_integrator(scene.integrator, scene.control);
    judge_dt(estimate_stability(scene), scene.dt, scene);
  } catch (const InputError&) {
  }
}

}  // namespace kiln::fuzz
