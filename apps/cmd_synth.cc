// clothfit synth: synthetic measurement tables from parameters (docs/cli.md).
#include <iomanip>
#include <sstream>

#include "apps/commands.h"
#include "apps/full_binary.h"
#include "apps/progress.h"
#include "data_synthetic/synthetic_table.h"
#include "data_synthetic/virtual_gonio.h"
#include "io/image_stack.h"
#include "io/input_error.h"
#include "io/text_util.h"
#include "models/bounded.h"

namespace clothfit {

namespace {

// clothfit synth --gonio PATTERN: the virtual gonioreflectometer.
int RunGonio(const CommandArgs& args) {
  VirtualGonioOptions options;
  if (!ParseWeavePattern(args.Get("gonio"), &options.pattern)) {
    args.Fail("option '--gonio': expected plain, satin or knit, got '" +
              args.Get("gonio") + "'");
  }
  const long texels = args.GetInt("texels");
  const long directions = args.GetInt("directions");
  if (texels < 1 || texels > 1024)
    args.Fail("option '--texels': must be in [1, 1024]");
  if (directions < 1 || directions > 64) {
    args.Fail("option '--directions': must be in [1, 64]");
  }
  const long supersample = args.GetInt("supersample");
  if (supersample < 1 || supersample > 16) {
    args.Fail("option '--supersample': must be in [1, 16]");
  }
  options.texels = static_cast<int>(texels);
  options.directions = static_cast<int>(directions);
  options.supersample = static_cast<int>(supersample);
  options.glossy = args.GetDouble("glossy");
  options.gap = args.GetDouble("gap");
  options.seed = static_cast<uint64_t>(args.GetInt("seed"));
  if (args.Has("stack") == args.Has("out")) {
    args.Fail("--gonio writes one table: give --out T.csv or --stack M.csv");
  }
#ifdef CLOTHFIT_LIGHT
  if (args.Has("stack")) RunInFullBinary();  // images
#endif
  progress::Task task("synth", "texels");
  options.progress = [&task](int done, int total) { task.Update(done, total); };
  const MeasurementTable table = MeasureVirtualGonio(options);
  if (args.Has("stack")) {
    const std::string ext = args.Get("image-ext");
    if (ext != ".exr" && ext != ".png" && ext != ".tif" && ext != ".tiff") {
      args.Fail("option '--image-ext': expected .exr, .png or .tif");
    }
#ifndef CLOTHFIT_LIGHT
    WriteImageStack(table, args.Get("stack"), ext, true);
#endif
  } else {
    WriteTableWithProgress(table, args.Required("out"));
  }
  return 0;
}

}  // namespace

int RunSynth(int argc, char** argv) {
  // The slab has tables of its own (apps/cmd_synth_slab.cc).
  const std::string model_name = ModelArgument(argc, argv);
  if (model_name == "slab") return RunSynthSlab(argc, argv);
  if (!model_name.empty()) {
    throw InputError(
        "clothfit synth: option '--model': only slab is chosen "
        "this way (other models: --params or --preset)");
  }
  CommandArgs args(
      "synth",
      "clothfit synth (--params P.json | --preset NAME) --out T.csv "
      "[--rows N] [--noise F] [--seed S] [--dirs D.csv] [--quantity Q]\n"
      "       clothfit synth --gonio plain|satin|knit [--texels S] "
      "[--directions N] [--supersample K] [--seed S] (--out T.csv | --stack "
      "M.csv)\n"
      "       clothfit synth --model slab ... (see clothfit synth --model "
      "slab --help)",
      "Writes a synthetic measurement table: the model's values at random "
      "directions (uniform in solid angle,\n5 % of rows at grazing 89.9 deg) "
      "or at the directions of D.csv, with multiplicative Gaussian noise.\n"
      "With --noise the table gets sigma = noise * clean value per channel. "
      "Thread models write thread-frame\ntables (wi above, wo anywhere on the "
      "sphere); cloth models reflection tables. Deterministic from --seed.");
  args.Option("params", "P.json", "parameter file (docs/formats.md)");
  args.Option("preset", "NAME", "a preset instead of --params");
  args.Option("out", "T.csv", "output table");
  args.Option("rows", "N", "number of random direction pairs", "2000");
  args.Option("noise", "F", "relative noise standard deviation, >= 0", "0");
  args.Option("seed", "S", "random seed (integer)", "1");
  args.Option("dirs", "D.csv", "use these directions instead of random ones");
  args.Option("max-theta-deg", "DEG",
              "largest polar angle of random directions, (0, 90]", "90");
  args.Option("quantity", "Q", "brdf or cosine_weighted", "brdf");
  args.Flag("energy-bound",
            "thread, cloth: draw the bounded model, which conserves energy on "
            "both sides (the default, what fit fits; a file's own bound is "
            "kept)");
  args.Flag("paper-model",
            "thread, cloth: draw the paper's model instead (what fit "
            "--paper-model fits; a file's bound is dropped)");
  args.Option("gonio", "PATTERN",
              "virtual gonioreflectometer over woven micro-geometry: plain, "
              "satin or knit (instead of a model)");
  args.Option("texels", "S", "gonio: S x S texels", "8");
  args.Option("directions", "N", "gonio: N x N light and view directions", "8");
  args.Option("supersample", "K",
              "gonio: K x K rays per texel and direction (footprint average)",
              std::to_string(VirtualGonioOptions().supersample));
  args.Option("glossy", "W",
              "gonio: weight of the glossy term, in [0, 1] (the diffuse term "
              "has 1 - W)",
              text_util::FormatNumber(VirtualGonioOptions().glossy));
  args.Option("gap", "G",
              "gonio: space between threads in tile units (0: no holes)",
              text_util::FormatNumber(VirtualGonioOptions().gap));
  args.Option("stack", "M.csv",
              "gonio: write an image stack (manifest) "
              "instead of --out");
  args.Option("image-ext", "EXT", "gonio stack image format", ".exr");
  // --stack is a manifest written here (one read by fit).
  args.Files({"params", "dirs"}, {"out", "stack"});
  if (!args.Parse(argc, argv, 2)) return 0;
  if (args.Has("gonio")) return RunGonio(args);
  SynthOptions options;
  options.quantity = ModelQuantityOption(args, "quantity");
  ParamFile model =
      LoadEvaluableModel(args, options.quantity, "option '--quantity'");
  {
    auto* thread = std::get_if<ThreadParams>(&model.params);
    auto* cloth = std::get_if<ClothParams>(&model.params);
    for (const char* flag : {"energy-bound", "paper-model"}) {
      if (args.Has(flag) && !thread && !cloth) {
        args.Fail(std::string("--") + flag +
                  " is for the thread and cloth models");
      }
    }
    if (args.Has("energy-bound") && args.Has("paper-model")) {
      args.Fail("--paper-model and --energy-bound exclude each other");
    }
    if (args.Has("paper-model")) {
      if (thread) thread->energy_bound = nullptr;
      if (cloth) cloth->energy_bound = nullptr;
    } else if ((thread && !thread->energy_bound) ||
               (cloth && !cloth->energy_bound)) {
      // What fit fits by default: a file's own bound is the model's; else
      // the bound of its values.
      model.params = WithEnergyBound(model.params);
    }
  }
  const std::string out_path = args.Required("out");
  options.noise = args.GetDouble("noise");
  if (options.noise < 0.0 || options.noise > 1.0) {
    args.Fail("option '--noise': must be in [0, 1], got " + args.Get("noise"));
  }
  const long seed = args.GetInt("seed");
  Random random(static_cast<uint64_t>(seed));

  MeasurementTable table;
  if (args.Has("dirs")) {
    if (args.Has("rows") || args.Has("max-theta-deg")) {
      args.Fail("--dirs replaces --rows and --max-theta-deg");
    }
    ReadTableOptions read_options;
    read_options.values_optional = true;
    table = ReadTableOption(args, args.Get("dirs"), read_options);
  } else {
    DirectionSampling sampling;
    const long rows = args.GetInt("rows");
    // 1e7 rows take ~40 s and ~4 GB here; 1e8 could not be held.
    if (rows < 1 || rows > 10000000) {
      args.Fail("option '--rows': must be in [1, 1e7], got " +
                args.Get("rows"));
    }
    sampling.rows = static_cast<int>(rows);
    const double max_theta = args.GetDouble("max-theta-deg");
    if (!(max_theta > 0.0 && max_theta <= 90.0)) {
      args.Fail("option '--max-theta-deg': must be in (0, 90], got " +
                args.Get("max-theta-deg"));
    }
    sampling.min_cos_theta =
        max_theta >= 90.0 ? 0.0 : std::cos(Radians(max_theta));
    sampling.full_sphere_out = FullSphereOut(model.params);
    table.rows = SampleDirections(sampling, &random);
    table.direction_columns = DirectionColumns::kAngles;
  }
  table.channels = 3;
  table.has_weight = false;
  SynthesizeValues(model.params, options, &random, &table);
  std::ostringstream sample;
  sample << "synthetic, model " << ModelName(model.params);
  if (args.Has("preset")) sample << " preset " << args.Get("preset");
  if (args.Has("params")) sample << " from " << args.Get("params");
  sample << ", noise " << text_util::FormatNumber(options.noise, 6) << ", seed "
         << seed;
  table.SetMeta("sample", sample.str());
  WriteTableWithProgress(table, out_path);
  if (const auto* slab = std::get_if<SlabParams>(&model.params)) {
    NoteSlabRegime(*slab);
  }
  return 0;
}

}  // namespace clothfit
