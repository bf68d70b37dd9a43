#include "fuzz/fuzz_util.h"

#include <unistd.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <system_error>

namespace clothfit::fuzz {
namespace {

void RemoveScratchDir() {
  std::error_code error;
  std::filesystem::remove_all(ScratchDir(), error);
}

std::string MakeScratchDir() {
  const char* base = std::getenv("TMPDIR");
  std::string pattern =
      std::string(base && *base ? base : "/tmp") + "/clothfit-fuzz-XXXXXX";
  if (::mkdtemp(pattern.data()) == nullptr) {
    std::perror("clothfit fuzz: mkdtemp");
    std::abort();
  }
  return pattern;
}

}  // namespace

const std::string& ScratchDir() {
  // Never destroyed, so that the exit handler can still read it.
  static const std::string* const dir = [] {
    auto* made = new std::string(MakeScratchDir());
    std::atexit(RemoveScratchDir);
    return made;
  }();
  return *dir;
}

void WriteBytes(const std::string& path, const uint8_t* data, size_t size) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out.write(reinterpret_cast<const char*>(data),
            static_cast<std::streamsize>(size));
  out.close();
  if (!out) {
    std::fprintf(stderr, "clothfit fuzz: cannot write %s\n", path.c_str());
    std::abort();
  }
}

}  // namespace clothfit::fuzz
