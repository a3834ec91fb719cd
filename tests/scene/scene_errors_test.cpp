// Bad scenes: each class of error names the file, the line and the key, and what was expected.
#include <catch2/catch.hpp>
#include <string>

#include "integrators/integrator.h"
#include "src/base/error.h"
#include "src/scene/scene_yaml.h"
#include "tests/support.h"

using namespace kiln;
using testing::error_of;
using testing::replaced;

namespace {

const std::string& good = testing::two_discs_on_a_floor;

// Parses `text` and returns the error message (empty if it parsed).
}  // namespace

TEST_CASE("a good scene parses", "[errors]") { CHECK(error_of(good).empty()); }

TEST_CASE("an unknown key is an error naming file, line, key and the valid keys", "[errors]") {
  const std::string msg = error_of(replaced(good, "dt: 1.0e-6", "dtt: 1.0e-6"));
  CHECK(msg.find("bad.yaml:10") != std::string::npos);
  CHECK(msg.find("key 'dtt'") != std::string::npos);
  CHECK(msg.find("'dt'") != std::string::npos);  // the nearest valid key is offered
}

TEST_CASE("an unknown nested key names its dotted path", "[errors]") {
  const std::string msg = error_of(replaced(good, "restitution: 0.8", "restitutoin: 0.8"));
  CHECK(msg.find("bad.yaml:3") != std::string::npos);
  CHECK(msg.find("materials.copper.restitutoin") != std::string::npos);
  CHECK(msg.find("'restitution'") != std::string::npos);
}

TEST_CASE("a wrong type is an error saying what was expected", "[errors]") {
  const std::string msg = error_of(replaced(good, "radius: 0.002", "radius: small"));
  CHECK(msg.find("bad.yaml:6") != std::string::npos);
  CHECK(msg.find("particles.0.radius") != std::string::npos);
  CHECK(msg.find("expected a positive number") != std::string::npos);
}

TEST_CASE("a missing required value is an error naming the key", "[errors]") {
  const std::string msg = error_of(replaced(good, "t_end: 0.01\n", ""));
  CHECK(msg.find("bad.yaml:1") != std::string::npos);
  CHECK(msg.find("'t_end'") != std::string::npos);
}

TEST_CASE("impossible values: negative radius, restitution of 0 or above 1", "[errors]") {
  const std::string radius = error_of(replaced(good, "radius: 0.002", "radius: -0.002"));
  CHECK(radius.find("bad.yaml:6: key 'particles.0.radius'") != std::string::npos);
  const std::string e = error_of(replaced(good, "restitution: 0.8", "restitution: 1.3"));
  CHECK(e.find("bad.yaml:3: key 'materials.copper.restitution'") != std::string::npos);
  CHECK(e.find("[0.01, 1]") != std::string::npos);
  // Each end is explained by its own reason (1.5 was told only why 0.01 is the lower bound).
  CHECK(e.find("above 1 an impact would give back more energy than it took") != std::string::npos);
  CHECK(e.find("below 0.01") == std::string::npos);
  const std::string zero = error_of(replaced(good, "restitution: 0.8", "restitution: 0"));
  CHECK(zero.find("below 0.01 a spring-dashpot contact") != std::string::npos);
}

TEST_CASE("overlapping initial particles are an error unless allowed", "[errors]") {
  const std::string overlapping = replaced(good, "[0.01, 0.01]", "[0.003, 0.01]");
  const std::string msg = error_of(overlapping);
  CHECK(msg.find("bad.yaml:5: key 'particles.0'") != std::string::npos);
  CHECK(msg.find("overlap") != std::string::npos);
  CHECK(msg.find("allow_overlap") != std::string::npos);
  CHECK(error_of(overlapping + "allow_overlap: true\n").empty());
}

TEST_CASE("an unknown material or choice lists the valid ones", "[errors]") {
  const std::string material = error_of(replaced(good, "- material: copper", "- material: coper"));
  CHECK(material.find("bad.yaml:5: key 'particles.0.material'") != std::string::npos);
  CHECK(material.find("'copper'") != std::string::npos);
  const std::string model = error_of(good + "contact_model: hooke\n");
  CHECK(model.find("key 'contact_model'") != std::string::npos);
  CHECK(model.find("'linear'") != std::string::npos);
  CHECK(model.find("'hertz'") != std::string::npos);
}

TEST_CASE("a Hertz contact without Young's modulus is an error at the contact entry", "[errors]") {
  const std::string msg = error_of(good + "contacts:\n  - between: [copper, copper]\n    model: hertz\n");
  CHECK(msg.find("bad.yaml:13") != std::string::npos);
  CHECK(msg.find("youngs_modulus") != std::string::npos);
}

TEST_CASE("set overrides by dotted path and a bad path lists the nearest keys", "[errors]") {
  CHECK(parse_scene(good, "bad.yaml", {"materials.copper.restitution=0.5"}).laws[0].contact.restitution == 0.5);
  const std::string path = error_of(good, {"materials.coper.restitution=0.5"});
  CHECK(path.find("--set: key 'materials.coper'") != std::string::npos);
  CHECK(path.find("'copper'") != std::string::npos);
  const std::string value = error_of(good, {"dt=-1"});
  CHECK(value.find("--set: key 'dt'") != std::string::npos);
  const std::string unknown = error_of(good, {"tend=1"});
  CHECK(unknown.find("--set: key 'tend'") != std::string::npos);
  CHECK(unknown.find("'t_end'") != std::string::npos);
}

TEST_CASE("an unknown integrator name lists the valid names, closest first", "[errors]") {
  try {
    make_integrator("velocity-verlett");
    FAIL("no error");
  } catch (const InputError& e) {
    const std::string msg = e.what();
    CHECK(msg.find("'velocity-verlet',") != std::string::npos);
    CHECK(msg.find("'verlet'") != std::string::npos);
  }
}

TEST_CASE("malformed YAML names the line", "[errors]") {
  CHECK(error_of("name: x\nmaterials: {a: [1, 2}\n").find("bad.yaml:2") != std::string::npos);
}

TEST_CASE("a rolling model outside the choices, or a damping ratio the chosen model has no use for, is refused",
          "[scene]") {
  const std::string bad_model = error_of(replaced(good, "dt: 1.0e-6", "rolling_model: viscous\ndt: 1.0e-6"));
  CHECK(bad_model.find("bad.yaml:10") != std::string::npos);
  CHECK(bad_model.find("rolling_model") != std::string::npos);
  CHECK(bad_model.find("constant") != std::string::npos);
  CHECK(bad_model.find("epsd") != std::string::npos);
  const std::string contacts = "contacts:\n  - {between: [copper, copper], rolling_friction: 0.1, rolling_damping_ratio: 0.3}\n";
  const std::string unused = error_of(replaced(good, "particles:", contacts + "particles:"));
  CHECK(unused.find("rolling_damping_ratio") != std::string::npos);
  CHECK(unused.find("epsd only") != std::string::npos);
  CHECK(error_of(replaced(good, "particles:", "rolling_model: epsd\n" + contacts + "particles:")).empty());
}
