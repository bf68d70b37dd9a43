// The renderer API (api/material.h): every kind of parameter file, the
// parameter mip map's texel and level selection, errors at load time, no
// allocation and concurrent evaluation.
#include "api/material.h"

#include <gtest/gtest.h>

#include <algorithm>
#include <atomic>
#include <cstdlib>
#include <new>
#include <thread>
#include <vector>

#include "fitting/lafortune_mip.h"
#include "io/param_mipmap.h"
#include "io/params_json.h"
#include "models/presets.h"
#include "tests/direction_util.h"
#include "tests/io_test_util.h"

// Counts every allocation of the test program (global operator new).
namespace {
std::atomic<long> g_allocations{0};
}  // namespace
void* operator new(std::size_t size) {
  ++g_allocations;
  if (void* p = std::malloc(size == 0 ? 1 : size)) return p;
  throw std::bad_alloc();
}
// GCC sees free() on memory from operator new and warns, not knowing that
// this operator new is malloc().
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmismatched-new-delete"
void operator delete(void* p) noexcept { std::free(p); }
void operator delete(void* p, std::size_t) noexcept { std::free(p); }
#pragma GCC diagnostic pop

namespace clothfit {
namespace {

using testing_util::Dir;
using testing_util::ErrorOf;
using testing_util::ExpectHas;
using testing_util::FreshTestDir;

const std::vector<std::pair<glm::dvec3, glm::dvec3>>& Pairs() {
  static const std::vector<std::pair<glm::dvec3, glm::dvec3>> kPairs = {
      {Dir(30, 10), Dir(40, 200)},
      {Dir(70, -40), Dir(20, 60)},
      {Dir(5, 0), Dir(85, 180)},
      {Dir(45, 90), Dir(45, 270)}};
  return kPairs;
}

ModelParams Satin() {
  ClothParams c;
  EXPECT_TRUE(GetPreset("polyester_satin_charmeuse", &c));
  return c;
}

std::vector<ModelParams> EveryModel() {
  ThreadParams thread;
  thread.albedo = {0.3, 0.5, 0.7};
  LafortuneModel lafortune;
  lafortune.params.lobes.push_back(LafortuneLobe());
  SlabParams slab;
  slab.tau = glm::dvec3(0.4);
  slab.albedo = {0.9, 0.8, 0.7};
  return {thread, Satin(), lafortune, slab};
}

TEST(Material, EveryParameterFileEvaluatesAsTheModel) {
  const auto dir = FreshTestDir("material_");
  for (const ModelParams& params : EveryModel()) {
    const std::string path =
        (dir / (std::string(ModelName(params)) + ".json")).string();
    WriteParamFile(ParamFile{params, ""}, path);
    const Material m = Material::Load(path);
    EXPECT_EQ(m.Kind(), ModelName(params));
    EXPECT_EQ(m.Levels(), 1);
    for (const auto& [wi, wo] : Pairs()) {
      const glm::dvec3 rho =
          Evaluate(params, wi, wo, Quantity::kCosineWeighted);
      const glm::dvec3 f = Evaluate(params, wi, wo, Quantity::kBrdf);
      for (int c = 0; c < 3; ++c) {
        EXPECT_NEAR(m.Rho(wi, wo)[c], rho[c], 1e-12 * std::abs(rho[c]));
        EXPECT_NEAR(m.F(wi, wo)[c], f[c], 1e-12 * std::abs(f[c]));
        // f = rho / cos(theta_i) (docs/formats.md).
        EXPECT_NEAR(m.F(wi, wo)[c] * wi.z, m.Rho(wi, wo)[c],
                    1e-12 * std::abs(rho[c]));
      }
    }
  }
}

// A parameter file's scale (what --fit-scale found) reaches the renderer.
TEST(Material, ScaleOfThreadAndClothFilesMultipliesTheModel) {
  ClothParams cloth;
  ASSERT_TRUE(GetPreset("linen_plain", &cloth));
  ClothParams scaled_cloth = cloth;
  scaled_cloth.scale = 0.25;
  ThreadParams thread = cloth.threads[0].params;
  ThreadParams scaled_thread = thread;
  scaled_thread.scale = 0.25;
  const auto dir = FreshTestDir("material_scale_");
  const std::vector<std::pair<ModelParams, ModelParams>> cases = {
      {cloth, scaled_cloth}, {thread, scaled_thread}};
  for (size_t k = 0; k < cases.size(); ++k) {
    const std::string path =
        (dir / ("scaled" + std::to_string(k) + ".json")).string();
    WriteParamFile(ParamFile{cases[k].second, ""}, path);
    const Material m = Material::Load(path);
    const glm::dvec3 wi = glm::normalize(glm::dvec3(0.3, 0.1, 0.9));
    const glm::dvec3 wo = glm::normalize(glm::dvec3(-0.4, 0.2, 0.8));
    const glm::dvec3 want =
        0.25 * Evaluate(cases[k].first, wi, wo, Quantity::kBrdf);
    const glm::dvec3 got = m.F(wi, wo);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(got[c], want[c], 1e-12 * (1.0 + want[c])) << k;
    }
    EXPECT_GT(want.x, 0.0);
  }
}

TEST(Material, SlabTransmitsThroughTheOtherSide) {
  SlabParams slab;
  slab.tau = glm::dvec3(0.4);
  slab.albedo = {0.9, 0.8, 0.7};
  const Material m = Material::FromParams(slab);
  const glm::dvec3 wi = Dir(30, 0);
  const glm::dvec3 below = -Dir(20, 0);
  EXPECT_GT(m.F(wi, below).x, 0.0);
  // A cloth patch reflects only.
  EXPECT_EQ(Material::FromParams(Satin()).F(wi, below), glm::dvec3(0.0));
}

// A 2 x 2 level of diffuse-only texels (rho = diffuse * wi.z) and its
// 1 x 1 level.
LafortuneMipResult DiffuseMip() {
  LafortuneMipResult r;
  LafortuneLevel base;
  base.width = base.height = 2;
  for (int i = 0; i < 4; ++i) {
    LafortuneFitResult t;
    t.params.params.diffuse = glm::dvec3(0.1 * (i + 1), 0.05, 0.5);
    base.texels.push_back(t);
  }
  LafortuneLevel top;
  top.width = top.height = 1;
  LafortuneFitResult t;
  t.params.params.diffuse = glm::dvec3(0.25, 0.05, 0.5);
  top.texels.push_back(t);
  r.levels = {base, top};
  return r;
}

// The EXR alone is a material (its index is in its header), under any
// case of its extension: "G16.EXR" was read as JSON ("invalid JSON").
TEST(Material, MipmapLoadsAloneAndWithAnUpperCaseExtension) {
  const auto dir = FreshTestDir("material_");
  const std::string path = (dir / "G16.EXR").string();
  WriteParamMipmap(ToParamMipmap(DiffuseMip()), path);
  std::filesystem::remove(path + ".json");
  const Material m = Material::Load(path);
  EXPECT_EQ(m.Kind(), "lafortune_mipmap");
  EXPECT_EQ(m.Levels(), 2);
}

TEST(Material, MipmapPicksTheNearestTexelOfTheLevel) {
  const auto dir = FreshTestDir("material_");
  const std::string path = (dir / "diffuse.exr").string();
  WriteParamMipmap(ToParamMipmap(DiffuseMip()), path);
  const Material m = Material::Load(path);
  EXPECT_EQ(m.Kind(), "lafortune_mipmap");
  ASSERT_EQ(m.Levels(), 2);
  EXPECT_EQ(m.Width(0), 2);
  EXPECT_EQ(m.Height(1), 1);
  const glm::dvec3 wi = Dir(40, 30), wo = Dir(10, 200);
  // (s, t) in [0, 1]^2: texel (x, y) = (floor(2 s), floor(2 t)), clamped.
  struct Case {
    double s, t;
    int level;
    double diffuse_r;
  };
  for (const Case& c :
       {Case{0.1, 0.1, 0, 0.1}, Case{0.9, 0.1, 0, 0.2}, Case{0.1, 0.9, 0, 0.3},
        Case{0.9, 0.9, 0, 0.4}, Case{1.0, 1.0, 0, 0.4}, Case{-3.0, 0.2, 0, 0.1},
        Case{0.9, 0.9, 1, 0.25}, Case{0.9, 0.9, 7, 0.25},
        Case{0.9, 0.9, -1, 0.4}}) {
    EXPECT_NEAR(m.Rho(wi, wo, c.s, c.t, c.level).x, c.diffuse_r * wi.z, 1e-7)
        << c.s << "," << c.t << " level " << c.level;
    EXPECT_NEAR(m.F(wi, wo, c.s, c.t, c.level).x, c.diffuse_r, 1e-7);
  }
}

// Bilinear: texel centres at (x + 0.5) / 2, clamped at the edges;
// trilinear: bilinear on two levels, blended by the fraction of lod; the
// level itself is the nearest one otherwise.
TEST(Material, MipmapFiltersBilinearlyAndTrilinearly) {
  const auto dir = FreshTestDir("material_");
  const std::string path = (dir / "diffuse.exr").string();
  WriteParamMipmap(ToParamMipmap(DiffuseMip()), path);
  const Material bilinear = Material::Load(path, TexelFilter::kBilinear);
  const Material trilinear = Material::Load(path, TexelFilter::kTrilinear);
  const Material nearest = Material::Load(path);
  EXPECT_EQ(bilinear.Filter(), TexelFilter::kBilinear);
  const glm::dvec3 wi = Dir(40, 30), wo = Dir(10, 200);
  struct Case {
    const Material* m;
    double s, t, lod, diffuse_r;
  };
  for (const Case& c :
       {Case{&bilinear, 0.25, 0.25, 0, 0.1},
        Case{&bilinear, 0.75, 0.75, 0, 0.4},
        Case{&bilinear, 0.5, 0.25, 0, 0.15}, Case{&bilinear, 0.25, 0.5, 0, 0.2},
        Case{&bilinear, 0.5, 0.5, 0, 0.25},
        Case{&bilinear, 0.375, 0.25, 0, 0.125},
        Case{&bilinear, 0.0, 0.0, 0, 0.1}, Case{&bilinear, 1.0, -2.0, 0, 0.2},
        Case{&bilinear, 0.5, 0.25, 0.4, 0.15},
        Case{&bilinear, 0.5, 0.25, 0.6, 0.25},
        Case{&trilinear, 0.5, 0.25, 0.5, 0.2},
        Case{&trilinear, 0.5, 0.25, 0.25, 0.175},
        Case{&trilinear, 0.5, 0.25, 1.7, 0.25},
        Case{&trilinear, 0.5, 0.25, -1.0, 0.15},
        Case{&nearest, 0.9, 0.9, 0.4, 0.4},
        Case{&nearest, 0.9, 0.9, 0.6, 0.25}}) {
    EXPECT_NEAR(c.m->F(wi, wo, c.s, c.t, c.lod).x, c.diffuse_r, 1e-7)
        << c.s << "," << c.t << " lod " << c.lod;
    EXPECT_NEAR(c.m->Rho(wi, wo, c.s, c.t, c.lod).x, c.diffuse_r * wi.z, 1e-7);
  }
}

TEST(Material, LevelReaderMatchesTheTexelReaderAndNamesMissingChannels) {
  LafortuneMipResult r = DiffuseMip();
  r.views = {glm::dvec3(0, 0, 1), glm::normalize(glm::dvec3(1, 0, 1))};
  for (LafortuneLevel& level : r.levels) {
    for (size_t i = 0; i < level.texels.size(); ++i) {
      LafortuneModel& m = level.texels[i].params;
      m.params.lobes.assign(i % 3, LafortuneLobe());
      if (!m.params.lobes.empty()) m.params.lobes[0].n = glm::dvec3(i + 2.0);
      m.lut.views = r.views;
      m.lut.color = {glm::dvec3(1.0), glm::dvec3(0.5 + 0.1 * i)};
      m.lut.alpha = {1.0, 0.5};
    }
  }
  ParamMipmap mipmap = ToParamMipmap(r);
  for (int l = 0; l < 2; ++l) {
    const std::vector<LafortuneModel> level = LevelFromParamMipmap(mipmap, l);
    const ParamImage& image = mipmap.levels[l];
    ASSERT_EQ(level.size(), size_t(image.width) * image.height);
    for (int y = 0; y < image.height; ++y) {
      for (int x = 0; x < image.width; ++x) {
        const LafortuneModel a = TexelFromParamMipmap(mipmap, l, x, y);
        const LafortuneModel& b = level[size_t(y) * image.width + x];
        ASSERT_EQ(a.params.lobes.size(), b.params.lobes.size());
        for (size_t k = 0; k < a.params.lobes.size(); ++k) {
          EXPECT_EQ(a.params.lobes[k].n, b.params.lobes[k].n);
          EXPECT_EQ(a.params.lobes[k].cx, b.params.lobes[k].cx);
        }
        EXPECT_EQ(a.params.diffuse, b.params.diffuse);
        EXPECT_EQ(a.lut.color, b.lut.color);
        EXPECT_EQ(a.lut.alpha, b.lut.alpha);
        EXPECT_EQ(a.lut.views, b.lut.views);
      }
    }
  }
  EXPECT_EQ(LevelFromParamMipmap(mipmap, 0)[2].params.lobes.size(), 2u);
  // A texel with two lobes in a map that lost lobe 1's N.G channel.
  const auto it =
      std::find(mipmap.channels.begin(), mipmap.channels.end(), "lobe1.N.G");
  ASSERT_NE(it, mipmap.channels.end());
  *it = "renamed";
  ExpectHas(ErrorOf([&] { LevelFromParamMipmap(mipmap, 0); }),
            {"no channel 'lobe1.N.G'"});
}

TEST(Material, LoadErrorsNameTheFileAndTheProblem) {
  const auto dir = FreshTestDir("material_");
  const std::string missing = (dir / "missing.json").string();
  ExpectHas(ErrorOf([&] { Material::Load(missing); }), {missing});
  ExpectHas(ErrorOf([&] { Material::Load((dir / "none.exr").string()); }),
            {"none.exr"});
  ThreadParams bad;
  bad.eta = -1.0;
  ExpectHas(ErrorOf([&] { Material::FromParams(bad); }), {"eta"});
}

// Evaluation and sampling, filtered too.
TEST(Material, EvaluationDoesNotAllocate) {
  const auto dir = FreshTestDir("material_");
  const std::string path = (dir / "diffuse.exr").string();
  WriteParamMipmap(ToParamMipmap(DiffuseMip()), path);
  const long load_start = g_allocations.load();
  std::vector<Material> materials = {
      Material::Load(path), Material::Load(path, TexelFilter::kTrilinear)};
  EXPECT_GT(g_allocations.load() - load_start, 0);  // the counter counts
  for (const ModelParams& p : EveryModel()) {
    materials.push_back(Material::FromParams(p));
  }
  glm::dvec3 sum(0.0);
  const auto& pairs = Pairs();  // a static built on first use: before
  const long before = g_allocations.load();
  for (const Material& m : materials) {
    for (const auto& [wi, wo] : pairs) {
      sum += m.F(wi, wo, 0.7, 0.2, 0) + m.Rho(wi, wo, 0.3, 0.6, 1);
      const BsdfSampleT<double> b = m.Sample(wo, 0.3, 0.7, 0.4, 0.5, 0.5);
      sum += b.weight * m.Pdf(wo, wi, 0.4, 0.5, 0.5);
    }
  }
  EXPECT_EQ(g_allocations.load() - before, 0);
  EXPECT_GT(sum.x, 0.0);
}

TEST(Material, ConcurrentEvaluationMatchesSerial) {
  const Material m = Material::FromParams(Satin());
  std::vector<glm::dvec3> dirs;
  for (int i = 0; i < 64; ++i) dirs.push_back(Dir(i * 1.4, i * 37.0));
  std::vector<glm::dvec3> serial;
  for (const glm::dvec3& wi : dirs) {
    for (const glm::dvec3& wo : dirs) serial.push_back(m.F(wi, wo));
  }
  constexpr int kThreads = 4;
  std::vector<std::vector<glm::dvec3>> out(kThreads);
  std::vector<std::thread> pool;
  for (int k = 0; k < kThreads; ++k) {
    pool.emplace_back([&, k] {
      for (const glm::dvec3& wi : dirs) {
        for (const glm::dvec3& wo : dirs) out[k].push_back(m.F(wi, wo));
      }
    });
  }
  for (std::thread& t : pool) t.join();
  for (const auto& o : out) EXPECT_EQ(o, serial);
}

}  // namespace
}  // namespace clothfit
