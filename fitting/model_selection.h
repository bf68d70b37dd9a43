// "Model no more than the data need": fits a ladder of simpler
// configurations and keeps the simplest whose relative RMS error meets a
// tolerance, reporting every candidate tried with its error and BIC.
//
// Cloth candidates, simplest first: fewer tangent samples T (threads with
// a tangent curve are resampled at T = 1, 2, 4, ... up to their sample
// count), kd fixed to 0 or 1 for every thread, one albedo shared by all
// threads; complexity = number of free parameters, then T. Thread
// candidates: kd fixed to 0, to 1, or free. Candidates are fitted in order
// of complexity and the search stops at the first that meets the
// tolerance (later ones are more complex); none meeting it, the full model
// is kept and the report says so.
#pragma once

#include <string>
#include <vector>

#include "fitting/cloth_fit.h"
#include "fitting/thread_fit.h"

namespace clothfit {

struct CandidateReport {
  std::string description;  // e.g. "T=2, kd=0, shared albedo"
  int free_parameters = 0;
  int samples = 0;  // total tangent samples (cloth); < 0: none (printed -)
  double relative_rms = 0.0;
  // Bayesian information criterion, chi2 + k ln(n) with sigma given,
  // n ln(RSS / n) + k ln(n) otherwise; lower is better.
  double bic = 0.0;
  // The pooled relative RMS on held-out rows (k-fold over lights,
  // fitting/lafortune_select.h); < 0: not computed.
  double heldout_relative_rms = -1.0;
  bool usable = false;
  bool meets_tolerance = false;
  // The whole-table fit's wall time and whether it converged (< 0: not
  // recorded; fitting/fabric_select.h records both).
  double seconds = -1.0;
  bool converged = false;
  // Why a usable candidate was not eligible (e.g. "lobes[1] collapsed"),
  // or "".
  std::string note;
};

struct SelectionReport {
  double tolerance = 0.0;
  std::vector<CandidateReport> candidates;  // in the order tried
  int chosen = -1;                          // index into candidates
  std::string reason;
};

// The BIC with the noise level unknown, n ln(RSS / n) + k ln n (RSS
// floored at 1e-300): k free parameters, n residuals.
double BicOfRss(double rss, double n, int k);

std::string SelectionReportText(const SelectionReport& report);
std::string SelectionReportJson(const SelectionReport& report);

struct ClothSelection {
  ClothFitResult fit;
  ClothParams params;  // the chosen configuration (its weave may differ)
  SelectionReport report;
};

// `c` with each thread's tangent curve sampled at T = t points where the
// thread has more offsets than that and a valid curve (the ladder's
// tangent-sample variants); *changed (may be null) tells whether any was.
ClothParams ResampleTangentCurves(const ClothParams& c, int t, bool* changed);

ClothSelection SelectClothModel(const MeasurementTable& table,
                                const ClothParams& init,
                                const ClothFitOptions& options,
                                double tolerance);

struct ThreadSelection {
  ThreadFitResult fit;
  SelectionReport report;
};

ThreadSelection SelectThreadModel(const MeasurementTable& table,
                                  const ThreadFitOptions& options,
                                  double tolerance);

}  // namespace clothfit
