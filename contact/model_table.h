// The models of the contact law as a scene names them, in plain data (src/base/model_keys.h): for
// each normal and each rolling model, its name, the keys of a `contacts:` entry that only it reads
// (their meaning, units and ranges), and what a pair using it needs of its materials. The scene
// reader walks these tables; their behaviour is the models' structs (contact/normal_force.h).
#pragma once
#include <span>

#include "contact/contact_law.h"
#include "src/base/model_keys.h"

namespace kiln::contact {

using NormalModelEntry = ModelEntry<NormalModel, ContactLaw>;
using RollingModelEntry = ModelEntry<RollingModel, ContactLaw>;

// Every model once, in the order a scene's choices list them.
std::span<const NormalModelEntry> normal_models();
std::span<const RollingModelEntry> rolling_models();

}  // namespace kiln::contact
