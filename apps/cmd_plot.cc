// clothfit plot: the figures of a model against a measurement table
// (report/fit_figures.h; docs/plots.md says what each shows).
#include <cstdio>
#include <filesystem>

#include "apps/commands.h"
#include "io/atomic_file.h"
#include "io/text_util.h"
#include "report/fit_figures.h"

namespace clothfit {
namespace {

std::string FigureList() {
  std::string list;
  for (const std::string& name : kFigureNames) {
    list += (list.empty() ? "" : ",") + name;
  }
  return list;
}

bool EndsWith(const std::string& s, const std::string& end) {
  return s.size() >= end.size() &&
         s.compare(s.size() - end.size(), end.size(), end) == 0;
}

}  // namespace

void AddPlotOptions(CommandArgs* args) {
  args->Option("params", "P.json", "parameter file (docs/formats.md)");
  args->Option("preset", "NAME", "a preset instead of --params");
  args->Option("data", "T.csv", "measurement table (docs/formats.md)");
  args->Option("incidence-deg", "LIST",
               "incidence angles of the polar panels, comma-separated",
               "0,30,60");
  args->Option("phi-deg", "PHI", "azimuth of the polar panels' plane", "0");
  args->Option("window-deg", "W",
               "how far measured rows may lie from a polar panel", "5");
}

PlotOptions ReadPlotOptions(const CommandArgs& args) {
  PlotOptions options;
  options.phi_deg = args.GetDouble("phi-deg");
  options.window_deg = args.GetDouble("window-deg");
  if (!(options.window_deg > 0.0 && options.window_deg < 90.0)) {
    args.Fail("option '--window-deg': must be in (0, 90)");
  }
  options.incidence_deg = NumberListOption(args, "incidence-deg");
  for (const double deg : options.incidence_deg) {
    if (!(deg >= 0.0 && deg < 90.0)) {
      args.Fail("option '--incidence-deg': " + text_util::FormatNumber(deg) +
                " is not an angle in [0, 90)");
    }
  }
  // Four panels a row: more would not be readable.
  constexpr size_t kMaxPanels = 16;
  if (options.incidence_deg.size() > kMaxPanels) {
    args.Fail("option '--incidence-deg': at most " +
              std::to_string(kMaxPanels) + " angles (a panel each), got " +
              std::to_string(options.incidence_deg.size()));
  }
  return options;
}

std::string PlotLabel(const CommandArgs& args) {
  auto name = [&](const std::string& option) {
    return std::filesystem::path(args.Get(option)).filename().string();
  };
  const std::string model =
      args.Has("preset") ? "preset " + args.Get("preset") : name("params");
  return model + (args.Has("data") ? " against " + name("data") : "");
}

ParamFile LoadPlotInputs(const CommandArgs& args,
                         std::optional<MeasurementTable>* table) {
  if (args.Has("data")) {
    *table = ReadTableOption(args, args.Get("data"));
    if ((*table)->quantity == Quantity::kTransmittance) {
      args.Fail(args.Get("data") +
                ": the figures draw reflection, not transmittance");
    }
  }
  return LoadEvaluableModel(
      args, *table ? (*table)->quantity : Quantity::kBrdf,
      *table ? args.Get("data") : std::string("the figures (BRDF)"));
}

void PrintNotes(const std::vector<std::string>& notes) {
  for (const std::string& note : notes)
    std::fprintf(stderr, "%s\n", note.c_str());
}

int RunPlot(int argc, char** argv) {
  CommandArgs args(
      "plot",
      "clothfit plot (--params P.json | --preset NAME) [--data T.csv] --out "
      "DIR/|PREFIX|P.png [--figures LIST] [--incidence-deg LIST] [--phi-deg "
      "PHI] [--window-deg W]",
      "Draws a model against a measurement table, one PNG per figure:\n"
      "  scatter    model against measured, every row (log axes for a wide "
      "range)\n"
      "  residuals  relative residual of every row against theta_i, theta_o "
      "and the phase angle\n"
      "  polar      per incidence, the slice in the plane of incidence at "
      "azimuth PHI (curve)\n"
      "             and the rows within W of it (dots), \"N of M rows\" per "
      "panel\n"
      "  halfdiff   the model over theta_h, theta_d (Rusinkiewicz) at phi_d = "
      "90 deg\n"
      "  sphere     a sphere under one directional light, seen "
      "orthographically\n"
      "  albedo     the directional albedo a(theta_o) at phi_o = 0, 45, 90 "
      "deg\n"
      "--out DIR/ (or an existing folder) writes DIR/NAME.png; another "
      "PREFIX writes PREFIX_NAME.png;\n"
      "--out P.png writes only the polar figure to P.png. The first three "
      "need --data\n(without it they are skipped with a note). See "
      "docs/plots.md.");
  AddPlotOptions(&args);
  args.Option("out", "DIR/|PREFIX|P.png", "where the figures go");
  args.Option("figures", "LIST", "figures to draw, comma-separated",
              FigureList());
  // --out names a folder or a prefix: each figure's file is checked below.
  args.Files({"data", "params"}, {});
  if (!args.Parse(argc, argv, 2)) return 0;
  const std::string out = args.Required("out");
  const bool single_polar = EndsWith(out, ".png");
  std::vector<std::string> figures = ListOption(args, "figures");
  for (const std::string& name : figures) {
    if (std::find(kFigureNames.begin(), kFigureNames.end(), name) ==
        kFigureNames.end()) {
      args.Fail("option '--figures': unknown figure '" + name + "'" +
                text_util::DidYouMean(name, kFigureNames) + " (one of " +
                FigureList() + ")");
    }
  }
  if (single_polar && args.Has("figures")) {
    args.Fail("option '--figures': --out " + out +
              " is the single polar figure; give a folder (DIR/) or a prefix "
              "for several");
  }
  if (single_polar) figures = {"polar"};
  for (const std::string& name : figures) {
    if (FigureNeedsData(name) && !args.Has("data") &&
        (args.Has("figures") || single_polar)) {
      args.Fail("figure '" + name + "' needs a table: give --data T.csv");
    }
  }
  const PlotOptions options = ReadPlotOptions(args);
  std::optional<MeasurementTable> table;
  const ParamFile model = LoadPlotInputs(args, &table);
  // Where each figure goes; each checked before any is drawn.
  const bool folder = !single_polar && (EndsWith(out, "/") ||
                                        std::filesystem::is_directory(out));
  auto path_of = [&](const std::string& name) {
    if (single_polar) return out;
    if (folder) return (std::filesystem::path(out) / (name + ".png")).string();
    return out + "_" + name + ".png";
  };
  if (folder) {
    std::error_code error;
    std::filesystem::create_directories(out, error);
    if (error)
      args.Fail(out + ": cannot create the folder: " + error.message());
  }
  for (const std::string& name : figures) {
    if (FigureNeedsData(name) && !args.Has("data")) continue;
    args.CheckDerivedOutput("the " + name + " figure", path_of(name));
  }
  const WrittenFigures written =
      WriteFitFigures(model.params, PlotLabel(args), table ? &*table : nullptr,
                      figures, options, path_of);
  for (const auto& [name, path] : written.files) {
    std::printf("wrote %s\n", path.c_str());
  }
  PrintNotes(written.notes);
  // docs/models.md: the tool says where the slab model is inexact.
  if (const auto* slab = std::get_if<SlabParams>(&model.params)) {
    NoteSlabRegime(*slab);
  }
  return 0;
}

}  // namespace clothfit
