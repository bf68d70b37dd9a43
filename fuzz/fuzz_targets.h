// Fuzz targets for the readers: one function per reader, fed
// arbitrary bytes. Each treats InputError (io/input_error.h) as the
// expected answer to bad input and returns; anything else is a bug and
// escapes: a crash, a sanitizer report, another exception, or a contract
// violation (FuzzContractError: e.g. a NaN in a table that was read
// successfully, or a written file that does not read back).
//
// The same functions run under libFuzzer (fuzz/fuzz_main.cc, clang,
// CLOTHFIT_FUZZ=ON) and in the normal build's replay test
// (fuzz/replay_test.cc), which feeds them every file of fuzz/corpus/<name>/
// and fuzz/regressions/<name>/.
#pragma once

#include <cstddef>
#include <cstdint>
#include <stdexcept>
#include <string>

namespace clothfit {

// A successfully read result broke the reader's documented contract.
class FuzzContractError : public std::logic_error {
 public:
  explicit FuzzContractError(const std::string& message)
      : std::logic_error("contract violated: " + message) {}
};

// Measurement tables (io/table.h ParseTable, the parser ReadTable streams
// into): rows finite, unit directions, sigma > 0; FormatTable reads back.
void FuzzTable(const uint8_t* data, size_t size);
// Parameter files (io/params_json.h ParseParamFile, every model): a holes
// file's numbers are finite; FormatParamFile reads back to the same text.
void FuzzParams(const uint8_t* data, size_t size);
// Image-stack manifests (io/image_stack.h ReadImageStack): the manifest
// text is written beside a few small valid images (img_000.exr,
// img_001.png, grey.png, rgba.png, big.png, written once per process).
void FuzzImageStack(const uint8_t* data, size_t size);
// Masks (io/mask_io.h ReadMask): the bytes are the image file, written to
// a temporary file named for the format its first bytes announce.
void FuzzMask(const uint8_t* data, size_t size);

struct FuzzTarget {
  const char* name;  // folder under fuzz/corpus/ and fuzz/regressions/
  void (*run)(const uint8_t* data, size_t size);
};
inline constexpr FuzzTarget kFuzzTargets[] = {
    {"table", FuzzTable},
    {"params", FuzzParams},
    {"image_stack", FuzzImageStack},
    {"mask", FuzzMask},
};

}  // namespace clothfit
