#include "io/table.h"

#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <filesystem>
#include <functional>
#include <glm/common.hpp>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "io/atomic_file.h"
#include "io/input_error.h"
#include "io/table_parser_internal.h"
#include "io/text_util.h"
#include "models/math.h"

namespace clothfit {

using table_internal::IsRecognisedMetaKey;
using table_internal::TableParser;
using text_util::FormatNumber;
using text_util::Lower;
using text_util::OneLine;
using text_util::Trim;

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

std::optional<std::string> ArbitraryScaleNote(const MeasurementTable& table) {
  for (const auto& [key, value] : table.metadata) {
    const std::string v = Lower(value);
    const bool says =
        (Lower(key) == "scale" && (v == "arbitrary" || v == "relative")) ||
        (v.find("arbitrary") != std::string::npos &&
         v.find("scale") != std::string::npos);
    if (says) return key + ": " + value;
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

namespace {

// Hands each line of a piece of a file that ends in it to the parser
// (without its '\n'; a line begun in an earlier piece is gathered in
// *pending), calling after_line() after each, and keeps the piece's
// unfinished last line in *pending.
template <typename AfterLine>
void FeedLines(std::string_view chunk, std::string* pending,
               TableParser* parser, const AfterLine& after_line) {
  size_t start = 0;
  while (true) {
    const size_t end = chunk.find('\n', start);
    if (end == std::string_view::npos) break;
    if (pending->empty()) {
      parser->Line(chunk.substr(start, end - start));
    } else {
      pending->append(chunk.substr(start, end - start));
      parser->Line(*pending);
      pending->clear();
    }
    after_line();
    start = end + 1;
  }
  pending->append(chunk.substr(start));
  parser->CheckLineLength(pending->size());
}

void FeedLines(std::string_view chunk, std::string* pending,
               TableParser* parser) {
  FeedLines(chunk, pending, parser, [] {});
}

}  // namespace

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
  bool reserved = error.value() != 0 || options.row_sink;
  ReadFileInChunks(path, [&](std::string_view chunk) {
    bytes_read += chunk.size();
    if (options.progress && error.value() == 0) {
      options.progress(static_cast<double>(bytes_read),
                       static_cast<double>(file_bytes));
    }
    FeedLines(chunk, &pending, &parser);
    if (!reserved && parser.rows() > 0) {
      reserved = true;
      const double per_byte = static_cast<double>(parser.rows()) / bytes_read;
      parser.Reserve(static_cast<size_t>(1.02 * per_byte * file_bytes) + 16);
    }
  });
  parser.Line(pending);  // the last line (empty after a final '\n')
  return parser.Finish();
}

MeasurementTable ReadTableHeader(const std::string& path,
                                 const ReadTableOptions& options) {
  struct HeaderDone {};  // stops the read at the header
  TableParser parser(path, options);
  std::string pending;
  try {
    ReadFileInChunks(path, [&](std::string_view chunk) {
      FeedLines(chunk, &pending, &parser, [&] {
        if (parser.HeaderRead()) throw HeaderDone();
      });
    });
  } catch (const HeaderDone&) {
    return parser.table();
  }
  parser.Line(pending);
  if (parser.HeaderRead()) return parser.table();
  parser.Finish();                         // throws: no header
  throw InputError(path + ": no header");  // not reached
}

ReadTableResult ParseTable(const std::string& text, const std::string& name,
                           const ReadTableOptions& options) {
  return TableParser(name, options).Parse(text);
}

namespace {

// Appends "theta,phi," in degrees for the unit vector w. A direction read
// from angles comes back through its unit vector a few ulps off (60 as
// 59.999999999999993): when the angles rounded to 15 significant digits
// give the same vector to 1e-15, they are written so; otherwise exactly.
void AppendAngles(const glm::dvec3& w, std::string* out) {
  double theta = 0.0;
  double phi = 0.0;
  AnglesFromDirection(w, &theta, &phi);
  const std::string theta15 = FormatNumber(Degrees(theta), 15);
  const std::string phi15 = FormatNumber(Degrees(phi), 15);
  const glm::dvec3 back =
      DirectionFromAngles(Radians(std::strtod(theta15.c_str(), nullptr)),
                          Radians(std::strtod(phi15.c_str(), nullptr)));
  const glm::dvec3 d = glm::abs(back - w);
  if (std::max({d.x, d.y, d.z}) <= 1e-15) {
    *out += theta15 + ',' + phi15 + ',';
  } else {
    *out +=
        FormatNumber(Degrees(theta)) + ',' + FormatNumber(Degrees(phi)) + ',';
  }
}

// The text of FormatTable, handed to `sink` in pieces of about 1 MiB (a
// table of millions of rows is never held as one string).
void FormatTableTo(const MeasurementTable& table,
                   const std::function<void(const std::string&)>& sink,
                   const TableProgress& progress = {}) {
  constexpr size_t kPiece = 1 << 20;
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
  size_t rows_done = 0;
  for (const TableRow& row : table.rows) {
    ++rows_done;
    numbers.clear();
    std::string angles;  // "theta,phi," of each direction written as angles
    auto add_direction = [&](const glm::dvec3& w) {
      if (vectors) {
        numbers.insert(numbers.end(), {w.x, w.y, w.z});
      } else {
        AppendAngles(w, &angles);
      }
    };
    if (incident) add_direction(row.wi);
    add_direction(row.wo);
    out += angles;
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
    if (out.size() >= kPiece) {
      sink(out);
      out.clear();
      if (progress) {
        progress(static_cast<double>(rows_done),
                 static_cast<double>(table.rows.size()));
      }
    }
  }
  sink(out);
}

// Throws unless every number of the rows is one ReadTable reads back: finite,
// and values, sigmas and weights at most kMaxTableMagnitude in magnitude.
void CheckRowsReadable(const MeasurementTable& table, const std::string& path) {
  for (size_t i = 0; i < table.rows.size(); ++i) {
    const TableRow& row = table.rows[i];
    const double numbers[] = {row.value.x, row.value.y, row.value.z,
                              row.sigma.x, row.sigma.y, row.sigma.z,
                              row.weight,  row.alpha};
    bool ok = std::isfinite(glm::dot(row.wi, row.wi)) &&
              std::isfinite(glm::dot(row.wo, row.wo)) &&
              std::isfinite(glm::dot(row.normal, row.normal));
    for (const double x : numbers) ok = ok && std::abs(x) <= kMaxTableMagnitude;
    if (ok) continue;
    std::ostringstream why;
    why.precision(6);
    why << path << ": not written: row " << i + 1;
    if (row.source_line > 0) why << " (line " << row.source_line << " read)";
    why << " has value (" << row.value.x << ", " << row.value.y << ", "
        << row.value.z << ") at wi (" << row.wi.x << ", " << row.wi.y << ", "
        << row.wi.z << "), wo (" << row.wo.x << ", " << row.wo.y << ", "
        << row.wo.z << "): a table holds finite numbers, values at most "
        << kMaxTableMagnitude
        << " in magnitude (the model's parameters give none there)";
    throw InputError(why.str());
  }
}

}  // namespace

std::string FormatTable(const MeasurementTable& table) {
  std::string text;
  FormatTableTo(table, [&](const std::string& piece) { text += piece; });
  return text;
}

void WriteTable(const MeasurementTable& table, const std::string& path,
                const TableProgress& progress) {
  CheckRowsReadable(table, path);
  OutputFile out(path);
  FormatTableTo(
      table, [&](const std::string& piece) { out.Write(piece); }, progress);
  out.Commit();
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

double RelativeNoiseFloor(std::vector<double> magnitudes) {
  double typical = 0.0;
  if (!magnitudes.empty()) {
    auto middle = magnitudes.begin() + magnitudes.size() / 2;
    std::nth_element(magnitudes.begin(), middle, magnitudes.end());
    typical = *middle;
    if (!(typical > 0.0)) {
      typical = *std::max_element(magnitudes.begin(), magnitudes.end());
    }
  }
  return typical > 0.0 ? 0.01 * typical : 1.0;
}

}  // namespace clothfit
