// clothfit fit --model auto: the model family a fabric's table supports,
// chosen by held-out error (fitting/fabric_select.h). Writes the chosen
// fit to --out and the table of candidates beside it.
#include <iostream>
#include <sstream>

#include "apps/commands.h"
#include "fitting/fabric_select.h"
#include "io/atomic_file.h"
#include "io/text_util.h"

namespace clothfit {
namespace {

// P.json -> P.candidates.csv (other names: NAME.candidates.csv).
std::string CandidatesPath(const std::string& out) {
  const std::string stem = text_util::HasExtension(out, ".json")
                               ? out.substr(0, out.size() - 5)
                               : out;
  return stem + ".candidates.csv";
}

std::string CandidatesCsv(const SelectionReport& r) {
  std::ostringstream out;
  out.precision(6);
  out << "candidate,free_parameters,relative_rms,heldout_relative_rms,bic,"
         "seconds,converged,chosen,note\n";
  for (size_t i = 0; i < r.candidates.size(); ++i) {
    const CandidateReport& c = r.candidates[i];
    std::string note = c.note;
    for (char& ch : note) {
      if (ch == '"') ch = '\'';
    }
    out << '"' << c.description << "\"," << c.free_parameters << ","
        << c.relative_rms << ",";
    if (c.heldout_relative_rms >= 0.0) out << c.heldout_relative_rms;
    out << "," << c.bic << "," << c.seconds << ","
        << (c.converged ? "yes" : "no") << ","
        << (static_cast<int>(i) == r.chosen ? "yes" : "no") << ",\"" << note
        << "\"\n";
  }
  return out.str();
}

}  // namespace

int RunFitAuto(const CommandArgs& args, const SolverOptions& solver) {
  for (const char* option :
       {"init", "preset", "generic-start", "tolerance", "fix", "free",
        "also-free", "design-points", "starts", "truth", "per-channel-tau"}) {
    if (args.Has(option)) {
      args.Fail(std::string("--") + option +
                " is not available with --model auto (it fits each "
                "candidate with its defaults)");
    }
  }
  FabricSelectOptions options;
  options.solver = solver;
  options.fit_scale = args.Has("fit-scale");
  options.energy_bound = !args.Has("paper-model");
  if (args.Has("folds")) {
    const long k = args.GetInt("folds");
    if (k < 2 || k > 100) args.Fail("option '--folds': must be in [2, 100]");
    options.folds = static_cast<int>(k);
  }
  options.progress = solver.progress;
  const MeasurementTable table = ReadDataOption(args);
  WarnArbitraryScale(args, table);
  const std::string candidates = CandidatesPath(args.Get("out"));
  CheckWritable(candidates);
  const FabricSelection s = SelectFabricModel(table, options);
  WriteFileAtomically(candidates, CandidatesCsv(s.selection));
  FitExtras extras;
  extras.text = SelectionReportText(s.selection) + "candidates written to " +
                candidates + "\n\n";
  extras.json.emplace_back("selection", SelectionReportJson(s.selection));
  return FinishFit(args, s.params, s.report, {}, extras);
}

}  // namespace clothfit
