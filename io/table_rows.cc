#include <algorithm>
#include <cmath>
#include <string>

#include "io/table_parser_internal.h"
#include "io/text_util.h"
#include "models/math.h"

namespace clothfit {
namespace table_internal {

using text_util::FormatNumber;
using text_util::Quote;
using text_util::SplitFields;
using text_util::Trim;

double TableParser::Angle(int column) const {
  return column_radians_[column] ? numbers_[column] : Radians(numbers_[column]);
}

void TableParser::ParseRow(std::string_view text, int line, TableRow* out) {
  const std::vector<std::string_view> fields = SplitFields(text, separator_);
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
    std::optional<double> parsed = ParseNumber(field);
    if (!parsed && separator_ != ',' &&
        field.find(',') != std::string_view::npos) {
      // A decimal comma ("0,25"), as spreadsheets write with ';' or tabs.
      std::string dotted(field);
      std::replace(dotted.begin(), dotted.end(), ',', '.');
      parsed = ParseNumber(dotted);
    }
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
    numbers_[column] = number * column_factor_[column];
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
    for (int column = incident_columns_ ? kThetaI : kThetaO; column <= kPhiO;
         ++column) {
      const bool radians = column_radians_[column];
      const double max_theta = radians ? kPi : 180.0;
      const double max_phi = radians ? 2.0 * kPi : 360.0;
      const char* range_theta =
          radians ? "[0, pi] radians" : "[0, 180] degrees";
      const char* range_phi =
          radians ? "[-2 pi, 2 pi] radians" : "[-360, 360] degrees";
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

  // A valid row: what AddWarnings looks at.
  if (table.direction_columns == DirectionColumns::kAngles) {
    for (int column = incident_columns_ ? kThetaI : kThetaO; column <= kPhiO;
         ++column) {
      double& largest = column == kThetaI || column == kThetaO ? largest_theta_
                                                               : largest_phi_;
      largest = std::max(largest, std::abs(numbers_[column]));
    }
  }
  if (has_values_) {
    SampleValue(table.channels == 1
                    ? row.value.x
                    : (row.value.x + row.value.y + row.value.z) / 3.0);
  }
  *out = row;
}

}  // namespace table_internal
}  // namespace clothfit
