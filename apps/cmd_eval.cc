// clothfit eval: a model's values at the directions of a table (SPEC §5).
#include "apps/commands.h"

namespace clothfit {

int RunEval(int argc, char** argv) {
  CommandArgs args(
      "eval",
      "clothfit eval --params P.json --dirs D.csv --out O.csv "
      "[--quantity brdf|cosine_weighted]",
      "Evaluates the model of P.json at every direction pair of D.csv and "
      "writes D's rows with the model's r,g,b.\nD.csv is a measurement table "
      "(SPEC §2); its value columns, if any, are ignored.\nFor a thread model "
      "the directions are in the thread frame (tangent +x, normal +z).\nA "
      "slab gives f_r or f_t (wo on the far side), and for a transmittance "
      "table D the direct transmittance.");
  args.Option("params", "P.json", "parameter file (SPEC §4)");
  args.Option("preset", "NAME", "a preset instead of --params");
  args.Option("dirs", "D.csv", "directions (a measurement table)");
  args.Option("out", "O.csv", "output table");
  args.Option("quantity", "Q", "brdf or cosine_weighted", "brdf");
  if (!args.Parse(argc, argv, 2)) return 0;
  const ParamFile model = LoadModelOption(args);
  const Quantity quantity = ModelQuantityOption(args, "quantity");
  const std::string out_path = args.Required("out");
  ReadTableOptions read_options;
  read_options.values_optional = true;
  MeasurementTable table = ReadTable(args.Required("dirs"), read_options).table;
  if (table.quantity != Quantity::kTransmittance) {
    table.quantity = quantity;
  } else if (!ModelPredicts(model.params, Quantity::kTransmittance)) {
    args.Fail(args.Get("dirs") +
              ": a transmittance table has no incident directions to "
              "evaluate a BRDF at");
  }
  table.channels = 3;
  table.has_sigma = false;
  table.SetMeta("model", ModelName(model.params));
  for (TableRow& row : table.rows) {
    row.value = Evaluate(model.params, row.wi, row.wo, table.quantity);
    row.sigma = glm::dvec3(1.0);
  }
  WriteTable(table, out_path);
  if (const auto* slab = std::get_if<SlabParams>(&model.params)) {
    if (table.quantity != Quantity::kTransmittance) NoteSlabRegime(*slab);
  }
  return 0;
}

}  // namespace clothfit
