// What the rows of a least-squares problem say about it: the first
// non-finite model value, and how many residuals are distinct; and the
// sample of rows a large problem's starts are solved on. Each visits the
// predictions in turn: nothing is held for all rows.
#include <cmath>
#include <cstdint>
#include <map>
#include <random>
#include <set>
#include <sstream>
#include <string>
#include <tuple>
#include <vector>

#include "fitting/least_squares.h"
#include "io/table.h"

namespace clothfit {

std::vector<uint32_t> SampleRows(size_t n, size_t m) {
  std::vector<uint32_t> out;
  if (m >= n) {
    out.resize(n);
    for (size_t i = 0; i < n; ++i) out[i] = static_cast<uint32_t>(i);
    return out;
  }
  out.reserve(m);
  std::mt19937_64 random(0x5eed);
  std::uniform_real_distribution<double> u(0.0, 1.0);
  // Algorithm S: row i is taken with probability (wanted) / (left).
  for (size_t i = 0; i < n && out.size() < m; ++i) {
    if (static_cast<double>(n - i) * u(random) <
        static_cast<double>(m - out.size())) {
      out.push_back(static_cast<uint32_t>(i));
    }
  }
  return out;
}

std::string NonFiniteRow(const LeastSquaresProblem& lsq,
                         const std::vector<double>& x) {
  std::string out_text;
  lsq.predict(x, [&](double model, double measured, const TableRow* row) {
    if (!out_text.empty()) return;  // the first one
    if (std::isfinite(model) && std::isfinite(model - measured)) return;
    std::ostringstream out;
    out.precision(6);
    out << "the model value is " << model << " (data " << measured << ") at ";
    if (row != nullptr && row->source_line > 0) {
      out << "line " << row->source_line << " of the table";
    } else {
      out << "a row made in memory";
    }
    if (row != nullptr) {
      out << ", wi (" << row->wi.x << ", " << row->wi.y << ", " << row->wi.z
          << "), wo (" << row->wo.x << ", " << row->wo.y << ", " << row->wo.z
          << ")";
    }
    out << ", with";
    for (size_t k = 0; k < lsq.specs.size() && k < x.size(); ++k) {
      out << (k ? ", " : " ") << lsq.specs[k].name << " = " << x[k];
    }
    out_text = out.str();
  });
  return out_text;
}

int DistinctResiduals(const LeastSquaresProblem& lsq,
                      const std::vector<double>& x, int residuals, int enough) {
  // A row's pairs are its channels; rows at one place (directions, texel,
  // normal) repeat one measurement.
  using Place = std::tuple<double, double, double, double, double, double, int,
                           int, double, double, double>;
  std::set<const TableRow*> seen;
  std::set<Place> places;
  // Each place has at least one residual: enough of them settle it.
  bool settled = false;
  auto visit = [&](const TableRow* row) {
    if (settled || row == nullptr || !seen.insert(row).second) return;
    places.insert({row->wi.x, row->wi.y, row->wi.z, row->wo.x, row->wo.y,
                   row->wo.z, row->s, row->t, row->normal.x, row->normal.y,
                   row->normal.z});
    settled = static_cast<int>(places.size()) >= enough;
  };
  if (lsq.row) {
    for (size_t i = 0; i < lsq.rows && !settled; ++i) visit(lsq.row(i));
  } else {
    lsq.predict(x, [&](double, double, const TableRow* row) { visit(row); });
  }
  if (settled) return residuals;
  if (seen.empty() || places.size() == seen.size()) return residuals;
  return static_cast<int>(static_cast<double>(residuals) * places.size() /
                          seen.size());
}

}  // namespace clothfit
