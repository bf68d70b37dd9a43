// The readers' side of io/atomic_file.h: whole documents, files piece by
// piece, and whether an input is a regular file.
#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <cerrno>
#include <cstring>
#include <string>
#include <vector>

#include "io/atomic_file.h"
#include "io/input_error.h"

namespace clothfit {
namespace {

[[noreturn]] void ThrowReadError(const std::string& path, int error) {
  throw InputError(path + ": cannot read: " + std::strerror(error));
}

}  // namespace

void ReadFileInChunks(const std::string& path,
                      const std::function<void(std::string_view)>& consume) {
  const int fd = ::open(path.c_str(), O_RDONLY | O_CLOEXEC);
  if (fd < 0) ThrowReadError(path, errno);
  struct stat info;
  if (::fstat(fd, &info) != 0) {
    const int error = errno;
    ::close(fd);
    ThrowReadError(path, error);
  }
  if (S_ISDIR(info.st_mode)) {
    ::close(fd);
    ThrowReadError(path, EISDIR);
  }
  std::vector<char> buffer(1 << 20);
  while (true) {
    const ssize_t got = ::read(fd, buffer.data(), buffer.size());
    if (got < 0) {
      if (errno == EINTR) continue;
      const int error = errno;
      ::close(fd);
      ThrowReadError(path, error);
    }
    if (got == 0) break;
    try {
      consume(std::string_view(buffer.data(), static_cast<size_t>(got)));
    } catch (...) {
      ::close(fd);
      throw;
    }
  }
  ::close(fd);
}

std::string RegularFileProblem(const std::string& path) {
  struct stat info;
  if (::stat(path.c_str(), &info) != 0) return std::strerror(errno);
  if (S_ISDIR(info.st_mode)) return std::strerror(EISDIR);
  if (!S_ISREG(info.st_mode)) {
    return "not a regular file (a device, pipe or socket)";
  }
  return "";
}

std::string ReadFileToString(const std::string& path, size_t max_bytes) {
  std::string content;
  ReadFileInChunks(path, [&](std::string_view chunk) {
    if (chunk.size() > max_bytes - content.size()) {
      throw InputError(path + ": larger than the " +
                       std::to_string(max_bytes >> 20) +
                       " MiB limit of a document");
    }
    content.append(chunk);
  });
  return content;
}

}  // namespace clothfit
