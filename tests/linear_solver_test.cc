// The linear solver knob (fitting/linear_solver.h): names parse
// and unknown ones are rejected (library and `fit --linear-solver`), and
// the thread, slab and Lafortune fits recover the same parameters with
// every solver.
#include "fitting/linear_solver.h"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <string>
#include <vector>

#include "fitting/lafortune_fit.h"
#include "fitting/lafortune_mip.h"
#include "fitting/slab_fit.h"
#include "fitting/thread_fit.h"
#include "models/presets.h"
#include "tests/cli_test_util.h"
#include "tests/fit_test_util.h"
#include "tests/io_test_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;
using testing_util::ExpectBadInput;
using testing_util::NoisyTable;

constexpr double kNoiseFreeTolerance = 1e-4;  // relative, per parameter

void ExpectNear(const std::vector<double>& fitted,
                const std::vector<double>& truth, const std::string& what) {
  ASSERT_EQ(fitted.size(), truth.size());
  for (size_t i = 0; i < truth.size(); ++i) {
    EXPECT_NEAR(fitted[i], truth[i],
                kNoiseFreeTolerance * std::max(1e-3, std::abs(truth[i])))
        << what << ", entry " << i;
  }
}

TEST(LinearSolver, NamesRoundTripAndUnknownOnesAreRejected) {
  const std::vector<LinearSolver> all = AllLinearSolvers();
  ASSERT_EQ(all.size(), 4u);
  for (LinearSolver s : all) {
    LinearSolver parsed = LinearSolver::kDenseQr;
    const std::string name = LinearSolverName(s);
    ASSERT_TRUE(ParseLinearSolver(name, &parsed)) << name;
    EXPECT_EQ(parsed, s) << name;
    EXPECT_NE(LinearSolverNames().find(name), std::string::npos) << name;
  }
  LinearSolver unchanged = LinearSolver::kDenseNormalCholesky;
  for (const char* bad : {"", "svd", "dense_svd", "DENSE_QR", "cgnr"}) {
    EXPECT_FALSE(ParseLinearSolver(bad, &unchanged)) << bad;
  }
  EXPECT_EQ(unchanged, LinearSolver::kDenseNormalCholesky);
}

TEST(LinearSolver, ThreadFitsRecoverTheTruthWithEverySolver) {
  ClothParams satin;
  ASSERT_TRUE(GetPreset("polyester_satin_charmeuse", &satin));
  const ThreadParams truth = satin.threads[0].params;
  const MeasurementTable table = NoisyTable(truth, 0.0, 7, 600);
  std::vector<double> want(FlatSize(truth));
  ToArray(truth, want.data());
  for (LinearSolver s : AllLinearSolvers()) {
    ThreadFitOptions options = testing_util::PaperModel<ThreadFitOptions>();
    options.solver.linear_solver = s;
    const ThreadFitResult r = FitThread(table, options);
    EXPECT_TRUE(r.report.converged) << LinearSolverName(s) << r.report.message;
    std::vector<double> got(FlatSize(r.params));
    ToArray(r.params, got.data());
    ExpectNear(got, want, "thread, " + LinearSolverName(s));
  }
}

TEST(LinearSolver, SlabFitsRecoverTheTruthWithEverySolver) {
  SlabParams truth;
  truth.tau = glm::dvec3(0.05);
  truth.albedo = glm::dvec3(0.4, 0.3, 0.2);
  const MeasurementTable table = NoisyTable(truth, 0.0, 11, 600);
  std::vector<double> want(FlatSize(truth));
  ToArray(truth, want.data());
  for (LinearSolver s : AllLinearSolvers()) {
    SlabFitOptions options;
    options.solver.linear_solver = s;
    const SlabFitResult r = FitSlab({table}, options);
    EXPECT_TRUE(r.report.converged) << LinearSolverName(s) << r.report.message;
    std::vector<double> got(FlatSize(r.params));
    ToArray(r.params, got.data());
    ExpectNear(got, want, "slab, " + LinearSolverName(s));
  }
}

// A one-lobe Lafortune model without lookup table, sampled noise-free at
// 8 x 8 lights x 8 x 8 views.
TEST(LinearSolver, LafortuneFitsRecoverTheTruthWithEverySolver) {
  LafortuneParams truth;
  truth.diffuse = {0.12, 0.08, 0.05};  // plausible: albedo < 1
  LafortuneLobe lobe;
  lobe.cx = {-0.9, -0.8, -0.7};
  lobe.cy = {-0.8, -0.8, -0.9};
  lobe.cz = {0.9, 0.95, 1.0};
  lobe.n = {8, 12, 15};
  truth.lobes = {lobe};
  const std::vector<glm::dvec3> dirs = testing_util::Hemisphere(8);
  LafortuneModel model;
  model.params = truth;
  const MeasurementTable table =
      testing_util::LafortuneTable(model, dirs, dirs);
  std::vector<size_t> rows(table.rows.size());
  for (size_t i = 0; i < rows.size(); ++i) rows[i] = i;
  const TexelSamples samples =
      CollectSamples(table, LafortuneWeighting(table, NoiseModel()),
                     ViewIndex(table), rows, nullptr);
  for (LinearSolver s : AllLinearSolvers()) {
    LafortuneFitOptions options;
    options.lobes = 1;
    options.lookup_table = false;
    options.function_tolerance = 1e-12;
    options.max_iterations = 200;
    options.linear_solver = s;
    const LafortuneFitResult r = FitLafortune(samples, options);
    ASSERT_TRUE(r.report.usable) << LinearSolverName(s) << r.report.message;
    ASSERT_EQ(r.params.params.lobes.size(), 1u);
    for (int c = 0; c < 3; ++c) {
      const LafortuneLobe& got = r.params.params.lobes[0];
      ExpectNear(
          {r.params.params.diffuse[c], got.cx[c], got.cy[c], got.cz[c],
           got.n[c]},
          {truth.diffuse[c], lobe.cx[c], lobe.cy[c], lobe.cz[c], lobe.n[c]},
          "lafortune, " + LinearSolverName(s));
    }
  }
}

// fit --linear-solver: an unknown name is bad input naming the option, for
// the least-squares fits and the Lafortune fit alike.
TEST(LinearSolver, CommandLineRejectsUnknownSolversWithExitStatus2) {
  const fs::path dir = testing_util::FreshTestDir("linear_solver_test_");
  const std::string table = (dir / "t.csv").string();
  ASSERT_EQ(testing_util::RunClothfit(dir, {"synth", "--preset", "velvet",
                                            "--rows", "50", "--out", table})
                .status,
            0);
  const std::string out = (dir / "p.json").string();
  for (const char* model : {"thread", "lafortune"}) {
    ExpectBadInput(dir,
                   {"fit", "--model", model, "--data", table, "--linear-solver",
                    "dense_svd", "--out", out},
                   {"--linear-solver", "dense_svd", "dense_qr"});
  }
}

}  // namespace
}  // namespace clothfit
