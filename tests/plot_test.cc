// clothfit plot and its figures (report/fit_figures.h): every figure is
// written for a CUReT table, the polar panels count the rows inside their
// window (counted here from the table's angles by spherical trigonometry),
// the scatter and residuals use every row, the half/difference angles
// invert, and bad requests exit 2.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "io/table.h"
#include "models/math.h"
#include "models/presets.h"
#include "report/fit_figures.h"
#include "tests/cli_test_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using testing_util::Describe;
using testing_util::ExpectBadInput;
using testing_util::FreshTestDir;
using testing_util::ReadText;
using testing_util::RunClothfit;
using testing_util::RunResult;

const std::string kVelvet =
    std::string(CLOTHFIT_SHARED_DIR) + "/data/curet/curet_07_velvet.csv";

ModelParams Velvet() {
  ClothParams c;
  EXPECT_TRUE(GetPreset("velvet", &c));
  return c;
}

// Width and height from a PNG's IHDR chunk; {0, 0} when not a PNG.
std::pair<uint32_t, uint32_t> PngSize(const fs::path& path) {
  const std::string bytes = ReadText(path);
  if (bytes.size() < 24 || bytes.compare(0, 8, "\x89PNG\r\n\x1a\n") != 0 ||
      bytes.compare(12, 4, "IHDR") != 0) {
    return {0, 0};
  }
  auto be32 = [&](size_t at) {
    uint32_t v = 0;
    for (size_t k = 0; k < 4; ++k) {
      v = (v << 8) | static_cast<unsigned char>(bytes[at + k]);
    }
    return v;
  };
  return {be32(16), be32(20)};
}

// The table's angle columns (degrees) as read from the text.
struct Angles {
  double theta_i, phi_i, theta_o, phi_o;
};
std::vector<Angles> ReadAngles(const std::string& path) {
  std::ifstream in(path);
  std::vector<Angles> out;
  std::string line;
  bool header = false;
  while (std::getline(in, line)) {
    if (line.empty() || line[0] == '#') continue;
    if (!header) {
      EXPECT_EQ(line.rfind("theta_i,phi_i,theta_o,phi_o", 0), 0u) << line;
      header = true;
      continue;
    }
    std::istringstream fields(line);
    Angles a;
    char comma;
    fields >> a.theta_i >> comma >> a.phi_i >> comma >> a.theta_o >> comma >>
        a.phi_o;
    out.push_back(a);
  }
  return out;
}

TEST(PlotTest, WritesEveryFigureForACuretTable) {
  const fs::path dir = FreshTestDir("plot_");
  const RunResult r =
      RunClothfit(dir, {"plot", "--preset", "velvet", "--data", kVelvet,
                        "--out", (dir / "figs/").string()});
  ASSERT_EQ(r.status, 0) << Describe(r);
  for (const std::string& name : kFigureNames) {
    const fs::path png = dir / "figs" / (name + ".png");
    const auto [w, h] = PngSize(png);
    EXPECT_GE(w, 400u) << name;
    EXPECT_GE(h, 250u) << name;
    EXPECT_NE(r.out.find("wrote " + png.string()), std::string::npos) << r.out;
  }
  // 14 of 205 rows lie near the default planes: the warning says so and
  // names the figures that show every row.
  EXPECT_NE(r.err.find("warning: the polar panels show 14 of 205 rows"),
            std::string::npos)
      << r.err;
  EXPECT_NE(r.err.find("scatter"), std::string::npos) << r.err;
  // A prefix, and figures without a table: skipped with a note.
  const RunResult p = RunClothfit(
      dir, {"plot", "--preset", "velvet", "--out", (dir / "v").string()});
  ASSERT_EQ(p.status, 0) << Describe(p);
  for (const char* name : {"halfdiff", "sphere", "albedo"}) {
    EXPECT_GT(PngSize(dir / ("v_" + std::string(name) + ".png")).first, 0u);
  }
  EXPECT_FALSE(fs::exists(dir / "v_scatter.png"));
  EXPECT_NE(p.err.find("note: scatter needs a table"), std::string::npos)
      << p.err;
  // --out P.png: the one polar figure, as before.
  const RunResult single =
      RunClothfit(dir, {"plot", "--preset", "velvet", "--data", kVelvet,
                        "--out", (dir / "p.png").string()});
  ASSERT_EQ(single.status, 0) << Describe(single);
  EXPECT_GT(PngSize(dir / "p.png").first, 0u);
}

TEST(PlotTest, PolarPanelsCountTheRowsInsideTheirWindow) {
  const MeasurementTable table = ReadTable(kVelvet).table;
  const std::vector<Angles> angles = ReadAngles(kVelvet);
  ASSERT_EQ(angles.size(), 205u);
  ASSERT_EQ(table.rows.size(), 205u);
  PlotOptions options;
  options.incidence_deg = {0, 22.5, 45, 67.5};
  options.phi_deg = 0.0;
  options.window_deg = 12.0;
  size_t shown = 0;
  const std::vector<PolarPanel> panels =
      PolarPanels(Velvet(), table, options, &shown);
  ASSERT_EQ(panels.size(), 4u);
  std::vector<bool> any(angles.size(), false);
  for (size_t p = 0; p < panels.size(); ++p) {
    const double ti = Radians(options.incidence_deg[p]);
    size_t inside = 0;
    for (size_t k = 0; k < angles.size(); ++k) {
      const Angles& a = angles[k];
      // The angle between the row's light and the panel's (phi = 0):
      // the spherical law of cosines.
      const double cos_light = std::cos(Radians(a.theta_i)) * std::cos(ti) +
                               std::sin(Radians(a.theta_i)) * std::sin(ti) *
                                   std::cos(Radians(a.phi_i));
      // The view's elevation out of the plane y = 0.
      const double off_plane =
          std::asin(std::sin(Radians(a.theta_o)) * std::sin(Radians(a.phi_o)));
      const double w = Radians(options.window_deg);
      if (a.theta_o < 90.0 && cos_light >= std::cos(w) &&
          std::abs(off_plane) <= w) {
        ++inside;
        any[k] = true;
      }
    }
    EXPECT_EQ(panels[p].measured_value.size(), inside) << p;
    EXPECT_NE(panels[p].title.find(std::to_string(inside) + " of 205 rows"),
              std::string::npos)
        << panels[p].title;
    EXPECT_EQ(panels[p].model_angle_deg.size(), 179u);
  }
  EXPECT_EQ(shown,
            static_cast<size_t>(std::count(any.begin(), any.end(), true)));
  EXPECT_GT(shown, 14u);  // the wider window sees more
}

TEST(PlotTest, ScatterAndResidualsUseEveryRow) {
  const MeasurementTable table = ReadTable(kVelvet).table;
  const std::vector<Angles> angles = ReadAngles(kVelvet);
  const RowComparison rows = CompareRows(Velvet(), table);
  ASSERT_EQ(rows.measured.size(), 205u);
  ASSERT_EQ(rows.model.size(), 205u);
  ASSERT_EQ(rows.phase_deg.size(), 205u);
  for (size_t k = 0; k < angles.size(); ++k) {
    EXPECT_NEAR(rows.measured[k], table.rows[k].value.x, 1e-12);
    EXPECT_NEAR(rows.theta_i_deg[k], angles[k].theta_i, 1e-9);
    EXPECT_NEAR(rows.theta_o_deg[k], angles[k].theta_o, 1e-9);
    // The phase angle from the angles (spherical law of cosines).
    const Angles& a = angles[k];
    const double cos_phase =
        std::cos(Radians(a.theta_i)) * std::cos(Radians(a.theta_o)) +
        std::sin(Radians(a.theta_i)) * std::sin(Radians(a.theta_o)) *
            std::cos(Radians(a.phi_i - a.phi_o));
    EXPECT_NEAR(rows.phase_deg[k],
                Degrees(std::acos(std::clamp(cos_phase, -1.0, 1.0))), 1e-6);
    EXPECT_TRUE(std::isfinite(rows.model[k]));
  }
}

TEST(PlotTest, HalfDifferenceAnglesInvert) {
  // Mirror directions: h is the normal, theta_d the angle of incidence.
  const double a = Radians(40.0);
  const glm::dvec3 wi(std::sin(a), 0.0, std::cos(a)),
      wo(-std::sin(a), 0.0, std::cos(a));
  const HalfDiff m = ToHalfDiff(wi, wo);
  EXPECT_NEAR(m.theta_h, 0.0, 1e-12);
  EXPECT_NEAR(m.theta_d, a, 1e-12);
  EXPECT_NEAR(PhaseAngle(wi, wo), 2.0 * a, 1e-12);
  // Retro-reflection: theta_d = 0, h = wi.
  const HalfDiff r = ToHalfDiff(wi, wi);
  EXPECT_NEAR(r.theta_h, a, 1e-12);
  EXPECT_NEAR(r.theta_d, 0.0, 1e-7);
  for (double th : {5.0, 30.0, 60.0}) {
    for (double td : {10.0, 45.0, 80.0}) {
      for (double pd : {-120.0, 30.0, 90.0}) {
        HalfDiff in;
        in.theta_h = Radians(th);
        in.phi_h = Radians(20.0);
        in.theta_d = Radians(td);
        in.phi_d = Radians(pd);
        const auto [i, o] = FromHalfDiff(in);
        EXPECT_NEAR(glm::length(i), 1.0, 1e-12);
        EXPECT_NEAR(glm::length(o), 1.0, 1e-12);
        // The half vector of the pair is at (theta_h, phi_h).
        const glm::dvec3 h = glm::normalize(i + o);
        EXPECT_NEAR(std::acos(h.z), in.theta_h, 1e-9);
        const HalfDiff back = ToHalfDiff(i, o);
        EXPECT_NEAR(back.theta_h, in.theta_h, 1e-9);
        EXPECT_NEAR(back.phi_h, in.phi_h, 1e-9);
        EXPECT_NEAR(back.theta_d, in.theta_d, 1e-9);
        EXPECT_NEAR(back.phi_d, in.phi_d, 1e-9);
      }
    }
  }
}

TEST(PlotTest, BadRequestsExit2) {
  const fs::path dir = FreshTestDir("plot_");
  const std::string out = (dir / "figs/").string();
  ExpectBadInput(dir,
                 {"plot", "--preset", "velvet", "--figures", "scatter,sphere",
                  "--out", out},
                 {"figure 'scatter' needs a table", "--data"});
  ExpectBadInput(
      dir,
      {"plot", "--preset", "velvet", "--data", kVelvet, "--figures",
       "sphere,polr", "--out", out},
      {"--figures", "unknown figure 'polr'", "did you mean 'polar'"});
  ExpectBadInput(
      dir, {"plot", "--preset", "velvet", "--out", (dir / "p.png").string()},
      {"figure 'polar' needs a table"});
  ExpectBadInput(dir,
                 {"plot", "--preset", "velvet", "--data", kVelvet, "--figures",
                  "scatter", "--out", (dir / "p.png").string()},
                 {"--figures", "single polar figure"});
  EXPECT_FALSE(fs::exists(dir / "figs"));
}

}  // namespace
}  // namespace clothfit
