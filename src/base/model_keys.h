// The models of a law as plain data: each model's name in a scene file and the keys that only it
// reads. A law in contact/ or thermal/ lists its models here, and the scene reader walks the list
// (src/scene/read_laws.cpp): it reads a model's keys, checks their ranges and refuses them for
// the other models, without naming any model itself. So a new model is a new row, where its law is.
#pragma once
#include <cmath>
#include <span>
#include <stdexcept>

namespace kiln {

// The values a key accepts: an interval, each end open or closed.
struct Accepted {
  double lo = 0, hi = INFINITY;
  bool lo_open = false, hi_open = true;
  bool operator==(const Accepted&) const = default;
};
inline constexpr Accepted positive_number{0, INFINITY, true, true};
inline constexpr Accepted non_negative_number{0, INFINITY, false, true};

// A key that belongs to one model (or a few, each listing it): where its value goes in the law's
// parameters `Params`, what it accepts and means.
template <class Params>
struct OwnedKey {
  const char* key;
  const char* meaning;  // what it is, with its units: said when the key is given to another model
  double Params::*field;
  Accepted accepts;
  bool required = false;          // the model cannot do without it
  const char* excludes = nullptr;  // a key it cannot be given with (it takes that key's place)
};

// One model of a law. `instead`, when set, says how it does without the keys of the other models
// (told to a scene that gives it one of them). `needed`, when set, is the parameter that must end
// up positive for a pair that uses the model, `needs` what the scene must give for it.
template <class Model, class Params>
struct ModelEntry {
  Model model;
  const char* name;   // in a scene file
  const char* title;  // in a sentence
  std::span<const OwnedKey<Params>> keys;
  const char* instead = nullptr;
  double Params::*needed = nullptr;
  const char* needs = nullptr;
};

// The entry of `model` in `table`. Every model has one (each law's tests check it): a model
// missing from its table is a programming error, not a scene's.
template <class Model, class Params>
const ModelEntry<Model, Params>& entry_of(std::span<const ModelEntry<Model, Params>> table, Model model) {
  for (const auto& e : table)
    if (e.model == model) return e;
  throw std::logic_error("a model without an entry in its law's table");
}

}  // namespace kiln
