// The independent implementation's reference values (docs/models.md):
// ../shared/data/conformance/microcylinder_rho.csv, one row per (preset,
// wi, wo) with the cloth model's rho.
#pragma once

#include <gtest/gtest.h>

#include <fstream>
#include <glm/vec3.hpp>
#include <sstream>
#include <string>
#include <vector>

namespace clothfit {
namespace testing_util {

struct ConformanceRow {
  std::string preset;
  glm::dvec3 wi, wo, rho;
};

// Every row of the file, in file order; a failed assertion (and no rows)
// when the file is missing or its header is not the expected one.
inline std::vector<ConformanceRow> ReadConformanceRows() {
  const std::string path = std::string(CLOTHFIT_SHARED_DIR) +
                           "/data/conformance/microcylinder_rho.csv";
  std::vector<ConformanceRow> rows;
  std::ifstream in(path);
  EXPECT_TRUE(in) << "cannot open " << path;
  std::string line;
  std::getline(in, line);
  EXPECT_EQ(line, "preset,wi_x,wi_y,wi_z,wo_x,wo_y,wo_z,rho_r,rho_g,rho_b");
  while (std::getline(in, line)) {
    std::stringstream fields(line);
    std::string field;
    ConformanceRow row;
    std::getline(fields, row.preset, ',');
    double v[9];
    for (double& x : v) {
      std::getline(fields, field, ',');
      x = std::stod(field);
    }
    row.wi = glm::dvec3(v[0], v[1], v[2]);
    row.wo = glm::dvec3(v[3], v[4], v[5]);
    row.rho = glm::dvec3(v[6], v[7], v[8]);
    rows.push_back(row);
  }
  return rows;
}

}  // namespace testing_util
}  // namespace clothfit
