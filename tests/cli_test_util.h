// Helpers for the tests that run the clothfit executable (docs/cli.md):
// running it with captured output, and the checks every bad input must
// pass.
#pragma once

#include <gtest/gtest.h>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <initializer_list>
#include <iterator>
#include <set>
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

// A texture-map fit that wrote its map: exit 0, or exit 1 because some
// texel has a lobe entry at a search limit or was scaled down to conserve
// energy (named, the map still written).
inline bool WroteTextureMap(const RunResult& r) {
  return r.status == 0 ||
         (r.status == 1 &&
          (r.err.find("at a search limit") != std::string::npos ||
           r.err.find("scaled down to conserve energy") != std::string::npos) &&
          r.err.find("no usable solution") == std::string::npos);
}

inline std::string Describe(const RunResult& r) {
  return "exit " + std::to_string(r.status) + "\nstdout:\n" + r.out +
         "\nstderr:\n" + r.err;
}

// The names of the regular files in `dir`.
inline std::set<std::string> FilesIn(const std::filesystem::path& dir) {
  std::set<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(dir)) {
    names.insert(entry.path().filename().string());
  }
  return names;
}

inline size_t Count(const std::string& text, const std::string& piece) {
  size_t n = 0;
  for (size_t pos = text.find(piece); pos != std::string::npos;
       pos = text.find(piece, pos + 1)) {
    ++n;
  }
  return n;
}

// Bad input: exit status 2, one error message on stderr (one line,
// "error: ...") holding every piece, nothing on stdout, and no file left
// behind in `dir` other than those it held before.
inline void ExpectBadInput(const std::filesystem::path& dir,
                           const std::vector<std::string>& args,
                           const std::vector<std::string>& pieces) {
  const std::set<std::string> before = FilesIn(dir);
  const RunResult r = RunClothfit(dir, args);
  std::string what;
  for (const std::string& a : args) what += " " + a;
  EXPECT_EQ(r.status, 2) << what << "\n" << Describe(r);
  EXPECT_EQ(r.err.rfind("error: ", 0), 0u) << what << "\n" << r.err;
  EXPECT_EQ(Count(r.err, "\n"), 1u) << what << "\n" << r.err;
  EXPECT_EQ(r.out, "") << what;
  for (const std::string& piece : pieces) {
    EXPECT_NE(r.err.find(piece), std::string::npos)
        << what << ": '" << piece << "' not in: " << r.err;
  }
  EXPECT_EQ(FilesIn(dir), before) << what;
}

}  // namespace testing_util
}  // namespace clothfit
