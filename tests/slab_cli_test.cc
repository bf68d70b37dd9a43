// Slab parameter files (io/params_json, docs/formats.md) and the slab commands
// of the clothfit executable: synth --model slab (formulas, Monte Carlo, the
// error chart), fit --model slab, eval on slab files.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "io/params_json.h"
#include "io/table.h"
#include "models/evaluate.h"
#include "tests/cli_test_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using testing_util::Describe;
using testing_util::ErrorOf;
using testing_util::ExpectBadInput;
using testing_util::ExpectHas;
using testing_util::ReadText;
using testing_util::RunClothfit;
using testing_util::RunResult;
using testing_util::WriteText;

fs::path TestDir() { return testing_util::FreshTestDir("slab_cli_test_"); }

TEST(SlabParamsFile, ScalarAndPerChannelTauRoundTrip) {
  const ParamFile scalar = ParseParamFile(
      R"({"model": "slab", "tau": 0.5, "albedo": [0.9, 0.8, 0.7]})", "s.json");
  const SlabParams& p = std::get<SlabParams>(scalar.params);
  EXPECT_EQ(p.tau, glm::dvec3(0.5));
  EXPECT_EQ(p.albedo, glm::dvec3(0.9, 0.8, 0.7));
  EXPECT_EQ(std::string(ModelName(scalar.params)), "slab");
  const std::string text = FormatParamFile(scalar);
  EXPECT_NE(text.find("\"tau\": 0.5,"), std::string::npos) << text;
  SlabParams rgb;
  rgb.tau = {0.1, 0.2, 0.30000000000000004};
  rgb.albedo = glm::dvec3(1.0 / 3.0);
  const ParamFile back =
      ParseParamFile(FormatParamFile(ParamFile{rgb, ""}), "rgb.json");
  EXPECT_EQ(std::get<SlabParams>(back.params).tau, rgb.tau);
  EXPECT_EQ(std::get<SlabParams>(back.params).albedo, rgb.albedo);
}

TEST(SlabParamsFile, BadValuesAreRejectedByKey) {
  auto error = [](const std::string& text) {
    return ErrorOf([&] { ParseParamFile(text, "bad.json"); });
  };
  ExpectHas(error(R"({"model": "slab", "tau": 0, "albedo": 0.5})"),
            {"bad.json", "'tau'", "[1e-12, 10000]"});
  ExpectHas(error(R"({"model": "slab", "tau": -1, "albedo": 0.5})"),
            {"bad.json", "'tau'"});
  ExpectHas(
      error(R"({"model": "slab", "tau": 0.2, "albedo": [0.5, 1.2, 0.5]})"),
      {"bad.json", "'albedo'", "[0, 1]", "1.2"});
  ExpectHas(error(R"({"model": "slab", "albedo": 0.5})"), {"'tau'", "missing"});
  ExpectHas(error(R"({"model": "slab", "tau": 0.2, "albedo": 0.5, "g": 0})"),
            {"'g'", "unknown key"});
  ExpectHas(error(R"({"model": "slab", "tau": [0.2, 0.1], "albedo": 0.5})"),
            {"'tau'", "3 numbers"});
}

// synth (formulas) -> fit, with eval checking the fitted file: the fit
// recovers the parameters and eval gives the library's values for
// reflection, transmission and direct-transmittance rows.
TEST(SlabCli, SynthFitEvalRoundTrip) {
  const fs::path dir = TestDir();
  const std::string bsdf = (dir / "T.csv").string();
  const std::string direct = (dir / "D.csv").string();
  const std::string fit = (dir / "fit.json").string();
  RunResult r = RunClothfit(
      dir, {"synth", "--model", "slab", "--tau", "0.1,0.2,0.4", "--albedo",
            "0.9,0.6,0.3", "--out", bsdf, "--transmittance", direct});
  ASSERT_EQ(r.status, 0) << Describe(r);
  r = RunClothfit(dir, {"fit", "--model", "slab", "--per-channel-tau", "--data",
                        bsdf + "," + direct, "--out", fit});
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_NE(r.out.find("validity:"), std::string::npos) << r.out;
  EXPECT_NE(r.out.find("Constant-alpha baseline"), std::string::npos);
  const ParamFile file = ReadParamFile(fit);
  const SlabParams& p = std::get<SlabParams>(file.params);
  const glm::dvec3 tau(0.1, 0.2, 0.4), albedo(0.9, 0.6, 0.3);
  for (int c = 0; c < 3; ++c) {
    EXPECT_NEAR(p.tau[c], tau[c], 1e-6 * tau[c]);
    EXPECT_NEAR(p.albedo[c], albedo[c], 1e-6 * albedo[c]);
  }
  EXPECT_NE(file.fit_json.find("\"validity\""), std::string::npos);
  EXPECT_NE(file.fit_json.find("\"constant_alpha_baseline\""),
            std::string::npos);

  for (const std::string& dirs : {bsdf, direct}) {
    const std::string out = (dir / "O.csv").string();
    r = RunClothfit(dir,
                    {"eval", "--params", fit, "--dirs", dirs, "--out", out});
    ASSERT_EQ(r.status, 0) << Describe(r);
    const MeasurementTable want = ReadTable(dirs).table;
    const MeasurementTable got = ReadTable(out).table;
    EXPECT_EQ(got.quantity, want.quantity);
    ASSERT_EQ(got.rows.size(), want.rows.size());
    for (size_t i = 0; i < got.rows.size(); ++i) {
      const glm::dvec3 f =
          Evaluate(file.params, got.rows[i].wi, got.rows[i].wo, got.quantity);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(got.rows[i].value[c], f[c], 1e-12 * std::abs(f[c]));
        // And the synthetic data they came from (to the fit's accuracy).
        EXPECT_NEAR(got.rows[i].value[c], want.rows[i].value[c],
                    1e-5 * std::abs(want.rows[i].value[c]));
      }
    }
  }
}

TEST(SlabCli, MonteCarloTablesAreDeterministicAndCarrySigma) {
  const fs::path dir = TestDir();
  std::vector<std::string> texts;
  for (const char* threads : {"1", "2"}) {
    const std::string out =
        (dir / (std::string("T") + threads + ".csv")).string();
    const std::string direct = (dir / "D.csv").string();
    const RunResult r = RunClothfit(dir, {"synth",
                                          "--model",
                                          "slab",
                                          "--tau",
                                          "0.05",
                                          "--albedo",
                                          "0.8",
                                          "--mc",
                                          "--photons",
                                          "5000",
                                          "--threads",
                                          threads,
                                          "--theta-i",
                                          "0,45",
                                          "--theta-o",
                                          "0,30,60",
                                          "--out",
                                          out,
                                          "--transmittance",
                                          direct,
                                          "--seed",
                                          "3"});
    ASSERT_EQ(r.status, 0) << Describe(r);
    texts.push_back(ReadText(out));
    const MeasurementTable t = ReadTable(out).table;
    EXPECT_TRUE(t.has_sigma);
    ASSERT_EQ(t.rows.size(), 2u * 2u * 3u);
    EXPECT_LT(t.rows.back().wo.z, 0.0);
    const MeasurementTable d = ReadTable(direct).table;
    EXPECT_EQ(d.quantity, Quantity::kTransmittance);
    EXPECT_EQ(d.channels, 1);
    EXPECT_NE(ReadText(direct).find("theta_o,phi_o,value,sigma"),
              std::string::npos);
  }
  EXPECT_EQ(texts[0], texts[1]);
}

TEST(SlabCli, ErrorMapWritesPngAndCsv) {
  const fs::path dir = TestDir();
  const std::string png = (dir / "map.png").string();
  const RunResult r = RunClothfit(
      dir, {"synth", "--model", "slab", "--error-map", png, "--taus", "0.003,1",
            "--albedos", "0.2,1", "--photons", "4000"});
  ASSERT_EQ(r.status, 0) << Describe(r);
  const std::string image = ReadText(png);
  ASSERT_GT(image.size(), 1000u);
  EXPECT_EQ(image.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  const std::string csv = ReadText(dir / "map.csv");
  EXPECT_NE(csv.find("tau,albedo,relative_rms_error"), std::string::npos);
  // Four cells; the thin, dark one is within 1 %, the thick, bright one far
  // outside.
  std::vector<std::vector<double>> cells;
  size_t pos = csv.find("estimated_error\n") + 16;
  while (pos < csv.size()) {
    const size_t end = csv.find('\n', pos);
    std::vector<double> row;
    size_t a = pos;
    while (a < end) {
      size_t b = csv.find(',', a);
      if (b == std::string::npos || b > end) b = end;
      row.push_back(std::stod(csv.substr(a, b - a)));
      a = b + 1;
    }
    cells.push_back(row);
    pos = end + 1;
  }
  ASSERT_EQ(cells.size(), 4u);
  EXPECT_EQ(cells[0][0], 0.003);
  EXPECT_EQ(cells[0][1], 0.2);
  EXPECT_LT(cells[0][2], 0.01);
  EXPECT_EQ(cells[3][0], 1.0);
  EXPECT_EQ(cells[3][1], 1.0);
  EXPECT_GT(cells[3][2], 0.3);
}

TEST(SlabCli, FitReportsDataOutsideTheRegime) {
  const fs::path dir = TestDir();
  const std::string data = (dir / "T.csv").string();
  const std::string direct = (dir / "D.csv").string();
  RunResult r =
      RunClothfit(dir, {"synth", "--model", "slab", "--tau", "0.8", "--albedo",
                        "0.95", "--mc", "--photons", "5000", "--out", data,
                        "--transmittance", direct});
  ASSERT_EQ(r.status, 0) << Describe(r);
  r = RunClothfit(dir, {"fit", "--model", "slab", "--data", data + "," + direct,
                        "--out", (dir / "fit.json").string()});
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_NE(r.out.find("OUTSIDE the model's regime"), std::string::npos)
      << r.out;
  EXPECT_NE(r.err.find("warning: the data are outside"), std::string::npos)
      << r.err;
}

// docs/models.md: where single scattering is not accurate, the tool says so.
// The regimes come from the Monte Carlo chart of docs/slab.md: tau = 0.001,
// A = 1 is within 0.4 %; tau = 0.01, A = 0.8 is 2.2 % off (both below the
// paper's bound tau < 0.2). The note goes with the formulas' BSDF values
// only: Monte Carlo values and the direct transmittance are exact.
TEST(SlabCli, FormulasNoteWhenOutsideTheRegime) {
  const fs::path dir = TestDir();
  const std::string t = (dir / "T.csv").string();
  const std::string d = (dir / "D.csv").string();
  const std::string o = (dir / "O.csv").string();
  WriteText(dir / "in.json", R"({"model": "slab", "tau": 0.001, "albedo": 1})");
  WriteText(dir / "out.json",
            R"({"model": "slab", "tau": 0.01, "albedo": 0.8})");
  const std::string in_params = (dir / "in.json").string();
  const std::string out_params = (dir / "out.json").string();
  // Exit 0, the output written, and either nothing on stderr or one note
  // holding every piece.
  auto expect_note = [&](const std::vector<std::string>& args,
                         const std::string& path,
                         const std::vector<std::string>& pieces) {
    fs::remove(path);
    const RunResult r = RunClothfit(dir, args);
    std::string what;
    for (const std::string& a : args) what += " " + a;
    EXPECT_EQ(r.status, 0) << what << "\n" << Describe(r);
    EXPECT_GT(ReadTable(path).table.rows.size(), 0u) << what;
    if (pieces.empty()) {
      EXPECT_EQ(r.err, "") << what;
      return;
    }
    EXPECT_EQ(r.err.rfind("note: ", 0), 0u) << what << "\n" << r.err;
    EXPECT_EQ(testing_util::Count(r.err, "\n"), 1u) << what << "\n" << r.err;
    for (const std::string& piece : pieces) {
      EXPECT_NE(r.err.find(piece), std::string::npos)
          << what << ": '" << piece << "' not in: " << r.err;
    }
  };
  const std::vector<std::string> note = {"tau = 0.01", "albedo = 0.8", "regime",
                                         "synth --model slab --mc"};
  // Within the regime: no note, from synth or eval.
  expect_note({"synth", "--model", "slab", "--params", in_params, "--out", t,
               "--transmittance", d},
              t, {});
  expect_note({"eval", "--params", in_params, "--dirs", t, "--out", o}, o, {});
  // Outside: synth --model slab, plain synth of a slab file, eval.
  expect_note({"synth", "--model", "slab", "--tau", "0.01", "--albedo", "0.8",
               "--out", t},
              t, note);
  expect_note({"synth", "--params", out_params, "--rows", "20", "--out", t}, t,
              note);
  expect_note({"eval", "--params", out_params, "--dirs", t, "--out", o}, o,
              note);
  // One channel outside is enough; the note gives every channel.
  expect_note({"synth", "--model", "slab", "--tau", "0.001,0.001,0.01",
               "--albedo", "1,1,0.8", "--out", t},
              t, {"tau = 0.001,0.001,0.01", "albedo = 1,1,0.8"});
  // Exact values: the direct transmittance, Monte Carlo.
  expect_note({"synth", "--model", "slab", "--params", out_params,
               "--transmittance", d},
              d, {});
  expect_note({"eval", "--params", out_params, "--dirs", d, "--out", o}, o, {});
  expect_note(
      {"synth", "--model", "slab", "--params", out_params, "--mc", "--photons",
       "2000", "--theta-i", "30", "--theta-o", "0,60", "--out", t},
      t, {});
  // A polar plot of the model against the table: the same note.
  ASSERT_EQ(RunClothfit(dir, {"synth", "--model", "slab", "--params", in_params,
                              "--out", t})
                .status,
            0);
  for (const std::string& params : {in_params, out_params}) {
    const std::string png = (dir / "plot.png").string();
    const RunResult r = RunClothfit(
        dir, {"plot", "--params", params, "--data", t, "--out", png});
    ASSERT_EQ(r.status, 0) << Describe(r);
    EXPECT_TRUE(fs::exists(png));
    // (Besides the polar figure's warning that its panels show 27 of the
    // 108 rows.)
    if (params == in_params) {
      EXPECT_EQ(r.err.find("note: "), std::string::npos) << r.err;
    } else {
      EXPECT_NE(r.err.find("\nnote: tau = 0.01"), std::string::npos) << r.err;
    }
  }
}

TEST(SlabCli, FitThatDoesNotConvergeExitsOne) {
  const fs::path dir = TestDir();
  const std::string data = (dir / "T.csv").string();
  RunResult r = RunClothfit(dir, {"synth", "--model", "slab", "--tau", "0.3",
                                  "--albedo", "0.7", "--out", data});
  ASSERT_EQ(r.status, 0) << Describe(r);
  r = RunClothfit(
      dir, {"fit", "--model", "slab", "--data", data, "--max-iterations", "1",
            "--starts", "1", "--out", (dir / "fit.json").string()});
  EXPECT_EQ(r.status, 1) << Describe(r);
  EXPECT_NE(r.err.find("the fit did not converge"), std::string::npos) << r.err;
}

TEST(SlabCli, BadInputExitsTwoWithOneMessage) {
  const fs::path dir = TestDir();
  const std::string out = (dir / "T.csv").string();
  WriteText(dir / "zero.json", R"({"model": "slab", "tau": 0, "albedo": 0.5})");
  WriteText(dir / "thread.json",
            R"({"model": "thread", "eta": 1.5, "kd": 0.1, "gamma_s_deg": 3,
                "gamma_v_deg": 5, "albedo": 0.5})");
  ExpectBadInput(dir,
                 {"synth", "--model", "slab", "--params",
                  (dir / "zero.json").string(), "--out", out},
                 {"zero.json", "'tau'", "[1e-12, 10000]"});
  ExpectBadInput(dir,
                 {"synth", "--model", "slab", "--tau", "0.2", "--albedo", "1.5",
                  "--out", out},
                 {"albedo", "[0, 1]"});
  ExpectBadInput(dir, {"synth", "--model", "slab", "--tau", "-1", "--out", out},
                 {"tau", "[1e-12, 10000]"});
  ExpectBadInput(dir,
                 {"synth", "--model", "slab", "--tau", "0.2", "--theta-o",
                  "10,95", "--out", out},
                 {"--theta-o", "95"});
  ExpectBadInput(dir, {"synth", "--model", "slab", "--tau", "0.2"},
                 {"--out", "--transmittance"});
  ExpectBadInput(dir,
                 {"synth", "--model", "slab", "--tau", "0.2", "--mc", "--noise",
                  "0.1", "--out", out},
                 {"--noise", "--mc"});
  ExpectBadInput(dir, {"synth", "--model", "cloth", "--out", out}, {"--model"});
  ExpectBadInput(
      dir,
      {"fit", "--model", "slab", "--data", (dir / "missing.csv").string(),
       "--out", (dir / "f.json").string()},
      {"missing.csv"});
  const std::string data = (dir / "D.csv").string();
  ASSERT_EQ(RunClothfit(dir, {"synth", "--model", "slab", "--tau", "0.2",
                              "--out", data})
                .status,
            0);
  ExpectBadInput(
      dir,
      {"fit", "--model", "slab", "--data", data, "--init",
       (dir / "thread.json").string(), "--out", (dir / "f.json").string()},
      {"thread.json", "slab"});
  ExpectBadInput(dir,
                 {"fit", "--model", "slab", "--data", data, "--fix", "depth",
                  "--out", (dir / "f.json").string()},
                 {"depth"});
}

TEST(SlabCli, HelpDescribesTheSlabCommands) {
  const fs::path dir = TestDir();
  RunResult r = RunClothfit(dir, {"synth", "--model", "slab", "--help"});
  ASSERT_EQ(r.status, 0) << Describe(r);
  for (const char* piece : {"--mc", "--error-map", "--single-scatter",
                            "--transmittance", "docs/slab.md"}) {
    EXPECT_NE(r.out.find(piece), std::string::npos) << piece;
  }
  r = RunClothfit(dir, {"fit", "--help"});
  ASSERT_EQ(r.status, 0) << Describe(r);
  EXPECT_NE(r.out.find("slab"), std::string::npos);
  EXPECT_NE(r.out.find("--per-channel-tau"), std::string::npos);
}

}  // namespace
}  // namespace clothfit
