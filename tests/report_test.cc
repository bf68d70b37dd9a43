// clothfit report: the page embeds every figure, the fit's summary, its
// parameter values with their standard deviations and the selection's
// candidates; in headless Chromium it loads without an error and its WebGL
// sphere (the model's GLSL) draws what the sphere figure (the C++ model)
// shows, on the background around it.
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <cmath>
#include <cstdio>
#include <cstring>
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "report/fit_figures.h"
#include "tests/browser_test_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using namespace testing_util;  // NOLINT

const std::string kVelvet =
    std::string(CLOTHFIT_SHARED_DIR) + "/data/curet/curet_07_velvet.csv";

struct Image {
  int width = 0, height = 0, channels = 0;
  std::vector<unsigned char> pixels;
  const unsigned char* At(int x, int y) const {
    return &pixels[(size_t(y) * width + x) * channels];
  }
};

Image ReadImage(const std::string& path) {
  Image image;
  auto in = OIIO::ImageInput::open(path);
  if (!in) {
    ADD_FAILURE() << "cannot read " << path;
    return image;
  }
  image.width = in->spec().width;
  image.height = in->spec().height;
  image.channels = in->spec().nchannels;
  image.pixels.resize(size_t(image.width) * image.height * image.channels);
  in->read_image(0, 0, 0, image.channels, OIIO::TypeDesc::UINT8,
                 image.pixels.data());
  return image;
}

// A Lafortune fit with a held-out selection of the lobe count.
fs::path FitVelvet(const fs::path& dir) {
  const fs::path params = dir / "velvet.json";
  const RunResult r =
      RunClothfit(dir, {"fit", "--model", "lafortune", "--data", kVelvet,
                        "--select", "heldout", "--out", params.string()});
  EXPECT_TRUE(r.status == 0 || r.status == 1) << Describe(r);
  EXPECT_TRUE(fs::exists(params)) << Describe(r);
  return params;
}

TEST(ReportTest, EmbedsEveryFigureTheFitAndTheSelection) {
  const fs::path dir = FreshTestDir("report_");
  const fs::path params = FitVelvet(dir);
  const fs::path page = dir / "r.html";
  const RunResult r =
      RunClothfit(dir, {"report", "--params", params.string(), "--data",
                        kVelvet, "--out", page.string()});
  ASSERT_EQ(r.status, 0) << Describe(r);
  const std::string html = ReadText(page);
  for (const std::string& name : kFigureNames) {
    const std::string open = "<figure id=\"figure-" + name + "\"><img alt=\"" +
                             name + "\" src=\"data:image/png;base64,";
    const size_t at = html.find(open);
    ASSERT_NE(at, std::string::npos) << name;
    const size_t start = at + open.size();
    const std::vector<uint8_t> png =
        DecodeBase64(html.substr(start, html.find('"', start) - start));
    ASSERT_GT(png.size(), 1000u) << name;
    EXPECT_EQ(std::string(png.begin(), png.begin() + 4), "\x89PNG") << name;
  }
  EXPECT_EQ(Count(html, "data:image/png;base64,"), kFigureNames.size());
  // Nothing fetched: no external URL.
  EXPECT_EQ(html.find("http://"), std::string::npos);
  EXPECT_EQ(html.find("https://"), std::string::npos);
  // Every fitted value and standard deviation, in one row per parameter.
  const nlohmann::json fit = nlohmann::json::parse(ReadText(params))["fit"];
  ASSERT_GT(fit["values"].size(), 10u);
  for (const auto& [name, value] : fit["values"].items()) {
    char row[200];
    std::snprintf(row, sizeof(row), "<tr><td>%s</td><td>%.6g</td><td>",
                  name.c_str(), value.get<double>());
    const size_t at = html.find(row);
    ASSERT_NE(at, std::string::npos) << row;
    if (fit["stddev"].contains(name)) {
      char sd[64];
      std::snprintf(sd, sizeof(sd), "%.6g</td>",
                    fit["stddev"][name].get<double>());
      EXPECT_EQ(html.compare(at + std::strlen(row), std::strlen(sd), sd), 0)
          << name << ": " << html.substr(at, 160);
    }
  }
  char rms[64];
  std::snprintf(rms, sizeof(rms), "<th>relative_rms</th><td>%.6g</td>",
                fit["relative_rms"].get<double>());
  EXPECT_NE(html.find(rms), std::string::npos) << rms;
  EXPECT_NE(html.find("<th>termination</th><td>" +
                      fit["termination"].get<std::string>()),
            std::string::npos);
  ASSERT_TRUE(fit.contains("selection"));
  for (const auto& c : fit["selection"]["candidates"]) {
    EXPECT_NE(
        html.find("<tr><td>" + c["description"].get<std::string>() + "</td>"),
        std::string::npos)
        << c["description"];
  }
}

TEST(ReportTest, SphereDrawsInHeadlessChromium) {
  if (!fs::exists(kChromium)) GTEST_SKIP() << "no " << kChromium;
  const fs::path dir = FreshTestDir("report_");
  const fs::path params = FitVelvet(dir);
  const fs::path page = dir / "r.html";
  ASSERT_EQ(RunClothfit(dir, {"report", "--params", params.string(), "--data",
                              kVelvet, "--out", page.string()})
                .status,
            0);
  const std::string url = "file://" + fs::absolute(page).string();
  const std::string dom = DumpDom(url, dir);
  EXPECT_EQ(PreText(dom, "status").rfind("OK light", 0), 0u)
      << PreText(dom, "status");
  const fs::path shot = dir / "shot.png";
  const std::string command =
      std::string(kChromium) +
      " --headless=new --no-sandbox --disable-dev-shm-usage "
      "--use-angle=swiftshader --enable-unsafe-swiftshader "
      "--hide-scrollbars --force-device-scale-factor=1 "
      "--window-size=800,600 --virtual-time-budget=20000 --screenshot=" +
      Quote(shot.string()) + " " + Quote(url) + " >/dev/null 2>&1";
  ASSERT_EQ(std::system(command.c_str()), 0);
  const Image image = ReadImage(shot.string());
  ASSERT_GE(image.width, 256);
  ASSERT_GE(image.height, 256);
  // The sphere figure of the same page: the C++ model's picture (its
  // sphere 256 pixels wide, centred, 40 pixels below the top).
  const std::string html = ReadText(page);
  const std::string open = "<img alt=\"sphere\" src=\"data:image/png;base64,";
  const size_t start = html.find(open) + open.size();
  const std::vector<uint8_t> png =
      DecodeBase64(html.substr(start, html.find('"', start) - start));
  const fs::path figure = dir / "sphere.png";
  WriteText(figure, std::string(png.begin(), png.end()));
  const Image reference = ReadImage(figure.string());
  const int x0 = (reference.width - 256) / 2, y0 = 40;
  int inside = 0, lit = 0, outside = 0, background = 0;
  double difference = 0.0;
  for (int y = 0; y < 256; ++y) {
    for (int x = 0; x < 256; ++x) {
      const double u = (x + 0.5) / 128.0 - 1.0, v = 1.0 - (y + 0.5) / 128.0;
      const double r = std::sqrt(u * u + v * v);
      const unsigned char* p = image.At(x, y);
      const bool grey = std::abs(p[0] - 128) <= 2 &&
                        std::abs(p[1] - 128) <= 2 && std::abs(p[2] - 128) <= 2;
      if (r > 1.02) {
        ++outside;
        background += grey;
      } else if (r < 0.98) {
        ++inside;
        lit += p[0] + p[1] + p[2] > 30;
        const unsigned char* q = reference.At(x0 + x, y0 + y);
        for (int c = 0; c < 3; ++c) difference += std::abs(p[c] - q[c]);
      }
    }
  }
  EXPECT_EQ(background, outside);
  // The lit half of the sphere, and WebGL's float GLSL agreeing with the
  // C++ model in double to a few 8-bit levels on average.
  EXPECT_GT(lit, inside / 4);
  EXPECT_LT(difference / (3.0 * inside), 3.0);
}

}  // namespace
}  // namespace clothfit
