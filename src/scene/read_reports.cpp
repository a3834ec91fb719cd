// The case quantities a scene asks for (`report: [name, ...]`), each checked against what the
// scene has (src/scene/observer_catalogue.h).
#include "src/scene/scene_parts.h"

#include "src/scene/observer_catalogue.h"

namespace kiln::scene_parts {

void read_reports(const SceneNode& root, Scene& scene) {
  if (auto report = root.optional("report")) {
    for (const SceneNode& q : report->items()) {
      const std::string name = q.text();
      const ObserverEntry* observer = find_observer(name);
      if (!observer) q.fail("unknown quantity '" + name + "'; available: " + choices_nearest_first(name, observer_names()));
      if (const std::string need = observer->needs(scene); !need.empty()) q.fail("'" + name + "' needs " + need);
      scene.report.push_back(name);
    }
  }
}

}  // namespace kiln::scene_parts
