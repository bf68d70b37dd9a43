// The bad-input matrix: every reader through every command that
// uses it - measurement tables, parameter files, holes parameter files,
// masks, image stacks - and every command's output path. Each defect gives
// exit 2 and one message naming the file (with line and column, or the
// key, where there is one) and the problem; nothing on stdout, no file
// left behind (testing_util::ExpectBadInput).
#include <gtest/gtest.h>

#include <cctype>
#include <filesystem>
#include <functional>
#include <ostream>
#include <string>
#include <vector>

#include "io/mask_io.h"
#include "io/table.h"
#include "models/math.h"
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

struct Defect {
  std::string name;
  std::string content;  // the bad file's bytes
  // The message must hold each; one starting with ":" follows the name.
  std::vector<std::string> pieces;
};

// A command line with "BAD" where the defective file goes and "OUT" (with
// an extension where the command needs one) where its output goes.
using Command = std::vector<std::string>;

const char kTableHeader[] = "theta_i,phi_i,theta_o,phi_o,r,g,b\n";
const char kTableRow[] = "10,0,20,180,0.1,0.2,0.3\n";

// A directory of valid inputs: a brdf table (good.csv), a transmittance
// table (dirs.csv), a thread parameter file, a holes parameter file and a
// mask; `BAD` and `OUT` paths inside it.
class BadInputTest : public ::testing::Test {
 protected:
  void SetUp() override {
    dir_ = testing_util::FreshTestDir("bad_input_");
    WriteText(dir_ / "good.csv", std::string(kTableHeader) + kTableRow +
                                     "30,90,40,270,1,2,3\n" +
                                     "50,10,60,200,0.5,0.5,0.5\n");
    MeasurementTable views;
    views.quantity = Quantity::kTransmittance;
    views.channels = 1;
    for (double theta : {0.0, 30.0, 50.0}) {
      TableRow row;
      row.wo = DirectionFromAngles(Radians(theta), 0.3);
      row.value = glm::dvec3(0.5);
      views.rows.push_back(row);
    }
    WriteTable(views, (dir_ / "dirs.csv").string());
    WriteText(dir_ / "thread.json",
              "{\"model\": \"thread\", \"eta\": 1.5, \"kd\": 0.2, "
              "\"gamma_s_deg\": 6, \"gamma_v_deg\": 14, "
              "\"albedo\": [0.3, 0.2, 0.1]}");
    WriteText(dir_ / "holes.json",
              "{\"model\": \"holes\", \"thickness_texels\": 1.0}");
    WriteMask(MaskFromRows({"#####", "#..##", "#..##", "#####", "#####"}),
              (dir_ / "net.png").string());
  }

  std::vector<std::string> Fill(const Command& command,
                                const std::string& bad) const {
    std::vector<std::string> args;
    for (const std::string& word : command) {
      if (word == "BAD") {
        args.push_back(bad);
      } else if (word.rfind("OUT", 0) == 0) {  // OUT, OUT.exr, ...
        args.push_back((dir_ / ("out" + word.substr(3))).string());
      } else if (word.find('.') != std::string::npos && word[0] != '-' &&
                 fs::exists(dir_ / word)) {
        args.push_back((dir_ / word).string());  // one of the valid inputs
      } else {
        args.push_back(word);
      }
    }
    return args;
  }

  // Every defect through every command; the bad file is `name`.
  void CheckMatrix(const std::vector<Command>& commands,
                   const std::vector<Defect>& defects,
                   const std::string& name) {
    const std::string bad = (dir_ / name).string();
    for (const Defect& defect : defects) {
      WriteText(bad, defect.content);
      for (const Command& command : commands) {
        SCOPED_TRACE(defect.name + ": " + command[0] + " " + command[1]);
        // ":3:5:" means "bad.csv:3:5:" (file, line, column together).
        std::vector<std::string> pieces = {name};
        for (const std::string& piece : defect.pieces) {
          pieces.push_back(!piece.empty() && piece[0] == ':' ? name + piece
                                                             : piece);
        }
        ExpectBadInput(dir_, Fill(command, bad), pieces);
      }
    }
    fs::remove(bad);
  }

  fs::path dir_;
};

std::vector<Defect> TableDefects() {
  const std::string h = kTableHeader, r = kTableRow;
  return {
      {"empty file", "", {"no header"}},
      {"header only", h, {":1:", "no rows"}},
      {"missing column",
       "theta_i,phi_i,theta_o,r,g,b\n10,0,20,1,1,1\n",
       {":1:", "missing column 'phi_o'"}},
      {"duplicate column",
       "theta_i,phi_i,theta_o,phi_o,r,g,b,r\n" + r.substr(0, r.size() - 1) +
           ",1\n",
       {":1:8:", "duplicate column 'r'"}},
      {"unknown column",
       "theta_i,phi_i,theta_o,phi_o,r,g,b,colour\n" +
           r.substr(0, r.size() - 1) + ",1\n",
       {":1:8:", "unknown column 'colour'"}},
      {"non-numeric",
       h + r + "10,0,abc,180,1,1,1\n",
       {":3:3:", "'theta_o'", "cannot parse 'abc'"}},
      {"nan", h + r + "10,0,20,180,nan,1,1\n", {":3:5:", "not a finite"}},
      {"inf", h + r + "10,0,20,180,1,-inf,1\n", {":3:6:", "not a finite"}},
      {"angle out of range",
       h + r + "10,0,200,180,1,1,1\n",
       {":3:3:", "angle 200 is out of range"}},
      {"zero direction vector",
       "wi_x,wi_y,wi_z,wo_x,wo_y,wo_z,r,g,b\n0,0,1,0,0,1,1,1,1\n"
       "0,0,0,0,0,1,1,1,1\n",
       {":3:1:", "zero vector"}},
      {"negative sigma",
       "theta_i,phi_i,theta_o,phi_o,r,g,b,sigma\n10,0,20,180,1,1,1,-1\n",
       {":2:8:", "sigma must be positive"}},
      {"inconsistent channel count",
       h + r + "10,0,20,180,1,1\n",
       {":3:", "6 fields, header has 7"}},
      {"value and rgb mixed",
       "theta_i,phi_i,theta_o,phi_o,value,r,g,b\n10,0,20,180,1,1,1,1\n",
       {":1:", "cannot be mixed"}},
      {"huge value",
       h + r + "10,0,20,180,1,1,1e300\n",
       {":3:7:", "out of range"}},
      {"non-UTF-8 bytes",
       h + r + "10,0,2\xff\xfe,180,1,1,1\n",
       {":3:3:", "cannot parse '2\\xff\\xfe'"}},
  };
}

std::vector<Command> TableCommands() {
  return {
      {"eval", "--params", "thread.json", "--dirs", "BAD", "--out", "OUT"},
      {"synth", "--params", "thread.json", "--dirs", "BAD", "--out", "OUT"},
      {"fit", "--model", "thread", "--data", "BAD", "--out", "OUT"},
      {"fit", "--model", "cloth", "--preset", "linen_plain", "--data", "BAD",
       "--out", "OUT"},
      {"fit", "--model", "slab", "--data", "BAD", "--out", "OUT"},
      {"fit", "--model", "lafortune", "--data", "BAD", "--out", "OUT.json"},
      {"fit", "--model", "holes", "--mask", "net.png", "--data", "BAD", "--out",
       "OUT"},
      {"plot", "--params", "thread.json", "--data", "BAD", "--out", "OUT"},
      {"holes", "eval", "--mask", "net.png", "--thickness", "1", "--dirs",
       "BAD", "--out", "OUT"},
      {"holes", "truth", "--mask", "net.png", "--thickness", "1", "--dirs",
       "BAD", "--out", "OUT"},
  };
}

std::vector<Defect> ParamFileDefects() {
  const std::string good =
      "\"model\": \"thread\", \"kd\": 0.2, \"gamma_s_deg\": 6, "
      "\"gamma_v_deg\": 14, \"albedo\": [0.3, 0.2, 0.1]";
  return {
      {"empty file", "", {"invalid JSON", "line 1, column 1"}},
      {"syntax error",
       "{\n" + good + ",\n,\"eta\": 1}",
       {"invalid JSON", "line 3"}},
      {"truncated", "{" + good + ", \"eta\": 1.", {"invalid JSON"}},
      {"not an object", "[1, 2]", {"must be a JSON object"}},
      {"unknown model",
       "{\"model\": \"velvet\"}",
       {"key 'model'", "unknown model"}},
      {"missing key", "{" + good + "}", {"key 'eta'", "missing"}},
      {"unknown key",
       "{" + good + ", \"eta\": 1.5, \"colour\": 1}",
       {"key 'colour'", "unknown"}},
      {"wrong type",
       "{" + good + ", \"eta\": \"high\"}",
       {"key 'eta'", "must be a number"}},
      {"out of range",
       "{" + good + ", \"eta\": -1}",
       {"key 'eta'", "must be in"}},
      {"nan", "{" + good + ", \"eta\": NaN}", {"invalid JSON"}},
      {"huge value",
       "{" + good + ", \"eta\": 1e400}",
       {"invalid JSON", "number overflow", "1e400"}},
      {"non-UTF-8 bytes",
       "{" + good + ", \"eta\": 1.5, \"n\xff\": 1}",
       {"invalid JSON", "ill-formed UTF-8", "\\xff"}},
  };
}

std::vector<Command> ParamFileCommands() {
  return {
      {"eval", "--params", "BAD", "--dirs", "good.csv", "--out", "OUT"},
      {"synth", "--params", "BAD", "--rows", "10", "--out", "OUT"},
      {"fit", "--model", "thread", "--data", "good.csv", "--init", "BAD",
       "--out", "OUT"},
      {"fit", "--model", "thread", "--data", "good.csv", "--truth", "BAD",
       "--out", "OUT"},
      {"fit", "--model", "cloth", "--data", "good.csv", "--init", "BAD",
       "--out", "OUT"},
      {"fit", "--model", "slab", "--data", "good.csv", "--init", "BAD", "--out",
       "OUT"},
      {"plot", "--params", "BAD", "--data", "good.csv", "--out", "OUT"},
      {"render", "--params", "BAD", "--out", "OUT.exr"},
      {"synth", "--model", "slab", "--params", "BAD", "--out", "OUT"},
  };
}

std::vector<Command> HolesParamCommands() {
  return {
      {"holes", "eval", "--mask", "net.png", "--params", "BAD", "--dirs",
       "dirs.csv", "--out", "OUT"},
      {"holes", "truth", "--mask", "net.png", "--params", "BAD", "--dirs",
       "dirs.csv", "--out", "OUT"},
      {"fit", "--model", "holes", "--mask", "net.png", "--data", "dirs.csv",
       "--init", "BAD", "--out", "OUT"},
  };
}

std::vector<Defect> HolesParamDefects() {
  return {
      {"empty file", "", {"invalid JSON"}},
      {"truncated",
       "{\"model\": \"holes\", \"thickness_texels\": ",
       {"invalid JSON"}},
      {"missing key",
       "{\"model\": \"holes\"}",
       {"thickness_texels", "missing"}},
      {"negative thickness",
       "{\"model\": \"holes\", \"thickness_texels\": -2}",
       {"thickness_texels"}},
      {"unknown key",
       "{\"model\": \"holes\", \"thickness_texels\": 1, \"depth\": 1}",
       {"'depth'", "unknown"}},
      {"huge value",
       "{\"model\": \"holes\", \"thickness_texels\": 1e999}",
       {"number overflow"}},
  };
}

std::vector<Command> MaskCommands() {
  return {
      {"holes", "analyze", "--mask", "BAD", "--out", "OUT"},
      {"holes", "eval", "--mask", "BAD", "--thickness", "1", "--dirs",
       "dirs.csv", "--out", "OUT"},
      {"holes", "truth", "--mask", "BAD", "--thickness", "1", "--dirs",
       "dirs.csv", "--out", "OUT"},
      {"fit", "--model", "holes", "--mask", "BAD", "--data", "dirs.csv",
       "--out", "OUT"},
      {"render", "--params", "holes.json", "--mask", "BAD", "--out", "OUT.exr"},
  };
}

// `bytes` with `count` bytes from `at` inverted.
std::string Garbled(std::string bytes, size_t at, size_t count) {
  for (size_t i = at; i < at + count && i < bytes.size(); ++i) {
    bytes[i] = static_cast<char>(~bytes[i]);
  }
  return bytes;
}

// Image bytes: a valid PNG of a mask cut short or garbled, an empty file,
// text.
std::vector<Defect> MaskDefects(const fs::path& dir) {
  const std::string path = (dir / "whole.png").string();
  WriteMask(MaskFromRows({"##.", "#..", "###"}), path);
  const std::string png = ReadText(path);
  fs::remove(path);
  return {
      {"truncated PNG", png.substr(0, 40), {"cannot read mask image"}},
      {"truncated PNG data",
       png.substr(0, png.size() - 20),
       {"cannot read mask image"}},
      {"empty file", "", {"cannot read mask image"}},
      {"not an image", "hello\n", {"cannot read mask image"}},
      // Whole chunks, but the compressed pixels garbled: libpng itself
      // would print a line of its own before OpenImageIO's message.
      {"corrupt PNG data",
       Garbled(png, png.find("IDAT") + 8, 10),
       {"cannot read mask image"}},
  };
}

// One reader through one command: every defect of the reader.
struct MatrixCase {
  std::string reader;
  Command command;
  std::function<std::vector<Defect>(const fs::path& dir)> defects;
  std::string bad_name;
};

// gtest prints a parameter as bytes unless told otherwise.
void PrintTo(const MatrixCase& c, std::ostream* out) {
  *out << c.reader << ":";
  for (const std::string& word : c.command) *out << " " << word;
}

std::vector<MatrixCase> MatrixCases() {
  std::vector<MatrixCase> cases;
  auto add = [&](const std::string& reader,
                 const std::vector<Command>& commands,
                 std::function<std::vector<Defect>(const fs::path&)> defects,
                 const std::string& bad_name) {
    for (const Command& c : commands)
      cases.push_back({reader, c, defects, bad_name});
  };
  add(
      "table", TableCommands(), [](const fs::path&) { return TableDefects(); },
      "bad.csv");
  add(
      "params", ParamFileCommands(),
      [](const fs::path&) { return ParamFileDefects(); }, "bad.json");
  add(
      "holes_params", HolesParamCommands(),
      [](const fs::path&) { return HolesParamDefects(); }, "bad.json");
  add("mask", MaskCommands(), MaskDefects, "bad.png");
  return cases;
}

// "table_fit_model_thread_data": the reader and the command's words
// (options and values, not paths).
std::string CaseName(const ::testing::TestParamInfo<MatrixCase>& info) {
  std::string name = info.param.reader;
  for (const std::string& word : info.param.command) {
    if (word == "BAD" || word.rfind("OUT", 0) == 0 ||
        word.find('.') != std::string::npos) {
      continue;
    }
    std::string clean;
    for (char c : word) {
      if (std::isalnum(static_cast<unsigned char>(c))) clean += c;
    }
    if (!clean.empty()) name += "_" + clean;
  }
  return name;
}

class BadInputMatrixTest : public BadInputTest,
                           public ::testing::WithParamInterface<MatrixCase> {};

TEST_P(BadInputMatrixTest, EveryDefectIsExitTwoWithOneMessage) {
  const MatrixCase& c = GetParam();
  CheckMatrix({c.command}, c.defects(dir_), c.bad_name);
}

INSTANTIATE_TEST_SUITE_P(Readers, BadInputMatrixTest,
                         ::testing::ValuesIn(MatrixCases()), CaseName);

// An image stack's manifest and its images (fit --model lafortune
// --stack): the defects of a table that a manifest can have, and broken
// images.
TEST_F(BadInputTest, ImageStacksThroughFit) {
  const RunResult synth = RunClothfit(
      dir_, {"synth", "--gonio", "plain", "--texels", "2", "--directions", "2",
             "--stack", (dir_ / "stack.csv").string()});
  ASSERT_EQ(synth.status, 0) << Describe(synth);
  const std::string image = ReadText(dir_ / "stack_0000.exr");
  WriteText(dir_ / "cut.exr", image.substr(0, image.size() / 2));
  WriteText(dir_ / "text.exr", "not an image\n");
  const std::string h = "theta_i,phi_i,theta_o,phi_o,file\n";
  CheckMatrix(
      {{"fit", "--model", "lafortune", "--stack", "BAD", "--out", "OUT"}},
      {
          {"empty file", "", {"bad_stack.csv"}},
          {"header only", h, {"bad_stack.csv:1"}},
          {"missing column",
           "theta_i,phi_i,theta_o,file\n1,2,3,cut.exr\n",
           {"bad_stack.csv:1", "phi_o"}},
          {"non-numeric",
           h + "1,2,x,4,stack_0000.exr\n",
           {"bad_stack.csv:2:3", "cannot parse"}},
          {"nan", h + "1,2,nan,4,stack_0000.exr\n", {"bad_stack.csv:2:3"}},
          {"angle out of range",
           h + "1,2,400,4,stack_0000.exr\n",
           {"bad_stack.csv:2:3", "out of range"}},
          {"missing image",
           h + "1,2,3,4,none.exr\n",
           {"none.exr", "No such file", "bad_stack.csv:2"}},
          {"truncated EXR",
           h + "1,2,3,4,cut.exr\n",
           {"cut.exr", "cannot read image", "bad_stack.csv:2"}},
          {"not an image",
           h + "1,2,3,4,text.exr\n",
           {"text.exr", "cannot read image", "bad_stack.csv:2"}},
          {"non-UTF-8 file name",
           h + "1,2,3,4,n\xff.exr\n",
           {"cannot read image", "bad_stack.csv:2"}},
          {"missing normal map",
           "# normal_map: none_n.exr\n" + h + "1,2,3,4,stack_0000.exr\n",
           {"none_n.exr", "No such file", "bad_stack.csv:1"}},
          {"normal map not an image",
           "# normal_map: text.exr\n" + h + "1,2,3,4,stack_0000.exr\n",
           {"text.exr", "cannot read image", "bad_stack.csv:1"}},
          {"normal map named twice",
           "# normal_map: a.exr\n# normal_map: a.exr\n" + h +
               "1,2,3,4,stack_0000.exr\n",
           {"bad_stack.csv:2", "normal_map", "first on line 1"}},
      },
      "bad_stack.csv");
}

// A missing input file, for every reader.
TEST_F(BadInputTest, MissingFilesAreNamed) {
  const std::string none = (dir_ / "none.csv").string();
  const std::string none_json = (dir_ / "none.json").string();
  const std::string none_png = (dir_ / "none.png").string();
  for (const Command& command : TableCommands()) {
    ExpectBadInput(dir_, Fill(command, none), {"none.csv"});
  }
  ExpectBadInput(
      dir_,
      Fill({"eval", "--params", "BAD", "--dirs", "good.csv", "--out", "OUT"},
           none_json),
      {"none.json"});
  ExpectBadInput(
      dir_, Fill({"render", "--params", "BAD", "--out", "OUT.exr"}, none_json),
      {"none.json"});
  ExpectBadInput(
      dir_,
      Fill({"holes", "analyze", "--mask", "BAD", "--out", "OUT"}, none_png),
      {"none.png"});
  ExpectBadInput(
      dir_,
      Fill({"fit", "--model", "lafortune", "--stack", "BAD", "--out", "OUT"},
           none),
      {"none.csv"});
}

// An output path inside a regular file cannot be created: every command
// that writes says so before it works (and leaves nothing).
TEST_F(BadInputTest, UnwritableOutputForEveryCommand) {
  const std::string out = (dir_ / "good.csv" / "out").string();
  const std::vector<Command> commands = {
      {"eval", "--params", "thread.json", "--dirs", "good.csv", "--out"},
      {"synth", "--params", "thread.json", "--rows", "10", "--out"},
      {"synth", "--model", "slab", "--tau", "0.2", "--albedo", "0.5", "--out"},
      {"fit", "--model", "thread", "--data", "good.csv", "--out"},
      {"fit", "--model", "slab", "--data", "good.csv", "--out"},
      {"fit", "--model", "lafortune", "--data", "good.csv", "--out"},
      {"fit", "--model", "holes", "--mask", "net.png", "--data", "dirs.csv",
       "--out"},
      {"plot", "--params", "thread.json", "--data", "good.csv", "--out"},
      {"holes", "analyze", "--mask", "net.png", "--out"},
      {"holes", "eval", "--mask", "net.png", "--thickness", "1", "--dirs",
       "dirs.csv", "--out"},
      {"holes", "truth", "--mask", "net.png", "--thickness", "1", "--dirs",
       "dirs.csv", "--out"},
      {"render", "--params", "thread.json", "--out"},
      {"preset", "silk_shot", "--out"},
  };
  for (Command command : commands) {
    command.push_back("BAD");
    SCOPED_TRACE(command[0] + " " + command[1]);
    ExpectBadInput(dir_, Fill(command, out), {"good.csv/out"});
  }
}

}  // namespace
}  // namespace clothfit
