// A plausibility check of an image file's structure before OpenImageIO
// opens it, for the formats whose Debian 12 libraries trust sizes they read
// from the file (found by fuzz/mask_target.cc; docs/reliability.md):
//
// - OpenEXR 3.1 allocates what a header attribute's size says: a 700-byte
//   file whose string attribute claims 1.8 GB makes it allocate and fill
//   1.8 GB before it notices the file is short; a data window of 2^31
//   lines sizes its line-offset table from it. Checked: every attribute
//   (name, type, int32 size, value; one header per part) fits in the file,
//   and the data window has at most `max_pixels` pixels and no more lines
//   than the file can hold offsets for.
// - libpng + OpenImageIO 2.4 leak memory when a PNG ends early (the read
//   callback longjmps past a std::string). Checked: the chunks (big-endian
//   length, type, data, CRC) fit in the file, up to IEND.
//
// Other formats, and files that do not start with the EXR or PNG magic
// number, are left to OpenImageIO.
#pragma once

#include <cstdint>
#include <string>

namespace clothfit {

// "" when the file is plausible or not EXR/PNG; otherwise the problem
// (without the file name), e.g. "truncated PNG: chunk 'IDAT' needs 4096
// bytes, the file has 12 left".
std::string CheckImageHeader(const std::string& path, int64_t max_pixels);

}  // namespace clothfit
