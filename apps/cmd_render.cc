// clothfit render: preview renders of a parameter file
// (render/preview.h): the cloth on cylinders in three orientations (the
// paper's Fig. 12), a slab front- and back-lit over a checker, a hole
// texture on tilted panels; a Lafortune parameter mip map (.exr) tiled over
// the cylinders, each pixel reading the level that matches its footprint; with
// --compare, a second file's render below the first at the same exposure.
// Linear EXR (with the model, parameters and command line in its header)
// plus tone-mapped PNG with labels.
#include <cstdio>
#include <filesystem>
#include <vector>

#include "apps/commands.h"
#include "apps/progress.h"
#include "holes/hole_texture.h"
#include "io/atomic_file.h"
#include "io/text_util.h"
#include "models/presets.h"
#include "render/preview.h"

namespace clothfit {
namespace {

// One row of the render: the image (its row title set) and what the EXR's
// header says of it.
struct RenderedRow {
  PreviewImage image;
  std::string model;   // ModelName, or "lafortune mip map"
  std::string params;  // the parameter file as JSON (FormatParamFile)
};

// The render of --FILE_OPTION P.json or --PRESET_OPTION NAME, its row
// titled "ROLE: P.json (MODEL)" or "ROLE: preset NAME (MODEL)" (the top
// row's role: "fit" for a file with a "fit" object or a mip map, else
// "params"; a compare row that is a fit adds ", fitted"); a slab's
// parameters are added to *slabs (for the regime note, once written).
RenderedRow RenderOption(const CommandArgs& args,
                         const std::string& file_option,
                         const std::string& preset_option,
                         const PreviewOptions& options, const char* role,
                         std::vector<SlabParams>* slabs) {
  RenderedRow row;
  std::string title;
  bool fitted = false;  // a file with a "fit" object, or a mip map
  if (args.Has(preset_option)) {
    const ClothParams preset = RequirePreset(args, args.Get(preset_option));
    row.image = RenderCylinders(preset, options);
    row.model = ModelName(ModelParams(preset));
    row.params = FormatParamFile(ParamFile(preset));
    title = std::string(role ? role : "params") + ": preset " +
            args.Get(preset_option);
  } else {
    const std::string path = args.Get(file_option);
    const std::string name = std::filesystem::path(path).filename().string();
    if (text_util::HasExtension(path, ".exr")) {
      row.image = RenderCylinders(MipmapRho(Material::Load(path), options.tile),
                                  options);
      row.model = "lafortune mip map";
      row.params = "";  // the parameters are the texels of the file
      fitted = true;
      title = std::string(role ? role : "fit") + ": " + name;
    } else {
      const ParamFile file = ReadParamFile(path);
      if (std::holds_alternative<HolesModel>(file.params)) {
        row.image = RenderHoles(
            LoadHolesModel(file, path,
                           args.Has("mask") ? args.Get("mask") : ""),
            options);
      } else if (const auto* slab = std::get_if<SlabParams>(&file.params)) {
        slabs->push_back(*slab);
        row.image = RenderSlab(*slab, options);
      } else {
        row.image = RenderCylinders(file.params, options);
      }
      row.model = ModelName(file.params);
      row.params = FormatParamFile(file);
      fitted = !file.fit_json.empty();
      title = std::string(role     ? role
                          : fitted ? "fit"
                                   : "params") +
              ": " + name;
    }
  }
  // The compare row says whether it is a fit (the top row's role does).
  row.image.row_titles = {title + " (" + row.model +
                          (role && fitted ? ", fitted" : "") + ")"};
  return row;
}

// The command line as typed ("clothfit render ..."), arguments with
// blanks or quotes in single quotes.
std::string CommandLine(int argc, char** argv) {
  std::string line = "clothfit";
  for (int i = 1; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool plain =
        !arg.empty() && arg.find_first_of(" \t\n'\"\\$") == std::string::npos;
    line += " " + (plain ? arg : "'" + arg + "'");
  }
  return line;
}

}  // namespace

int RunRender(int argc, char** argv) {
  CommandArgs args(
      "render",
      "clothfit render (--params P.json|P.exr | --preset NAME) [--compare "
      "Q.json | "
      "--compare-preset NAME] --out R.exr [--png R.png] [options]",
      "Preview renders under a point light, orthographic camera: cloth, "
      "thread and Lafortune parameters\n(and Lafortune mip maps, tiled) wrap "
      "cylinders with the warp "
      "vertical, horizontal and diagonal (Sadeghi et al. 2013, Fig. 12); a\n"
      "slab is a tilted panel over a checker, front-lit and back-lit; a holes "
      "file a panel at three\ntilts over a checker. --compare renders a "
      "second file below the first at the same exposure.\nWrites linear "
      "OpenEXR (its header: model, parameters, command line, version) and a "
      "tone-mapped PNG\nwith a label above each row (which file) and panel "
      "(which orientation, an arrow along the\nwarp); render/preview.h "
      "describes the scene.");
  args.Option(
      "params", "P.json",
      "parameter file (docs/formats.md, or holes), or a Lafortune parameter "
      "mip map P.exr");
  args.Option("preset", "NAME", "a preset instead of --params");
  args.Option("compare", "Q.json", "a second parameter file, rendered below");
  args.Option("compare-preset", "NAME", "a preset instead of --compare");
  args.Option("mask", "M.png",
              "the mask of a holes file (default: the file's \"mask\")");
  args.Option("tile", "W",
              "world size of one repeat of a mip map's texture (cylinder "
              "radius 1), (0, 100]",
              "0.8");
  args.Option("out", "R.exr", "linear render (OpenEXR)");
  args.Option("png", "R.png", "tone-mapped render (default: --out as .png)");
  args.Option("size", "N", "pixels per panel side, 8..1024", "192");
  args.Option("light-deg", "THETA,PHI",
              "direction of the light from the camera axis", "45,45");
  args.Option("light-distance", "D", "distance of the light (radius 1)", "6");
  args.Option("tilt-deg", "DEG", "tilt of slab and holes panels, [0, 40]",
              "35");
  args.Option("exposure", "E",
              "multiplier before tone mapping (default: the 99th percentile "
              "maps to 1)");
  if (!args.Parse(argc, argv, 2)) return 0;
  if (args.Has("params") == args.Has("preset")) {
    args.Fail("give exactly one of --params FILE and --preset NAME");
  }
  if (args.Has("compare") && args.Has("compare-preset")) {
    args.Fail("give at most one of --compare FILE and --compare-preset NAME");
  }
  const std::string out = args.Required("out");
  if (out.size() < 5 || !text_util::HasExtension(out, ".exr")) {
    args.Fail("option '--out': must name an .exr file, got '" + out + "'");
  }
  const std::string png = args.Has("png")
                              ? args.Get("png")
                              : out.substr(0, out.size() - 4) + ".png";
  if (!args.Has("png")) args.CheckDerivedOutput("the PNG beside --out", png);
  if (!text_util::HasExtension(png, ".png")) {
    args.Fail("option '--png': must name a .png file, got '" + png + "'");
  }
  PreviewOptions options;
  const long size = args.GetInt("size");
  if (size < 8 || size > 1024)
    args.Fail("option '--size': must be in [8, 1024]");
  options.size = static_cast<int>(size);
  const std::vector<double> light = NumberListOption(args, "light-deg");
  if (light.size() != 2 || !(light[0] >= 0.0 && light[0] < 90.0)) {
    args.Fail("option '--light-deg': expected THETA,PHI with THETA in [0, 90)");
  }
  const double theta = Radians(light[0]), phi = Radians(light[1]);
  options.light = glm::dvec3(std::sin(theta) * std::cos(phi),
                             std::sin(theta) * std::sin(phi), std::cos(theta));
  options.light_distance = args.GetDouble("light-distance");
  if (!(options.light_distance >= 2.0 && options.light_distance <= 1e6)) {
    args.Fail("option '--light-distance': must be in [2, 1e6]");
  }
  options.tilt_deg = args.GetDouble("tilt-deg");
  if (!(options.tilt_deg >= 0.0 && options.tilt_deg <= 40.0)) {
    args.Fail("option '--tilt-deg': must be in [0, 40]");
  }
  options.tile = args.GetDouble("tile");
  if (!(options.tile > 0.0 && options.tile <= 100.0)) {
    args.Fail("option '--tile': must be in (0, 100]");
  }
  CheckWritable(out);
  CheckWritable(png);
  std::vector<SlabParams> slabs;
  const RenderedRow top = [&] {
    const progress::Activity activity("render");
    return RenderOption(args, "params", "preset", options, nullptr, &slabs);
  }();
  PreviewImage image = top.image;
  // The EXR's header: what was rendered and how (docs/renderer.md).
  std::vector<ExrAttribute> header = {
      {"clothfit:version", CLOTHFIT_VERSION},
      {"clothfit:command", CommandLine(argc, argv)},
      {"clothfit:model", top.model},
      {"clothfit:params", top.params},
      {"clothfit:rows", image.row_titles[0]}};
  if (args.Has("compare") || args.Has("compare-preset")) {
    const RenderedRow compare = [&] {
      const progress::Activity activity("render: the comparison");
      return RenderOption(args, "compare", "compare-preset", options, "compare",
                          &slabs);
    }();
    image = StackRows(image, compare.image);
    header.push_back({"clothfit:compare_model", compare.model});
    header.push_back({"clothfit:compare_params", compare.params});
    header[4].second += "\n" + compare.image.row_titles[0];
  }
  double exposure = AutoExposure(image);
  if (args.Has("exposure")) {
    exposure = args.GetDouble("exposure");
    if (!(exposure > 0.0 && std::isfinite(exposure))) {
      args.Fail("option '--exposure': must be > 0");
    }
  }
  header.push_back({"clothfit:exposure", text_util::FormatNumber(exposure)});
  WritePreview(image, exposure, out, png, header);
  std::printf("wrote %s (%d x %d) and %s (with labels), exposure %.4g\n",
              out.c_str(), image.width, image.height, png.c_str(), exposure);
  // docs/models.md: the tool says where the slab model is inexact.
  for (const SlabParams& slab : slabs) NoteSlabRegime(slab);
  return 0;
}

}  // namespace clothfit
