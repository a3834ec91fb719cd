// libFuzzer target of the scene reader (tests/fuzz/check_scene.h says what one input goes
// through). Built with -DKILN_FUZZ=ON: see the end of CMakeLists.txt. Half of the mutations are
// structural (yaml_mutator.h: aliases into their own anchors, numbers at their edges), half are
// libFuzzer's own byte mutations, which also reach what is not YAML.
#include <cstddef>
#include <cstdint>
#include <cstring>
#include <string>

#include "tests/fuzz/check_scene.h"
#include "tests/fuzz/yaml_mutator.h"

extern "C" size_t LLVMFuzzerMutate(uint8_t* data, size_t size, size_t max_size);

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  kiln::fuzz::check_scene(std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}

extern "C" size_t LLVMFuzzerCustomMutator(uint8_t* data, size_t size, size_t max_size, unsigned int seed) {
  if (seed % 2 == 0) {
    const std::string mutated = kiln::fuzz::mutate_yaml(std::string(reinterpret_cast<const char*>(data), size), seed / 2);
    if (!mutated.empty() && mutated.size() <= max_size) {
      std::memcpy(data, mutated.data(), mutated.size());
      return mutated.size();
    }
  }
  return LLVMFuzzerMutate(data, size, max_size);
}
