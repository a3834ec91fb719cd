// Ensembles in the studies (`--seeds`): on a chaotic flow each point of a study (an integrator
// and a step) is run as members 0 .. N-1 of the scene (the scene key ensemble_member: every seed
// the scene declares is mixed with the member's number, src/scene/scene.h), and what is compared
// is the ensemble's mean, with the statistics of src/studies/ensemble_statistics.h.
//
// Every point of a study runs the same members, so a point's bias against the reference is
// measured seed by seed (the paired t test): the runs of one seed start from one fill.
#pragma once
#include <functional>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "src/scene/scene.h"
#include "src/studies/ensemble_statistics.h"
#include "src/studies/study_runs.h"

namespace kiln {

struct EnsembleOptions {
  int seeds = 0;           // members 0 .. seeds-1; 0: no ensemble, one run of the scene as written
  bool automatic = false;  // --seeds auto: members are added until every point's standard error <= se_target
  double se_target = 0;    // --se (the quantity's unit)
  int max_seeds = 64;      // --max-seeds: the cap of --seeds auto (and of recommend's grown ensembles)
  bool max_seeds_given = false;
  double level = 0.95;     // --level: confidence level of every interval and test
  double power = 0.8;      // the power at which the smallest detectable bias is stated
  double tolerance = 0;    // --tolerance: the bias the user accepts (the quantity's unit); 0: none
  bool level_given = false;  // --level was given
  bool on() const { return seeds > 0 || automatic; }
};

// order, sweep and wp: --level and --tolerance judge ensembles, and --max-seeds caps --seeds auto:
// each is refused without them (they were taken and ignored).
void require_seeds_for_statistics(const EnsembleOptions& options);

// The --seeds, --se, --max-seeds, --level and --tolerance options as given, checked together:
// "auto" needs --se; a number needs no --se; two members at least (one has no spread).
// A --max-seeds given (max_seeds_given) is refused with a fixed --seeds N; a --tolerance given
// (tolerance_given) must be above 0.
EnsembleOptions ensemble_options(const std::string& seeds, double se, int max_seeds, bool max_seeds_given, double level,
                                 double tolerance, bool tolerance_given);

// Refuses an ensemble study that cannot mean what it says: a quantity that is not one number per
// run (a field or a list has no ensemble mean here), or a scene that declares nothing random
// (every member would be the same run).
void check_ensemble(const Scene& scene, const std::string& quantity);

// The override that makes a run member m.
std::string member_set(int member);

// The ensemble's members: slot k of every point runs member number(k), the numbers 0, 1, 2, ...
// except those whose scene cannot be built, skipped and named (a fill near its jamming limit
// places fewer discs for some seeds: member 3 of T6 placed 211 of its 214). Only the member's
// draws differ from the scene, which loaded, so such a failure is the draw's.
class Members {
 public:
  Members(std::string scene, std::vector<std::string> sets) : scene_(std::move(scene)), sets_(std::move(sets)) {}
  int number(int slot);
  // Skipped numbers, with the reason of each.
  const std::vector<std::pair<int, std::string>>& skipped() const { return skipped_; }

 private:
  std::string scene_;
  std::vector<std::string> sets_;
  std::vector<int> numbers_;
  int next_ = 0;
  std::vector<std::pair<int, std::string>> skipped_;
};

// Runs every point (a StudyRun giving integrator, step and overrides) as an ensemble of the same
// members; `run` runs a list of StudyRuns (run_study with the study's scene and quantity). With
// automatic, every point starts with 4 members and all grow together (they stay paired) to the
// size the largest standard error asks for, (se / target)^2 times the members so far, until each
// point's standard error is at most the target or the cap is reached. A point with a failed
// member has no statistics (its failure is kept).
struct EnsembleRuns {
  std::vector<std::vector<StudyRun>> points;  // [point][member]
  int members = 0;
  bool target_reached = true;  // false: --seeds auto stopped at its cap
  int rounds = 0;
};
EnsembleRuns run_ensembles(const std::vector<StudyRun>& points, const EnsembleOptions& options, Members& members,
                           const std::function<void(std::vector<StudyRun>&)>& run);

// Members grown in place: each ensemble of `grow` (a point's members so far, in order, and the
// point they run) gets members up to `to` (exclusive), all run as one batch.
struct Growth {
  std::vector<StudyRun>* members;
  StudyRun point;
  int to;
};
void grow_ensembles(const std::vector<Growth>& grow, Members& members,
                    const std::function<void(std::vector<StudyRun>&)>& run);

// The values of a point's members (the first number of each), or empty when a member failed or
// did not measure the quantity.
std::vector<double> member_values(const std::vector<StudyRun>& members);
// The first run failure of a point's members, naming the member ("" when every run ended), and
// whether it was a stability check.
std::string member_failure(const std::vector<StudyRun>& members, bool* unstable = nullptr);
// Why a point whose runs all ended has no values: the first member that did not measure the
// quantity (a heap not yet formed, a window not yet reached), or "".
std::string member_unmeasured(const std::vector<StudyRun>& members, const std::string& quantity);
// Either of the two, the run failure first.
std::string member_problem(const std::vector<StudyRun>& members, const std::string& quantity);

// An ensemble's statistics at `level`, with each member's value (members 0, 1, ... in slot order).
nlohmann::json ensemble_json(const std::vector<double>& values, double level);
nlohmann::json bias_json(const Bias& b, double tolerance);
// How a study says what its ensembles are, for headings and JSON.
nlohmann::json ensemble_settings_json(const EnsembleOptions& o, const EnsembleRuns& runs, const Members& members);
std::string ensemble_heading(const EnsembleOptions& o, const EnsembleRuns& runs, const Members& members,
                             const std::string& reference);

}  // namespace kiln
