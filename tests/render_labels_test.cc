// What tells a reader of `clothfit render`'s files what they show: the
// labelled PNG (render/preview.h LabelledDisplay: a band per row with the
// row's and the panels' titles and the warp arrows), the EXR's header
// (model, parameters, command line, version) and the default size.
#include <ImfHeader.h>
#include <ImfInputFile.h>
#include <ImfStringAttribute.h>
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "models/presets.h"
#include "render/preview.h"
#include "tests/cli_test_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using testing_util::Describe;
using testing_util::RunClothfit;
using testing_util::RunResult;

// Counts of the pixels of a rectangle of the display that are ink (dark
// grey), arrow (clearly blue) or neither.
struct Ink {
  int dark = 0, blue = 0;
};
Ink CountInk(const DisplayImage& d, int x0, int y0, int x1, int y1) {
  Ink ink;
  for (int y = y0; y < y1; ++y) {
    for (int x = x0; x < x1; ++x) {
      const float* p = &d.rgb[(size_t(y) * d.width + x) * 3];
      if (p[0] < 0.5f && p[1] < 0.5f && p[2] < 0.5f) ++ink.dark;
      if (p[2] > p[0] + 0.25f) ++ink.blue;
    }
  }
  return ink;
}

ModelParams Linen() {
  ClothParams p;
  EXPECT_TRUE(GetPreset("linen_plain", &p));
  return p;
}

TEST(RenderLabels, EachRowAndPanelIsTitledAndEachCylinderHasItsWarpArrow) {
  PreviewOptions o;
  o.size = 160;
  PreviewImage top = RenderCylinders(Linen(), o);
  top.row_titles = {"fit: P.json (cloth)"};
  const PreviewImage bottom = RenderCylinders(Linen(), o);  // no row title
  const PreviewImage image = StackRows(top, bottom);
  ASSERT_EQ(image.panel_titles.size(), 6u);
  const double exposure = AutoExposure(image);
  const DisplayImage d = LabelledDisplay(image, exposure);
  ASSERT_EQ(d.width, image.width);
  ASSERT_EQ(d.height, image.height + 2 * kLabelBand);
  ASSERT_EQ(d.rgb.size(), size_t(d.width) * d.height * 3);
  const int line = kLabelBand / 2;
  for (int row = 0; row < 2; ++row) {
    const int band = row * (o.size + kLabelBand);
    // The row's title on the band's first line: only where one is given.
    const int title_ink = CountInk(d, 0, band, d.width, band + line).dark;
    if (row == 0) {
      EXPECT_GT(title_ink, 50);
    } else {
      EXPECT_EQ(title_ink, 0);
    }
    for (int panel = 0; panel < 3; ++panel) {
      const Ink ink = CountInk(d, panel * o.size, band + line,
                               (panel + 1) * o.size, band + kLabelBand);
      EXPECT_GT(ink.dark, 50) << "row " << row << " panel " << panel;
      EXPECT_GT(ink.blue, 10) << "row " << row << " panel " << panel;
    }
    // Below the band, the panels' tone-mapped pixels, unchanged.
    for (int k : {o.size / 2, o.size + o.size / 3}) {
      const glm::dvec3 v = image.At(k, row * o.size + o.size / 2);
      const double x = std::clamp(v.x * exposure, 0.0, 1.0);
      const double srgb =
          x <= 0.0031308 ? 12.92 * x : 1.055 * std::pow(x, 1.0 / 2.4) - 0.055;
      const int y = band + kLabelBand + o.size / 2;
      EXPECT_NEAR(d.rgb[(size_t(y) * d.width + k) * 3], srgb, 0.5 / 255 + 1e-6);
    }
  }
}

TEST(RenderLabels, PanelsThatAreNotCylindersGetNoArrow) {
  PreviewOptions o;
  o.size = 160;
  SlabParams slab;
  const PreviewImage image = RenderSlab(slab, o);
  const DisplayImage d = LabelledDisplay(image, 1.0);
  for (int panel = 0; panel < 2; ++panel) {
    const Ink ink =
        CountInk(d, panel * o.size, 0, (panel + 1) * o.size, kLabelBand);
    EXPECT_GT(ink.dark, 50);  // "front-lit", "back-lit"
    EXPECT_EQ(ink.blue, 0);
  }
}

std::string HeaderString(const Imf::Header& header, const char* name) {
  const auto* a = header.findTypedAttribute<Imf::StringAttribute>(name);
  return a ? a->value() : "<missing " + std::string(name) + ">";
}

// The EXR's header, read with OpenEXR: the model and parameter file of
// each row (the file's JSON as `clothfit preset` writes it), the command
// line and the version; 192-pixel panels by default.
TEST(RenderLabels, ExrHeaderNamesModelParametersCommandAndVersion) {
  const fs::path dir = testing_util::FreshTestDir("render_labels_test_");
  const RunResult preset = RunClothfit(
      dir, {"preset", "linen_plain", "--out", (dir / "p.json").string()});
  ASSERT_EQ(preset.status, 0) << Describe(preset);
  const std::string params = testing_util::ReadText(dir / "p.json");
  const std::string exr = (dir / "r.exr").string();
  const RunResult r =
      RunClothfit(dir, {"render", "--params", (dir / "p.json").string(),
                        "--compare-preset", "linen_plain", "--out", exr});
  ASSERT_EQ(r.status, 0) << Describe(r);
  Imf::InputFile file(exr.c_str());
  const Imf::Header& header = file.header();
  const Imath::Box2i window = header.dataWindow();
  EXPECT_EQ(window.max.x - window.min.x + 1, 3 * 192);  // default size
  EXPECT_EQ(window.max.y - window.min.y + 1, 2 * 192);
  EXPECT_EQ(HeaderString(header, "clothfit:model"), "cloth");
  EXPECT_EQ(HeaderString(header, "clothfit:params"), params);
  EXPECT_EQ(HeaderString(header, "clothfit:compare_model"), "cloth");
  EXPECT_EQ(HeaderString(header, "clothfit:compare_params"), params);
  EXPECT_EQ(HeaderString(header, "clothfit:version"), CLOTHFIT_VERSION);
  const std::string command = HeaderString(header, "clothfit:command");
  EXPECT_EQ(command.rfind("clothfit render --params ", 0), 0u) << command;
  EXPECT_NE(command.find("--compare-preset linen_plain --out"),
            std::string::npos)
      << command;
  EXPECT_EQ(HeaderString(header, "clothfit:rows"),
            "params: p.json (cloth)\ncompare: preset linen_plain (cloth)");
  // The PNG beside it: the same panels under two label bands.
  auto png = OIIO::ImageInput::open((dir / "r.png").string());
  ASSERT_TRUE(png);
  EXPECT_EQ(png->spec().width, 3 * 192);
  EXPECT_EQ(png->spec().height, 2 * 192 + 2 * kLabelBand);
}

}  // namespace
}  // namespace clothfit
