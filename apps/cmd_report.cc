// clothfit report: one self-contained HTML page of a fit
// (report/html_report.h).
#include <cstdio>

#include "apps/commands.h"
#include "io/atomic_file.h"
#include "report/html_report.h"

namespace clothfit {

int RunReport(int argc, char** argv) {
  CommandArgs args(
      "report",
      "clothfit report (--params P.json | --preset NAME) [--data T.csv] "
      "--out R.html [--incidence-deg LIST] [--phi-deg PHI] [--window-deg W]",
      "Writes one self-contained HTML page (no other file, no network): the "
      "figures of\n`clothfit plot` (inline PNG), the fit summary and the "
      "parameters with their standard\ndeviations from the parameter file's "
      "\"fit\" object, the candidates of a model\nselection, and a lit "
      "sphere drawn by WebGL 2 from the model's GLSL with a draggable\n"
      "light. See docs/plots.md.");
  AddPlotOptions(&args);
  args.Option("out", "R.html", "the page");
  if (!args.Parse(argc, argv, 2)) return 0;
  const std::string out = args.Required("out");
  CheckWritable(out);
  ReportInput input;
  input.options = ReadPlotOptions(args);
  std::optional<MeasurementTable> table;
  input.model = LoadPlotInputs(args, &table);
  if (table) input.table = &*table;
  input.label = PlotLabel(args);
  std::vector<std::string> notes;
  const std::string html = ReportHtml(input, &notes);
  WriteFileAtomically(out, html);
  std::printf("wrote %s\n", out.c_str());
  PrintNotes(notes);
  return 0;
}

}  // namespace clothfit
