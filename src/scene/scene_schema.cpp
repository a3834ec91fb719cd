// The scene file's schema: every documented key by the path of its map. allow() checks a map
// against it, and --set may add any key it lists.
#include "src/scene/scene_parts.h"


namespace kiln::scene_parts {

const KeySchema& scene_schema() {
  static const KeySchema schema = {
    {"", {"name", "description", "mass_model", "thickness", "gravity", "materials", "contact_model", "contacts",
          "conduction_model", "rolling_model", "heat_from_dissipation", "mechanics", "freeze", "particles", "walls",
          "integrator", "rtol", "atol", "contact_events", "linear_solver", "dt", "t_end", "output_interval", "skin",
          "allow_overlap", "checks", "stop", "report", "periodic", "ensemble_member"}},
    {"periodic", {"x", "y"}},
    {"materials", {"*"}},
    {"materials.*", {"density", "youngs_modulus", "poisson_ratio", "stiffness", "restitution", "friction",
                     "rolling_friction", "specific_heat", "conductivity", "electrical_resistivity"}},
    {"contacts.*", contact_entry_keys()},
    {"particles.*", {"material", "radius", "velocity", "random_velocity", "angular_velocity", "temperature", "at",
                     "fill", "lattice", "file", "format", "attach", "fixed"}},
    {"particles.*.radius", {"uniform"}},
    {"particles.*.random_velocity", {"max", "seed"}},
    {"particles.*.temperature", {"x_split", "left", "right"}},
    {"particles.*.fill", {"rectangle", "polygon", "count", "seed", "attempts"}},
    {"particles.*.lattice", {"kind", "origin", "spacing", "rows", "columns", "jitter", "seed"}},
    {"walls.*", {"name", "material", "motion", "temperature", "segment", "polyline", "box", "circle", "arc", "closed",
                 "tolerance", "svg"}},
    {"walls.*.svg", {"file", "scale", "offset", "tolerance", "group"}},
    {"walls.*.motion", wall_motion_keys()},
    {"walls.*.temperature", {"steps", "ramp"}},
    {"walls.*.circle", {"centre", "radius"}},
    {"walls.*.arc", {"centre", "radius", "from_deg", "to_deg"}},
    {"freeze", {"kinetic_energy_below", "not_before", "latest", "dt", "output_interval", "integrator"}},
    {"atol", {"position", "velocity", "angle", "temperature", "other"}},
    {"checks", {"max_overlap_fraction"}},
    {"stop", {"kinetic_energy_below", "not_before"}},
};
  return schema;
}

}  // namespace kiln::scene_parts
