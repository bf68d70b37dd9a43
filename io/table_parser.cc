#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <string>

#include "io/table_parser_internal.h"
#include "io/text_util.h"

namespace clothfit {
namespace table_internal {

using text_util::Lower;
using text_util::Quote;
using text_util::SplitFields;
using text_util::Trim;

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

void TableParser::CheckLineLength(size_t bytes) const {
  if (bytes > kMaxLineBytes) {
    Fail(line_ + 1, 0,
         "line longer than " + std::to_string(kMaxLineBytes >> 20) +
             " MiB (the limit of a table line; is this a table?)");
  }
}

void TableParser::Line(std::string_view content) {
  CheckLineLength(content.size());
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

}  // namespace table_internal
}  // namespace clothfit
