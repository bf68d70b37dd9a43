// Importance sampling through the renderer API (api/material.h Sample and
// Pdf) for every model, in double and float, validated as Mitsuba and pbrt
// validate BSDFs: Pearson's chi-square of the sampled directions against
// the pdf integrated over equal-area bins of the sphere, at several views
// (5 per model, up to 89.5 degrees); the pdf integrates to the share of
// non-delta samples; each sample's pdf is Pdf at its direction and its weight
// is rho / pdf, finite; the mean weight is the directional albedo that
// quadrature of Rho gives; samples stay on the sides F covers. Texture maps
// are sampled with bilinear and trilinear filtering.
#include <gtest/gtest.h>

#include <memory>
#include <random>
#include <string>
#include <vector>

#include "api/material.h"
#include "holes/hole_texture.h"
#include "io/lafortune_mipmap.h"
#include "io/param_mipmap.h"
#include "io/params_json.h"
#include "models/presets.h"
#include "tests/direction_util.h"
#include "tests/io_test_util.h"
#include "tests/sampling_test_util.h"

namespace clothfit {
namespace {

using testing_util::Dir;
using testing_util::Preset;
using testing_util::TiltedLafortune;

using testing_util::BinIntegrals;
using testing_util::Pearson;
using testing_util::SphereBin;

// A linen turned by 30 degrees with a flat tangent sample and a diffuse
// term (every optional freedom of the cloth model).
ClothParams TurnedLinen() {
  ClothParams c = Preset("linen_plain");
  c.rotation_deg = 30.0;
  c.threads[0].offsets_deg = {-25.0, 0.0, 25.0};
  c.diffuse = glm::dvec3(0.05, 0.1, 0.02);
  return c;
}

SlabParams Slab() {
  SlabParams s;
  s.tau = glm::dvec3(0.3, 0.5, 0.8);
  s.albedo = glm::dvec3(0.9, 0.8, 0.6);
  return s;
}

struct Lookup {
  double s = 0.0, t = 0.0, lod = 0.0;
};

// Which sides F covers: the upper hemisphere (reflection), or the whole
// sphere (a thread; a slab reflects and transmits).
enum class Domain { kUpper, kSphere };

// The checks of the file comment for one material and view.
template <typename Real>
void CheckSampler(const MaterialT<Real>& m, const glm::dvec3& wo_d,
                  const Lookup& at, Domain domain, const std::string& name,
                  int quadrature = 8) {
  using Vec = glm::vec<3, Real>;
  const Vec wo(wo_d);
  const double tolerance = std::is_same_v<Real, float> ? 2e-4 : 1e-9;
  SCOPED_TRACE(name + " wo (" + std::to_string(wo_d.x) + ", " +
               std::to_string(wo_d.y) + ", " + std::to_string(wo_d.z) + ")");
  const std::vector<double> p = BinIntegrals(
      [&](const glm::dvec3& w) {
        return double(m.Pdf(wo, Vec(w), Real(at.s), Real(at.t), Real(at.lod)));
      },
      quadrature);
  double continuous = 0.0;
  for (double x : p) continuous += x;
  // Quadrature of the directional albedo over the same grid.
  const std::vector<double> albedo_bins = BinIntegrals(
      [&](const glm::dvec3& w) {
        return double(
            m.Rho(Vec(w), wo, Real(at.s), Real(at.t), Real(at.lod)).y);
      },
      quadrature);
  double albedo = 0.0;
  for (double x : albedo_bins) albedo += x;

  constexpr int kSamples = 200000;
  std::vector<double> counts(p.size() + 1, 0.0);  // the last: delta samples
  std::mt19937_64 rng(23);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  double weight_sum = 0.0, weight_squares = 0.0, delta_probability = 0.0;
  for (int i = 0; i < kSamples; ++i) {
    const BsdfSampleT<Real> b = m.Sample(wo, Real(u(rng)), Real(u(rng)),
                                         Real(at.s), Real(at.t), Real(at.lod));
    ASSERT_TRUE(std::isfinite(b.pdf) && b.pdf > Real(0)) << b.pdf;
    for (int c = 0; c < 3; ++c) ASSERT_TRUE(std::isfinite(b.weight[c]));
    ASSERT_NEAR(glm::length(glm::dvec3(b.wi)), 1.0, 10 * tolerance);
    if (b.delta) {
      ASSERT_EQ(glm::dvec3(b.wi), -glm::dvec3(wo));
      delta_probability = b.pdf;
      counts.back() += 1.0;
      continue;
    }
    if (domain == Domain::kUpper) {
      ASSERT_GE(b.wi.z, Real(0));
    }
    const Real pdf = m.Pdf(wo, b.wi, Real(at.s), Real(at.t), Real(at.lod));
    ASSERT_NEAR(b.pdf, pdf, tolerance * pdf);
    const Vec rho = m.Rho(b.wi, wo, Real(at.s), Real(at.t), Real(at.lod));
    for (int c = 0; c < 3; ++c) {
      ASSERT_NEAR(b.weight[c], rho[c] / pdf, tolerance * rho[c] / pdf + 1e-30);
    }
    weight_sum += b.weight.y;
    weight_squares += double(b.weight.y) * b.weight.y;
    counts[SphereBin(glm::dvec3(b.wi))] += 1.0;
  }
  // The pdf integrates to the share of samples that are not the delta.
  EXPECT_NEAR(continuous, 1.0 - delta_probability, 3e-3);
  std::vector<double> expected = p;
  expected.push_back(delta_probability);
  const testing_util::ChiSquare chi = Pearson(counts, expected, kSamples);
  EXPECT_TRUE(chi.Passes())
      << "chi2 " << chi.statistic << " (critical " << chi.critical << ") with "
      << chi.dof << " dof, " << chi.stray << " samples where the pdf is ~0";
  // The estimator's mean is the albedo: within 5 standard errors plus the
  // quadrature's error (1 %).
  const double mean = weight_sum / kSamples;
  const double se = std::sqrt(
      std::max(weight_squares / kSamples - mean * mean, 0.0) / kSamples);
  EXPECT_NEAR(mean, albedo, 5.0 * se + 0.01 * albedo + 1e-9) << "albedo";
}

const glm::dvec3 kViews[] = {Dir(0, 0), Dir(30, 300), Dir(45, 30), Dir(80, 200),
                             Dir(89.5, 120)};

template <typename Real>
void CheckEveryView(const MaterialT<Real>& m, Domain domain,
                    const std::string& name, const Lookup& at = {},
                    int quadrature = 8) {
  for (const glm::dvec3& wo : kViews) {
    CheckSampler(m, wo, at, domain, name, quadrature);
  }
}

template <typename Real>
class MaterialSampling : public ::testing::Test {};
using Reals = ::testing::Types<double, float>;
TYPED_TEST_SUITE(MaterialSampling, Reals);

TYPED_TEST(MaterialSampling, ClothPresetsAndATurnedLinen) {
  using M = MaterialT<TypeParam>;
  CheckEveryView(M::FromParams(Preset("polyester_satin_charmeuse")),
                 Domain::kUpper, "satin");
  CheckEveryView(M::FromParams(Preset("velvet")), Domain::kUpper, "velvet");
  CheckEveryView(M::FromParams(TurnedLinen()), Domain::kUpper, "linen");
}

TYPED_TEST(MaterialSampling, ThreadOnBothSides) {
  ThreadParams thread;
  thread.albedo = glm::dvec3(0.3, 0.5, 0.7);
  const auto m = MaterialT<TypeParam>::FromParams(thread);
  CheckEveryView(m, Domain::kSphere, "thread");
  CheckSampler(m, Dir(120, 40), {}, Domain::kSphere, "thread from below");
}

TYPED_TEST(MaterialSampling, LafortuneLobesOnATiltedTexel) {
  CheckEveryView(MaterialT<TypeParam>::FromParams(TiltedLafortune()),
                 Domain::kUpper, "lafortune");
}

TYPED_TEST(MaterialSampling, GltfSheenOverASmoothAndARoughBase) {
  SheenParams sheen;
  sheen.base_color = glm::dvec3(0.3, 0.2, 0.1);
  sheen.sheen_color = glm::dvec3(0.7, 0.5, 0.4);
  sheen.sheen_roughness = 0.35;
  for (double roughness : {0.25, 0.9}) {
    sheen.roughness = roughness;
    // A GGX lobe of alpha 0.0625 at 89.5 degrees needs 16 x 16 points per
    // bin for the pdf's integral to reach 3e-3 (8 x 8: 8e-3; the error
    // falls as 1 / n^2).
    CheckEveryView(MaterialT<TypeParam>::FromParams(sheen), Domain::kUpper,
                   "sheen, roughness " + std::to_string(roughness), {}, 16);
  }
}

TYPED_TEST(MaterialSampling, SlabReflectsTransmitsAndPassesLightStraight) {
  const auto m = MaterialT<TypeParam>::FromParams(Slab());
  CheckEveryView(m, Domain::kSphere, "slab");
  CheckSampler(m, Dir(150, 10), {}, Domain::kSphere, "slab from below");
  // A delta sample carries the direct transmittance exp(-tau / |wo.z|).
  for (const glm::dvec3& wo : {Dir(30, 0), Dir(150, 10)}) {
    const BsdfSampleT<TypeParam> b =
        m.Sample(glm::vec<3, TypeParam>(wo), TypeParam(0), TypeParam(0.5));
    ASSERT_TRUE(b.delta);
    for (int c = 0; c < 3; ++c) {
      EXPECT_NEAR(b.weight[c] * b.pdf,
                  std::exp(-Slab().tau[c] / std::abs(wo.z)), 1e-6);
    }
  }
}

// A 2 x 2 Lafortune map over a 1 x 1 level whose texels differ in frame,
// lobes and diffuse term.
std::string WriteLafortuneMap(const std::string& name) {
  LafortuneTexelMap base;
  base.width = base.height = 2;
  for (int i = 0; i < 4; ++i) {
    LafortuneModel m = TiltedLafortune();
    m.normal =
        glm::normalize(glm::dvec3(0.3 * (i % 2) - 0.1, 0.2 * (i / 2), 1));
    m.params.lobes[0].n *= 0.5 + 0.5 * i;
    m.params.diffuse *= 1.0 + i;
    base.texels.push_back(m);
  }
  LafortuneTexelMap top;
  top.width = top.height = 1;
  LafortuneModel m = TiltedLafortune();
  m.params.lobes.resize(1);
  m.params.lobes[0].n = glm::dvec3(6.0);
  top.texels.push_back(m);
  const std::string path =
      (testing_util::FreshTestDir("material_sampling_") / name).string();
  WriteParamMipmap(ToParamMipmap({base, top}, {}), path);
  return path;
}

TYPED_TEST(MaterialSampling, TextureMapsWithBilinearAndTrilinearFiltering) {
  const std::string path = WriteLafortuneMap("map.exr");
  for (TexelFilter filter : {TexelFilter::kBilinear, TexelFilter::kTrilinear}) {
    const auto m = MaterialT<TypeParam>::Load(path, filter);
    // Between the four texel centres of level 0 and (trilinear) a quarter
    // of the way to level 1: every tap has a share.
    const Lookup at{0.4, 0.65, 0.25};
    CheckEveryView(m, Domain::kUpper,
                   filter == TexelFilter::kBilinear ? "bilinear" : "trilinear",
                   at);
  }
}

// A holes file that holds its mask's tile loads without the mask (the
// renderer API reads no image): F and Pdf are 0 and every sample is the
// direct transmission, weighted by the model's transmittance. Without the
// tile, loading says how to add it.
TYPED_TEST(MaterialSampling, HolesFileWithItsTileTransmitsStraightThrough) {
  using Vec = glm::vec<3, TypeParam>;
  const Mask mask = MaskFromRows(
      {"##..#.#.", "#...#..#", "........", "###.##.#", "#.#.#..#"});
  HolesModel model;
  model.params.thickness_texels = 0.8;
  model.params.wall_color = glm::dvec3(0.1, 0.3, 0.5);
  model.tile = std::make_shared<const HolesTile>(
      HolesTileOf(AnalyzeMask(mask, true), HoleMethod::kExtension));
  ParamFile file(model);
  file.holes.path = "net.png";  // not there: the tile suffices
  const auto dir = testing_util::FreshTestDir("material_sampling_");
  const std::string path = (dir / "holes.json").string();
  WriteParamFile(file, path);
  const auto m = MaterialT<TypeParam>::Load(path);
  EXPECT_EQ(m.Kind(), "holes");
  for (const glm::dvec3& wo : kViews) {
    const Vec w(wo);
    const BsdfSampleT<TypeParam> b =
        m.Sample(w, TypeParam(0.7), TypeParam(0.2));
    ASSERT_TRUE(b.delta);
    EXPECT_EQ(b.wi, -w);
    EXPECT_EQ(b.pdf, TypeParam(1));
    const glm::dvec3 t = Transmittance(model, wo);
    for (int c = 0; c < 3; ++c) EXPECT_NEAR(b.weight[c], t[c], 1e-6);
    EXPECT_EQ(m.F(Dir(20, 10), w), Vec(TypeParam(0)));
    EXPECT_EQ(m.Pdf(w, -w), TypeParam(0));
  }
  file.params = HolesModel{model.params, nullptr};
  WriteParamFile(file, path);
  testing_util::ExpectHas(
      testing_util::ErrorOf([&] { MaterialT<TypeParam>::Load(path); }),
      {"holes.json", "tile", "net.png", "clothfit holes tile"});
}

}  // namespace
}  // namespace clothfit
