// libFuzzer target of `kiln run --restart` on a changed checkpoint (tests/fuzz/check_checkpoint.h
// says what one input is and goes through). Built with -DKILN_FUZZ=ON: see the end of CMakeLists.txt.
#include <cstddef>
#include <cstdint>

#include "tests/fuzz/check_checkpoint.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  kiln::fuzz::check_checkpoint(data, size, KILN_CASES);
  return 0;
}
