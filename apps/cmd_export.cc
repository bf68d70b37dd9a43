// clothfit export --format gltf: a fitted model, a preset or a measured
// table as a glTF 2.0 cloth (export/gltf.h) whose material, the glTF
// metallic-roughness base under KHR_materials_sheen (models/sheen.h), is
// fitted to the source (fitting/sheen_conversion.h); the error the
// conversion leaves is printed and stored in the material's extras.
#include <cmath>
#include <cstdio>
#include <filesystem>
#include <iostream>
#include <nlohmann/json.hpp>
#include <string>

#include "apps/commands.h"
#include "apps/progress.h"
#include "export/glsl.h"
#include "export/gltf.h"
#include "fitting/sheen_conversion.h"
#include "io/atomic_file.h"
#include "io/lafortune_mipmap.h"
#include "io/param_mipmap.h"
#include "io/text_util.h"

namespace clothfit {

namespace {

// --format glsl: the model's GLSL with its parameters (export/glsl.h).
int ExportGlsl(const CommandArgs& args) {
  if (args.Has("data")) args.Fail("--format glsl exports a model, not a table");
  const std::string out = args.Required("out");
  CheckWritable(out);
  const std::string filter_name = args.Get("filter");
  TexelFilter filter = TexelFilter::kNearest;
  if (filter_name == "bilinear") {
    filter = TexelFilter::kBilinear;
  } else if (filter_name == "trilinear") {
    filter = TexelFilter::kTrilinear;
  } else if (filter_name != "nearest") {
    args.Fail(
        "option '--filter': expected nearest, bilinear or trilinear, got '" +
        filter_name + "'");
  }
  if (args.Has("params") &&
      text_util::HasExtension(args.Get("params"), ".exr")) {
    // A texture map: the GLSL and its parameter texture array beside it.
    const ParamMipmap mipmap = ReadParamMipmap(args.Get("params"));
    std::vector<LafortuneTexelMap> levels;
    for (size_t l = 0; l < mipmap.levels.size(); ++l) {
      LafortuneTexelMap level;
      level.width = mipmap.levels[l].width;
      level.height = mipmap.levels[l].height;
      level.texels = LevelFromParamMipmap(mipmap, static_cast<int>(l));
      levels.push_back(std::move(level));
    }
    const std::vector<glm::dvec3> views =
        levels.empty() || levels[0].texels.empty()
            ? std::vector<glm::dvec3>()
            : levels[0].texels[0].lut.views;
    const GlslMap map = GlslMapSource(levels, views, filter);
    const std::filesystem::path out_path(out);
    const std::string bin =
        (out_path.parent_path() / (out_path.stem().string() + ".params.bin"))
            .string();
    CheckOutputsDistinct({{"--out", out}, {"the parameters", bin}},
                         {{"--params", args.Get("params")}});
    WriteFileAtomically(
        bin, std::string(reinterpret_cast<const char*>(map.texels.data()),
                         map.texels.size() * sizeof(float)));
    WriteFileAtomically(out, map.source);
    std::printf(
        "wrote %s (a %zu-level texture map: clothfit_f_map, clothfit_rho_map)\n"
        "wrote %s (the parameter array: %d layers of RGBA float32)\n",
        out.c_str(), levels.size(), bin.c_str(), map.layers);
    return 0;
  }
  const ParamFile file = LoadModelOption(args);
  WriteFileAtomically(out, GlslSource(file.params));
  std::printf("wrote %s (%s model: clothfit_f, clothfit_rho)\n", out.c_str(),
              ModelName(file.params));
  return 0;
}

// --format gltf of a Lafortune parameter mip map: one glTF material per
// texel of --level, fitted on a 5 x 8 direction grid (1,600 pairs per
// texel), as the four textures of the material (export/gltf.h
// SheenTextures); the error is that of the 8-bit textures.
int ExportGltfMap(const CommandArgs& args, int grid, const std::string& out) {
  const ParamMipmap mipmap = ReadParamMipmap(args.Get("params"));
  const long level = args.GetInt("level");
  if (level < 0 || level >= static_cast<long>(mipmap.levels.size())) {
    args.Fail("option '--level': the map has levels 0.." +
              std::to_string(mipmap.levels.size() - 1));
  }
  const int width = mipmap.levels[level].width;
  const int height = mipmap.levels[level].height;
  const std::vector<LafortuneModel> texels =
      LevelFromParamMipmap(mipmap, static_cast<int>(level));
  constexpr int kPolar = 5, kAzimuth = 8;
  NoiseModel absolute;
  absolute.kind = NoiseKind::kAbsolute;
  std::vector<SheenParams> fitted;
  int not_converged = 0;
  progress::Task task("export", "texels");
  for (const LafortuneModel& texel : texels) {
    const SheenConversion c =
        ConvertToSheen(ReflectionGrid(texel, kPolar, kAzimuth), absolute);
    fitted.push_back(c.params);
    not_converged += c.report.converged ? 0 : 1;
    task.Update(fitted.size(), texels.size());
  }
  std::vector<SheenParams> quantized;
  GltfMaterial material;
  material.name = "texture map";
  material.textures = SheenTextures(fitted, width, height, &quantized);
  material.sheen.base_color = material.sheen.sheen_color = glm::dvec3(1.0);
  material.sheen.roughness = material.sheen.sheen_roughness = 1.0;
  double diff2 = 0.0, data2 = 0.0;
  for (size_t i = 0; i < texels.size(); ++i) {
    AddGridError(texels[i], quantized[i], kPolar, kAzimuth, &diff2, &data2);
  }
  const double relative_rms = data2 > 0.0 ? std::sqrt(diff2 / data2) : 0.0;
  const nlohmann::ordered_json extras = {
      {"clothfit",
       {{"source", args.Get("params")},
        {"source_model", "lafortune_mipmap"},
        {"level", level},
        {"texels", texels.size()},
        {"conversion",
         {{"quantity", "cosine_weighted"},
          {"rows", texels.size() * kPolar * kAzimuth * kPolar * kAzimuth},
          {"relative_rms", relative_rms},
          {"texels_not_converged", not_converged}}}}}};
  material.extras_json = extras.dump();
  const std::vector<std::string> written =
      WriteGltf(ClothMesh(grid), material, out);
  std::printf(
      "%s level %ld (%d x %d texels) as glTF sheen textures\n"
      "conversion error: relative rms %.4g over %zu texels (8-bit textures; "
      "%d texel fit(s) not converged)\n",
      args.Get("params").c_str(), level, width, height, relative_rms,
      texels.size(), not_converged);
  for (const std::string& f : written) std::printf("wrote %s\n", f.c_str());
  if (not_converged > 0) {
    std::cerr << "error: " << not_converged
              << " texel fit(s) did not converge (parameters at a search "
                 "limit)\n";
    return 1;
  }
  return 0;
}

}  // namespace

int RunExport(int argc, char** argv) {
  CommandArgs args(
      "export",
      "clothfit export --format gltf (--params P.json | --preset NAME | "
      "--data T.csv) --out FILE.gltf|FILE.glb\n       clothfit export "
      "--format glsl (--params P.json | --preset NAME) --out FILE.glsl",
      "Writes a glTF 2.0 cloth (a draped sheet) whose material - the "
      "metallic-roughness base (metallic 0)\nunder KHR_materials_sheen - is "
      "fitted to the source: a parameter file's or a preset's reflectance\n"
      "on a grid of 108 x 108 directions (rho = f cos), or a measured table. "
      "The error the conversion\nleaves is printed and stored in the "
      "material's extras (docs/renderer.md).\nglsl: GLSL ES 3.00 functions "
      "clothfit_f and clothfit_rho of a thread, cloth, lafortune or slab\n"
      "model with its parameters as constants.");
  args.Option("format", "F", "gltf or glsl", "gltf");
  args.Option("params", "P.json", "a fitted model (any reflection model)");
  args.Option("preset", "NAME", "a preset fabric instead");
  args.Option("data", "T.csv", "a measured table instead");
  args.Option("out", "FILE.gltf", ".gltf (+ .bin beside it) or .glb");
  args.Option("grid", "N", "quads per side of the sheet", "48");
  args.Option("level", "L", "gltf of a texture map: the mip level", "0");
  args.Option("filter", "F",
              "glsl of a texture map: nearest, bilinear or trilinear",
              "nearest");
  if (!args.Parse(argc, argv, 2)) return 0;
  const std::string format = args.Get("format");
  if (format == "glsl") return ExportGlsl(args);
  if (format != "gltf") {
    args.Fail("option '--format': expected gltf or glsl, got '" + format + "'");
  }
  const std::string out = args.Required("out");
  if (!text_util::HasExtension(out, ".gltf") &&
      !text_util::HasExtension(out, ".glb")) {
    args.Fail("option '--out': a glTF file ends in .gltf or .glb");
  }
  const int sources =
      args.Has("params") + args.Has("preset") + args.Has("data");
  if (sources != 1) {
    args.Fail("give exactly one of --params, --preset and --data");
  }
  const long grid = args.GetInt("grid");
  if (grid < 1 || grid > 1024)
    args.Fail("option '--grid': must be in [1, 1024]");
  CheckWritable(out);
  std::string source, source_model;
  SheenConversion conversion;
  if (args.Has("data")) {
    const MeasurementTable table = ReadDataOption(args);
    source = args.Get("data");
    source_model = "measured table";
    const progress::Activity activity("export: fitting the sheen");
    conversion = ConvertToSheen(table, NoiseModel());
  } else {
    if (args.Has("params") &&
        text_util::HasExtension(args.Get("params"), ".exr")) {
      return ExportGltfMap(args, static_cast<int>(grid), out);
    }
    const ParamFile file = LoadModelOption(args);
    source = args.Has("params") ? args.Get("params") : args.Get("preset");
    source_model = ModelName(file.params);
    NoiseModel absolute;
    absolute.kind = NoiseKind::kAbsolute;
    const progress::Activity activity("export: fitting the sheen");
    conversion = ConvertToSheen(ReflectionGrid(file.params), absolute);
  }
  const SheenParams& s = conversion.params;
  nlohmann::ordered_json extras = {
      {"clothfit",
       {{"source", source},
        {"source_model", source_model},
        {"conversion",
         {{"quantity", conversion.quantity},
          {"rows", conversion.rows},
          {"relative_rms", conversion.relative_rms},
          {"rms", conversion.rms},
          {"converged", conversion.report.converged}}}}}};
  GltfMaterial material;
  material.name =
      source_model == "measured table" ? "measured cloth" : source_model;
  material.sheen = s;
  material.extras_json = extras.dump();
  const std::vector<std::string> written =
      WriteGltf(ClothMesh(static_cast<int>(grid)), material, out);
  std::printf(
      "%s (%s) as glTF sheen: base_color %.4g %.4g %.4g, roughness %.4g, "
      "sheen_color %.4g %.4g %.4g, sheen_roughness %.4g\n"
      "conversion error: relative rms %.4g (rms %.4g) over %d rows of %s\n",
      source.c_str(), source_model.c_str(), s.base_color.x, s.base_color.y,
      s.base_color.z, s.roughness, s.sheen_color.x, s.sheen_color.y,
      s.sheen_color.z, s.sheen_roughness, conversion.relative_rms,
      conversion.rms, conversion.rows, conversion.quantity.c_str());
  for (const std::string& f : written) std::printf("wrote %s\n", f.c_str());
  if (!conversion.report.converged) {
    std::cerr << "error: the material's fit did not converge ("
              << conversion.report.termination
              << "): " << conversion.report.message << "\n";
    return 1;
  }
  return 0;
}

}  // namespace clothfit
