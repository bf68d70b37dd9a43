// The bench's SciPy peer (benchmarks/peer/scipy_models.py) fits
// the same models as clothfit: its NumPy thread, cloth and slab formulas
// match clothfit's values on noise-free tables written here, and its cloth
// matches the independent implementation of the conformance data
// (docs/models.md). Skipped where /usr/bin/python3 has no SciPy (the bench then
// skips the peer).
#include <gtest/gtest.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <map>
#include <nlohmann/json.hpp>
#include <string>

#include "data_synthetic/holes_truth.h"
#include "data_synthetic/synthetic_table.h"
#include "holes/hole_texture.h"
#include "io/params_json.h"
#include "io/table.h"
#include "models/presets.h"
#include "tests/cli_test_util.h"
#include "tests/conformance_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;

constexpr double kAgreement = 1e-9;  // largest difference / largest value

bool HaveScipy() {
  return std::system("/usr/bin/python3 -c 'import scipy' 2>/dev/null") == 0;
}

// The peer's largest relative difference from the table's values at
// `params_json` (scipy_models.py check).
double PeerDifference(const fs::path& dir, const std::string& model,
                      const std::string& params_json,
                      const MeasurementTable& t) {
  const std::string params_path = (dir / (model + ".json")).string();
  const std::string table_path = (dir / (model + ".csv")).string();
  const std::string out_path = (dir / (model + "_out.json")).string();
  testing_util::WriteText(params_path, params_json);
  WriteTable(t, table_path);
  const std::string command =
      "/usr/bin/python3 " CLOTHFIT_PEER_DIR "/scipy_models.py check " + model +
      " " + params_path + " " + table_path + " > " + out_path;
  EXPECT_EQ(std::system(command.c_str()), 0) << command;
  const nlohmann::json out =
      nlohmann::json::parse(testing_util::ReadText(out_path));
  EXPECT_EQ(out.at("rows").get<size_t>(), t.rows.size());
  return out.at("max_relative_difference").get<double>();
}

double PeerDifference(const fs::path& dir, const std::string& model,
                      const ModelParams& params, const MeasurementTable& t) {
  return PeerDifference(dir, model, FormatParamFile({params, ""}), t);
}

MeasurementTable CleanTable(const ModelParams& truth, bool full_sphere) {
  DirectionSampling sampling;
  sampling.rows = 400;
  sampling.full_sphere_out = full_sphere;
  return SyntheticTable(truth, sampling, SynthOptions(), 5);
}

TEST(PeerModels, ThreadAndSlabMatchClothfitOnBothSides) {
  if (!HaveScipy()) GTEST_SKIP() << "no SciPy in /usr/bin/python3";
  const fs::path dir = testing_util::FreshTestDir("peer_models_test_");
  for (const char* preset : {"polyester_satin_charmeuse", "velvet"}) {
    ClothParams cloth;
    ASSERT_TRUE(GetPreset(preset, &cloth));
    for (const ClothThread& thread : cloth.threads) {
      EXPECT_LT(PeerDifference(dir, "thread", thread.params,
                               CleanTable(thread.params, true)),
                kAgreement)
          << preset;
    }
  }
  SlabParams slab;
  slab.tau = glm::dvec3(0.05, 0.2, 0.6);
  slab.albedo = glm::dvec3(0.4, 0.3, 0.2);
  const MeasurementTable table = CleanTable(slab, true);
  int transmission = 0;
  for (const TableRow& r : table.rows) transmission += r.wo.z < 0.0;
  EXPECT_GT(transmission, 100);  // both f_r and f_t are compared
  EXPECT_LT(PeerDifference(dir, "slab", slab, table), kAgreement);
}

TEST(PeerModels, ClothMatchesClothfitAndTheConformanceData) {
  if (!HaveScipy()) GTEST_SKIP() << "no SciPy in /usr/bin/python3";
  const fs::path dir = testing_util::FreshTestDir("peer_models_test_");
  // The conformance rows (rho) of each preset, as brdf tables (f = rho /
  // wi.z).
  std::map<std::string, MeasurementTable> tables;
  for (const testing_util::ConformanceRow& c :
       testing_util::ReadConformanceRows()) {
    TableRow row;
    row.wi = c.wi;
    row.wo = c.wo;
    row.value = c.rho / c.wi.z;
    tables[c.preset].quantity = Quantity::kBrdf;
    tables[c.preset].rows.push_back(row);
  }
  ASSERT_EQ(tables.size(), 5u);
  for (const auto& [preset, table] : tables) {
    ClothParams cloth;
    ASSERT_TRUE(GetPreset(preset, &cloth)) << preset;
    // docs/models.md: the independent implementation, to 1e-6 relative.
    EXPECT_LT(PeerDifference(dir, "cloth", cloth, table), 1e-6) << preset;
    EXPECT_LT(PeerDifference(dir, "cloth", cloth, CleanTable(cloth, false)),
              kAgreement)
        << preset;
  }
}

// Holes: the peer's Algorithm 3.1 on the tile's nine counts against
// clothfit's tile evaluation (every view quadrant, offsets clamped and not,
// a wall colour), one channel as the bench's tables have.
TEST(PeerModels, HolesMatchClothfitsTileEvaluation) {
  if (!HaveScipy()) GTEST_SKIP() << "no SciPy in /usr/bin/python3";
  const fs::path dir = testing_util::FreshTestDir("peer_models_test_");
  const HoleTexture texture = AnalyzeMask(RandomMask(24, 20, 0.45, 7), false);
  const int top = texture.counts.levels() - 1;
  const LevelTexels level = GatherLevel(texture, top);
  HolesParams p;
  p.thickness_texels = 0.7;
  p.wall_color = glm::dvec3(0.3);
  MeasurementTable table;
  table.quantity = Quantity::kTransmittance;
  table.channels = 1;
  for (double theta : {0.0, 20.0, 45.0, 70.0}) {
    for (double phi : {0.0, 30.0, 100.0, 200.0, 290.0}) {
      TableRow row;
      row.wo = DirectionFromAngles(Radians(theta), Radians(phi));
      row.value = TransmittanceOfRatios(
          p, EvaluateTile(texture, HoleMethod::kAlgorithm31, top,
                          ViewOffset(p.thickness_texels, row.wo)));
      table.rows.push_back(row);
    }
  }
  nlohmann::json j;
  j["model"] = "holes";
  j["thickness_texels"] = p.thickness_texels;
  j["wall_color"] = {0.3, 0.3, 0.3};
  j["counts"] = level.counts[0].counts;
  j["texels"] = level.area;
  EXPECT_LT(PeerDifference(dir, "holes", j.dump(), table), kAgreement);
}

}  // namespace
}  // namespace clothfit
