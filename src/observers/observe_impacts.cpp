// Impacts on walls (case C2, the energy spectrum of a mill's lifters): each time a particle
// starts touching a wall (a wall group: its segments together) it has struck it with the
// kinetic energy of its approach, E = m u_n^2 / 2, u_n the particle's velocity relative to the
// wall's point along the contact normal at the first step of contact (so to O(dt) of the contact's
// onset; a wall has no mass, so the particle's own mass carries the energy). Counted per wall, with
// a histogram of log-spaced energies written to result.h5 (impact_energy_histogram, W x B, and its
// bin edges) and per wall in summary.json `wall_impacts`: impacts, total, mean and largest energy.
// A particle that rolls or slides along a wall makes one impact, when it arrives. Only the wall's
// segments are struck here: blows on grains attached to a wall (rough walls) are not counted,
// though their forces are in the wall's load.
#include <algorithm>
#include <cmath>

#include "src/dem/dem_system.h"
#include "src/observers/observer.h"

namespace kiln {

namespace {

// Ten bins a decade from 1e-12 J (a 1 mm grain at 1 mm/s) to 1e3 J: wide enough for any scene
// kiln runs; energies outside land in the end bins.
constexpr double lowest_energy = 1e-12;
constexpr int decades = 15, bins_per_decade = 10, bins = decades * bins_per_decade;

class ImpactObserver final : public Observer {
 public:
  explicit ImpactObserver(const DemSystem& sys)
      : sys_(sys), walls_(static_cast<int>(sys.scene().walls.size())) {
    touching_.assign(static_cast<size_t>(sys.particles()) * walls_, 0);
    now_ = touching_;
    histogram_.assign(static_cast<size_t>(walls_) * bins, 0.0);
    count_.assign(walls_, 0.0);
    total_.assign(walls_, 0.0);
    largest_.assign(walls_, 0.0);
  }

  void sample(double t, const double* y) override {
    const double *px = y + sys_.x_at(), *py = y + sys_.y_at();
    const double *vx = y + sys_.vx_at(), *vy = y + sys_.vy_at();
    sys_.wall_geometry(t, y, a_, b_);
    std::fill(now_.begin(), now_.end(), 0);
    const ContactList& candidates = sys_.wall_contacts();
    for (int p = 0; p < candidates.size(); ++p) {
      const int i = candidates.i[p], s = candidates.j[p];
      if (sys_.attached(i)) continue;
      // The contact rule of the force stage (a shared vertex belongs to one segment).
      const Vec2 c = sys_.cell().image_near({px[i], py[i]}, 0.5 * (a_[s] + b_[s]));
      WallHit hit;
      if (!disc_segment_contact(sys_.scene().segments, a_, b_, s, c, sys_.radius(i), hit)) continue;
      const int w = sys_.scene().segments[s].wall;
      const size_t key = static_cast<size_t>(i) * walls_ + w;
      if (now_[key]) continue;  // one impact per wall, however many of its segments it touches
      now_[key] = 1;
      if (touching_[key]) continue;
      // hit.normal points from the centre to the wall: the approach speed is along it.
      const double approach = dot(Vec2{vx[i], vy[i]} - sys_.wall_point_velocity(w, hit.closest, t, y), hit.normal);
      if (approach <= 0) continue;  // arrived by sliding in or moving away: no blow
      book(w, 0.5 * sys_.mass(i) * approach * approach);
    }
    touching_.swap(now_);
  }

  void report(double, const double*, nlohmann::json& out) override {
    nlohmann::json walls = nlohmann::json::array();
    for (int w = 0; w < walls_; ++w)
      walls.push_back({{"name", sys_.scene().walls[w].name},
                       {"impacts", count_[w]},
                       {"total_energy", total_[w]},
                       {"mean_energy", count_[w] > 0 ? nlohmann::json(total_[w] / count_[w]) : nlohmann::json(nullptr)},
                       {"largest_energy", largest_[w]}});
    out["wall_impacts"] = walls;
  }

  void tables(std::vector<ResultTable>& out) const override {
    std::vector<double> edges(bins + 1);
    for (int k = 0; k <= bins; ++k) edges[k] = lowest_energy * std::pow(10.0, static_cast<double>(k) / bins_per_decade);
    out.push_back({"impact_energy_histogram", "1", {static_cast<hsize_t>(walls_), static_cast<hsize_t>(bins)}, histogram_});
    out.push_back({"impact_energy_bin_edges", "J", {static_cast<hsize_t>(bins + 1)}, edges});
  }

  void state(ObserverState& s) override {
    // Per particle and wall, per wall and bin, per wall: the lengths constructed.
    s.field("touching", touching_, {touching_.size()});
    s.field("histogram", histogram_, {histogram_.size()});
    s.field("count", count_, {count_.size()});
    s.field("total", total_, {total_.size()});
    s.field("largest", largest_, {largest_.size()});
  }

 private:
  void book(int w, double energy) {
    const int bin = std::clamp(static_cast<int>(std::floor(std::log10(energy / lowest_energy) * bins_per_decade)), 0, bins - 1);
    histogram_[static_cast<size_t>(w) * bins + bin] += 1;
    count_[w] += 1;
    total_[w] += energy;
    largest_[w] = std::max(largest_[w], energy);
  }

  const DemSystem& sys_;
  int walls_;
  std::vector<Vec2> a_, b_;
  std::vector<uint8_t> touching_, now_;  // particle x wall, at the last step and this one
  std::vector<double> histogram_, count_, total_, largest_;
};

}  // namespace

std::unique_ptr<Observer> make_impact_observer(const DemSystem& system) { return std::make_unique<ImpactObserver>(system); }

}  // namespace kiln
