// Output files are written to a temporary name beside the target and renamed
// into place only when complete, so a failed or interrupted run never leaves
// a half-written file and never clobbers an earlier good one.
#pragma once

#include <functional>
#include <string>
#include <string_view>

namespace clothfit {

// Writes `content` to `path` atomically. Throws InputError naming the path
// and the system's reason when the file cannot be written.
void WriteFileAtomically(const std::string& path, const std::string& content);

// Writes `path` atomically through `write`, for libraries that open the
// file themselves (OpenEXR, OpenImageIO): `write` is given the name of a
// new, empty file beside `path`, writes it, and returns "" or the problem
// ("cannot write image: ..."). The file is renamed over `path` when
// `write` succeeded and removed otherwise, also when it throws. Throws
// InputError "path: problem".
void WriteAtomicallyVia(
    const std::string& path,
    const std::function<std::string(const std::string&)>& write);

// Throws InputError ("path: cannot write: reason") unless a file can be
// created beside `path` (its directory exists and is writable): a command
// checks its output before a long computation, not after. Leaves nothing
// behind.
void CheckWritable(const std::string& path);

// Reads a whole file. Throws InputError naming the path when it cannot.
std::string ReadFileToString(const std::string& path);

// Reads a file piece by piece (1 MiB at a time), handing each piece to
// `consume` (pieces split lines anywhere); a file of any size in constant
// memory. Throws InputError naming the path when it cannot be read;
// exceptions from `consume` pass through.
void ReadFileInChunks(const std::string& path,
                      const std::function<void(std::string_view)>& consume);

}  // namespace clothfit
