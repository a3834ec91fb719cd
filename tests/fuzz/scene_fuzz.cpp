// libFuzzer target of the scene reader (tests/fuzz/check_scene.h says what one input goes
// through). Built with -DKILN_FUZZ=ON: see the end of CMakeLists.txt.
#include <cstddef>
#include <cstdint>
#include <string>

#include "tests/fuzz/check_scene.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  kiln::fuzz::check_scene(std::string(reinterpret_cast<const char*>(data), size));
  return 0;
}
