// Where a run's time goes: the wall time of each stage of a step, accumulated over the run.
// `kiln run --profile` prints it; summary.json holds it as `profile` (seconds per stage, and per
// step). The clock is read twice per stage and force evaluation (about 50 ns), which is below a
// percent of an evaluation of any scene with more than a few dozen contacts.
#pragma once
#include <array>
#include <chrono>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace kiln {

enum class Stage {
  neighbour_update,   // candidate lists rebuilt (Box2D tree, merge of the contact history)
  particle_contacts,  // particle-particle contact forces (and heat made by dissipation)
  wall_contacts,      // particle-wall contact forces, wall loads
  conduction,         // heat conducted through contacts and from walls
  integration,        // the integrator's own work: the step less the stages above
  checks,             // stability checks, every step and at frames
  observers,          // case quantities sampled
  output,             // frames and checkpoints written
  count
};

const char* stage_name(Stage s);
// The table of a profile as summary.json holds it (StageProfile::json).
std::string profile_table(const nlohmann::json& profile);

class StageProfile {
 public:
  using Clock = std::chrono::steady_clock;
  void add(Stage s, double seconds) { seconds_[static_cast<int>(s)] += seconds; }
  double seconds(Stage s) const { return seconds_[static_cast<int>(s)]; }
  void merge(const StageProfile& o) {
    for (int k = 0; k < static_cast<int>(Stage::count); ++k) seconds_[k] += o.seconds_[k];
  }
  // Checkpoints: the seconds of every stage, in the order of Stage.
  std::vector<double> values() const { return {seconds_.begin(), seconds_.end()}; }
  void set_values(const std::vector<double>& v) {
    for (size_t k = 0; k < seconds_.size() && k < v.size(); ++k) seconds_[k] = v[k];
  }
  // {"seconds": {stage: s}, "per_step": {stage: s}, "steps": n}
  nlohmann::json json(long steps) const;

 private:
  std::array<double, static_cast<int>(Stage::count)> seconds_{};
};

// Adds the wall time from its construction to its destruction to one stage.
class StageTimer {
 public:
  StageTimer(StageProfile& p, Stage s) : profile_(p), stage_(s), start_(StageProfile::Clock::now()) {}
  ~StageTimer() {
    profile_.add(stage_, std::chrono::duration<double>(StageProfile::Clock::now() - start_).count());
  }
  StageTimer(const StageTimer&) = delete;
  StageTimer& operator=(const StageTimer&) = delete;

 private:
  StageProfile& profile_;
  Stage stage_;
  StageProfile::Clock::time_point start_;
};

}  // namespace kiln
