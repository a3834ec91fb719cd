// `kiln recommend`: the cheapest integrator and step that give one quantity of a scene to a
// tolerance, found by a short staged probe, with the table that justifies it and what it did not try.
//
// The probe. Each candidate integrator starts at 0.9 of its own stability limit on the scene
// (src/run/stability.h: a step beyond it is never probed, so never recommended) and halves its
// step, round by round, all candidates' runs of a round in parallel. A candidate stops once a step
// meets the tolerance (smaller steps only cost more), once its next step would cost more than the
// cheapest step found so far that meets it (a halving doubles the cost), after `halvings` steps,
// or when the budget is spent. The error of a step is:
//  - on a scene that declares nothing random: its difference from the exact value where one is
//    registered, else from a fine adaptive run whose own accuracy is measured and added;
//  - on a chaotic scene (one that declares a seed): the bias of its ensemble mean against the
//    reference ensemble (the candidate of highest order at a quarter of its finest step),
//    paired seed by seed; it meets the tolerance when its whole confidence interval lies within
//    it. The members are as many as the reference's standard error asks for (--seeds auto with
//    --se a quarter of the tolerance, unless --seeds says otherwise).
// The cost of a step is the wall time of one run on one thread (a single run of the scene at
// that step is what a user pays for), measured once per run.
#pragma once
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "src/studies/study_ensemble.h"

namespace kiln {

struct RecommendOptions {
  std::string scene;
  std::vector<std::string> sets;
  std::string quantity;                 // required: a state field or a case quantity
  std::vector<std::string> integrators = {"velocity-verlet", "erk2", "erk4"};
  double budget = 0;                    // CPU seconds for every run of the probe; 0: no budget
  int halvings = 6;                     // steps probed per candidate, at most
  double fine_rtol = 1e-11;             // the fine reference run's tolerance (scenes without randomness)
  double t_end = 0;
  std::string out_dir;
  int threads = 0;
  bool heat_stage = false;
  bool quiet = false;
  EnsembleOptions ensemble;  // tolerance: the error asked for (--tolerance, required)
};

nlohmann::json run_recommend(const RecommendOptions& options);

}  // namespace kiln
