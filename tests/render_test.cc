// Preview renders (render/preview.h) against radiance computed by hand for
// models whose value has a closed form, and `clothfit render` (files,
// sizes, bad input).
#include <OpenImageIO/imageio.h>
#include <gtest/gtest.h>

#include <filesystem>
#include <string>
#include <vector>

#include "holes/hole_texture.h"
#include "io/lafortune_mipmap.h"
#include "io/mask_io.h"
#include "io/param_mipmap.h"
#include "render/preview.h"
#include "tests/cli_test_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using testing_util::Describe;
using testing_util::ExpectBadInput;
using testing_util::RunClothfit;
using testing_util::RunResult;
using testing_util::WriteText;

fs::path TestDir() { return testing_util::FreshTestDir("render_test_"); }

PreviewOptions Small() {
  PreviewOptions o;
  o.size = 24;
  return o;
}

// The cylinder's point under panel pixel (i, j) and the light's direction
// and I / r^2 there (render/preview.h's scene), or false off the cylinder.
bool CylinderPoint(const PreviewOptions& o, int i, int j, glm::dvec3* point,
                   glm::dvec3* wi, double* irradiance) {
  const double x = ((i + 0.5) / o.size * 2.0 - 1.0) * 1.2;
  const double y = (1.0 - (j + 0.5) / o.size * 2.0) * 1.2;
  if (!(std::abs(x) < 1.0)) return false;
  *point = glm::dvec3(x, y, std::sqrt(1.0 - x * x));
  const glm::dvec3 to_light = o.light * o.light_distance - *point;
  *wi = glm::normalize(to_light);
  *irradiance =
      o.light_distance * o.light_distance / glm::dot(to_light, to_light);
  return true;
}

TEST(Render, DiffuseCylindersAreLambertianInEveryOrientation) {
  const PreviewOptions o = Small();
  LafortuneModel diffuse;
  diffuse.params.diffuse = glm::dvec3(0.2, 0.4, 0.6);
  const PreviewImage image = RenderCylinders(diffuse, o);
  ASSERT_EQ(image.width, 3 * o.size);
  ASSERT_EQ(image.height, o.size);
  for (int panel = 0; panel < 3; ++panel) {
    for (int j = 0; j < o.size; ++j) {
      for (int i = 0; i < o.size; ++i) {
        glm::dvec3 p, wi;
        double e = 0.0;
        glm::dvec3 expected(0.0);
        if (CylinderPoint(o, i, j, &p, &wi, &e)) {
          // rho = diffuse cos(theta_i); the normal of the unit cylinder
          // about +y is (x, 0, z).
          const double cos_i = glm::dot(glm::dvec3(p.x, 0.0, p.z), wi);
          if (cos_i > 0.0) expected = diffuse.params.diffuse * cos_i * e;
        }
        const glm::dvec3 got = image.At(panel * o.size + i, j);
        for (int c = 0; c < 3; ++c) {
          EXPECT_NEAR(got[c], expected[c], 1e-12)
              << panel << " " << i << "," << j;
        }
      }
    }
  }
}

// A Lafortune lobe [Cx l.x v.x]^1 alone reveals where the warp (+x of the
// surface frame) runs: along the axis (0, 1, 0), around it (z, 0, -x), or
// between them at 45 degrees.
TEST(Render, CylinderPanelsTurnTheWarpVerticalHorizontalDiagonal) {
  const PreviewOptions o = Small();
  LafortuneModel lobe;
  lobe.params.diffuse = glm::dvec3(0.0);
  LafortuneLobe x_only;
  x_only.cx = glm::dvec3(1.0);
  x_only.cy = x_only.cz = glm::dvec3(0.0);
  x_only.n = glm::dvec3(1.0);
  lobe.params.lobes = {x_only};
  const PreviewImage image = RenderCylinders(lobe, o);
  EXPECT_EQ(image.panel_titles,
            (std::vector<std::string>{"warp vertical", "warp horizontal",
                                      "warp diagonal"}));
  EXPECT_EQ(image.panel_warp_deg, (std::vector<double>{0.0, 90.0, 45.0}));
  double lit = 0.0;
  for (int panel = 0; panel < 3; ++panel) {
    const double a = Radians(panel == 0 ? 0.0 : panel == 1 ? 90.0 : 45.0);
    for (int j = 0; j < o.size; ++j) {
      for (int i = 0; i < o.size; ++i) {
        glm::dvec3 p, wi;
        double e = 0.0;
        double expected = 0.0;
        if (CylinderPoint(o, i, j, &p, &wi, &e)) {
          const glm::dvec3 n(p.x, 0.0, p.z);
          const glm::dvec3 warp = std::cos(a) * glm::dvec3(0.0, 1.0, 0.0) +
                                  std::sin(a) * glm::dvec3(p.z, 0.0, -p.x);
          // wo = +z: v.x = warp.z; l.x = wi . warp; l.z = wi . n.
          const double lx_vx = glm::dot(wi, warp) * warp.z;
          const double lz = glm::dot(wi, n);
          if (lz > 0.0 && lx_vx > 0.0) expected = lz * lx_vx * e;
        }
        EXPECT_NEAR(image.At(panel * o.size + i, j).x, expected, 1e-12)
            << "panel " << panel << " pixel " << i << "," << j;
        lit += expected;
      }
    }
  }
  EXPECT_GT(lit, 1.0);  // the comparison is not between zeros
}

// A 2 x 2 level 0 of diffuse texels (red 0.1, 0.2 / 0.3, 0.4 by row) and a
// 1 x 1 level 1 (red 0.25), written as a parameter mip map and loaded.
Material DiffuseMipmap(const fs::path& dir) {
  LafortuneTexelMap base, top;
  base.width = base.height = 2;
  for (int i = 0; i < 4; ++i) {
    LafortuneModel t;
    t.params.diffuse = glm::dvec3(0.1 * (i + 1), 0.05, 0.5);
    base.texels.push_back(t);
  }
  top.width = top.height = 1;
  top.texels.resize(1);
  top.texels[0].params.diffuse = glm::dvec3(0.25, 0.05, 0.5);
  const std::string path = (dir / "diffuse.exr").string();
  WriteParamMipmap(ToParamMipmap({base, top}, {}), path);
  return Material::Load(path);
}

TEST(Render, MipLevelIsTheOneWhoseTexelsMatchTheFootprint) {
  const double tile = 0.8, texel = tile / 64;  // 64 texels per tile
  EXPECT_EQ(MipLevelForFootprint(texel, tile, 64, 7), 0);
  EXPECT_EQ(MipLevelForFootprint(0.5 * texel, tile, 64, 7), 0);
  EXPECT_EQ(MipLevelForFootprint(1.4 * texel, tile, 64, 7), 0);  // log2 0.49
  EXPECT_EQ(MipLevelForFootprint(1.5 * texel, tile, 64, 7), 1);  // log2 0.58
  EXPECT_EQ(MipLevelForFootprint(2 * texel, tile, 64, 7), 1);
  EXPECT_EQ(MipLevelForFootprint(16 * texel, tile, 64, 7), 4);
  EXPECT_EQ(MipLevelForFootprint(1e6 * texel, tile, 64, 7), 6);  // clamped
  EXPECT_EQ(MipLevelForFootprint(1e6 * texel, tile, 64, 1), 0);  // one level
  EXPECT_EQ(MipLevelForFootprint(std::nan(""), tile, 64, 7), 0);
}

TEST(Render, MipmapTextureRepeatsEveryTileAndReadsTheFootprintsLevel) {
  const Material m = DiffuseMipmap(TestDir());
  const double tile = 0.8;
  const SurfaceRho rho = MipmapRho(m, tile);
  const glm::dvec3 wi = glm::normalize(glm::dvec3(0.3, 0.1, 0.8));
  const glm::dvec3 wo(0.0, 0.0, 1.0);
  const double fine = 0.01;  // far below a texel (0.4): level 0
  struct Case {
    double u, v, footprint, red;
  };
  for (const Case& c :
       {Case{0.1, 0.1, fine, 0.1}, Case{0.5, 0.1, fine, 0.2},
        Case{0.1, 0.5, fine, 0.3}, Case{0.5, 0.5, fine, 0.4},
        // Repeats, also towards negative coordinates.
        Case{0.1 + 3 * tile, 0.1, fine, 0.1},
        Case{0.5 - 2 * tile, 0.5 - tile, fine, 0.4}, Case{-0.1, 0.1, fine, 0.2},
        // A footprint of two texels: level 1.
        Case{0.1, 0.1, 0.8, 0.25}}) {
    EXPECT_NEAR(rho(wi, wo, glm::dvec2(c.u, c.v), c.footprint).x, c.red * wi.z,
                1e-7)
        << c.u << "," << c.v << " footprint " << c.footprint;
  }
}

// The cylinders of a mip map: each pixel shows the texel under its
// texture coordinates (warp vertical: u = y along the axis, v = -asin(x)
// around it; threads horizontal: u = asin(x), v = y) at its footprint's
// level, lit like a diffuse surface.
TEST(Render, MipmapCylindersMapTheTextureAlongTheWarp) {
  const Material m = DiffuseMipmap(TestDir());
  PreviewOptions o = Small();
  // Texels of 0.1, the size of a pixel: grazing pixels read level 1.
  const double tile = 0.2, pixel = 2.4 / o.size;
  const PreviewImage image = RenderCylinders(MipmapRho(m, tile), o);
  auto red = [&](double u, double v, double footprint) {
    if (footprint * 2 / tile >= std::sqrt(2.0)) return 0.25;  // level 1
    const int x = static_cast<int>(2 * (u / tile - std::floor(u / tile)));
    const int y = static_cast<int>(2 * (v / tile - std::floor(v / tile)));
    return 0.1 * (1 + x + 2 * y);
  };
  int level0 = 0, level1 = 0;
  for (int panel = 0; panel < 2; ++panel) {
    for (int j = 0; j < o.size; ++j) {
      for (int i = 0; i < o.size; ++i) {
        glm::dvec3 p, wi;
        double e = 0.0, expected = 0.0;
        if (CylinderPoint(o, i, j, &p, &wi, &e)) {
          const double arc = std::asin(p.x), footprint = pixel / p.z;
          const double r =
              panel == 0 ? red(p.y, -arc, footprint) : red(arc, p.y, footprint);
          (r == 0.25 ? level1 : level0)++;
          const double cos_i = glm::dot(glm::dvec3(p.x, 0.0, p.z), wi);
          if (cos_i > 0.0) expected = r * cos_i * e;
        }
        EXPECT_NEAR(image.At(panel * o.size + i, j).x, expected, 1e-6)
            << "panel " << panel << " pixel " << i << "," << j;
      }
    }
  }
  EXPECT_GT(level0, 100);  // both levels are seen
  EXPECT_GT(level1, 10);
}

// A mip map whose texels all hold one model renders like that model.
TEST(Render, UniformMipmapRendersLikeItsModel) {
  LafortuneModel model;
  model.params.diffuse = glm::dvec3(0.2, 0.3, 0.4);
  LafortuneLobe lobe;
  lobe.cx = lobe.cy = glm::dvec3(-0.8);
  lobe.cz = glm::dvec3(0.9);
  lobe.n = glm::dvec3(12.0);
  model.params.lobes = {lobe};
  std::vector<LafortuneTexelMap> levels;
  for (int size : {4, 2, 1}) {
    LafortuneTexelMap level;
    level.width = level.height = size;
    level.texels.assign(size_t(size) * size, model);
    levels.push_back(level);
  }
  const fs::path dir = TestDir();
  WriteParamMipmap(ToParamMipmap(levels, {}), (dir / "uniform.exr").string());
  const Material m = Material::Load((dir / "uniform.exr").string());
  const PreviewOptions o = Small();
  const PreviewImage textured = RenderCylinders(MipmapRho(m, 0.8), o);
  const PreviewImage plain = RenderCylinders(model, o);
  ASSERT_EQ(textured.pixels.size(), plain.pixels.size());
  double lit = 0.0;
  for (size_t k = 0; k < plain.pixels.size(); ++k) {
    for (int c = 0; c < 3; ++c) {
      // The mip map stores float parameters.
      EXPECT_NEAR(textured.pixels[k][c], plain.pixels[k][c],
                  1e-5 * (1.0 + plain.pixels[k][c]))
          << k;
    }
    lit += plain.pixels[k].x;
  }
  EXPECT_GT(lit, 1.0);
}

TEST(Render, SlabPanelsShowTheBackdropThroughThinAndHideItBehindThick) {
  const PreviewOptions o = Small();
  SlabParams thin;
  thin.tau = glm::dvec3(1e-9);
  thin.albedo = glm::dvec3(0.5);
  for (const glm::dvec3& v : RenderSlab(thin, o).pixels) {
    const bool checker = std::abs(v.x - kCheckerDark) < 1e-6 ||
                         std::abs(v.x - kCheckerLight) < 1e-6;
    EXPECT_TRUE(checker) << v.x;
  }
  // Thick and black: the back-lit panel is black where it covers the
  // backdrop, a 1.6 cos(tilt) x 1.6 rectangle of the 2.4 x 2.4 panel.
  SlabParams thick;
  thick.tau = glm::dvec3(50.0);
  thick.albedo = glm::dvec3(0.0);
  const PreviewImage image = RenderSlab(thick, o);
  int black = 0;
  for (int j = 0; j < o.size; ++j) {
    for (int i = o.size; i < 2 * o.size; ++i) {
      if (image.At(i, j).x < 1e-9) ++black;
    }
  }
  const double expected =
      1.6 * std::cos(Radians(o.tilt_deg)) * 1.6 / (2.4 * 2.4) * o.size * o.size;
  EXPECT_NEAR(black, expected, 2.0 * o.size);
}

TEST(Render, HolesPanelsLetTheBackdropThroughByTheirTransmittance) {
  PreviewOptions o = Small();
  o.tilt_deg = 30.0;
  // Lit from behind: the column tops (cos_i = 0) add no light.
  o.light = glm::dvec3(0.0, 0.0, -1.0);
  // Opaque and open columns alternating along x, h = 1: a panel tilted by t
  // about y sees the holes at the view offset (tan t, 0), so Algorithm 3.1
  // gives transparent = (1 - min(tan t, 1)) / 2 (half the texels open, a
  // wall of each open texel in the way of a fraction tan t of it).
  HolesModel model;
  model.params.thickness_texels = 1.0;
  model.tile = std::make_shared<const HolesTile>(HolesTileOf(
      AnalyzeMask(MaskFromRows({"#."}), false), HoleMethod::kAlgorithm31));
  const PreviewImage image = RenderHoles(model, o);
  ASSERT_EQ(image.width, 3 * o.size);
  const int centre = o.size / 2;
  for (int panel = 0; panel < 3; ++panel) {
    const glm::dvec3 v = image.At(panel * o.size + centre, centre);
    const glm::dvec2 p = PanelPoint(centre, centre, o.size);
    const double backdrop =
        (int(std::floor(p.x / 0.3)) + int(std::floor(p.y / 0.3))) % 2 == 0
            ? kCheckerLight
            : kCheckerDark;
    const double transparent =
        0.5 * (1.0 - std::min(std::tan(Radians(30.0 * panel)), 1.0));
    EXPECT_NEAR(v.x, backdrop * transparent, 1e-12);
  }
}

// Width, height and channel 0 of an image file.
std::vector<float> ReadImage(const std::string& path, int* w, int* h) {
  auto in = OIIO::ImageInput::open(path);
  EXPECT_TRUE(in) << path;
  if (!in) return {};
  *w = in->spec().width;
  *h = in->spec().height;
  std::vector<float> pixels(size_t(*w) * *h * in->spec().nchannels);
  in->read_image(0, 0, 0, in->spec().nchannels, OIIO::TypeDesc::FLOAT,
                 pixels.data());
  return pixels;
}

TEST(RenderCli, PresetAgainstPresetWritesExrAndPngOneRowEach) {
  const fs::path dir = TestDir();
  const RunResult r =
      RunClothfit(dir, {"render", "--preset", "polyester_satin_charmeuse",
                        "--compare-preset", "polyester_satin_charmeuse_back",
                        "--size", "16", "--out", (dir / "satin.exr").string()});
  ASSERT_EQ(r.status, 0) << Describe(r);
  int w = 0, h = 0;
  const std::vector<float> exr =
      ReadImage((dir / "satin.exr").string(), &w, &h);
  EXPECT_EQ(w, 48);
  EXPECT_EQ(h, 32);
  // The PNG: a label band above each of the two rows.
  int pw = 0, ph = 0;
  ReadImage((dir / "satin.png").string(), &pw, &ph);
  EXPECT_EQ(pw, 48);
  EXPECT_EQ(ph, 32 + 2 * kLabelBand);
  // The rows differ: front and back of the satin.
  double top = 0.0, bottom = 0.0;
  for (size_t i = 0; i < exr.size() / 2; ++i) top += exr[i];
  for (size_t i = exr.size() / 2; i < exr.size(); ++i) bottom += exr[i];
  EXPECT_GT(top, 0.0);
  EXPECT_GT(std::abs(top - bottom), 0.01 * top);
}

TEST(RenderCli, HolesFileNeedsAMaskAndRendersThreeTilts) {
  const fs::path dir = TestDir();
  WriteText(dir / "holes.json",
            R"({"model": "holes", "thickness_texels": 1.0})");
  Mask mask = MaskFromRows({"#..", "...", "..."});
  WriteMask(mask, (dir / "net.png").string());
  const RunResult r =
      RunClothfit(dir, {"render", "--params", (dir / "holes.json").string(),
                        "--mask", (dir / "net.png").string(), "--size", "16",
                        "--out", (dir / "h.exr").string()});
  ASSERT_EQ(r.status, 0) << Describe(r);
  int w = 0, h = 0;
  ReadImage((dir / "h.exr").string(), &w, &h);
  EXPECT_EQ(w, 48);
  ExpectBadInput(dir,
                 {"render", "--params", (dir / "holes.json").string(), "--out",
                  (dir / "x.exr").string()},
                 {"holes.json", "--mask"});
}

TEST(RenderCli, MipmapFileRendersTiledCylindersAndComparesWithAPreset) {
  const fs::path dir = TestDir();
  DiffuseMipmap(dir);
  const std::string map = (dir / "diffuse.exr").string();
  const RunResult r =
      RunClothfit(dir, {"render", "--params", map, "--compare-preset",
                        "linen_plain", "--tile", "0.5", "--size", "16", "--out",
                        (dir / "m.exr").string()});
  ASSERT_EQ(r.status, 0) << Describe(r);
  int w = 0, h = 0;
  const std::vector<float> exr = ReadImage((dir / "m.exr").string(), &w, &h);
  EXPECT_EQ(w, 48);
  EXPECT_EQ(h, 32);
  double top = 0.0;
  for (size_t i = 0; i < exr.size() / 2; ++i) top += exr[i];
  EXPECT_GT(top, 0.0);
  ExpectBadInput(dir,
                 {"render", "--params", map, "--tile", "0", "--out",
                  (dir / "x.exr").string()},
                 {"--tile"});
  WriteText(dir / "broken.exr", "not an OpenEXR file");
  ExpectBadInput(dir,
                 {"render", "--params", (dir / "broken.exr").string(), "--out",
                  (dir / "x.exr").string()},
                 {"broken.exr"});
}

// docs/models.md: a slab outside the single-scattering regime is rendered, with
// one note saying so; one within it gets none.
TEST(RenderCli, SlabOutsideTheRegimeIsRenderedWithANote) {
  const fs::path dir = TestDir();
  WriteText(dir / "in.json", R"({"model": "slab", "tau": 0.001, "albedo": 1})");
  WriteText(dir / "out.json",
            R"({"model": "slab", "tau": 0.01, "albedo": 0.8})");
  for (const char* name : {"in", "out"}) {
    const RunResult r = RunClothfit(
        dir, {"render", "--params",
              (dir / (std::string(name) + ".json")).string(), "--size", "8",
              "--out", (dir / (std::string(name) + ".exr")).string()});
    ASSERT_EQ(r.status, 0) << Describe(r);
    EXPECT_TRUE(fs::exists(dir / (std::string(name) + ".png")));
    if (std::string(name) == "in") {
      EXPECT_EQ(r.err, "");
    } else {
      EXPECT_EQ(r.err.rfind("note: ", 0), 0u) << r.err;
      EXPECT_NE(r.err.find("tau = 0.01"), std::string::npos) << r.err;
    }
  }
}

TEST(RenderCli, BadInputExitsTwoAndWritesNothing) {
  const fs::path dir = TestDir();
  const std::string out = (dir / "r.exr").string();
  WriteText(dir / "slab.json",
            R"({"model": "slab", "tau": 0.5, "albedo": [0.9, 0.8, 0.7]})");
  ExpectBadInput(
      dir, {"render", "--params", (dir / "none.json").string(), "--out", out},
      {"none.json"});
  ExpectBadInput(
      dir, {"render", "--preset", "linen_plain", "--size", "4", "--out", out},
      {"--size"});
  ExpectBadInput(
      dir,
      {"render", "--preset", "linen_plain", "--out", (dir / "r.png").string()},
      {"--out", ".exr"});
  ExpectBadInput(dir,
                 {"render", "--params", (dir / "slab.json").string(),
                  "--compare-preset", "linen_plain", "--out", out},
                 {"side by side"});
  ExpectBadInput(dir, {"render", "--preset", "nope", "--out", out}, {"nope"});
}

}  // namespace
}  // namespace clothfit
