// Runs the clothfit executable in tests: arguments quoted for /bin/sh,
// stdout and stderr captured, the exit status returned.
#pragma once

#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <string>
#include <vector>

namespace clothfit {
namespace testing_util {

inline std::string ReadText(const std::filesystem::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::string(std::istreambuf_iterator<char>(in),
                     std::istreambuf_iterator<char>());
}

inline void WriteText(const std::filesystem::path& path,
                      const std::string& text) {
  std::ofstream out(path, std::ios::binary);
  out << text;
}

// Single-quotes a word for /bin/sh.
inline std::string Quote(const std::string& word) {
  std::string out = "'";
  for (char c : word) {
    if (c == '\'') {
      out += "'\\''";
    } else {
      out += c;
    }
  }
  return out + "'";
}

struct RunResult {
  int status = -1;  // exit status, -1 if the process did not exit normally
  std::string out;
  std::string err;
};

// Runs `clothfit ARGS...` with stdout and stderr captured in files of
// `dir` (named so that they do not clash with the files a test checks).
inline RunResult RunClothfit(const std::filesystem::path& dir,
                             const std::vector<std::string>& args) {
  std::string command = Quote(CLOTHFIT_BINARY);
  for (const std::string& arg : args) command += " " + Quote(arg);
  const std::filesystem::path out_path = dir / "_stdout.txt";
  const std::filesystem::path err_path = dir / "_stderr.txt";
  command += " </dev/null >" + Quote(out_path.string()) + " 2>" +
             Quote(err_path.string());
  const int raw = std::system(command.c_str());
  RunResult result;
  if (raw != -1 && WIFEXITED(raw)) result.status = WEXITSTATUS(raw);
  result.out = ReadText(out_path);
  result.err = ReadText(err_path);
  std::filesystem::remove(out_path);
  std::filesystem::remove(err_path);
  return result;
}

inline std::string Describe(const RunResult& r) {
  return "exit " + std::to_string(r.status) + "\nstdout:\n" + r.out +
         "\nstderr:\n" + r.err;
}

}  // namespace testing_util
}  // namespace clothfit
