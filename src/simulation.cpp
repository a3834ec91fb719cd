#include "src/simulation.h"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <filesystem>
#include <memory>
#include <sstream>

#include "integrators/integrator.h"
#include "src/dem_system.h"
#include "src/error.h"
#include "src/observers.h"
#include "src/output_h5.h"
#include "src/outputs.h"
#include "src/progress.h"
#include "src/stability_guard.h"
#include "thermal/frozen_conduction.h"

namespace kiln {

namespace {

// Output files are written under temporary names and renamed only when the run succeeds.
class OutputFiles {
 public:
  OutputFiles(const std::string& dir, const DemSystem& sys, const Scene& scene) : dir_(dir), sys_(sys) {
    if (dir_.empty()) return;
    std::filesystem::create_directories(dir_);
    h5_ = std::make_unique<H5Frames>(path("result.h5.tmp"), sys.particles(), sys.thermal());
    h5_->attribute("scene", scene.name);
    h5_->attribute("integrator", scene.integrator);
    h5_->attribute("dt", scene.dt);
    h5_->attribute("kiln_version", KILN_VERSION);
    std::vector<double> r(sys.particles());
    for (int i = 0; i < sys.particles(); ++i) r[i] = sys.radius(i);
    h5_->write_constant(r);
  }
  ~OutputFiles() {
    if (!done_ && h5_) {
      h5_->close();
      std::filesystem::remove(path("result.h5.tmp"));
    }
  }
  void frame(double t, const double* y) {
    times_.push_back(t);
    if (!h5_) return;
    h5_->append(t, y + sys_.x_at(), y + sys_.y_at(), y + sys_.vx_at(), y + sys_.vy_at(),
                sys_.rotates() ? y + sys_.angle_at() : nullptr, sys_.rotates() ? y + sys_.omega_at() : nullptr,
                sys_.thermal() ? y + sys_.temperature_at() : nullptr);
  }
  void finish(double t, const double* y, const nlohmann::json& summary) {
    if (!h5_) return;
    h5_->close();
    std::filesystem::rename(path("result.h5.tmp"), path("result.h5"));
    write_file_atomically(path("result.xdmf"), xdmf_document("result.h5", sys_.particles(), times_, sys_.thermal()));
    write_file_atomically(path("summary.json"), summary.dump(2) + "\n");
    PictureInput pic;
    for (int i = 0; i < sys_.particles(); ++i) {
      pic.centre.push_back({y[sys_.x_at() + i], y[sys_.y_at() + i]});
      pic.radius.push_back(sys_.radius(i));
      pic.value.push_back(sys_.thermal() ? y[sys_.temperature_at() + i]
                                         : std::hypot(y[sys_.vx_at() + i], y[sys_.vy_at() + i]));
    }
    pic.value_label = sys_.thermal() ? "temperature" : "speed (m/s)";
    sys_.wall_geometry(t, pic.wall_a, pic.wall_b);
    std::ostringstream title;
    title << sys_.scene().name << "  t = " << t << " s  (" << sys_.scene().integrator << ")";
    pic.title = title.str();
    write_picture(path("picture.png"), pic);
    done_ = true;
  }

 private:
  std::string path(const std::string& name) const { return (std::filesystem::path(dir_) / name).string(); }
  std::string dir_;
  const DemSystem& sys_;
  std::unique_ptr<H5Frames> h5_;
  std::vector<double> times_;
  bool done_ = false;
};

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

}  // namespace

nlohmann::json run_scene(const Scene& scene, const RunOptions& options) {
  const auto wall_start = std::chrono::steady_clock::now();
  DemSystem system(scene);
  std::vector<double> y = system.initial_state();
  std::vector<std::unique_ptr<Observer>> observers;
  for (const std::string& name : scene.report) observers.push_back(make_observer(name, system));

  // The mechanical stage (skipped in a thermal-only scene): the full state, at dt.
  std::unique_ptr<Integrator> integrator = make_integrator(scene.integrator, scene.control);
  if (scene.frozen) {
    system.prepare(0, y.data(), 0);
  } else {
    integrator->start(system, 0.0, y.data(), scene.dt);
  }
  const EnergyLedger initial = system.energy(0, y.data());
  StabilityGuard guard(scene, system, initial);
  OutputFiles files(options.out_dir, system, scene);
  Progress progress(scene.name, options.quiet);
  files.frame(0, y.data());
  for (auto& o : observers) o->sample(0, y.data());

  std::vector<double> history_time{0.0}, history_error{0.0};
  double contacts_sum = 0;
  long contact_samples = 0;
  auto count_contacts = [&](double t) {
    const auto c = system.count_contacts(t, y.data());
    contacts_sum += (2.0 * c.particle_particle + c.particle_wall) / system.particles();
    ++contact_samples;
  };
  count_contacts(0);

  enum class Ended { at_end, at_rest, frozen };
  long total_steps = 0, total_rhs = 0;
  StepSizes all_steps;
  // Steps one stage from t0 to t_end (steps of dt, or adaptive), with a frame every `interval`.
  // Steps are never cut to land on frames: a frame is the state of the step that reaches its time
  // (stamped with that step's time). Only the last step may be shorter, to end on t_end.
  auto run_stage = [&](Integrator& stepper, double t0, double dt, double interval, bool mechanics, double& t,
                       StepSizes& sizes) {
    const double tol = 1e-9 * dt;
    long k = 0, frames = 1;
    double next_frame = t0 + interval;
    stepper.set_stop_time(scene.t_end);
    while (t < scene.t_end - tol) {
      stepper.step();
      ++k;
      t = stepper.time();
      sizes.add(stepper.stats().last_step);
      if (mechanics) guard.every_step(t);
      guard.temperatures(t, y.data());
      for (auto& o : observers) o->sample(t, y.data());
      const bool at_end = t >= scene.t_end - tol;
      if (t >= next_frame - tol || at_end) {
        guard.finite(t, y.data(), system.layout().size());
        const EnergyLedger now = system.energy(t, y.data());
        guard.energy(t, now);
        history_time.push_back(t);
        history_error.push_back(balance_error(initial, now));
        files.frame(t, y.data());
        count_contacts(t);
        progress.update(t, scene.t_end);
        while (next_frame <= t + tol) next_frame = t0 + (++frames) * interval;  // no drift from summing
        if (mechanics && scene.stop_kinetic_energy > 0 && t >= scene.stop_not_before &&
            now.kinetic < scene.stop_kinetic_energy)
          return at_end ? Ended::at_end : Ended::at_rest;
        if (mechanics && scene.freeze.enabled && !at_end &&
            ((t >= scene.freeze.not_before && now.kinetic < scene.freeze.kinetic_energy_below) ||
             t >= scene.freeze.latest))
          return Ended::frozen;
      } else if (k % 64 == 0) {
        guard.finite(t, y.data(), system.layout().size());
      }
    }
    return Ended::at_end;
  };

  double t = 0, frozen_at = NAN;
  nlohmann::json frozen_network;  // the conduction network of the frozen stage
  Ended ended = Ended::frozen;
  nlohmann::json integrator_stats;
  if (!scene.frozen) {
    StepSizes sizes;
    guard.set_stage(scene.dt);
    ended = run_stage(*integrator, 0, scene.dt, scene.output_interval, true, t, sizes);
    total_steps += sizes.count;  // the steps the run kept (ARKODE's count adds redone ones)
    total_rhs += integrator->stats().rhs_evals;
    integrator_stats = integrator->statistics();
    integrator_stats["step_size"] = sizes.json();
    all_steps.merge(sizes);
  }
  if (ended == Ended::frozen && options.stop_at_freeze) {
    frozen_at = t;
  } else if (ended == Ended::frozen) {
    // Freeze: the residual kinetic energy is removed (booked as dissipated), the conductances of
    // the contact network are fixed, and only the temperatures are integrated from here on.
    frozen_at = t;
    const EnergyLedger before = system.energy(t, y.data());
    for (int k = system.vx_at(); k < system.ledger_at(); ++k) y[k] = 0;
    y[system.ledger_at() + ledger_damping] += before.kinetic;
    thermal::FrozenConduction heat = thermal::freeze_network(system, t, y.data());
    // Explicit stepping of the frozen network is stable below 2 / lambda_max (Gershgorin bound).
    frozen_network = {{"links", heat.links().size()}, {"explicit_dt_limit", 2 / heat.stiffest_rate()}};
    const double dt = scene.frozen ? scene.dt : scene.freeze.dt;
    const double interval = scene.frozen ? scene.output_interval
                            : scene.freeze.output_interval > 0 ? scene.freeze.output_interval
                                                               : (scene.t_end - t) / 100;
    const std::string& heat_integrator =
        scene.frozen || scene.freeze.integrator.empty() ? scene.integrator : scene.freeze.integrator;
    std::unique_ptr<Integrator> heat_stepper = make_integrator(heat_integrator, scene.control);
    const auto heat_start = std::chrono::steady_clock::now();
    heat_stepper->start(heat, t, y.data() + system.ledger_at(), dt);
    StepSizes sizes;
    guard.set_stage(dt, real_stability_of(heat_integrator) / heat.stiffest_rate());
    if (t < scene.t_end) ended = run_stage(*heat_stepper, t, dt, interval, false, t, sizes);
    total_steps += sizes.count;
    total_rhs += heat_stepper->stats().rhs_evals;
    nlohmann::json& heat_stats = scene.frozen ? integrator_stats : integrator_stats["heat_stage"];
    heat_stats = heat_stepper->statistics();
    heat_stats["step_size"] = sizes.json();
    heat_stats["integrator"] = heat_integrator;
    heat_stats["dt"] = dt;
    heat_stats["rhs_evals"] = heat_stepper->stats().rhs_evals;
    heat_stats["wall_seconds"] = std::chrono::duration<double>(std::chrono::steady_clock::now() - heat_start).count();
    all_steps.merge(sizes);
  }
  progress.finish();
  const EnergyLedger final_energy = system.energy(t, y.data());
  const double wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

  nlohmann::json summary;
  summary["scene"] = scene.name;
  summary["integrator"] = scene.integrator;
  summary["dt"] = scene.dt;
  summary["t_end"] = t;
  summary["stopped_early"] = ended == Ended::at_rest;
  summary["frozen_at"] = std::isfinite(frozen_at) ? nlohmann::json(frozen_at) : nlohmann::json(nullptr);
  if (!frozen_network.is_null()) summary["frozen_network"] = frozen_network;
  summary["steps"] = total_steps;
  summary["step_size"] = all_steps.json();
  summary["rhs_evals"] = total_rhs;
  summary["integrator_stats"] = integrator_stats;
  summary["rtol"] = scene.control.rtol;
  summary["wall_seconds"] = wall_seconds;
  summary["particle_steps_per_second"] = system.particles() * static_cast<double>(total_steps) / wall_seconds;
  summary["particles"] = system.particles();
  summary["rotation"] = system.rotates();
  summary["thermal"] = system.thermal();
  summary["mean_contacts"] = contacts_sum / contact_samples;
  summary["neighbour_rebuilds"] = system.rebuilds();
  summary["skin"] = system.skin();
  summary["energy"] = ledger_json(final_energy, initial, system.thermal());
  summary["energy"]["history"] = {{"time", history_time}, {"balance_error", history_error}};
  const StabilityEstimate& est = guard.estimate();
  summary["stability"] = {{"contact_duration", est.contact_duration},
                          {"shortest_pair", est.shortest_pair},
                          {"dt_limit", est.dt_limit},
                          {"recommended_dt", est.recommended_dt}};
  if (system.thermal()) {
    summary["stability"]["thermal_dt_limit"] = est.thermal_dt_limit;
    summary["stability"]["thermal_relaxation_time"] = est.thermal_relaxation_time;
  }
  summary["checks"] = guard.figures();
  summary["kiln_version"] = KILN_VERSION;
  for (auto& o : observers) o->report(t, y.data(), summary);
  if (options.final_fields) {
    const int n = system.particles();
    FinalFields& f = *options.final_fields;
    f.position.assign(y.begin() + system.x_at(), y.begin() + system.x_at() + 2 * n);
    f.velocity.assign(y.begin() + system.vx_at(), y.begin() + system.vx_at() + 2 * n);
    if (system.thermal()) f.temperature.assign(y.begin() + system.temperature_at(), y.begin() + system.temperature_at() + n);
  }
  files.finish(t, y.data(), summary);
  return summary;
}

}  // namespace kiln
