// The GLSL export (export/glsl.h, export/glsl/*.glsl: the one second copy of
// the models' formulas) evaluated on the GPU path of a real browser: headless
// Chromium runs each exported model as a WebGL 2 fragment shader over 1,500
// direction pairs (web/eval_glsl.html) and reads the float values back; they
// match the C++ model (Material, double) within 1e-4 relative to the larger
// of the value and a thousandth of the model's largest value over the pairs.
#include <gtest/gtest.h>

#include <fstream>
#include <memory>
#include <random>
#include <string>
#include <vector>

#include "api/material.h"
#include "holes/hole_texture.h"
#include "io/lafortune_mipmap.h"
#include "io/param_mipmap.h"
#include "io/params_json.h"
#include "models/bounded.h"
#include "tests/browser_test_util.h"
#include "tests/cli_test_util.h"
#include "tests/direction_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using testing_util::Dir;
using testing_util::Preset;

enum class Domain { kUpper, kSphere, kOpposite };

struct Job {
  std::string name;
  ModelParams model;
  Domain domain;
  std::string fn = "f";  // f | direct
};

// 1,500 pairs: uniform on the domain's sides, a tenth of them with one
// direction at 89.9 degrees; rounded to float (what the GPU reads).
std::vector<glm::vec3> Pairs(Domain domain, uint64_t seed) {
  std::mt19937_64 rng(seed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  auto direction = [&](bool upper, bool grazing) {
    const double theta = grazing ? 89.9 : Degrees(std::acos(u(rng)));
    glm::dvec3 w = Dir(theta, 360.0 * u(rng));
    if (!upper) w.z = -w.z;
    return glm::vec3(w);
  };
  std::vector<glm::vec3> out;
  for (int k = 0; k < 1500; ++k) {
    const bool grazing = k % 10 == 0;
    const bool wi_up = domain == Domain::kUpper || u(rng) < 0.5;
    const bool wo_up =
        domain == Domain::kUpper
            ? true
            : (domain == Domain::kOpposite ? !wi_up : u(rng) < 0.5);
    out.push_back(direction(wi_up, grazing && k % 20 == 0));
    out.push_back(direction(wo_up, grazing && k % 20 != 0));
  }
  return out;
}

// TiltedLafortune with a lookup table of 6 views.
LafortuneModel TiltedLafortuneWithTable() {
  LafortuneModel m = testing_util::TiltedLafortune();
  for (int k = 0; k < 6; ++k) {
    m.lut.views.push_back(Dir(10.0 + 14.0 * k, 60.0 * k));
    m.lut.color.push_back(glm::dvec3(0.8 + 0.05 * k, 1.0, 1.1 - 0.04 * k));
    m.lut.alpha.push_back(1.0);
  }
  return m;
}

// A holed layer of thickness 1.3 over an 8 x 8 mask, with the tile of
// `level` (1: 4 x 4 texels) evaluated by `method`.
HolesModel HolesWithTile(HoleMethod method, int level) {
  const Mask mask =
      MaskFromRows({"##..#.#.", "#...#..#", "........", "###.##.#", "#.#.#..#",
                    "...#...#", "#....#..", "##.#.##."});
  HolesModel model;
  model.params.thickness_texels = 1.3;
  model.params.wall_color = glm::dvec3(0.1, 0.3, 0.5);
  model.tile = std::make_shared<const HolesTile>(HolesTileOf(
      AnalyzeMask(mask, method == HoleMethod::kExtension), method, level));
  return model;
}

// web/eval_glsl.html's DOM after it ran the jobs of `manifest` (JSON) on
// the files in `dir`.
std::string RunJobs(const fs::path& dir, const std::string& manifest) {
  testing_util::WriteText(dir / "jobs.json", manifest);
  testing_util::ServeWebPage(dir, "eval_glsl.html");
  const testing_util::LocalServer server(dir);
  EXPECT_GT(server.port(), 0);
  return testing_util::DumpDom(server.Url("eval_glsl.html?manifest=jobs.json"),
                               dir);
}

TEST(GlslBrowser, EveryExportedModelMatchesTheCppModelOnTheGpu) {
  if (!testing_util::BrowserAvailable()) {
    GTEST_SKIP() << "no browser: /usr/bin/chromium is not installed "
                    "(scripts/setup.sh installs Debian's chromium)";
  }
  ThreadParams thread;
  thread.albedo = glm::dvec3(0.3, 0.5, 0.7);
  ClothParams turned = Preset("linen_plain");
  turned.rotation_deg = 30.0;
  turned.threads[0].offsets_deg = {-25.0, 0.0, 25.0};
  turned.diffuse = glm::dvec3(0.05, 0.1, 0.02);
  turned.scale = 0.8;
  SlabParams slab;
  slab.tau = glm::dvec3(0.3, 0.5, 0.8);
  slab.albedo = glm::dvec3(0.9, 0.8, 0.6);
  SlabParams thin = slab;
  thin.tau = glm::dvec3(0.01, 0.002, 0.05);
  std::vector<Job> jobs = {
      {"thread", thread, Domain::kSphere},
      {"linen", Preset("linen_plain"), Domain::kUpper},
      {"satin", Preset("polyester_satin_charmeuse"), Domain::kUpper},
      {"velvet", Preset("velvet"), Domain::kUpper},
      {"turned_linen", turned, Domain::kUpper},
      {"lafortune", TiltedLafortuneWithTable(), Domain::kUpper},
      {"slab", slab, Domain::kSphere},
      {"thin_slab", thin, Domain::kOpposite},
      {"slab_direct", slab, Domain::kSphere, "direct"},
      {"holes", HolesWithTile(HoleMethod::kExtension, kTopLevel),
       Domain::kSphere, "transmittance"},
      {"holes_level1", HolesWithTile(HoleMethod::kAlgorithm31, 1),
       Domain::kSphere, "transmittance"}};
  // Thread and cloth with their energy bounds (export/glsl/energy_bound.glsl),
  // as the command line reads them.
  for (Job& job : jobs) job.model = WithEnergyBound(job.model);

  const fs::path dir = testing_util::FreshTestDir("glsl_browser_");
  std::string manifest = "[";
  std::vector<std::vector<glm::vec3>> pairs;
  for (size_t j = 0; j < jobs.size(); ++j) {
    const Job& job = jobs[j];
    const std::string params = (dir / (job.name + ".json")).string();
    WriteParamFile(ParamFile(job.model), params);
    const testing_util::RunResult r = testing_util::RunClothfit(
        dir, {"export", "--format", "glsl", "--params", params, "--out",
              (dir / (job.name + ".glsl")).string()});
    ASSERT_EQ(r.status, 0) << testing_util::Describe(r);
    pairs.push_back(Pairs(job.domain, 100 + j));
    std::ofstream(dir / (job.name + ".dirs"), std::ios::binary)
        .write(reinterpret_cast<const char*>(pairs.back().data()),
               pairs.back().size() * sizeof(glm::vec3));
    manifest += std::string(j ? "," : "") + "{\"glsl\": \"" + job.name +
                ".glsl\", \"dirs\": \"" + job.name + ".dirs\", \"fn\": \"" +
                job.fn + "\"}";
  }
  const std::string dom = RunJobs(dir, manifest + "]");
  ASSERT_EQ(testing_util::PreText(dom, "done"), "DONE") << dom.substr(0, 500);

  for (size_t j = 0; j < jobs.size(); ++j) {
    const Job& job = jobs[j];
    const std::vector<float> gpu = testing_util::FloatsOf(
        testing_util::PreText(dom, "out" + std::to_string(j)));
    const size_t n = pairs[j].size() / 2;
    ASSERT_EQ(gpu.size(), 3 * n) << job.name;
    // F for the BSDF jobs (a holes model's F is 0: it has none).
    const Material m = Material::FromParams(
        job.fn == "f" ? job.model : ModelParams(SlabParams()));
    std::vector<glm::dvec3> ref(n);
    double peak = 0.0;
    for (size_t k = 0; k < n; ++k) {
      const glm::dvec3 wi(pairs[j][2 * k]), wo(pairs[j][2 * k + 1]);
      if (job.fn == "direct") {
        ref[k] = SlabDirectTransmittance(std::get<SlabParams>(job.model), wo);
      } else if (job.fn == "transmittance") {
        ref[k] = Transmittance(std::get<HolesModel>(job.model), wo);
      } else {
        ref[k] = m.F(wi, wo);
      }
      for (int c = 0; c < 3; ++c) peak = std::max(peak, std::abs(ref[k][c]));
    }
    ASSERT_GT(peak, 0.0) << job.name;
    double worst = 0.0;
    size_t worst_k = 0;
    for (size_t k = 0; k < n; ++k) {
      for (int c = 0; c < 3; ++c) {
        const double e = std::abs(gpu[3 * k + c] - ref[k][c]) /
                         std::max(std::abs(ref[k][c]), 1e-3 * peak);
        if (!(e <= worst)) {
          worst = e;
          worst_k = k;
        }
      }
    }
    std::printf("%-12s largest relative difference %.3g over %zu pairs\n",
                job.name.c_str(), worst, n);
    EXPECT_LT(worst, 1e-4) << job.name << " at pair " << worst_k << ": gpu ("
                           << gpu[3 * worst_k] << ", " << gpu[3 * worst_k + 1]
                           << ", " << gpu[3 * worst_k + 2] << ") C++ ("
                           << ref[worst_k].x << ", " << ref[worst_k].y << ", "
                           << ref[worst_k].z << ")";
  }
}

// A Lafortune texture map (2 x 2 texels over 1 x 1, tilted texels with two
// lobes and a 4-view lookup table) exported with each filter and evaluated
// on the GPU at random (s, t, lod): the values of Material::Load(map,
// filter).
TEST(GlslBrowser, TextureMapsMatchTheFilteredMaterialOnTheGpu) {
  if (!testing_util::BrowserAvailable()) {
    GTEST_SKIP() << "no browser: /usr/bin/chromium is not installed "
                    "(scripts/setup.sh installs Debian's chromium)";
  }
  const fs::path dir = testing_util::FreshTestDir("glsl_browser_");
  std::vector<glm::dvec3> views;
  for (int k = 0; k < 4; ++k) views.push_back(Dir(15.0 + 20.0 * k, 90.0 * k));
  LafortuneTexelMap base, top;
  base.width = base.height = 2;
  for (int i = 0; i < 4; ++i) {
    LafortuneModel m = testing_util::TiltedLafortune();
    m.normal =
        glm::normalize(glm::dvec3(0.3 * (i % 2) - 0.1, 0.2 * (i / 2), 1));
    m.params.lobes[0].n *= 0.5 + 0.5 * i;
    m.params.diffuse *= 1.0 + i;
    m.lut.views = views;
    for (int k = 0; k < 4; ++k) {
      m.lut.color.push_back(glm::dvec3(0.8 + 0.1 * k, 1.0 - 0.05 * i, 1.0));
      m.lut.alpha.push_back(1.0);
    }
    base.texels.push_back(m);
  }
  top.width = top.height = 1;
  LafortuneModel t = base.texels[1];
  t.params.lobes.resize(1);  // fewer lobes than level 0
  top.texels.push_back(t);
  const std::string path = (dir / "map.exr").string();
  WriteParamMipmap(ToParamMipmap({base, top}, views), path);

  std::mt19937_64 rng(5);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  const std::vector<glm::vec3> pairs = Pairs(Domain::kUpper, 77);
  std::vector<glm::vec3> uv;
  for (size_t k = 0; k < pairs.size() / 2; ++k) {
    uv.push_back(glm::vec3(u(rng), u(rng), 1.2 * u(rng)));
  }
  std::ofstream(dir / "map.dirs", std::ios::binary)
      .write(reinterpret_cast<const char*>(pairs.data()),
             pairs.size() * sizeof(glm::vec3));
  std::ofstream(dir / "map.uv", std::ios::binary)
      .write(reinterpret_cast<const char*>(uv.data()),
             uv.size() * sizeof(glm::vec3));
  const std::vector<std::pair<std::string, TexelFilter>> filters = {
      {"nearest", TexelFilter::kNearest},
      {"bilinear", TexelFilter::kBilinear},
      {"trilinear", TexelFilter::kTrilinear}};
  std::string manifest = "[";
  for (size_t j = 0; j < filters.size(); ++j) {
    const std::string name = "map_" + filters[j].first;
    const testing_util::RunResult r = testing_util::RunClothfit(
        dir, {"export", "--format", "glsl", "--params", path, "--filter",
              filters[j].first, "--out", (dir / (name + ".glsl")).string()});
    ASSERT_EQ(r.status, 0) << testing_util::Describe(r);
    ASSERT_TRUE(fs::exists(dir / (name + ".params.bin")));
    manifest += std::string(j ? "," : "") + "{\"glsl\": \"" + name +
                ".glsl\", \"dirs\": \"map.dirs\", \"fn\": \"map\", "
                "\"params\": \"" +
                name +
                ".params.bin\", \"layers\": " + std::to_string(2 + 4 * 2 + 4) +
                ", \"sizes\": [[2, 2], [1, 1]], \"uv\": \"map.uv\"}";
  }
  const std::string dom = RunJobs(dir, manifest + "]");
  ASSERT_EQ(testing_util::PreText(dom, "done"), "DONE") << dom.substr(0, 500);
  for (size_t j = 0; j < filters.size(); ++j) {
    const std::vector<float> gpu = testing_util::FloatsOf(
        testing_util::PreText(dom, "out" + std::to_string(j)));
    const size_t n = pairs.size() / 2;
    ASSERT_EQ(gpu.size(), 3 * n) << filters[j].first;
    const Material m = Material::Load(path, filters[j].second);
    std::vector<glm::dvec3> ref(n);
    double peak = 0.0;
    for (size_t k = 0; k < n; ++k) {
      ref[k] = m.F(glm::dvec3(pairs[2 * k]), glm::dvec3(pairs[2 * k + 1]),
                   uv[k].x, uv[k].y, uv[k].z);
      for (int c = 0; c < 3; ++c) peak = std::max(peak, std::abs(ref[k][c]));
    }
    double worst = 0.0;
    for (size_t k = 0; k < n; ++k) {
      for (int c = 0; c < 3; ++c) {
        worst = std::max(worst, std::abs(gpu[3 * k + c] - ref[k][c]) /
                                    std::max(std::abs(ref[k][c]), 1e-3 * peak));
      }
    }
    std::printf("map, %-9s largest relative difference %.3g over %zu pairs\n",
                filters[j].first.c_str(), worst, n);
    EXPECT_LT(worst, 1e-4) << filters[j].first;
  }
}

}  // namespace
}  // namespace clothfit
