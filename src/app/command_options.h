// The options several commands share: positive numbers, and the scene with its overrides (kiln run
// and kiln check).
#pragma once
#include <CLI/CLI.hpp>

#include <string>
#include <vector>

#include "src/scene/scene.h"

namespace kiln {

// A time, a step or a tolerance: a positive finite number. CLI11's PositiveNumber accepts "nan"
// (which then was ignored) and states its range as 300 digits.
extern const CLI::Validator positive_finite;
// A relative tolerance a scene takes, [1e-14, 1): a study's --rtols, checked before its runs (a
// level of 1e-300 was a failed run in the table; issue 28's review).
extern const CLI::Validator relative_tolerance;
// An integrator's name (aliases included), refused at its option with the valid names nearest
// first: a typo in --integrator was reported as "--set: key 'integrator'".
extern const CLI::Validator integrator_name;

struct SceneArgs {
  std::string path;
  std::string integrator;
  double dt = 0, t_end = 0, rtol = 0, atol = 0;
  bool contact_events = false;
  std::vector<std::string> sets;
};

// Command-line options become --set overrides, so they pass through the same checks as the file.
std::vector<std::string> overrides_of(const SceneArgs& a);
// The scene with its overrides, its integrator known (an unknown name fails before anything runs).
Scene load(const SceneArgs& a);
void add_scene_options(CLI::App* cmd, SceneArgs& a);

}  // namespace kiln
