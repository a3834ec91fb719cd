#include "src/simulation.h"

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
#include "src/stability.h"

namespace kiln {

namespace {

// Output files are written under temporary names and renamed only when the run succeeds.
class OutputFiles {
 public:
  OutputFiles(const std::string& dir, const DemSystem& sys, const Scene& scene) : dir_(dir), sys_(sys) {
    if (dir_.empty()) return;
    std::filesystem::create_directories(dir_);
    h5_ = std::make_unique<H5Frames>(path("result.h5.tmp"), sys.particles());
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
                sys_.rotates() ? y + sys_.angle_at() : nullptr, sys_.rotates() ? y + sys_.omega_at() : nullptr);
  }
  void finish(double t, const double* y, const nlohmann::json& summary) {
    if (!h5_) return;
    h5_->close();
    std::filesystem::rename(path("result.h5.tmp"), path("result.h5"));
    write_file_atomically(path("result.xdmf"), xdmf_document("result.h5", sys_.particles(), times_));
    write_file_atomically(path("summary.json"), summary.dump(2) + "\n");
    PictureInput pic;
    for (int i = 0; i < sys_.particles(); ++i) {
      pic.centre.push_back({y[sys_.x_at() + i], y[sys_.y_at() + i]});
      pic.radius.push_back(sys_.radius(i));
      pic.value.push_back(std::hypot(y[sys_.vx_at() + i], y[sys_.vy_at() + i]));
    }
    pic.value_label = "speed (m/s)";
    sys_.wall_geometry(t, pic.wall_a, pic.wall_b);
    std::ostringstream title;
    title << sys_.scene().name << "  t = " << t << " s  (" << sys_.scene().integrator << ", dt = " << sys_.scene().dt
          << " s)";
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

// Instability checks; a failure names the check, the time and the recommended dt.
class StabilityGuard {
 public:
  StabilityGuard(const Scene& scene, const DemSystem& sys, const EnergyLedger& initial)
      : scene_(scene), sys_(sys), initial_(initial), estimate_(estimate_stability(scene)) {}
  void every_step(double t) const {
    if (sys_.max_overlap_fraction() > scene_.max_overlap_fraction) {
      std::ostringstream s;
      s << "overlap reached " << sys_.max_overlap_fraction() << " of a radius (limit "
        << scene_.max_overlap_fraction << ", checks.max_overlap_fraction)";
      fail(t, s.str());
    }
  }
  void finite(double t, const double* y, int size) const {
    for (int k = 0; k < size; ++k)
      if (!std::isfinite(y[k])) fail(t, "the state holds NaN or infinity (component " + std::to_string(k) + ")");
  }
  // Energy blow-up: the ledger's error exceeds a quarter of all the energy that has changed form.
  void energy(double t, const EnergyLedger& now) const {
    const double throughput = std::abs(initial_.kinetic) + std::abs(now.kinetic) + std::abs(initial_.elastic) +
                              std::abs(now.elastic) + std::abs(now.potential - initial_.potential) +
                              std::abs(now.dissipated_damping) + std::abs(now.dissipated_friction) +
                              std::abs(now.work_by_walls);
    const double error = balance_error(initial_, now);
    if (throughput > 0 && error > 0.25 * throughput) {
      std::ostringstream s;
      s << "energy blow-up: the balance error " << error << " J exceeds a quarter of the energy exchanged ("
        << throughput << " J)";
      fail(t, s.str());
    }
  }
  const StabilityEstimate& estimate() const { return estimate_; }

 private:
  [[noreturn]] void fail(double t, const std::string& what) const {
    std::ostringstream s;
    s << "unstable run at t = " << t << " s: " << what << ". dt = " << scene_.dt
      << " s; the stability estimate recommends dt <= " << estimate_.recommended_dt << " s (contact duration "
      << estimate_.contact_duration << " s, " << estimate_.shortest_pair << "; limit " << estimate_.dt_limit << " s)";
    throw InstabilityError(s.str());
  }
  const Scene& scene_;
  const DemSystem& sys_;
  EnergyLedger initial_;
  StabilityEstimate estimate_;
};

nlohmann::json ledger_json(const EnergyLedger& e, const EnergyLedger& initial) {
  return {{"kinetic", e.kinetic},
          {"potential", e.potential},
          {"elastic", e.elastic},
          {"dissipated_damping", e.dissipated_damping},
          {"dissipated_friction", e.dissipated_friction},
          {"work_by_walls", e.work_by_walls},
          {"initial_total", initial.total()},
          {"balance_error", balance_error(initial, e)}};
}

}  // namespace

nlohmann::json run_scene(const Scene& scene, const RunOptions& options) {
  const auto wall_start = std::chrono::steady_clock::now();
  DemSystem system(scene);
  std::vector<double> y = system.initial_state();
  std::unique_ptr<Integrator> integrator = make_integrator(scene.integrator);
  std::vector<std::unique_ptr<Observer>> observers;
  for (const std::string& name : scene.report) observers.push_back(make_observer(name, system));

  // Whole steps only: t_k = k dt, so no drift from summing dt.
  const long steps = std::max(1L, std::lround(std::ceil(scene.t_end / scene.dt - 1e-9)));
  const long frame_every = std::max(1L, std::lround(scene.output_interval / scene.dt));

  integrator->start(system, 0.0, y.data(), scene.dt);
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

  long k = 0;
  double t = 0;
  bool stopped_early = false;
  while (k < steps) {
    integrator->step();
    ++k;
    t = k * scene.dt;
    guard.every_step(t);
    for (auto& o : observers) o->sample(t, y.data());
    if (k % frame_every == 0 || k == steps) {
      guard.finite(t, y.data(), system.layout().size());
      const EnergyLedger now = system.energy(t, y.data());
      guard.energy(t, now);
      history_time.push_back(t);
      history_error.push_back(balance_error(initial, now));
      files.frame(t, y.data());
      count_contacts(t);
      progress.update(t, steps * scene.dt);
      if (scene.stop_kinetic_energy > 0 && t >= scene.stop_not_before && now.kinetic < scene.stop_kinetic_energy) {
        stopped_early = k < steps;
        break;
      }
    } else if (k % 64 == 0) {
      guard.finite(t, y.data(), system.layout().size());
    }
  }
  progress.finish();
  const EnergyLedger final_energy = system.energy(t, y.data());
  const double wall_seconds = std::chrono::duration<double>(std::chrono::steady_clock::now() - wall_start).count();

  nlohmann::json summary;
  summary["scene"] = scene.name;
  summary["integrator"] = scene.integrator;
  summary["dt"] = scene.dt;
  summary["t_end"] = t;
  summary["stopped_early"] = stopped_early;
  summary["steps"] = integrator->stats().steps;
  summary["rhs_evals"] = integrator->stats().rhs_evals;
  summary["wall_seconds"] = wall_seconds;
  summary["particle_steps_per_second"] = system.particles() * static_cast<double>(k) / wall_seconds;
  summary["particles"] = system.particles();
  summary["rotation"] = system.rotates();
  summary["mean_contacts"] = contacts_sum / contact_samples;
  summary["neighbour_rebuilds"] = system.rebuilds();
  summary["skin"] = system.skin();
  summary["energy"] = ledger_json(final_energy, initial);
  summary["energy"]["history"] = {{"time", history_time}, {"balance_error", history_error}};
  summary["stability"] = {{"contact_duration", guard.estimate().contact_duration},
                          {"shortest_pair", guard.estimate().shortest_pair},
                          {"dt_limit", guard.estimate().dt_limit},
                          {"recommended_dt", guard.estimate().recommended_dt}};
  summary["kiln_version"] = KILN_VERSION;
  for (auto& o : observers) o->report(t, y.data(), summary);
  files.finish(t, y.data(), summary);
  return summary;
}

}  // namespace kiln
