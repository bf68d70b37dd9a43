// The solver's options of the fit commands (clothfit fit, holes fit):
// --loss, --max-iterations, --threads, --linear-solver and the noise model
// (docs/cli.md).
#include <cmath>
#include <string>

#include "apps/commands.h"
#include "apps/progress.h"
#include "io/text_util.h"

namespace clothfit {

void AddSolverOptions(CommandArgs* args, const SolverOptions& defaults,
                      bool robust_loss, const std::string& threads_help,
                      const std::string& noise_default) {
  if (robust_loss) {
    args->Option("loss", "L", "robust loss: none, huber or cauchy", "none");
    args->Option("loss-scale", "S", "robust loss scale, in sigmas",
                 text_util::FormatNumber(defaults.loss_scale, 6));
  }
  args->Option("max-iterations", "N",
               "solver iteration cap (per solve), 1 to " +
                   std::to_string(kMaxSolverIterations),
               std::to_string(defaults.max_iterations));
  args->Option(
      "threads", "N",
      threads_help + ", 0 (every core) to " + std::to_string(kMaxSolverThreads),
      std::to_string(defaults.num_threads));
  args->Option("linear-solver", "S",
               "linear solver of the solver's steps: " + LinearSolverNames(),
               LinearSolverName(defaults.linear_solver));
  args->Option("noise", "M",
               "noise model of the values: table (the sigma column), "
               "relative (sigma = F max(|value|, floor)) or absolute "
               "(sigma = F); default: " +
                   noise_default,
               "");
  args->Option("noise-level", "F",
               "the noise level F (relative: a fraction of the value; "
               "absolute: sigma); default: estimated from the residuals",
               "");
  args->Option("noise-floor", "X",
               "relative noise: values below X weigh as X; default: 1 % of "
               "the median |value| per channel",
               "");
}

SolverOptions ReadSolverOptions(const CommandArgs& args, bool robust_loss) {
  SolverOptions s;
  if (robust_loss) {
    const std::string loss = args.Get("loss");
    if (loss == "none") {
      s.loss = Loss::kNone;
    } else if (loss == "huber") {
      s.loss = Loss::kHuber;
    } else if (loss == "cauchy") {
      s.loss = Loss::kCauchy;
    } else {
      args.Fail("option '--loss': expected none, huber or cauchy, got '" +
                loss + "'");
    }
    s.loss_scale = args.GetDouble("loss-scale");
    if (!(s.loss_scale > 0.0)) args.Fail("option '--loss-scale': must be > 0");
  }
  const long iterations = args.GetInt("max-iterations");
  if (iterations < 1 || iterations > kMaxSolverIterations) {
    args.Fail("option '--max-iterations': must be in [1, " +
              std::to_string(kMaxSolverIterations) + "]");
  }
  s.max_iterations = static_cast<int>(iterations);
  const long threads = args.GetInt("threads");
  if (threads < 0 || threads > kMaxSolverThreads) {
    args.Fail("option '--threads': must be in [0, " +
              std::to_string(kMaxSolverThreads) + "]");
  }
  s.num_threads = static_cast<int>(threads);
  const std::string name = args.Get("linear-solver");
  if (!ParseLinearSolver(name, &s.linear_solver)) {
    args.Fail("option '--linear-solver': expected " + LinearSolverNames() +
              ", got '" + name + "'");
  }
  if (args.Has("noise")) {
    const std::string noise = args.Get("noise");
    if (noise == "table") {
      s.noise.kind = NoiseKind::kTable;
    } else if (noise == "relative") {
      s.noise.kind = NoiseKind::kRelative;
    } else if (noise == "absolute") {
      s.noise.kind = NoiseKind::kAbsolute;
    } else {
      args.Fail(
          "option '--noise': expected table, relative or absolute, "
          "got '" +
          noise + "'");
    }
  }
  if (args.Has("noise-level")) {
    s.noise.level = args.GetDouble("noise-level");
    if (!(s.noise.level > 0.0) || !std::isfinite(s.noise.level)) {
      args.Fail("option '--noise-level': must be > 0");
    }
    if (s.noise.kind == NoiseKind::kTable) {
      args.Fail(
          "option '--noise-level': the noise model 'table' takes the "
          "sigma column as it is");
    }
  }
  if (args.Has("noise-floor")) {
    s.noise.floor = args.GetDouble("noise-floor");
    if (!(s.noise.floor > 0.0) || !std::isfinite(s.noise.floor)) {
      args.Fail("option '--noise-floor': must be > 0");
    }
    if (s.noise.kind != NoiseKind::kRelative &&
        s.noise.kind != NoiseKind::kDefault) {
      args.Fail(
          "option '--noise-floor': only the relative noise model has "
          "a floor");
    }
  }
  // The work starts: the input's warnings, then a progress line on a
  // terminal.
  auto task = std::make_shared<progress::Task>("fit", "");
  s.progress = [task](const std::string& what) {
    progress::FlushWarnings();
    task->Say(what);
  };
  return s;
}

}  // namespace clothfit
