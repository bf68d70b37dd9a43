#include "apps/full_binary.h"

#include <limits.h>
#include <unistd.h>

#include <cerrno>
#include <cstdio>
#include <cstring>
#include <iostream>
#include <string>

#include "io/input_error.h"

namespace clothfit {
namespace {

int program_argc = 0;
char** program_argv = nullptr;

}  // namespace

void SetProgramArguments(int argc, char** argv) {
  program_argc = argc;
  program_argv = argv;
}

void RunInFullBinary() {
  char self[PATH_MAX];
  const ssize_t n = ::readlink("/proc/self/exe", self, sizeof(self) - 1);
  if (n <= 0 || program_argv == nullptr) {
    throw InputError(
        "clothfit-full: cannot be found (this command needs images)");
  }
  std::string path(self, static_cast<size_t>(n));
  path = path.substr(0, path.rfind('/') + 1) + "clothfit-full";
  std::cout.flush();
  std::fflush(stdout);
  ::execv(path.c_str(), program_argv);
  throw InputError(path + ": cannot run: " + std::strerror(errno) +
                   " (clothfit runs it for commands that read or write "
                   "images; install it beside clothfit)");
}

}  // namespace clothfit
