#include <algorithm>
#include <charconv>
#include <cstdlib>
#include <string>
#include <utility>

#include "io/table_parser_internal.h"
#include "io/text_util.h"
#include "models/math.h"

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
  if (key.empty()) return;
  if (key == "clothfit-table") {  // "# clothfit-table: N", the same line
    if (value != "1") {
      Fail(line, 0,
           "unsupported table format version " + Quote(value) +
               " (this clothfit reads '# clothfit-table 1')");
    }
    return;
  }
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

void TableParser::DetectSeparator(std::string_view header) {
  size_t count[3] = {0, 0, 0};
  bool quoted = false;
  for (const char c : header) {
    if (c == '"') quoted = !quoted;
    if (quoted) continue;
    count[0] += c == ',';
    count[1] += c == ';';
    count[2] += c == '\t';
  }
  separator_ = ',';
  if (count[1] > count[0] && count[1] >= count[2]) separator_ = ';';
  if (count[2] > count[0] && count[2] > count[1]) separator_ = '\t';
}

namespace {

// A header field split into its name and its unit: "theta_i [deg]" and
// "theta_i (deg)" give ("theta_i", "deg"); both lower-case and trimmed.
std::pair<std::string, std::string> NameAndUnit(std::string_view field) {
  field = Trim(field);
  if (!field.empty() && (field.back() == ']' || field.back() == ')')) {
    const char open = field.back() == ']' ? '[' : '(';
    const size_t at = field.rfind(open);
    if (at != std::string_view::npos && at > 0) {
      return {Lower(Trim(field.substr(0, at))),
              Lower(Trim(field.substr(at + 1, field.size() - at - 2)))};
    }
  }
  return {Lower(field), ""};
}

bool IsAngleColumn(int column) { return column >= kThetaI && column <= kPhiO; }

bool IsValueColumn(int column) {
  return column == kValue || (column >= kR && column <= kSigmaB);
}

}  // namespace

void TableParser::ApplyUnit(int column, const std::string& unit, int line,
                            int field_column) {
  column_factor_[column] = 1.0;
  column_radians_[column] = radians_;
  if (unit.empty()) return;
  auto fail = [&](const std::string& expected) {
    Fail(line, field_column,
         ColumnLabel(column) + ": unknown unit " + Quote(unit) + " (" +
             expected + ")");
  };
  if (IsAngleColumn(column)) {
    const bool degrees = unit == "deg" || unit == "degree" ||
                         unit == "degrees" || unit == "\xC2\xB0";
    const bool radians = unit == "rad" || unit == "radian" || unit == "radians";
    if (!degrees && !radians) fail("expected deg or rad");
    if (units_line_ > 0 && radians != radians_) {
      Fail(line, field_column,
           ColumnLabel(column) + ": unit " + Quote(unit) +
               " contradicts the 'units' metadata on line " +
               std::to_string(units_line_));
    }
    column_radians_[column] = radians;
    column_units_ = true;
    return;
  }
  if (IsValueColumn(column)) {
    if (unit == "%") {
      column_factor_[column] = 0.01;
      percent_unit_ = true;
    } else if (unit != "1/sr" && unit != "sr^-1" && unit != "sr-1" &&
               unit != "1") {
      fail("expected 1/sr, sr^-1, 1 or %");
    }
    return;
  }
  Fail(line, field_column,
       ColumnLabel(column) + ": takes no unit, got " + Quote(unit));
}

void TableParser::ParseHeader(std::string_view text, int line) {
  field_of_.fill(-1);
  DetectSeparator(text);
  const std::vector<std::string_view> fields = SplitFields(text, separator_);
  std::vector<std::string> names(kColumnNames.begin(), kColumnNames.end());
  for (size_t i = 0; i < fields.size(); ++i) {
    const int field_column = static_cast<int>(i) + 1;
    auto [name, unit] = NameAndUnit(fields[i]);
    if (name.empty()) Fail(line, field_column, "empty column name");
    const auto known =
        std::find(kColumnNames.begin(), kColumnNames.end(), name);
    if (known == kColumnNames.end()) {
      Fail(line, field_column,
           "unknown column " + Quote(name) +
               text_util::DidYouMean(name, names) + " (expected " +
               "theta_i,phi_i,theta_o,phi_o or wi_x,wi_y,wi_z,wo_x,wo_y,wo_z; "
               "value or r,g,b; optional sigma or sigma_r,sigma_g,sigma_b, "
               "weight, alpha, s,t, normal_x,normal_y,normal_z; a unit may "
               "follow a name: 'theta_i [deg]', 'theta_i (rad)')");
    }
    const int column = static_cast<int>(known - kColumnNames.begin());
    if (Has(column)) {
      Fail(line, field_column,
           "duplicate " + ColumnLabel(column) + " (first at column " +
               std::to_string(field_of_[column] + 1) + ")");
    }
    ApplyUnit(column, unit, line, field_column);
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
    result_.table.source = name_;
    return;
  }
  TableRow row;
  if (!options_.skip_invalid) {
    ParseRow(content, line_, &row);
  } else {
    try {
      ParseRow(content, line_, &row);
    } catch (const InputError& error) {
      if (result_.skipped == 0) result_.first_skip_reason = error.what();
      ++result_.skipped;
      return;
    }
  }
  // Outside the try: what the sink throws is not a row to skip.
  Accept(row);
}

void TableParser::Accept(const TableRow& row) {
  ++rows_;
  if (options_.row_sink) {
    options_.row_sink(result_.table, row);
  } else {
    result_.table.rows.push_back(row);
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
  if (rows_ == 0) {
    if (result_.skipped > 0) {
      Fail(header_line, 0,
           "table has no rows: all " + std::to_string(result_.skipped) +
               " rows were invalid (first: " + result_.first_skip_reason + ")");
    }
    Fail(header_line, 0, "table has no rows (only a header)");
  }
  result_.table.source = name_;
  AddWarnings();
  return std::move(result_);
}

void TableParser::SampleValue(double value) {
  if (value_count_ == 0) largest_value_ = smallest_value_ = value;
  largest_value_ = std::max(largest_value_, value);
  smallest_value_ = std::min(smallest_value_, value);
  if (value_count_++ % value_stride_ != 0) return;
  value_sample_.push_back(value);
  if (value_sample_.size() < kValueSample) return;
  for (size_t i = 0; 2 * i < value_sample_.size(); ++i) {
    value_sample_[i] = value_sample_[2 * i];
  }
  value_sample_.resize((value_sample_.size() + 1) / 2);
  value_stride_ *= 2;
}

void TableParser::AddWarnings() {
  const MeasurementTable& table = result_.table;
  const size_t rows = rows_;
  // Radians read as degrees: every angle within [0, pi/2] (theta) and
  // [-2 pi, 2 pi] (phi) means directions within 1.6 degrees of the normal,
  // which no gonioreflectometer table is.
  if (table.direction_columns == DirectionColumns::kAngles && !radians_ &&
      !column_units_ && rows >= 3 && largest_theta_ > 0.0 &&
      largest_theta_ <= kPi / 2.0 + 1e-9 && largest_phi_ <= 2.0 * kPi + 1e-9) {
    result_.warnings.push_back(
        name_ + ": every angle is within the range of radians (largest theta " +
        text_util::FormatNumber(largest_theta_, 4) + ", largest |phi| " +
        text_util::FormatNumber(largest_phi_, 4) + ") but the table is read " +
        (units_line_ > 0 ? "in degrees, as its 'units' line says"
                         : "in degrees (the default)") +
        ": if the angles are radians, add the line '# units: radians' or "
        "name the columns 'theta_i [rad]', ...");
  }
  // Percent: a reflectance (brdf, cosine-weighted or transmittance) whose
  // median over the rows exceeds 1 while no value exceeds 100.
  if (has_values_ && !percent_unit_ && !value_sample_.empty() &&
      smallest_value_ >= 0.0 && largest_value_ <= 100.0) {
    std::vector<double> sample = value_sample_;
    const auto middle = sample.begin() + sample.size() / 2;
    std::nth_element(sample.begin(), middle, sample.end());
    if (*middle > 1.0) {
      result_.warnings.push_back(
          name_ + ": the values look like percent (median " +
          text_util::FormatNumber(*middle, 4) + ", largest " +
          text_util::FormatNumber(largest_value_, 4) +
          "; a reflectance's median is below 1): if they are, give the "
          "value columns the unit '[%]' ('value [%]' or 'r [%]', ...) or "
          "divide them by 100");
    }
  }
}

}  // namespace table_internal
}  // namespace clothfit
