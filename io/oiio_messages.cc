#include "io/oiio_messages.h"

#include <fcntl.h>
#include <unistd.h>

#include <cstdio>

namespace clothfit {
namespace {

std::mutex& StderrMutex() {
  static std::mutex mutex;
  return mutex;
}

}  // namespace

std::string OneLineMessage(const std::string& message) {
  std::string line;
  size_t start = 0;
  while (start <= message.size()) {
    size_t end = message.find('\n', start);
    if (end == std::string::npos) end = message.size();
    std::string part = message.substr(start, end - start);
    while (!part.empty() && (part.back() == ' ' || part.back() == '\r')) {
      part.pop_back();
    }
    if (!part.empty()) line += (line.empty() ? "" : "; ") + part;
    start = end + 1;
  }
  return line.empty() ? "unknown error" : line;
}

QuietStderr::QuietStderr() : lock_(StderrMutex()) {
  std::fflush(stderr);
  saved_ = dup(STDERR_FILENO);
  const int null = open("/dev/null", O_WRONLY | O_CLOEXEC);
  if (saved_ >= 0 && null >= 0) dup2(null, STDERR_FILENO);
  if (null >= 0) close(null);
}

QuietStderr::~QuietStderr() {
  std::fflush(stderr);
  if (saved_ >= 0) {
    dup2(saved_, STDERR_FILENO);
    close(saved_);
  }
}

}  // namespace clothfit
