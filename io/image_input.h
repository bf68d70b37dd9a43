// Reading an image's pixels with OpenImageIO, shared by the readers of
// masks (io/mask_io.h) and image stacks (io/image_stack.h).
#pragma once

#include <functional>
#include <string>
#include <vector>

namespace clothfit {

struct ImagePixels {
  int width = 0, height = 0, depth = 1;
  int channels = 0;
  int alpha_channel = -1;     // as the file names it; -1: none named
  std::vector<float> pixels;  // row by row, channels interleaved
};

// Opens `path` with the values as stored (PNG/TIFF colours not multiplied
// by alpha) and reads every channel as float. `check_header` (may be
// empty) sees the header before the pixels are allocated and may throw.
// Returns false with *error set to OpenImageIO's message on one line when
// the file cannot be opened or read. libpng prints its errors on stderr by
// itself before OpenImageIO returns them: stderr is silenced meanwhile, so
// that bad input gets one message (the caller's).
bool ReadImagePixels(
    const std::string& path,
    const std::function<void(const ImagePixels&)>& check_header,
    ImagePixels* image, std::string* error);

// A library's (possibly multi-line) message on one line.
std::string OneLineMessage(const std::string& message);

}  // namespace clothfit
