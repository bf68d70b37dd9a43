// Fuzz target: image-stack manifests (io/image_stack.h).
#include <filesystem>
#include <string>
#include <vector>

#include "fuzz/fuzz_util.h"
#include "io/image_stack.h"
#include "io/input_error.h"

namespace clothfit {
namespace {

using fuzz::Require;

// The images a manifest may list, written once per process beside it: the
// kinds ReadImageStack reads (float EXR, 8-bit PNG; grey, rgb, rgba), one
// of another size, and normal maps (any rgb image is one; zero.exr has a
// zero normal).
const std::string& StackDir() {
  static const std::string* const dir = [] {
    auto* made = new std::string(fuzz::ScratchDir() + "/stack");
    const std::string folder = *made;
    std::vector<float> rgb = {0.1f, 0.2f, 0.3f, 0.4f, 0.5f, 0.6f,
                              0.7f, 0.8f, 0.9f, 1.0f, 0.0f, 0.5f};
    std::vector<float> rgba = {0.1f, 0.2f, 0.3f, 1.0f, 0.4f, 0.5f, 0.6f, 0.5f,
                               0.7f, 0.8f, 0.9f, 0.0f, 1.0f, 0.0f, 0.5f, 1.0f};
    std::vector<float> grey = {0.0f, 0.25f, 0.5f, 1.0f};
    std::vector<float> big(3 * 2 * 3, 0.5f);
    std::vector<float> zero = rgb;
    zero[9] = zero[10] = zero[11] = 0.0f;
    std::filesystem::create_directories(folder);
    WriteImage(folder + "/img_000.exr", 2, 2, 3, false, true, rgb);
    WriteImage(folder + "/img_001.png", 2, 2, 3, false, false, rgb);
    WriteImage(folder + "/grey.png", 2, 2, 1, false, false, grey);
    WriteImage(folder + "/rgba.png", 2, 2, 3, true, false, rgba);
    WriteImage(folder + "/big.png", 3, 2, 3, false, false, big);
    WriteImage(folder + "/zero.exr", 2, 2, 3, false, true, zero);
    return made;
  }();
  return *dir;
}

}  // namespace

void FuzzImageStack(const uint8_t* data, size_t size) {
  const std::string manifest = StackDir() + "/manifest.csv";
  fuzz::WriteBytes(manifest, data, size);
  for (const int stride : {1, 2}) {
    ReadStackOptions options;
    options.stride = stride;
    MeasurementTable table;
    try {
      table = ReadImageStack(manifest, options);
    } catch (const InputError&) {
      return;  // the expected answer to bad input
    }
    fuzz::CheckTable(table);
    Require(table.has_texels, "a stack has texel indices");
    for (const TableRow& row : table.rows) {
      Require(row.s >= 0 && row.s < 3 && row.t >= 0 && row.t < 2,
              "texel inside the image");
    }
  }
}

}  // namespace clothfit
