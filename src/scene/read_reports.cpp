// The case quantities a scene asks for (`report: [name, ...]`), each checked against what the
// scene has.
#include "src/scene/scene_parts.h"

#include <algorithm>

#include "src/observers/observers.h"

namespace kiln::scene_parts {

void read_reports(const SceneNode& root, Scene& scene) {
  if (auto report = root.optional("report")) {
    for (const SceneNode& q : report->items()) {
      const std::string name = q.text();
      const auto& known = observer_names();
      if (std::find(known.begin(), known.end(), name) == known.end())
        q.fail("unknown quantity '" + name + "'; available: " + choices_nearest_first(name, known));
      if (const std::string need = observer_needs(name, scene); !need.empty()) q.fail("'" + name + "' needs " + need);
      scene.report.push_back(name);
    }
  }
}

}  // namespace kiln::scene_parts
