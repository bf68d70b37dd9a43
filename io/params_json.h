// Parameter files (SPEC §4): one JSON object with a "model" key.
//
//   {"model": "thread", "eta": 1.539, "kd": 0.1, "gamma_s_deg": 2.5,
//    "gamma_v_deg": 5.0, "albedo": [0.035, 0.01295, 0.0105]}
//   {"model": "cloth", "threads": [{"direction": "u", "coverage": 0.33,
//    "offsets_deg": [-25, 25], "eta": 1.46, ...}, ...]}
//   {"model": "slab", "tau": 0.5, "albedo": [0.9, 0.8, 0.7]}
//
// A cloth thread gives its tangent samples either explicitly ("offsets_deg")
// or as a tangent curve ("curve_offsets_deg", "curve_lengths", "samples").
// Unknown keys, missing keys, wrong types and out-of-range values are errors
// that name the file and the key (as a JSON path, e.g. threads[1].kd).
// A "fit" object (written by `clothfit fit`) is kept verbatim as text.
#pragma once

#include <string>
#include <variant>

#include "models/evaluate.h"
#include "models/holes.h"

namespace clothfit {

struct ParamFile {
  ModelParams params;
  // The "fit" object as serialised JSON text, empty when absent.
  std::string fit_json;
};

// "thread" | "cloth" | "lafortune" | "slab".
const char* ModelName(const ModelParams& params);

// Throws InputError naming `name` and the key on any problem.
ParamFile ParseParamFile(const std::string& text, const std::string& name);
ParamFile ReadParamFile(const std::string& path);

// Pretty-printed JSON (2-space indent, 17 significant digits).
std::string FormatParamFile(const ParamFile& file);
// Atomic write (io/atomic_file.h). Throws InputError when it cannot write.
void WriteParamFile(const ParamFile& file, const std::string& path);

// A holes parameter file (issue 6), read and written by `clothfit holes`
// and `clothfit fit --model holes` (the model needs a mask, so it is not a
// ModelParams):
//   {"model": "holes", "thickness_texels": 2.0, "wall_color": [0, 0, 0],
//    "mask": "net.png", "threshold": 0.5, "method": "extension", "fit": {..}}
// "mask", "threshold" and "method" record how the fit saw the mask
// (optional; informational).
struct HolesParamFile {
  HolesParams params;
  std::string mask;        // "" when absent
  double threshold = 0.5;  // mask threshold
  std::string method;      // "alg31" | "extension" | ""
  std::string fit_json;    // the "fit" object as text, empty when absent
};

HolesParamFile ParseHolesParamFile(const std::string& text,
                                   const std::string& name);
HolesParamFile ReadHolesParamFile(const std::string& path);
void WriteHolesParamFile(const HolesParamFile& file, const std::string& path);

}  // namespace clothfit
