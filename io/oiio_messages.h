// OpenImageIO's messages for the image readers (masks, image stacks): on
// one line, and only ours. libpng prints its errors on stderr by itself
// before OpenImageIO returns them, so that bad input would get two
// messages; OpenImageIO's calls run Quietly. Only the library call: an
// AddressSanitizer report from our own code must still reach stderr.
#pragma once

#include <mutex>
#include <string>

namespace clothfit {

// A library's (possibly multi-line) message on one line; "unknown error"
// when empty.
std::string OneLineMessage(const std::string& message);

// Points file descriptor 2 at /dev/null while alive (one at a time in the
// process: the saved descriptor must be the real stderr).
class QuietStderr {
 public:
  QuietStderr();
  ~QuietStderr();
  QuietStderr(const QuietStderr&) = delete;
  QuietStderr& operator=(const QuietStderr&) = delete;

 private:
  std::lock_guard<std::mutex> lock_;
  int saved_ = -1;
};

// Runs `call` (an OpenImageIO read) with stderr silenced; returns its
// result.
template <typename Call>
auto Quietly(Call call) {
  QuietStderr quiet;
  return call();
}

}  // namespace clothfit
