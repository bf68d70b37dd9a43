// The glTF export (export/gltf.h, fitting/sheen_conversion.h, clothfit
// export): the sheet's mesh, the document's structure and the .glb
// container as glTF 2.0 defines them, the conversion (exact for a sheen
// source, its error stored and printed for others), bad input, and the
// Khronos glTF Validator's verdict (web/validate_gltf.mjs, installed by
// scripts/setup.sh).
#include <gtest/gtest.h>

#include <cstdlib>
#include <cstring>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "export/gltf.h"
#include "export/png.h"
#include "fitting/sheen_conversion.h"
#include "io/lafortune_mipmap.h"
#include "io/param_mipmap.h"
#include "models/presets.h"
#include "tests/cli_test_util.h"
#include "tests/direction_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

using testing_util::Velvety;

namespace fs = std::filesystem;
using json = nlohmann::json;
using testing_util::Describe;
using testing_util::RunClothfit;
using testing_util::RunResult;

glm::vec3 At(const std::vector<float>& v, uint32_t i) {
  return glm::vec3(v[3 * i], v[3 * i + 1], v[3 * i + 2]);
}

TEST(GltfExport, SheetHasUnitNormalsAndTrianglesFacingThem) {
  const TriangleMesh mesh = ClothMesh(8);
  ASSERT_EQ(mesh.Vertices(), 81u);
  ASSERT_EQ(mesh.indices.size(), 8u * 8u * 6u);
  ASSERT_EQ(mesh.uvs.size(), 2 * mesh.Vertices());
  for (uint32_t i = 0; i < mesh.Vertices(); ++i) {
    EXPECT_NEAR(glm::length(At(mesh.normals, i)), 1.0f, 1e-6f);
  }
  for (size_t t = 0; t < mesh.indices.size(); t += 3) {
    const uint32_t a = mesh.indices[t], b = mesh.indices[t + 1],
                   c = mesh.indices[t + 2];
    ASSERT_LT(std::max({a, b, c}), mesh.Vertices());
    const glm::vec3 face =
        glm::cross(At(mesh.positions, b) - At(mesh.positions, a),
                   At(mesh.positions, c) - At(mesh.positions, a));
    EXPECT_GT(glm::dot(face, At(mesh.normals, a)), 0.0f) << "triangle " << t;
  }
}

TEST(GltfExport, DocumentAndGlbFollowTheSpecification) {
  const TriangleMesh mesh = ClothMesh(4);
  GltfMaterial material;
  material.sheen = Velvety();
  material.extras_json = "{\"note\": 1}";
  const GltfDocument doc = BuildGltf(mesh, material, "c.bin");
  const json j = json::parse(doc.json);
  EXPECT_EQ(j["asset"]["version"], "2.0");
  EXPECT_EQ(j["buffers"][0]["uri"], "c.bin");
  EXPECT_EQ(j["buffers"][0]["byteLength"], doc.bin.size());
  for (const json& view : j["bufferViews"]) {
    EXPECT_EQ(view["byteOffset"].get<size_t>() % 4, 0u);
    EXPECT_LE(
        view["byteOffset"].get<size_t>() + view["byteLength"].get<size_t>(),
        doc.bin.size());
  }
  EXPECT_EQ(j["accessors"][0]["count"], mesh.Vertices());
  EXPECT_EQ(j["accessors"][3]["count"], mesh.indices.size());
  EXPECT_EQ(j["accessors"][0]["max"][0], 1.0);
  const json& m = j["materials"][0];
  EXPECT_EQ(m["pbrMetallicRoughness"]["metallicFactor"], 0.0);
  EXPECT_EQ(m["pbrMetallicRoughness"]["roughnessFactor"], 0.6);
  EXPECT_EQ(m["extensions"]["KHR_materials_sheen"]["sheenRoughnessFactor"],
            0.35);
  EXPECT_EQ(m["extensions"]["KHR_materials_sheen"]["sheenColorFactor"][1], 0.5);
  EXPECT_EQ(m["extras"]["note"], 1);
  // .glb: "glTF", version 2, total length, then the JSON and BIN chunks.
  const GltfDocument glb_doc = BuildGltf(mesh, material, "");
  EXPECT_FALSE(json::parse(glb_doc.json)["buffers"][0].contains("uri"));
  const std::vector<uint8_t> glb = GlbBytes(glb_doc);
  auto u32 = [&](size_t at) {
    uint32_t v;
    std::memcpy(&v, glb.data() + at, 4);
    return v;
  };
  EXPECT_EQ(u32(0), 0x46546C67u);
  EXPECT_EQ(u32(4), 2u);
  EXPECT_EQ(u32(8), glb.size());
  const uint32_t json_length = u32(12);
  EXPECT_EQ(json_length % 4, 0u);
  EXPECT_EQ(u32(16), 0x4E4F534Au);
  EXPECT_EQ(u32(20 + json_length), (glb_doc.bin.size() + 3) / 4 * 4);
  EXPECT_EQ(u32(24 + json_length), 0x004E4942u);
}

TEST(GltfExport, ConversionIsExactForASheenSourceAndMeasuredForCloth) {
  NoiseModel absolute;
  absolute.kind = NoiseKind::kAbsolute;
  const SheenConversion exact =
      ConvertToSheen(ReflectionGrid(Velvety()), absolute);
  EXPECT_TRUE(exact.report.converged);
  EXPECT_LT(exact.relative_rms, 1e-6);
  EXPECT_NEAR(exact.params.sheen_roughness, 0.35, 1e-5);
  EXPECT_NEAR(exact.params.base_color.x, 0.3, 1e-5);
  EXPECT_EQ(exact.rows, 108 * 108);
  ClothParams satin;
  ASSERT_TRUE(GetPreset("polyester_satin_charmeuse", &satin));
  const SheenConversion lossy = ConvertToSheen(ReflectionGrid(satin), absolute);
  EXPECT_TRUE(std::isfinite(lossy.relative_rms));
  EXPECT_GT(lossy.relative_rms, 0.01);  // a sheen is not a satin
  EXPECT_LT(lossy.relative_rms, 1.0);   // but better than nothing
  // A model that does not reflect has no glTF material.
  EXPECT_THROW(ReflectionGrid(HolesModel{}), InputError);
}

// The Khronos glTF Validator on `file`: exit 0 (no error, no warning).
void ExpectValid(const fs::path& file) {
  const std::string web = std::string(CLOTHFIT_SOURCE_DIR) + "/web";
  ASSERT_TRUE(fs::exists(web + "/node_modules/gltf-validator"))
      << "the validator is missing: run scripts/setup.sh (npm ci in web/)";
  const std::string log = file.string() + ".validator.txt";
  const std::string command = "node " +
                              testing_util::Quote(web + "/validate_gltf.mjs") +
                              " " + testing_util::Quote(file.string()) + " >" +
                              testing_util::Quote(log) + " 2>&1";
  const int status = std::system(command.c_str());
  EXPECT_EQ(status, 0) << testing_util::ReadText(log);
}

TEST(GltfExport, CliWritesFilesTheValidatorAccepts) {
  const fs::path dir = testing_util::FreshTestDir("export_");
  const std::string gltf = (dir / "satin.gltf").string();
  RunResult r = RunClothfit(dir, {"export", "--format", "gltf", "--preset",
                                  "polyester_satin_charmeuse", "--out", gltf});
  ASSERT_EQ(r.status, 0) << Describe(r);
  ASSERT_TRUE(fs::exists(dir / "satin.bin"));
  const json j = json::parse(testing_util::ReadText(gltf));
  const json& conversion =
      j["materials"][0]["extras"]["clothfit"]["conversion"];
  const double relative_rms = conversion["relative_rms"].get<double>();
  EXPECT_GT(relative_rms, 0.0);
  char printed[64];
  std::snprintf(printed, sizeof(printed), "relative rms %.4g", relative_rms);
  EXPECT_NE(r.out.find(printed), std::string::npos) << r.out;
  ExpectValid(gltf);
  // A sheen parameter file as one .glb.
  const std::string params = (dir / "s.json").string();
  testing_util::WriteText(
      params,
      "{\"model\": \"sheen\", \"base_color\": [0.3, 0.2, 0.1], \"roughness\": "
      "0.6, \"sheen_color\": [0.7, 0.5, 0.4], \"sheen_roughness\": 0.35}");
  const std::string glb = (dir / "s.glb").string();
  r = RunClothfit(dir, {"export", "--params", params, "--out", glb});
  ASSERT_EQ(r.status, 0) << Describe(r);
  ExpectValid(glb);
  // A CUReT fabric's measured table.
  const std::string linen = (dir / "linen.gltf").string();
  r = RunClothfit(
      dir, {"export", "--data",
            std::string(CLOTHFIT_SHARED_DIR) + "/data/curet/curet_44_linen.csv",
            "--out", linen});
  ASSERT_EQ(r.status, 0) << Describe(r);
  ExpectValid(linen);
}

// A PNG of stored deflate blocks, read back by hand (PNG 1.2 §11, RFC
// 1950/1951): signature, IHDR, the scanlines after filter byte 0, and the
// Adler-32 of the raw data.
TEST(GltfExport, PngEncoderWritesTheImage) {
  const int w = 3, h = 2;
  std::vector<uint8_t> pixels;
  for (int k = 0; k < w * h * 4; ++k) pixels.push_back(uint8_t(k * 9));
  const std::string png = EncodePng(w, h, 4, pixels);
  ASSERT_EQ(png.substr(0, 8), std::string("\x89PNG\r\n\x1a\n", 8));
  auto be32 = [&](size_t at) {
    return (uint32_t(uint8_t(png[at])) << 24) |
           (uint32_t(uint8_t(png[at + 1])) << 16) |
           (uint32_t(uint8_t(png[at + 2])) << 8) |
           uint32_t(uint8_t(png[at + 3]));
  };
  EXPECT_EQ(png.substr(12, 4), "IHDR");
  EXPECT_EQ(be32(16), 3u);
  EXPECT_EQ(be32(20), 2u);
  EXPECT_EQ(uint8_t(png[24]), 8);  // bit depth
  EXPECT_EQ(uint8_t(png[25]), 6);  // RGBA
  const size_t idat = 8 + 12 + 13;
  EXPECT_EQ(png.substr(idat + 4, 4), "IDAT");
  const std::string z = png.substr(idat + 8, be32(idat));
  ASSERT_EQ(uint8_t(z[2]), 1);  // one final stored block
  const size_t n = uint8_t(z[3]) | (uint8_t(z[4]) << 8);
  ASSERT_EQ(n, size_t(h) * (1 + w * 4));
  const std::string raw = z.substr(7, n);
  for (int y = 0; y < h; ++y) {
    EXPECT_EQ(raw[y * (1 + w * 4)], 0);  // filter type 0
    for (int k = 0; k < w * 4; ++k) {
      EXPECT_EQ(uint8_t(raw[y * (1 + w * 4) + 1 + k]), pixels[y * w * 4 + k]);
    }
  }
  EXPECT_EQ(png.substr(png.size() - 8, 4), "IEND");
  // sRGB: 0 and 1 exact, 0.5 at byte 188, and back within a byte's step.
  EXPECT_EQ(SrgbByte(0.0), 0);
  EXPECT_EQ(SrgbByte(1.0), 255);
  EXPECT_EQ(SrgbByte(0.5), 188);
  EXPECT_NEAR(SrgbToLinear(SrgbByte(0.2)), 0.2, 0.003);
}

// A Lafortune texture map exported as textures: the validator accepts the
// file, each texel gets its own material (a brighter texel a brighter base
// colour), and the conversion error is stored.
TEST(GltfExport, TextureMapBecomesTextures) {
  const fs::path dir = testing_util::FreshTestDir("export_");
  LafortuneTexelMap base, top;
  base.width = base.height = 2;
  for (int i = 0; i < 4; ++i) {
    LafortuneModel m;
    m.params.diffuse = glm::dvec3(0.04 + 0.05 * i, 0.06, 0.05);
    LafortuneLobe lobe;
    lobe.cx = lobe.cy = glm::dvec3(0.6);  // a broad back-scattering lobe
    lobe.cz = glm::dvec3(0.6);
    lobe.n = glm::dvec3(3.0);
    m.params.lobes = {lobe};
    base.texels.push_back(m);
  }
  top.width = top.height = 1;
  top.texels.push_back(base.texels[2]);
  const std::string map = (dir / "map.exr").string();
  WriteParamMipmap(ToParamMipmap({base, top}, {}), map);
  const std::string out = (dir / "map.gltf").string();
  const RunResult r =
      RunClothfit(dir, {"export", "--params", map, "--out", out});
  ASSERT_EQ(r.status, 0) << Describe(r);
  ExpectValid(out);
  const json j = json::parse(testing_util::ReadText(out));
  ASSERT_EQ(j["images"].size(), 4u);
  const json& m = j["materials"][0];
  EXPECT_TRUE(m["pbrMetallicRoughness"].contains("baseColorTexture"));
  EXPECT_TRUE(
      m["extensions"]["KHR_materials_sheen"].contains("sheenRoughnessTexture"));
  const double error =
      m["extras"]["clothfit"]["conversion"]["relative_rms"].get<double>();
  EXPECT_GT(error, 0.0);
  EXPECT_LT(error, 1.0);
  // The base colour texture's red channel grows with the texels' rho_d
  // (texel i at row i / 2, column i % 2): read its stored block.
  const std::string bin = testing_util::ReadText(dir / "map.bin");
  const json& view = j["bufferViews"][j["images"][0]["bufferView"].get<int>()];
  const std::string png = bin.substr(view["byteOffset"].get<size_t>(),
                                     view["byteLength"].get<size_t>());
  const std::string raw = png.substr(8 + 12 + 13 + 8 + 7);  // IDAT's data
  std::vector<int> red;
  for (int y = 0; y < 2; ++y) {
    for (int x = 0; x < 2; ++x) red.push_back(uint8_t(raw[y * 7 + 1 + 3 * x]));
  }
  EXPECT_LT(red[0], red[1]);
  EXPECT_LT(red[1], red[2]);
  EXPECT_LT(red[2], red[3]);
}

TEST(GltfExport, BadInputIsExitTwo) {
  const fs::path dir = testing_util::FreshTestDir("export_");
  const std::string out = (dir / "o.gltf").string();
  testing_util::ExpectBadInput(
      dir, {"export", "--preset", "velvet", "--out", (dir / "o.obj").string()},
      {".gltf or .glb"});
  testing_util::ExpectBadInput(
      dir, {"export", "--preset", "velvet", "--params", "x.json", "--out", out},
      {"exactly one"});
  testing_util::ExpectBadInput(
      dir, {"export", "--format", "usd", "--preset", "velvet", "--out", out},
      {"--format", "usd"});
  testing_util::WriteText(dir / "holes.json",
                          "{\"model\": \"holes\", \"thickness_texels\": 1}");
  testing_util::ExpectBadInput(
      dir, {"export", "--params", (dir / "holes.json").string(), "--out", out},
      {"holes", "glTF"});
}

}  // namespace
}  // namespace clothfit
