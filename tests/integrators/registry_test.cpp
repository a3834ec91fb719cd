// What kiln knows of each integrator comes from its registry entry: the orders from its Butcher
// tables, what it can do from the entry's capabilities, and every part of kiln reads those.
#include <catch2/catch.hpp>

#include <string>

#include "integrators/integrator.h"
#include "src/base/error.h"
#include "src/scene/scene_yaml.h"
#include "tests/support.h"

using namespace kiln;

TEST_CASE("an ARKODE table's orders are SUNDIALS' q and p, as its name's stages_embedding_order says", "[registry]") {
  int tables = 0;
  for (const IntegratorInfo& info : integrator_catalogue()) {
    if (info.scheme != IntegratorScheme::arkode || info.implicit || !info.alias_of.empty()) continue;
    ++tables;
    // NAME_s_p_q, or NAME_s_q without an embedding (KNOTH_WOLKE_3_3).
    const std::string& t = info.erk_table;
    const int q = std::stoi(t.substr(t.rfind('_') + 1));
    INFO(t);
    CHECK(info.order == q);
    if (info.embedding > 0) CHECK(std::stoi(t.substr(t.rfind('_', t.rfind('_') - 1) + 1)) == info.embedding);
    else CHECK(t == "KNOTH_WOLKE_3_3");
  }
  CHECK(tables == 15);
}

TEST_CASE("an integrator accepts the step control its entry allows, and nothing else", "[registry]") {
  for (const IntegratorInfo& info : integrator_catalogue()) {
    INFO(info.name);
    StepControl events;
    events.contact_events = true;
    StepControl adaptive;
    adaptive.rtol = 1e-6;
    if (info.locates_contact_events) CHECK_NOTHROW(make_integrator(info.name, events));
    else CHECK_THROWS_AS(make_integrator(info.name, events), InputError);
    if (info.embedding > 0) CHECK_NOTHROW(make_integrator(info.name, adaptive));
    else CHECK_THROWS_AS(make_integrator(info.name, adaptive), InputError);
    if (!info.alias_of.empty()) {
      const IntegratorInfo& target = integrator_info(info.alias_of);
      CHECK(target.order == info.order);
      CHECK(target.erk_table == info.erk_table);
      CHECK(target.dirk_table == info.dirk_table);
    }
  }
}

TEST_CASE("a scene refuses for moving grains every integrator whose entry integrates no contacts", "[registry]") {
  int refused = 0;
  for (const IntegratorInfo& info : integrator_catalogue()) {
    if (info.integrates_contacts) continue;
    ++refused;
    const std::string text = testing::case_text("t3_heap.yaml");
    CHECK_THROWS_WITH(parse_scene(text, "t3_heap.yaml", {"integrator=" + info.name}),
                      Catch::Contains(info.name + " integrates heat on frozen networks only"));
  }
  CHECK(refused >= 1);  // imex1
}
