// The reader of measurement tables (io/table.h) behind ReadTable and
// ParseTable: the known columns and a line-by-line parser, split over
// table_parser.cc (metadata, header, lines) and table_rows.cc (a row's
// fields). For io/table*.cc only (not installed).
#pragma once

#include <array>
#include <optional>
#include <string>
#include <string_view>
#include <vector>

#include "io/input_error.h"
#include "io/table.h"

namespace clothfit {
namespace table_internal {

// Columns a table may have. The order is the order of semantic checks.
enum ColumnId : int {
  kThetaI,
  kPhiI,
  kThetaO,
  kPhiO,
  kWiX,
  kWiY,
  kWiZ,
  kWoX,
  kWoY,
  kWoZ,
  kValue,
  kR,
  kG,
  kB,
  kSigma,
  kSigmaR,
  kSigmaG,
  kSigmaB,
  kWeight,
  kAlpha,
  kS,
  kT,
  kNormalX,
  kNormalY,
  kNormalZ,
  kColumnCount
};

constexpr std::array<const char*, kColumnCount> kColumnNames = {
    "theta_i", "phi_i",    "theta_o",  "phi_o",   "wi_x",   "wi_y",  "wi_z",
    "wo_x",    "wo_y",     "wo_z",     "value",   "r",      "g",     "b",
    "sigma",   "sigma_r",  "sigma_g",  "sigma_b", "weight", "alpha", "s",
    "t",       "normal_x", "normal_y", "normal_z"};

// The number a field spells (decimal, as strtod: optional sign, exponent,
// inf/nan); nullopt when it spells none. std::from_chars does the common case
// without allocating; values beyond the double range take strtod's answer
// (+-inf, or a subnormal / 0).
std::optional<double> ParseNumber(std::string_view field);

// "column 'theta_i'" for messages.
std::string ColumnLabel(int column);

// The metadata keys the reader interprets itself.
bool IsRecognisedMetaKey(const std::string& key);

// Parsing state shared by the header and row readers.
class TableParser {
 public:
  // Longest line of a table (a row of clothfit's columns is under 1 KiB): a
  // file without line breaks is refused before it fills the memory.
  static constexpr size_t kMaxLineBytes = size_t{1} << 20;

  TableParser(const std::string& name, const ReadTableOptions& options)
      : name_(name), options_(options) {}

  ReadTableResult Parse(std::string_view text);
  // Line by line (without its '\n'), then Finish: what Parse does, for a
  // file read piece by piece.
  void Line(std::string_view content);
  // Throws "FILE:LINE: line longer than ..." when the line being read is
  // already `bytes` long and that is more than kMaxLineBytes: a reader
  // checks before it gathers more of one line.
  void CheckLineLength(size_t bytes) const;
  ReadTableResult Finish();
  // Rows read so far (kept, or handed to the options' row_sink).
  size_t rows() const { return rows_; }
  // Whether the header line has been read; then table() has the columns
  // and metadata (no rows yet).
  bool HeaderRead() const { return header_line_ > 0; }
  const MeasurementTable& table() const { return result_.table; }
  void Reserve(size_t rows) { result_.table.rows.reserve(rows); }

 private:
  [[noreturn]] void Fail(int line, int column,
                         const std::string& problem) const {
    throw InputError(FormatLocation(name_, line, column) + ": " + problem);
  }

  void ParseMetadata(std::string_view content, int line);
  void ParseHeader(std::string_view text, int line);
  // Requires all columns in [first, first + count) to be present.
  void RequireAll(int first, int count, int line);
  // The first present column in [first, first + count), or -1.
  int FirstPresent(int first, int count) const;
  bool Has(int column) const { return field_of_[column] >= 0; }
  // Parses and checks a row into *row (what AddWarnings looks at is noted).
  void ParseRow(std::string_view text, int line, TableRow* row);
  // A valid row: kept, or handed to the row sink.
  void Accept(const TableRow& row);
  double Angle(int column) const;
  // The separator of the header line: of ',', ';' and tab the one it holds
  // most often (',' when it holds none); the rows use the same.
  void DetectSeparator(std::string_view header);
  // A header field's unit ("theta_i [deg]", "theta_i (rad)", "value [%]"),
  // lower-case; checked against the column and the '# units' line.
  void ApplyUnit(int column, const std::string& unit, int line,
                 int field_column);
  // Table-level warnings (ReadTableResult::warnings), from what the rows
  // showed.
  void AddWarnings();
  // Keeps every value_stride_-th value for the median of AddWarnings (at
  // most kValueSample of them: the stride doubles when full).
  void SampleValue(double value);

  const std::string& name_;
  const ReadTableOptions& options_;
  bool has_values_ = true;  // false: a directions-only table
  ReadTableResult result_;
  size_t rows_ = 0;       // valid rows read
  int line_ = 0;          // lines seen
  int header_line_ = 0;   // line of the header, 0 before it
  bool radians_ = false;  // the '# units' line's
  // Per angle column: radians (from '# units' or the column's unit).
  std::array<bool, kColumnCount> column_radians_{};
  // Per column: the factor of its unit ('%': 0.01), 1 without.
  std::array<double, kColumnCount> column_factor_{};
  bool column_units_ = false;  // an angle column named its unit
  bool percent_unit_ = false;  // a value column had the unit '%'
  char separator_ = ',';
  // What the rows showed, for AddWarnings: the largest |theta| and |phi|
  // as written, and a sample of the values.
  double largest_theta_ = 0.0, largest_phi_ = 0.0;
  double largest_value_ = 0.0, smallest_value_ = 0.0;
  std::vector<double> value_sample_;
  size_t value_count_ = 0, value_stride_ = 1;
  static constexpr size_t kValueSample = size_t{1} << 16;
  int quantity_line_ = 0;
  int units_line_ = 0;
  // Field index (0-based) of each known column, -1 when absent.
  std::array<int, kColumnCount> field_of_{};
  std::vector<std::string> header_names_;
  bool incident_columns_ = false;
  // Numbers of the row being parsed, indexed by ColumnId.
  std::array<double, kColumnCount> numbers_{};
};

}  // namespace table_internal
}  // namespace clothfit
