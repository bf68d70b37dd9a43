// clothfit fit --model lafortune: Lafortune lobes with per-view lookup
// tables (Daubert et al. 2001) for one table, or per texel and mip level
// for a spatially varying table or image stack.
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <iostream>
#include <memory>
#include <optional>
#include <sstream>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "apps/full_binary.h"
#include "apps/lafortune_options.h"
#include "apps/progress.h"
#include "fitting/lafortune_fit.h"
#include "fitting/lafortune_level_select.h"
#include "fitting/lafortune_merge.h"
#include "fitting/lafortune_mip.h"
#include "fitting/lafortune_part.h"
#include "fitting/lafortune_select.h"
#include "io/atomic_file.h"
#include "io/image_stack.h"
#include "io/param_mipmap.h"
#include "io/text_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;

#ifndef CLOTHFIT_LIGHT
// --region X0,Y0,W,H as four integers.
PixelRegion RegionOption(const CommandArgs& args) {
  const std::vector<std::string> items = ListOption(args, "region");
  int v[4] = {0, 0, 0, 0};
  bool ok = items.size() == 4;
  for (size_t i = 0; ok && i < 4; ++i) {
    char* end = nullptr;
    const long n = std::strtol(items[i].c_str(), &end, 10);
    ok = end != items[i].c_str() && *end == '\0' && n >= 0 && n <= (1 << 28);
    v[i] = static_cast<int>(n);
  }
  if (!ok) {
    args.Fail(
        "option '--region': expected X0,Y0,W,H (four integers >= 0), "
        "got '" +
        args.Get("region") + "'");
  }
  return {v[0], v[1], v[2], v[3]};
}

// The fit's arguments as a part records them for merge: without --out,
// --region, --stack (recorded on their own) and --threads (which changes
// no result), --init made absolute.
std::vector<std::string> RecordedFitArguments(int argc, char** argv) {
  std::vector<std::string> out;
  for (int i = 2; i < argc; ++i) {
    const std::string arg = argv[i];
    const size_t equals = arg.find('=');
    const std::string name = arg.substr(0, equals);
    const bool inline_value = equals != std::string::npos;
    if (name == "--out" || name == "--region" || name == "--stack" ||
        name == "--threads") {
      if (!inline_value) ++i;  // and its value
      continue;
    }
    if (name == "--init") {
      const std::string value = inline_value ? arg.substr(equals + 1)
                                             : (i + 1 < argc ? argv[++i] : "");
      out.push_back("--init");
      out.push_back(fs::absolute(value).lexically_normal().string());
      continue;
    }
    out.push_back(arg);
  }
  return out;
}

// The rows of an image stack (of `region`; width 0: every pixel), after
// checking that no image of it is --out or its index copy.
MeasurementTable ReadStackFor(const std::string& stack,
                              const PixelRegion& region,
                              const std::string& out_path) {
  ReadStackOptions read;
  std::vector<std::string> images;
  read.images = &images;
  read.region = region;
  MeasurementTable table = ReadImageStack(stack, read);
  std::vector<NamedFile> inputs;
  for (const std::string& image : images) {
    inputs.push_back({"an image of --stack", image});
  }
  CheckOutputsDistinct(
      {{"--out", out_path}, {"--out's index copy", out_path + ".json"}},
      inputs);
  return table;
}

#endif

// fit --stack --region: one block of the texture as a part file.
int FitLafortuneRegion(const CommandArgs& args, int argc, char** argv,
                       LafortuneMipOptions options,
                       const std::string& out_path) {
#ifdef CLOTHFIT_LIGHT
  (void)args, (void)argc, (void)argv, (void)options, (void)out_path;
  RunInFullBinary();
#else
  if (!WeightingIsPerRow(options.noise)) {
    args.Fail(
        "option '--noise': relative noise in a block needs "
        "--noise-floor (the default floor is the whole texture's "
        "median value)");
  }
  if (!text_util::HasExtension(out_path, ".exr")) {
    args.Fail(
        "--region writes a part of a texel map: --out must be an .exr "
        "file");
  }
  const std::string stack = args.Get("stack");
  const PixelRegion region = RegionOption(args);
  LafortunePartInfo info;
  {
    const ImageStackReader reader(stack);
    info.texture_width = reader.width();
    info.texture_height = reader.height();
  }
  const std::string problem =
      LafortuneRegionProblem(region.x, region.y, region.width, region.height,
                             info.texture_width, info.texture_height);
  if (!problem.empty()) args.Fail("option '--region': " + problem);
  info.x = region.x;
  info.y = region.y;
  info.width = region.width;
  info.height = region.height;
  info.mip = options.mip;
  info.stack = fs::absolute(stack).lexically_normal().string();
  info.fit = RecordedFitArguments(argc, argv);
  const MeasurementTable table = ReadStackFor(stack, region, out_path);
  progress::FlushWarnings();  // the work starts
  auto task = std::make_shared<progress::Task>("fit", "texel fits");
  options.progress = [task](int done, int total) { task->Update(done, total); };
  const LafortuneMipResult result = FitLafortuneMip(table, options);
  return FinishLafortuneMip(result, ToPartMipmap(result, info), out_path);
#endif
}

// One model from a table file read row by row (FitLafortuneRows): the
// fit holds its samples, not the table. The first pass warns as
// ReadTableOption does; the later ones read the same file again.
LafortuneFitResult FitLafortuneFile(const CommandArgs& args,
                                    const std::string& path,
                                    const MeasurementTable& header,
                                    const LafortuneMipOptions& options) {
  int passes = 0;
  TableRowPasses rows;
  rows.table = &header;
  rows.each = [&](const std::function<void(const TableRow&)>& row) {
    ReadTableOptions read;
    read.row_sink = [&row](const MeasurementTable&, const TableRow& r) {
      row(r);
    };
    if (passes++ == 0) {
      ReadTableOption(args, path, read);
      return;
    }
    read.skip_invalid = args.Has("skip-invalid");
    progress::Task task("reading " + path + " again", "MB");
    read.progress = [&task](double done, double total) {
      task.Update(done / 1e6, total / 1e6);
    };
    ReadTable(path, read);
  };
  return FitLafortuneRows(rows, options);
}

}  // namespace

int RunFitLafortune(int argc, char** argv) {
  CommandArgs args = LafortuneFitArgs();
  if (!args.Parse(argc, argv, 2)) return 0;
  const std::string out_path = args.Required("out");
  if (args.Has("data") == args.Has("stack")) {
    args.Fail("give exactly one of --data and --stack");
  }
  CheckWritable(out_path);  // before the fit, not after
  LafortuneFitSetup setup;
  ReadLafortuneFitOptions(args, &setup);
  LafortuneMipOptions& options = setup.options;
  const bool select = setup.select;
  const long folds = setup.folds;
  if (args.Has("region")) {
    if (!args.Has("stack")) args.Fail("--region needs --stack");
    if (select) {
      args.Fail(
          "--region: --select heldout chooses over the whole map; "
          "leave it out");
    }
    return FitLafortuneRegion(args, argc, argv, options, out_path);
  }
  MeasurementTable table;
  // A table file for one model (no s,t columns), read row by row: its
  // columns and metadata, and no rows.
  std::optional<MeasurementTable> header;
  const std::string source = args.Get(args.Has("stack") ? "stack" : "data");
  if (args.Has("stack")) {
#ifdef CLOTHFIT_LIGHT
    RunInFullBinary();
#else
    table = ReadStackFor(source, PixelRegion(), out_path);
#endif
  } else if (!select && RegularFileProblem(source).empty()) {
    ReadTableOptions read;
    read.skip_invalid = args.Has("skip-invalid");
    header = ReadTableHeader(source, read);
    if (header->has_texels) {
      header.reset();
      table = ReadTableOption(args, source);
    }
  } else {  // a pipe is read once; --select folds the rows
    table = ReadTableOption(args, source);
  }

  if (header || !table.has_texels) {  // one model for the whole table
    if (!text_util::HasExtension(out_path, ".json")) {
      args.Fail(
          "a table without s,t columns gives one model: --out must be "
          "a .json parameter file");
    }
    if (options.mip) args.Fail("--mip needs a table with s,t columns");
    if (select) {
      for (const char* other : {"lobes", "no-lut", "tolerance", "init"}) {
        if (args.Has(other)) {
          args.Fail(std::string("--select heldout chooses the lobes and the "
                                "lookup table: leave out --") +
                    other);
        }
      }
      const LafortuneSelection chosen =
          SelectLafortuneHeldOut(table, options, static_cast<int>(folds));
      if (chosen.report.chosen < 0) {
        std::cerr << "error: --select heldout: " << chosen.report.reason
                  << "; nothing written\n";
        return 1;
      }
      FitExtras extras;
      extras.text = SelectionReportText(chosen.report) + "\n";
      extras.json.emplace_back("selection", SelectionReportJson(chosen.report));
      return FinishFit(args, chosen.fit.params, chosen.fit.report, {}, extras);
    }
    const LafortuneFitResult fit =
        header ? FitLafortuneFile(args, source, *header, options)
               : FitLafortuneTable(table, options);
    WarnNotReflection(fit.report, "lafortune");
    if (options.fit.lookup_table &&
        fit.report.lut_views_fitted < fit.report.lut_views) {
      std::fprintf(stderr,
                   "warning: lookup table: %d of %d views have at least %d "
                   "samples (%.1f rows per view); the others take T "
                   "interpolated from those%s\n",
                   fit.report.lut_views_fitted, fit.report.lut_views,
                   options.fit.min_lut_samples,
                   static_cast<double>(fit.report.rows) /
                       std::max(1, fit.report.lut_views),
                   fit.report.lut_views_fitted == 0 ? " (none: T = 1)" : "");
    }
    return FinishFit(args, fit.params, fit.report, {}, FitExtras());
  }

  if (select && !options.mip) {
    args.Fail(
        "--select heldout on a table with s,t columns chooses the mip "
        "level: add --mip");
  }
  if (!text_util::HasExtension(out_path, ".exr")) {
    args.Fail(
        "a table with s,t columns gives a model per texel: --out must "
        "be an .exr file");
  }
  progress::FlushWarnings();  // the work starts
  auto task = std::make_shared<progress::Task>("fit", "texel fits");
  options.progress = [task](int done, int total) { task->Update(done, total); };
  LafortuneMipResult result;
  std::string selection_json;  // with --select: metadata.fit.selection
  if (select) {
    LafortuneLevelSelection chosen =
        SelectLafortuneLevelHeldOut(table, options, static_cast<int>(folds));
    progress::Clear();
    std::cout << SelectionReportText(chosen.report);
    if (chosen.level < 0) {
      std::cerr << "error: --select heldout: " << chosen.report.reason
                << "; nothing written\n";
      return 1;
    }
    selection_json = SelectionReportJson(chosen.report);
    result = std::move(chosen.mip);
  } else {
    result = FitLafortuneMip(table, options);
  }
  return FinishLafortuneMip(result, ToParamMipmap(result, selection_json),
                            out_path);
}

}  // namespace clothfit
