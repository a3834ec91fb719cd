// Case quantities: what a standard case reports in summary.json beyond the energy ledger.
// A scene asks for them by name (`report: [bounce_heights]`); each samples the state after
// every step and writes its figures at the end.
#pragma once
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "src/output/output_h5.h"
#include "src/base/snapshot.h"

namespace kiln {

class DemSystem;

// What an observer has accumulated, for checkpoints: its fields listed once for both directions.
using ObserverState = SnapshotFields;

class Observer {
 public:
  virtual ~Observer() = default;
  virtual void sample(double /*t*/, const double* /*y*/) {}  // after every step; most need only the end
  virtual void report(double t, const double* y, nlohmann::json& summary) = 0;
  // Tables for result.h5 (histograms and the like), written when the run ends.
  virtual void tables(std::vector<ResultTable>& /*out*/) const {}
  // Checkpoints: what sample() accumulated (nothing, for observers that look only at the end).
  virtual void state(ObserverState& /*s*/) {}
};

struct Scene;

const std::vector<std::string>& observer_names();
// What `scene` lacks for the observer `name` ("a thermal scene", ...), or "" when it has all.
std::string observer_needs(const std::string& name, const Scene& scene);
std::unique_ptr<Observer> make_observer(const std::string& name, const DemSystem& system);

// Observers of single cases, each in a file of its own (observe_*.cpp).
std::unique_ptr<Observer> make_shear_observer(const DemSystem& system);  // N3
std::string shear_observer_needs(const Scene& scene);
std::unique_ptr<Observer> make_impact_observer(const DemSystem& system);  // C2
std::unique_ptr<Observer> make_discharge_observer(const DemSystem& system);  // C3
std::string discharge_observer_needs(const Scene& scene);

// Heap figures from a settled pile (used by the `heap` observer, testable on its own).
struct HeapShape {
  double angle_left_deg = NAN, angle_right_deg = NAN, angle_deg = NAN;
  double packing_fraction = NAN;
};
HeapShape measure_heap(const std::vector<double>& x, const std::vector<double>& y, const std::vector<double>& r);

}  // namespace kiln
