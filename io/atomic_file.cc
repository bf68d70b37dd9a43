// The writers' side of io/atomic_file.h. A regular output is written to an
// unnamed file in its directory (Linux O_TMPFILE; a named temporary file
// where the file system has none) and linked and renamed over the target
// only when complete, so that a crash, a full disk or a kill -9 leaves the
// earlier file and nothing else. Devices, pipes and standard output are
// written directly. Named temporary files are removed on SIGINT, SIGTERM,
// SIGHUP and SIGQUIT.
#include "io/atomic_file.h"

#include <fcntl.h>
#include <limits.h>
#include <sys/stat.h>
#include <unistd.h>

#include <atomic>
#include <cerrno>
#include <csignal>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <filesystem>
#include <iostream>
#include <mutex>
#include <optional>
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

// Writes all of `data` to `fd`; returns 0 or the errno of the failure.
int WriteAll(int fd, const char* data, size_t left) {
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

// Named temporary files that exist now, removed by the signal handler: a
// fixed table of fixed buffers, since a handler may not allocate.
constexpr int kTempSlots = 16;
char temp_names[kTempSlots][PATH_MAX];
std::atomic<bool> temp_used[kTempSlots];

void RemoveTempsAndDie(int signal) {
  for (int i = 0; i < kTempSlots; ++i) {
    if (temp_used[i].load()) ::unlink(temp_names[i]);
  }
  std::signal(signal, SIG_DFL);
  std::raise(signal);
}

// Installs the handler for the signals that end a process by default (not
// for one that its parent set to be ignored, as nohup does).
void InstallSignalCleanup() {
  static std::once_flag once;
  std::call_once(once, [] {
    for (int signal : {SIGINT, SIGTERM, SIGHUP, SIGQUIT}) {
      struct sigaction old {};
      if (::sigaction(signal, nullptr, &old) != 0) continue;
      if (old.sa_handler != SIG_DFL) continue;
      struct sigaction action {};
      action.sa_handler = RemoveTempsAndDie;
      sigemptyset(&action.sa_mask);
      ::sigaction(signal, &action, nullptr);
    }
  });
}

// Registers a named temporary file for removal on a signal; -1 when the
// table is full (the file is then only removed by its owner).
int RegisterTemp(const std::string& name) {
  InstallSignalCleanup();
  if (name.size() >= PATH_MAX) return -1;
  for (int i = 0; i < kTempSlots; ++i) {
    bool expected = false;
    if (temp_used[i].load() ||
        !temp_used[i].compare_exchange_strong(expected, true)) {
      continue;
    }
    std::memcpy(temp_names[i], name.c_str(), name.size() + 1);
    return i;
  }
  return -1;
}

void UnregisterTemp(int slot) {
  if (slot >= 0) temp_used[slot].store(false);
}

std::string DirectoryOf(const std::string& path) {
  const size_t slash = path.rfind('/');
  if (slash == std::string::npos) return ".";
  return slash == 0 ? "/" : path.substr(0, slash);
}

// A temporary name beside `path` whose last component fits NAME_MAX: the
// target's name, shortened if need be, + ".tmp.PID.N".
std::string TempNameBeside(const std::string& path) {
  const size_t slash = path.rfind('/');
  const std::string dir =
      slash == std::string::npos ? "" : path.substr(0, slash + 1);
  std::string base = slash == std::string::npos ? path : path.substr(slash + 1);
  const std::string suffix = ".tmp." + std::to_string(::getpid()) + "." +
                             std::to_string(temp_counter.fetch_add(1));
  if (base.size() + suffix.size() > NAME_MAX) {
    base.resize(NAME_MAX - suffix.size());
  }
  return dir + base + suffix;
}

// Whether `a` and `b` are one existing file (device and inode: also
// through hard links).
bool SameFile(const std::string& a, const std::string& b) {
  struct stat sa, sb;
  return ::stat(a.c_str(), &sa) == 0 && ::stat(b.c_str(), &sb) == 0 &&
         sa.st_dev == sb.st_dev && sa.st_ino == sb.st_ino;
}

// The absolute path `path` names, its existing part with links resolved.
std::string Canonical(const std::string& path) {
  std::error_code error;
  const std::filesystem::path absolute = std::filesystem::absolute(path, error);
  if (error) return path;
  const std::filesystem::path p =
      std::filesystem::weakly_canonical(absolute, error);
  return error ? absolute.string() : p.string();
}

// N when `path` is this process's /proc/self/fd/N (or /proc/PID/fd/N,
// /dev/fd/N: its folder resolves to one of these).
std::optional<int> OwnDescriptor(const std::string& path) {
  const size_t slash = path.rfind('/');
  if (slash == std::string::npos || slash + 1 >= path.size()) {
    return std::nullopt;
  }
  const std::string name = path.substr(slash + 1);
  if (name.size() > 9 ||
      name.find_first_not_of("0123456789") != std::string::npos) {
    return std::nullopt;
  }
  char folder[PATH_MAX];
  const std::string dir = slash == 0 ? "/" : path.substr(0, slash);
  if (::realpath(dir.c_str(), folder) == nullptr) return std::nullopt;
  const std::string own = "/proc/" + std::to_string(::getpid()) + "/fd";
  if (folder != own && std::string(folder) != "/proc/self/fd") {
    return std::nullopt;
  }
  return std::stoi(name);
}

}  // namespace

void CheckOutputsDistinct(const std::vector<NamedFile>& outputs,
                          const std::vector<NamedFile>& inputs) {
  for (size_t i = 0; i < outputs.size(); ++i) {
    const NamedFile& out = outputs[i];
    if (out.path == "-") continue;
    const OutputTarget target = ResolveOutput(out.path);
    if (target.direct()) continue;
    for (const NamedFile& in : inputs) {
      if (in.path.empty() || in.path == "-" ||
          !SameFile(target.path, in.path)) {
        continue;
      }
      throw InputError(out.path + ": " + out.option +
                       " names the same file as " + in.option + " (" + in.path +
                       "): an input is never overwritten; choose another "
                       "output");
    }
    for (size_t j = 0; j < i; ++j) {
      const NamedFile& other = outputs[j];
      if (other.path == "-" ||
          (Canonical(target.path) != Canonical(other.path) &&
           !SameFile(target.path, other.path))) {
        continue;
      }
      throw InputError(out.path + ": " + out.option +
                       " names the same file as " + other.option +
                       ": each output needs its own file");
    }
  }
}

OutputTarget ResolveOutput(const std::string& path) {
  if (path.empty()) {
    throw InputError("'': cannot write: an output needs a file name");
  }
  if (path == "-") return {path, OutputTarget::kDescriptor, 1};
  std::string p = path;
  for (int hop = 0; hop < 40; ++hop) {
    // /dev/stdout links to /proc/self/fd/1, whose own link ("pipe:[N]", or
    // a file the shell opened) is not a path to follow: the descriptor is.
    const std::optional<int> fd = OwnDescriptor(p);
    if (fd) return {p, OutputTarget::kDescriptor, *fd};
    struct stat info;
    if (::lstat(p.c_str(), &info) != 0) {
      if (errno == ENOENT) return {p, OutputTarget::kNewFile};
      ThrowWriteError(path, errno);
    }
    if (S_ISLNK(info.st_mode)) {
      std::vector<char> link(PATH_MAX + 1);
      const ssize_t n = ::readlink(p.c_str(), link.data(), PATH_MAX);
      if (n < 0) ThrowWriteError(path, errno);
      const std::string to(link.data(), static_cast<size_t>(n));
      p = to.front() == '/' ? to : DirectoryOf(p) + "/" + to;
      continue;
    }
    if (S_ISDIR(info.st_mode)) ThrowWriteError(path, EISDIR);
    if (S_ISREG(info.st_mode)) return {p, OutputTarget::kRegularFile};
    return {p, OutputTarget::kSpecialFile};
  }
  ThrowWriteError(path, ELOOP);
}

OutputFile::OutputFile(const std::string& path)
    : path_(path), target_(ResolveOutput(path)) {
  // A device, pipe or standard output gets the content once it is complete,
  // copied from a file staged in the temporary directory.
  const bool direct = target_.direct();
  std::string dir;
  if (direct) {
    const char* tmp = std::getenv("TMPDIR");
    dir = tmp != nullptr && *tmp != '\0' ? tmp : "/tmp";
  } else {
    dir = DirectoryOf(target_.path);
  }
  fd_ = ::open(dir.c_str(), O_TMPFILE | O_RDWR | O_CLOEXEC, 0666);
  if (fd_ >= 0) {
    write_path_ = "/proc/self/fd/" + std::to_string(fd_);
    if (::access(write_path_.c_str(), W_OK) == 0) return;
    ::close(fd_);  // no /proc: a named file instead
    fd_ = -1;
  }
  const std::string beside = direct ? dir + "/clothfit-output" : target_.path;
  for (int attempt = 0; attempt < 100 && fd_ < 0; ++attempt) {
    write_path_ = TempNameBeside(beside);
    fd_ = ::open(write_path_.c_str(), O_RDWR | O_CREAT | O_EXCL | O_CLOEXEC,
                 0666);
    if (fd_ < 0 && errno != EEXIST) ThrowWriteError(path_, errno);
  }
  if (fd_ < 0) ThrowWriteError(path_, EEXIST);
  named_ = true;
  slot_ = RegisterTemp(write_path_);
}

OutputFile::~OutputFile() {
  if (named_) ::unlink(write_path_.c_str());
  UnregisterTemp(slot_);
  if (fd_ >= 0) ::close(fd_);
}

void OutputFile::Write(const std::string& content) {
  const int error = WriteAll(fd_, content.data(), content.size());
  if (error != 0) ThrowWriteError(path_, error);
}

void OutputFile::Commit() {
  if (target_.direct()) {
    CopyToTarget();
    return;
  }
  if (!named_) {
    // Give the unnamed file a temporary name (registered, for the moment
    // until the rename) and rename that over the target.
    std::string name;
    int error = EEXIST;
    for (int attempt = 0; attempt < 100 && error == EEXIST; ++attempt) {
      name = TempNameBeside(target_.path);
      error = ::linkat(AT_FDCWD, write_path_.c_str(), AT_FDCWD, name.c_str(),
                       AT_SYMLINK_FOLLOW) == 0
                  ? 0
                  : errno;
    }
    if (error != 0) ThrowWriteError(path_, error);
    write_path_ = name;
    named_ = true;
    slot_ = RegisterTemp(write_path_);
  }
  if (std::rename(write_path_.c_str(), target_.path.c_str()) != 0) {
    ThrowWriteError(path_, errno);
  }
  named_ = false;  // it is the target now: nothing to remove
  UnregisterTemp(slot_);
  slot_ = -1;
}

void OutputFile::CopyToTarget() {
  int out = target_.fd;
  if (target_.kind == OutputTarget::kDescriptor) {
    std::cout.flush();  // what the command printed before comes first
    std::fflush(stdout);
  } else {
    out = ::open(target_.path.c_str(), O_WRONLY | O_CLOEXEC);
    if (out < 0) ThrowWriteError(path_, errno);
  }
  std::vector<char> buffer(1 << 20);
  off_t offset = 0;
  int error = 0;
  while (error == 0) {
    const ssize_t got = ::pread(fd_, buffer.data(), buffer.size(), offset);
    if (got < 0 && errno == EINTR) continue;
    if (got <= 0) {
      error = got < 0 ? errno : 0;
      break;
    }
    offset += got;
    error = WriteAll(out, buffer.data(), static_cast<size_t>(got));
  }
  if (target_.kind != OutputTarget::kDescriptor && ::close(out) != 0 &&
      error == 0) {
    error = errno;
  }
  if (error != 0) ThrowWriteError(path_, error);
}

void WriteFileAtomically(const std::string& path, const std::string& content) {
  OutputFile out(path);
  out.Write(content);
  out.Commit();
}

void WriteAtomicallyVia(
    const std::string& path,
    const std::function<std::string(const std::string&)>& write) {
  OutputFile out(path);
  const std::string problem = write(out.write_path());
  if (!problem.empty()) throw InputError(path + ": " + problem);
  out.Commit();
}

void CheckWritable(const std::string& path) {
  const OutputTarget target = ResolveOutput(path);
  if (target.kind == OutputTarget::kDescriptor) {
    if (::fcntl(target.fd, F_GETFL) < 0) ThrowWriteError(path, errno);
    return;
  }
  if (target.kind == OutputTarget::kSpecialFile) {
    if (::access(target.path.c_str(), W_OK) != 0) {
      ThrowWriteError(path, errno);
    }
    return;
  }
  OutputFile probe(path);  // removed again: nothing is committed
}

}  // namespace clothfit
