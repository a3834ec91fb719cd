#include "contact/model_table.h"

namespace kiln::contact {

namespace {

// The Hertz law takes its stiffness from the materials' moduli, and its dashpot (N s/m^1.25) from
// the restitution, so a linear damping rate has no meaning there.
constexpr OwnedKey<ContactLaw> linear_keys[] = {
    {"stiffness", "the linear spring's k (N/m)", &ContactLaw::stiffness, positive_number},
    {"damping_rate", "the linear dashpot's rate gamma_n, c = m_eff gamma_n (1/s)", &ContactLaw::damping_rate,
     non_negative_number, false, "restitution"},
};

constexpr NormalModelEntry normal_table[] = {
    {NormalModel::linear, "linear", "linear", linear_keys, nullptr, &ContactLaw::stiffness,
     "a stiffness (materials' or the contact's 'stiffness')"},
    {NormalModel::hertz, "hertz", "Hertz", {},
     "takes its stiffness from youngs_modulus and poisson_ratio and is damped through its restitution",
     &ContactLaw::effective_modulus, "youngs_modulus on both materials"},
};

constexpr OwnedKey<ContactLaw> epsd_keys[] = {
    {"rolling_damping_ratio", "the rolling dashpot's ratio eta_r, c_r = eta_r 2 sqrt(I_r k_r)",
     &ContactLaw::rolling_damping_ratio, non_negative_number},
};

constexpr RollingModelEntry rolling_table[] = {
    {RollingModel::constant, "constant", "constant", {}},
    {RollingModel::epsd, "epsd", "epsd", epsd_keys},
};

}  // namespace

std::span<const NormalModelEntry> normal_models() { return normal_table; }
std::span<const RollingModelEntry> rolling_models() { return rolling_table; }

}  // namespace kiln::contact
