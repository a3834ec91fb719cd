// Structural mutations of a scene, for the scene fuzzer (scene_fuzz.cpp). libFuzzer's byte
// mutations rarely turn a valid scene into another valid scene with a new structure: an alias
// that points into its own anchor (issue 26's crash) needs `*name` typed inside the anchored map,
// at a place where YAML reads it as a node, and in 2 x 60 s from the seeds they never did. Here
// the scene is read as YAML and changed as a tree: a node made to share another node (which
// yaml-cpp's emitter writes as an anchor and an alias, and as an alias inside its own anchor when
// the other node holds it), a number scaled by a power of ten or set to an edge value, a list
// item repeated, a key removed. Lines after the "#--set" marker (check_scene.h) are kept as they are.
#pragma once
#include <yaml-cpp/yaml.h>

#include <cstdint>
#include <cstring>
#include <random>
#include <string>
#include <vector>

namespace kiln::fuzz {

namespace detail {

// The scene's distinct nodes (a node shared by aliases once), at most `cap` of them.
inline void collect(const YAML::Node& node, std::vector<YAML::Node>& out, size_t cap) {
  if (out.size() >= cap) return;
  for (const YAML::Node& seen : out)
    if (seen.is(node)) return;
  out.push_back(node);
  if (node.IsMap())
    for (auto kv : node) collect(kv.second, out, cap);
  else if (node.IsSequence())
    for (auto item : node) collect(item, out, cap);
}

inline std::string edge_number(std::mt19937& rng, double v) {
  static const char* const edges[] = {"0", "-1", "1", "1e308", "-1e308", "1e-320", ".nan", ".inf", "4294967298",
                                      "9223372036854775807", "1e6", "1000000"};
  if (rng() % 3 == 0) return edges[rng() % (sizeof edges / sizeof *edges)];
  const int power = static_cast<int>(rng() % 61) - 30;
  return std::to_string(v) + "e" + std::to_string(power);  // v x 10^power, as text
}

}  // namespace detail

// A structurally mutated `input`, or "" when it is not YAML (libFuzzer's byte mutations go on).
inline std::string mutate_yaml(const std::string& input, unsigned seed) {
  const std::string marker = "\n#--set\n";
  const size_t at = input.find(marker);
  std::mt19937 rng(seed);
  YAML::Node root;
  try {
    root = YAML::Load(input.substr(0, at));
  } catch (const YAML::Exception&) {
    return "";
  }
  std::vector<YAML::Node> nodes, containers;
  detail::collect(root, nodes, 4096);
  for (const YAML::Node& n : nodes)
    if ((n.IsMap() || n.IsSequence()) && n.size() > 0) containers.push_back(n);
  if (containers.empty()) return "";
  YAML::Node c = containers[rng() % containers.size()];
  const size_t pick = rng() % c.size();
  // The chosen child of c, as a handle whose assignment changes the tree (yaml-cpp's operator=
  // on a node of a tree makes it refer to the assigned node: the two are then one node).
  YAML::Node child;
  YAML::Node key;
  if (c.IsMap()) {
    size_t k = 0;
    for (auto kv : c)
      if (k++ == pick) {
        child = kv.second;
        key = kv.first;
      }
  } else {
    child = c[pick];
  }
  try {
    switch (rng() % 4) {
      case 0:  // share: an alias to any node, its own ancestors included
        child = nodes[rng() % nodes.size()];
        break;
      case 1: {  // a number scaled or set to an edge value
        std::vector<YAML::Node> numbers;
        for (const YAML::Node& n : nodes) {
          double v = 0;
          if (n.IsScalar() && YAML::convert<double>::decode(n, v)) numbers.push_back(n);
        }
        if (numbers.empty()) return "";
        YAML::Node n = numbers[rng() % numbers.size()];
        n = detail::edge_number(rng, n.as<double>());
        break;
      }
      case 2:  // a list item repeated, or a map's value copied under a key of its own
        if (c.IsSequence()) c.push_back(YAML::Clone(child));
        else child = YAML::Clone(nodes[rng() % nodes.size()]);
        break;
      default:  // a key or an item removed
        if (c.IsMap()) c.remove(key);
        else c.remove(pick);
    }
    YAML::Emitter out;
    out << root;
    if (!out.good()) return "";
    return std::string(out.c_str()) + "\n" + (at == std::string::npos ? "" : input.substr(at + 1));
  } catch (const std::exception&) {
    return "";
  }
}

}  // namespace kiln::fuzz
