// Measurement tables (docs/formats.md): CSV with '#' metadata lines and a
// header row.
//
//   # clothfit-table 1
//   # quantity: brdf            brdf | cosine_weighted | transmittance
//   # units: degrees            degrees | radians
//   theta_i,phi_i,theta_o,phi_o,r,g,b
//
// Directions are stored as unit vectors (wi towards the light, wo towards the
// viewer, both pointing away from the surface). Values carry one channel
// ("value") or three ("r,g,b"); a one-channel table keeps its value in all
// three components of `value` so that models can be evaluated per channel.
#pragma once

#include <functional>
#include <glm/vec3.hpp>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "models/quantity.h"

namespace clothfit {

enum class DirectionColumns { kAngles, kVectors };

// "brdf" | "cosine_weighted" | "transmittance"; std::nullopt if unknown.
std::optional<Quantity> ParseQuantity(const std::string& text);
const char* QuantityName(Quantity quantity);

// The largest magnitude of a value, sigma or weight a table may hold (and
// the smallest sigma is its inverse): beyond it, a squared normalised
// residual could overflow a fit's cost. ReadTable rejects such fields.
inline constexpr double kMaxTableMagnitude = 1e30;

struct TableRow {
  glm::dvec3 wi{0.0, 0.0, 1.0};  // unit vector towards the light
  glm::dvec3 wo{0.0, 0.0, 1.0};  // unit vector towards the viewer
  glm::dvec3 value{0.0};         // measured quantity per channel
  glm::dvec3 sigma{1.0};         // 1-sigma error per channel (> 0)
  double weight = 1.0;           // residual weight (>= 0)
  int s = -1, t = -1;            // texel indices, -1 when absent
  double alpha = 1.0;  // coverage of the view, [0, 1] (column "alpha")
  // The texel's average surface normal, unit (columns
  // "normal_x,normal_y,normal_z"): the frame a spatially varying fit
  // evaluates the texel's lobes in (Daubert et al. 2001, Section 3).
  glm::dvec3 normal{0.0, 0.0, 1.0};
  int source_line = 0;  // 1-based line in the file (0: made in memory)
};

// Light and view both above the surface (wi.z > 0 and wo.z > 0): a row a
// reflection-only model (cloth, Lafortune) can explain.
inline bool IsReflectionRow(const TableRow& row) {
  return row.wi.z > 0.0 && row.wo.z > 0.0;
}

struct MeasurementTable {
  // The file it was read from, for messages ("" when made in memory).
  std::string source;
  // Metadata lines in file order, keys lower-cased; unknown keys are kept.
  std::vector<std::pair<std::string, std::string>> metadata;
  Quantity quantity = Quantity::kBrdf;
  int channels = 3;  // 1 ("value") or 3 ("r,g,b")
  DirectionColumns direction_columns = DirectionColumns::kAngles;
  bool has_sigma = false;
  bool has_weight = false;
  bool has_texels = false;  // s,t columns present
  bool has_alpha = false;   // alpha column present (per-view coverage)
  bool has_normal = false;  // normal_x,normal_y,normal_z columns present
  std::vector<TableRow> rows;

  // Value of a metadata key (case-insensitive), if present.
  std::optional<std::string> Meta(const std::string& key) const;
  // Sets (or replaces) a metadata key.
  void SetMeta(const std::string& key, const std::string& value);
};

struct ReadTableOptions {
  // Drop rows that fail validation instead of failing; the number dropped is
  // returned in ReadTableResult::skipped together with the first reason.
  bool skip_invalid = false;
  // Accept a table without value columns (a list of directions, as
  // `clothfit eval --dirs` takes); values are then 0 and channels 3.
  bool values_optional = false;
  // ReadTable: called after each piece of the file with the bytes read so
  // far and the file's size (for a progress line); may be empty.
  std::function<void(double bytes_read, double bytes_total)> progress;
  // When set, each valid row is handed to it, in file order, and not kept:
  // the result's table has the columns and metadata but no rows (a fit
  // that reads a table of millions of rows into its own compact form
  // never holds the rows). `table` is that header.
  std::function<void(const MeasurementTable& table, const TableRow& row)>
      row_sink;
};

struct ReadTableResult {
  MeasurementTable table;
  int skipped = 0;
  std::string first_skip_reason;  // "file:line:col: problem" of the first
  // What looks wrong but may be right, "FILE: ..." each: every angle
  // within radian range in a table read in degrees; values that look like
  // percent. The commands print them as warnings.
  std::vector<std::string> warnings;
};

// For a table whose metadata says its values are on an arbitrary scale
// (a key "scale" with value "arbitrary" or "relative", or any metadata
// value that says "arbitrary ... scale", as CUReT's "arbitrary common
// scale"): that metadata line, "key: value". nullopt otherwise.
std::optional<std::string> ArbitraryScaleNote(const MeasurementTable& table);

// Reads a table. Throws InputError naming file, line and column on bad input:
// missing/duplicate/unknown column, unparsable number, NaN/Inf, angle out of
// range, zero direction vector, negative sigma, wrong field count, empty table.
ReadTableResult ReadTable(const std::string& path,
                          const ReadTableOptions& options = {});
// The columns and metadata of a table (no rows), reading no further than
// its header line. Throws InputError as ReadTable on a bad header, or
// when the file ends before one.
MeasurementTable ReadTableHeader(const std::string& path,
                                 const ReadTableOptions& options = {});
// Same, from text already in memory; `name` is used in messages.
ReadTableResult ParseTable(const std::string& text, const std::string& name,
                           const ReadTableOptions& options = {});

// Writes a table (values in the shortest form that reads back exactly,
// angles to 15 significant digits, metadata first). The file is written
// to a temporary name and renamed into place when complete. Throws
// InputError if the path cannot be written.
// `progress`, if given, is called after each piece (about 1 MiB) with the
// rows written so far and their count.
using TableProgress = std::function<void(double done, double total)>;
void WriteTable(const MeasurementTable& table, const std::string& path,
                const TableProgress& progress = {});
std::string FormatTable(const MeasurementTable& table);

// Spherical angles (radians) <-> unit vectors, docs/formats.md
glm::dvec3 DirectionFromAngles(double theta, double phi);
void AnglesFromDirection(const glm::dvec3& w, double* theta, double* phi);

// The floor of relative noise for a channel whose values have these
// magnitudes: 1 % of their median (of their largest where half are 0; 1
// where all are). A reflectance table spans decades (a thread's highlight
// is 1,000x its median), so a floor tied to the largest value would weigh
// most rows alike. The fits' default relative noise model uses it
// (fitting/residual_weight.h), and synth's noisy tables, so that their
// sigma is what the default fit would weigh a row by.
double RelativeNoiseFloor(std::vector<double> magnitudes);

}  // namespace clothfit
