// Case quantities: what a standard case reports in summary.json beyond the energy ledger.
// A scene asks for them by name (`report: [bounce_heights]`, src/scene/observer_catalogue.h, which
// lists each one's keys); each samples the state after every step and writes its figures at the end.
#pragma once
#include <cmath>
#include <memory>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "src/base/snapshot.h"
#include "src/output/output_h5.h"

namespace kiln {

class DemSystem;

// What an observer has accumulated, for checkpoints: its fields listed once for both directions.
using ObserverState = SnapshotFields;

class Observer {
 public:
  virtual ~Observer() = default;
  // After every step: no allocation or lookup here. Most observers need only the end.
  virtual void sample(double /*t*/, const double* /*y*/) {}
  // Writes exactly the keys the catalogue lists for it (src/scene/observer_catalogue.cpp).
  virtual void report(double t, const double* y, nlohmann::json& summary) = 0;
  // Tables for result.h5 (histograms and the like), written when the run ends.
  virtual void tables(std::vector<ResultTable>& /*out*/) const {}
  // Checkpoints: what sample() accumulated (nothing, for observers that look only at the end).
  virtual void state(ObserverState& /*s*/) {}
};

// The observer of the catalogue's entry `name` (src/observers/observer_factory.cpp).
std::unique_ptr<Observer> make_observer(const std::string& name, const DemSystem& system);

// A figure as summary.json holds it: null when the case could not measure it (NaN).
inline nlohmann::json number_or_null(double v) { return std::isfinite(v) ? nlohmann::json(v) : nlohmann::json(nullptr); }

}  // namespace kiln
