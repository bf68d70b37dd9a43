#include "io/table.h"

#include <algorithm>
#include <array>
#include <cerrno>
#include <charconv>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <optional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "io/atomic_file.h"
#include "io/input_error.h"
#include "io/text_util.h"
#include "models/math.h"

namespace clothfit {
namespace {

using text_util::FormatNumber;
using text_util::Lower;
using text_util::OneLine;
using text_util::Quote;
using text_util::SplitFields;
using text_util::Trim;

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
std::optional<double> ParseNumber(std::string_view field) {
  std::string_view digits = field;
  if (digits.size() > 1 && digits[0] == '+' && digits[1] != '+' &&
      digits[1] != '-') {
    digits.remove_prefix(1);  // from_chars takes no '+'
  }
  double number = 0.0;
  const char* last = digits.data() + digits.size();
  const auto [end, error] = std::from_chars(digits.data(), last, number);
  if (end != last ||
      (error != std::errc() && error != std::errc::result_out_of_range)) {
    return std::nullopt;
  }
  if (error == std::errc::result_out_of_range) {
    const std::string text(field);
    return std::strtod(text.c_str(), nullptr);
  }
  return number;
}

std::string ColumnLabel(int column) {
  return std::string("column '") + kColumnNames[column] + "'";
}

bool IsRecognisedMetaKey(const std::string& key) {
  return key == "quantity" || key == "units" || key == "clothfit-table";
}

// Parsing state shared by the header and row readers.
class TableParser {
 public:
  TableParser(const std::string& name, const ReadTableOptions& options)
      : name_(name), options_(options) {}

  ReadTableResult Parse(std::string_view text);
  // Line by line (without its '\n'), then Finish: what Parse does, for a
  // file read piece by piece.
  void Line(std::string_view content);
  ReadTableResult Finish();
  size_t rows() const { return result_.table.rows.size(); }
  void Reserve(size_t rows) { result_.table.rows.reserve(rows); }

 private:
  [[noreturn]] void Fail(int line, int column, const std::string& problem) {
    throw InputError(FormatLocation(name_, line, column) + ": " + problem);
  }

  void ParseMetadata(std::string_view content, int line);
  void ParseHeader(std::string_view text, int line);
  // Requires all columns in [first, first + count) to be present.
  void RequireAll(int first, int count, int line);
  // The first present column in [first, first + count), or -1.
  int FirstPresent(int first, int count) const;
  bool Has(int column) const { return field_of_[column] >= 0; }
  void ParseRow(std::string_view text, int line);
  double Angle(int column) const;

  const std::string& name_;
  const ReadTableOptions& options_;
  bool has_values_ = true;  // false: a directions-only table
  ReadTableResult result_;
  int line_ = 0;         // lines seen
  int header_line_ = 0;  // line of the header, 0 before it
  bool radians_ = false;
  int quantity_line_ = 0;
  int units_line_ = 0;
  // Field index (0-based) of each known column, -1 when absent.
  std::array<int, kColumnCount> field_of_{};
  std::vector<std::string> header_names_;
  bool incident_columns_ = false;
  // Numbers of the row being parsed, indexed by ColumnId.
  std::array<double, kColumnCount> numbers_{};
};

void TableParser::ParseMetadata(std::string_view content, int line) {
  // The format line "# clothfit-table N": this reader reads version 1.
  if (const auto version =
          text_util::FormatVersion(content, "clothfit-table")) {
    if (*version != "1") {
      Fail(line, 0,
           "unsupported table format version " + Quote(*version) +
               " (this clothfit reads '# clothfit-table 1')");
    }
    return;
  }
  const size_t colon = content.find(':');
  if (colon == std::string_view::npos) return;  // A comment.
  const std::string key = Lower(Trim(content.substr(0, colon)));
  const std::string value(Trim(content.substr(colon + 1)));
  if (key.empty() || key == "clothfit-table") return;
  MeasurementTable& table = result_.table;
  if (key == "quantity") {
    const std::optional<Quantity> quantity = ParseQuantity(value);
    if (!quantity) {
      Fail(line, 0,
           "metadata 'quantity': unknown quantity " + Quote(value) +
               " (expected brdf, cosine_weighted or transmittance)");
    }
    if (quantity_line_ > 0 && *quantity != table.quantity) {
      Fail(line, 0,
           "metadata 'quantity': given again with a different value (first "
           "on line " +
               std::to_string(quantity_line_) + ")");
    }
    table.quantity = *quantity;
    quantity_line_ = line;
  } else if (key == "units") {
    const std::string units = Lower(value);
    if (units != "degrees" && units != "radians") {
      Fail(line, 0,
           "metadata 'units': unknown units " + Quote(value) +
               " (expected degrees or radians)");
    }
    if (units_line_ > 0 && radians_ != (units == "radians")) {
      Fail(line, 0,
           "metadata 'units': given again with a different value (first on "
           "line " +
               std::to_string(units_line_) + ")");
    }
    radians_ = units == "radians";
    units_line_ = line;
  }
  table.metadata.emplace_back(key, value);
}

int TableParser::FirstPresent(int first, int count) const {
  for (int column = first; column < first + count; ++column) {
    if (Has(column)) return column;
  }
  return -1;
}

void TableParser::RequireAll(int first, int count, int line) {
  for (int column = first; column < first + count; ++column) {
    if (!Has(column)) Fail(line, 0, "missing " + ColumnLabel(column));
  }
}

void TableParser::ParseHeader(std::string_view text, int line) {
  field_of_.fill(-1);
  const std::vector<std::string_view> fields = SplitFields(text);
  for (size_t i = 0; i < fields.size(); ++i) {
    const int field_column = static_cast<int>(i) + 1;
    std::string name = Lower(Trim(fields[i]));
    if (name.empty()) Fail(line, field_column, "empty column name");
    const auto known =
        std::find(kColumnNames.begin(), kColumnNames.end(), name);
    if (known == kColumnNames.end()) {
      Fail(line, field_column,
           "unknown column " + Quote(name) + " (expected " +
               "theta_i,phi_i,theta_o,phi_o or wi_x,wi_y,wi_z,wo_x,wo_y,wo_z; "
               "value or r,g,b; optional sigma or sigma_r,sigma_g,sigma_b, "
               "weight, alpha, s,t, normal_x,normal_y,normal_z)");
    }
    const int column = static_cast<int>(known - kColumnNames.begin());
    if (Has(column)) {
      Fail(line, field_column,
           "duplicate " + ColumnLabel(column) + " (first at column " +
               std::to_string(field_of_[column] + 1) + ")");
    }
    field_of_[column] = static_cast<int>(i);
    header_names_.push_back(std::move(name));
  }

  MeasurementTable& table = result_.table;
  const bool transmittance = table.quantity == Quantity::kTransmittance;

  // Directions: angles or vectors, never both.
  const int first_angle = FirstPresent(kThetaI, 4);
  const int first_vector = FirstPresent(kWiX, 6);
  if (first_angle >= 0 && first_vector >= 0) {
    const int later = field_of_[first_angle] > field_of_[first_vector]
                          ? first_angle
                          : first_vector;
    Fail(line, field_of_[later] + 1,
         ColumnLabel(later) +
             ": angle columns (theta_*, phi_*) and vector columns (wi_*, "
             "wo_*) cannot be mixed");
  }
  if (first_vector >= 0) {
    table.direction_columns = DirectionColumns::kVectors;
    incident_columns_ = !transmittance || FirstPresent(kWiX, 3) >= 0;
    if (incident_columns_) RequireAll(kWiX, 3, line);
    RequireAll(kWoX, 3, line);
  } else {
    table.direction_columns = DirectionColumns::kAngles;
    incident_columns_ = !transmittance || FirstPresent(kThetaI, 2) >= 0;
    if (incident_columns_) RequireAll(kThetaI, 2, line);
    RequireAll(kThetaO, 2, line);
  }

  // Values: "value" or "r,g,b".
  if (Has(kValue)) {
    const int rgb = FirstPresent(kR, 3);
    if (rgb >= 0) {
      Fail(line, field_of_[rgb] + 1,
           ColumnLabel(rgb) + ": 'value' and 'r,g,b' cannot be mixed");
    }
    table.channels = 1;
  } else if (FirstPresent(kR, 3) >= 0) {
    RequireAll(kR, 3, line);
    table.channels = 3;
  } else if (options_.values_optional) {
    table.channels = 3;
    has_values_ = false;
  } else {
    Fail(line, 0, "missing column 'value' (or 'r,g,b')");
  }

  // Optional columns.
  const int per_channel_sigma = FirstPresent(kSigmaR, 3);
  if (Has(kSigma) && per_channel_sigma >= 0) {
    Fail(line, field_of_[per_channel_sigma] + 1,
         ColumnLabel(per_channel_sigma) +
             ": 'sigma' and 'sigma_r,sigma_g,sigma_b' cannot be mixed");
  }
  if (per_channel_sigma >= 0) {
    if (table.channels == 1) {
      Fail(line, field_of_[per_channel_sigma] + 1,
           ColumnLabel(per_channel_sigma) +
               ": per-channel sigma needs 'r,g,b' values (use 'sigma' with "
               "'value')");
    }
    RequireAll(kSigmaR, 3, line);
  }
  table.has_sigma = Has(kSigma) || per_channel_sigma >= 0;
  table.has_weight = Has(kWeight);
  table.has_alpha = Has(kAlpha);
  if (Has(kS) || Has(kT)) RequireAll(kS, 2, line);
  table.has_texels = Has(kS);
  if (FirstPresent(kNormalX, 3) >= 0) RequireAll(kNormalX, 3, line);
  table.has_normal = Has(kNormalX);
}

double TableParser::Angle(int column) const {
  return radians_ ? numbers_[column] : numbers_[column] * kRadiansPerDegree;
}

void TableParser::ParseRow(std::string_view text, int line) {
  const std::vector<std::string_view> fields = SplitFields(text);
  const size_t expected = header_names_.size();
  if (fields.size() < expected) {
    Fail(line, static_cast<int>(fields.size()) + 1,
         "row has " + std::to_string(fields.size()) + " fields, header has " +
             std::to_string(expected) + " (missing column '" +
             header_names_[fields.size()] + "')");
  }
  if (fields.size() > expected) {
    Fail(line, static_cast<int>(expected) + 1,
         "row has " + std::to_string(fields.size()) + " fields, header has " +
             std::to_string(expected));
  }

  // Syntax, left to right.
  std::array<int, kColumnCount> column_of_field{};
  for (int column = 0; column < kColumnCount; ++column) {
    if (Has(column)) column_of_field[field_of_[column]] = column;
  }
  for (size_t i = 0; i < fields.size(); ++i) {
    const int column = column_of_field[i];
    const int field_column = static_cast<int>(i) + 1;
    const std::string_view field = Trim(fields[i]);
    if (field.empty()) {
      Fail(line, field_column,
           ColumnLabel(column) + ": empty field (expected a number)");
    }
    const std::optional<double> parsed = ParseNumber(field);
    if (!parsed) {
      Fail(line, field_column,
           ColumnLabel(column) + ": cannot parse " + Quote(field) +
               " as a number");
    }
    const double number = *parsed;
    if (!std::isfinite(number)) {
      Fail(line, field_column,
           ColumnLabel(column) + ": " + Quote(field) +
               " is not a finite number");
    }
    numbers_[column] = number;
  }

  // Meaning, in column order.
  auto fail_at = [&](int column, const std::string& problem) {
    Fail(line, field_of_[column] + 1, ColumnLabel(column) + ": " + problem);
  };
  auto vector_at = [&](int first) {
    const glm::dvec3 v(numbers_[first], numbers_[first + 1],
                       numbers_[first + 2]);
    // Scale first so that tiny or huge components neither underflow nor
    // overflow while normalising.
    const double scale =
        std::max({std::abs(v.x), std::abs(v.y), std::abs(v.z)});
    if (!(scale > 0.0)) {
      fail_at(first, std::string("zero vector (") + kColumnNames[first] + ", " +
                         kColumnNames[first + 1] + ", " +
                         kColumnNames[first + 2] + ")");
    }
    const glm::dvec3 scaled = v / scale;
    return scaled / std::sqrt(scaled.x * scaled.x + scaled.y * scaled.y +
                              scaled.z * scaled.z);
  };
  TableRow row;
  row.source_line = line;
  const MeasurementTable& table = result_.table;
  if (table.direction_columns == DirectionColumns::kAngles) {
    const double max_theta = radians_ ? kPi : 180.0;
    const double max_phi = radians_ ? 2.0 * kPi : 360.0;
    const char* range_theta = radians_ ? "[0, pi] radians" : "[0, 180] degrees";
    const char* range_phi =
        radians_ ? "[-2 pi, 2 pi] radians" : "[-360, 360] degrees";
    for (int column = incident_columns_ ? kThetaI : kThetaO; column <= kPhiO;
         ++column) {
      const bool theta = column == kThetaI || column == kThetaO;
      const double value = numbers_[column];
      const double low = theta ? 0.0 : -max_phi;
      const double high = theta ? max_theta : max_phi;
      if (value < low || value > high) {
        fail_at(column, "angle " + FormatNumber(value) + " is out of range " +
                            (theta ? range_theta : range_phi));
      }
    }
    if (incident_columns_) {
      row.wi = DirectionFromAngles(Angle(kThetaI), Angle(kPhiI));
    }
    row.wo = DirectionFromAngles(Angle(kThetaO), Angle(kPhiO));
  } else {
    if (incident_columns_) row.wi = vector_at(kWiX);
    row.wo = vector_at(kWoX);
  }

  // Values, sigmas and weights beyond kMaxTableMagnitude (or sigmas below its
  // inverse) are not measurements: their squared normalised residuals
  // would overflow a fit's cost.
  auto check_magnitude = [&](int column) {
    if (std::abs(numbers_[column]) > kMaxTableMagnitude) {
      fail_at(column, FormatNumber(numbers_[column]) +
                          " is out of range (magnitude at most 1e30)");
    }
    return numbers_[column];
  };
  if (!has_values_) {
    row.value = glm::dvec3(0.0);
  } else if (table.channels == 1) {
    row.value = glm::dvec3(check_magnitude(kValue));
  } else {
    row.value = glm::dvec3(check_magnitude(kR), check_magnitude(kG),
                           check_magnitude(kB));
  }

  auto check_sigma = [&](int column) {
    if (!(numbers_[column] > 0.0)) {
      fail_at(column,
              "sigma must be positive, got " + FormatNumber(numbers_[column]));
    }
    if (numbers_[column] < 1.0 / kMaxTableMagnitude) {
      fail_at(column, "sigma " + FormatNumber(numbers_[column]) +
                          " is out of range (at least 1e-30)");
    }
    return check_magnitude(column);
  };
  if (Has(kSigma)) {
    row.sigma = glm::dvec3(check_sigma(kSigma));
  } else if (Has(kSigmaR)) {
    const double r = check_sigma(kSigmaR);
    const double g = check_sigma(kSigmaG);
    const double b = check_sigma(kSigmaB);
    row.sigma = glm::dvec3(r, g, b);
  }

  if (Has(kWeight)) {
    if (numbers_[kWeight] < 0.0) {
      fail_at(kWeight, "weight must be non-negative, got " +
                           FormatNumber(numbers_[kWeight]));
    }
    row.weight = check_magnitude(kWeight);
  }

  if (Has(kAlpha)) {
    if (numbers_[kAlpha] < 0.0 || numbers_[kAlpha] > 1.0) {
      fail_at(kAlpha,
              "must be in [0, 1], got " + FormatNumber(numbers_[kAlpha]));
    }
    row.alpha = numbers_[kAlpha];
  }

  if (Has(kNormalX)) row.normal = vector_at(kNormalX);

  if (Has(kS)) {
    auto texel = [&](int column) {
      const double value = numbers_[column];
      if (value < 0.0 || value > 2147483647.0 || value != std::floor(value)) {
        fail_at(column, "expected a non-negative integer, got " +
                            Quote(Trim(fields[field_of_[column]])));
      }
      return static_cast<int>(value);
    };
    row.s = texel(kS);
    row.t = texel(kT);
  }

  result_.table.rows.push_back(row);
}

void TableParser::Line(std::string_view content) {
  ++line_;
  // A UTF-8 byte order mark (spreadsheet exports) is not part of the data.
  if (line_ == 1 && content.substr(0, 3) == "\xEF\xBB\xBF") {
    content.remove_prefix(3);
  }
  if (!content.empty() && content.back() == '\r') content.remove_suffix(1);
  const std::string_view trimmed = Trim(content);
  if (trimmed.empty()) return;
  if (trimmed.front() == '#') {
    // Before the header: metadata; after it: a comment.
    if (header_line_ == 0) ParseMetadata(trimmed.substr(1), line_);
    return;
  }
  if (header_line_ == 0) {
    ParseHeader(content, line_);
    header_line_ = line_;
    return;
  }
  if (!options_.skip_invalid) {
    ParseRow(content, line_);
    return;
  }
  try {
    ParseRow(content, line_);
  } catch (const InputError& error) {
    if (result_.skipped == 0) result_.first_skip_reason = error.what();
    ++result_.skipped;
  }
}

ReadTableResult TableParser::Parse(std::string_view text) {
  size_t start = 0;
  while (start <= text.size()) {
    size_t end = text.find('\n', start);
    if (end == std::string_view::npos) end = text.size();
    Line(text.substr(start, end - start));
    start = end + 1;
  }
  return Finish();
}

ReadTableResult TableParser::Finish() {
  const int header_line = header_line_;
  if (header_line == 0) {
    Fail(0, 0,
         "no header (expected a line of column names such as "
         "theta_i,phi_i,theta_o,phi_o,r,g,b)");
  }
  if (result_.table.rows.empty()) {
    if (result_.skipped > 0) {
      Fail(header_line, 0,
           "table has no rows: all " + std::to_string(result_.skipped) +
               " rows were invalid (first: " + result_.first_skip_reason + ")");
    }
    Fail(header_line, 0, "table has no rows (only a header)");
  }
  result_.table.source = name_;
  return std::move(result_);
}

}  // namespace

std::optional<Quantity> ParseQuantity(const std::string& text) {
  const std::string name = Lower(Trim(text));
  if (name == "brdf") return Quantity::kBrdf;
  if (name == "cosine_weighted") return Quantity::kCosineWeighted;
  if (name == "transmittance") return Quantity::kTransmittance;
  return std::nullopt;
}

const char* QuantityName(Quantity quantity) {
  switch (quantity) {
    case Quantity::kBrdf:
      return "brdf";
    case Quantity::kCosineWeighted:
      return "cosine_weighted";
    case Quantity::kTransmittance:
      return "transmittance";
  }
  return "brdf";
}

std::optional<std::string> MeasurementTable::Meta(
    const std::string& key) const {
  const std::string wanted = Lower(Trim(key));
  for (const auto& [name, value] : metadata) {
    if (Lower(name) == wanted) return value;
  }
  return std::nullopt;
}

void MeasurementTable::SetMeta(const std::string& key,
                               const std::string& value) {
  const std::string wanted = Lower(Trim(key));
  bool replaced = false;
  for (auto it = metadata.begin(); it != metadata.end();) {
    if (Lower(it->first) != wanted) {
      ++it;
    } else if (!replaced) {
      it->second = value;
      replaced = true;
      ++it;
    } else {
      it = metadata.erase(it);  // Later duplicates would shadow nothing.
    }
  }
  if (!replaced) metadata.emplace_back(wanted, value);
}

ReadTableResult ReadTable(const std::string& path,
                          const ReadTableOptions& options) {
  // Piece by piece: the file's text is never held whole (a 1 GB table
  // needs only its rows' memory).
  TableParser parser(path, options);
  std::string pending;  // a line split across pieces
  // The rows' vector is sized from the first piece's rows per byte: grown
  // by doubling, it would peak at up to 3 x the rows' memory while copying.
  std::error_code error;
  const uintmax_t file_bytes = std::filesystem::file_size(path, error);
  size_t bytes_read = 0;
  bool reserved = error.value() != 0;
  ReadFileInChunks(path, [&](std::string_view chunk) {
    bytes_read += chunk.size();
    size_t start = 0;
    while (true) {
      const size_t end = chunk.find('\n', start);
      if (end == std::string_view::npos) break;
      if (pending.empty()) {
        parser.Line(chunk.substr(start, end - start));
      } else {
        pending.append(chunk.substr(start, end - start));
        parser.Line(pending);
        pending.clear();
      }
      start = end + 1;
    }
    pending.append(chunk.substr(start));
    if (!reserved && parser.rows() > 0) {
      reserved = true;
      const double per_byte = static_cast<double>(parser.rows()) / bytes_read;
      parser.Reserve(static_cast<size_t>(1.02 * per_byte * file_bytes) + 16);
    }
  });
  parser.Line(pending);  // the last line (empty after a final '\n')
  return parser.Finish();
}

ReadTableResult ParseTable(const std::string& text, const std::string& name,
                           const ReadTableOptions& options) {
  return TableParser(name, options).Parse(text);
}

std::string FormatTable(const MeasurementTable& table) {
  const bool vectors = table.direction_columns == DirectionColumns::kVectors;
  // Transmittance tables leave out the incident direction unless a row has
  // one other than the default +z, which would otherwise be lost.
  bool incident = table.quantity != Quantity::kTransmittance;
  for (const TableRow& row : table.rows) {
    if (row.wi != glm::dvec3(0.0, 0.0, 1.0)) incident = true;
  }

  std::string out = "# clothfit-table 1\n";
  out += std::string("# quantity: ") + QuantityName(table.quantity) + "\n";
  out += "# units: degrees\n";
  for (const auto& [key, value] : table.metadata) {
    std::string name = Lower(Trim(OneLine(key)));
    std::replace(name.begin(), name.end(), ':', '_');
    if (name.empty() || IsRecognisedMetaKey(name)) continue;
    out += "# " + name + ": " + OneLine(value) + "\n";
  }

  std::vector<std::string> header;
  if (vectors) {
    if (incident) header.insert(header.end(), {"wi_x", "wi_y", "wi_z"});
    header.insert(header.end(), {"wo_x", "wo_y", "wo_z"});
  } else {
    if (incident) header.insert(header.end(), {"theta_i", "phi_i"});
    header.insert(header.end(), {"theta_o", "phi_o"});
  }
  const bool one_channel = table.channels == 1;
  if (one_channel) {
    header.push_back("value");
  } else {
    header.insert(header.end(), {"r", "g", "b"});
  }
  if (table.has_sigma) {
    if (one_channel) {
      header.push_back("sigma");
    } else {
      header.insert(header.end(), {"sigma_r", "sigma_g", "sigma_b"});
    }
  }
  if (table.has_weight) header.push_back("weight");
  if (table.has_alpha) header.push_back("alpha");
  if (table.has_normal) {
    header.insert(header.end(), {"normal_x", "normal_y", "normal_z"});
  }
  if (table.has_texels) header.insert(header.end(), {"s", "t"});
  for (size_t i = 0; i < header.size(); ++i) {
    if (i > 0) out += ',';
    out += header[i];
  }
  out += '\n';

  std::vector<double> numbers;
  for (const TableRow& row : table.rows) {
    numbers.clear();
    auto add_direction = [&](const glm::dvec3& w) {
      if (vectors) {
        numbers.insert(numbers.end(), {w.x, w.y, w.z});
      } else {
        double theta = 0.0;
        double phi = 0.0;
        AnglesFromDirection(w, &theta, &phi);
        numbers.insert(numbers.end(),
                       {theta * kDegreesPerRadian, phi * kDegreesPerRadian});
      }
    };
    if (incident) add_direction(row.wi);
    add_direction(row.wo);
    if (one_channel) {
      numbers.push_back(row.value.x);
    } else {
      numbers.insert(numbers.end(), {row.value.x, row.value.y, row.value.z});
    }
    if (table.has_sigma) {
      if (one_channel) {
        numbers.push_back(row.sigma.x);
      } else {
        numbers.insert(numbers.end(), {row.sigma.x, row.sigma.y, row.sigma.z});
      }
    }
    if (table.has_weight) numbers.push_back(row.weight);
    if (table.has_alpha) numbers.push_back(row.alpha);
    if (table.has_normal) {
      numbers.insert(numbers.end(), {row.normal.x, row.normal.y, row.normal.z});
    }
    for (size_t i = 0; i < numbers.size(); ++i) {
      if (i > 0) out += ',';
      out += FormatNumber(numbers[i]);
    }
    if (table.has_texels) {
      out += ',' + std::to_string(row.s) + ',' + std::to_string(row.t);
    }
    out += '\n';
  }
  return out;
}

void WriteTable(const MeasurementTable& table, const std::string& path) {
  WriteFileAtomically(path, FormatTable(table));
}

glm::dvec3 DirectionFromAngles(double theta, double phi) {
  const double sin_theta = std::sin(theta);
  return glm::dvec3(sin_theta * std::cos(phi), sin_theta * std::sin(phi),
                    std::cos(theta));
}

void AnglesFromDirection(const glm::dvec3& w, double* theta, double* phi) {
  // atan2 of the in-plane length and z equals acos(z) for unit vectors, but
  // keeps full precision near the poles and needs no prior normalisation.
  *theta = std::atan2(std::hypot(w.x, w.y), w.z);
  *phi = std::atan2(w.y, w.x);
}

}  // namespace clothfit
