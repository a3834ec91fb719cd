// `kiln recommend`: the cheapest integrator and step that give one quantity of a scene to a
// tolerance, found by a short staged probe, with the table that justifies it and what it did not try.
//
// The probe. Each candidate starts at 0.9 of its own stability limit on the scene at t = 0
// (src/run/stability.h) and halves its step, round by round, all candidates' runs of a round in
// parallel. Every run also measures the limit on its end state (a settled heap, a formed bed bind
// below t = 0's; an ensemble's members, each its own): a step beyond 0.9 of the smallest limit
// measured on its own runs, at t = 0 or on the candidate's earlier runs is never recommended, and
// after one the probe goes on from 0.8 of that limit (a margin for the spread of the limit between
// members and steps). A step meets the tolerance when its error
// does and its half step's does too (an error small by chance at t_end, as a harmonic contact's
// phase makes it, is not taken); a candidate stops once a step is so confirmed, once its next
// step would cost more than the cheapest confirmed step (a halving doubles the cost), after
// `halvings` steps, at the reference's step, or when the budget would be overrun: each batch of
// runs is predicted from what such runs cost (a failed run counts until it failed) and not
// started when it would end beyond the budget. The error of a step is:
//  - on a scene that declares nothing random: its difference from the exact value where one is
//    registered, else from a fine adaptive run, plus that run's measured accuracy;
//  - on a chaotic scene (one that declares a seed): the bias of its ensemble mean against the
//    reference ensemble (the highest-order candidate at its finest possible step, first / 2^halvings;
//    no candidate runs at or below it, so no half step is the reference itself; that reference's
//    own bias is not measured, and the output says so), paired seed by seed; it
//    meets the tolerance when its whole confidence interval lies within it. Ensembles start with 8
//    members (or --seeds N, fixed; or --max-seeds if smaller) and grow, with the reference's, only
//    while the verdict of a step that could be recommended is open, up to --max-seeds.
// The cost of a step is the wall time of one run on one thread (a single run of the scene at
// that step is what a user pays for); costs within a tenth, or of runs under 10 ms (clock noise),
// are a tie, which fewer forces win.
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
