// Real measurements (../shared/data/curet/, eleven CUReT fabrics, 205
// geometries each, one channel, arbitrary scale): every table reads, and
// the finding docs/curet.md reports holds - the plain weave with its
// tangent-offset magnitude and eta free (and a fitted scale) beats the best
// constant on every sample, where the fixed weave does not.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "fitting/cloth_fit.h"
#include "fitting/energy.h"
#include "fitting/fabric_select.h"
#include "fitting/lafortune_mip.h"
#include "fitting/lafortune_select.h"
#include "io/table.h"
#include "models/evaluate.h"
#include "models/presets.h"
#include "tests/fit_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;

std::vector<std::string> CuretTables() {
  std::vector<std::string> paths;
  const fs::path dir = fs::path(CLOTHFIT_SHARED_DIR) / "data" / "curet";
  for (const fs::directory_entry& e : fs::directory_iterator(dir)) {
    if (e.path().extension() == ".csv") paths.push_back(e.path().string());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

// RMS(mean - y) / RMS(y): the relative RMS error of the best constant.
double ConstantRelativeRms(const MeasurementTable& table) {
  double sum = 0.0, ss = 0.0;
  for (const TableRow& row : table.rows) sum += row.value.x;
  const double mean = sum / table.rows.size();
  double se = 0.0;
  for (const TableRow& row : table.rows) {
    se += (mean - row.value.x) * (mean - row.value.x);
    ss += row.value.x * row.value.x;
  }
  return std::sqrt(se / ss);
}

TEST(CuretTables, EveryFabricReadsAsAOneChannelBrdfTable) {
  const std::vector<std::string> paths = CuretTables();
  ASSERT_EQ(paths.size(), 11u);
  for (const std::string& path : paths) {
    const MeasurementTable table = ReadTable(path).table;
    EXPECT_EQ(table.rows.size(), 205u) << path;
    EXPECT_EQ(table.channels, 1) << path;
    EXPECT_EQ(table.quantity, Quantity::kBrdf) << path;
    for (const TableRow& row : table.rows) {
      EXPECT_TRUE(std::isfinite(row.value.x) && row.value.x >= 0.0)
          << path << ":" << row.source_line;
      EXPECT_GT(row.wi.z, 0.0) << path << ":" << row.source_line;
      EXPECT_GT(row.wo.z, 0.0) << path << ":" << row.source_line;
    }
  }
}

TEST(CuretFits, PlainWeaveWithFreeOffsetsBeatsTheBestConstantOnEveryFabric) {
  ClothParams linen;
  ASSERT_TRUE(GetPreset("linen_plain", &linen));
  // The paper's model (the bounded one, the default, fits these tables as
  // well where it lowers no row, and is 6-13x slower where it does:
  // docs/fitting.md).
  ClothFitOptions options = testing_util::PaperModel<ClothFitOptions>();
  options.fit_scale = true;
  // The metric is RMS(model - data) / RMS(data), which every residual
  // weighed alike minimises (the default for a table without sigma,
  // relative noise, minimises the relative error instead).
  options.solver.noise.kind = NoiseKind::kAbsolute;
  options.free_only = {"albedo",      "kd",  "gamma_s_deg",
                       "gamma_v_deg", "eta", "offset_scale"};
  for (const std::string& path : CuretTables()) {
    const MeasurementTable table = ReadTable(path).table;
    const ClothFitResult fit =
        FitCloth(table, GenericClothStart(linen), options);
    ASSERT_TRUE(fit.report.usable) << path << ": " << fit.report.message;
    const double constant = ConstantRelativeRms(table);
    EXPECT_LT(fit.report.relative_rms, constant)
        << path << ": constant " << constant;
    for (const ParameterReport& p : fit.report.parameters) {
      EXPECT_TRUE(std::isfinite(p.value)) << path << " " << p.name;
    }
  }
}

// RMS(model - y) / RMS(y) over `rows` of `table`, in the table's quantity.
double HeldOutError(const LafortuneModel& model, const MeasurementTable& table,
                    const std::vector<TableRow>& rows) {
  double se = 0.0, ss = 0.0;
  for (const TableRow& row : rows) {
    const double m = Value(model, row.wi, row.wo, table.quantity).x;
    se += (m - row.value.x) * (m - row.value.x);
    ss += row.value.x * row.value.x;
  }
  return std::sqrt(se / ss);
}

// The lookup table gets an entry only for views with enough samples
// (LafortuneFitOptions::min_lut_samples): on CUReT tables (1.4 rows per
// view) the default fit, lookup table on, is not worse on held-out rows
// (every 5th) than the same fit without one. 0.3 fitted a T per view and
// lost on held-out rows (K = 1: 0.190 against 0.173).
TEST(CuretFits, LafortuneLookupTableDoesNotLoseOnHeldOutRows) {
  for (const std::string& path : CuretTables()) {
    const MeasurementTable table = ReadTable(path).table;
    MeasurementTable train = table;
    train.rows.clear();
    std::vector<TableRow> held;
    for (size_t i = 0; i < table.rows.size(); ++i) {
      (i % 5 == 0 ? held : train.rows).push_back(table.rows[i]);
    }
    for (int lobes : {1, 2}) {
      LafortuneMipOptions with, without;
      with.fit.lobes = without.fit.lobes = lobes;
      without.fit.lookup_table = false;
      const LafortuneFitResult a = FitLafortuneTable(train, with);
      const LafortuneFitResult b = FitLafortuneTable(train, without);
      ASSERT_TRUE(a.report.usable && b.report.usable) << path;
      const double e_with = HeldOutError(a.params, table, held);
      const double e_without = HeldOutError(b.params, table, held);
      EXPECT_LE(e_with, e_without * (1.0 + 1e-9))
          << path << " K = " << lobes << ": with " << e_with << ", without "
          << e_without;
      EXPECT_EQ(a.report.lut_views_fitted, 0) << path;
    }
  }
}

// Rug b: the 3-lobe candidate's third lobe collapses to N = 0.5 (a
// near-constant): it is scored and noted, never chosen; the chosen model
// has no collapsed lobe and stands against the fewer-lobe candidates on
// held-out rows.
TEST(CuretFits, HeldOutSelectionNeverChoosesACollapsedLobe) {
  const fs::path path =
      fs::path(CLOTHFIT_SHARED_DIR) / "data" / "curet" / "curet_19_rug_b.csv";
  const MeasurementTable table = ReadTable(path.string()).table;
  const LafortuneSelection s =
      SelectLafortuneHeldOut(table, LafortuneMipOptions(), 5);
  ASSERT_GE(s.report.chosen, 0) << s.report.reason;
  int noted = 0;
  for (size_t i = 0; i < s.report.candidates.size(); ++i) {
    const CandidateReport& c = s.report.candidates[i];
    if (c.note.find("collapsed") == std::string::npos) continue;
    ++noted;
    EXPECT_NE(static_cast<int>(i), s.report.chosen) << c.description;
  }
  EXPECT_GE(noted, 1);
  EXPECT_EQ(s.report.candidates[3].description, "3 lobe(s), no lookup table");
  EXPECT_NE(s.report.candidates[3].note.find("lobes[2] collapsed"),
            std::string::npos)
      << s.report.candidates[3].note;
  for (const LafortuneLobe& lobe : s.fit.params.params.lobes) {
    for (int c = 0; c < 3; ++c) EXPECT_GT(lobe.n[c], 0.5 + 1e-6);
  }
  const CandidateReport& chosen = s.report.candidates[s.report.chosen];
  for (const CandidateReport& c : s.report.candidates) {
    if (c.note.empty() && c.usable) {
      EXPECT_LE(chosen.heldout_relative_rms, c.heldout_relative_rms)
          << c.description;
    }
  }
}

// The candidate of fit --model auto described so, or null.
const CandidateReport* FindCandidate(const SelectionReport& r,
                                     const std::string& description) {
  for (const CandidateReport& c : r.candidates) {
    if (c.description == description) return &c;
  }
  return nullptr;
}

// fit --model auto --fit-scale of a CUReT table (its file name).
FabricSelection SelectOnCuret(const std::string& name) {
  const fs::path path = fs::path(CLOTHFIT_SHARED_DIR) / "data" / "curet" / name;
  const MeasurementTable table = ReadTable(path.string()).table;
  FabricSelectOptions options;
  options.fit_scale = true;
  return SelectFabricModel(table, options);
}

// On real cloth (CUReT linen), the microcylinder model with its freedoms
// (rotation, free offsets, a Lambertian term, free coverages) predicts
// held-out rows better than two Lafortune lobes, converged, its
// coverages summing to at most 1 and with no more than twice the lobes'
// parameters; fit --model auto chooses it (docs/curet.md has every
// fabric), bounded (the default): it conserves energy on both sides.
TEST(CuretFits, ClothWithFreedomsBeatsTwoLafortuneLobesHeldOutOnLinen) {
  const FabricSelection s = SelectOnCuret("curet_44_linen.csv");
  const CandidateReport* lobes =
      FindCandidate(s.selection, "lafortune 2 lobe(s), no lookup table");
  const CandidateReport* cloth = FindCandidate(
      s.selection, "cloth plain + rotation, offsets, diffuse, coverage");
  ASSERT_TRUE(lobes && cloth);
  EXPECT_TRUE(cloth->converged) << cloth->note;
  EXPECT_LT(cloth->heldout_relative_rms, lobes->heldout_relative_rms);
  EXPECT_LE(cloth->free_parameters, 2 * lobes->free_parameters);
  EXPECT_LT(cloth->relative_rms, 0.10);
  ASSERT_TRUE(std::holds_alternative<ClothParams>(s.params))
      << SelectionReportText(s.selection);
  const ClothParams& c = std::get<ClothParams>(s.params);
  EXPECT_EQ(ValidateClothParams(c), "");
  EXPECT_LE(ModelEnergy(s.params).max_albedo, 1.0);
  EXPECT_LE(ModelLightSideEnergy(s.params).max_albedo, 1.0);
  double coverage = 0.0;
  for (const ClothThread& th : c.threads) coverage += th.coverage;
  EXPECT_LE(coverage, 1.0 + 1e-12);
}

// Lambswool: the plain weave with its freedoms and free coverages misses
// the mid-forward rows (the threads' narrow forward peak); with a free eta
// per thread instead, the Fresnel term's rise toward grazing (eta just
// above 1) shapes the surface reflection, and the same 17 parameters fit
// the table within 0.10 and predict held-out rows better, better than
// two Lafortune lobes too. (Solving 4 starts in full instead of screening
// 8, the search stopped at 0.103 in-sample and lost to the lobes:
// docs/fitting.md.)
TEST(CuretFits, FreeEtaFitsLambswoolBelowTenPercentAndBeatsTheLobes) {
  const FabricSelection s = SelectOnCuret("curet_22_lambswool.csv");
  const CandidateReport* lobes =
      FindCandidate(s.selection, "lafortune 2 lobe(s), no lookup table");
  const CandidateReport* coverage = FindCandidate(
      s.selection, "cloth plain + rotation, offsets, diffuse, coverage");
  const CandidateReport* eta = FindCandidate(
      s.selection, "cloth plain + rotation, offsets, diffuse, eta");
  ASSERT_TRUE(lobes && coverage && eta) << SelectionReportText(s.selection);
  EXPECT_TRUE(eta->converged) << eta->note;
  EXPECT_LT(eta->relative_rms, 0.9 * coverage->relative_rms);
  EXPECT_LT(eta->heldout_relative_rms, 0.9 * coverage->heldout_relative_rms);
  EXPECT_LT(eta->relative_rms, 0.10);
  EXPECT_LT(eta->heldout_relative_rms, lobes->heldout_relative_rms);
  EXPECT_LE(eta->free_parameters, 2 * lobes->free_parameters);
}

// Pooled held-out relative RMS of rug b's whole-table cloth fit `whole`
// (the plain weave with free eta), each fold (row index mod 5) fitted as
// fit --model auto fits it: from `whole`, one start, holding `held`.
double RugBFoldError(const MeasurementTable& table, const ClothParams& whole,
                     const std::vector<std::string>& held) {
  double se = 0.0, ss = 0.0;
  for (int f = 0; f < 5; ++f) {
    MeasurementTable part = table;
    part.rows.clear();
    for (size_t i = 0; i < table.rows.size(); ++i) {
      if (static_cast<int>(i % 5) != f) part.rows.push_back(table.rows[i]);
    }
    ClothFitOptions o;
    o.solver.noise.kind = NoiseKind::kAbsolute;
    o.fit_scale = true;
    o.also_free = {"rotation_deg", "offsets_deg", "diffuse", "eta"};
    o.fix = held;
    o.multi_start = false;
    o.solve_starts = 1;
    o.conserve_energy = false;
    o.energy_bound = false;  // the whole table's bound held, as auto's folds
    ClothParams init = whole;
    init.scale = 1.0;
    const ClothFitResult r = FitCloth(part, init, o);
    for (size_t i = f; i < table.rows.size(); i += 5) {
      const TableRow& row = table.rows[i];
      const double model =
          Evaluate(ModelParams(r.params), row.wi, row.wo, table.quantity).x;
      se += (model - row.value.x) * (model - row.value.x);
      ss += row.value.x * row.value.x;
    }
  }
  return std::sqrt(se / ss);
}

// Rug b: a fold's fit starts from the whole-table fit and holds the
// entries that had no effect there or sat on a bound
// (fitting/fabric_select.h HeldInFolds). The held-out error fit --model
// auto reports is that of these folds, recomputed here; it stays near the
// in-sample error (no fold leaves the basin for another, as rug a's
// free-coverage folds did in one run: 0.758 held-out against 0.073
// in-sample), and
// the cloth predicts the held-out rows better than two lobes. Whether
// holding beats freeing those entries depends on the basin the search
// finds: 0.16 against 0.17 in one run, 0.187 against 0.176 in another,
// whose fit has a volume lobe 0.3 degrees wide (docs/curet.md).
TEST(CuretFits, ClothFoldsStayInTheirBasinOnRugB) {
  const fs::path path =
      fs::path(CLOTHFIT_SHARED_DIR) / "data" / "curet" / "curet_19_rug_b.csv";
  const MeasurementTable table = ReadTable(path.string()).table;
  const FabricSelection s = SelectOnCuret("curet_19_rug_b.csv");
  const CandidateReport* lobes =
      FindCandidate(s.selection, "lafortune 2 lobe(s), no lookup table");
  const std::string name = "cloth plain + rotation, offsets, diffuse, eta";
  const CandidateReport* cloth = FindCandidate(s.selection, name);
  ASSERT_TRUE(lobes && cloth) << SelectionReportText(s.selection);
  EXPECT_TRUE(cloth->converged) << cloth->note;
  ASSERT_GT(cloth->heldout_relative_rms, 0.0);
  EXPECT_LT(cloth->heldout_relative_rms, lobes->heldout_relative_rms)
      << SelectionReportText(s.selection);
  ASSERT_GE(s.selection.chosen, 0);
  ASSERT_EQ(s.selection.candidates[s.selection.chosen].description, name)
      << SelectionReportText(s.selection);
  const ClothParams& whole = std::get<ClothParams>(s.params);
  // The default selection fits the bounded model: what it writes conserves
  // energy on both sides.
  EXPECT_LE(ModelEnergy(s.params).max_albedo, 1.0);
  EXPECT_LE(ModelLightSideEnergy(s.params).max_albedo, 1.0);
  const std::vector<std::string> held = HeldInFolds(s.report);
  ASSERT_FALSE(held.empty());
  const double held_error = RugBFoldError(table, whole, held);
  // The same folds as fit --model auto's.
  EXPECT_NEAR(held_error, cloth->heldout_relative_rms, 1e-6);
  EXPECT_LT(cloth->heldout_relative_rms, 1.5 * cloth->relative_rms)
      << SelectionReportText(s.selection);
}

// The bounded cloth (--energy-bound) settles on CUReT felt, whose weave
// (offsets, rotation, widths free) moves far from the linen preset and
// with it the peaks of the albedo over azimuth that the bound's tables
// hold: it converges, conserves energy on both sides, and fits about as
// well as the paper's model (which reflects more than it receives under
// grazing light). Until the bound's entries followed their crests and
// every peak they had, it did not settle in 4 solves.
TEST(CuretFits, BoundedClothSettlesOnFeltAndConservesEnergy) {
  const fs::path path =
      fs::path(CLOTHFIT_SHARED_DIR) / "data" / "curet" / "curet_01_felt.csv";
  const MeasurementTable table = ReadTable(path.string()).table;
  ClothParams linen;
  ASSERT_TRUE(GetPreset("linen_plain", &linen));
  ClothFitOptions options = testing_util::PaperModel<ClothFitOptions>();
  options.fit_scale = true;
  options.also_free = {"rotation_deg", "offsets_deg", "diffuse"};
  const ClothFitResult paper = FitCloth(table, linen, options);
  options.energy_bound = true;
  const ClothFitResult bounded = FitCloth(table, linen, options);
  ASSERT_TRUE(bounded.report.usable) << bounded.report.message;
  EXPECT_TRUE(bounded.report.converged) << bounded.report.message;
  ASSERT_NE(bounded.params.energy_bound, nullptr);
  EXPECT_NE(bounded.report.energy_bound.find("solve(s)"), std::string::npos);
  EXPECT_LE(bounded.report.max_albedo, 1.0);
  EXPECT_LE(ModelEnergy(bounded.params).max_albedo, 1.0);
  EXPECT_GT(ModelLightSideEnergy(paper.params).max_albedo, 1.0);
  EXPECT_LT(bounded.report.relative_rms, 1.05 * paper.report.relative_rms);
}

}  // namespace
}  // namespace clothfit
