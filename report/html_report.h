// `clothfit report`: one self-contained HTML page (no network access, no
// other file) with the figures of report/fit_figures.h as inline PNG
// (data: URLs), the fit summary and the parameter table with standard
// deviations (the parameter file's "fit" object), the candidates of a
// model selection ("fit.selection"), and an interactive lit sphere: the
// model's GLSL ES 3.00 (export/glsl.h GlslSource) drawn by WebGL 2 with a
// light the reader drags. The page reports its state in <pre
// id="status">: "OK ..." once the sphere is drawn, "ERROR ..." otherwise.
#pragma once

#include <string>

#include "io/params_json.h"
#include "io/table.h"
#include "report/fit_figures.h"

namespace clothfit {

struct ReportInput {
  ParamFile model;
  // Names the model and the table ("P.json against T.csv") in titles.
  std::string label;
  const MeasurementTable* table = nullptr;  // may be null
  PlotOptions options;
};

// The page; `notes` (may be null) gets the figures' notes.
std::string ReportHtml(const ReportInput& input,
                       std::vector<std::string>* notes = nullptr);

// The standard base64 alphabet with '=' padding (RFC 4648, Section 4).
std::string Base64(const std::string& bytes);

// `text` with &, <, >, " as HTML entities.
std::string HtmlEscape(const std::string& text);

}  // namespace clothfit
