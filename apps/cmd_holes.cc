// clothfit holes analyze|eval|truth and clothfit fit --model holes:
// semi-transparent textures with thickness (David-Babin 2022; docs/models.md;
// docs/holes.md).
#include <chrono>
#include <cstdio>
#include <cstdlib>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "apps/holes_options.h"
#include "apps/progress.h"
#include "bench/hole_charts.h"
#include "data_synthetic/holes_truth.h"
#include "data_synthetic/synthetic_table.h"
#include "fitting/holes_fit.h"
#include "holes/hole_texture.h"
#include "io/atomic_file.h"
#include "io/hole_exr.h"
#include "io/input_error.h"
#include "io/mask_io.h"
#include "io/params_json.h"
#include "io/text_util.h"

namespace clothfit {
namespace {

constexpr char kHolesUsage[] =
    "usage: clothfit holes analyze|eval|truth|tile [options]   (clothfit holes "
    "CMD --help)\n\n"
    "  analyze   counts of walls, triangles and opaque texels of a mask, "
    "their mip pyramid as OpenEXR\n"
    "  eval      transmittance of a mask with thickness (Algorithm 3.1 or "
    "the extension); charts\n"
    "  truth     ground-truth transmittance by ray traversal of the texel "
    "grid\n"
    "  tile      a holes parameter file with its mask's tile, which "
    "renderers load without the mask\n";

// The model and the directions it is evaluated at (eval, truth).
void AddModelOptions(CommandArgs* args) {
  args->Option("thickness", "H", "thickness h in texel widths");
  args->Option("wall-color", "C",
               "fraction of light reaching a wall that passes: C or R,G,B",
               "0");
  args->Option("params", "P.json", "a holes parameter file instead");
  args->Option("dirs", "D.csv", "view directions (a table)");
  args->Option("out", "O.csv", "transmittance table");
}

glm::dvec3 WallColorOption(const CommandArgs& args) {
  const std::vector<std::string> parts = ListOption(args, "wall-color");
  std::vector<double> values;
  for (const std::string& part : parts) {
    char* end = nullptr;
    values.push_back(std::strtod(part.c_str(), &end));
    if (*end != '\0') values.back() = -1.0;
  }
  if (values.size() == 1) values.resize(3, values[0]);
  if (values.size() != 3) {
    args.Fail("option '--wall-color': expected C or R,G,B");
  }
  return glm::dvec3(values[0], values[1], values[2]);
}

// The holes parameters of the file of option `option`.
HolesParams HolesParamsOption(const CommandArgs& args,
                              const std::string& option) {
  const std::string path = args.Get(option);
  return ModelOf<HolesModel>(ReadParamFile(path), path).params;
}

HolesParams ModelOption(const CommandArgs& args) {
  HolesParams params;
  if (args.Has("params") == args.Has("thickness")) {
    args.Fail("give exactly one of --thickness H and --params P.json");
  }
  if (args.Has("params")) return HolesParamsOption(args, "params");
  params.thickness_texels = args.GetDouble("thickness");
  params.wall_color = WallColorOption(args);
  const std::string invalid = ValidateParams(params);
  if (!invalid.empty()) args.Fail(invalid);
  return params;
}

// A transmittance table of the directions of --dirs (only wo is used).
MeasurementTable DirectionsTable(const CommandArgs& args) {
  ReadTableOptions options;
  options.values_optional = true;
  MeasurementTable table =
      ReadTableOption(args, args.Required("dirs"), options);
  table.quantity = Quantity::kTransmittance;
  table.has_sigma = table.has_weight = table.has_alpha = false;
  return table;
}

// Fills the table with the transmittance at each row's view, one channel
// when the wall colour is grey, and names the model in its metadata.
void FillTable(
    const CommandArgs& args, const HolesParams& params,
    const std::function<glm::dvec3(const glm::dvec3&)>& transmittance,
    MeasurementTable* table) {
  const glm::dvec3& c = params.wall_color;
  table->channels = c.x == c.y && c.y == c.z ? 1 : 3;
  table->SetMeta("model", "holes");
  table->SetMeta("mask", args.Get("mask"));
  table->SetMeta(kHolesThickness.name,
                 text_util::FormatNumber(params.thickness_texels));
  for (TableRow& row : table->rows) {
    row.value = transmittance(row.wo);
    row.sigma = glm::dvec3(1.0);
  }
}

std::string CsvBeside(const CommandArgs& args, const std::string& option) {
  const std::string png = args.Get(option);
  if (png.size() < 5 || !text_util::HasExtension(png, ".png")) {
    args.Fail("option '--" + option + "': the chart is a .png file");
  }
  const std::string csv = png.substr(0, png.size() - 4) + ".csv";
  args.CheckDerivedOutput("the CSV beside --" + option, csv);
  return csv;
}

std::vector<double> NumberList(const CommandArgs& args,
                               const std::string& option) {
  std::vector<double> out;
  for (const std::string& part : ListOption(args, option)) {
    char* end = nullptr;
    out.push_back(std::strtod(part.c_str(), &end));
    if (*end != '\0' || !(out.back() > 0.0) || out.back() > 1e4) {
      args.Fail("option '--" + option + "': expected positive numbers, got '" +
                part + "'");
    }
  }
  if (out.empty()) args.Fail("option '--" + option + "': empty list");
  return out;
}

int RunAnalyze(int argc, char** argv) {
  CommandArgs args(
      "holes analyze",
      "clothfit holes analyze --mask M.png --out C.exr [--distances D.exr] "
      "[--threshold T] [--source S] [--invert]",
      "Counts, per texel of a tiling mask, the walls (opaque neighbours "
      "top=+y, left, bottom, right), the triangles\n(opaque diagonal "
      "neighbours: the number of the two texels between that are not "
      "opaque) and the opaque texels\n(David-Babin 2022, Algorithm 3.1), "
      "sums them over 2 x 2 blocks down to 1 x 1, and writes the pyramid as "
      "a\ntiled, mip-mapped OpenEXR with nine channels and a JSON index "
      "(C.exr.json). --distances also writes the\nextension's run counts "
      "(8 directions x 8 distances; docs/holes.md).");
  AddMaskOptions(&args);
  args.Option("out", "C.exr", "the count pyramid (nine channels)");
  args.Option("distances", "D.exr", "also the run-count pyramid");
  if (!args.Parse(argc, argv, 3)) return 0;
  const std::string out = args.Required("out");
  const auto t0 = std::chrono::steady_clock::now();
  const Mask mask = LoadMask(args);
  const HoleTexture texture = [&] {
    const progress::Activity activity("holes analyze: counting the mask");
    return AnalyzeMask(mask, args.Has("distances"));
  }();
  const double seconds =
      std::chrono::duration<double>(std::chrono::steady_clock::now() - t0)
          .count();
  const nlohmann::ordered_json metadata = {
      {"mask", args.Get("mask")},
      {"threshold", args.GetDouble("threshold")},
      {"source", args.Get("source")},
      {"invert", args.Has("invert")},
      {"axes",
       "x = image column (right = +x), y = image row (top = +y = the next "
       "row)"},
      {"texels",
       "T = base texels summed: 4^level, or the block's area (ROUND_DOWN) "
       "when the size is not a power of two"}};
  WriteCountPyramid(texture.counts, CountKind::kHoleCounts, metadata.dump(),
                    out);
  if (args.Has("distances")) {
    WriteCountPyramid(texture.distances, CountKind::kHoleDistances,
                      metadata.dump(), args.Get("distances"));
  }
  const CountPyramid& c = texture.counts;
  const HoleTexel top = HoleTexelAt(c, c.levels() - 1, 0, 0);
  std::printf(
      "mask %s: %d x %d texels, %.4g opaque, %d levels (%.3f s)\n"
      "walls top/left/bottom/right: %.0f %.0f %.0f %.0f\n"
      "triangles topRight/topLeft/bottomLeft/bottomRight: %.0f %.0f %.0f "
      "%.0f\nwrote %s\n",
      args.Get("mask").c_str(), mask.width, mask.height, mask.OpaqueFraction(),
      c.levels(), seconds, top.counts[kWallTop], top.counts[kWallLeft],
      top.counts[kWallBottom], top.counts[kWallRight],
      top.counts[kTriangleTopRight], top.counts[kTriangleTopLeft],
      top.counts[kTriangleBottomLeft], top.counts[kTriangleBottomRight],
      out.c_str());
  if (args.Has("distances"))
    std::printf("wrote %s\n", args.Get("distances").c_str());
  return 0;
}

int RunErrorMap(const CommandArgs& args) {
  ErrorMapOptions options;
  options.hole_sizes.clear();
  for (double s : NumberList(args, "hole-sizes")) {
    if (s != static_cast<int>(s) || s > 64) {
      args.Fail("option '--hole-sizes': expected integers in [1, 64]");
    }
    options.hole_sizes.push_back(static_cast<int>(s));
  }
  options.thicknesses = NumberList(args, "thicknesses");
  const long samples = args.GetInt("samples");
  if (samples < 1 || samples > 256) {
    args.Fail("option '--samples': must be in [1, 256]");
  }
  options.truth_samples = static_cast<int>(samples);
  const std::string csv = CsvBeside(args, "error-map");
  WriteErrorMap(ComputeErrorMap(options), args.Get("error-map"), csv);
  std::printf("wrote %s and %s\n", args.Get("error-map").c_str(), csv.c_str());
  return 0;
}

int RunHolesEval(int argc, char** argv) {
  CommandArgs args(
      "holes eval",
      "clothfit holes eval --mask M.png (--thickness H | --params P.json) "
      "(--dirs D.csv --out O.csv | --chart C.png)\n"
      "       clothfit holes eval --error-map E.png [--hole-sizes LIST] "
      "[--thicknesses LIST]",
      "Transmittance of a tiling mask whose opaque texels are columns of "
      "height h, seen along the view directions wo of\nD.csv (a table; "
      "values ignored): rho_transparent + wall_color rho_occluded of the "
      "whole tile (mean over the\ntexels of --level) by Algorithm 3.1 "
      "(David-Babin 2022) or its extension to holes wider than one texel.\n"
      "--chart: transmittance vs view angle (both methods and the ground "
      "truth) as C.png and C.csv.\n--error-map: their RMS error over hole "
      "size x thickness for square holes (E.png, E.csv; no mask).");
  AddMaskOptions(&args);
  AddModelOptions(&args);
  AddMethodOptions(&args);
  args.Option("chart", "C.png", "transmittance vs view angle chart");
  args.Option("azimuth", "DEG", "chart: azimuth of the views", "0");
  args.Option("rays", "N", "chart: ground-truth rays per view", "1000000");
  args.Option("error-map", "E.png", "error map over hole size x thickness");
  const ErrorMapOptions defaults;
  std::string sizes, thicknesses;
  for (int size : defaults.hole_sizes) {
    sizes += (sizes.empty() ? "" : ",") + std::to_string(size);
  }
  for (double h : defaults.thicknesses) {
    char text[32];
    std::snprintf(text, sizeof(text), "%s%g", thicknesses.empty() ? "" : ",",
                  h);
    thicknesses += text;
  }
  args.Option("hole-sizes", "LIST", "error map: square hole sizes", sizes);
  args.Option("thicknesses", "LIST", "error map: thicknesses h", thicknesses);
  args.Option("samples", "N", "error map: truth rays per texel side", "32");
  if (!args.Parse(argc, argv, 3)) return 0;
  if (args.Has("error-map")) return RunErrorMap(args);
  if (args.Has("chart") == args.Has("dirs")) {
    args.Fail("give one of --dirs (with --out), --chart or --error-map");
  }
  const HolesParams params = ModelOption(args);
  const HoleMethod method = MethodOption(args);
  const Mask mask = LoadMask(args);
  // The run counts (64 per texel) only where the extension is evaluated.
  const HoleTexture texture =
      AnalyzeMask(mask, method == HoleMethod::kExtension || args.Has("chart"));
  const int level = LevelOption(args, texture);
  if (args.Has("chart")) {
    const std::string csv = CsvBeside(args, "chart");
    const long rays = args.GetInt("rays");
    // 1e7 rays a view take ~3.6 s for the chart: 1e8 is minutes.
    if (rays < 1 || rays > 100000000) {
      args.Fail("option '--rays': must be in [1, 1e8]");
    }
    std::vector<double> thetas;
    for (double t = 0.0; t <= 85.0; t += 2.5) thetas.push_back(t);
    const AngleCurve curve =
        TransmittanceVsAngle(mask, texture, params.thickness_texels,
                             args.GetDouble("azimuth"), thetas, level, rays);
    char title[256];
    std::snprintf(title, sizeof(title), "%s, h = %g, azimuth %g deg",
                  args.Get("mask").c_str(), params.thickness_texels,
                  curve.azimuth_deg);
    WriteAngleChart(curve, title, args.Get("chart"), csv);
    std::printf("wrote %s and %s\n", args.Get("chart").c_str(), csv.c_str());
    return 0;
  }
  const std::string out = args.Required("out");
  MeasurementTable table = DirectionsTable(args);
  const HolesTile tile = HolesTileOf(texture, method, level);
  FillTable(
      args, params,
      [&](const glm::dvec3& wo) {
        return HolesTransmittance(params, tile, wo);
      },
      &table);
  table.SetMeta("method", HoleMethodName(method));
  table.SetMeta("level", std::to_string(level));
  WriteTable(table, out);
  return 0;
}

int RunTruth(int argc, char** argv) {
  CommandArgs args(
      "holes truth",
      "clothfit holes truth --mask M.png (--thickness H | --params P.json) "
      "--dirs D.csv --out O.csv [--rays N] [--noise F --seed S]",
      "Ground-truth transmittance of a tiling mask with columns of height h "
      "at the view directions wo of D.csv: rays\nland on a grid over the "
      "tile and are traced exactly through the texel grid (2D DDA, any "
      "offset); the table\nholds rho_transparent + wall_color "
      "rho_occluded. --noise F multiplies each value by 1 + F N(0, 1) and "
      "sets sigma = F max(value, 0.01).");
  AddMaskOptions(&args);
  AddModelOptions(&args);
  args.Option("rays", "N", "rays per view over the tile", "1000000");
  args.Option("noise", "F", "relative noise standard deviation, >= 0", "0");
  args.Option("seed", "S", "random seed (integer)", "1");
  if (!args.Parse(argc, argv, 3)) return 0;
  const HolesParams params = ModelOption(args);
  const std::string out = args.Required("out");
  const long rays = args.GetInt("rays");
  const double noise = args.GetDouble("noise");
  if (rays < 1 || rays > 100000000) {
    args.Fail("option '--rays': must be in [1, 1e8]");
  }
  if (!(noise >= 0.0)) args.Fail("option '--noise': must be >= 0");
  const Mask mask = LoadMask(args);
  MeasurementTable table = DirectionsTable(args);
  // Rays of all views together: 1e9 is some minutes on this machine.
  if (static_cast<double>(rays) * table.rows.size() > 1e9) {
    args.Fail("option '--rays': " + std::to_string(rays) +
              " rays for each of " + std::to_string(table.rows.size()) +
              " views is more than 1e9 in all");
  }
  const Footprint tile = TileFootprint(mask, rays);
  const progress::Activity activity("holes truth: tracing rays");
  FillTable(
      args, params,
      [&](const glm::dvec3& wo) {
        return TransmittanceOfRatios(
            params,
            HoleTruth(mask, ViewOffset(params.thickness_texels, wo), tile));
      },
      &table);
  table.SetMeta("method", "truth (2D DDA)");
  if (noise > 0.0) {
    // Transmittance lies in [0, 1]: sigma is floored at 1 % of full scale
    // so that views with no light left keep a finite weight.
    Random random(static_cast<uint64_t>(args.GetInt("seed")));
    AddMultiplicativeNoise(noise, glm::dvec3(0.01), &random, &table);
  }
  WriteTable(table, out);
  return 0;
}

}  // namespace

int RunHoles(int argc, char** argv) {
  const std::string sub = argc >= 3 ? argv[2] : "";
  if (sub == "analyze") return RunAnalyze(argc, argv);
  if (sub == "eval") return RunHolesEval(argc, argv);
  if (sub == "truth") return RunTruth(argc, argv);
  if (sub == "tile") return RunHolesTile(argc, argv);
  if (sub == "--help" || sub == "-h" || sub == "help") {
    std::cout << kHolesUsage;
    return 0;
  }
  // One line, like every usage error.
  std::cerr << "error: "
            << (sub.empty() ? std::string("clothfit holes needs a subcommand")
                            : "unknown holes subcommand '" + sub + "'")
            << " (analyze, eval, truth or tile; see 'clothfit holes --help')\n";
  return 2;
}

int RunFitHoles(int argc, char** argv) {
  CommandArgs args(
      "fit",
      "clothfit fit --model holes --data T.csv --mask M.png --out P.json "
      "[--init P.json | --thickness H] [--fit-wall-color] [options]",
      "Fits the thickness h (and with --fit-wall-color the wall colour) of a "
      "mask whose opaque texels are columns of\nheight h to a transmittance "
      "table (quantity: transmittance; only wo is used): model = "
      "rho_transparent +\nwall_color rho_occluded of the whole tile (Algorithm "
      "3.1 or the extension). Ceres with automatic derivatives from\na grid "
      "of starting thicknesses; writes the parameters with a \"fit\" object "
      "(standard deviations).\nExit status 1 when the fit reaches no usable "
      "solution or does not converge.");
  args.Option("model", "M", "holes");
  args.Option("data", "T.csv", "transmittance table (docs/formats.md)");
  AddMaskOptions(&args);
  args.Option("out", "P.json", "result parameter file");
  args.Option("init", "P.json", "initial parameters (a holes file)");
  args.Option("thickness", "H", "initial thickness instead of --init");
  args.Flag("fit-wall-color", "also fit the wall colour");
  args.Option("fix", "A,B", "parameters held fixed");
  args.Option("free", "A,B", "free only these parameters");
  AddMethodOptions(&args);
  AddSolverOptions(&args, SolverOptions(), true,
                   "threads for residual evaluation");
  args.Option("truth", "P.json", "print these true values beside the fit");
  args.Flag("skip-invalid", "drop invalid table rows (reports how many)");
  if (!args.Parse(argc, argv, 2)) return 0;
  const std::string out = args.Required("out");
  CheckWritable(out);  // before the fit, not after
  HolesFitOptions options;
  options.solver = ReadSolverOptions(args, true);
  const HoleMethod method = MethodOption(args);
  options.fit_wall_color = args.Has("fit-wall-color");
  options.fix = ListOption(args, "fix");
  options.free_only = ListOption(args, "free");
  if (args.Has("init") && args.Has("thickness")) {
    args.Fail("give at most one of --init and --thickness");
  }
  if (args.Has("init")) options.init = HolesParamsOption(args, "init");
  if (args.Has("thickness")) {
    options.init = HolesParams();
    options.init->thickness_texels = args.GetDouble("thickness");
  }
  const MeasurementTable table = ReadDataOption(args);
  const Mask mask = LoadMask(args);
  const HoleTexture texture =
      AnalyzeMask(mask, method == HoleMethod::kExtension);
  const HolesTile tile =
      HolesTileOf(texture, method, LevelOption(args, texture));
  std::vector<double> truth;
  if (args.Has("truth")) {
    const HolesParams p = HolesParamsOption(args, "truth");
    truth.resize(FlatSize(p));
    ToArray(p, truth.data());
  }
  const HolesFitResult fit = FitHoles(table, tile, options);
  ParamFile file;
  file.params = HolesModel{fit.params, StorableTile(tile)};
  if (!std::get<HolesModel>(file.params).tile) {
    std::cerr << "warning: the tile has " << tile.texels.counts.size()
              << " texels (a file holds at most " << kMaxStoredTileTexels
              << "): " << out
              << " holds none, so readers need its mask (renderers cannot "
                 "load it; a higher --level can be stored)\n";
  }
  file.holes.path = args.Get("mask");
  file.holes.threshold = args.GetDouble("threshold");
  file.holes.method = method;
  return FinishFit(fit.report, truth, out, [&](const std::string& fit_json) {
    file.fit_json = fit_json;
    WriteParamFile(file, out);
  });
}

}  // namespace clothfit
