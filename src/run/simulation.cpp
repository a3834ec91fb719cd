#include "src/run/simulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <ctime>
#include <memory>
#include <random>
#include <sstream>

#include "integrators/integrator.h"
#include "src/base/wall_clock.h"
#include "src/dem/dem_system.h"
#include "src/base/error.h"
#include "src/observers/observer.h"
#include "src/scene/overrides.h"
#include "src/base/progress.h"
#include "src/base/text_format.h"
#include "src/output/run_outputs.h"
#include "src/scene/scene_yaml.h"
#include "src/run/stability_guard.h"
#include "src/dem/stage_profile.h"
#include "src/base/stop_signal.h"
#include "src/dem/frozen_conduction.h"

namespace kiln {

namespace {

// The steps a stage took: what summary.json reports as step_size (a fixed-step run shows dt,
// and a shorter last step where t_end is not a multiple of dt).
struct StepSizes {
  long count = 0;
  double min = INFINITY, max = 0, sum = 0, last = 0;
  void add(double h) {
    ++count;
    min = std::min(min, h);
    max = std::max(max, h);
    sum += h;
    last = h;
  }
  void merge(const StepSizes& o) {
    if (o.count == 0) return;
    count += o.count;
    min = std::min(min, o.min);
    max = std::max(max, o.max);
    sum += o.sum;
    last = o.last;
  }
  nlohmann::json json() const {
    if (count == 0) return {{"steps", 0}};
    return {{"steps", count}, {"min", min}, {"max", max}, {"mean", sum / count}, {"last", last}};
  }
  void state(SnapshotFields& f, const std::string& key) { f.reals(key, count, min, max, sum, last); }
};

nlohmann::json ledger_json(const EnergyLedger& e, const EnergyLedger& initial, bool thermal) {
  nlohmann::json j = {{"kinetic", e.kinetic},
          {"potential", e.potential},
          {"elastic", e.elastic},
          {"dissipated_damping", e.dissipated_damping},
          {"dissipated_friction", e.dissipated_friction},
          {"work_by_walls", e.work_by_walls},
          {"initial_total", initial.total()},
          {"balance_error", balance_error(initial, e)}};
  if (thermal) {
    j["thermal"] = e.thermal;
    j["thermal_change"] = e.thermal - initial.thermal;
    j["heat_from_walls"] = e.heat_from_walls;
    j["heat_from_dissipation"] = e.heat_from_dissipation;
  }
  return j;
}

std::vector<double> ledger_values(const EnergyLedger& e) {
  return {e.kinetic, e.potential, e.elastic, e.dissipated_damping, e.dissipated_friction,
          e.work_by_walls, e.thermal, e.heat_from_walls, e.heat_from_dissipation};
}

EnergyLedger ledger_of(const std::vector<double>& v) {
  EnergyLedger e;
  e.kinetic = v.at(0);
  e.potential = v.at(1);
  e.elastic = v.at(2);
  e.dissipated_damping = v.at(3);
  e.dissipated_friction = v.at(4);
  e.work_by_walls = v.at(5);
  e.thermal = v.at(6);
  e.heat_from_walls = v.at(7);
  e.heat_from_dissipation = v.at(8);
  return e;
}

// An integrator's statistics over a run resumed from checkpoints: counts and seconds add up, the
// rest (last step, names) is the latest segment's.
nlohmann::json merged_statistics(const nlohmann::json& before, nlohmann::json now) {
  for (const auto& [key, value] : before.items()) {
    if (!now.contains(key)) continue;
    const bool seconds = key.size() > 8 && key.compare(key.size() - 8, 8, "_seconds") == 0;
    if (value.is_number_integer() && now[key].is_number_integer())
      now[key] = value.get<long long>() + now[key].get<long long>();
    else if (seconds && value.is_number() && now[key].is_number())
      now[key] = value.get<double>() + now[key].get<double>();
  }
  return now;
}

// A run's identity: 64 random bits in hex, and the time it started (UTC, ISO 8601).
std::string new_run_id() {
  std::random_device device;
  std::ostringstream s;
  s << std::hex << ((static_cast<unsigned long long>(device()) << 32) | device());
  return s.str();
}

std::string utc_now() {
  const std::time_t now = std::time(nullptr);
  std::tm utc{};
  gmtime_r(&now, &utc);
  char text[32];
  std::strftime(text, sizeof text, "%Y-%m-%dT%H:%M:%SZ", &utc);
  return text;
}

// One run: the state, its two stages (mechanics, then after a freeze heat alone), the frames,
// the checks and the checkpoints. Everything a checkpoint must hold is a member.
class SceneRun {
 public:
  SceneRun(const Scene& scene, const RunOptions& options);
  nlohmann::json go();

 private:
  nlohmann::json run_and_publish();
  enum class Ended { at_end, at_rest, frozen, signal };
  enum Phase { mechanics_stage = 0, heat_stage = 1 };  // the stages of a run (not of a step)
  void start_fresh();
  void resume(const Snapshot& s);
  void enter_heat_stage(bool freezing, const Snapshot* s);
  Ended run_stage(Integrator& stepper, bool moving);
  Ended at_frame(bool moving, bool at_end);
  void count_contacts();
  void integrate_wall_loads(double h);
  void save_checkpoint();
  void state(SnapshotFields& f);
  void parts(SnapshotFields& f);
  void close_stage(Integrator& stepper, nlohmann::json& stats);
  nlohmann::json summary(Ended ended);
  double checkpoint_every() const {
    return options_.checkpoint_every > 0 ? options_.checkpoint_every : scene_.t_end / 20;
  }
  double frame_time(double index) const { return stage_t0_ + index * stage_interval_; }
  // The run's stages and the system's, integration being the steps less the system's stages.
  StageProfile profile() const {
    StageProfile p = profile_;
    p.merge(system_.profile());
    double inside = 0;
    for (Stage st : {Stage::neighbour_update, Stage::particle_contacts, Stage::wall_contacts, Stage::conduction})
      inside += system_.profile().seconds(st);
    p.add(Stage::integration, -std::min(inside, profile_.seconds(Stage::integration)));
    return p;
  }

  const Scene& scene_;
  const RunOptions& options_;
  const std::chrono::steady_clock::time_point wall_start_ = std::chrono::steady_clock::now();
  DemSystem system_;
  std::vector<double> y_;
  std::vector<std::unique_ptr<Observer>> observers_;
  std::unique_ptr<Integrator> integrator_;  // the mechanical stage's
  std::unique_ptr<thermal::FrozenConduction> network_;
  std::unique_ptr<Integrator> heat_stepper_;
  std::string heat_integrator_;
  EnergyLedger initial_;
  std::unique_ptr<StabilityGuard> guard_;
  std::unique_ptr<RunOutputs> files_;
  Progress progress_;
  StageProfile profile_;  // the run's own stages; the system keeps those of its evaluations
  std::string run_id_, start_time_;
  std::vector<double> resumed_at_;  // the times this run was resumed from checkpoints
  double wall_before_ = 0;          // wall seconds of the segments before the latest resume

  double t_ = 0;
  // The stage now running: which, where it started, its step, frame interval, steps taken, the
  // index of the latest frame time reached (a double: an interval far below the step makes it
  // huge), step sizes, and its integrator's counts from segments before a resume.
  Phase stage_ = mechanics_stage;
  double stage_t0_ = 0, stage_dt_ = 0, stage_interval_ = 0;
  long stage_steps_ = 0;
  double stage_frame_ = 0;
  StepSizes stage_sizes_;
  long stage_rhs_before_ = 0;
  nlohmann::json stage_stats_before_ = nlohmann::json::object();
  double heat_wall_before_ = 0;
  std::chrono::steady_clock::time_point heat_start_;
  // RunOptions::time_from_step: when the timed steps began, and the counts then.
  std::chrono::steady_clock::time_point timed_start_;
  long timed_steps_before_ = -1, timed_rhs_before_ = 0, timed_rebuilds_before_ = 0;
  double timed_seconds_ = 0, timed_neighbour_before_ = 0, timed_neighbour_seconds_ = 0;
  long timed_steps_ = 0, timed_rhs_ = 0, timed_rebuilds_ = 0;
  DemSystem::ContactCount timed_contacts_;  // at the end of the timed steps
  double next_checkpoint_ = INFINITY;
  // The run stopped at rest (its stop condition) at t_: saved with its last checkpoint, so that a run
  // whose publication failed there resumes to publish, not to step on past its rest.
  bool stopped_at_rest_ = false;
  long last_checkpoint_step_ = -1;

  // Totals of finished stages, the frames' ledger history and coordination numbers.
  long total_steps_ = 0, total_rhs_ = 0;
  StepSizes all_steps_;
  std::vector<double> history_time_, history_error_;
  double contacts_sum_ = 0;
  long contact_samples_ = 0;
  // Each wall's force (x, y), torque and power integrated over the steps: summary.json's time means.
  std::vector<double> wall_sums_;
  double wall_time_ = 0;
  double frozen_at_ = NAN;
  nlohmann::json frozen_network_, integrator_stats_ = nlohmann::json::object();
};

SceneRun::SceneRun(const Scene& scene, const RunOptions& options)
    : scene_(scene), options_(options), system_(scene), progress_(scene.name, options.quiet) {
  y_ = system_.initial_state();
  for (const std::string& name : scene.report) observers_.push_back(make_observer(name, system_));
  integrator_ = make_integrator(scene.integrator, scene.control);
  heat_integrator_ = scene.frozen || scene.freeze.integrator.empty() ? scene.integrator : scene.freeze.integrator;
}

void SceneRun::start_fresh() {
  run_id_ = new_run_id();
  start_time_ = utc_now();
  if (scene_.frozen) {
    system_.prepare(0, y_.data(), 0);
  } else {
    integrator_->start(system_, 0.0, y_.data(), scene_.dt);
  }
  initial_ = system_.energy(0, y_.data());
  guard_ = std::make_unique<StabilityGuard>(scene_, system_, initial_, *options_.estimate);
  if (!options_.out_dir.empty()) {
    files_ = std::make_unique<RunOutputs>(options_.out_dir, system_, run_id_);
    files_->frame(0, y_.data());
  }
  for (auto& o : observers_) o->sample(0, y_.data());
  history_time_ = {0.0};
  history_error_ = {0.0};
  count_contacts();
  stage_t0_ = 0;
  stage_dt_ = scene_.dt;
  stage_interval_ = scene_.output_interval;
  // A run killed at any point can be resumed: a checkpoint of the start, then one every
  // checkpoint_every (a twentieth of the run by default).
  next_checkpoint_ = checkpoint_every();
  save_checkpoint();
}

nlohmann::json SceneRun::go() {
  try {
    return run_and_publish();
  } catch (const OutputError& e) {
    // A full disk: what the run finished stays, for a restart once there is room.
    if (files_) throw OutputError(e.what() + files_->keep_finished_work());
    throw;
  }
}

nlohmann::json SceneRun::run_and_publish() {
  if (options_.resume) {
    resume(*options_.resume);
    // Checkpointed at t_end but not published (its output failed, or it was killed while
    // publishing): its last frame, which followed that checkpoint, is written again.
    if (files_ && t_ >= scene_.t_end - 1e-9 * stage_dt_ && files_->last_frame_time() < t_ - 1e-9 * stage_dt_)
      at_frame(stage_ == mechanics_stage && !scene_.frozen, true);
  } else {
    start_fresh();
  }
  Ended ended = Ended::frozen;
  if (stopped_at_rest_) {
    ended = Ended::at_rest;  // resumed to publish (above): nothing is stepped
    close_stage(*integrator_, integrator_stats_);
  } else if (stage_ == mechanics_stage && !scene_.frozen) {
    guard_->set_stage(scene_.dt);
    ended = run_stage(*integrator_, true);
    close_stage(*integrator_, integrator_stats_);
  }
  if (stage_ == heat_stage && options_.resume) {
    ended = run_stage(*heat_stepper_, false);
    close_stage(*heat_stepper_, scene_.frozen ? integrator_stats_ : integrator_stats_["heat_stage"]);
  } else if (ended == Ended::frozen && options_.stop_at_freeze) {
    frozen_at_ = t_;
  } else if (ended == Ended::frozen) {
    enter_heat_stage(true, nullptr);
    ended = t_ < scene_.t_end ? run_stage(*heat_stepper_, false) : Ended::at_end;
    close_stage(*heat_stepper_, scene_.frozen ? integrator_stats_ : integrator_stats_["heat_stage"]);
  }
  progress_.finish();
  nlohmann::json s = summary(ended);
  if (files_) {
    std::ostringstream title;
    title << scene_.name << "   t = " << t_ << " s of " << scene_.t_end << " s";
    std::vector<ResultTable> tables;
    for (const auto& o : observers_) o->tables(tables);
    files_->finish(t_, y_.data(), s, title.str(), tables);
  }
  if (ended == Ended::signal) {
    s["stopped_by"] = signal_name(stop_signal());
    if (files_) s["checkpoint"] = files_->checkpoint_path();
  }
  return s;
}

// Freeze (freezing: at the end of settling; otherwise a thermal-only scene or a resumed heat
// stage): the residual kinetic energy is removed (booked as dissipated), the conductances of the
// contact network are fixed, and only the temperatures are integrated from here on.
void SceneRun::enter_heat_stage(bool freezing, const Snapshot* s) {
  if (freezing) {
    frozen_at_ = t_;
    const EnergyLedger before = system_.energy(t_, y_.data());
    for (int k = system_.vx_at(); k < system_.ledger_at(); ++k) y_[k] = 0;
    y_[system_.ledger_at() + ledger_damping] += before.kinetic;
  }
  // The network depends only on the frozen positions and contact lists, unchanged since the freeze.
  network_ = std::make_unique<thermal::FrozenConduction>(thermal::freeze_network(system_, frozen_at_, y_.data()));
  // Explicit stepping of the frozen network is stable below 2 / lambda_max (its largest eigenvalue).
  const double stiffest = network_->stiffest_rate();
  frozen_network_ = {{"links", network_->links().size()}, {"explicit_dt_limit", 2 / stiffest}};
  heat_stepper_ = make_integrator(heat_integrator_, scene_.control);
  heat_start_ = std::chrono::steady_clock::now();
  if (!s) {
    stage_ = heat_stage;
    stage_t0_ = t_;
    stage_dt_ = scene_.frozen ? scene_.dt : scene_.freeze.dt;
    stage_interval_ = scene_.frozen ? scene_.output_interval
                      : scene_.freeze.output_interval > 0 ? scene_.freeze.output_interval
                                                          : (scene_.t_end - t_) / 100;
    stage_steps_ = 0;
    stage_frame_ = 0;
    stage_sizes_ = {};
    stage_rhs_before_ = 0;
    stage_stats_before_ = nlohmann::json::object();
    heat_wall_before_ = 0;
  }
  guard_->set_stage(stage_dt_, real_stability_of(heat_integrator_) / stiffest);
  if (s)
    heat_stepper_->resume(*network_, y_.data() + system_.ledger_at(), stage_dt_, *s, "integrator.");
  else
    heat_stepper_->start(*network_, t_, y_.data() + system_.ledger_at(), stage_dt_);
}

// The loads of each step's last evaluation, times the step (a rectangle rule over the steps).
void SceneRun::integrate_wall_loads(double h) {
  const auto& loads = system_.wall_loads();
  wall_sums_.resize(4 * loads.size());
  for (size_t w = 0; w < loads.size(); ++w) {
    wall_sums_[4 * w] += h * loads[w].force.x;
    wall_sums_[4 * w + 1] += h * loads[w].force.y;
    wall_sums_[4 * w + 2] += h * loads[w].torque;
    wall_sums_[4 * w + 3] += h * loads[w].power;
  }
  wall_time_ += h;
}

void SceneRun::count_contacts() {
  const auto c = system_.count_contacts(t_, y_.data());
  contacts_sum_ += (2.0 * c.particle_particle + c.particle_wall) / system_.particles();
  ++contact_samples_;
}

// A frame: written, checked (finite state, energy), sampled; then the stop conditions, which are
// decided at frames.
SceneRun::Ended SceneRun::at_frame(bool moving, bool at_end) {
  EnergyLedger now;
  {
    const StageTimer timer(profile_, Stage::checks);
    guard_->finite(t_, y_.data(), system_.layout().size());
    now = system_.energy(t_, y_.data());
    guard_->energy(t_, y_.data(), now);
  }
  history_time_.push_back(t_);
  history_error_.push_back(balance_error(initial_, now));
  {
    const StageTimer timer(profile_, Stage::output);
    if (files_) files_->frame(t_, y_.data());
  }
  count_contacts();
  progress_.update(t_, scene_.t_end);
  if (moving && !at_end && scene_.stop_kinetic_energy > 0 && t_ >= scene_.stop_not_before &&
      now.kinetic < scene_.stop_kinetic_energy)
    return Ended::at_rest;
  if (moving && !at_end && scene_.freeze.enabled &&
      ((t_ >= scene_.freeze.not_before && now.kinetic < scene_.freeze.kinetic_energy_below) ||
       t_ >= scene_.freeze.latest))
    return Ended::frozen;
  return Ended::at_end;
}

// Steps one stage to t_end (steps of dt, or adaptive), with a frame every stage_interval_.
// Steps are never cut to land on frames: a frame is the state of the step that reaches its time
// (stamped with that step's time), found by index from the stage's start, so any interval, however
// small against the step, costs one frame per step at most. Only the last step may be shorter, to
// end on t_end. A checkpoint follows the frame bookkeeping of its step and precedes the extra final
// frame of a run that ends (or is stopped) off the frame interval: a resumed run writes exactly the
// frames an uninterrupted one does.
SceneRun::Ended SceneRun::run_stage(Integrator& stepper, bool moving) {
  const double tol = 1e-9 * stage_dt_;
  stepper.set_stop_time(scene_.t_end);
  const bool timed = moving && options_.time_from_step >= 0;
  while (t_ < scene_.t_end - tol) {
    if (timed && stage_steps_ == options_.time_from_step) {
      timed_start_ = std::chrono::steady_clock::now();
      timed_steps_before_ = stage_steps_;
      timed_rhs_before_ = stepper.stats().rhs_evals;
      timed_rebuilds_before_ = system_.rebuilds();
      timed_neighbour_before_ = system_.profile().seconds(Stage::neighbour_update);
    }
    {
      const StageTimer timer(profile_, Stage::integration);  // less the system's stages, in summary()
      stepper.step();
    }
    ++stage_steps_;
    t_ = stepper.time();
    const double h = stepper.stats().last_step;
    stage_sizes_.add(h);
    {
      const StageTimer timer(profile_, Stage::checks);
      if (moving) guard_->every_step(t_, y_.data(), h);
      guard_->temperatures(t_, y_.data());
    }
    if (moving) integrate_wall_loads(h);
    {
      const StageTimer timer(profile_, Stage::observers);
      for (auto& o : observers_) o->sample(t_, y_.data());
    }
    const bool at_end = t_ >= scene_.t_end - tol;
    const bool regular = t_ >= frame_time(stage_frame_ + 1) - tol;
    Ended ended = Ended::at_end;
    if (regular) {
      // The latest frame time this step reached, by one division (counting the intervals passed
      // one by one never ended for an interval of 1e-300 s), then exact against frame_time().
      double f = std::max(stage_frame_ + 1, std::floor((t_ - stage_t0_ + tol) / stage_interval_));
      if (frame_time(f + 1) <= t_ + tol) f += 1;
      if (f > stage_frame_ + 1 && frame_time(f) > t_ + tol) f -= 1;
      stage_frame_ = f;
      ended = at_frame(moving, at_end);
    } else if (stage_steps_ % 64 == 0) {
      guard_->finite(t_, y_.data(), system_.layout().size());
    }
    const int signal = options_.stop_on_signal ? stop_signal() : 0;
    const bool stops = at_end || signal || ended == Ended::at_rest;
    stopped_at_rest_ = ended == Ended::at_rest;
    if (t_ >= next_checkpoint_ - tol || (stops && files_)) {
      // The next checkpoint time after this step, by one division: adding the interval until it
      // passed the step never ended where the step had jumped far ahead of the schedule.
      if (next_checkpoint_ <= t_ + tol) {
        next_checkpoint_ += checkpoint_every() * (std::floor((t_ + tol - next_checkpoint_) / checkpoint_every()) + 1);
        if (next_checkpoint_ <= t_ + tol) next_checkpoint_ += checkpoint_every();  // the division's rounding
      }
      const StageTimer timer(profile_, Stage::output);
      save_checkpoint();
    }
    if (stops && !regular) at_frame(moving, true);
    if (signal) return Ended::signal;
    if (ended != Ended::at_end) return ended;
  }
  return Ended::at_end;
}

void SceneRun::close_stage(Integrator& stepper, nlohmann::json& stats) {
  if (timed_steps_before_ >= 0 && stage_ == mechanics_stage) {
    timed_seconds_ = seconds_since(timed_start_);
    timed_steps_ = stage_steps_ - timed_steps_before_;
    timed_rhs_ = stepper.stats().rhs_evals - timed_rhs_before_;
    timed_rebuilds_ = system_.rebuilds() - timed_rebuilds_before_;
    timed_neighbour_seconds_ = system_.profile().seconds(Stage::neighbour_update) - timed_neighbour_before_;
    timed_contacts_ = system_.count_contacts(t_, y_.data());
  }
  total_steps_ += stage_sizes_.count;  // the steps the run kept (ARKODE's count adds redone ones)
  total_rhs_ += stage_rhs_before_ + stepper.stats().rhs_evals;
  stats = merged_statistics(stage_stats_before_, stepper.statistics());
  stats["step_size"] = stage_sizes_.json();
  all_steps_.merge(stage_sizes_);
  if (stage_ == heat_stage) {
    stats["integrator"] = heat_integrator_;
    stats["dt"] = stage_dt_;
    stats["rhs_evals"] = stage_rhs_before_ + stepper.stats().rhs_evals;
    stats["wall_seconds"] = heat_wall_before_ + seconds_since(heat_start_);
  }
}

// Everything that changes during a run, with the scene it belongs to.
void SceneRun::save_checkpoint() {
  if (!files_ || options_.source.text.empty() || last_checkpoint_step_ == total_steps_ + stage_steps_) return;
  last_checkpoint_step_ = total_steps_ + stage_steps_;
  Snapshot s;
  s.put_text("kiln_version", KILN_VERSION);
  s.put_text("scene.file", options_.source.file);
  s.put_text("scene.text", options_.source.text);
  std::string overrides;
  for (const std::string& o : options_.source.overrides) overrides += o + '\n';
  s.put_text("scene.overrides", overrides);
  std::string inputs;
  for (const std::string& i : scene_.inputs) inputs += i + '\n';
  s.put_text("scene.inputs", inputs);
  s.put("scene.output_interval", scene_.output_interval);
  s.put_integer("frames", files_->frames());
  SnapshotFields fields(s, "");
  state(fields);
  Integrator& stepper = stage_ == mechanics_stage ? *integrator_ : *heat_stepper_;
  SnapshotFields integrator(s, "integrator.");
  stepper.state(integrator);
  parts(fields);
  files_->checkpoint(s);
}

// What the run itself carries from step to step; what a saving run computes (seconds, counts,
// statistics of the running stage) is read back as what the resumed run starts from.
void SceneRun::state(SnapshotFields& f) {
  const bool saving = f.saving();
  f.field("run_id", run_id_);
  f.field("start_time", start_time_);
  f.field("time", t_);
  f.field("state", y_);  // a resumed run has checked its length
  f.field("resumed_at", resumed_at_);
  double wall = saving ? wall_before_ + seconds_since(wall_start_) : 0;
  f.field("wall_seconds", wall);
  std::vector<double> stages = saving ? profile().values() : std::vector<double>{};
  f.field("profile", stages, {profile().values().size()});
  std::vector<double> initial = saving ? ledger_values(initial_) : std::vector<double>{};
  f.field("initial_ledger", initial, {ledger_values(initial_).size()});
  f.field("history.time", history_time_);
  f.field("history.balance_error", history_error_, {history_time_.size()});
  f.reals("contacts", contacts_sum_, contact_samples_);
  f.field("walls.sums", wall_sums_, {0, 4 * scene_.walls.size()});
  f.field("walls.time", wall_time_);
  f.field("frozen_at", frozen_at_);
  f.field("stopped_at_rest", stopped_at_rest_);
  f.integers("totals", total_steps_, total_rhs_);
  all_steps_.state(f, "all_steps");
  f.field("integrator_stats", integrator_stats_);
  long long stage = stage_;
  f.field("stage", stage);
  const Integrator* stepper = !saving ? nullptr : stage_ == mechanics_stage ? integrator_.get() : heat_stepper_.get();
  double next_checkpoint = next_checkpoint_;
  double heat_wall = saving && stage_ == heat_stage ? heat_wall_before_ + seconds_since(heat_start_) : 0.0;
  f.reals("stage.times", stage_t0_, stage_dt_, stage_interval_, next_checkpoint, heat_wall);
  long rhs = saving ? stage_rhs_before_ + stepper->stats().rhs_evals : 0;
  f.integers("stage.counts", stage_steps_, rhs);
  f.field("stage.frame", stage_frame_);
  stage_sizes_.state(f, "stage.step_sizes");
  nlohmann::json stage_statistics = saving ? merged_statistics(stage_stats_before_, stepper->statistics()) : nlohmann::json();
  f.field("stage.statistics", stage_statistics);
  if (saving) return;
  // Times a run cannot go on from: a step that does not advance the time, frames or checkpoints
  // behind it (a changed checkpoint hung the run in its step loop).
  if (!(std::isfinite(t_) && t_ >= 0 && std::isfinite(stage_t0_) && stage_t0_ <= t_ && stage_dt_ > 0 &&
        t_ + stage_dt_ > t_ && t_ + scene_.dt > t_ && std::isfinite(stage_interval_) && stage_interval_ > 0 &&
        std::isfinite(next_checkpoint) && next_checkpoint >= t_))
    throw Snapshot::layout_error(f.source(), "holds times a run cannot go on from (time, stage start, step, frame "
                                             "interval or next checkpoint)");
  // Values that must agree with the time and the scene (issue 28's second review, each resumed
  // into a wrong summary or an off-grid frame with fresh checksums): the stage's last frame at or
  // before the time and its next after it; earlier resumptions in order and not after it; counts
  // not negative; a freeze time only where the scene freezes, not after the time, and in the heat
  // stage.
  const double slack = 1e-6 * stage_interval_;
  const bool frames_agree = stage_frame_ >= 0 && stage_frame_ == std::floor(stage_frame_) &&
                            frame_time(stage_frame_) <= t_ + slack && frame_time(stage_frame_ + 1) > t_ - slack;
  bool resumptions_agree = true;
  for (size_t k = 0; k < resumed_at_.size(); ++k)
    resumptions_agree = resumptions_agree && std::isfinite(resumed_at_[k]) && resumed_at_[k] >= 0 &&
                        resumed_at_[k] <= t_ && (k == 0 || resumed_at_[k] >= resumed_at_[k - 1]);
  const bool freezes = scene_.freeze.enabled || scene_.frozen;
  const bool freeze_agrees = std::isnan(frozen_at_) ? stage != heat_stage || scene_.frozen
                                                    : freezes && frozen_at_ >= 0 && frozen_at_ <= t_;
  if (!frames_agree || !resumptions_agree || !freeze_agrees || total_steps_ < 0 || total_rhs_ < 0 ||
      stage_steps_ < 0 || rhs < 0)
    throw InputError(f.source() + ": the checkpoint holds " +
                     (!frames_agree        ? "a stage frame ('stage.frame')"
                      : !resumptions_agree ? "times of earlier resumptions ('resumed_at')"
                      : !freeze_agrees     ? "a freeze time ('frozen_at')"
                                           : "a negative count ('totals', 'stage.counts')") +
                     " that disagrees with its own time and its scene: a changed checkpoint, refused");
  resumed_at_.push_back(t_);
  wall_before_ = wall;
  profile_.set_values(stages);  // the system's stages of earlier segments counted here
  initial_ = ledger_of(initial);
  stage_ = stage == heat_stage ? heat_stage : mechanics_stage;
  next_checkpoint_ = options_.checkpoint_every > 0 ? t_ + options_.checkpoint_every : next_checkpoint;
  heat_wall_before_ = heat_wall;
  stage_rhs_before_ = rhs;
  stage_stats_before_ = stage_statistics;
}

// The states of the run's parts, each under its own keys: the system, the checks, the observers.
void SceneRun::parts(SnapshotFields& f) {
  SnapshotFields system = f.within("system."), checks = f.within("checks.");
  system_.state(system);
  if (!f.saving()) guard_ = std::make_unique<StabilityGuard>(scene_, system_, initial_, *options_.estimate);
  guard_->state(checks);
  for (size_t k = 0; k < observers_.size(); ++k) {
    SnapshotFields observer = f.within("observer." + std::to_string(k) + ".");
    observers_[k]->state(observer);
  }
}

void SceneRun::resume(const Snapshot& s) {
  const double t = s.real("time");
  const int frames = s.integer_as<int>("frames", 0);  // 1e15 frames was said as "-1530494976 frames"
  const std::vector<double>& state_vector = s.reals("state");
  if (state_vector.size() != y_.size())
    throw InputError("the checkpoint's state has " + std::to_string(state_vector.size()) + " components, this scene's " +
                     std::to_string(y_.size()));
  SnapshotFields fields(s, "");
  state(fields);
  // Places and speeds no run can reach, refused: beyond 1e6 m from the origin along an axis that
  // is not periodic (a coordinate times 1e10 with fresh checksums was resumed and crashed the heap
  // observer), beyond 1e9 m along a periodic one, where the state keeps unwrapped positions (a
  // micrometre of resolution left: 1e300 could no longer move), and faster than light, for
  // particles, their rims and wall bodies alike (issue 28's reviews: each was resumed).
  const auto reach = [&](bool periodic) { return periodic ? 1e9 : farthest_coordinate; };
  for (int i = 0; i < system_.particles(); ++i) {
    const double x = y_[system_.x_at() + i], y = y_[system_.y_at() + i];
    if (!(std::abs(x) <= reach(scene_.periodic.x)) || !(std::abs(y) <= reach(scene_.periodic.y)))
      throw InputError(s.source() + ": the checkpoint places particle " + std::to_string(i) + " at (" +
                       format("%g, %g", x, y) + ") m in 'state', beyond 1e6 m from the origin (1e9 m along a "
                       "periodic axis), where no run can take one: refused");
    const double v = std::hypot(y_[system_.vx_at() + i], y_[system_.vy_at() + i]);
    const double rim = system_.omega_at() < 0 ? 0.0 : std::abs(y_[system_.omega_at() + i]) * system_.radius(i);
    if (!(v <= speed_of_light) || !(rim <= speed_of_light))
      throw InputError(s.source() + ": the checkpoint gives particle " + std::to_string(i) + " a speed of " +
                       format("%g", std::max(v, rim)) + " m/s in 'state' (its velocity or its rim's), faster than "
                       "light: refused");
  }
  for (int b = 0; b < system_.bodies(); ++b) {
    const double at = y_[system_.body_at() + b], speed = y_[system_.body_speed_at() + b];
    if (!(std::abs(at) <= farthest_coordinate) || !(std::abs(speed) <= speed_of_light))
      throw InputError(s.source() + ": the checkpoint moves a wall body by " + format("%g", at) + " m at " +
                       format("%g", speed) + " m/s in 'state', beyond 1e6 m or faster than light: refused");
  }
  // At t_end, a run that was not published (its output failed, or it was killed publishing) is
  // resumed to publish it.
  const bool published = options_.out_dir.empty() || RunOutputs::published(options_.out_dir, run_id_, t);
  if (!(scene_.t_end > t) && published)
    throw InputError("the checkpoint is at t = " + std::to_string(t) + " s: give a later --t-end to go on");
  // A run that stopped at rest and was published goes on from its rest when resumed (a later
  // --t-end asks for more); one whose publication failed is published.
  if (published) stopped_at_rest_ = false;
  parts(fields);
  if (!options_.out_dir.empty())
    files_ = std::make_unique<RunOutputs>(options_.out_dir, system_, run_id_, frames, s);
  if (stage_ == mechanics_stage) {
    integrator_->resume(system_, y_.data(), scene_.dt, s, "integrator.");
  } else {
    enter_heat_stage(false, &s);
  }
  // The run's time is its integrator's after every step: two times that disagree would each be
  // wrong somewhere (frames stamped with one, states advanced from the other).
  const Integrator& stepper = stage_ == mechanics_stage ? *integrator_ : *heat_stepper_;
  if (stepper.time() != t_)
    throw Snapshot::layout_error(fields.source(), "holds two times of the run: " + std::to_string(t_) +
                                                      " s (time) and its integrator's " +
                                                      std::to_string(stepper.time()) + " s (integrator.time)");
  last_checkpoint_step_ = total_steps_ + stage_steps_;
}

nlohmann::json SceneRun::summary(Ended ended) {
  const EnergyLedger final_energy = system_.energy(t_, y_.data());
  const double wall_seconds = wall_before_ + seconds_since(wall_start_);
  nlohmann::json summary;
  summary["scene"] = scene_.name;
  summary["run_id"] = run_id_;
  summary["start_time"] = start_time_;
  if (!resumed_at_.empty()) summary["resumed_at"] = resumed_at_;
  summary["integrator"] = scene_.integrator;
  summary["dt"] = scene_.dt;
  summary["t_end"] = t_;
  summary["stopped_early"] = ended == Ended::at_rest  ? nlohmann::json("at_rest")
                             : ended == Ended::signal ? nlohmann::json("signal")
                                                      : nlohmann::json(false);
  summary["frozen_at"] = std::isfinite(frozen_at_) ? nlohmann::json(frozen_at_) : nlohmann::json(nullptr);
  if (!frozen_network_.is_null()) summary["frozen_network"] = frozen_network_;
  summary["steps"] = total_steps_;
  summary["step_size"] = all_steps_.json();
  summary["rhs_evals"] = total_rhs_;
  summary["integrator_stats"] = integrator_stats_;
  summary["rtol"] = scene_.control.rtol;
  summary["wall_seconds"] = wall_seconds;
  summary["particle_steps_per_second"] = system_.particles() * static_cast<double>(total_steps_) / wall_seconds;
  summary["particles"] = system_.particles();
  summary["rotation"] = system_.rotates();
  summary["thermal"] = system_.thermal();
  summary["mean_contacts"] = contacts_sum_ / contact_samples_;
  // What the particles did to each wall, averaged over the time the mechanics ran (result.h5 has
  // every frame): force on the wall (N), torque about its centre (N m), power it delivered (W).
  summary["walls"] = nlohmann::json::array();
  for (size_t w = 0; w < scene_.walls.size() && wall_time_ > 0; ++w) {
    const double* sum = wall_sums_.data() + 4 * w;
    const double n = wall_time_;
    summary["walls"].push_back({{"name", scene_.walls[w].name},
                                {"mean_force", {sum[0] / n, sum[1] / n}},
                                {"mean_torque", sum[2] / n},
                                {"mean_power", sum[3] / n}});
  }
  summary["neighbour_rebuilds"] = system_.rebuilds();
  summary["curve_reorders"] = system_.reorders();
  if (timed_steps_before_ >= 0)
    summary["timed"] = {{"from_step", timed_steps_before_}, {"steps", timed_steps_}, {"rhs_evals", timed_rhs_},
                        {"neighbour_rebuilds", timed_rebuilds_}, {"neighbour_update_seconds", timed_neighbour_seconds_},
                        {"seconds", timed_seconds_}, {"particle_contacts", timed_contacts_.particle_particle},
                        {"wall_contacts", timed_contacts_.particle_wall}};
  summary["skin"] = system_.skin();
  summary["energy"] = ledger_json(final_energy, initial_, system_.thermal());
  summary["energy"]["history"] = {{"time", history_time_}, {"balance_error", history_error_}};
  const StabilityEstimate& est = guard_->estimate();
  summary["stability"] = estimate_json(est);
  if (options_.limit_at_end && stage_ == mechanics_stage && !est.integrator.empty())
    if (const auto end = limit_at(system_, t_, y_.data(), system_.layout().size(), est.integrator))
      summary["stability"]["at_end"] = limit_json(*end);
  summary["checks"] = guard_->figures();
  summary["profile"] = profile().json(total_steps_);
  summary["kiln_version"] = KILN_VERSION;
  for (auto& o : observers_) o->report(t_, y_.data(), summary);
  if (options_.final_fields) {
    const int n = system_.particles();
    FinalFields& f = *options_.final_fields;
    f.position.assign(y_.begin() + system_.x_at(), y_.begin() + system_.x_at() + 2 * n);
    f.velocity.assign(y_.begin() + system_.vx_at(), y_.begin() + system_.vx_at() + 2 * n);
    if (system_.thermal())
      f.temperature.assign(y_.begin() + system_.temperature_at(), y_.begin() + system_.temperature_at() + n);
  }
  return summary;
}

}  // namespace

// The estimate comes before the run's system exists: its linearisation and Lanczos basis, several
// times a step's memory, and the run's lists are never held at once (the 100,000-disc bench pile
// peaked at both together), and its seconds are not the run's (a study compares runs by their
// wall time: each run's time included the estimate's, seconds on a few thousand discs).
nlohmann::json run_scene(const Scene& scene, const RunOptions& options) {
  if (options.estimate) return SceneRun(scene, options).go();
  const StabilityEstimate estimate = estimate_stability(scene);
  RunOptions with_estimate = options;
  with_estimate.estimate = &estimate;
  return SceneRun(scene, with_estimate).go();
}

Scene scene_of_checkpoint(const Snapshot& checkpoint, const std::vector<std::string>& overrides, SceneRecord& source) {
  if (checkpoint.text("kiln_version") != KILN_VERSION)
    throw InputError("the checkpoint was written by kiln " + checkpoint.text("kiln_version") + ", this is kiln " +
                     KILN_VERSION + ": its state layout may differ; rerun the scene from the start");
  source.file = checkpoint.text("scene.file");
  source.text = checkpoint.text("scene.text");
  source.overrides.clear();
  std::istringstream lines(checkpoint.text("scene.overrides"));
  for (std::string line; std::getline(lines, line);)
    if (!line.empty()) source.overrides.push_back(line);
  // The frame interval stays the run's (its default follows t_end, which a resumed run changes).
  source.overrides.push_back(assignment("output_interval", checkpoint.real("scene.output_interval")));
  for (const std::string& o : overrides) source.overrides.push_back(o);
  Scene scene = parse_scene(source.text, source.file, source.overrides);
  std::string inputs;
  for (const std::string& i : scene.inputs) inputs += i + '\n';
  if (inputs != checkpoint.text("scene.inputs")) {
    std::string names;
    for (const std::string& i : scene.inputs) names += (names.empty() ? "" : ", ") + i.substr(0, i.find('\t'));
    throw InputError("a drawing the scene reads (" + names + ") has changed since the checkpoint was written: "
                     "its walls would jump; rerun the scene from the start");
  }
  return scene;
}

}  // namespace kiln
