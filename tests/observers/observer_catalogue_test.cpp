// The observer catalogue (src/scene/observer_catalogue.h) against the observers: each observer,
// run a few steps on the first shipped case that asks for it, writes exactly the keys the
// catalogue lists for it into summary.json, and the studies accept and read every one of them.
#include <algorithm>
#include <filesystem>
#include <set>

#include "src/run/simulation.h"
#include "src/scene/observer_catalogue.h"
#include "src/scene/overrides.h"
#include "src/studies/study_runs.h"
#include "tests/support.h"

using namespace kiln;
namespace fs = std::filesystem;

namespace {

// The paths of summary.json's values, as the catalogue names them: members of objects joined by
// dots, an array of objects (one per wall) standing for its elements' members.
void leaves(const nlohmann::json& j, const std::string& path, std::set<std::string>& out) {
  const bool objects = j.is_array() && !j.empty() &&
                       std::all_of(j.begin(), j.end(), [](const nlohmann::json& e) { return e.is_object(); });
  if (j.is_object()) {
    for (const auto& [key, value] : j.items()) leaves(value, path.empty() ? key : path + "." + key, out);
  } else if (objects) {
    for (const nlohmann::json& element : j) leaves(element, path, out);
  } else {
    out.insert(path);
  }
}

std::set<std::string> leaves(const nlohmann::json& j) {
  std::set<std::string> out;
  leaves(j, "", out);
  return out;
}

// The first shipped case whose report names `observer`, or "".
std::string case_of(const std::string& observer) {
  std::vector<fs::path> files;
  for (const auto& entry : fs::directory_iterator(KILN_CASES_DIR))
    if (entry.path().extension() == ".yaml") files.push_back(entry.path());
  std::sort(files.begin(), files.end());
  for (const fs::path& f : files) {
    const Scene scene = load_scene(f.string());
    if (std::find(scene.report.begin(), scene.report.end(), observer) != scene.report.end()) return f.string();
  }
  return "";
}

}  // namespace

TEST_CASE("every observer of the catalogue writes exactly its keys, and every key is a study quantity",
          "[observers]") {
  for (const ObserverEntry& entry : observer_catalogue()) {
    INFO("observer " << entry.name);
    const std::string file = case_of(entry.name);
    REQUIRE(!file.empty());  // a shipped case uses each observer
    INFO("case " << file);
    // 20 steps, histories sampled every 5: enough for every key to be written.
    const double dt = load_scene(file).dt;
    Scene scene = load_scene(file, {assignment("t_end", 20 * dt), assignment("output_interval", 5 * dt)});
    Scene bare = scene;
    bare.report.clear();
    scene.report = {entry.name};
    FinalFields fields;
    const nlohmann::json summary = run_scene(scene, {"", true, &fields});
    const nlohmann::json without = run_scene(bare, {"", true});
    std::set<std::string> written;
    const std::set<std::string> base = leaves(without);
    for (const std::string& path : leaves(summary))
      if (!base.count(path)) written.insert(path);
    std::set<std::string> listed;
    for (const ObserverKey& k : entry.keys)
      if (k.written_in(scene)) CHECK(listed.insert(k.path).second);  // each key once
    CHECK(written == listed);

    const std::vector<std::string> quantities = study_quantities(scene);
    for (const ObserverKey& k : entry.keys) {
      if (!k.written_in(scene) || k.kind == ObserverKey::Kind::text) continue;
      INFO("quantity " << k.path);
      CHECK(std::count(quantities.begin(), quantities.end(), k.path) == 1);
      CHECK_NOTHROW(check_quantity(scene, k.path));
      const std::vector<double> value = quantity_value(k.path, fields, summary);
      if (k.kind == ObserverKey::Kind::number) CHECK(value.size() == 1);
      CHECK((shape_of(scene, k.path) == QuantityShape::number) == (k.kind == ObserverKey::Kind::number));
      if (!k.against.empty()) CHECK(listed.count(k.against) == 1);  // drawn against a list of its own
    }
  }
}

TEST_CASE("a study names the observer of a case quantity its scene does not report", "[observers][study]") {
  const Scene scene = load_scene(testing::case_path("t1_free_fall.yaml"));
  CHECK_THROWS_WITH(check_quantity(scene, "discharge_rate"),
                    Catch::StartsWith("unknown quantity 'discharge_rate' for scene 't1_free_fall'; available: ") &&
                        Catch::Contains("'bounce_heights'") &&
                        Catch::EndsWith("('discharge_rate' is reported by 'discharge', which the scene's report: does "
                                        "not name)"));
  CHECK_THROWS_WITH(check_quantity(scene, "wall_impacts.name"), !Catch::Contains("is reported by"));
}

TEST_CASE("a list quantity is compared element by element, a figure not measured as NaN", "[observers][study]") {
  CHECK(max_abs_difference({1, 2, 3}, {1, 2.5}) == 0.5);  // the elements both have
  CHECK(std::isnan(max_abs_difference({}, {1})));
  CHECK(std::isnan(max_abs_difference({NAN}, {1})));
  const nlohmann::json summary = {{"wall_impacts", {{{"name", "a"}, {"impacts", 3}}, {{"name", "b"}, {"impacts", 5}}}},
                                  {"shear_profile", nullptr},
                                  {"heap_angle_deg", nullptr}};
  CHECK(quantity_value("wall_impacts.impacts", {}, summary) == std::vector<double>{3, 5});
  CHECK(std::isnan(quantity_value("shear_profile.gap", {}, summary).at(0)));
  CHECK(std::isnan(quantity_value("heap_angle_deg", {}, summary).at(0)));
}
