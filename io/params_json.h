// Parameter files (docs/formats.md): one JSON object with a "model" key.
//
//   {"model": "thread", "eta": 1.539, "kd": 0.1, "gamma_s_deg": 2.5,
//    "gamma_v_deg": 5.0, "albedo": [0.035, 0.01295, 0.0105]}
//   {"model": "cloth", "threads": [{"direction": "u", "coverage": 0.33,
//    "offsets_deg": [-25, 25], "eta": 1.46, ...}, ...]}
//   {"model": "slab", "tau": 0.5, "albedo": [0.9, 0.8, 0.7]}
//   {"model": "holes", "thickness_texels": 2.0, "wall_color": [0, 0, 0],
//    "mask": "net.png", "threshold": 0.5, "method": "extension"}
//   {"model": "sheen", "base_color": [0.3, 0.2, 0.1], "roughness": 0.8,
//    "sheen_color": [0.6, 0.5, 0.4], "sheen_roughness": 0.4}
//
// The keys, units and ranges of each model's parameters come from its
// parameter table (models/params.h); an rgb entry is an array of 3 numbers
// or one number for all three. A holes file names its mask ("mask",
// "threshold" and "method" record how a fit saw it) and may hold the
// mask's tile ("tile": the counts of the level the model evaluates,
// io/holes_tile_json_internal.h), which makes it usable without the mask
// (api/material.h reads no image). `clothfit fit --model holes` writes the
// tile when it has at most kMaxStoredTileTexels texels.
// A cloth thread gives its tangent samples either explicitly ("offsets_deg")
// or as a tangent curve ("curve_offsets_deg", "curve_lengths", "samples").
// Unknown keys, missing keys, wrong types and out-of-range values are errors
// that name the file and the key (as a JSON path, e.g. threads[1].kd).
// A "fit" object (written by `clothfit fit`) is kept verbatim as text.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <variant>

#include "io/input_error.h"
#include "models/evaluate.h"

namespace clothfit {

// Where a holes file's mask is, and how it was thresholded (informational:
// a command reads the mask itself, holes/hole_texture.h).
struct HolesMaskSource {
  std::string path;                  // "" when absent
  double threshold = 0.5;            // in (0, 1]
  std::optional<HoleMethod> method;  // the method a fit used
};

struct ParamFile {
  ParamFile() = default;
  ParamFile(ModelParams model, std::string fit = "")
      : params(std::move(model)), fit_json(std::move(fit)) {}

  ModelParams params;
  // The "fit" object as serialised JSON text, empty when absent.
  std::string fit_json;
  // A holes model's mask ("mask", "threshold", "method"); the model's tile
  // is the file's "tile", else null until the mask is analysed.
  HolesMaskSource holes;
};

// Throws InputError naming `name` and the key on any problem.
ParamFile ParseParamFile(const std::string& text, const std::string& name);
ParamFile ReadParamFile(const std::string& path);

// Pretty-printed JSON (2-space indent, 17 significant digits).
std::string FormatParamFile(const ParamFile& file);
// Atomic write (io/atomic_file.h). Throws InputError when it cannot write.
void WriteParamFile(const ParamFile& file, const std::string& path);

// The parameters of `file` as model P (ThreadParams, ...); throws
// InputError "NAME: expected a P parameter file, got M" for another model.
template <typename P>
const P& ModelOf(const ParamFile& file, const std::string& name) {
  if (const P* p = std::get_if<P>(&file.params)) return *p;
  throw InputError(name + ": expected a " + kModelInfo<P>.name +
                   " parameter file, got " + ModelName(file.params));
}

// "alg31" | "extension"; nullopt for anything else.
std::optional<HoleMethod> ParseHoleMethod(const std::string& text);

}  // namespace clothfit
