// Built against an installed clothfit (find_package(clothfit)); checks the
// installed headers and libraries against values computed independently:
//  1. a preset's rho against the conformance table of an independent
//     implementation of the microcylinder model (docs/models.md);
//  2. a fitted Lafortune file (a fit of a synthetic table of known lobes,
//     fitted_lafortune.json) through clothfit::Material against the
//     Lafortune formula written out here, with the file's numbers and with
//     the lobes the table was made from.
// Usage: consumer CONFORMANCE.csv FITTED.json; exit 0 when every check holds.
#include <clothfit/api/material.h>
#include <clothfit/models/presets.h>

#include <cmath>
#include <fstream>
#include <iostream>
#include <sstream>
#include <string>

#include "checks.h"

namespace {

using consumer::Check;
using consumer::failures;
using consumer::Near;

// Lafortune 1997 / Daubert 2001 eq. 2 with one lobe and no lookup table:
// rho = l.z (rho_d + [Cx lx vx + Cy ly vy + Cz lz vz]^N).
double LafortuneByHand(const double p[5], const double l[3],
                       const double v[3]) {
  const double a = p[1] * l[0] * v[0] + p[2] * l[1] * v[1] + p[3] * l[2] * v[2];
  return l[2] * (p[0] + (a > 0.0 ? std::pow(a, p[4]) : 0.0));
}

void CheckPresetAgainstConformance(const std::string& path) {
  std::ifstream in(path);
  Check(static_cast<bool>(in), "cannot open " + path);
  std::string line;
  std::getline(in, line);
  int rows = 0;
  while (std::getline(in, line)) {
    std::stringstream ss(line);
    std::string name, field;
    std::getline(ss, name, ',');
    double v[9];
    for (double& x : v) {
      std::getline(ss, field, ',');
      x = std::stod(field);
    }
    if (name != "polyester_satin_charmeuse") continue;
    clothfit::ClothParams preset;
    Check(clothfit::GetPreset(name, &preset), "preset " + name);
    const glm::dvec3 wi(v[0], v[1], v[2]), wo(v[3], v[4], v[5]);
    // Header-only path (clothfit::models) and the renderer API.
    const glm::dvec3 rho = clothfit::ClothRho(preset, wi, wo);
    const clothfit::Material material = clothfit::Material::FromParams(preset);
    const glm::dvec3 api_rho = material.Rho(wi, wo);
    const glm::dvec3 api_f = material.F(wi, wo);
    for (int c = 0; c < 3; ++c) {
      const std::string where = name + " row " + std::to_string(rows);
      Check(Near(rho[c], v[6 + c], 1e-6), where + " ClothRho");
      Check(Near(api_rho[c], v[6 + c], 1e-6), where + " Material::Rho");
      Check(Near(api_f[c], v[6 + c] / wi.z, 1e-6), where + " Material::F");
    }
    ++rows;
  }
  Check(rows == 60, "expected 60 satin rows, got " + std::to_string(rows));
}

void CheckFittedLafortune(const std::string& path) {
  const clothfit::Material m = clothfit::Material::Load(path);
  Check(m.Kind() == "lafortune", "kind of " + path + ": " + m.Kind());
  // Channel R of fitted_lafortune.json: diffuse, Cx, Cy, Cz, N.
  const double fitted_r[5] = {0.1000957759668295, -0.803444568412622,
                              -0.7169708998396055, 0.9027419063130582,
                              12.305400904555322};
  // The lobes the synthetic table was made from (its channels share them
  // except the diffuse term: 0.1, 0.2, 0.3).
  const double truth_diffuse[3] = {0.1, 0.2, 0.3};
  const double s = std::sqrt(0.5);
  const double pairs[3][2][3] = {{{0.0, 0.0, 1.0}, {0.0, 0.0, 1.0}},
                                 {{s, 0.0, s}, {-s, 0.0, s}},
                                 {{0.6, 0.0, 0.8}, {-0.48, -0.36, 0.8}}};
  for (const auto& pair : pairs) {
    const glm::dvec3 l(pair[0][0], pair[0][1], pair[0][2]);
    const glm::dvec3 v(pair[1][0], pair[1][1], pair[1][2]);
    const glm::dvec3 rho = m.Rho(l, v);
    Check(Near(rho.x, LafortuneByHand(fitted_r, pair[0], pair[1]), 1e-12),
          "fitted file, channel R, by hand");
    for (int c = 0; c < 3; ++c) {
      const double truth[5] = {truth_diffuse[c], -0.8, -0.7, 0.9, 12.0};
      Check(Near(rho[c], LafortuneByHand(truth, pair[0], pair[1]), 0.05),
            "fitted file vs the table's lobes, channel " + std::to_string(c));
      Check(Near(m.F(l, v)[c], rho[c] / l.z, 1e-12), "F = rho / wi.z");
    }
  }
}

}  // namespace

int main(int argc, char** argv) {
  if (argc != 3) {
    std::cerr << "usage: consumer CONFORMANCE.csv FITTED.json\n";
    return 2;
  }
  CheckPresetAgainstConformance(argv[1]);
  CheckFittedLafortune(argv[2]);
  std::cout << (failures == 0 ? "consumer: all checks passed\n"
                              : "consumer: checks failed\n");
  return failures == 0 ? 0 : 1;
}
