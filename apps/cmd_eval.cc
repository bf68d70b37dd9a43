// clothfit eval: a model's values at the directions of a table (docs/cli.md),
// or a Lafortune parameter mip map's at the texels of the table's rows.
#include <optional>
#include <string>

#include "api/material.h"
#include "apps/commands.h"
#include "apps/progress.h"
#include "io/input_error.h"
#include "io/text_util.h"

namespace clothfit {
namespace {

// --params P.exr: the Lafortune parameter mip map (api/material.h) at each
// row's texel (s, t) of --level, as the table's quantity (brdf or
// cosine_weighted). Nothing is written when a row's texel is outside the
// level.
void EvaluateMipmap(const CommandArgs& args, MeasurementTable* table) {
  const std::string params = args.Get("params");
  const std::string dirs = args.Get("dirs");
  if (!table->has_texels) {
    throw InputError(dirs + ": no s,t columns: a parameter mip map (" + params +
                     ") is evaluated at each row's texel (s, t)");
  }
  const Material material = Material::Load(params);
  const long level = args.GetInt("level");
  if (level < 0 || level >= material.Levels()) {
    args.Fail("option '--level': " + params + " has levels 0 to " +
              std::to_string(material.Levels() - 1) + ", got " +
              args.Get("level"));
  }
  const int l = static_cast<int>(level);
  const int width = material.Width(l), height = material.Height(l);
  for (TableRow& row : table->rows) {
    if (row.s >= width || row.t >= height) {
      throw InputError(
          FormatLocation(dirs, row.source_line, 0) + ": texel (s, t) = (" +
          std::to_string(row.s) + ", " + std::to_string(row.t) +
          ") is outside level " + std::to_string(l) + " of " + params + " (" +
          std::to_string(width) + " x " + std::to_string(height) + " texels)");
    }
    // Material takes (s, t) in [0, 1]^2: the centre of texel i of n is
    // (i + 0.5) / n.
    const double s = (row.s + 0.5) / width;
    const double t = (row.t + 0.5) / height;
    row.value = table->quantity == Quantity::kBrdf
                    ? material.F(row.wi, row.wo, s, t, l)
                    : material.Rho(row.wi, row.wo, s, t, l);
  }
  table->SetMeta("model", material.Kind());
  table->SetMeta("level", std::to_string(l));
}

}  // namespace

int RunEval(int argc, char** argv) {
  CommandArgs args(
      "eval",
      "clothfit eval --params P.json --dirs D.csv --out O.csv "
      "[--quantity brdf|cosine_weighted]\n"
      "       clothfit eval --params P.exr --dirs D.csv [--level L] --out "
      "O.csv [--quantity brdf|cosine_weighted]",
      "Evaluates the model of P.json at every direction pair of D.csv and "
      "writes D's rows with the model's r,g,b.\nD.csv is a measurement table "
      "(docs/formats.md); its value columns, if any, are ignored.\nFor a "
      "thread model "
      "the directions are in the thread frame (tangent +x, normal +z).\nA "
      "slab gives f_r or f_t (wo on the far side), and for a transmittance "
      "table D the direct transmittance.\nP.exr, a Lafortune parameter mip "
      "map (fit --model lafortune on a table with s,t columns), is evaluated\n"
      "at each row's texel: D needs s,t columns, texel indices of level L.");
  args.Option("params", "P.json",
              "parameter file (docs/formats.md) or mip map P.exr");
  args.Option("preset", "NAME", "a preset instead of --params");
  args.Option("dirs", "D.csv", "directions (a measurement table)");
  args.Option("out", "O.csv", "output table");
  args.Option("quantity", "Q", "brdf or cosine_weighted", "brdf");
  args.Option("level", "L", "P.exr: the mip level that s,t index", "0");
  if (!args.Parse(argc, argv, 2)) return 0;
  const bool mipmap =
      args.Has("params") && text_util::HasExtension(args.Get("params"), ".exr");
  if (mipmap && args.Has("preset")) {
    args.Fail("give exactly one of --params FILE and --preset NAME");
  }
  if (!mipmap && args.Has("level")) {
    args.Fail("--level goes with a parameter mip map (--params P.exr)");
  }
  const Quantity quantity = ModelQuantityOption(args, "quantity");
  const std::string out_path = args.Required("out");
  ReadTableOptions read_options;
  read_options.values_optional = true;
  MeasurementTable table =
      ReadTableOption(args, args.Required("dirs"), read_options);
  // A transmittance table is evaluated as such; any other as --quantity.
  if (table.quantity != Quantity::kTransmittance) table.quantity = quantity;
  if (mipmap && table.quantity == Quantity::kTransmittance) {
    args.Fail(args.Get("dirs") +
              ": a transmittance table has no incident directions to "
              "evaluate a BRDF at");
  }
  std::optional<ParamFile> model;
  if (!mipmap) {
    model = LoadEvaluableModel(args, table.quantity, args.Get("dirs"));
  }
  table.channels = 3;
  table.has_sigma = false;
  if (mipmap) {
    EvaluateMipmap(args, &table);
  } else {
    table.SetMeta("model", ModelName(model->params));
    progress::Task task("eval", "rows");
    const size_t rows = table.rows.size();
    for (size_t i = 0; i < rows; ++i) {
      TableRow& row = table.rows[i];
      row.value = Evaluate(model->params, row.wi, row.wo, table.quantity);
      if (i % 4096 == 4095) task.Update(i + 1.0, rows);
    }
    task.Update(rows, rows);
  }
  for (TableRow& row : table.rows) row.sigma = glm::dvec3(1.0);
  WriteTableWithProgress(table, out_path);
  if (model) {
    if (const auto* slab = std::get_if<SlabParams>(&model->params)) {
      if (table.quantity != Quantity::kTransmittance) NoteSlabRegime(*slab);
    }
  }
  return 0;
}

}  // namespace clothfit
