// Output files are written to a temporary name beside the target and renamed
// into place only when complete, so a failed or interrupted run never leaves
// a half-written file and never clobbers an earlier good one.
#pragma once

#include <string>

namespace clothfit {

// Writes `content` to `path` atomically. Throws InputError naming the path
// and the system's reason when the file cannot be written.
void WriteFileAtomically(const std::string& path, const std::string& content);

// Reads a whole file. Throws InputError naming the path when it cannot.
std::string ReadFileToString(const std::string& path);

}  // namespace clothfit
