// libFuzzer entry point for one target of fuzz/fuzz_targets.h, chosen at
// build time by CLOTHFIT_FUZZ_TARGET (fuzz/CMakeLists.txt builds one
// executable per target). Anything escaping the target (a contract
// violation, an unexpected exception) terminates: libFuzzer saves the input.
#include <cstddef>
#include <cstdint>

#include "fuzz/fuzz_targets.h"

extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  clothfit::CLOTHFIT_FUZZ_TARGET(data, size);
  return 0;
}
