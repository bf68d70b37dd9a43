#include "io/params_json.h"

#include <gtest/gtest.h>

#include <exception>
#include <initializer_list>
#include <string>
#include <variant>
#include <vector>

#include "io/input_error.h"
#include "models/presets.h"

namespace clothfit {
namespace {

// The name passed to the parser; every error message must carry it.
constexpr char kFileName[] = "params/my_fabric.json";

void ExpectThreadParamsEqual(const ThreadParams& a, const ThreadParams& b,
                             const std::string& where) {
  EXPECT_EQ(a.eta, b.eta) << where;
  EXPECT_EQ(a.kd, b.kd) << where;
  EXPECT_EQ(a.gamma_s_deg, b.gamma_s_deg) << where;
  EXPECT_EQ(a.gamma_v_deg, b.gamma_v_deg) << where;
  EXPECT_EQ(a.albedo.x, b.albedo.x) << where;
  EXPECT_EQ(a.albedo.y, b.albedo.y) << where;
  EXPECT_EQ(a.albedo.z, b.albedo.z) << where;
}

// Compares everything a parameter file can hold. A tangent curve is only
// representable in a file when it was sampled (samples > 0); a curve with
// samples == 0 (as the presets keep alongside their explicit offsets) is
// not written, so only its sample count is compared then.
void ExpectClothParamsEqual(const ClothParams& a, const ClothParams& b,
                            const std::string& where) {
  ASSERT_EQ(a.threads.size(), b.threads.size()) << where;
  for (size_t j = 0; j < a.threads.size(); ++j) {
    const std::string at = where + " threads[" + std::to_string(j) + "]";
    const ClothThread& x = a.threads[j];
    const ClothThread& y = b.threads[j];
    EXPECT_EQ(x.direction, y.direction) << at;
    EXPECT_EQ(x.coverage, y.coverage) << at;
    EXPECT_EQ(x.offsets_deg, y.offsets_deg) << at;
    EXPECT_EQ(x.curve.samples, y.curve.samples) << at;
    if (x.curve.samples > 0) {
      EXPECT_EQ(x.curve.offsets_deg, y.curve.offsets_deg) << at;
      EXPECT_EQ(x.curve.lengths, y.curve.lengths) << at;
    }
    ExpectThreadParamsEqual(x.params, y.params, at);
  }
}

// Parses `text` as kFileName and returns the InputError message ("" if the
// file was accepted). Any other exception fails the test.
std::string ParseError(const std::string& text) {
  try {
    ParseParamFile(text, kFileName);
  } catch (const InputError& error) {
    return error.what();
  } catch (const std::exception& error) {
    ADD_FAILURE() << "not an InputError: " << error.what() << "\nfor:\n"
                  << text;
    return "";
  }
  return "";
}

// Checks that parsing fails with a message naming the file and every piece.
void ExpectError(const std::string& text,
                 std::initializer_list<const char*> pieces) {
  const std::string message = ParseError(text);
  ASSERT_FALSE(message.empty()) << "accepted:\n" << text;
  EXPECT_NE(message.find(kFileName), std::string::npos)
      << "file name not in: " << message;
  for (const char* piece : pieces) {
    EXPECT_NE(message.find(piece), std::string::npos)
        << "'" << piece << "' not in: " << message;
  }
}

// The thread-parameter keys of a valid thread, with `extra` appended.
std::string ThreadKeys(const std::string& eta = "1.539",
                       const std::string& kd = "0.1",
                       const std::string& gamma_s_deg = "2.5",
                       const std::string& albedo = "[0.035, 0.01295, 0.0105]") {
  return "\"eta\": " + eta + ", \"kd\": " + kd +
         ", \"gamma_s_deg\": " + gamma_s_deg +
         ", \"gamma_v_deg\": 5.0, \"albedo\": " + albedo;
}

std::string ThreadFile(const std::string& keys = ThreadKeys(),
                       const std::string& extra = "") {
  return "{\"model\": \"thread\", " + keys + extra + "}";
}

// One cloth thread object: direction, coverage, the sample keys and the
// thread keys, plus `extra`.
std::string ClothThreadJson(
    const std::string& direction, const std::string& coverage,
    const std::string& samples = "\"offsets_deg\": [-25, 25]",
    const std::string& extra = "") {
  return "{\"direction\": \"" + direction + "\", \"coverage\": " + coverage +
         ", " + samples + ", " + ThreadKeys("1.46", "0.3", "12") + extra + "}";
}

std::string ClothFile(const std::string& thread0, const std::string& thread1,
                      const std::string& extra = "") {
  return "{\"model\": \"cloth\", \"threads\": [" + thread0 + ", " + thread1 +
         "]" + extra + "}";
}

std::string GoodClothFile() {
  return ClothFile(ClothThreadJson("u", "0.33"), ClothThreadJson("v", "0.33"));
}

TEST(ParamsJsonTest, ThreadFileParsesEveryField) {
  const ParamFile file = ParseParamFile(ThreadFile(), kFileName);
  ASSERT_TRUE(std::holds_alternative<ThreadParams>(file.params));
  const ThreadParams& p = std::get<ThreadParams>(file.params);
  EXPECT_EQ(p.eta, 1.539);
  EXPECT_EQ(p.kd, 0.1);
  EXPECT_EQ(p.gamma_s_deg, 2.5);
  EXPECT_EQ(p.gamma_v_deg, 5.0);
  EXPECT_EQ(p.albedo.x, 0.035);
  EXPECT_EQ(p.albedo.y, 0.01295);
  EXPECT_EQ(p.albedo.z, 0.0105);
  EXPECT_TRUE(file.fit_json.empty());
  EXPECT_STREQ(ModelName(file.params), "thread");
}

TEST(ParamsJsonTest, ThreadFileRoundTripsExactly) {
  ThreadParams p;
  // Values that need all 17 significant digits to survive.
  p.eta = 1.0 + 1.0 / 3.0;
  p.kd = 0.1 + 0.2;
  p.gamma_s_deg = 2.0 / 7.0;
  p.gamma_v_deg = 89.999999999999986;
  p.albedo = glm::dvec3(1e-300, 0.0, 1.0 / 9.0);
  const ParamFile original{p, ""};
  const std::string text = FormatParamFile(original);
  const ParamFile parsed = ParseParamFile(text, kFileName);
  ASSERT_TRUE(std::holds_alternative<ThreadParams>(parsed.params)) << text;
  ExpectThreadParamsEqual(std::get<ThreadParams>(parsed.params), p, "thread");
  EXPECT_TRUE(parsed.fit_json.empty());
  // Formatting is a fixed point.
  EXPECT_EQ(FormatParamFile(parsed), text);
}

TEST(ParamsJsonTest, EveryPresetRoundTripsExactly) {
  ASSERT_EQ(PresetNames().size(), 6u);
  for (const std::string& name : PresetNames()) {
    ClothParams preset;
    ASSERT_TRUE(GetPreset(name, &preset)) << name;
    const std::string text = FormatParamFile(ParamFile{preset, ""});
    const ParamFile parsed = ParseParamFile(text, name + ".json");
    ASSERT_TRUE(std::holds_alternative<ClothParams>(parsed.params)) << name;
    EXPECT_STREQ(ModelName(parsed.params), "cloth");
    ExpectClothParamsEqual(std::get<ClothParams>(parsed.params), preset, name);
    EXPECT_EQ(FormatParamFile(parsed), text) << name;
  }
}

TEST(ParamsJsonTest, ClothFileParsesDirectionsAndSamples) {
  const ParamFile file = ParseParamFile(
      ClothFile(ClothThreadJson("u", "0.6", "\"offsets_deg\": [-30, 0, 30]"),
                ClothThreadJson("v", "0.25")),
      kFileName);
  ASSERT_TRUE(std::holds_alternative<ClothParams>(file.params));
  const ClothParams& c = std::get<ClothParams>(file.params);
  ASSERT_EQ(c.threads.size(), 2u);
  EXPECT_EQ(c.threads[0].direction, ThreadDirection::kU);
  EXPECT_EQ(c.threads[1].direction, ThreadDirection::kV);
  EXPECT_EQ(c.threads[0].coverage, 0.6);
  EXPECT_EQ(c.threads[1].coverage, 0.25);
  EXPECT_EQ(c.threads[0].offsets_deg, (std::vector<double>{-30, 0, 30}));
  EXPECT_EQ(c.threads[1].offsets_deg, (std::vector<double>{-25, 25}));
  EXPECT_EQ(c.threads[0].curve.samples, 0);
  EXPECT_EQ(c.threads[1].params.eta, 1.46);
  EXPECT_EQ(c.threads[1].params.gamma_s_deg, 12.0);
}

TEST(ParamsJsonTest, TangentCurveIsSampledAndWrittenBackAsCurve) {
  const std::string curve =
      "\"curve_offsets_deg\": [-32, -32, -18, 0, 0, 18, 32, 32], "
      "\"curve_lengths\": [1.33, 0.66, 2, 2, 2, 0.66, 1.33], \"samples\": 9";
  const ParamFile file =
      ParseParamFile(ClothFile(ClothThreadJson("u", "0.9", curve),
                               ClothThreadJson("v", "0.1")),
                     kFileName);
  const ClothParams& c = std::get<ClothParams>(file.params);
  ASSERT_EQ(c.threads.size(), 2u);
  const ClothThread& th = c.threads[0];

  TangentCurve expected_curve;
  expected_curve.offsets_deg = {-32, -32, -18, 0, 0, 18, 32, 32};
  expected_curve.lengths = {1.33, 0.66, 2, 2, 2, 0.66, 1.33};
  expected_curve.samples = 9;
  EXPECT_EQ(th.curve.offsets_deg, expected_curve.offsets_deg);
  EXPECT_EQ(th.curve.lengths, expected_curve.lengths);
  EXPECT_EQ(th.curve.samples, 9);
  const std::vector<double> samples = SampleTangentCurve(expected_curve);
  ASSERT_EQ(samples.size(), 9u);
  EXPECT_EQ(th.offsets_deg, samples);

  const std::string text = FormatParamFile(file);
  EXPECT_NE(text.find("\"curve_offsets_deg\""), std::string::npos) << text;
  EXPECT_NE(text.find("\"curve_lengths\""), std::string::npos) << text;
  EXPECT_NE(text.find("\"samples\": 9"), std::string::npos) << text;
  // Thread 0 is written as a curve, thread 1 with explicit offsets: exactly
  // one explicit "offsets_deg" key in the whole file.
  const size_t first = text.find("\"offsets_deg\"");
  ASSERT_NE(first, std::string::npos) << text;
  EXPECT_EQ(text.find("\"offsets_deg\"", first + 1), std::string::npos) << text;

  const ParamFile again = ParseParamFile(text, kFileName);
  ExpectClothParamsEqual(std::get<ClothParams>(again.params), c, "curve");
}

TEST(ParamsJsonTest, TangentCurveJumpAtZeroLengthSegment) {
  // Two pieces joined by a jump: -30..-30 over length 1, jump to 10, then
  // 10..10 over length 1. Four samples: two on each side of the jump.
  const ParamFile file = ParseParamFile(
      ClothFile(ClothThreadJson("u", "0.5",
                                "\"curve_offsets_deg\": [-30, -30, 10, 10], "
                                "\"curve_lengths\": [1, 0, 1], \"samples\": 4"),
                ClothThreadJson("v", "0.5")),
      kFileName);
  EXPECT_EQ(std::get<ClothParams>(file.params).threads[0].offsets_deg,
            (std::vector<double>{-30, -30, 10, 10}));
}

TEST(ParamsJsonTest, FitObjectSurvivesRoundTrip) {
  const std::string fit =
      "{\"final_cost\": 0.5, \"rms\": 0.25, \"iterations\": 12, "
      "\"termination\": \"CONVERGENCE\", \"stddev\": {\"eta\": 0.01, "
      "\"kd\": 0.002}}";
  const ParamFile file =
      ParseParamFile(ThreadFile(ThreadKeys(), ", \"fit\": " + fit), kFileName);
  // Kept verbatim, keys in file order.
  EXPECT_EQ(file.fit_json,
            "{\"final_cost\":0.5,\"rms\":0.25,\"iterations\":12,"
            "\"termination\":\"CONVERGENCE\",\"stddev\":{\"eta\":0.01,"
            "\"kd\":0.002}}");
  const std::string text = FormatParamFile(file);
  EXPECT_NE(text.find("\"fit\""), std::string::npos) << text;
  const ParamFile again = ParseParamFile(text, kFileName);
  EXPECT_EQ(again.fit_json, file.fit_json);
  ExpectThreadParamsEqual(std::get<ThreadParams>(again.params),
                          std::get<ThreadParams>(file.params), "fit");

  const ParamFile cloth = ParseParamFile(
      ClothFile(ClothThreadJson("u", "0.33"), ClothThreadJson("v", "0.33"),
                ", \"fit\": " + fit),
      kFileName);
  EXPECT_EQ(ParseParamFile(FormatParamFile(cloth), kFileName).fit_json,
            file.fit_json);
}

TEST(ParamsJsonTest, GoodFilesAreAccepted) {
  // Guards the error tests below: their unmodified bases parse.
  EXPECT_EQ(ParseError(ThreadFile()), "");
  EXPECT_EQ(ParseError(GoodClothFile()), "");
}

// The model's scale (models/params.h kModelScale): optional, 1 when
// absent and then not written, kept exactly, validated; a cloth has one,
// its threads none.
TEST(ParamsJsonTest, ScaleOfThreadAndClothIsOptionalKeptAndValidated) {
  const ParamFile plain = ParseParamFile(ThreadFile(), kFileName);
  EXPECT_EQ(std::get<ThreadParams>(plain.params).scale, 1.0);
  EXPECT_EQ(FormatParamFile(plain).find("scale"), std::string::npos);
  const ParamFile thread =
      ParseParamFile(ThreadFile(ThreadKeys(), ", \"scale\": 0.3"), kFileName);
  EXPECT_EQ(std::get<ThreadParams>(thread.params).scale, 0.3);
  EXPECT_EQ(FormatParamFile(ParseParamFile(FormatParamFile(thread), kFileName)),
            FormatParamFile(thread));
  const ParamFile cloth = ParseParamFile(
      ClothFile(ClothThreadJson("u", "0.33"), ClothThreadJson("v", "0.33"),
                ", \"scale\": 2.5"),
      kFileName);
  EXPECT_EQ(std::get<ClothParams>(cloth.params).scale, 2.5);
  EXPECT_NE(FormatParamFile(cloth).find("\"scale\": 2.5"), std::string::npos);
  ExpectError(ThreadFile(ThreadKeys(), ", \"scale\": 0"),
              {"scale", "(0, 1e+06]"});
  ExpectError(ThreadFile(ThreadKeys(), ", \"scale\": -1"), {"scale"});
  ExpectError(ClothFile(ClothThreadJson("u", "0.33"),
                        ClothThreadJson("v", "0.33", "\"offsets_deg\": [0]",
                                        ", \"scale\": 0.5")),
              {"threads[1].scale", "unknown key"});
}

// The energy bound's tables: absent is the paper's model when parsed (and
// then not written); given, kept exactly through a write and a read; sizes,
// signs and unknown keys refused by name.
TEST(ParamsJsonTest, EnergyBoundIsOptionalKeptExactlyAndValidated) {
  const ParamFile plain = ParseParamFile(ThreadFile(), kFileName);
  EXPECT_EQ(std::get<ThreadParams>(plain.params).energy_bound, nullptr);
  EXPECT_EQ(FormatParamFile(plain).find("energy_bound"), std::string::npos);
  const std::string tables =
      ", \"energy_bound\": {\"light\": [0.1, 0.30000000000000004, 1.5], "
      "\"view\": [2.0, 1.25, 0.9]}";
  for (const std::string& text :
       {ThreadFile(ThreadKeys(), tables),
        ClothFile(ClothThreadJson("u", "0.33"), ClothThreadJson("v", "0.33"),
                  tables)}) {
    const ParamFile file = ParseParamFile(text, kFileName);
    const EnergyBound* b =
        std::holds_alternative<ThreadParams>(file.params)
            ? std::get<ThreadParams>(file.params).energy_bound.get()
            : std::get<ClothParams>(file.params).energy_bound.get();
    ASSERT_NE(b, nullptr);
    EXPECT_EQ(b->light, std::vector<double>({0.1, 0.30000000000000004, 1.5}));
    EXPECT_EQ(b->view, std::vector<double>({2.0, 1.25, 0.9}));
    const std::string written = FormatParamFile(file);
    EXPECT_EQ(FormatParamFile(ParseParamFile(written, kFileName)), written);
  }
  ExpectError(ThreadFile(ThreadKeys(),
                         ", \"energy_bound\": {\"light\": [1, 2], "
                         "\"view\": [1]}"),
              {"energy_bound", "same number"});
  ExpectError(ThreadFile(ThreadKeys(),
                         ", \"energy_bound\": {\"light\": [1, -2], "
                         "\"view\": [1, 1]}"),
              {"energy_bound", ">= 0"});
  ExpectError(
      ThreadFile(ThreadKeys(), ", \"energy_bound\": {\"light\": [1, 2]}"),
      {"energy_bound.view", "missing"});
  ExpectError(ThreadFile(ThreadKeys(),
                         ", \"energy_bound\": {\"light\": [1, 2], "
                         "\"view\": [1, 1], \"side\": 1}"),
              {"energy_bound.side", "unknown key"});
}

// The weave's optional freedoms: absent is the paper's model (0) and then
// not written; given, kept exactly; diffuse as one number or three;
// validated by name.
TEST(ParamsJsonTest, ClothRotationAndDiffuseAreOptionalKeptAndValidated) {
  const ParamFile plain = ParseParamFile(GoodClothFile(), kFileName);
  const ClothParams& p = std::get<ClothParams>(plain.params);
  EXPECT_EQ(p.rotation_deg, 0.0);
  EXPECT_EQ(p.diffuse, glm::dvec3(0.0));
  EXPECT_EQ(FormatParamFile(plain).find("rotation_deg"), std::string::npos);
  EXPECT_EQ(FormatParamFile(plain).find("diffuse"), std::string::npos);
  const ParamFile turned = ParseParamFile(
      ClothFile(ClothThreadJson("u", "0.33"), ClothThreadJson("v", "0.33"),
                ", \"rotation_deg\": -37.25, \"diffuse\": [0.1, 0.2, 0.3]"),
      kFileName);
  const ClothParams& t = std::get<ClothParams>(turned.params);
  EXPECT_EQ(t.rotation_deg, -37.25);
  EXPECT_EQ(t.diffuse, glm::dvec3(0.1, 0.2, 0.3));
  const std::string text = FormatParamFile(turned);
  EXPECT_EQ(FormatParamFile(ParseParamFile(text, kFileName)), text);
  EXPECT_NE(text.find("\"rotation_deg\": -37.25"), std::string::npos);
  const ParamFile grey = ParseParamFile(
      ClothFile(ClothThreadJson("u", "0.33"), ClothThreadJson("v", "0.33"),
                ", \"diffuse\": 0.25"),
      kFileName);
  EXPECT_EQ(std::get<ClothParams>(grey.params).diffuse, glm::dvec3(0.25));
  ExpectError(ClothFile(ClothThreadJson("u", "0.33"),
                        ClothThreadJson("v", "0.33"), ", \"diffuse\": 1.5"),
              {"diffuse", "[0, 1]"});
  ExpectError(
      ClothFile(ClothThreadJson("u", "0.33"), ClothThreadJson("v", "0.33"),
                ", \"rotation_deg\": 400"),
      {"rotation_deg"});
  ExpectError(ClothFile(ClothThreadJson("u", "0.33"),
                        ClothThreadJson("v", "0.33"), ", \"diffuse\": [1, 2]"),
              {"diffuse", "3 numbers"});
}

TEST(ParamsJsonTest, UnknownTopLevelKeyIsNamed) {
  ExpectError(ThreadFile(ThreadKeys(), ", \"sheen\": 1"),
              {"sheen", "unknown key"});
  ExpectError(ClothFile(ClothThreadJson("u", "0.33"),
                        ClothThreadJson("v", "0.33"), ", \"gloss\": true"),
              {"gloss", "unknown key"});
}

TEST(ParamsJsonTest, UnknownKeyInsideThreadIsNamedByPath) {
  ExpectError(ClothFile(ClothThreadJson("u", "0.33"),
                        ClothThreadJson("v", "0.33", "\"offsets_deg\": [0]",
                                        ", \"sheen\": 0.5")),
              {"threads[1].sheen", "unknown key"});
}

TEST(ParamsJsonTest, MissingKeyIsNamed) {
  ExpectError(
      "{\"model\": \"thread\", \"eta\": 1.5, \"kd\": 0.1, \"gamma_s_deg\": "
      "2.5, \"albedo\": [0.1, 0.1, 0.1]}",
      {"gamma_v_deg", "missing"});
  ExpectError("{\"eta\": 1.5}", {"model", "missing"});
  ExpectError(ClothFile(ClothThreadJson("u", "0.33"),
                        "{\"direction\": \"v\", \"offsets_deg\": [0], " +
                            ThreadKeys() + "}"),
              {"threads[1].coverage", "missing"});
}

TEST(ParamsJsonTest, WrongTypeIsNamed) {
  ExpectError(ThreadFile(ThreadKeys("\"1.5\"")), {"eta", "number"});
  ExpectError("{\"model\": \"cloth\", \"threads\": {}}", {"threads"});
  ExpectError(
      ClothFile(ClothThreadJson("u", "0.33"), ClothThreadJson("v", "\"half\"")),
      {"threads[1].coverage", "number"});
}

TEST(ParamsJsonTest, OutOfRangeValuesAreNamed) {
  ExpectError(ThreadFile(ThreadKeys("1.5", "2")), {"'kd'", "kd"});
  ExpectError(ThreadFile(ThreadKeys("1.5", "0.1", "0")), {"gamma_s_deg"});
  ExpectError(ThreadFile(ThreadKeys("1")), {"eta"});
  ExpectError(ThreadFile(ThreadKeys("1.5", "0.1", "2.5", "[0.1, -0.2, 0.3]")),
              {"albedo"});
  ExpectError(
      ClothFile(ClothThreadJson("u", "0.6"), ClothThreadJson("v", "0.5")),
      {"threads", "sum"});
  ExpectError(
      ClothFile(ClothThreadJson("u", "0.33", "\"offsets_deg\": [-25, 120]"),
                ClothThreadJson("v", "0.33")),
      {"threads[0].offsets_deg", "120"});
}

TEST(ParamsJsonTest, OutOfRangeThreadKeyInClothIsNamedByPath) {
  const std::string bad_kd =
      "{\"direction\": \"v\", \"coverage\": 0.33, \"offsets_deg\": [0], " +
      ThreadKeys("1.46", "2") + "}";
  ExpectError(ClothFile(ClothThreadJson("u", "0.33"), bad_kd),
              {"threads[1].kd"});
}

TEST(ParamsJsonTest, UnknownModelIsNamed) {
  ExpectError("{\"model\": \"velour\", \"eta\": 1.5}", {"model", "velour"});
}

TEST(ParamsJsonTest, UnknownDirectionIsNamed) {
  ExpectError(
      ClothFile(ClothThreadJson("u", "0.33"), ClothThreadJson("w", "0.33")),
      {"threads[1].direction"});
}

TEST(ParamsJsonTest, InvalidJsonNamesLineAndColumn) {
  ExpectError("{\"model\": \"thread\",\n  \"eta\": 1.5,,\n}",
              {"line", "column"});
  ExpectError("", {"JSON"});
}

TEST(ParamsJsonTest, NonObjectTopLevelIsRejected) {
  ExpectError("[1, 2, 3]", {"object"});
}

TEST(ParamsJsonTest, OffsetsAndCurveTogetherAreRejected) {
  ExpectError(ClothFile(ClothThreadJson("u", "0.33",
                                        "\"offsets_deg\": [-25, 25], "
                                        "\"curve_offsets_deg\": [-25, 25], "
                                        "\"curve_lengths\": [1], "
                                        "\"samples\": 4"),
                        ClothThreadJson("v", "0.33")),
              {"threads[0]", "offsets_deg", "curve"});
  // One curve key is enough to conflict.
  ExpectError(ClothFile(ClothThreadJson("u", "0.33",
                                        "\"offsets_deg\": [-25, 25], "
                                        "\"samples\": 4"),
                        ClothThreadJson("v", "0.33")),
              {"threads[0]", "offsets_deg"});
}

TEST(ParamsJsonTest, AlbedoWithTwoEntriesIsRejected) {
  ExpectError(ThreadFile(ThreadKeys("1.5", "0.1", "2.5", "[0.1, 0.2]")),
              {"albedo", "3"});
}

TEST(ParamsJsonTest, NonIntegerSamplesIsRejected) {
  ExpectError(ClothFile(ClothThreadJson("u", "0.33",
                                        "\"curve_offsets_deg\": [-25, 25], "
                                        "\"curve_lengths\": [1], "
                                        "\"samples\": 4.5"),
                        ClothThreadJson("v", "0.33")),
              {"threads[0].samples", "integer"});
}

TEST(ParamsJsonTest, InvalidTangentCurveIsNamedByPath) {
  ExpectError(ClothFile(ClothThreadJson("u", "0.33"),
                        ClothThreadJson("v", "0.33",
                                        "\"curve_offsets_deg\": [-25, 25], "
                                        "\"curve_lengths\": [1, 1], "
                                        "\"samples\": 4")),
              {"threads[1].curve_lengths"});
  ExpectError(ClothFile(ClothThreadJson("u", "0.33",
                                        "\"curve_offsets_deg\": [-25, 25], "
                                        "\"curve_lengths\": [1], "
                                        "\"samples\": 0"),
                        ClothThreadJson("v", "0.33")),
              {"threads[0].samples"});
}

TEST(ParamsJsonTest, ReadParamFileNamesMissingPath) {
  const std::string path =
      std::string(CLOTHFIT_TEST_TMP) + "/params_json_test_no_such_file.json";
  try {
    ReadParamFile(path);
    FAIL() << "read a file that does not exist";
  } catch (const InputError& error) {
    EXPECT_NE(std::string(error.what()).find(path), std::string::npos)
        << error.what();
  }
}

TEST(ParamsJsonTest, WriteThenReadParamFile) {
  ClothParams preset;
  ASSERT_TRUE(GetPreset("velvet", &preset));
  const std::string path =
      std::string(CLOTHFIT_TEST_TMP) + "/params_json_test_velvet.json";
  WriteParamFile(ParamFile{preset, "{\"iterations\":3}"}, path);
  const ParamFile read = ReadParamFile(path);
  ExpectClothParamsEqual(std::get<ClothParams>(read.params), preset, "velvet");
  EXPECT_EQ(read.fit_json, "{\"iterations\":3}");
}

}  // namespace
}  // namespace clothfit
