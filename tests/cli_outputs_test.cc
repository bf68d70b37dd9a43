// Where outputs go: a regular file is replaced atomically; a device, a pipe
// and "-" are written directly and their errors reported; a symbolic link
// is followed, not replaced; an output that names an input or another
// output is refused; long names and signals leave nothing behind. The
// devices are nodes made in the test's own directory (as root), never the
// system's /dev/null or /dev/full: a regression that renamed over them
// would replace the machine's device.
#include <gtest/gtest.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/sysmacros.h>
#include <sys/wait.h>
#include <unistd.h>

#include <cstdlib>
#include <filesystem>
#include <string>
#include <vector>

#include "tests/cli_test_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using testing_util::Describe;
using testing_util::ExpectBadInput;
using testing_util::ReadText;
using testing_util::RunClothfit;
using testing_util::RunResult;
using testing_util::WriteText;

class CliOutputsTest : public ::testing::Test {
 protected:
  void SetUp() override { dir_ = testing_util::FreshTestDir("cli_outputs_"); }
  void TearDown() override { fs::remove_all(dir_); }
  std::string P(const std::string& name) const {
    return (dir_ / name).string();
  }
  // A character device node `name` in the test's directory (1, minor: 3 is
  // null, 7 is full); false when this user may not make one.
  bool MakeDevice(const std::string& name, unsigned minor) const {
    return ::mknod(P(name).c_str(), S_IFCHR | 0666, makedev(1, minor)) == 0;
  }
  bool IsCharDevice(const std::string& name) const {
    struct stat info;
    return ::lstat(P(name).c_str(), &info) == 0 && S_ISCHR(info.st_mode);
  }
  RunResult Synth(const std::string& out, const std::string& rows = "20") {
    return RunClothfit(dir_, {"synth", "--preset", "linen_plain", "--rows",
                              rows, "--out", out});
  }
  fs::path dir_;
};

TEST_F(CliOutputsTest, DevicesAreWrittenDirectlyAndTheirErrorsReported) {
  if (!MakeDevice("null", 3) || !MakeDevice("full", 7) ||
      !MakeDevice("full.exr", 7) || !MakeDevice("null.exr", 3)) {
    GTEST_SKIP() << "cannot make device nodes (not root)";
  }
  RunResult r = Synth(P("null"));
  EXPECT_EQ(r.status, 0) << Describe(r);
  EXPECT_TRUE(IsCharDevice("null"));

  ExpectBadInput(dir_, {"synth", "--preset", "linen_plain", "--out", P("full")},
                 {P("full"), "cannot write", "No space left on device"});
  EXPECT_TRUE(IsCharDevice("full"));
  ExpectBadInput(dir_, {"preset", "linen_plain", "--out", P("full")},
                 {"No space left on device"});

  // A parameter mip map to a device: the EXR alone (it holds its index), no
  // "null.exr.json" made beside the device.
  ASSERT_EQ(Synth(P("t.csv"), "200").status, 0);
  r = RunClothfit(dir_, {"render", "--preset", "linen_plain", "--out",
                         P("null.exr"), "--png", P("r.png"), "--size", "16"});
  EXPECT_EQ(r.status, 0) << Describe(r);
  EXPECT_TRUE(IsCharDevice("null.exr"));
  ExpectBadInput(dir_,
                 {"render", "--preset", "linen_plain", "--out", P("full.exr"),
                  "--png", P("r2.png"), "--size", "16"},
                 {"No space left on device"});
  EXPECT_TRUE(IsCharDevice("full.exr"));
}

// "-", /dev/stdout and /proc/self/fd/1 are this process's standard output
// (here a file the test opened): written through the descriptor, not
// renamed over what its link points to. /dev/stdout is the test's own link
// of the same kind (-> /proc/self/fd/1), so that a regression cannot
// replace the machine's.
TEST_F(CliOutputsTest, DashAndDevStdoutAreStandardOutput) {
  fs::create_symlink("/proc/self/fd/1", dir_ / "stdout");
  for (const std::string& out :
       {std::string("-"), P("stdout"), std::string("/proc/self/fd/1")}) {
    SCOPED_TRACE(out);
    const RunResult r = Synth(out, "5");
    ASSERT_EQ(r.status, 0) << Describe(r);
    EXPECT_EQ(r.out.rfind("# clothfit-table 1\n", 0), 0u) << r.out;
    // The table: its '#' lines, the header and 5 rows.
    size_t rows = 0;
    for (size_t at = 0; at < r.out.size(); at = r.out.find('\n', at) + 1) {
      rows += r.out[at] != '#' ? 1 : 0;
      if (r.out.find('\n', at) == std::string::npos) break;
    }
    EXPECT_EQ(rows, 6u) << r.out;
  }
  EXPECT_FALSE(fs::exists(dir_ / "-"));
  EXPECT_TRUE(fs::is_symlink(dir_ / "stdout"));
}

TEST_F(CliOutputsTest, SymbolicLinksAreFollowedNotReplaced) {
  WriteText(dir_ / "real.csv", "earlier\n");
  fs::create_symlink("real.csv", dir_ / "link.csv");
  RunResult r = Synth(P("link.csv"));
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_TRUE(fs::is_symlink(dir_ / "link.csv"));
  EXPECT_EQ(ReadText(dir_ / "real.csv").rfind("# clothfit-table 1", 0), 0u);
  // A dangling link: its target is made.
  fs::create_symlink("made.csv", dir_ / "dangling.csv");
  r = Synth(P("dangling.csv"));
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_TRUE(fs::is_symlink(dir_ / "dangling.csv"));
  EXPECT_TRUE(fs::is_regular_file(dir_ / "made.csv"));
  // A loop is named as one.
  fs::create_symlink("loop.csv", dir_ / "loop.csv");
  ExpectBadInput(dir_,
                 {"synth", "--preset", "linen_plain", "--out", P("loop.csv")},
                 {P("loop.csv"), "Too many levels of symbolic links"});
}

TEST_F(CliOutputsTest, AnOutputThatNamesAnInputIsRefused) {
  ASSERT_EQ(Synth(P("a.csv"), "60").status, 0);
  const std::string before = ReadText(dir_ / "a.csv");
  fs::create_symlink("a.csv", dir_ / "alias.csv");
  fs::create_hard_link(dir_ / "a.csv", dir_ / "hard.csv");
  for (const char* out : {"a.csv", "alias.csv", "hard.csv"}) {
    ExpectBadInput(
        dir_,
        {"fit", "--model", "thread", "--data", P("a.csv"), "--out", P(out)},
        {"--out names the same file as --data", "never overwritten"});
    ExpectBadInput(dir_,
                   {"eval", "--preset", "linen_plain", "--dirs", P("a.csv"),
                    "--out", P(out)},
                   {"--out names the same file as --dirs"});
  }
  EXPECT_EQ(ReadText(dir_ / "a.csv"), before);
  ExpectBadInput(dir_,
                 {"synth", "--model", "slab", "--tau", "1", "--albedo", "0.5",
                  "--out", P("x.csv"), "--transmittance", P("x.csv")},
                 {"--transmittance names the same file as --out"});
  ExpectBadInput(dir_,
                 {"render", "--preset", "linen_plain", "--out", P("r.exr"),
                  "--png", P("r.exr")},
                 {"--png names the same file as --out"});
  // The same file by another name: compared as absolute paths.
  ExpectBadInput(
      dir_,
      {"synth", "--model", "slab", "--tau", "1", "--albedo", "0.5", "--out",
       P("y.csv"), "--transmittance", (dir_ / "." / "y.csv").string()},
      {"--transmittance names the same file as --out"});
  // Every table of a slab fit's list, every image of a stack.
  ExpectBadInput(dir_,
                 {"fit", "--model", "slab", "--data",
                  P("alias.csv") + "," + P("a.csv"), "--out", P("a.csv")},
                 {"--out names the same file as --data"});
  ASSERT_EQ(RunClothfit(dir_, {"synth", "--gonio", "plain", "--texels", "2",
                               "--directions", "2", "--stack", P("m.csv")})
                .status,
            0);
  ExpectBadInput(dir_,
                 {"fit", "--model", "lafortune", "--stack", P("m.csv"), "--out",
                  P("m_0000.exr")},
                 {"--out names the same file as an image of --stack"});
  // A mip map's index copy is an output too.
  WriteText(dir_ / "mask.pgm", "P2\n2 2\n255\n0 255\n255 0\n");
  ExpectBadInput(dir_,
                 {"holes", "analyze", "--mask", P("mask.pgm"), "--out",
                  P("c.exr"), "--distances", P("c.exr.json")},
                 {"the index copy of --out names the same file as "
                  "--distances"});
  // Every output is checked before the run: the first was written, then
  // the second failed.
  ExpectBadInput(
      dir_,
      {"synth", "--model", "slab", "--tau", "1", "--albedo", "0.5", "--out",
       P("first.csv"), "--transmittance", P("nodir/second.csv")},
      {"nodir/second.csv: cannot write"});
  // An output a command derives: render's PNG beside --out.
  WriteText(dir_ / "r.png", "a mask");
  ExpectBadInput(dir_,
                 {"render", "--preset", "linen_plain", "--mask", P("r.png"),
                  "--out", P("r.exr")},
                 {"the PNG beside --out names the same file as --mask"});
  // --out and --stack were both accepted and --out ignored.
  ExpectBadInput(dir_,
                 {"synth", "--gonio", "plain", "--texels", "2", "--directions",
                  "2", "--out", P("g.csv"), "--stack", P("m.csv")},
                 {"give --out T.csv or --stack M.csv"});
}

// A temporary name is the target's + ".tmp.PID.N": for a 250-byte name it
// would pass NAME_MAX (255) and the write failed.
TEST_F(CliOutputsTest, LongOutputNamesAreWritten) {
  const std::string name = std::string(246, 'n') + ".csv";
  const RunResult r = Synth(P(name));
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_EQ(testing_util::FilesIn(dir_).count(name), 1u);
  EXPECT_EQ(testing_util::FilesIn(dir_).size(), 1u);  // no temporary left
}

// SIGINT, SIGTERM or SIGHUP while a large table is written: the earlier file
// stays, and no temporary file is left.
TEST_F(CliOutputsTest, SignalsLeaveTheEarlierFileAndNoTemporary) {
  for (const int signal : {SIGINT, SIGTERM, SIGHUP, SIGKILL}) {
    SCOPED_TRACE(signal);
    WriteText(dir_ / "big.csv", "earlier result\n");
    const pid_t pid = fork();
    ASSERT_GE(pid, 0);
    if (pid == 0) {
      const std::string out = P("big.csv");
      execl(CLOTHFIT_BINARY, CLOTHFIT_BINARY, "synth", "--preset",
            "linen_plain", "--rows", "1000000", "--out", out.c_str(),
            static_cast<char*>(nullptr));
      _exit(127);
    }
    usleep(1500 * 1000);  // 1e6 rows take ~4 s; the writing starts ~1 s
    ASSERT_EQ(kill(pid, signal), 0);
    int status = 0;
    ASSERT_EQ(waitpid(pid, &status, 0), pid);
    ASSERT_TRUE(WIFSIGNALED(status)) << "the synth ended before the signal";
    EXPECT_EQ(ReadText(dir_ / "big.csv"), "earlier result\n");
    EXPECT_EQ(testing_util::FilesIn(dir_), std::set<std::string>({"big.csv"}));
  }
}

// A full disk (a 256 KiB tmpfs, where this user may mount one): exit 2
// naming the output, and nothing left: no partial table, and no images of
// an image stack whose later images or manifest did not fit (synth --stack
// left m_normal.exr).
TEST_F(CliOutputsTest, AFullDiskLeavesNothingBehind) {
  const fs::path tiny = dir_ / "tiny";
  fs::create_directory(tiny);
  if (std::system(("mount -t tmpfs -o size=256k tmpfs " +
                   testing_util::Quote(tiny.string()) + " 2>/dev/null")
                      .c_str()) != 0) {
    GTEST_SKIP() << "cannot mount a tmpfs here";
  }
  struct Unmount {
    std::string path;
    ~Unmount() { std::system(("umount " + testing_util::Quote(path)).c_str()); }
  } unmount{tiny.string()};
  RunResult r = RunClothfit(
      dir_, {"synth", "--gonio", "plain", "--texels", "16", "--directions", "4",
             "--stack", (tiny / "m.csv").string()});
  EXPECT_EQ(r.status, 2) << Describe(r);
  EXPECT_NE(r.err.find("No space left on device"), std::string::npos) << r.err;
  EXPECT_TRUE(fs::is_empty(tiny));
  r = Synth((tiny / "big.csv").string(), "20000");
  EXPECT_EQ(r.status, 2) << Describe(r);
  EXPECT_NE(r.err.find("big.csv: cannot write: No space left on device"),
            std::string::npos)
      << r.err;
  EXPECT_TRUE(fs::is_empty(tiny));
}

TEST_F(CliOutputsTest, MessagesNameTheProblem) {
  ExpectBadInput(dir_, {"synth", "--preset", "linen_plain", "--out", ""},
                 {"option '--out' needs a value"});
  ExpectBadInput(dir_,
                 {"plot", "--preset", "linen_plain", "--incidence-deg", "",
                  "--out", P("p.png")},
                 {"option '--incidence-deg' needs a value"});
  std::string many = "0";
  for (int i = 1; i < 3000; ++i) many += "," + std::to_string(i % 90);
  ASSERT_EQ(Synth(P("t.csv")).status, 0);
  ExpectBadInput(dir_,
                 {"plot", "--preset", "linen_plain", "--data", P("t.csv"),
                  "--incidence-deg", many, "--out", P("p.png")},
                 {"at most 16 angles", "got 3000"});
  ExpectBadInput(dir_, {}, {"no command given", "clothfit --help"});
  // One alternation cannot measure the lookup table's change: it said the
  // table "still changed by 0 (threshold 0.1)".
  ASSERT_EQ(RunClothfit(dir_, {"synth", "--gonio", "plain", "--texels", "1",
                               "--directions", "8", "--out", P("g.csv")})
                .status,
            0);
  std::string table;
  for (std::string text = ReadText(dir_ / "g.csv"); !text.empty();) {
    std::string line = text.substr(0, text.find('\n'));
    text.erase(0, line.size() + 1);
    if (line[0] != '#') line.erase(line.rfind(',', line.rfind(',') - 1));
    table += line + "\n";  // without its s,t columns
  }
  WriteText(dir_ / "g.csv", table);
  const RunResult one =
      RunClothfit(dir_, {"fit", "--model", "lafortune", "--data", P("g.csv"),
                         "--alternations", "1", "--solve", "alternate", "--out",
                         P("g.json")});
  EXPECT_NE(one.out.find("1 alternation (the lookup table's change is "
                         "measured from the second on)"),
            std::string::npos)
      << Describe(one);
  EXPECT_NE(one.err.find("before the lookup table's change could be measured"),
            std::string::npos)
      << Describe(one);
  EXPECT_EQ(one.err.find("still changed by 0"), std::string::npos) << one.err;
  // A newline in a file name stays inside the one line.
  ExpectBadInput(dir_,
                 {"fit", "--model", "thread", "--data", P("a\nb.csv"), "--out",
                  P("o.json")},
                 {"a\\x0ab.csv"});
}

}  // namespace
}  // namespace clothfit
