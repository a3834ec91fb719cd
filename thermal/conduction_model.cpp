#include "thermal/conduction_model.h"

namespace kiln::thermal {

namespace {

constexpr OwnedKey<ConductionParams> constant_keys[] = {
    {"conductance", "the contact's conductance H (W/K)", &ConductionParams::conductance, positive_number, true},
};
constexpr OwnedKey<ConductionParams> batchelor_obrien_keys[] = {
    {"softened_modulus_ratio", "E_simulated / E_real of a softened Young's modulus", &ConductionParams::modulus_ratio,
     {0, 1, true, false}},
};
constexpr OwnedKey<ConductionParams> pipe_network_keys[] = {
    {"contact_resistance", "the contact resistance R_c per unit length (m K/W)", &ConductionParams::contact_resistance,
     non_negative_number},
};

constexpr ConductionModelEntry table[] = {
    {ConductionModel::lens, "lens", "lens", {}},
    {ConductionModel::hertz, "hertz", "Hertz", {}},
    {ConductionModel::batchelor_obrien, "batchelor_obrien", "Batchelor-O'Brien", batchelor_obrien_keys},
    {ConductionModel::pipe_network, "pipe_network", "pipe network", pipe_network_keys},
    {ConductionModel::constant, "constant", "constant", constant_keys},
    {ConductionModel::none, "none", "no", {}},
};

}  // namespace

std::span<const ConductionModelEntry> conduction_models() { return table; }

}  // namespace kiln::thermal
