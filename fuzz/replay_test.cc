// Replays every file of fuzz/corpus/<target>/ and fuzz/regressions/<target>/
// through the fuzz targets (fuzz/fuzz_targets.h) in the normal build, so
// that the seeds and every crash the fuzzers found stay checked without
// clang. A file fails the test when the target lets anything but InputError
// escape (a FuzzContractError names the broken promise).
#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <ostream>
#include <string>
#include <vector>

#include "fuzz/fuzz_targets.h"

namespace clothfit {

// Test names show the target's name, not its bytes.
void PrintTo(const FuzzTarget& target, std::ostream* out) {
  *out << target.name;
}

namespace {

namespace fs = std::filesystem;

std::vector<fs::path> FilesUnder(const fs::path& folder) {
  std::vector<fs::path> files;
  if (!fs::is_directory(folder)) return files;
  for (const fs::directory_entry& entry : fs::directory_iterator(folder)) {
    if (entry.is_regular_file()) files.push_back(entry.path());
  }
  std::sort(files.begin(), files.end());
  return files;
}

std::vector<uint8_t> ReadBytes(const fs::path& path) {
  std::ifstream in(path, std::ios::binary);
  return std::vector<uint8_t>(std::istreambuf_iterator<char>(in), {});
}

class ReplayTest : public testing::TestWithParam<FuzzTarget> {};

TEST_P(ReplayTest, EveryCorpusAndRegressionFileIsHandled) {
  const FuzzTarget& target = GetParam();
  const fs::path root(CLOTHFIT_FUZZ_DIR);
  std::vector<fs::path> files = FilesUnder(root / "corpus" / target.name);
  ASSERT_FALSE(files.empty()) << "no seeds in fuzz/corpus/" << target.name;
  const std::vector<fs::path> regressions =
      FilesUnder(root / "regressions" / target.name);
  files.insert(files.end(), regressions.begin(), regressions.end());
  for (const fs::path& file : files) {
    SCOPED_TRACE(file.string());
    const std::vector<uint8_t> bytes = ReadBytes(file);
    EXPECT_NO_THROW(target.run(bytes.data(), bytes.size()));
  }
}

INSTANTIATE_TEST_SUITE_P(Targets, ReplayTest, testing::ValuesIn(kFuzzTargets),
                         [](const testing::TestParamInfo<FuzzTarget>& info) {
                           return std::string(info.param.name);
                         });

}  // namespace
}  // namespace clothfit
