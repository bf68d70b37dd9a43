#include "io/image_stack.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <glm/geometric.hpp>
#include <initializer_list>
#include <random>
#include <string>
#include <vector>

#include "io/atomic_file.h"
#include "io/input_error.h"
#include "io/table.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;

constexpr double kPi = 3.14159265358979323846;

fs::path TestDir() { return testing_util::FreshTestDir("image_stack_test_"); }

void WriteText(const fs::path& path, const std::string& text) {
  std::ofstream out(path, std::ios::binary | std::ios::trunc);
  out << text;
}

using testing_util::ErrorOf;
using testing_util::ExpectHas;

void ExpectNear(const glm::dvec3& a, const glm::dvec3& b, double tolerance) {
  EXPECT_NEAR(a.x, b.x, tolerance);
  EXPECT_NEAR(a.y, b.y, tolerance);
  EXPECT_NEAR(a.z, b.z, tolerance);
}

// A stack table: `pairs` direction pairs, each a full width x height grid,
// rows image-major and row-major within an image (the reader's order).
// Values are floats (exact in a float EXR); with `unit` they lie in [0, 1].
MeasurementTable StackTable(int pairs, int width, int height, int channels,
                            bool unit, unsigned seed = 3) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<float> uniform(unit ? 0.0f : -2.0f,
                                                unit ? 1.0f : 5.0f);
  std::uniform_real_distribution<float> coverage(0.0f, 1.0f);
  MeasurementTable table;
  table.quantity = Quantity::kCosineWeighted;
  table.channels = channels;
  table.has_texels = true;
  table.has_alpha = true;
  table.SetMeta("sample", "velvet");
  for (int k = 0; k < pairs; ++k) {
    const glm::dvec3 wi = DirectionFromAngles(0.1 + 0.3 * k, 0.5 * k);
    const glm::dvec3 wo = DirectionFromAngles(0.7 + 0.2 * k, kPi - 0.4 * k);
    for (int t = 0; t < height; ++t) {
      for (int s = 0; s < width; ++s) {
        TableRow row;
        row.wi = wi;
        row.wo = wo;
        if (channels == 1) {
          row.value = glm::dvec3(uniform(random));
        } else {
          row.value =
              glm::dvec3(uniform(random), uniform(random), uniform(random));
        }
        row.alpha = coverage(random);
        row.s = s;
        row.t = t;
        table.rows.push_back(row);
      }
    }
  }
  table.rows[0].alpha = 0.0;
  table.rows[1].alpha = 1.0;
  return table;
}

void ExpectSameRows(const MeasurementTable& read,
                    const MeasurementTable& written, double tolerance,
                    bool alpha) {
  ASSERT_EQ(read.rows.size(), written.rows.size());
  for (size_t i = 0; i < read.rows.size(); ++i) {
    const TableRow& a = read.rows[i];
    const TableRow& b = written.rows[i];
    ExpectNear(a.wi, b.wi, 1e-15);
    ExpectNear(a.wo, b.wo, 1e-15);
    if (tolerance == 0.0) {
      EXPECT_EQ(a.value, b.value) << "row " << i;
      if (alpha) {
        EXPECT_EQ(a.alpha, b.alpha) << "row " << i;
      }
    } else {
      ExpectNear(a.value, b.value, tolerance);
      if (alpha) {
        EXPECT_NEAR(a.alpha, b.alpha, tolerance) << "row " << i;
      }
    }
    if (!alpha) {
      EXPECT_EQ(a.alpha, 1.0);
    }
    EXPECT_EQ(a.s, b.s);
    EXPECT_EQ(a.t, b.t);
    EXPECT_EQ(a.sigma, glm::dvec3(1.0));
    EXPECT_EQ(a.weight, 1.0);
  }
}

TEST(ImageStackTest, ExrRgbaRoundTrip) {
  const fs::path dir = TestDir();
  const std::string manifest = (dir / "stack.csv").string();
  const MeasurementTable table = StackTable(3, 5, 4, 3, /*unit=*/false);
  WriteImageStack(table, manifest, ".exr", /*with_alpha=*/true);
  for (const char* file :
       {"stack_0000.exr", "stack_0001.exr", "stack_0002.exr"}) {
    EXPECT_TRUE(fs::exists(dir / file)) << file;
  }
  EXPECT_FALSE(fs::exists(dir / "stack_0003.exr"));

  const std::string text = ReadFileToString(manifest);
  EXPECT_EQ(text.rfind("# clothfit-stack 1\n# quantity: cosine_weighted\n"
                       "# units: degrees\n# sample: velvet\n"
                       "theta_i,phi_i,theta_o,phi_o,file\n",
                       0),
            0u)
      << text;
  EXPECT_NE(text.find(",stack_0002.exr\n"), std::string::npos) << text;

  const MeasurementTable back = ReadImageStack(manifest);
  EXPECT_EQ(back.quantity, Quantity::kCosineWeighted);
  EXPECT_EQ(back.channels, 3);
  EXPECT_TRUE(back.has_alpha);
  EXPECT_TRUE(back.has_texels);
  EXPECT_FALSE(back.has_sigma);
  EXPECT_FALSE(back.has_weight);
  EXPECT_EQ(back.Meta("sample"), "velvet");
  ExpectSameRows(back, table, 0.0, /*alpha=*/true);
  EXPECT_EQ(back.rows[0].source_line, 6);
  EXPECT_EQ(back.rows.back().source_line, 8);

  // The table itself round-trips through CSV with its alpha column.
  const MeasurementTable csv = ParseTable(FormatTable(back), "mem").table;
  EXPECT_TRUE(csv.has_alpha);
  EXPECT_EQ(csv.rows[7].alpha, back.rows[7].alpha);
}

TEST(ImageStackTest, ExrWithoutAlphaAndGrey) {
  const fs::path dir = TestDir();
  const std::string manifest = (dir / "rgb.csv").string();
  const MeasurementTable table = StackTable(2, 3, 2, 3, false);
  WriteImageStack(table, manifest, "exr", /*with_alpha=*/false);
  const MeasurementTable back = ReadImageStack(manifest);
  EXPECT_FALSE(back.has_alpha);
  EXPECT_EQ(back.channels, 3);
  ExpectSameRows(back, table, 0.0, /*alpha=*/false);

  // One channel (Y) with and without alpha.
  const MeasurementTable grey = StackTable(2, 3, 2, 1, false);
  for (bool with_alpha : {true, false}) {
    const std::string grey_manifest =
        (dir / (with_alpha ? "grey_a.csv" : "grey.csv")).string();
    WriteImageStack(grey, grey_manifest, ".exr", with_alpha);
    const MeasurementTable grey_back = ReadImageStack(grey_manifest);
    EXPECT_EQ(grey_back.channels, 1);
    EXPECT_EQ(grey_back.has_alpha, with_alpha);
    ExpectSameRows(grey_back, grey, 0.0, with_alpha);
  }
}

TEST(ImageStackTest, PngRoundTrip) {
  const fs::path dir = TestDir();
  const MeasurementTable table = StackTable(3, 5, 4, 3, /*unit=*/true);
  const std::string manifest = (dir / "png.csv").string();
  WriteImageStack(table, manifest, ".png", /*with_alpha=*/true);
  EXPECT_TRUE(fs::exists(dir / "png_0001.png"));
  const MeasurementTable back = ReadImageStack(manifest);
  EXPECT_EQ(back.channels, 3);
  EXPECT_TRUE(back.has_alpha);
  ExpectSameRows(back, table, 0.5 / 255 + 1e-6, /*alpha=*/true);

  // Grey + alpha PNG.
  const MeasurementTable grey = StackTable(2, 4, 3, 1, true);
  const std::string grey_manifest = (dir / "grey.csv").string();
  WriteImageStack(grey, grey_manifest, ".png", /*with_alpha=*/true);
  const MeasurementTable grey_back = ReadImageStack(grey_manifest);
  EXPECT_EQ(grey_back.channels, 1);
  EXPECT_TRUE(grey_back.has_alpha);
  ExpectSameRows(grey_back, grey, 0.5 / 255 + 1e-6, /*alpha=*/true);

  // Values outside [0, 1] are clamped in 8-bit images.
  MeasurementTable wide = StackTable(1, 2, 1, 3, true);
  wide.rows[0].value = glm::dvec3(-1.0, 2.0, 0.5);
  const std::string wide_manifest = (dir / "wide.csv").string();
  WriteImageStack(wide, wide_manifest, ".png", /*with_alpha=*/false);
  const MeasurementTable wide_back = ReadImageStack(wide_manifest);
  ExpectNear(wide_back.rows[0].value, {0.0, 1.0, 0.5}, 0.5 / 255 + 1e-6);
}

TEST(ImageStackTest, Stride) {
  const fs::path dir = TestDir();
  const std::string manifest = (dir / "s.csv").string();
  const MeasurementTable table = StackTable(3, 5, 4, 3, false);
  WriteImageStack(table, manifest, ".exr", true);
  ReadStackOptions options;
  options.stride = 2;
  const MeasurementTable back = ReadImageStack(manifest, options);
  // x in {0, 2, 4}, y in {0, 2}, per image.
  ASSERT_EQ(back.rows.size(), 3u * 3u * 2u);
  size_t i = 0;
  for (int k = 0; k < 3; ++k) {
    for (int y = 0; y < 4; y += 2) {
      for (int x = 0; x < 5; x += 2) {
        const TableRow& row = back.rows[i++];
        const TableRow& original = table.rows[(k * 4 + y) * 5 + x];
        EXPECT_EQ(row.s, x);
        EXPECT_EQ(row.t, y);
        EXPECT_EQ(row.value, original.value);
        EXPECT_EQ(row.alpha, original.alpha);
      }
    }
  }
  options.stride = 0;
  ExpectHas(ErrorOf([&] { ReadImageStack(manifest, options); }),
            {manifest, "stride"});
}

TEST(ImageStackTest, HandWrittenManifest) {
  const fs::path dir = TestDir();
  // Images from a written stack, listed by a manifest with the file column
  // first, vector directions and a relative sub-folder.
  fs::create_directories(dir / "img");
  const MeasurementTable table = StackTable(2, 2, 2, 3, false);
  WriteImageStack(table, (dir / "img" / "a.csv").string(), ".exr", false);
  WriteText(dir / "m.csv",
            "\xEF\xBB\xBF# clothfit-stack 1\r\n# Quantity: transmittance\r\n"
            "# note: x\r\n\r\n FILE ,wo_x,wo_y,wo_z\r\n"
            "img/a_0001.exr,0,0,-2\r\n# skipped\r\n"
            " img/a_0000.exr ,3,0,-4\r\n");
  const MeasurementTable back = ReadImageStack((dir / "m.csv").string());
  EXPECT_EQ(back.quantity, Quantity::kTransmittance);
  EXPECT_EQ(back.direction_columns, DirectionColumns::kVectors);
  EXPECT_EQ(back.Meta("note"), "x");
  ASSERT_EQ(back.rows.size(), 8u);
  ExpectNear(back.rows[0].wo, {0, 0, -1}, 1e-15);
  ExpectNear(back.rows[0].wi, {0, 0, 1}, 1e-15);
  ExpectNear(back.rows[4].wo, {0.6, 0, -0.8}, 1e-15);
  EXPECT_EQ(back.rows[0].value, table.rows[4].value);
  EXPECT_EQ(back.rows[4].value, table.rows[0].value);
  EXPECT_EQ(back.rows[4].source_line, 8);
}

// StackTable with a normal per texel, tilted differently at every texel.
MeasurementTable WithNormals(MeasurementTable table) {
  table.has_normal = true;
  for (TableRow& row : table.rows) {
    row.normal = glm::normalize(glm::dvec3(0.3 * std::sin(row.s + 1.0),
                                           -0.2 * std::cos(2.0 * row.t), 1.0));
  }
  return table;
}

TEST(ImageStackTest, NormalMapCarriesEachTexelsNormal) {
  const fs::path dir = TestDir();
  const MeasurementTable table = WithNormals(StackTable(3, 5, 4, 3, false));
  struct Format {
    const char* ext;
    double tolerance;  // float; 8 bit as 0.5 (n + 1)
  };
  for (const Format& f : {Format{".exr", 1e-7}, Format{".png", 0.006}}) {
    const std::string manifest =
        (dir / (std::string("n") + (f.ext + 1) + ".csv")).string();
    WriteImageStack(table, manifest, f.ext, false);
    const std::string normal_file =
        std::string("n") + (f.ext + 1) + "_normal" + f.ext;
    EXPECT_TRUE(fs::exists(dir / normal_file)) << normal_file;
    EXPECT_NE(
        ReadFileToString(manifest).find("# normal_map: " + normal_file + "\n"),
        std::string::npos);
    const MeasurementTable back = ReadImageStack(manifest);
    EXPECT_TRUE(back.has_normal) << f.ext;
    EXPECT_FALSE(back.Meta("normal_map").has_value());
    ASSERT_EQ(back.rows.size(), table.rows.size());
    for (size_t i = 0; i < back.rows.size(); ++i) {
      ExpectNear(back.rows[i].normal, table.rows[i].normal, f.tolerance);
      EXPECT_NEAR(glm::length(back.rows[i].normal), 1.0, 1e-12);
    }
    // Stride keeps each kept pixel's normal.
    ReadStackOptions options;
    options.stride = 2;
    const MeasurementTable strided = ReadImageStack(manifest, options);
    for (const TableRow& row : strided.rows) {
      ExpectNear(row.normal, table.rows[size_t(row.t) * 5 + row.s].normal,
                 f.tolerance);
    }
    // Through CSV the normals become columns.
    EXPECT_TRUE(ParseTable(FormatTable(back), "mem").table.has_normal);
  }
  // Without a normal map: the surface normal, no columns.
  const std::string plain = (dir / "plain.csv").string();
  WriteImageStack(StackTable(2, 3, 2, 3, false), plain, ".exr", false);
  EXPECT_FALSE(fs::exists(dir / "plain_normal.exr"));
  const MeasurementTable back = ReadImageStack(plain);
  EXPECT_FALSE(back.has_normal);
  EXPECT_EQ(back.rows[0].normal, glm::dvec3(0.0, 0.0, 1.0));
}

// Writes a 5 x 4 rgba EXR stack of three images as dir/stack.csv.
std::string WriteSampleStack(const fs::path& dir) {
  const std::string manifest = (dir / "stack.csv").string();
  WriteImageStack(StackTable(3, 5, 4, 3, false), manifest, ".exr", true);
  return manifest;
}

TEST(ImageStackErrorTest, MissingImage) {
  const fs::path dir = TestDir();
  const std::string manifest = WriteSampleStack(dir);
  fs::remove(dir / "stack_0001.exr");
  ExpectHas(
      ErrorOf([&] { ReadImageStack(manifest); }),
      {(dir / "stack_0001.exr").string(), "cannot read", manifest + ":7"});
}

TEST(ImageStackErrorTest, TruncatedImage) {
  const fs::path dir = TestDir();
  const std::string manifest = WriteSampleStack(dir);
  const std::string image = (dir / "stack_0002.exr").string();
  const std::string full = ReadFileToString(image);
  for (size_t keep :
       {full.size() / 2, full.size() - 1, size_t{20}, size_t{0}}) {
    WriteText(image, full.substr(0, keep));
    ExpectHas(ErrorOf([&] { ReadImageStack(manifest); }), {image});
  }

  const MeasurementTable table = StackTable(2, 16, 16, 3, true);
  const std::string png_manifest = (dir / "png.csv").string();
  WriteImageStack(table, png_manifest, ".png", true);
  const std::string png = (dir / "png_0000.png").string();
  const std::string png_full = ReadFileToString(png);
  for (size_t keep : {png_full.size() / 2, png_full.size() - 20, size_t{30},
                      size_t{8}, size_t{0}}) {
    WriteText(png, png_full.substr(0, keep));
    ExpectHas(ErrorOf([&] { ReadImageStack(png_manifest); }), {png});
  }

  WriteText(png, "not an image at all");
  ExpectHas(ErrorOf([&] { ReadImageStack(png_manifest); }), {png});
}

TEST(ImageStackErrorTest, ImagesOfDifferentSizes) {
  const fs::path dir = TestDir();
  const std::string manifest = WriteSampleStack(dir);
  WriteImageStack(StackTable(1, 3, 2, 3, false), (dir / "small.csv").string(),
                  ".exr", true);
  std::string text = ReadFileToString(manifest);
  const size_t at = text.find("stack_0001.exr");
  ASSERT_NE(at, std::string::npos);
  text.replace(at, 14, "small_0000.exr");
  WriteText(manifest, text);
  ExpectHas(ErrorOf([&] { ReadImageStack(manifest); }),
            {(dir / "small_0000.exr").string(), "3 x 2",
             (dir / "stack_0000.exr").string(), "5 x 4", manifest + ":7"});
}

TEST(ImageStackErrorTest, BadManifest) {
  const fs::path dir = TestDir();
  const std::string manifest = WriteSampleStack(dir);
  auto error_for = [&](const std::string& text) {
    WriteText(manifest, text);
    return ErrorOf([&] { ReadImageStack(manifest); });
  };
  ExpectHas(error_for("# quantity: brdf\ntheta_i,phi_i,theta_o,phi_o\n"
                      "30,0,45,180\n"),
            {manifest + ":2:", "missing column 'file'"});
  ExpectHas(
      error_for("# quantity: brdf\n\ntheta_i,phi_i,theta_o,phi_o,file\n"
                "30,0,45,180,stack_0000.exr\n"
                "30,abc,45,180,stack_0001.exr\n"),
      {manifest + ":5:2: column 'phi_i': cannot parse 'abc' as a number"});
  ExpectHas(error_for("file,theta_i,phi_i,theta_o,phi_o\n"
                      "stack_0000.exr,30,0,45,1e999\n"),
            {manifest + ":2:5:", "'phi_o'", "finite"});
  ExpectHas(error_for("theta_i,phi_i,theta_o,phi_o,file\n"
                      "30,0,245,180,stack_0000.exr\n"),
            {manifest + ":2:3:", "'theta_o'", "out of range"});
  ExpectHas(error_for("theta_i,phi_i,theta_o,phi_o,file\n30,0,45,180\n"),
            {manifest + ":2:5:", "4 fields, header has 5"});
  ExpectHas(error_for("theta_i,phi_i,theta_o,phi_o,file\n30,0,45,180, \n"),
            {manifest + ":2:5:", "empty file name"});
  ExpectHas(error_for("theta_i,phi_i,theta_o,phi_o,r,file\n30,0,45,180,1,x\n"),
            {manifest + ":1:5:", "unknown column 'r'"});
  ExpectHas(error_for("theta_i,phi_i,theta_o,file,phi_o,file\n"),
            {manifest + ":1:6:", "duplicate column 'file'"});
  ExpectHas(error_for("theta_i,phi_i,theta_o,file\n1,2,3,x.exr\n"),
            {manifest + ":1:", "missing column 'phi_o'"});
  ExpectHas(error_for("theta_i,phi_i,theta_o,phi_o,file\n# none\n"),
            {manifest + ":1:", "no images"});
  ExpectHas(error_for("# only metadata\n"), {manifest, "no header"});
  ExpectHas(error_for("# clothfit-stack 2\ntheta_i,phi_i,theta_o,phi_o,file\n"
                      "1,2,3,4,stack_0000.exr\n"),
            {manifest + ":1:", "version '2'", "clothfit-stack 1"});
  ExpectHas(error_for("# units: parsecs\ntheta_i,phi_i,theta_o,phi_o,file\n"
                      "1,2,3,4,x.exr\n"),
            {manifest + ":1:", "units"});
  ExpectHas(ErrorOf([&] { ReadImageStack((dir / "absent.csv").string()); }),
            {(dir / "absent.csv").string(), "cannot read"});
}

TEST(ImageStackErrorTest, BadNormalMap) {
  const fs::path dir = TestDir();
  const std::string manifest = WriteSampleStack(dir);
  const std::string rows = ReadFileToString(manifest);
  // A manifest with `lines` before the stack's own lines.
  auto error_for = [&](const std::string& lines) {
    WriteText(manifest, lines + rows);
    return ErrorOf([&] { ReadImageStack(manifest); });
  };
  auto write_exr = [&](const std::string& name, int width, int height,
                       int channels, const std::vector<float>& pixels) {
    WriteImage((dir / name).string(), width, height, channels, false, true,
               pixels);
  };
  std::vector<float> up(5 * 4 * 3, 0.0f);
  for (size_t i = 2; i < up.size(); i += 3) up[i] = 1.0f;
  write_exr("up.exr", 5, 4, 3, up);
  ASSERT_NO_THROW({
    WriteText(manifest, "# normal_map: up.exr\n" + rows);
    EXPECT_TRUE(ReadImageStack(manifest).has_normal);
  });

  ExpectHas(error_for("# normal_map: none.exr\n"),
            {(dir / "none.exr").string(), "cannot read", manifest + ":1"});
  write_exr("small.exr", 3, 2, 3, std::vector<float>(3 * 2 * 3, 1.0f));
  ExpectHas(error_for("# normal_map: small.exr\n"),
            {(dir / "stack_0000.exr").string(), "5 x 4",
             (dir / "small.exr").string(), "3 x 2"});
  write_exr("grey.exr", 5, 4, 1, std::vector<float>(5 * 4, 1.0f));
  ExpectHas(error_for("# normal_map: grey.exr\n"),
            {(dir / "grey.exr").string(), "3 colour channels", "got 1",
             manifest + ":1"});
  std::vector<float> zero = up;
  zero[(2 * 5 + 3) * 3 + 2] = 0.0f;  // pixel (3, 2)
  write_exr("zero.exr", 5, 4, 3, zero);
  ExpectHas(error_for("# note: x\n# normal_map: zero.exr\n"),
            {(dir / "zero.exr").string(), "pixel (3, 2)", "zero normal",
             manifest + ":2"});
  // clothfit writes no NaN: a portable float map (rows bottom first) with a
  // NaN in column 1 of every row.
  std::string pfm = "PF\n5 4\n-1.0\n";
  for (int y = 0; y < 4; ++y) {
    for (int x = 0; x < 5; ++x) {
      for (int c = 0; c < 3; ++c) {
        const float v =
            x == 1 && c == 0 ? std::nanf("") : (c == 2 ? 1.0f : 0.0f);
        pfm.append(reinterpret_cast<const char*>(&v), sizeof(v));
      }
    }
  }
  std::ofstream(dir / "nan.pfm", std::ios::binary) << pfm;
  ExpectHas(error_for("# normal_map: nan.pfm\n"),
            {(dir / "nan.pfm").string(), "pixel (1, 0) channel 0 is NaN"});
  ExpectHas(error_for("# normal_map:  \n"),
            {manifest + ":1:", "'normal_map'", "empty file name"});
  ExpectHas(error_for("# normal_map: up.exr\n# Normal_Map: up.exr\n"),
            {manifest + ":2:", "'normal_map'", "first on line 1"});

  // The writer needs one normal per texel.
  MeasurementTable table = WithNormals(StackTable(2, 3, 2, 3, false));
  table.rows[6 + 4].normal = glm::dvec3(0.0, 0.0, 1.0);  // pair 1, (1, 1)
  ExpectHas(ErrorOf([&] {
              WriteImageStack(table, (dir / "w.csv").string(), ".exr", false);
            }),
            {(dir / "w.csv").string(), "texel (1, 1)", "rows 5 and 11",
             "one normal per texel"});
}

TEST(ImageStackErrorTest, WriteNeedsFullGrids) {
  const fs::path dir = TestDir();
  const std::string manifest = (dir / "w.csv").string();
  MeasurementTable table = StackTable(3, 5, 4, 3, false);

  MeasurementTable missing = table;
  missing.rows.erase(missing.rows.begin() + 25);  // pair 1, texel (0, 1)
  ExpectHas(ErrorOf([&] { WriteImageStack(missing, manifest, ".exr", true); }),
            {manifest, "direction pair 1", "texel (0, 1) is missing"});

  MeasurementTable twice = table;
  twice.rows[3].s = 2;  // pair 0: (2, 0) twice, (3, 0) missing
  ExpectHas(ErrorOf([&] { WriteImageStack(twice, manifest, ".exr", true); }),
            {manifest, "direction pair 0", "texel (2, 0) given twice"});

  MeasurementTable no_texels = table;
  no_texels.rows[7].s = -1;
  ExpectHas(
      ErrorOf([&] { WriteImageStack(no_texels, manifest, ".exr", true); }),
      {manifest, "row 8", "texel"});

  ExpectHas(ErrorOf([&] {
              WriteImageStack(MeasurementTable(), manifest, ".exr", true);
            }),
            {manifest, "empty"});
  ExpectHas(ErrorOf([&] { WriteImageStack(table, manifest, ".nope", true); }),
            {"w_0000.nope"});
  EXPECT_FALSE(fs::exists(manifest));
  // Nothing (no temporary files either) was left behind.
  EXPECT_TRUE(fs::is_empty(dir));
}

}  // namespace
}  // namespace clothfit
