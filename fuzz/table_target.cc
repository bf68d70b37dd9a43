// Fuzz target: measurement tables (io/table.h).
#include <glm/geometric.hpp>
#include <string>

#include "fuzz/fuzz_util.h"
#include "io/input_error.h"
#include "io/table.h"

namespace clothfit {
namespace {

using fuzz::Finite;
using fuzz::Require;

bool FiniteVec(const glm::dvec3& v) {
  return Finite(v.x) && Finite(v.y) && Finite(v.z);
}

bool Unit(const glm::dvec3& v) {
  return FiniteVec(v) && std::abs(glm::length(v) - 1.0) < 1e-9;
}

}  // namespace

// What ReadTable promises of a table it returns (io/table.h, docs/formats.md).
void fuzz::CheckTable(const MeasurementTable& table) {
  Require(!table.rows.empty(), "a table read without error has rows");
  Require(table.channels == 1 || table.channels == 3, "channels 1 or 3");
  for (const TableRow& row : table.rows) {
    const std::string at = "row of line " + std::to_string(row.source_line);
    Require(Unit(row.wi) && Unit(row.wo), at + ": unit directions");
    Require(FiniteVec(row.value), at + ": finite value");
    Require(FiniteVec(row.sigma) && row.sigma.x > 0 && row.sigma.y > 0 &&
                row.sigma.z > 0,
            at + ": finite sigma > 0");
    Require(Finite(row.weight) && row.weight >= 0, at + ": weight >= 0");
    Require(Finite(row.alpha) && row.alpha >= 0 && row.alpha <= 1,
            at + ": alpha in [0, 1]");
    Require(Unit(row.normal), at + ": unit normal");
    Require(table.has_texels || (row.s == -1 && row.t == -1),
            at + ": no texel without s,t columns");
    if (table.channels == 1) {
      Require(row.value.x == row.value.y && row.value.x == row.value.z,
              at + ": a one-channel value in all three components");
    }
  }
}

namespace {

// A table that was read must write and read back: same rows, same numbers
// (17 significant digits), directions within rounding of the angles.
void CheckRoundTrip(const MeasurementTable& table) {
  MeasurementTable back;
  try {
    back = ParseTable(FormatTable(table), "round trip").table;
  } catch (const InputError& error) {
    throw FuzzContractError(std::string("FormatTable output does not read "
                                        "back: ") +
                            error.what());
  }
  Require(back.rows.size() == table.rows.size(), "round trip keeps the rows");
  Require(back.channels == table.channels && back.quantity == table.quantity,
          "round trip keeps channels and quantity");
  for (size_t i = 0; i < table.rows.size(); ++i) {
    const TableRow& a = table.rows[i];
    const TableRow& b = back.rows[i];
    const std::string at = "round trip of row " + std::to_string(i);
    Require(a.value == b.value && a.sigma == b.sigma && a.weight == b.weight &&
                a.alpha == b.alpha && a.s == b.s && a.t == b.t,
            at + ": same numbers");
    Require(glm::length(a.wi - b.wi) < 1e-9 && glm::length(a.wo - b.wo) < 1e-9,
            at + ": same directions");
    Require(!table.has_normal || glm::length(a.normal - b.normal) < 1e-9,
            at + ": same normal");
  }
}

void ParseAndCheck(const std::string& text, const ReadTableOptions& options) {
  ReadTableResult result;
  try {
    result = ParseTable(text, "fuzz.csv", options);
  } catch (const InputError&) {
    return;  // the expected answer to bad input
  }
  Require(result.skipped >= 0, "skipped >= 0");
  Require(options.skip_invalid || result.skipped == 0,
          "no skipped rows unless asked");
  fuzz::CheckTable(result.table);
  CheckRoundTrip(result.table);
}

}  // namespace

void FuzzTable(const uint8_t* data, size_t size) {
  const std::string text(reinterpret_cast<const char*>(data), size);
  ParseAndCheck(text, {});
  ReadTableOptions lenient;
  lenient.skip_invalid = true;
  lenient.values_optional = true;
  ParseAndCheck(text, lenient);
}

}  // namespace clothfit
