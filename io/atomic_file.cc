#include "io/atomic_file.h"

#include <fcntl.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <cstdio>
#include <cstring>
#include <string>
#include <vector>

#include "io/input_error.h"

namespace clothfit {
namespace {

// Distinguishes temporary files of concurrent writers within one process.
std::atomic<unsigned> temp_counter{0};

[[noreturn]] void ThrowWriteError(const std::string& path, int error) {
  throw InputError(path + ": cannot write: " + std::strerror(error));
}

[[noreturn]] void ThrowReadError(const std::string& path, int error) {
  throw InputError(path + ": cannot read: " + std::strerror(error));
}

// Writes all of `content` to `fd`; returns 0 or the errno of the failure.
int WriteAll(int fd, const std::string& content) {
  const char* data = content.data();
  size_t left = content.size();
  while (left > 0) {
    const ssize_t written = ::write(fd, data, left);
    if (written < 0) {
      if (errno == EINTR) continue;
      return errno;
    }
    data += written;
    left -= static_cast<size_t>(written);
  }
  return 0;
}

// Creates a new temporary file beside `path` (so that rename() stays within
// one file system and is atomic); returns its descriptor, sets *temp_path.
int CreateTempBeside(const std::string& path, std::string* temp_path) {
  if (path.empty()) ThrowWriteError(path, ENOENT);
  int fd = -1;
  for (int attempt = 0; attempt < 100 && fd < 0; ++attempt) {
    *temp_path = path + ".tmp." + std::to_string(::getpid()) + "." +
                 std::to_string(temp_counter.fetch_add(1));
    fd = ::open(temp_path->c_str(), O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC,
                0666);
    if (fd < 0 && errno != EEXIST) ThrowWriteError(path, errno);
  }
  if (fd < 0) ThrowWriteError(path, EEXIST);
  return fd;
}

}  // namespace

void CheckWritable(const std::string& path) {
  std::string temp_path;
  const int fd = CreateTempBeside(path, &temp_path);
  ::close(fd);
  ::unlink(temp_path.c_str());
}

void WriteFileAtomically(const std::string& path, const std::string& content) {
  std::string temp_path;
  const int fd = CreateTempBeside(path, &temp_path);

  int error = WriteAll(fd, content);
  if (::close(fd) != 0 && error == 0) error = errno;
  if (error == 0 && std::rename(temp_path.c_str(), path.c_str()) != 0) {
    error = errno;
  }
  if (error != 0) {
    ::unlink(temp_path.c_str());
    ThrowWriteError(path, error);
  }
}

void WriteAtomicallyVia(
    const std::string& path,
    const std::function<std::string(const std::string&)>& write) {
  std::string temp_path;
  ::close(CreateTempBeside(path, &temp_path));
  std::string problem;
  try {
    problem = write(temp_path);
  } catch (...) {
    ::unlink(temp_path.c_str());
    throw;
  }
  if (problem.empty() && std::rename(temp_path.c_str(), path.c_str()) != 0) {
    problem = std::string("cannot write: ") + std::strerror(errno);
  }
  if (!problem.empty()) {
    ::unlink(temp_path.c_str());
    throw InputError(path + ": " + problem);
  }
}

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

std::string ReadFileToString(const std::string& path) {
  std::string content;
  ReadFileInChunks(path,
                   [&](std::string_view chunk) { content.append(chunk); });
  return content;
}

}  // namespace clothfit
