// One run of a scene: integrate, check stability, sample case quantities, write the outputs,
// checkpoint, and resume from a checkpoint.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "src/scene/scene.h"
#include "src/base/snapshot.h"

namespace kiln {

// The final state's fields, for studies: x of every particle then y, the same for velocities,
// and temperatures (empty when the scene is not thermal).
struct StabilityEstimate;  // src/run/stability.h

struct FinalFields {
  std::vector<double> position, velocity, temperature;
};

// Where a scene came from, recorded in its checkpoints so that a resumed run rebuilds it.
struct SceneRecord {
  std::string file;                    // the name in messages
  std::string text;                    // the YAML text
  std::vector<std::string> overrides;  // the --set assignments, in order
};

struct RunOptions {
  std::string out_dir;     // empty: write no files (tests and studies)
  bool quiet = false;
  FinalFields* final_fields = nullptr;  // filled at the end when given
  bool stop_at_freeze = false;          // end where the mechanics freeze (the settled state)
  // Runs with files and a recorded source: checkpoint.h5 at the start, every `checkpoint_every`
  // seconds of simulated time (0: a twentieth of t_end), at the run's end and when a signal stops it.
  double checkpoint_every = 0;
  SceneRecord source = {};
  // SIGINT and SIGTERM (caught by the caller, src/base/stop_signal.h) stop the run between two steps.
  bool stop_on_signal = false;
  const Snapshot* resume = nullptr;  // go on from this checkpoint, of this scene
  // Benchmarks: from this step of the mechanical stage on (>= 0), its steps, right-hand sides and
  // wall seconds are summary.json's "timed" (checks, frames and ledger included, as in any run).
  long time_from_step = -1;
  // summary.json's stability.at_end: the integrator's limit on the contacts at the run's end (a
  // settled pile's network, which the start may not have; `kiln sweep` asks it of its finest run).
  bool limit_at_end = false;
  // The scene's estimate when the caller has it already (`kiln run` judged dt with it): not
  // computed again for the guard (on 10,000 pressed discs it takes seconds).
  const StabilityEstimate* estimate = nullptr;
};

// Runs the scene to its end (or its stop condition) and returns the summary (also written to
// out_dir/summary.json). Throws InstabilityError when a check fails and OutputError when an output
// cannot be written, leaving no output behind either way.
nlohmann::json run_scene(const Scene& scene, const RunOptions& options);

// The scene a checkpoint records (its text and overrides, then `overrides` on top) and checks
// that this kiln can resume it: InputError otherwise.
Scene scene_of_checkpoint(const Snapshot& checkpoint, const std::vector<std::string>& overrides,
                          SceneRecord& source);

}  // namespace kiln
