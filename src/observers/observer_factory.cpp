// The one factory: each entry of the observer catalogue (src/scene/observer_catalogue.cpp) and
// the implementation that writes its keys, one file each (observe_*.cpp). The makers are declared
// here, their only caller, and defined in those files; a mismatch fails to link.
#include <stdexcept>

#include "src/observers/observer.h"

namespace kiln {

std::unique_ptr<Observer> make_bounce_observer(const DemSystem& system);               // observe_bounce.cpp
std::unique_ptr<Observer> make_discharge_observer(const DemSystem& system);            // observe_discharge.cpp
std::unique_ptr<Observer> make_heap_observer(const DemSystem& system);                 // observe_heap.cpp
std::unique_ptr<Observer> make_incline_observer(const DemSystem& system);              // observe_incline.cpp
std::unique_ptr<Observer> make_mixing_observer(const DemSystem& system);               // observe_mixing.cpp
std::unique_ptr<Observer> make_species_mixing_observer(const DemSystem& system);       // observe_mixing.cpp
std::unique_ptr<Observer> make_shear_observer(const DemSystem& system);                // observe_shear.cpp
std::unique_ptr<Observer> make_temperature_observer(const DemSystem& system);          // observe_temperatures.cpp
std::unique_ptr<Observer> make_temperature_profile_observer(const DemSystem& system);  // observe_temperature_profile.cpp
std::unique_ptr<Observer> make_impact_observer(const DemSystem& system);               // observe_impacts.cpp

namespace {

struct Maker {
  const char* name;  // the catalogue's
  std::unique_ptr<Observer> (*make)(const DemSystem&);
};
const Maker makers[] = {
    {"bounce_heights", make_bounce_observer},
    {"discharge", make_discharge_observer},
    {"heap", make_heap_observer},
    {"incline_motion", make_incline_observer},
    {"mixing", make_mixing_observer},
    {"species_mixing", make_species_mixing_observer},
    {"shear_profile", make_shear_observer},
    {"temperatures", make_temperature_observer},
    {"temperature_profile", make_temperature_profile_observer},
    {"wall_impacts", make_impact_observer},
};

}  // namespace

std::unique_ptr<Observer> make_observer(const std::string& name, const DemSystem& system) {
  for (const Maker& m : makers)
    if (name == m.name) return m.make(system);
  // The scene reader accepted the name from the catalogue: an entry without a maker here.
  throw std::logic_error("make_observer: the catalogue's observer '" + name + "' has no implementation");
}

}  // namespace kiln
