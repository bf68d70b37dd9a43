// A minimal PNG encoder for the glTF export's textures (PNG 1.2, ISO/IEC
// 15948): 8-bit RGB or RGBA, filter 0, the image data in stored (not
// compressed) deflate blocks, so that the export needs no image library.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace clothfit {

// The PNG file of a width x height image with `channels` (3 or 4) bytes
// per pixel, rows top to bottom. Throws std::invalid_argument for a size
// that does not match.
std::string EncodePng(int width, int height, int channels,
                      const std::vector<uint8_t>& pixels);

// Linear [0, 1] to the 8-bit sRGB encoding glTF's colour textures use
// (IEC 61966-2-1), and to a plain 8-bit value.
uint8_t SrgbByte(double linear);
uint8_t LinearByte(double value);
// The linear value an 8-bit sRGB byte decodes to.
double SrgbToLinear(uint8_t byte);

}  // namespace clothfit
