// clothfit merge: the parts of a texel map fitted in blocks (fit --region)
// as one map, the levels above the blocks fitted from their children and
// the stack's rows (docs/scale.md).
#include <algorithm>
#include <cstdio>
#include <filesystem>
#include <string>
#include <vector>

#include "apps/commands.h"
#include "apps/lafortune_options.h"
#include "fitting/lafortune_merge.h"
#include "fitting/lafortune_part.h"
#include "io/atomic_file.h"
#include "io/image_stack.h"
#include "io/input_error.h"
#include "io/text_util.h"

namespace clothfit {
namespace {

namespace fs = std::filesystem;

// Rows of one image streamed at a time: a strip of about this many rows
// (each ~150 bytes) bounds the merge's memory for the rows.
constexpr size_t kStripRows = size_t{1} << 17;

// The part files of --parts: a folder's *.exr files (by name), or a list.
std::vector<std::string> PartPaths(const CommandArgs& args) {
  const std::string given = args.Get("parts");
  std::error_code error;
  if (!fs::is_directory(given, error)) return ListOption(args, "parts");
  std::vector<std::string> paths;
  for (const fs::directory_entry& entry : fs::directory_iterator(given)) {
    if (entry.is_regular_file(error) &&
        text_util::HasExtension(entry.path().string(), ".exr")) {
      paths.push_back(entry.path().string());
    }
  }
  std::sort(paths.begin(), paths.end());
  if (paths.empty()) {
    throw InputError(given + ": no part files (*.exr) in the folder");
  }
  return paths;
}

}  // namespace

int RunBlocks(int argc, char** argv) {
  CommandArgs args(
      "blocks", "clothfit blocks --stack M.csv --block B",
      "Prints the blocks of B x B texels that tile an image stack's texture, "
      "one X0,Y0,W,H per line: the --region of each part\nof a fit in "
      "blocks (a task of scripts/dask_fit.py, an index of a Slurm job array; "
      "docs/scale.md).");
  args.Option("stack", "M.csv", "the image-stack manifest");
  args.Option("block", "B", "block side in texels, a power of two", "64");
  if (!args.Parse(argc, argv, 2)) return 0;
  const long block = args.GetInt("block");
  if (block < 1 || block > (1 << 28)) {
    args.Fail("option '--block': must be a power of two >= 1");
  }
  const ImageStackReader reader(args.Required("stack"));
  const int b = static_cast<int>(block);
  const std::string problem =
      LafortuneRegionProblem(0, 0, b, b, reader.width(), reader.height());
  if (!problem.empty()) args.Fail("option '--block': " + problem);
  for (int y = 0; y < reader.height(); y += b) {
    for (int x = 0; x < reader.width(); x += b) {
      std::printf("%d,%d,%d,%d\n", x, y, b, b);
    }
  }
  return 0;
}

int RunMerge(int argc, char** argv) {
  CommandArgs args(
      "merge",
      "clothfit merge --parts LIST|DIR --out P.exr [--stack M.csv] "
      "[--threads N]",
      "Merges the parts of a Lafortune texel map fitted in blocks (clothfit "
      "fit --stack M.csv --region X0,Y0,W,H --out part.exr)\ninto one "
      "map: checks that they tile the texture exactly once, takes their "
      "levels, and fits the levels above the blocks\nfrom their children "
      "and the stack's images (read a strip at a time), as a fit of the "
      "whole stack would: the same map, bit for bit.");
  args.Option("parts", "LIST|DIR",
              "the part files, comma-separated, or a folder of them (its "
              "*.exr files)");
  args.Option("out", "P.exr", "the merged map (and its index P.exr.json)");
  args.Option("stack", "M.csv",
              "the stack the parts were fitted on, where it is now (default: "
              "the path the parts record)");
  args.Option("threads", "N", "fits of the levels above the blocks in parallel",
              "0 (every core)");
  if (!args.Parse(argc, argv, 2)) return 0;
  const std::string out_path = args.Required("out");
  if (!text_util::HasExtension(out_path, ".exr")) {
    args.Fail("--out must be an .exr file");
  }
  CheckWritable(out_path);
  const std::vector<std::string> paths = PartPaths(args);
  std::vector<LafortunePart> parts;
  for (const std::string& path : paths) {
    parts.push_back(ReadLafortunePart(path));
  }
  LafortuneMipResult merged = AssembleLafortuneParts(parts);
  const LafortunePartInfo& info = parts.front().info;
  // The fit's options as the parts record them, read as fit reads them.
  CommandArgs fit_args = LafortuneFitArgs();
  std::vector<std::string> words = {"clothfit", "fit"};
  words.insert(words.end(), info.fit.begin(), info.fit.end());
  std::vector<char*> fit_argv;
  for (std::string& word : words) fit_argv.push_back(word.data());
  try {
    fit_args.Parse(static_cast<int>(fit_argv.size()), fit_argv.data(), 2);
  } catch (const InputError& e) {
    throw InputError(parts.front().path +
                     ": the fit options it records: " + e.what());
  }
  LafortuneFitSetup setup;
  ReadLafortuneFitOptions(fit_args, &setup);
  LafortuneMipOptions& options = setup.options;
  options.threads = 0;
  if (args.Has("threads")) {
    const long threads = args.GetInt("threads");
    if (threads < 1 || threads > 256) {
      args.Fail("option '--threads': must be 1 to 256");
    }
    options.threads = static_cast<int>(threads);
  }
  const std::string stack = args.Has("stack") ? args.Get("stack") : info.stack;
  ImageStackReader reader(stack);
  if (reader.width() != info.texture_width ||
      reader.height() != info.texture_height) {
    throw InputError(stack + ": the images are " +
                     std::to_string(reader.width()) + " x " +
                     std::to_string(reader.height()) + ", the parts' texture " +
                     std::to_string(info.texture_width) + " x " +
                     std::to_string(info.texture_height));
  }
  // Neither a part nor an image of the stack is overwritten.
  std::vector<NamedFile> inputs;
  for (const std::string& path : paths) inputs.push_back({"--parts", path});
  for (size_t k = 0; k < reader.images(); ++k) {
    inputs.push_back({"an image of the stack", reader.ImagePath(k)});
  }
  if (!reader.NormalMapPath().empty()) {
    inputs.push_back({"the stack's normal map", reader.NormalMapPath()});
  }
  CheckOutputsDistinct(
      {{"--out", out_path}, {"--out's index copy", out_path + ".json"}},
      inputs);
  const int width = reader.width(), height = reader.height();
  const int strip = static_cast<int>(
      std::max<size_t>(1, kStripRows / static_cast<size_t>(width)));
  const LafortuneRowStream stream = [&](const auto& row) {
    MeasurementTable rows = reader.header();
    for (size_t k = 0; k < reader.images(); ++k) {
      for (int y = 0; y < height; y += strip) {
        rows.rows.clear();
        reader.AppendRows(k, {0, y, width, std::min(strip, height - y)}, 1,
                          false, &rows);
        for (const TableRow& r : rows.rows) row(k, r);
      }
    }
  };
  FitLafortuneUpperLevels(reader.directions(), width, height, stream, options,
                          LafortunePartLevels(info), &merged);
  return FinishLafortuneMip(merged, MergedParamMipmap(merged, parts), out_path);
}

}  // namespace clothfit
