// The observer catalogue: every case quantity a scene may ask for under `report:`, what it needs of
// the scene, and the keys it writes into summary.json with their units and meaning. The one list
// that the scene reader (names and needs), the studies (every number and list key is a --quantity)
// and `kiln plot` (units, labels, what a list is drawn against) read; the observers that write the
// keys are src/observers/observe_*.cpp, made from their names by src/observers/observer_factory.cpp.
// tests/observers/observer_catalogue_test.cpp runs each observer's case and checks that it writes
// exactly these keys.
//
// A key's path is dotted: "shear_profile.eta" is the member eta of the object shear_profile; in an
// array of objects (one per wall) it names that member of every element, which together make a
// list ("wall_impacts.impacts"). A figure a case could not measure is null; a null object stands
// for all its members.
#pragma once
#include <string>
#include <vector>

namespace kiln {

struct Scene;

struct ObserverKey {
  enum class Kind {
    number,  // one value
    list,    // values per bounce, per layer, per sample, per wall, ...
    text,    // a label (a wall's name): no quantity
  };
  std::string path;
  Kind kind = Kind::number;
  std::string unit;     // SI; "1" for ratios and counts, "deg" for angles, "C" for temperatures
  std::string meaning;
  std::string against;  // a list drawn against another list of its object (time, eta): that list's path
  bool thermal_only = false;  // written in thermal scenes only
  bool headline = false;      // a case's figure of merit: what `kiln sweep` studies without --quantity
  bool written_in(const Scene& scene) const;
};

struct ObserverEntry {
  std::string name;                    // as a scene names it under `report:`
  std::string (*needs)(const Scene&);  // what the scene lacks for it ("a thermal scene"), or ""
  std::vector<ObserverKey> keys;       // in the order the observer writes them
};

const std::vector<ObserverEntry>& observer_catalogue();
std::vector<std::string> observer_names();
// The entry named `name`, or nullptr.
const ObserverEntry* find_observer(const std::string& name);

}  // namespace kiln
