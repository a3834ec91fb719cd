// What the study commands share: independent runs of one scene with different integrators and
// steps, spread over threads and, under mpirun, over ranks (src/studies/study_ranks.h; each run writes
// only its own slot, so results never depend on the number of threads or ranks), and the
// quantities they can be compared on.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "src/run/simulation.h"
#include "src/run/stability.h"
#include "src/scene/scene.h"

namespace kiln {

struct StudyRun {
  StudyRun(std::string name, double step, std::vector<std::string> extra = {})
      : integrator(std::move(name)), dt(step), sets(std::move(extra)) {}
  std::string integrator;
  double dt;
  std::vector<std::string> sets;  // further overrides (rtol, ...)
  int repeats = 1;                // timed runs after one warm-up when > 1; the minimum is kept
  bool limit_at_end = false;      // ask for the stability limit on the contacts at the run's end
  // Results.
  std::vector<double> value;  // the studied quantity at the end
  long rhs_evals = 0;
  double seconds = 0;         // wall time (the minimum over the repeats; a failed run's until it failed)
  bool unstable = false;      // stopped by a stability check
  std::string failure;        // why it failed, if it did
  nlohmann::json at_end;      // that limit (src/run/stability.h limit_json), when asked and it ran to the end
};

// Runs scene (with `sets`) to t_end for every run, showing how many have finished on a terminal
// unless quiet. Under mpirun each rank runs a share on its `threads` workers (0: every core it may
// run on) and every rank ends with every run's results; throws RankFailed when another rank failed.
// With heat_stage the runs' integrators and steps are the frozen heating stage's (freeze.integrator,
// freeze.dt): the scene settles the same way in every run.
void run_study(const std::string& scene, const std::vector<std::string>& sets, double t_end, const std::string& quantity,
               std::vector<StudyRun>& runs, int threads, bool quiet = true, bool heat_stage = false);

// Quantities a scene can be studied on: its state fields, then every number and list its report:
// adds (the observer catalogue's keys, src/scene/observer_catalogue.h), then every run's own
// figures: mean_contacts and, per wall, walls.<name>.mean_torque, mean_power and mean_force (a
// list of x and y), the loads averaged over the run as summary.json gives them. A list (bounce heights,
// layers, walls) is compared as the fields are, as a vector: max abs over its elements, over those
// both runs have when their lengths differ.
std::vector<std::string> study_quantities(const Scene& scene);
// The case's figures of merit (the catalogue's headline keys), which `kiln sweep` studies by default.
std::vector<std::string> headline_quantities(const Scene& scene);
// What a valid quantity is: a state field, a list or one number (a case scalar).
enum class QuantityShape { field, list, number };
QuantityShape shape_of(const Scene& scene, const std::string& quantity);
// What a study compares when no quantity is given: the temperatures of a scene whose mechanics are
// frozen (its positions never move) or of a study of the heating stage, the positions otherwise.
std::string default_quantity(const Scene& scene, bool heat_stage = false);
// Fails with the available quantities, nearest first, unless `quantity` is one of them.
void check_quantity(const Scene& scene, const std::string& quantity);

// The reference values of a study: the registered exact solution ("analytic"), or the same scene
// run with Dormand-Prince adaptive at `fine_rtol` (1e-11 unless a study asks otherwise: stiff
// scenes with many contact onsets cost minutes there) from `fine_dt` ("fine"). A fine reference's
// accuracy is measured, not assumed: its largest difference from the same run at a tenth of the
// tolerance, whose own error is about ten times smaller where the error follows the tolerance
// (and round-off where neither can go lower). Fails with the registered solutions when there is
// none.
// Throws InputError, beginning with `what`, when t_end / dt steps exceed kiln run's step-count
// limit (its moving steps, or the heating's with `heat_stage`).
void refuse_too_many_steps(const Scene& base, double dt, double t_end, bool heat_stage, const std::string& what);

struct StudyReference {
  std::vector<double> value;
  double accuracy = 0;  // max abs over the components; 0: exact
};
StudyReference study_reference(const Scene& scene, const std::string& path, const std::vector<std::string>& sets,
                               const std::string& quantity, double t_end, const std::string& kind, double fine_dt,
                               double fine_rtol, bool heat_stage = false);

// The step limit that binds a study's runs of `integrator`: conduction's alone on a frozen scene
// (or the heating stage), the smaller of the two on a thermal scene that moves, the contacts'
// otherwise. Conduction's is 2 / lambda_max times the integrator's reach on the negative real axis
// / 2 (none for IMEX, whose moving scenes are then bound by their contacts), on the network at
// t = 0 (what check refuses by); the heating stage's network forms during the run, and the
// dense-packing estimate stands for it.
struct StudyLimit {
  double dt = INFINITY;
  bool conduction = false;  // conduction's limit binds
};
StudyLimit study_limit(const StabilityEstimate& est, const Scene& scene, const std::string& integrator, bool heat_stage);

// A study whose every run failed has no figure to report: StudyError naming the first run's reason.
void require_a_result(const std::vector<StudyRun>& runs);

// Over the elements both have; NaN when there are none or one is NaN (a figure not measured).
double max_abs_difference(const std::vector<double>& a, const std::vector<double>& b);

// The value of `quantity` at the end of a run: a field, or the summary's value at the catalogue
// key's path (null, not measured: NaN).
std::vector<double> quantity_value(const std::string& quantity, const FinalFields& fields, const nlohmann::json& summary);

}  // namespace kiln
