// One run of a scene: integrate, check stability, sample case quantities, write the outputs.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "src/scene.h"

namespace kiln {

// The final state's fields, for studies: x of every particle then y, the same for velocities,
// and temperatures (empty when the scene is not thermal).
struct FinalFields {
  std::vector<double> position, velocity, temperature;
};

struct RunOptions {
  std::string out_dir;     // empty: write no files (tests and studies)
  bool quiet = false;
  FinalFields* final_fields = nullptr;  // filled at the end when given
  bool stop_at_freeze = false;          // end where the mechanics freeze (the settled state)
};

// Runs the scene to its end (or its stop condition) and returns the summary (also written to
// out_dir/summary.json). Throws InstabilityError when a check fails, leaving no output behind.
nlohmann::json run_scene(const Scene& scene, const RunOptions& options);

}  // namespace kiln
