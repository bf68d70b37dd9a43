// A renderer's use of clothfit::api alone: loads a fitted Lafortune file
// and a parameter mip map (written here with clothfit::io, which the api
// component brings) and evaluates them against the formula written out
// by hand. Usage: renderer FITTED.json WORK_DIR; exit 0 when every check
// holds.
#include <clothfit/api/material.h>
#include <clothfit/io/lafortune_mipmap.h>

#include <cmath>
#include <iostream>
#include <string>
#include <vector>

#include "../consumer/checks.h"

namespace {

using consumer::Check;
using consumer::failures;
using consumer::Near;

// Daubert et al. 2001, eq. 2 with one lobe and no lookup table.
double LafortuneByHand(double diffuse, double cx, double cy, double cz,
                       double n, const glm::dvec3& l, const glm::dvec3& v) {
  const double a = cx * l.x * v.x + cy * l.y * v.y + cz * l.z * v.z;
  return l.z * (diffuse + (a > 0.0 ? std::pow(a, n) : 0.0));
}

void CheckFile(const std::string& path) {
  const clothfit::Material m = clothfit::Material::Load(path);
  Check(m.Kind() == "lafortune", "kind of " + path + ": " + m.Kind());
  // Channel R of fitted_lafortune.json (tests/consumer/).
  const glm::dvec3 l(0.6, 0.0, 0.8), v(-0.48, -0.36, 0.8);
  Check(Near(m.Rho(l, v).x,
             LafortuneByHand(0.1000957759668295, -0.803444568412622,
                             -0.7169708998396055, 0.9027419063130582,
                             12.305400904555322, l, v),
             1e-12),
        "fitted file, channel R");
  // A sampled direction: its pdf is Pdf there and its weight rho / pdf.
  const clothfit::BsdfSampleT<double> b = m.Sample(v, 0.3, 0.6);
  Check(b.pdf > 0.0 && Near(b.pdf, m.Pdf(v, b.wi), 1e-12 * b.pdf) &&
            Near(b.weight.x, m.Rho(b.wi, v).x / b.pdf, 1e-12 * b.weight.x),
        "sample of " + path);
}

// A 2 x 2 map of diffuse texels over a 1 x 1 level; the renderer reads the
// texel that holds (s, t) and F = rho / wi.z.
void CheckMipmap(const std::string& dir) {
  clothfit::LafortuneTexelMap base, top;
  base.width = base.height = 2;
  for (int i = 0; i < 4; ++i) {
    clothfit::LafortuneModel t;
    t.params.diffuse = glm::dvec3(0.1 * (i + 1), 0.5, 0.25);
    base.texels.push_back(t);
  }
  top.width = top.height = 1;
  top.texels.resize(1);
  top.texels[0].params.diffuse = glm::dvec3(0.7, 0.5, 0.25);
  const std::string path = dir + "/diffuse.exr";
  clothfit::WriteParamMipmap(clothfit::ToParamMipmap({base, top}, {}), path);
  const clothfit::Material m = clothfit::Material::Load(path);
  Check(m.Levels() == 2, "levels");
  const glm::dvec3 wi(0.0, 0.6, 0.8), wo(0.0, 0.0, 1.0);
  // Texel (x, y) = (1, 0) holds s in [0.5, 1), t in [0, 0.5): red 0.2.
  Check(Near(m.Rho(wi, wo, 0.75, 0.25, 0).x, 0.2 * 0.8, 1e-7), "texel (1, 0)");
  Check(Near(m.F(wi, wo, 0.25, 0.75, 0).x, 0.3, 1e-7), "texel (0, 1), F");
  Check(Near(m.F(wi, wo, 0.25, 0.75, 1).x, 0.7, 1e-7), "level 1");
  // Bilinear between the four texels: red (0.1 + 0.2 + 0.3 + 0.4) / 4.
  const clothfit::Material b =
      clothfit::Material::Load(path, clothfit::TexelFilter::kBilinear);
  Check(Near(b.F(wi, wo, 0.5, 0.5, 0).x, 0.25, 1e-7), "bilinear");
  // Sampled with trilinear filtering: the texels' mixture, consistent
  // with F (diffuse texels: cosine sampling, weight = the blended albedo).
  const clothfit::Material t =
      clothfit::Material::Load(path, clothfit::TexelFilter::kTrilinear);
  const clothfit::BsdfSampleT<double> s = t.Sample(wo, 0.4, 0.3, 0.5, 0.5, 0.5);
  Check(s.pdf > 0.0 && Near(s.pdf, t.Pdf(wo, s.wi, 0.5, 0.5, 0.5), 1e-12) &&
            Near(s.weight.x, (0.5 * 0.25 + 0.5 * 0.7) * clothfit::kPi, 1e-6),
        "trilinear sample");
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: renderer FITTED.json WORK_DIR\n";
    return 2;
  }
  try {
    CheckFile(argv[1]);
    CheckMipmap(argv[2]);
  } catch (const std::exception& error) {
    std::cerr << "FAIL: " << error.what() << "\n";
    return 1;
  }
  std::cout << (failures == 0 ? "renderer: all checks passed\n"
                              : "renderer: checks failed\n");
  return failures == 0 ? 0 : 1;
}
